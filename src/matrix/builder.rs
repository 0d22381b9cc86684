//! Build a [`ContactMatrix`] from `(bin1, bin2, count)` triplets.
//!
//! Pixels may come in any order and either triangle; the builder mirrors lower-triangle pixels to
//! the upper triangle, sorts, sums duplicates and drops pixels whose summed count is zero.

use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::matrix::{ContactMatrix, CountType, Weights};

/// Collects triplets, then builds an immutable [`ContactMatrix`].
#[derive(Debug)]
pub struct MatrixBuilder {
    bins: BinTable,
    count_type: CountType,
    triplets: Vec<(u32, u32, f64)>,
    weights: Vec<Weights>,
}

impl MatrixBuilder {
    /// A builder for a matrix over `bins` with counts of type `count_type`.
    pub fn new(bins: BinTable, count_type: CountType) -> Self {
        MatrixBuilder {
            bins,
            count_type,
            triplets: Vec::new(),
            weights: Vec::new(),
        }
    }

    /// The bin table the pixels refer to.
    pub fn bins(&self) -> &BinTable {
        &self.bins
    }

    /// Mark counts as reals (e.g. when a non-integer count is seen).
    pub fn set_count_type(&mut self, count_type: CountType) {
        self.count_type = count_type;
    }

    /// Add one pixel; `(bin1, bin2)` may be in either triangle.
    pub fn push(&mut self, bin1: u64, bin2: u64, count: f64) -> Result<()> {
        let n_bins = self.bins.n_bins() as u64;
        if bin1 >= n_bins || bin2 >= n_bins {
            return Err(Error::Invalid(format!(
                "pixel ({bin1}, {bin2}) is out of range: the bin table has {n_bins} bins"
            )));
        }
        if !count.is_finite() {
            return Err(Error::Invalid(format!(
                "pixel ({bin1}, {bin2}) has a non-finite count {count}"
            )));
        }
        let (i, j) = if bin1 <= bin2 {
            (bin1, bin2)
        } else {
            (bin2, bin1)
        };
        self.triplets.push((i as u32, j as u32, count));
        Ok(())
    }

    /// Attach a weight column (one value per bin).
    pub fn add_weights(&mut self, weights: Weights) -> Result<()> {
        crate::matrix::insert_weights(&mut self.weights, self.bins.n_bins(), weights)
    }

    /// Number of triplets pushed so far (before duplicates are summed).
    pub fn n_triplets(&self) -> usize {
        self.triplets.len()
    }

    /// Sort, sum duplicates, drop zeros and build the CSR matrix.
    pub fn build(mut self) -> ContactMatrix {
        self.triplets.sort_unstable_by_key(|&(i, j, _)| (i, j));
        let n_bins = self.bins.n_bins();
        let mut row_offsets = vec![0usize; n_bins + 1];
        let mut bin2 = Vec::with_capacity(self.triplets.len());
        let mut counts = Vec::with_capacity(self.triplets.len());
        let mut rows = Vec::with_capacity(self.triplets.len());
        for &(i, j, c) in &self.triplets {
            if rows.last() == Some(&i) && bin2.last() == Some(&j) {
                *counts.last_mut().expect("a pixel was pushed") += c;
            } else {
                rows.push(i);
                bin2.push(j);
                counts.push(c);
            }
        }
        let mut kept = 0;
        for k in 0..counts.len() {
            if counts[k] != 0.0 {
                rows[kept] = rows[k];
                bin2[kept] = bin2[k];
                counts[kept] = counts[k];
                kept += 1;
            }
        }
        rows.truncate(kept);
        bin2.truncate(kept);
        counts.truncate(kept);
        for &i in &rows {
            row_offsets[i as usize + 1] += 1;
        }
        for i in 0..n_bins {
            row_offsets[i + 1] += row_offsets[i];
        }
        ContactMatrix {
            bins: self.bins,
            row_offsets,
            bin2,
            counts,
            count_type: self.count_type,
            weights: self.weights,
        }
    }
}
