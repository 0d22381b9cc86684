//! Juicer's expected-value vectors, as a `.hic` file stores them in its footer.
//!
//! # Method
//!
//! As Juicer's `ExpectedValueCalculation` computes them when it writes a `.hic` (hictk's writer
//! reproduces them; `CN.mm9` at 10 Mb agrees with hictk 2.2 to float32 precision, see the tests):
//!
//! - Every intra-chromosomal pixel adds its value (raw count, or normalised count with a
//!   normalisation vector; pixels with a non-finite value are skipped) to `actual[d]`,
//!   `d = bin2 - bin1`, and to its chromosome's total.
//! - Each chromosome that received a value has `n = floor(length / resolution)` bins (Juicer's
//!   count, which leaves out a last partial bin) and adds `n - d` to `possible[d]` for `d < n`.
//!   The vectors have `max n` entries; pixels at larger distances count only in the totals.
//! - `expected[d]` is `actual / possible` summed over a window around `d` that grows until it
//!   holds at least 400 contacts (5 % shot noise), Juicer's smoothing of sparse diagonals.
//! - Each chromosome gets the scale factor `sum_d (n - d) expected[d] / total`, so that a reader
//!   dividing the vector by it finds the chromosome's own total again (`expected / factor`, as
//!   straw and hictk read it).
//!
//! Chromosomes are identified by their index in the bin table; writers add Juicer's offset for
//! the `All` pseudo-chromosome themselves.

use rayon::prelude::*;

use crate::genome::BinTable;
use crate::matrix::{PixelBlock, PixelSlice};

/// Contacts a smoothing window must hold (Juicer's shot-noise minimum).
pub const SHOT_NOISE_MIN: f64 = 400.0;

/// One expected-value vector with its per-chromosome scale factors.
#[derive(Clone, Debug, PartialEq)]
pub struct JuicerExpected {
    /// The bin size the vector was computed at.
    pub resolution: u64,
    /// Expected value at each distance in bins.
    pub values: Vec<f64>,
    /// `(chromosome index in the bin table, scale factor)` for each chromosome with contacts.
    pub chrom_scale_factors: Vec<(usize, f64)>,
}

/// Accumulates intra-chromosomal values for one [`JuicerExpected`].
#[derive(Clone, Debug)]
pub struct JuicerExpectedBuilder {
    resolution: u64,
    /// Juicer's bin count of each chromosome (`floor(length / resolution)`).
    chrom_bins: Vec<usize>,
    actual: Vec<f64>,
    totals: Vec<f64>,
    seen: Vec<bool>,
}

impl JuicerExpectedBuilder {
    /// An empty accumulator for the chromosomes of `bins` (fixed-size bins of `resolution`).
    pub fn new(bins: &BinTable, resolution: u64) -> Self {
        let chrom_bins: Vec<usize> = bins
            .chroms()
            .iter()
            .map(|c| (c.length_bp / resolution) as usize)
            .collect();
        let n_max = chrom_bins.iter().copied().max().unwrap_or(0);
        JuicerExpectedBuilder {
            resolution,
            actual: vec![0.0; n_max],
            totals: vec![0.0; chrom_bins.len()],
            seen: vec![false; chrom_bins.len()],
            chrom_bins,
        }
    }

    /// Add one intra-chromosomal value at `distance` bins on chromosome `chrom`; non-finite
    /// values are skipped, as Juicer skips them.
    #[inline]
    pub fn add(&mut self, chrom: usize, distance: usize, value: f64) {
        if !value.is_finite() {
            return;
        }
        self.totals[chrom] += value;
        self.seen[chrom] = true;
        if let Some(slot) = self.actual.get_mut(distance) {
            *slot += value;
        }
    }

    /// Add the pixels of one chromosome, their bins counted from its first: raw counts, or
    /// `count / (v_i v_j)` with a divisive vector `divisive` (NaN values skipped).
    pub fn add_chrom_pixels(
        &mut self,
        chrom: usize,
        pixels: PixelSlice<'_>,
        divisive: Option<&[f64]>,
    ) {
        for k in 0..pixels.len() {
            let (i, j) = (pixels.bin1[k] as usize, pixels.bin2[k] as usize);
            let value = match divisive {
                Some(v) => pixels.count[k] / (v[i] * v[j]),
                None => pixels.count[k],
            };
            self.add(chrom, i.abs_diff(j), value);
        }
    }

