//! higlass-server's API over the files served, as plain functions of a request's path and query
//! (the HTTP layer only carries them): `tilesets/`, `tileset_info/`, `tiles/`, `chrom-sizes/`.
//!
//! Every malformed request (an unknown endpoint, a query that is not `key=value` pairs, a tile id
//! that is not `UID.z.x.y[.transform]`, too many ids, too long a query) is a 400 with a JSON
//! `{"error": ...}`; a well-formed id of a UID not served answers `{"error": "No such tileset with
//! uid: ..."}` in its place, as higlass-server does.

use std::borrow::Cow;
use std::collections::{BTreeMap, HashMap};
use std::fmt::Write;
use std::sync::{Arc, Mutex};

use serde_json::{Value, json};

use super::registry::{Data, Entry, Registry};
use contactmap::tiles::{Aggregation, TileId, dense_json_text, shown};

/// The longest query answered (bytes).
pub const MAX_QUERY_BYTES: usize = 16 * 1024;
/// The most tile ids (or tileset UIDs) one request may ask for.
pub const MAX_IDS: usize = 256;

/// An answer: HTTP status, content type and body.
pub struct Reply {
    pub status: u16,
    pub content_type: &'static str,
    pub body: Vec<u8>,
}

impl Reply {
    fn json(value: &Value) -> Reply {
        Reply {
            status: 200,
            content_type: "application/json",
            body: value.to_string().into_bytes(),
        }
    }

    /// A JSON error with `status`.
    pub fn error(status: u16, message: &str) -> Reply {
        Reply {
            status,
            content_type: "application/json",
            body: json!({ "error": message }).to_string().into_bytes(),
        }
    }
}

/// A query's decoded `key=value` pairs.
pub type QueryPairs<'a> = Vec<(Cow<'a, str>, Cow<'a, str>)>;

/// The query's `key=value` pairs, decoded (`%2F`, `+`), or what is wrong with it.
pub fn parse_query(query: &str) -> Result<QueryPairs<'_>, String> {
    if query.len() > MAX_QUERY_BYTES {
        return Err(format!(
            "the query is {} bytes, more than the {MAX_QUERY_BYTES} answered",
            query.len()
        ));
    }
    let pairs: Vec<_> = form_urlencoded::parse(query.as_bytes()).collect();
    if pairs.len() > MAX_IDS * 2 {
        return Err(format!("the query has {} parameters", pairs.len()));
    }
    Ok(pairs)
}

/// Tiles as JSON text, kept up to a size in bytes; the least recently used go first.
pub struct TileCache {
    capacity: usize,
    state: Mutex<CacheState>,
}

#[derive(Default)]
struct CacheState {
    tiles: HashMap<String, (Arc<str>, u64)>,
    by_use: BTreeMap<u64, String>,
    bytes: usize,
    clock: u64,
}

impl TileCache {
    /// A cache holding at most `capacity` bytes of tiles (0: none kept).
    pub fn new(capacity: usize) -> TileCache {
        TileCache {
            capacity,
            state: Mutex::new(CacheState::default()),
        }
    }

    fn get(&self, key: &str) -> Option<Arc<str>> {
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let state = &mut *state;
        let (text, used) = state.tiles.get_mut(key)?;
        state.clock += 1;
        let key = state.by_use.remove(used).expect("indexed by use");
        *used = state.clock;
        state.by_use.insert(state.clock, key);
        Some(text.clone())
    }

    fn put(&self, key: String, text: Arc<str>) {
        if text.len() > self.capacity {
            return;
        }
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let state = &mut *state;
        if state.tiles.contains_key(&key) {
            return;
        }
        while state.bytes + text.len() > self.capacity {
            let Some((_, oldest)) = state.by_use.pop_first() else {
                break;
            };
            if let Some((gone, _)) = state.tiles.remove(&oldest) {
                state.bytes -= gone.len();
            }
        }
        state.clock += 1;
        state.bytes += text.len();
        state.by_use.insert(state.clock, key.clone());
        state.tiles.insert(key, (text, state.clock));
    }

    /// Bytes held.
    #[cfg(test)]
    pub fn bytes(&self) -> usize {
        self.state.lock().unwrap_or_else(|e| e.into_inner()).bytes
    }
}

