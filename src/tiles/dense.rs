//! One level's 256 x 256 tiles, computed as clodius' `make_tiles` / `get_data` do.
//!
//! clodius places a pixel by its bins' starts on the concatenated genome: column
//! `(genome_start1 - tile_start1) / resolution`, row likewise for the second bin. Chromosome
//! lengths are rarely multiples of the resolution, so at a chromosome's end two bins can fall in
//! one column; numpy's assignment keeps the last pixel written there, in the stored (bin1, bin2)
//! order, and so does this. A column is NaN when a bin placed in it has a NaN weight, and so is
//! every column from the genome's end on.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use crate::error::{Error, Result};
use crate::io::MatrixReader;

/// Bins along a tile's side.
pub const TILE_SIZE: usize = 256;

/// Weight columns read once per level.
type ColumnCache = Mutex<HashMap<String, Arc<Vec<f64>>>>;

/// One resolution of a tileset.
pub(super) struct Level {
    /// Bin size in base pairs.
    pub resolution: u64,
    pub reader: Box<dyn MatrixReader>,
    /// Each bin's start on the concatenated genome, ascending.
    starts: Vec<u64>,
    /// The genome's length.
    pub length: u64,
    /// The bin table's weight columns, as names.
    columns: Vec<String>,
    cache: ColumnCache,
}

/// Balancing by a weight column as clodius applies it: `count * w1 * w2` for cooler's
/// multiplicative `weight`, `count / w1 / w2` for the divisive KR, VC and VC_SQRT (hic2cool's
/// columns and a `.hic`'s norm vectors), each in that order in f64.
pub(super) struct Balance {
    /// The column's values as stored.
    pub weights: Arc<Vec<f64>>,
    pub divide: bool,
}

impl Level {
    pub fn new(resolution: u64, reader: Box<dyn MatrixReader>) -> Result<Level> {
        if resolution == 0 {
            return Err(Error::Argument(format!(
                "{}: a resolution of 0 bp",
                reader.source()
            )));
        }
        let bins = reader.bins();
        let mut offsets = Vec::with_capacity(bins.n_chroms());
        let mut length = 0u64;
        for chrom in bins.chroms() {
            offsets.push(length);
            length += chrom.length_bp;
        }
        let starts: Vec<u64> = bins
            .iter()
            .map(|bin| offsets[bin.chrom_id] + bin.start)
            .collect();
        let columns = reader.weight_names();
        Ok(Level {
            resolution,
            reader,
            starts,
            length,
            columns,
            cache: ColumnCache::default(),
        })
    }

    pub fn has_column(&self, name: &str) -> bool {
        self.columns.iter().any(|c| c == name)
    }

    /// Weight column `name` as stored, read once.
    pub fn column(&self, name: &str) -> Result<Arc<Vec<f64>>> {
        let mut cache = self.cache.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(values) = cache.get(name) {
            return Ok(values.clone());
        }
        let values = Arc::new(self.reader.stored_weights(name)?.values);
        if values.len() != self.starts.len() {
            return Err(Error::Data(format!(
                "{}: weight column '{name}' has {} values for {} bins",
                self.reader.source(),
                values.len(),
                self.starts.len()
            )));
        }
        cache.insert(name.to_string(), values.clone());
        Ok(values)
    }

    /// Tile `(x, y)`: see [`super::Tileset::tile`].
    pub fn tile(&self, x: u64, y: u64, balance: Option<&Balance>) -> Result<Vec<f32>> {
        let span = self.resolution * TILE_SIZE as u64;
        let start = |t: u64| {
            t.checked_mul(span)
                .filter(|s| s.checked_add(span).is_some())
                .ok_or_else(|| Error::Argument(format!("tile position {t} is out of range")))
        };
        let (start1, start2) = (start(x)?, start(y)?);
        let (rows, cols) = (self.bins_in(start1, span), self.bins_in(start2, span));
        let mut out = vec![0f32; TILE_SIZE * TILE_SIZE];
        let res = self.resolution;
        if !rows.is_empty() && !cols.is_empty() {
            self.reader
                .read_stored_pixels(rows.clone(), cols.clone(), &mut |block| {
                    for k in 0..block.len() {
                        let (b1, b2) = (block.bin1[k] as usize, block.bin2[k] as usize);
                        let column = ((self.starts[b1] - start1) / res) as usize;
                        let row = ((self.starts[b2] - start2) / res) as usize;
                        let count = block.count[k];
                        let value = match balance {
                            None => count,
                            Some(b) if b.divide => count / b.weights[b1] / b.weights[b2],
                            Some(b) => count * b.weights[b1] * b.weights[b2],
                        };
                        out[row * TILE_SIZE + column] = nan_to_num(value) as f32;
                    }
                    Ok(())
                })?;
        }
        // clodius masks when the transform has weights, and also when a tile starts past the
        // genome's end on either axis (its empty answer carries empty bin tables, not none).
        let past_end = start1 >= self.length || start2 >= self.length;
        if balance.is_some() || past_end {
            if let Some(b) = balance.filter(|_| !past_end) {
                for bin in rows.clone() {
                    if b.weights[bin].is_nan() {
                        let column = ((self.starts[bin] - start1) / res) as usize;
                        for row in 0..TILE_SIZE {
                            out[row * TILE_SIZE + column] = f32::NAN;
                        }
                    }
                }
                for bin in cols.clone() {
                    if b.weights[bin].is_nan() {
                        let row = ((self.starts[bin] - start2) / res) as usize;
                        out[row * TILE_SIZE..(row + 1) * TILE_SIZE].fill(f32::NAN);
                    }
                }
            }
            for column in self.past_end(start1) {
                for row in 0..TILE_SIZE {
                    out[row * TILE_SIZE + column] = f32::NAN;
                }
            }
            for row in self.past_end(start2) {
                out[row * TILE_SIZE..(row + 1) * TILE_SIZE].fill(f32::NAN);
            }
        }
        Ok(out)
    }

    /// The bins whose genome start lies in `[start, start + span)`.
    fn bins_in(&self, start: u64, span: u64) -> std::ops::Range<usize> {
        let first = self.starts.partition_point(|&s| s < start);
        let end = self.starts.partition_point(|&s| s < start + span);
        first..end
    }

    /// The tile's columns (or rows) clodius masks as past the genome's end when the tile starts
    /// at `start`: those holding a position `length + k * resolution` (k >= 0) of the tile.
    fn past_end(&self, start: u64) -> std::ops::Range<usize> {
        let (res, end) = (self.resolution, start + self.resolution * TILE_SIZE as u64);
        if self.length >= end {
            return 0..0;
        }
        // the first such position at or after the tile's start
        let first = if self.length >= start {
            self.length
        } else {
            self.length + (start - self.length).div_ceil(res) * res
        };
        if first >= end {
            return 0..0;
        }
        let column = ((first - start) / res) as usize;
        column..column + (end - first).div_ceil(res) as usize
    }
}

/// numpy's `nan_to_num`: NaN to 0, the infinities to the largest finite values.
fn nan_to_num(value: f64) -> f64 {
    if value.is_nan() {
        0.0
    } else if value == f64::INFINITY {
        f64::MAX
    } else if value == f64::NEG_INFINITY {
        f64::MIN
    } else {
        value
    }
}
