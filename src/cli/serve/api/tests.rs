//! The API's answers: tiles and tileset_info through the endpoints against clodius 0.22.2's
//! (data/tiles/, `scripts/tiles_references.py`), malformed requests, the cache, and a fuzz of
//! the query and tile-id parsers.

use std::path::PathBuf;
use std::sync::OnceLock;

use base64::Engine;
use proptest::prelude::*;
use serde_json::Value;

use super::*;

fn data(name: &str) -> PathBuf {
    [env!("CARGO_MANIFEST_DIR"), "data", name].iter().collect()
}

/// One API over the two maps clodius answered for, shared by the tests.
fn api() -> &'static Api {
    static API: OnceLock<Api> = OnceLock::new();
    API.get_or_init(|| Api {
        registry: Registry::open(&[
            data("tiles/domains.bed.gz"),
            data("tiles/track.bedgraph.gz"),
            data("tiles/dots.bedpe.gz"),
            data("cooler_test_file.mcool"),
            data("tiles/square.mcool"),
        ])
        .unwrap(),
        cache: TileCache::new(1 << 20),
    })
}

fn get(path: &str, query: &str) -> (u16, Value) {
    let reply = api().respond(path, query);
    let body = String::from_utf8(reply.body).unwrap();
    let value = serde_json::from_str(&body).unwrap_or_else(|e| panic!("{body}: {e}"));
    (reply.status, value)
}

fn reference(file: &str, what: &str) -> Value {
    let path = data(&format!("tiles/{file}.{what}.json"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|_| {
        let gz = std::fs::File::open(path.with_extension("json.gz")).unwrap();
        let mut text = String::new();
        std::io::Read::read_to_string(&mut flate2::read::GzDecoder::new(gz), &mut text).unwrap();
        text
    });
    serde_json::from_str(&text).unwrap()
}

/// A tile's dtype, CRC-32 of its decoded bytes and NaN count, as the reference keeps them.
fn digest(tile: &Value) -> (String, u32, usize) {
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(tile["dense"].as_str().unwrap())
        .unwrap();
    let width = if tile["dtype"] == "float16" { 2 } else { 4 };
    let n_nan = bytes
        .chunks(width)
        .filter(|b| match b {
            [a, b] => half::f16::from_le_bytes([*a, *b]).is_nan(),
            [a, b, c, d] => f32::from_le_bytes([*a, *b, *c, *d]).is_nan(),
            _ => unreachable!(),
        })
        .count();
    (
        tile["dtype"].as_str().unwrap().to_string(),
        crc32fast::hash(&bytes),
        n_nan,
    )
}

#[test]
fn tiles_through_the_api_equal_clodius() {
    for (uid, file) in [
        ("cooler_test_file", "cooler_test_file.mcool"),
        ("square", "square.mcool"),
    ] {
        let Value::Object(expected) = reference(file, "tiles") else {
            panic!()
        };
        // the ids as HiGlass sends them, several to a request
        let ids: Vec<String> = expected
            .keys()
            .map(|k| format!("{uid}.{}", k.strip_suffix(".default").unwrap_or(k)))
            .collect();
        for chunk in ids.chunks(16) {
            let query: Vec<String> = chunk.iter().map(|id| format!("d={id}")).collect();
            let (status, tiles) = get("/api/v1/tiles/", &query.join("&"));
            assert_eq!(status, 200);
            for id in chunk {
                let want = &expected[id.strip_prefix(&format!("{uid}.")).unwrap()];
                match tiles.get(id) {
                    None => assert!(want.is_null(), "{id}: clodius gave a tile"),
                    Some(tile) => {
                        let got = digest(tile);
                        let want_digest = (
                            want["dtype"].as_str().unwrap().to_string(),
                            want["crc32"].as_u64().unwrap() as u32,
                            want["n_nan"].as_u64().unwrap() as usize,
                        );
                        assert_eq!(got, want_digest, "{id}");
                    }
                }
            }
        }
    }
}

#[test]
fn tileset_info_through_the_api_is_clodius_with_the_name() {
    let (status, info) = get("/api/v1/tileset_info/", "d=square&d=nope");
    assert_eq!(status, 200);
    let mut square = info["square"].clone();
    assert_eq!(square["name"], "square.mcool");
    assert_eq!(square["coordSystem"], "square");
    for key in ["name", "coordSystem", "coordSystem2"] {
        square.as_object_mut().unwrap().remove(key);
    }
    let mut transforms = square["transforms"].as_array().unwrap().clone();
    transforms.sort_by_key(|t| t["value"].as_str().unwrap().to_string());
    square["transforms"] = Value::Array(transforms);
    assert_eq!(square, reference("square.mcool", "tileset_info"));
    assert_eq!(info["nope"]["error"], "No such tileset with uid: nope");
}

/// The uids of an interval tile's records, and those the reference lists for it.
fn uids<'a>(tile: &'a Value, reference: &'a Value) -> (Vec<&'a Value>, Vec<&'a Value>) {
    let got = tile.as_array().unwrap().iter().map(|r| &r["uid"]).collect();
    (got, reference.as_array().unwrap().iter().collect())
}