    /// Add another accumulator's values (same genome and bin size).
    pub fn merge(&mut self, other: &JuicerExpectedBuilder) {
        for (a, b) in self.actual.iter_mut().zip(&other.actual) {
            *a += b;
        }
        for (a, b) in self.totals.iter_mut().zip(&other.totals) {
            *a += b;
        }
        for (a, b) in self.seen.iter_mut().zip(&other.seen) {
            *a |= b;
        }
    }

    /// The smoothed vector and the scale factors.
    pub fn finish(&self) -> JuicerExpected {
        let mut possible = vec![0.0f64; self.actual.len()];
        let mut n_max = 0;
        for (chrom, &n) in self.chrom_bins.iter().enumerate() {
            if !self.seen[chrom] {
                continue;
            }
            n_max = n_max.max(n);
            for (d, slot) in possible.iter_mut().enumerate().take(n) {
                *slot += (n - d) as f64;
            }
        }
        let actual = &self.actual[..n_max];
        let possible = &possible[..n_max];
        let mut values = vec![0.0; n_max];
        if n_max > 0 {
            // A window [low, high] kept centred on d: grown until it holds SHOT_NOISE_MIN
            // contacts, then shrunk from both ends while it still would.
            let (mut numerator, mut denominator) = (actual[0], possible[0]);
            let (mut low, mut high) = (0usize, 0usize);
            for value in values.iter_mut() {
                if numerator < SHOT_NOISE_MIN {
                    while numerator < SHOT_NOISE_MIN && high + 1 < n_max {
                        high += 1;
                        numerator += actual[high];
                        denominator += possible[high];
                    }
                } else if high > low {
                    while high > low && numerator - actual[low] - actual[high] >= SHOT_NOISE_MIN {
                        numerator -= actual[low] + actual[high];
                        denominator -= possible[low] + possible[high];
                        low += 1;
                        high -= 1;
                    }
                }
                *value = numerator / denominator;
                if high + 2 < n_max {
                    numerator += actual[high + 1] + actual[high + 2];
                    denominator += possible[high + 1] + possible[high + 2];
                    high += 2;
                } else if high + 1 < n_max {
                    numerator += actual[high + 1];
                    denominator += possible[high + 1];
                    high += 1;
                }
            }
        }
        let chrom_scale_factors = self
            .chrom_bins
            .iter()
            .enumerate()
            .filter(|&(chrom, _)| self.seen[chrom])
            .map(|(chrom, &n)| {
                let expected: f64 = values
                    .iter()
                    .take(n)
                    .enumerate()
                    .map(|(d, v)| (n - d) as f64 * v)
                    .sum();
                (chrom, expected / self.totals[chrom])
            })
            .collect();
        JuicerExpected {
            resolution: self.resolution,
            values,
            chrom_scale_factors,
        }
    }
}

/// Raw expected values at several resolutions at once, from the pixels of the finest one (a
/// pixel's distance at a coarser resolution is the distance of its coarse bins).
#[derive(Clone, Debug)]
pub struct MultiResolutionExpected {
    chrom_of: Vec<u32>,
    offsets: Vec<usize>,
    /// `(resolution / base bin size, accumulator)`.
    levels: Vec<(u64, JuicerExpectedBuilder)>,
}

impl MultiResolutionExpected {
    /// Accumulators for `resolutions` (multiples of the fixed bin size of `bins`).
    pub fn new(bins: &BinTable, resolutions: &[u64]) -> Self {
        let base = bins.resolution().unwrap_or(1);
        MultiResolutionExpected {
            chrom_of: (0..bins.n_bins())
                .map(|b| bins.chrom_of(b) as u32)
                .collect(),
            offsets: bins.chrom_offsets().to_vec(),
            levels: resolutions
                .iter()
                .map(|&r| (r / base, JuicerExpectedBuilder::new(bins, r)))
                .collect(),
        }
    }

    /// Add pixels of the base bins (genome-wide ids); the resolutions take them in parallel.
    pub fn add(&mut self, block: &PixelBlock) {
        let (chrom_of, offsets) = (&self.chrom_of, &self.offsets);
        self.levels.par_iter_mut().for_each(|(factor, builder)| {
            for k in 0..block.len() {
                let (b1, b2) = (block.bin1[k] as usize, block.bin2[k] as usize);
                let chrom = chrom_of.get(b1).copied();
                if chrom.is_none() || chrom != chrom_of.get(b2).copied() {
                    continue;
                }
                let chrom = chrom.unwrap_or_default() as usize;
                let offset = offsets[chrom];
                let (x, y) = (
                    (b1 - offset) as u64 / *factor,
                    (b2 - offset) as u64 / *factor,
                );
                builder.add(chrom, y.abs_diff(x) as usize, block.count[k]);
            }
        });
    }

