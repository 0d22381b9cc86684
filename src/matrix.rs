//! The sparse contact matrix and the pixel blocks that readers stream.
//!
//! A [`ContactMatrix`] stores the upper triangle (`bin1 <= bin2`) of a symmetric genome-wide
//! matrix in compressed sparse rows, as cooler's `symmetric-upper` storage mode does, together with
//! its bin table and any number of named per-bin weight columns. It is built once by a
//! [`MatrixBuilder`] (which sums duplicate pixels) and is immutable afterwards.
//!
//! Large files are not loaded into a `ContactMatrix`: readers stream [`PixelBlock`]s sorted by
//! `(bin1, bin2)`, so that a whole-genome 10 kb map can be dumped or converted with bounded memory.

pub mod builder;
pub mod pixels;

use std::ops::Range;

use ndarray::Array2;

use crate::error::{Error, Result};
use crate::genome::BinTable;
pub use builder::{MatrixBuilder, ZeroCounts};
pub use pixels::{PixelSlice, PixelSource, Pixels};

/// How counts are stored: integers (raw read counts) or floating point (already normalised).
///
/// Counts are held as `f64` in memory either way (every 32-bit integer is exact in an `f64`); the
/// type decides how they are written back (cooler's `int32` or `float64` `count` column) and printed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CountType {
    /// Whole numbers (cooler `int32`).
    Integer,
    /// Real numbers (cooler `float64`).
    Float,
}

/// A block of pixels in columnar layout, sorted by `(bin1, bin2)` with `bin1 <= bin2`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PixelBlock {
    /// Row bin ids (genome-wide).
    pub bin1: Vec<u64>,
    /// Column bin ids (genome-wide).
    pub bin2: Vec<u64>,
    /// Counts.
    pub count: Vec<f64>,
}

impl PixelBlock {
    /// An empty block with room for `capacity` pixels.
    pub fn with_capacity(capacity: usize) -> Self {
        PixelBlock {
            bin1: Vec::with_capacity(capacity),
            bin2: Vec::with_capacity(capacity),
            count: Vec::with_capacity(capacity),
        }
    }

    /// Number of pixels.
    pub fn len(&self) -> usize {
        self.count.len()
    }

    /// True when the block holds no pixel.
    pub fn is_empty(&self) -> bool {
        self.count.is_empty()
    }

    /// Append one pixel.
    pub fn push(&mut self, bin1: u64, bin2: u64, count: f64) {
        self.bin1.push(bin1);
        self.bin2.push(bin2);
        self.count.push(count);
    }

    /// Remove every pixel, keeping the allocations.
    pub fn clear(&mut self) {
        self.bin1.clear();
        self.bin2.clear();
        self.count.clear();
    }

    /// Keep only the pixels `(bin1, bin2, count)` for which `keep` is true, in order.
    pub fn retain(&mut self, keep: impl Fn(u64, u64, f64) -> bool) {
        let mut kept = 0;
        for k in 0..self.len() {
            if keep(self.bin1[k], self.bin2[k], self.count[k]) {
                self.bin1[kept] = self.bin1[k];
                self.bin2[kept] = self.bin2[k];
                self.count[kept] = self.count[k];
                kept += 1;
            }
        }
        self.bin1.truncate(kept);
        self.bin2.truncate(kept);
        self.count.truncate(kept);
    }

    /// Keep only the pixels of the upper triangle (`bin2 >= bin1`).
    pub fn retain_upper(&mut self) {
        self.retain(|bin1, bin2, _| bin2 >= bin1);
    }

    /// Keep only the pixels whose `bin2` lies in `cols`.
    pub fn retain_cols(&mut self, cols: &Range<u64>) {
        self.retain(|_, bin2, _| cols.contains(&bin2));
    }
}

/// A named per-bin weight column, in cooler's multiplicative convention:
/// `balanced[i, j] = count[i, j] * weight[i] * weight[j]`; `NaN` marks a masked bin.
#[derive(Clone, Debug, PartialEq)]
pub struct Weights {
    /// Column name (`weight`, `KR`, `VC`, `SCALE` ...).
    pub name: String,
    /// One value per bin.
    pub values: Vec<f64>,
    /// How the values were obtained, when they were not stored multiplicatively (e.g. ".hic KR
    /// vector, divisive: inverted on read").
    pub provenance: Option<String>,
}