/// The API over a registry.
pub struct Api {
    pub registry: Registry,
    pub cache: TileCache,
}

impl Api {
    /// Answer `GET path?query` for a path under `/api/v1/`.
    pub fn respond(&self, path: &str, query: &str) -> Reply {
        let endpoint = path
            .strip_prefix("/api/v1/")
            .map(|rest| rest.trim_end_matches('/'));
        let query = match parse_query(query) {
            Ok(query) => query,
            Err(message) => return Reply::error(400, &message),
        };
        let values = |key: &str| -> Vec<&str> {
            query
                .iter()
                .filter(|(k, _)| k == key)
                .map(|(_, v)| v.as_ref())
                .collect()
        };
        match endpoint {
            Some("tilesets") => self.tilesets(&values("dt"), &values("t"), &values("ac")),
            Some("tileset_info") => self.tileset_info(&values("d")),
            Some("tiles") => self.tiles(&values("d")),
            Some("chrom-sizes") => self.chrom_sizes(&values("id"), &values("type")),
            _ => Reply::error(
                404,
                &format!(
                    "no such endpoint '{}' (this server answers /api/v1/tilesets/, \
                     /api/v1/tileset_info/, /api/v1/tiles/, /api/v1/chrom-sizes/)",
                    shown(path)
                ),
            ),
        }
    }

    /// `tilesets/`: the files served, filtered by datatype (`dt`), filetype (`t`) and a part of
    /// the name (`ac`) as higlass-server filters them.
    fn tilesets(&self, datatypes: &[&str], filetypes: &[&str], names: &[&str]) -> Reply {
        let results: Vec<Value> = self
            .registry
            .entries
            .iter()
            .filter(|e| datatypes.is_empty() || datatypes.contains(&e.datatype))
            .filter(|e| filetypes.is_empty() || filetypes.contains(&e.filetype))
            .filter(|e| names.iter().all(|n| e.name.contains(n)))
            .map(|e| {
                json!({
                    "uuid": e.uid,
                    "name": e.name,
                    "datatype": e.datatype,
                    "filetype": e.filetype,
                    "coordSystem": e.coord_system,
                    "coordSystem2": "",
                    "private": false,
                    "description": "",
                })
            })
            .collect();
        Reply::json(&json!({
            "count": results.len(),
            "next": null,
            "previous": null,
            "results": results,
        }))
    }

    /// `tileset_info/?d=UID...`: clodius' tileset_info with `name`, `coordSystem` and
    /// `coordSystem2`, as higlass-server adds them.
    fn tileset_info(&self, uids: &[&str]) -> Reply {
        if let Err(message) = count_ids(uids, "d") {
            return Reply::error(400, &message);
        }
        let mut out = serde_json::Map::new();
        for &uid in uids {
            let info = match self.registry.get(uid) {
                Some(entry) => {
                    let mut info = entry.info();
                    info["name"] = json!(entry.name);
                    info["coordSystem"] = json!(entry.coord_system);
                    info["coordSystem2"] = json!("");
                    info
                }
                None => no_such(uid),
            };
            out.insert(uid.to_string(), info);
        }
        Reply::json(&Value::Object(out))
    }

    /// `tiles/?d=UID.z.x.y[.transform]...`: `{id: tile}`; a tile past the last zoom level is
    /// left out, as clodius leaves it out.
    fn tiles(&self, ids: &[&str]) -> Reply {
        if let Err(message) = count_ids(ids, "d") {
            return Reply::error(400, &message);
        }
        let mut parsed = Vec::with_capacity(ids.len());
        for &id in ids {
            match TileId::parse(id) {
                Ok(tile) => parsed.push((id, tile)),
                Err(message) => return Reply::error(400, &message),
            }
        }
        let mut body = String::from("{");
        let mut seen = std::collections::HashSet::new();
        for (id, tile) in parsed {
            if !seen.insert(id) {
                continue;
            }
            let text = match self.registry.get(tile.uid) {
                Some(entry) => match self.tile_text(entry, &tile) {
                    Some(text) => text,
                    None => continue,
                },
                None => no_such(tile.uid).to_string().into(),
            };
            if body.len() > 1 {
                body.push(',');
            }
            let _ = write!(body, "{}:{}", Value::from(id), text);
        }
        body.push('}');
        Reply {
            status: 200,
            content_type: "application/json",
            body: body.into_bytes(),
        }
    }

