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

use std::collections::HashMap;

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
        let genome = Genome::new(chroms, source);
        let kinds = kinds(records);
        let mut rows = Vec::with_capacity(records.len());
        for (ix, record) in records.iter().enumerate() {
            let chr_offset = genome.offset(record, 0, ix)?;
            let (start, end) = (
                genome.position(record, 1, ix)?,
                genome.position(record, 2, ix)?,
            );
            rows.push(Row {
                x_start: chr_offset + start,
                x_end: chr_offset + end,
                chr_offset,
                importance: importance(ix as u64),
                fields: typed(record, &kinds),
            });
        }
        Ok(Intervals {
            chroms: genome.chroms(),
            length: genome.length,
            rows,
        })
    }

    /// `tileset_info` as clodius' `bedfile.tileset_info`: `max_width` the genome's length,
    /// `max_zoom` its base-2 logarithm rounded down, `min_pos` `[0]`, `max_pos` the length,
    /// `chromsizes`.
    pub fn info(&self) -> Value {
        let mut info = extent(&self.chroms, self.length);
        info["min_pos"] = json!([0]);
        info["max_pos"] = json!([self.length]);
        info
    }

    /// Tile `x` of zoom level `zoom`: the records in it, each `{uid, xStart, xEnd, chrOffset,
    /// importance, fields}` (`uid`: the record's row, from 0), in file order.
    pub fn tile(&self, zoom: u32, x: u64) -> Value {
        let (start, end) = tile_span(self.length, zoom, x);
        let mut hits: Vec<usize> = (0..self.rows.len())
            .filter(|&i| self.rows[i].x_end as f64 >= start && self.rows[i].x_start as f64 <= end)
            .collect();
        keep_most_important(&mut hits, |i| self.rows[i].importance, MAX_PER_TILE);
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

/// The concatenated genome records are placed on, and what a record's placement can get wrong.
pub(super) struct Genome<'a> {
    chroms: &'a [Chrom],
    offsets: HashMap<&'a str, u64>,
    /// The genome's length.
    pub length: u64,
    source: &'a str,
}

impl<'a> Genome<'a> {
    /// The genome of `chroms`; `source` names the records' file in errors.
    pub fn new(chroms: &'a [Chrom], source: &'a str) -> Genome<'a> {
        let mut offsets = HashMap::new();
        let mut length = 0u64;
        for chrom in chroms {
            offsets.insert(chrom.name.as_str(), length);
            length += chrom.length_bp;
        }
        Genome {
            chroms,
            offsets,
            length,
            source,
        }
    }

    /// `[name, length]` of each chromosome.
    pub fn chroms(&self) -> Vec<(String, u64)> {
        self.chroms
            .iter()
            .map(|c| (c.name.clone(), c.length_bp))
            .collect()
    }

    fn error(&self, ix: usize, what: String) -> Error {
        Error::Data(format!("{}: record {}: {what}", self.source, ix + 1))
    }

    /// The offset of the chromosome named in field `k` of record `ix`.
    pub fn offset(&self, record: &[String], k: usize, ix: usize) -> Result<u64> {
        let name = record.get(k).map(String::as_str).unwrap_or("");
        self.offsets.get(name).copied().ok_or_else(|| {
            self.error(
                ix,
                format!("chromosome '{name}' is not among the map's chromosomes"),
            )
        })
    }

    /// The position in field `k` of record `ix`.
    pub fn position(&self, record: &[String], k: usize, ix: usize) -> Result<u64> {
        let text = record.get(k).map(String::as_str).unwrap_or("");
        text.parse::<u64>()
            .map_err(|_| self.error(ix, format!("'{text}' is not a position")))
    }
}

/// A record's fields, each as its column's kind makes it.
pub(super) fn typed(record: &[String], kinds: &[Kind]) -> Vec<Value> {
    record
        .iter()
        .zip(kinds)
        .map(|(text, kind)| kind.value(text))
        .collect()
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

/// Of a crowded tile's records (`hits`, by row), the `max` most important, in file order.
pub(super) fn keep_most_important(
    hits: &mut Vec<usize>,
    importance: impl Fn(usize) -> f64,
    max: usize,
) {
    if hits.len() > max {
        hits.sort_by(|&a, &b| importance(b).total_cmp(&importance(a)));
        hits.truncate(max);
        hits.sort_unstable();
    }
}

/// What clodius' interval tilesets say of their genome: `max_width` its length, `max_zoom` the
/// length's base-2 logarithm rounded down, `chromsizes`.
pub(super) fn extent(chroms: &[(String, u64)], length: u64) -> Value {
    json!({
        "max_width": length,
        "max_zoom": ((length as f64).ln() / 2f64.ln()) as u64,
        "chromsizes": chroms.iter().map(|(n, l)| json!([n, l])).collect::<Vec<_>>(),
    })
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
