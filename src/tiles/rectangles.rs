//! Rectangle tiles of a BEDPE file (dots, loops, domain pairs) for HiGlass'
//! `2d-rectangle-domains` tracks, as clodius 0.22.2 serves a BEDPE file that is not indexed
//! (`clodius.tiles.bedpe`).
//!
//! Each record is placed on the concatenated genome on both axes; zoom level `z` cuts the genome
//! into `2^z` tiles per axis; a 2D tile (`UID.z.x.y`) lists the records whose first anchor meets
//! column `x` and second anchor row `y` (both ends included), a 1D tile (`UID.z.x`) those with
//! either anchor in `x`; at most 512. As for BED tracks, `importance` is fixed per record and a
//! crowded tile keeps the most important (clodius: random on every request).

use serde_json::{Value, json};

use super::intervals::{Genome, extent, importance, keep_most_important, kinds, tile_span, typed};
use crate::error::Result;
use crate::genome::Chrom;

/// The most records in one tile.
pub const MAX_RECTANGLES_PER_TILE: usize = 512;

/// A BEDPE file's records on a genome.
pub struct Rectangles {
    chroms: Vec<(String, u64)>,
    length: u64,
    header: String,
    rows: Vec<Rectangle>,
}

struct Rectangle {
    x: (u64, u64),
    y: (u64, u64),
    offsets: (u64, u64),
    importance: f64,
    fields: Vec<Value>,
}

impl Rectangles {
    /// The records (each a BEDPE line's fields as text: chrom1, start1, end1, chrom2, start2,
    /// end2, ...) on the genome `chroms`, with the file's header line if it has one (clodius
    /// sends it joined by tabs). Columns are typed as [`super::Intervals::new`] types them.
    pub fn new(
        chroms: &[Chrom],
        records: &[Vec<String>],
        header: Option<&[String]>,
        source: &str,
    ) -> Result<Rectangles> {
        let genome = Genome::new(chroms, source);
        let kinds = kinds(records);
        let mut rows = Vec::with_capacity(records.len());
        for (ix, record) in records.iter().enumerate() {
            let (ox, oy) = (genome.offset(record, 0, ix)?, genome.offset(record, 3, ix)?);
            let at = |k: usize| genome.position(record, k, ix);
            rows.push(Rectangle {
                x: (ox + at(1)?, ox + at(2)?),
                y: (oy + at(4)?, oy + at(5)?),
                offsets: (ox, oy),
                importance: importance(ix as u64),
                fields: typed(record, &kinds),
            });
        }
        Ok(Rectangles {
            chroms: genome.chroms(),
            length: genome.length,
            header: header.map(|h| h.join("\t")).unwrap_or_default(),
            rows,
        })
    }

    /// `tileset_info` as clodius' `bedpe.tileset_info`.
    pub fn info(&self) -> Value {
        let mut info = extent(&self.chroms, self.length);
        info["min_pos"] = json!([0, 0]);
        info["max_pos"] = json!([self.length, self.length]);
        info["header"] = json!(self.header);
        info
    }

    /// Tile `(x, y)` of zoom level `zoom` (a 1D tile when `y` is `None`): the records in it,
    /// each `{uid, xStart, xEnd, yStart, yEnd, xChrOffset, yChrOffset, importance, fields}`.
    pub fn tile(&self, zoom: u32, x: u64, y: Option<u64>) -> Value {
        let (x0, x1) = tile_span(self.length, zoom, x);
        let meets =
            |(start, end): (u64, u64), (a, b): (f64, f64)| end as f64 >= a && start as f64 <= b;
        let mut hits: Vec<usize> = (0..self.rows.len())
            .filter(|&i| {
                let row = &self.rows[i];
                match y {
                    Some(y) => {
                        meets(row.x, (x0, x1)) && meets(row.y, tile_span(self.length, zoom, y))
                    }
                    None => meets(row.x, (x0, x1)) || meets(row.y, (x0, x1)),
                }
            })
            .collect();
        keep_most_important(
            &mut hits,
            |i| self.rows[i].importance,
            MAX_RECTANGLES_PER_TILE,
        );
        Value::Array(
            hits.into_iter()
                .map(|i| {
                    let row = &self.rows[i];
                    json!({
                        "uid": i,
                        "xStart": row.x.0,
                        "xEnd": row.x.1,
                        "yStart": row.y.0,
                        "yEnd": row.y.1,
                        "xChrOffset": row.offsets.0,
                        "yChrOffset": row.offsets.1,
                        "importance": row.importance,
                        "fields": row.fields,
                    })
                })
                .collect(),
        )
    }
}