    /// One tile's JSON, from the cache or computed; `None` past a map's last zoom level.
    fn tile_text(&self, entry: &Entry, tile: &TileId) -> Option<Arc<str>> {
        let transform = tile.transform.unwrap_or("default");
        let y = tile.y.map_or(String::new(), |y| format!(".{y}"));
        let key = format!("{}.{}.{}{y}.{transform}", entry.uid, tile.zoom, tile.x);
        if let Some(text) = self.cache.get(&key) {
            return Some(text);
        }
        let error = |message: String| Some(json!({ "error": message }).to_string().into());
        let text: Arc<str> = match (&entry.data, tile.y) {
            (Data::Map(tileset), Some(y)) => match tileset.tile(tile.zoom, tile.x, y, transform) {
                Ok(None) => return None,
                Ok(Some(values)) => dense_json_text(&values).into(),
                // not kept: a read that failed may succeed later
                Err(error) => {
                    return Some(json!({ "error": error.to_string() }).to_string().into());
                }
            },
            (Data::Intervals(intervals), None) => {
                intervals.tile(tile.zoom as u32, tile.x).to_string().into()
            }
            (Data::Vector(vector), None) => {
                let tile = Aggregation::parse(tile.transform)
                    .and_then(|mode| vector.tile(tile.zoom as u32, tile.x, mode));
                match tile {
                    Ok(None) => return None,
                    Ok(Some(values)) => dense_json_text(&values).into(),
                    Err(e) => return error(e.to_string()),
                }
            }
            (Data::Map(_), None) => {
                return error(format!("{} is a map: its tiles are UID.z.x.y", entry.uid));
            }
            (Data::Rectangles(rectangles), y) => rectangles
                .tile(tile.zoom as u32, tile.x, y)
                .to_string()
                .into(),
            (Data::Intervals(_) | Data::Vector(_), Some(_)) => {
                return error(format!(
                    "{} is a 1D track: its tiles are UID.z.x",
                    entry.uid
                ));
            }
        };
        self.cache.put(key, text.clone());
        Some(text)
    }

    /// `chrom-sizes/?id=UID`: the chromosomes as `name<TAB>length` lines (`type=json`: as
    /// higlass-server's JSON, `{name: {"size": length}}`).
    fn chrom_sizes(&self, ids: &[&str], types: &[&str]) -> Reply {
        let [uid] = ids else {
            return Reply::error(400, "chrom-sizes takes one id: ?id=UID");
        };
        let Some(entry) = self.registry.get(uid) else {
            return Reply::error(400, &format!("No such tileset with uid: {}", shown(uid)));
        };
        let chromsizes = entry.info()["chromsizes"].clone();
        let pairs = chromsizes.as_array().cloned().unwrap_or_default();
        match types {
            [] | ["tsv"] => {
                let mut text = String::new();
                for pair in &pairs {
                    let _ = writeln!(text, "{}\t{}", pair[0].as_str().unwrap_or(""), pair[1]);
                }
                Reply {
                    status: 200,
                    content_type: "text/plain; charset=utf-8",
                    body: text.into_bytes(),
                }
            }
            ["json"] => {
                let map: serde_json::Map<String, Value> = pairs
                    .iter()
                    .map(|p| {
                        (
                            p[0].as_str().unwrap_or("").to_string(),
                            json!({"size": p[1]}),
                        )
                    })
                    .collect();
                Reply::json(&Value::Object(map))
            }
            _ => Reply::error(400, "chrom-sizes: type is tsv (the default) or json"),
        }
    }
}

/// higlass-server's answer for a UID it does not have.
fn no_such(uid: &str) -> Value {
    json!({ "error": format!("No such tileset with uid: {}", shown(uid)) })
}

fn count_ids(ids: &[&str], key: &str) -> Result<(), String> {
    if ids.is_empty() {
        return Err(format!("no {key}= in the query"));
    }
    if ids.len() > MAX_IDS {
        return Err(format!(
            "{} ids in one request, more than the {MAX_IDS} answered",
            ids.len()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests;