    /// The vectors, one per resolution in the order given.
    pub fn finish(&self) -> Vec<JuicerExpected> {
        self.levels
            .iter()
            .map(|(_, builder)| builder.finish())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::Chrom;

    fn genome() -> BinTable {
        BinTable::fixed(vec![Chrom::new("a", 1050), Chrom::new("b", 600)], 100).unwrap()
    }

    #[test]
    fn dense_diagonals_are_plain_averages_and_factors_give_back_the_totals() {
        // Every diagonal holds >= 400 contacts: no smoothing window, but for the last one.
        let bins = genome();
        let mut builder = JuicerExpectedBuilder::new(&bins, 100);
        let mut totals = [0.0; 2];
        for (chrom, n) in [(0usize, 10usize), (1, 6)] {
            for i in 0..n {
                for j in i..n {
                    let value = 100_000.0 / (1.0 + (j - i) as f64) + (i % 3) as f64;
                    builder.add(chrom, j - i, value);
                    totals[chrom] += value;
                }
            }
        }
        let expected = builder.finish();
        assert_eq!(expected.values.len(), 10);
        // sum and possible pixels of diagonal d over both chromosomes
        let diagonal = |d: usize| {
            let (mut sum, mut possible) = (0.0, 0.0);
            for n in [10usize, 6] {
                if d < n {
                    possible += (n - d) as f64;
                    for i in 0..n - d {
                        sum += 100_000.0 / (1.0 + d as f64) + (i % 3) as f64;
                    }
                }
            }
            (sum, possible)
        };
        for d in 0..9 {
            let (sum, possible) = diagonal(d);
            approx::assert_relative_eq!(expected.values[d], sum / possible, max_relative = 1e-12);
        }
        // Juicer's window cannot stay centred on the last diagonal: it keeps the one before.
        let ((s8, p8), (s9, p9)) = (diagonal(8), diagonal(9));
        approx::assert_relative_eq!(
            expected.values[9],
            (s8 + s9) / (p8 + p9),
            max_relative = 1e-12
        );
        for &(chrom, factor) in &expected.chrom_scale_factors {
            let n = [10usize, 6][chrom];
            let back: f64 = (0..n)
                .map(|d| (n - d) as f64 * expected.values[d])
                .sum::<f64>()
                / factor;
            approx::assert_relative_eq!(back, totals[chrom], max_relative = 1e-12);
        }
    }

    #[test]
    fn sparse_diagonals_are_averaged_over_a_window_of_400_contacts() {
        // One chromosome of 10 bins, 100 contacts on each diagonal (plus NaN, skipped):
        // d = 0 needs diagonals 0..=3 (400 contacts), the window then stays centred.
        let bins = BinTable::fixed(vec![Chrom::new("a", 1000)], 100).unwrap();
        let mut builder = JuicerExpectedBuilder::new(&bins, 100);
        for d in 0..10 {
            builder.add(0, d, 100.0);
            builder.add(0, d, f64::NAN);
        }
        let expected = builder.finish();
        let possible = |d: usize| (10 - d) as f64;
        let window = |lo: usize, hi: usize| {
            (lo..=hi).map(|_| 100.0).sum::<f64>() / (lo..=hi).map(possible).sum::<f64>()
        };
        assert_eq!(expected.values[0], window(0, 3));
        // d = 1: the window grew by two to [0, 5]; 600 contacts, shrinking both ends leaves
        // [1, 4] (400).
        assert_eq!(expected.values[1], window(1, 4));
        assert_eq!(expected.values[2], window(2, 5));
        assert_eq!(expected.chrom_scale_factors.len(), 1);
    }

    #[test]
    fn chromosomes_without_contacts_add_no_possible_pixels_and_no_factor() {
        let bins = genome();
        let mut builder = JuicerExpectedBuilder::new(&bins, 100);
        builder.add(1, 0, 500.0);
        let expected = builder.finish();
        // only chromosome b (6 bins) counts
        assert_eq!(expected.values.len(), 6);
        assert_eq!(expected.chrom_scale_factors.len(), 1);
        assert_eq!(expected.chrom_scale_factors[0].0, 1);
    }
}