impl Weights {
    /// Build multiplicative weights from a divisive vector (Juicer / hic2cool convention:
    /// `balanced = count / (v[i] * v[j])`). Zero, negative and non-finite entries become `NaN`.
    pub fn from_divisive(name: impl Into<String>, divisive: &[f64], provenance: String) -> Self {
        Weights {
            name: name.into(),
            values: divisive.iter().map(|&v| invert_weight(v)).collect(),
            provenance: Some(provenance),
        }
    }
}

/// Convert one weight between the divisive and multiplicative conventions: `1 / w`, with zero,
/// negative and non-finite weights (masked bins) becoming `NaN`.
pub fn invert_weight(weight: f64) -> f64 {
    if weight.is_finite() && weight > 0.0 {
        1.0 / weight
    } else {
        f64::NAN
    }
}

/// Add `weights` to `columns`, replacing a column of the same name; its length must be `n_bins`.
pub(crate) fn insert_weights(
    columns: &mut Vec<Weights>,
    n_bins: usize,
    weights: Weights,
) -> Result<()> {
    if weights.values.len() != n_bins {
        return Err(Error::Invalid(format!(
            "weight column '{}' has {} values for {n_bins} bins",
            weights.name,
            weights.values.len()
        )));
    }
    columns.retain(|w| w.name != weights.name);
    columns.push(weights);
    Ok(())
}

/// A symmetric contact matrix held in memory: bins, upper-triangle pixels in CSR, weights.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactMatrix {
    bins: BinTable,
    /// `row_offsets[i]..row_offsets[i + 1]` are the pixels of row `i`.
    row_offsets: Vec<usize>,
    bin2: Vec<u32>,
    counts: Vec<f64>,
    count_type: CountType,
    weights: Vec<Weights>,
}

impl ContactMatrix {
    /// The bin table.
    pub fn bins(&self) -> &BinTable {
        &self.bins
    }

    /// Number of stored (upper-triangle, non-zero) pixels.
    pub fn nnz(&self) -> usize {
        self.counts.len()
    }

    /// Sum of stored counts (each off-diagonal pixel counted once, as `cooler info` does).
    pub fn sum(&self) -> f64 {
        self.counts.iter().sum()
    }

    /// Whether counts are integers or reals.
    pub fn count_type(&self) -> CountType {
        self.count_type
    }

    /// The pixels of row `bin1`: column ids (ascending) and counts.
    pub fn row(&self, bin1: usize) -> (&[u32], &[f64]) {
        let range = self.row_offsets[bin1]..self.row_offsets[bin1 + 1];
        (&self.bin2[range.clone()], &self.counts[range])
    }

    /// CSR row offsets (`n_bins + 1` entries), as cooler's `indexes/bin1_offset`.
    pub fn row_offsets(&self) -> &[usize] {
        &self.row_offsets
    }

    /// The stored count at `(bin1, bin2)` in either triangle (0 when absent).
    pub fn get(&self, bin1: usize, bin2: usize) -> f64 {
        let (i, j) = if bin1 <= bin2 {
            (bin1, bin2)
        } else {
            (bin2, bin1)
        };
        let (cols, counts) = self.row(i);
        match cols.binary_search(&(j as u32)) {
            Ok(k) => counts[k],
            Err(_) => 0.0,
        }
    }

    /// Weight columns.
    pub fn weights(&self) -> &[Weights] {
        &self.weights
    }

    /// The weight column called `name`.
    pub fn weight(&self, name: &str) -> Option<&Weights> {
        self.weights.iter().find(|w| w.name == name)
    }

    /// Add or replace a weight column (its length must equal the number of bins).
    pub fn set_weights(&mut self, weights: Weights) -> Result<()> {
        insert_weights(&mut self.weights, self.bins.n_bins(), weights)
    }

    /// The stored pixels with `bin1` in `rows` and `bin2` in `cols` (upper triangle only, as
    /// `cooler dump --range --range2` without `--fill-lower`), sorted by `(bin1, bin2)`.
    pub fn pixels_in(&self, rows: Range<usize>, cols: Range<usize>) -> PixelBlock {
        let mut block = PixelBlock::default();
        for bin1 in rows {
            let (bin2s, counts) = self.row_window(bin1, &cols);
            for (&bin2, &count) in bin2s.iter().zip(counts) {
                block.push(bin1 as u64, bin2 as u64, count);
            }
        }
        block
    }

