//! Coverage: per bin, the sum of the raw counts of its row and column of the full (symmetric)
//! matrix, as cooltools 0.7.1 `coverage` computes it (`cov_cis_raw`, `cov_tot_raw`): each stored
//! pixel `(i, j)` counts for bin `i` and for bin `j` (a diagonal pixel twice), pixels with
//! `|j - i| < ignore_diags` left out; the cis coverage counts only pixels within a chromosome.
//! [`balanced_coverage`] sums balanced pixels instead (`cov_cis_<weight>`, `cov_tot_<weight>`):
//! a bin without a weight adds nothing to the others and its own coverage is NaN.

use crate::error::Result;
use crate::io::MatrixReader;

/// Cis and total coverage per bin.
#[derive(Clone, Debug, PartialEq)]
pub struct Coverage {
    /// From pixels within the bin's chromosome.
    pub cis: Vec<f64>,
    /// From every pixel.
    pub total: Vec<f64>,
}

/// The coverage of `reader`'s map (one pass over its pixels), raw counts.
///
/// # Examples
///
/// ```
/// use contactmap::compare::coverage::coverage;
/// use contactmap::io::{open_matrix, OpenOptions};
///
/// let reader = open_matrix("data/yeast.10kb.cool", &OpenOptions::default())?;
/// let cov = coverage(reader.as_ref(), 2)?;
/// // cooltools.coverage(clr, ignore_diags=2) of this map: its first bins
/// assert_eq!(cov.total[..3], [95292.0, 166004.0, 153147.0]);
/// assert_eq!(cov.cis[..3], [43489.0, 54205.0, 45077.0]);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn coverage(reader: &dyn MatrixReader, ignore_diags: usize) -> Result<Coverage> {
    sums(reader, ignore_diags, None)
}

/// The coverage of `reader`'s map balanced by `weights` (one per bin, NaN where a bin has
/// none): each pixel counts `count * w_i * w_j`, NaN weights as 0, and a bin with a NaN weight
/// has NaN coverage (cooltools `coverage(clr_weight_name=...)`).
///
/// ```
/// use contactmap::compare::coverage::{balanced_coverage, coverage};
/// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
///
/// let reader = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
/// let weights = reader.weights("weight")?.values;
/// let ones = vec![1.0; weights.len()];
/// // with weights of 1, the raw coverage
/// assert_eq!(balanced_coverage(reader.as_ref(), 2, &ones)?, coverage(reader.as_ref(), 2)?);
/// let balanced = balanced_coverage(reader.as_ref(), 2, &weights)?;
/// let k = weights.iter().position(|w| w.is_nan()).expect("a masked bin");
/// assert!(balanced.total[k].is_nan() && balanced.cis[k].is_nan());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn balanced_coverage(
    reader: &dyn MatrixReader,
    ignore_diags: usize,
    weights: &[f64],
) -> Result<Coverage> {
    let mut cov = sums(reader, ignore_diags, Some(weights))?;
    for (k, w) in weights.iter().enumerate() {
        if w.is_nan() {
            cov.cis[k] = f64::NAN;
            cov.total[k] = f64::NAN;
        }
    }
    Ok(cov)
}

/// Row-and-column sums of the pixels, balanced by `weights` (NaN as 0) when given.
fn sums(
    reader: &dyn MatrixReader,
    ignore_diags: usize,
    weights: Option<&[f64]>,
) -> Result<Coverage> {
    let bins = reader.bins();
    let weight = |k: usize| weights.map_or(1.0, |w| if w[k].is_nan() { 0.0 } else { w[k] });
    let n = bins.n_bins();
    let chrom_of: Vec<usize> = (0..n).map(|b| bins.chrom_of(b)).collect();
    let (mut cis, mut total) = (vec![0.0; n], vec![0.0; n]);
    reader.read_pixels(0..n, 0..n, &mut |block| {
        for k in 0..block.len() {
            let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
            if j.abs_diff(i) < ignore_diags {
                continue;
            }
            let count = weight(i) * weight(j) * block.count[k];
            total[i] += count;
            total[j] += count;
            if chrom_of[i] == chrom_of[j] {
                cis[i] += count;
                cis[j] += count;
            }
        }
        Ok(())
    })?;
    Ok(Coverage { cis, total })
}

/// The total of a map: the sum of its stored pixels (each contact once), raw, or balanced by
/// `weights` (pixels of a bin without a weight left out), for bringing two maps to one depth.
///
/// ```
/// use contactmap::compare::coverage::{balanced_coverage, total};
/// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
///
/// let reader = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
/// assert_eq!(total(reader.as_ref(), None)?, reader.totals()?.1);
/// // each contact counts twice in the coverage (once per bin)
/// let weights = reader.weights("weight")?.values;
/// let coverage: f64 = balanced_coverage(reader.as_ref(), 0, &weights)?
///     .total
///     .iter()
///     .filter(|v| !v.is_nan())
///     .sum();
/// let balanced = total(reader.as_ref(), Some(&weights))?;
/// assert!((2.0 * balanced - coverage).abs() < 1e-9 * coverage);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn total(reader: &dyn MatrixReader, weights: Option<&[f64]>) -> Result<f64> {
    let Some(weights) = weights else {
        return Ok(reader.totals()?.1);
    };
    let n = reader.bins().n_bins();
    let mut sum = 0.0;
    reader.read_pixels(0..n, 0..n, &mut |block| {
        for k in 0..block.len() {
            let value =
                weights[block.bin1[k] as usize] * weights[block.bin2[k] as usize] * block.count[k];
            if !value.is_nan() {
                sum += value;
            }
        }
        Ok(())
    })?;
    Ok(sum)
}
