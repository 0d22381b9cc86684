//! The sparse contact matrix held in memory (upper triangle in compressed sparse rows).

use std::ops::Range;

use ndarray::Array2;

use super::block::{CountType, PixelBlock};
use super::weights::{Weights, insert_weights};
use crate::error::Result;
use crate::genome::BinTable;

/// A symmetric contact matrix held in memory: bins, upper-triangle pixels in CSR, weights.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactMatrix {
    pub(super) bins: BinTable,
    /// `row_offsets[i]..row_offsets[i + 1]` are the pixels of row `i`.
    pub(super) row_offsets: Vec<usize>,
    pub(super) bin2: Vec<u32>,
    pub(super) counts: Vec<f64>,
    pub(super) count_type: CountType,
    pub(super) weights: Vec<Weights>,
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