    /// The pixels of row `bin1` whose column lies in `cols`: column ids and counts.
    pub fn row_window(&self, bin1: usize, cols: &Range<usize>) -> (&[u32], &[f64]) {
        let (bin2s, counts) = self.row(bin1);
        let lo = bin2s.partition_point(|&c| (c as usize) < cols.start);
        let hi = bin2s.partition_point(|&c| (c as usize) < cols.end);
        (&bin2s[lo..hi], &counts[lo..hi])
    }

    /// Dense view of the rectangle `rows x cols`, with both triangles filled from the stored upper
    /// triangle (the full symmetric matrix, as `cooler.Cooler.matrix(balance=False)`).
    pub fn dense(&self, rows: Range<usize>, cols: Range<usize>) -> Array2<f64> {
        let mut out = Array2::zeros((rows.len(), cols.len()));
        // A stored pixel (i, j), i <= j, lands at (i, j) and at its mirror (j, i).
        let first = rows.start.min(cols.start);
        let last = rows.end.max(cols.end).min(self.bins.n_bins());
        for i in first..last {
            let (bin2s, counts) = self.row(i);
            for (&c, &v) in bin2s.iter().zip(counts) {
                let j = c as usize;
                if rows.contains(&i) && cols.contains(&j) {
                    out[[i - rows.start, j - cols.start]] = v;
                }
                if i != j && rows.contains(&j) && cols.contains(&i) {
                    out[[j - rows.start, i - cols.start]] = v;
                }
            }
        }
        out
    }

    /// All pixels, sorted, as one block.
    pub fn all_pixels(&self) -> PixelBlock {
        self.pixels_in(0..self.bins.n_bins(), 0..self.bins.n_bins())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::Chrom;

    fn small() -> ContactMatrix {
        let bins = BinTable::fixed(vec![Chrom::new("a", 30), Chrom::new("b", 20)], 10).unwrap();
        let mut b = MatrixBuilder::new(bins, CountType::Integer);
        for &(i, j, c) in &[
            (0, 0, 1.0),
            (0, 2, 2.0),
            (2, 0, 3.0),
            (1, 4, 4.0),
            (4, 4, 5.0),
        ] {
            b.push(i, j, c).unwrap();
        }
        b.build()
    }

    #[test]
    fn builder_sums_duplicates_and_mirrors_lower_pixels() {
        let m = small();
        assert_eq!(m.nnz(), 4);
        assert_eq!(m.sum(), 15.0);
        assert_eq!(m.get(0, 2), 5.0);
        assert_eq!(m.get(2, 0), 5.0);
        assert_eq!(m.get(1, 1), 0.0);
        assert_eq!(m.row_offsets(), &[0, 2, 3, 3, 3, 4]);
    }

    #[test]
    fn dense_view_is_symmetric() {
        let m = small();
        let d = m.dense(0..5, 0..5);
        for i in 0..5 {
            for j in 0..5 {
                assert_eq!(d[[i, j]], d[[j, i]]);
                assert_eq!(d[[i, j]], m.get(i, j));
            }
        }
        let r = m.dense(3..5, 0..2);
        assert_eq!(r[[1, 1]], 4.0);
        assert_eq!(r[[0, 0]], 0.0);
    }

    #[test]
    fn rectangle_query_keeps_the_upper_triangle() {
        let m = small();
        let p = m.pixels_in(0..2, 2..5);
        assert_eq!(p.bin1, vec![0, 1]);
        assert_eq!(p.bin2, vec![2, 4]);
        assert_eq!(p.count, vec![5.0, 4.0]);
    }

    #[test]
    fn divisive_weights_are_inverted() {
        let w = Weights::from_divisive("KR", &[2.0, 0.0, f64::NAN, 0.5], "test".into());
        assert_eq!(w.values[0], 0.5);
        assert!(w.values[1].is_nan() && w.values[2].is_nan());
        assert_eq!(w.values[3], 2.0);
    }
}