/// A BED track through the API: clodius' records in each tile (`UID.z.x`), its tileset_info.
#[test]
fn bed_tiles_through_the_api_equal_clodius() {
    let expected = reference("domains.bed", "tiles");
    let ids: Vec<&String> = expected["tiles"].as_object().unwrap().keys().collect();
    let query: Vec<String> = ids.iter().map(|id| format!("d=domains.{id}")).collect();
    let (status, tiles) = get("/api/v1/tiles/", &query.join("&"));
    assert_eq!(status, 200);
    for id in ids {
        let (got, want) = uids(&tiles[format!("domains.{id}")], &expected["tiles"][id]);
        assert_eq!(got, want, "{id}");
    }
    let (_, info) = get("/api/v1/tileset_info/", "d=domains");
    assert_eq!(
        info["domains"]["max_width"],
        reference("domains.bed", "tileset_info")["max_width"]
    );
    let (_, wrong) = get("/api/v1/tiles/", "d=domains.1.0.0&d=square.1.0");
    assert!(
        wrong["domains.1.0.0"]["error"]
            .as_str()
            .unwrap()
            .contains("1D track")
    );
    assert!(
        wrong["square.1.0"]["error"]
            .as_str()
            .unwrap()
            .contains("is a map")
    );
}

/// A bedGraph track through the API (`UID.z.x[.mode]`): clodius' bigWig tiles of it.
#[test]
fn vector_tiles_through_the_api_equal_clodius() {
    let Value::Object(expected) = reference("track.bedgraph", "tiles") else {
        panic!()
    };
    let ids: Vec<&String> = expected.keys().take(60).collect();
    let query: Vec<String> = ids.iter().map(|id| format!("d=track.{id}")).collect();
    let (status, tiles) = get("/api/v1/tiles/", &query.join("&"));
    assert_eq!(status, 200);
    for id in ids {
        let (dtype, crc, n_nan) = digest(&tiles[format!("track.{id}")]);
        let want = &expected[id];
        assert_eq!(
            (dtype.as_str(), crc as u64, n_nan as u64),
            (
                want["dtype"].as_str().unwrap(),
                want["crc32"].as_u64().unwrap(),
                want["n_nan"].as_u64().unwrap()
            ),
            "{id}"
        );
    }
    let (_, list) = get("/api/v1/tilesets/", "dt=vector");
    assert_eq!(list["results"][0]["uuid"], "track");
    assert_eq!(list["results"][0]["filetype"], "bigwig");
    let (_, info) = get("/api/v1/tileset_info/", "d=track");
    assert_eq!(info["track"]["tile_size"], 1024);
    let (_, bad) = get("/api/v1/tiles/", "d=track.0.0.std");
    assert!(
        bad["track.0.0.std"]["error"]
            .as_str()
            .unwrap()
            .contains("mean, min, max and sum")
    );
}

