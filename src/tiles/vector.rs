//! Vector tiles of a 1D track (a bedGraph; the insulation, eigenvector and coverage tables
//! contactmap writes) for HiGlass' line and bar tracks, as clodius 0.22.2 serves a bigWig
//! (`clodius.tiles.bigwig`) holding the same intervals.
//!
//! The track's values are kept as a bigWig keeps them (float32). Zoom level `z` of `d` levels
//! (`2^d * 1024 bp` the first power of two at least the genome's length) has bins of
//! `2^(d - z)` bp, 1,024 to a tile; a tile is cut at chromosome ends into pieces, each piece
//! summarised as pybigtools' `values(chrom, start, end, bins)` does (bin `i` of a piece of length
//! `L` in `n` bins starts at `floor(i * L / n)`: the mean of the covered bases, the minimum or
//! maximum of the values met, or the sum of value times bases; NaN where nothing is covered),
//! and the pieces joined as clodius joins them (a piece's last bin dropped where the pieces ran
//! more than a bin ahead). Past the genome's end the values are NaN.

use serde_json::{Value, json};

use crate::error::{Error, Result};
use crate::genome::Chrom;

/// Bins in a vector tile.
pub const VECTOR_TILE_SIZE: u64 = 1024;

/// A 1D track on a genome.
pub struct Vector {
    chroms: Vec<(String, u64)>,
    /// Each chromosome's start on the concatenated genome, and the genome's length last.
    offsets: Vec<u64>,
    /// The number of zoom levels below the first (`d`).
    depth: u32,
    /// Per chromosome, its intervals `(start, end, value)` sorted by start.
    intervals: Vec<Vec<(u64, u64, f32)>>,
}

/// How a bin's value is made from the intervals it covers (clodius' `aggregation_modes`; `std`
/// and the range modes are not computed).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aggregation {
    /// The mean over the covered bases (the default).
    Mean,
    /// The smallest value met.
    Min,
    /// The largest value met.
    Max,
    /// The sum of value times covered bases.
    Sum,
}

impl Aggregation {
    /// The mode a tile id names (`UID.z.x.mean`), `mean` when none.
    pub fn parse(name: Option<&str>) -> Result<Aggregation> {
        match name.unwrap_or("mean") {
            "mean" => Ok(Aggregation::Mean),
            "min" => Ok(Aggregation::Min),
            "max" => Ok(Aggregation::Max),
            "sum" => Ok(Aggregation::Sum),
            other => Err(Error::Argument(format!(
                "aggregation '{other}': a vector track offers mean, min, max and sum"
            ))),
        }
    }
}

impl Vector {
    /// The track of `records` (chrom, start, end, value; a NaN value is no data) on the genome
    /// `chroms`. `source` names the file in errors (with the record, 1-based).
    pub fn new(
        chroms: &[Chrom],
        records: &[(String, u64, u64, f64)],
        source: &str,
    ) -> Result<Vector> {
        let mut offsets = Vec::with_capacity(chroms.len() + 1);
        let mut total = 0u64;
        for chrom in chroms {
            offsets.push(total);
            total += chrom.length_bp;
        }
        offsets.push(total);
        let mut intervals = vec![Vec::new(); chroms.len()];
        for (k, (chrom, start, end, value)) in records.iter().enumerate() {
            let bad = |what: String| Error::Data(format!("{source}: record {}: {what}", k + 1));
            let Some(c) = chroms.iter().position(|c| &c.name == chrom) else {
                return Err(bad(format!(
                    "chromosome '{chrom}' is not among the map's chromosomes"
                )));
            };
            if start >= end || *end > chroms[c].length_bp {
                return Err(bad(format!(
                    "{start}-{end} is not an interval inside {chrom} ({} bp)",
                    chroms[c].length_bp
                )));
            }
            if !value.is_nan() {
                intervals[c].push((*start, *end, *value as f32));
            }
        }
        for (c, list) in intervals.iter_mut().enumerate() {
            list.sort_by_key(|&(start, end, _)| (start, end));
            if let Some(w) = list.windows(2).find(|w| w[1].0 < w[0].1) {
                return Err(Error::Data(format!(
                    "{source}: intervals {}-{} and {}-{} of {} overlap (a track holds one value \
                     per base, as a bigWig does)",
                    w[0].0, w[0].1, w[1].0, w[1].1, chroms[c].name
                )));
            }
        }
        let cover = total.div_ceil(VECTOR_TILE_SIZE).max(1);
        let depth = u64::BITS - (cover - 1).leading_zeros();
        Ok(Vector {
            chroms: chroms
                .iter()
                .map(|c| (c.name.clone(), c.length_bp))
                .collect(),
            offsets,
            depth,
            intervals,
        })
    }

