//! Interval tiles of a BED file (TAD domains, boundaries, peaks) for HiGlass' `bedlike` tracks,
//! as clodius 0.22.2 serves a BED file that is not indexed (`clodius.tiles.bedfile`).
//!
//! Each record is placed on the concatenated genome (`xStart = offset(chrom) + start`,
//! `xEnd = offset(chrom) + end`); zoom level `z` cuts the genome's length into `2^z` tiles, and a
//! tile lists the records with `xEnd >= tile start` and `xStart <= tile end` (both ends
//! included, as clodius' query), at most 1,024. Two choices differ from clodius, both because
//! its are random: a record's `importance` is a fixed pseudo-random number of its row (clodius
//! draws a new one on every request, so features flicker as a viewer pans), and a tile with more
//! than 1,024 records keeps the 1,024 most important (clodius keeps a random sample).

use serde_json::{Value, json};

use crate::error::{Error, Result};
use crate::genome::Chrom;

/// The most records in one tile.
pub const MAX_PER_TILE: usize = 1024;

/// A BED file's records on a genome.
pub struct Intervals {
    chroms: Vec<(String, u64)>,
    length: u64,
    rows: Vec<Row>,
}

struct Row {
    x_start: u64,
    x_end: u64,
    chr_offset: u64,
    importance: f64,
    fields: Vec<Value>,
}

impl Intervals {
    /// The records (each a BED line's fields as text: chrom, start, end, ...) on the genome
    /// `chroms`. A column whose every value is an integer is sent as integers, one whose every
    /// value is a number as numbers, as clodius' table reader types them; others as text.
    /// `source` names the file in errors (with the record's line, 1-based among records).
    pub fn new(chroms: &[Chrom], records: &[Vec<String>], source: &str) -> Result<Intervals> {
        let mut offsets = std::collections::HashMap::new();
        let mut length = 0u64;
        for chrom in chroms {
            offsets.insert(chrom.name.as_str(), length);
            length += chrom.length_bp;
        }
        let kinds = kinds(records);
        let mut rows = Vec::with_capacity(records.len());
        for (ix, record) in records.iter().enumerate() {
            let field = |k: usize| record.get(k).map(String::as_str).unwrap_or("");
            let bad = |what: String| Error::Data(format!("{source}: record {}: {what}", ix + 1));
            let &chr_offset = offsets.get(field(0)).ok_or_else(|| {
                bad(format!(
                    "chromosome '{}' is not among the map's chromosomes",
                    field(0)
                ))
            })?;
            let position = |k: usize| {
                field(k)
                    .parse::<u64>()
                    .map_err(|_| bad(format!("'{}' is not a position", field(k))))
            };
            let (start, end) = (position(1)?, position(2)?);
            rows.push(Row {
                x_start: chr_offset + start,
                x_end: chr_offset + end,
                chr_offset,
                importance: importance(ix as u64),
                fields: record
                    .iter()
                    .zip(&kinds)
                    .map(|(text, kind)| kind.value(text))
                    .collect(),
            });
        }
        Ok(Intervals {
            chroms: chroms
                .iter()
                .map(|c| (c.name.clone(), c.length_bp))
                .collect(),
            length,
            rows,
        })
    }

    /// `tileset_info` as clodius' `bedfile.tileset_info`: `max_width` the genome's length,
    /// `max_zoom` its base-2 logarithm rounded down, `min_pos` `[0]`, `max_pos` the length,
    /// `chromsizes`.
    pub fn info(&self) -> Value {
        json!({
            "max_width": self.length,
            "max_zoom": max_zoom(self.length),
            "chromsizes": self.chroms.iter().map(|(n, l)| json!([n, l])).collect::<Vec<_>>(),
            "min_pos": [0],
            "max_pos": [self.length],
        })
    }

    /// Tile `x` of zoom level `zoom`: the records in it, each `{uid, xStart, xEnd, chrOffset,
    /// importance, fields}` (`uid`: the record's row, from 0), in file order.
    pub fn tile(&self, zoom: u32, x: u64) -> Value {
        let (start, end) = tile_span(self.length, zoom, x);
        let mut hits: Vec<usize> = (0..self.rows.len())
            .filter(|&i| self.rows[i].x_end as f64 >= start && self.rows[i].x_start as f64 <= end)
            .collect();
        if hits.len() > MAX_PER_TILE {
            hits.sort_by(|&a, &b| self.rows[b].importance.total_cmp(&self.rows[a].importance));
            hits.truncate(MAX_PER_TILE);
            hits.sort_unstable();
        }
        Value::Array(
            hits.into_iter()
                .map(|i| {
                    let row = &self.rows[i];
                    json!({
                        "uid": i,
                        "xStart": row.x_start,
                        "xEnd": row.x_end,
                        "chrOffset": row.chr_offset,
                        "importance": row.importance,
                        "fields": row.fields,
                    })
                })
                .collect(),
        )
    }
}

/// Where tile `x` of zoom level `zoom` starts and ends on a genome of `length` bp, as clodius
/// computes it (`x * max_width / 2**z` in float64).
pub(super) fn tile_span(length: u64, zoom: u32, x: u64) -> (f64, f64) {
    let at = |k: u64| (k as u128 * length as u128) as f64 / 2f64.powi(zoom.min(1023) as i32);
    (at(x), at(x + 1))
}

/// Each column's kind, from all its values.
pub(super) fn kinds(records: &[Vec<String>]) -> Vec<Kind> {
    let n_columns = records.iter().map(Vec::len).max().unwrap_or(0);
    (0..n_columns)
        .map(|c| Kind::of(records.iter().filter_map(|r| r.get(c).map(String::as_str))))
        .collect()
}

/// The `max_zoom` clodius gives a genome of `length` bp: its base-2 logarithm, rounded down.
pub(super) fn max_zoom(length: u64) -> u64 {
    ((length as f64).ln() / 2f64.ln()) as u64
}

/// How a column's values are sent.
#[derive(Clone, Copy)]
pub(super) enum Kind {
    Integer,
    Real,
    Text,
}

impl Kind {
    fn of<'a>(values: impl Iterator<Item = &'a str> + Clone) -> Kind {
        if values.clone().all(|v| v.parse::<i64>().is_ok()) {
            Kind::Integer
        } else if values
            .clone()
            .all(|v| v.parse::<f64>().is_ok_and(f64::is_finite))
        {
            Kind::Real
        } else {
            Kind::Text
        }
    }

    pub(super) fn value(self, text: &str) -> Value {
        match self {
            Kind::Integer => text
                .parse::<i64>()
                .map_or_else(|_| json!(text), |v| json!(v)),
            Kind::Real => text
                .parse::<f64>()
                .map_or_else(|_| json!(text), |v| json!(v)),
            Kind::Text => json!(text),
        }
    }
}

/// A record's fixed importance in [0, 1): a mix of its row number (splitmix64).
pub(super) fn importance(row: u64) -> f64 {
    let mut z = row.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}