/// A BEDPE track through the API: clodius' records in its 2D (`UID.z.x.y`) and 1D tiles.
#[test]
fn bedpe_tiles_through_the_api_equal_clodius() {
    let expected = reference("dots.bedpe", "tiles");
    let ids: Vec<&String> = expected["tiles"]
        .as_object()
        .unwrap()
        .keys()
        .take(100)
        .collect();
    let query: Vec<String> = ids.iter().map(|id| format!("d=dots.{id}")).collect();
    let (status, tiles) = get("/api/v1/tiles/", &query.join("&"));
    assert_eq!(status, 200);
    for id in ids {
        let (got, want) = uids(&tiles[format!("dots.{id}")], &expected["tiles"][id]);
        assert_eq!(got, want, "{id}");
    }
    let (_, list) = get("/api/v1/tilesets/", "dt=2d-rectangle-domains");
    assert_eq!(list["results"][0]["uuid"], "dots");
    assert_eq!(list["results"][0]["coordSystem"], "dm6");
}

#[test]
fn the_list_and_chrom_sizes() {
    let (status, list) = get("/api/v1/tilesets/", "limit=100&dt=matrix");
    assert_eq!(get("/api/v1/tilesets/", "").1["count"], 5);
    assert_eq!(status, 200);
    assert_eq!(list["count"], 2);
    assert_eq!(list["results"][0]["uuid"], "cooler_test_file");
    assert_eq!(list["results"][0]["coordSystem"], "dm6");
    assert_eq!(list["results"][1]["datatype"], "matrix");
    assert_eq!(get("/api/v1/tilesets/", "dt=vector").1["count"], 1);
    // the BED track, after the maps, on its map's genome
    let (_, tracks) = get("/api/v1/tilesets/", "dt=bedlike");
    assert_eq!(tracks["count"], 1);
    assert_eq!(tracks["results"][0]["uuid"], "domains");
    assert_eq!(tracks["results"][0]["filetype"], "bedfile");
    assert_eq!(tracks["results"][0]["coordSystem"], "dm6");
    assert_eq!(get("/api/v1/tilesets/", "ac=squ").1["count"], 1);
    let reply = api().respond("/api/v1/chrom-sizes/", "id=square");
    assert_eq!(
        String::from_utf8(reply.body).unwrap(),
        "chrA\t520500\nchrB\t29999\nchrC\t20001\n"
    );
    let (_, json) = get("/api/v1/chrom-sizes/", "id=square&type=json");
    assert_eq!(json["chrB"]["size"], 29999);
}

#[test]
fn malformed_requests_are_400_with_a_json_error() {
    let too_many: Vec<String> = (0..=MAX_IDS).map(|x| format!("d=square.2.{x}.0")).collect();
    let long = format!("d={}", "a".repeat(MAX_QUERY_BYTES));
    let cases = [
        ("/api/v1/tiles/", "".to_string()),
        ("/api/v1/tiles/", "d=square.2.0.0.KR.x".to_string()),
        ("/api/v1/tiles/", "d=square.x.0.0".to_string()),
        ("/api/v1/tiles/", "d=square.2.%2B1.0".to_string()),
        ("/api/v1/tiles/", "d=square.99.0.0".to_string()),
        (
            "/api/v1/tiles/",
            "d=square.2.99999999999999999999.0".to_string(),
        ),
        (
            "/api/v1/tiles/",
            "d=..%2F..%2Fetc%2Fpasswd.0.0.0".to_string(),
        ),
        ("/api/v1/tiles/", "d=%2Fetc%2Fpasswd.0.0.0".to_string()),
        ("/api/v1/tiles/", "d=square.2.0.0.a%2Fb".to_string()),
        ("/api/v1/tiles/", too_many.join("&")),
        ("/api/v1/tiles/", long),
        ("/api/v1/tileset_info/", "".to_string()),
        ("/api/v1/chrom-sizes/", "id=a&id=b".to_string()),
        ("/api/v1/chrom-sizes/", "id=..%2Fsquare".to_string()),
        ("/api/v1/chrom-sizes/", "id=square&type=xml".to_string()),
    ];
    for (path, query) in &cases {
        let (status, body) = get(path, query);
        assert_eq!(status, 400, "{path}?{query}: {body}");
        assert!(body["error"].as_str().is_some_and(|e| !e.is_empty()));
    }
    assert_eq!(get("/api/v1/../../etc/passwd", "").0, 404);
    assert_eq!(get("/api/v2/tiles/", "d=square.0.0.0").0, 404);
}

