//! Compartment eigenvectors of the genome-wide inter-chromosomal map (cooltools' `trans_eig`).
//!
//! Step for step as cooltools 0.7.1 (`eigs_trans` with its defaults):
//!
//! 1. `A`: the balanced genome-wide matrix with its cis blocks set to 0. Bins whose trans
//!    column sums to 0 (or has no weight) are bad: their rows and columns are 0.
//! 2. Trans values of good pairs above the 99.95th percentile of all good trans pairs (zeros
//!    included) are clipped to it; bins whose trans coverage is above 0 but below the 1st
//!    percentile of the non-zero coverages are dropped (bad).
//! 3. Twice: each cis entry `(i, j)`, `i <= j`, of good bins is replaced by a value drawn from
//!    the good trans entries of row `i` or row `j` ("fake cis"), then the whole matrix is balanced by
//!    cooltools' damped iterative correction (`iterative_correction_symmetric`: up to 1000
//!    rounds, until the variance of the round's factors is below 1e-5). The draws use the C
//!    library's `random()` from its default seed, as cooltools' compiled `fake_cis` does, in
//!    the same order, so the filled values are the same ([`GlibcRandom`]).
//! 4. `O = (A - mean) / mean` (mean over good pairs), 0 on bad rows; the eigenpairs of largest
//!    magnitude, vectors scaled to norm `sqrt(|eigenvalue|)`.
//!
//! The matrix is dense (`8 n^2` bytes for `n` bins, as in cooltools): trans compartments are a
//! low-resolution analysis (1 Mb: 3,000 bins for a mammal, 72 MB).

use rayon::prelude::*;

use crate::compartments::cis::RegionEigs;
use crate::compartments::eigen::{self, SymmetricOperator};
use crate::error::{Error, Result};
use crate::numeric::quantile_of_sorted;

/// Parameters of [`trans_eig`], with cooltools' defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransEigParams {
    /// Eigenvectors to compute (cooltools: 3).
    pub n_eigs: usize,
    /// Trans values above this percentile are clipped (cooltools: 99.95).
    pub perc_top: f64,
    /// Bins with trans coverage below this percentile of the non-zero ones are dropped
    /// (cooltools: 1).
    pub perc_bottom: f64,
}

impl TransEigParams {
    /// Check the values: at least one eigenvector, percentiles in 0..=100.
    pub fn check(&self) -> crate::error::Result<()> {
        if self.n_eigs == 0 {
            return Err(crate::error::Error::parameter(
                "n_eigs",
                0,
                "expected at least 1",
            ));
        }
        for (name, value) in [
            ("perc_top", self.perc_top),
            ("perc_bottom", self.perc_bottom),
        ] {
            if !(0.0..=100.0).contains(&value) {
                return Err(crate::error::Error::parameter(
                    name,
                    value,
                    "expected a percentile in 0..100",
                ));
            }
        }
        Ok(())
    }
}

impl Default for TransEigParams {
    fn default() -> Self {
        TransEigParams {
            n_eigs: 3,
            perc_top: 99.95,
            perc_bottom: 1.0,
        }
    }
}

/// The C library's `random()` from its default state, `srandom(1)`: glibc's additive feedback
/// generator (`TYPE_3`), `r[i] = r[i - 3] + r[i - 31]` (wrapping), output `r[i] >> 1`.
#[derive(Clone, Debug)]
pub struct GlibcRandom {
    ring: [u32; 34],
    at: u64,
}

impl GlibcRandom {
    /// The state after `srandom(seed)`.
    pub fn new(seed: u32) -> Self {
        let mut r = [0i64; 31];
        r[0] = if seed == 0 { 1 } else { seed as i64 };
        for i in 1..31 {
            // 16807 * r[i - 1] % 2147483647 without overflow (Schrage), as glibc computes it
            let hi = r[i - 1] / 127773;
            let lo = r[i - 1] % 127773;
            let mut word = 16807 * lo - 2836 * hi;
            if word < 0 {
                word += 2147483647;
            }
            r[i] = word;
        }
        let mut ring = [0u32; 34];
        for i in 0..34 {
            ring[i] = r[i % 31] as u32;
        }
        let mut g = GlibcRandom { ring, at: 34 };
        // glibc discards the first 310 outputs
        for _ in 34..344 {
            g.step();
        }
        g
    }

    fn step(&mut self) -> u32 {
        let i = self.at;
        let value =
            self.ring[((i - 31) % 34) as usize].wrapping_add(self.ring[((i - 3) % 34) as usize]);
        self.ring[(i % 34) as usize] = value;
        self.at += 1;
        value
    }