    /// `tileset_info` as clodius' `bigwig.tileset_info`.
    pub fn info(&self) -> Value {
        let width = VECTOR_TILE_SIZE << self.depth;
        let modes = |pairs: &[(&str, &str)]| {
            pairs
                .iter()
                .map(|(name, value)| json!({"name": name, "value": value}))
                .collect::<Vec<_>>()
        };
        json!({
            "min_pos": [0],
            "max_pos": [width],
            "max_width": width,
            "tile_size": VECTOR_TILE_SIZE,
            "max_zoom": self.depth,
            "chromsizes": self.chroms.iter().map(|(n, l)| json!([n, l])).collect::<Vec<_>>(),
            "aggregation_modes": modes(&[("Mean", "mean"), ("Min", "min"), ("Max", "max"),
                ("Standard Deviation", "std"), ("Sum", "sum")]),
            "range_modes": modes(&[("Min-Max", "minMax"), ("Whisker", "whisker")]),
        })
    }

    /// Tile `x` of zoom level `zoom` (`None` past the last level).
    pub fn tile(&self, zoom: u32, x: u64, mode: Aggregation) -> Result<Option<Vec<f64>>> {
        if zoom > self.depth {
            return Ok(None);
        }
        let binsize = 1u64 << (self.depth - zoom);
        let span = VECTOR_TILE_SIZE * binsize;
        let start_pos = x
            .checked_mul(span)
            .filter(|s| s.checked_add(span).is_some())
            .ok_or_else(|| Error::Argument(format!("tile position {x} is out of range")))?;
        let end_pos = start_pos + span;
        let n = self.chroms.len();
        // clodius' abs2genomic: the chromosome holding each end (n past the genome's end)
        let chrom_of = |pos: u64| self.offsets.partition_point(|&o| o <= pos) - 1;
        let (lo, hi) = (chrom_of(start_pos), chrom_of(end_pos));
        let mut pieces = Vec::new();
        let mut start = start_pos - self.offsets[lo];
        for cid in lo..hi {
            pieces.push((cid, start, self.chroms[cid].1));
            start = 0;
        }
        pieces.push((hi, start, end_pos - self.offsets[hi]));
        let (mut data_position, mut binned_position) = (0u64, 0u64);
        let mut out = Vec::with_capacity(VECTOR_TILE_SIZE as usize);
        for (cid, start, end) in pieces {
            let n_bins = (end - start).div_ceil(binsize);
            let mut values = if cid >= n {
                vec![f64::NAN; n_bins as usize]
            } else {
                self.summarise(cid, start, end, n_bins, mode)
            };
            data_position += end - start;
            let (first, last) = (start / binsize, end.div_ceil(binsize));
            if first >= last {
                continue;
            }
            binned_position += binsize * (last - first);
            if binned_position - data_position > binsize {
                binned_position -= binsize;
                values.pop();
            }
            out.extend(values);
        }
        Ok(Some(out))
    }

    /// `n_bins` bins over `[start, end)` of chromosome `cid`, as pybigtools' `values`.
    fn summarise(
        &self,
        cid: usize,
        start: u64,
        end: u64,
        n_bins: u64,
        mode: Aggregation,
    ) -> Vec<f64> {
        let list = &self.intervals[cid];
        let length = end - start;
        let edge = |i: u64| start + (i as u128 * length as u128 / n_bins as u128) as u64;
        // intervals do not overlap: sorted by start, their ends ascend too
        let mut cursor = list.partition_point(|&(_, e, _)| e <= start);
        (0..n_bins)
            .map(|i| {
                let (a, b) = (edge(i), edge(i + 1));
                while cursor < list.len() && list[cursor].1 <= a {
                    cursor += 1;
                }
                let (mut sum, mut covered) = (0f64, 0u64);
                let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
                for &(s, e, v) in list[cursor..].iter().take_while(|&&(s, _, _)| s < b) {
                    let overlap = e.min(b) - s.max(a);
                    let v = v as f64;
                    sum += v * overlap as f64;
                    covered += overlap;
                    min = min.min(v);
                    max = max.max(v);
                }
                if covered == 0 {
                    return f64::NAN;
                }
                match mode {
                    Aggregation::Mean => sum / covered as f64,
                    Aggregation::Min => min,
                    Aggregation::Max => max,
                    Aggregation::Sum => sum,
                }
            })
            .collect()
    }
}