#[test]
fn tiles_past_the_last_zoom_level_are_left_out_and_missing_columns_are_errors() {
    let (status, tiles) = get(
        "/api/v1/tiles/",
        "d=square.2.0.0&d=cooler_test_file.0.0.0.KR&d=other.0.0.0&d=square.1.0.0&d=square.1.0.0",
    );
    assert_eq!(status, 200);
    let tiles = tiles.as_object().unwrap();
    assert!(!tiles.contains_key("square.2.0.0"));
    assert!(
        tiles["cooler_test_file.0.0.0.KR"]["error"]
            .as_str()
            .unwrap()
            .contains("no 'KR' column")
    );
    assert_eq!(
        tiles["other.0.0.0"]["error"],
        "No such tileset with uid: other"
    );
    assert_eq!(tiles.len(), 3, "a repeated id is answered once");
}

#[test]
fn the_cache_keeps_the_most_recently_used_within_its_size() {
    let cache = TileCache::new(10);
    cache.put("a".into(), "aaaa".into());
    cache.put("b".into(), "bbbb".into());
    assert!(cache.get("a").is_some()); // a is now the most recent
    cache.put("c".into(), "cccc".into()); // evicts b
    assert!(cache.get("b").is_none());
    assert_eq!(cache.get("a").as_deref(), Some("aaaa"));
    assert_eq!(cache.get("c").as_deref(), Some("cccc"));
    assert_eq!(cache.bytes(), 8);
    cache.put("big".into(), "x".repeat(11).into()); // larger than the cache: not kept
    assert!(cache.get("big").is_none());
    let none = TileCache::new(0);
    none.put("a".into(), "a".into());
    assert_eq!(none.bytes(), 0);
}

#[test]
fn tile_ids_parse_as_higlass_writes_them() {
    assert_eq!(
        TileId::parse("GM12878.3.5.7.KR"),
        Ok(TileId {
            uid: "GM12878",
            zoom: 3,
            x: 5,
            y: Some(7),
            transform: Some("KR")
        })
    );
    assert_eq!(TileId::parse("a-b_c.0.0.0").unwrap().transform, None);
    let track = TileId::parse("domains.3.5").unwrap();
    assert_eq!((track.x, track.y, track.transform), (5, None, None));
    assert_eq!(TileId::parse("v.3.5.mean").unwrap().transform, Some("mean"));
    for bad in [
        "",
        "a",
        "a.1",
        "a.1.2.KR.x",
        "a.1.2.3.4.5",
        ".1.2.3",
        "a.1.2.3.",
        "a.-1.2.3",
        "a.1. 2.3",
    ] {
        assert!(TileId::parse(bad).is_err(), "{bad:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The fuzz of the query parser (CI runs it with the tests): any query, any path under
    /// /api/, is answered with 200, 400 or 404 and a JSON body, never a panic.
    #[test]
    fn any_request_is_answered_with_json(
        endpoint in prop::sample::select(vec!["tiles/", "tileset_info/", "tilesets/", "chrom-sizes/", "x/"]),
        query in "[a-z=&%.0-9A-F_/+-]{0,80}|d=(square|cooler_test_file|domains|x)(\\.[0-9]{1,3}){2,3}(\\.(KR|weight|VC|x))?",
        raw in proptest::collection::vec(any::<u8>(), 0..64),
    ) {
        let path = format!("/api/v1/{endpoint}");
        let raw = String::from_utf8_lossy(&raw).into_owned();
        for q in [query.as_str(), raw.as_str()] {
            let reply = api().respond(&path, q);
            prop_assert!([200, 400, 404].contains(&reply.status), "{} {path}?{q}", reply.status);
            if reply.content_type == "application/json" {
                prop_assert!(serde_json::from_slice::<Value>(&reply.body).is_ok());
            }
            let _ = TileId::parse(q);
        }
    }
}