    /// The next `random()`: 31 bits.
    pub fn random(&mut self) -> u32 {
        self.step() >> 1
    }
}

impl Default for GlibcRandom {
    fn default() -> Self {
        GlibcRandom::new(1)
    }
}

/// A dense symmetric matrix, row-major.
#[derive(Clone, Debug)]
pub struct DenseMatrix {
    n: usize,
    values: Vec<f64>,
}

impl DenseMatrix {
    /// An `n x n` matrix of zeros, or an error when it would not fit in `max_bytes`.
    pub fn zeros(n: usize, max_bytes: u64) -> Result<Self> {
        let bytes = (n as u64) * (n as u64) * 8;
        if bytes > max_bytes {
            return Err(Error::Unsupported(format!(
                "trans eigenvectors need the genome-wide matrix dense ({n} bins: {:.1} GB, more than the {:.1} GB available): use a coarser resolution (trans compartments are computed at 250 kb to 1 Mb)",
                bytes as f64 / 1e9,
                max_bytes as f64 / 1e9
            )));
        }
        Ok(DenseMatrix {
            n,
            values: vec![0.0; n * n],
        })
    }

    /// Set `(i, j)` and `(j, i)`.
    pub fn set(&mut self, i: usize, j: usize, value: f64) {
        self.values[i * self.n + j] = value;
        self.values[j * self.n + i] = value;
    }

    /// Replace every entry `(i, j)` by `f(i, j, value)`, rows in parallel.
    fn update(&mut self, f: impl Fn(usize, usize, f64) -> f64 + Sync) {
        let n = self.n.max(1);
        self.values
            .par_chunks_mut(n)
            .enumerate()
            .for_each(|(i, row)| {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = f(i, j, *v);
                }
            });
    }

    /// Zero the rows and columns of the bins `masked`.
    fn zero_masked(&mut self, masked: &[bool]) {
        self.update(|i, j, v| if masked[i] || masked[j] { 0.0 } else { v });
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.values[i * self.n + j]
    }

    fn row_sums(&self) -> Vec<f64> {
        self.values
            .par_chunks(self.n.max(1))
            .map(|row| row.iter().sum())
            .collect()
    }
}

/// numpy's `percentile(values, p)` (linear interpolation) of `values`, sorted in place.
fn percentile(values: &mut [f64], p: f64) -> f64 {
    values.par_sort_unstable_by(f64::total_cmp);
    quantile_of_sorted(values, p / 100.0)
}

/// cooltools' `fake_cis`: every cis entry `(i, j)`, `i <= j`, of good bins takes the value of a
/// trans entry of row `i` or row `j` (a coin, `random() % 2`), at column `random() % n`, drawn
/// again until that column is a good bin of another chromosome.
fn fake_cis(a: &mut DenseMatrix, chrom_of: &[u32], rng: &mut GlibcRandom) {
    let n = a.n;
    let sums = a.row_sums();
    // cooltools' mask: 1 cis, 0 trans, 2 on the rows and columns of empty bins
    let empty: Vec<bool> = sums.iter().map(|s| s.abs() <= 1e-10).collect();
    for i in 0..n {
        if empty[i] {
            continue;
        }
        for j in i..n {
            if chrom_of[j] != chrom_of[i] || empty[j] {
                continue;
            }
            loop {
                let row = if rng.random().is_multiple_of(2) { i } else { j };
                let s = rng.random() as usize % n;
                if chrom_of[s] != chrom_of[row] && !empty[s] {
                    let v = a.at(row, s);
                    a.set(i, j, v);
                    break;
                }
            }
        }
    }
}

/// cooltools' `iterative_correction_symmetric` (numba, damped by 0.8; variance criterion).
fn iterative_correction(a: &mut DenseMatrix, max_iter: usize, tol: f64) {
    let n = a.n;
    let mut total = vec![1.0f64; n];
    let mut mask = vec![false; n];
    for _ in 0..max_iter {
        let sums = a.row_sums();
        mask = sums.iter().map(|&s| s == 0.0).collect();
        let good: Vec<f64> = sums
            .iter()
            .zip(&mask)
            .filter(|(_, m)| !**m)
            .map(|(s, _)| *s)
            .collect();
        let mean = good.iter().sum::<f64>() / good.len() as f64;
        let s: Vec<f64> = sums
            .iter()
            .zip(&mask)
            .map(|(&v, &m)| {
                let v = if m { 1.0 } else { v / mean };
                (v - 1.0) * 0.8 + 1.0
            })
            .collect();
        for (t, f) in total.iter_mut().zip(&s) {
            *t *= f;
        }
        a.update(|i, j, v| v / (s[i] * s[j]));
        let m = s.iter().sum::<f64>() / n as f64;
        let var = s.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / n as f64;
        if tol > 0.0 && var < tol {
            break;
        }
    }
    let good: Vec<f64> = total
        .iter()
        .zip(&mask)
        .filter(|(_, m)| !**m)
        .map(|(t, _)| *t)
        .collect();
    let corr = good.iter().sum::<f64>() / good.len().max(1) as f64;
    let factor = corr * corr;
    a.values.par_iter_mut().for_each(|v| *v *= factor);
}

