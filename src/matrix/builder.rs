//! Build a [`ContactMatrix`] from `(bin1, bin2, count)` triplets.
//!
//! Pixels may come in any order and either triangle; the builder mirrors lower-triangle pixels to
//! the upper triangle, sorts and sums duplicates. What happens to pixels whose summed count is
//! zero is the caller's choice ([`ZeroCounts`]): a reader of a pixel table keeps them, as
//! `cooler load` does, while [`MatrixBuilder::build`] drops them.

use super::block::CountType;
use super::contact::ContactMatrix;
use super::weights::Weights;
use crate::error::{Error, Result};
use crate::genome::BinTable;

/// What [`MatrixBuilder::build_with`] does with a pixel whose summed count is zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ZeroCounts {
    /// Leave it out of the matrix (a computed matrix, where a zero is no contact).
    Drop,
    /// Store it as a pixel of count 0 (a pixel table that lists it explicitly, as `cooler load`
    /// keeps it).
    Keep,
}

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
            return Err(Error::Data(format!(
                "pixel ({bin1}, {bin2}) is out of range: the bin table has {n_bins} bins"
            )));
        }
        if !count.is_finite() {
            return Err(Error::Data(format!(
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
        super::weights::insert_weights(&mut self.weights, self.bins.n_bins(), weights)
    }

    /// Number of triplets pushed so far (before duplicates are summed).
    pub fn n_triplets(&self) -> usize {
        self.triplets.len()
    }

    /// Build the matrix straight from pixels already sorted by `(bin1, bin2)`, upper triangle,
    /// without repeats (as the pairs reader produces them): no triplet copy is held.
    pub fn from_sorted(
        bins: BinTable,
        count_type: CountType,
        pixels: impl ExactSizeIterator<Item = (u64, u64, f64)>,
    ) -> Result<ContactMatrix> {
        let n_bins = bins.n_bins();
        let mut row_offsets = vec![0usize; n_bins + 1];
        let mut bin2 = Vec::with_capacity(pixels.len());
        let mut counts = Vec::with_capacity(pixels.len());
        let mut last: Option<(u64, u64)> = None;
        for (i, j, count) in pixels {
            if i > j || j >= n_bins as u64 || last.is_some_and(|l| l >= (i, j)) {
                return Err(Error::Data(format!(
                    "pixel ({i}, {j}) is out of order, below the diagonal or out of range"
                )));
            }
            last = Some((i, j));
            row_offsets[i as usize + 1] += 1;
            bin2.push(j as u32);
            counts.push(count);
        }
        for i in 0..n_bins {
            row_offsets[i + 1] += row_offsets[i];
        }
        Ok(ContactMatrix {
            bins,
            row_offsets,
            bin2,
            counts,
            count_type,
            weights: Vec::new(),
        })
    }

    /// Sort, sum duplicates, drop the pixels whose summed count is zero and build the CSR matrix:
    /// [`build_with`](Self::build_with) with [`ZeroCounts::Drop`].
    pub fn build(self) -> ContactMatrix {
        self.build_with(ZeroCounts::Drop)
    }

    /// Sort, sum duplicates, keep or drop the pixels whose summed count is zero as `zeros` says,
    /// and build the CSR matrix.
    pub fn build_with(mut self, zeros: ZeroCounts) -> ContactMatrix {
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
            if zeros == ZeroCounts::Keep || counts[k] != 0.0 {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::Chrom;

    #[test]
    fn sorted_pixels_build_the_same_matrix_and_disorder_is_refused() {
        let bins = BinTable::fixed(vec![Chrom::new("a", 50), Chrom::new("b", 30)], 10).unwrap();
        let pixels = [
            (0u64, 0u64, 2.0),
            (0, 4, 1.0),
            (2, 3, 5.0),
            (5, 7, 1.0),
            (7, 7, 3.0),
        ];
        let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
        for &(i, j, c) in pixels.iter().rev() {
            builder.push(j, i, c).unwrap();
        }
        let sorted =
            MatrixBuilder::from_sorted(bins.clone(), CountType::Integer, pixels.iter().copied())
                .unwrap();
        assert_eq!(sorted, builder.build());
        let swapped = [(0u64, 4u64, 1.0), (0, 0, 2.0)];
        assert!(MatrixBuilder::from_sorted(bins, CountType::Integer, swapped.into_iter()).is_err());
    }

    /// Zero-count pixels in both triangles, one of them pushed twice, and one non-zero pixel.
    fn with_zeros() -> MatrixBuilder {
        let bins = BinTable::fixed(vec![Chrom::new("a", 30)], 10).unwrap();
        let mut builder = MatrixBuilder::new(bins, CountType::Integer);
        for (i, j, c) in [(0, 1, 0.0), (1, 0, 0.0), (2, 2, 3.0), (0, 0, 0.0)] {
            builder.push(i, j, c).unwrap();
        }
        builder
    }

    #[test]
    fn zero_pixels_are_dropped_or_kept_as_the_caller_says() {
        let dropped = with_zeros().build_with(ZeroCounts::Drop);
        let pixels = dropped.all_pixels();
        assert_eq!(
            (pixels.bin1, pixels.bin2, pixels.count),
            (vec![2], vec![2], vec![3.0])
        );
        assert_eq!(with_zeros().build(), dropped);
        let kept = with_zeros().build_with(ZeroCounts::Keep).all_pixels();
        assert_eq!(kept.bin1, vec![0, 0, 2]);
        assert_eq!(kept.bin2, vec![0, 1, 2]);
        assert_eq!(kept.count, vec![0.0, 0.0, 3.0]);
    }
}