/// The centred matrix restricted to its good bins.
struct Centred<'a> {
    a: &'a DenseMatrix,
    good: Vec<usize>,
    mean: f64,
}

impl SymmetricOperator for Centred<'_> {
    fn dim(&self) -> usize {
        self.good.len()
    }

    fn apply(&self, x: &[f64], y: &mut [f64]) {
        let sum_x: f64 = x.iter().sum();
        y.par_iter_mut().enumerate().for_each(|(k, out)| {
            let row = &self.a.values[self.good[k] * self.a.n..];
            let dot: f64 = self.good.iter().zip(x).map(|(&j, &xj)| row[j] * xj).sum();
            *out = dot / self.mean - sum_x;
        });
    }
}

/// cooltools' `trans_eig` on the balanced genome-wide matrix `a` (NaN-free: 0 for bins without
/// a weight), `chrom_of[i]` the chromosome of bin `i` (see the module documentation).
pub fn trans_eig(mut a: DenseMatrix, chrom_of: &[u32], params: &TransEigParams) -> RegionEigs {
    let n = a.n;
    // 1. cis blocks out; bad bins out
    a.update(|i, j, v| {
        if chrom_of[i] == chrom_of[j] || !v.is_finite() {
            0.0
        } else {
            v
        }
    });
    let zero_bad = |a: &mut DenseMatrix| -> Vec<bool> {
        let bad: Vec<bool> = a.row_sums().iter().map(|&s| s == 0.0).collect();
        a.zero_masked(&bad);
        bad
    };
    let bad = zero_bad(&mut a);
    // 2. clip trans blowouts, drop low-coverage bins
    let mut trans_values: Vec<f64> = Vec::new();
    for i in 0..n {
        for j in 0..n {
            if !bad[i] && !bad[j] && chrom_of[i] != chrom_of[j] {
                trans_values.push(a.at(i, j));
            }
        }
    }
    if trans_values.is_empty() {
        return RegionEigs::nan(params.n_eigs, n);
    }
    let limit = percentile(&mut trans_values, params.perc_top);
    drop(trans_values);
    a.update(|i, j, v| {
        if !bad[i] && !bad[j] && chrom_of[i] != chrom_of[j] && v > limit {
            limit
        } else {
            v
        }
    });
    let margins = a.row_sums();
    let mut nonzero: Vec<f64> = margins.iter().copied().filter(|&m| m > 0.0).collect();
    let cutoff = percentile(&mut nonzero, params.perc_bottom);
    let dropped: Vec<bool> = margins.iter().map(|&m| m > 0.0 && m < cutoff).collect();
    a.zero_masked(&dropped);
    let bad = zero_bad(&mut a);
    // 3. fake cis and balance, twice
    let mut rng = GlibcRandom::default();
    for _ in 0..2 {
        fake_cis(&mut a, chrom_of, &mut rng);
        iterative_correction(&mut a, 1000, 1e-5);
    }
    // 4. centre by the mean over good pairs
    let good: Vec<usize> = (0..n).filter(|&i| !bad[i]).collect();
    let total: f64 = good
        .par_iter()
        .map(|&i| good.iter().map(|&j| a.at(i, j)).sum::<f64>())
        .sum();
    let mean = total / (good.len() * good.len()) as f64;
    let operator = Centred { a: &a, good, mean };
    let dim = operator.dim();
    let k = params.n_eigs.min(dim.saturating_sub(1));
    let solved = eigen::largest_magnitude(&operator, k);
    RegionEigs::from_eigenpairs(params.n_eigs, n, &operator.good, &solved)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glibc_random_default_sequence() {
        // the first outputs of glibc's random() without srandom (printf("%ld", random()))
        let mut g = GlibcRandom::default();
        let first: Vec<u32> = (0..5).map(|_| g.random()).collect();
        assert_eq!(
            first,
            vec![1804289383, 846930886, 1681692777, 1714636915, 1957747793]
        );
    }
}
