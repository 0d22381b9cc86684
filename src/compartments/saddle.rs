//! The saddle of a track: digitisation, sums and counts of observed/expected by class pair, and
//! the saddle strength (see the [module documentation](super)).

use crate::error::{Error, Result};
use crate::genome::View;
use crate::matrix::{PixelSlice, PixelSource};
use crate::numeric::{linspace, quantile_of_sorted};

/// How the track's class edges are placed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Binning {
    /// Quantiles `lo..hi` of the track values (fractions in `0..=1`), cooltools' `qrange`.
    Quantiles(f64, f64),
    /// Values `lo..hi`, cooltools' `vrange`.
    Values(f64, f64),
}

/// Parameters of [`saddle_cis`], with cooltools' defaults for the distances.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SaddleParams {
    /// Classes between the first and the last edge (two more hold the values outside).
    pub n_bins: usize,
    /// Where the edges are.
    pub binning: Binning,
    /// Pairs closer than this many bins are left out (cooltools: 3).
    pub min_diag: usize,
    /// Pairs farther than this many bins are left out (cooltools: none).
    pub max_diag: Option<usize>,
}

impl SaddleParams {
    /// Check the values: at least one class; a quantile range within `0..=1`, low first; a
    /// value range of numbers, low first; `max_diag`, when given, not below `min_diag`.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::compartments::saddle::{Binning, SaddleParams};
    ///
    /// let params = SaddleParams { n_bins: 50, binning: Binning::Quantiles(0.025, 0.975), min_diag: 3, max_diag: None };
    /// assert!(params.check().is_ok());
    /// let bad = SaddleParams { binning: Binning::Quantiles(0.9, 0.1), ..params };
    /// assert!(bad.check().is_err());
    /// ```
    pub fn check(&self) -> Result<()> {
        if self.n_bins == 0 {
            return Err(Error::parameter("n_bins", 0, "expected at least 1"));
        }
        match self.binning {
            Binning::Quantiles(lo, hi)
                if !((0.0..=1.0).contains(&lo) && (0.0..=1.0).contains(&hi) && lo <= hi) =>
            {
                return Err(Error::parameter(
                    "qrange",
                    format!("{lo},{hi}"),
                    "expected quantiles LO,HI within 0..1, low first",
                ));
            }
            Binning::Values(lo, hi) if lo.is_nan() || hi.is_nan() || lo > hi => {
                return Err(Error::parameter(
                    "vrange",
                    format!("{lo},{hi}"),
                    "expected values LO,HI, low first",
                ));
            }
            _ => {}
        }
        if let Some(max) = self.max_diag.filter(|&max| max < self.min_diag) {
            return Err(Error::parameter(
                "max_diag",
                max,
                format!("expected at least min_diag ({})", self.min_diag),
            ));
        }
        Ok(())
    }
}

/// A digitised track: the edges and each bin's class (`-1` for NaN).
#[derive(Clone, Debug, PartialEq)]
pub struct Digitized {
    /// `n_bins + 1` edges.
    pub edges: Vec<f64>,
    /// Class of every bin: `0..=n_bins + 1`, or `-1`.
    pub classes: Vec<i32>,
}

/// numpy's `nanpercentile(values, 100 * q)` with linear interpolation, for sorted finite values.
fn percentile(sorted: &[f64], q: f64) -> f64 {
    // cooltools passes 100 * q; numpy divides by 100 again
    quantile_of_sorted(sorted, (q * 100.0) / 100.0)
}

/// Cut `track` into classes as cooltools' `digitize` does.
///
/// # Examples
///
/// ```
/// use contactmap::compartments::saddle::{digitize, Binning};
///
/// let track = [0.0, 1.0, 2.0, 3.0, 6.0, 9.0, -1.0, f64::NAN];
/// let by_value = digitize(&track, 3, Binning::Values(0.0, 9.0))?;
/// assert_eq!(by_value.edges, [0.0, 3.0, 6.0, 9.0]);
/// // below the first edge: 0; from the last edge on: n_bins + 1; NaN: -1
/// assert_eq!(by_value.classes, [1, 1, 1, 2, 3, 4, 0, -1]);
/// let by_quantile = digitize(&track, 2, Binning::Quantiles(0.0, 1.0))?;
/// assert_eq!(by_quantile.edges, [-1.0, 2.0, 9.0]); // min, median, max of the values
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn digitize(track: &[f64], n_bins: usize, binning: Binning) -> Result<Digitized> {
    if n_bins == 0 {
        return Err(Error::Argument(
            "the number of saddle bins must be at least 1".into(),
        ));
    }
    let edges = match binning {
        Binning::Values(lo, hi) => {
            if lo.is_nan() || hi.is_nan() || lo > hi {
                return Err(Error::Argument(format!(
                    "the value range {lo}..{hi} is empty"
                )));
            }
            linspace(lo, hi, n_bins + 1)
        }
        Binning::Quantiles(lo, hi) => {
            if !(0.0..=1.0).contains(&lo) || !(0.0..=1.0).contains(&hi) || lo > hi {
                return Err(Error::Argument(format!(
                    "the quantile range {lo}..{hi} must lie within 0..1, low first"
                )));
            }
            let mut sorted: Vec<f64> = track.iter().copied().filter(|v| !v.is_nan()).collect();
            if sorted.is_empty() {
                return Err(Error::Data(
                    "the track has no value on a bin with a weight".into(),
                ));
            }
            sorted.sort_unstable_by(f64::total_cmp);
            linspace(lo, hi, n_bins + 1)
                .into_iter()
                .map(|q| percentile(&sorted, q))
                .collect()
        }
    };
    let classes = track
        .iter()
        .map(|&v| {
            if v.is_nan() {
                -1
            } else {
                edges.partition_point(|&e| e <= v) as i32
            }
        })
        .collect();
    Ok(Digitized { edges, classes })
}

/// Saddle sums and counts: `(n_bins + 2)^2` values each, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Saddle {
    /// Classes on a side (`n_bins + 2`).
    pub n_classes: usize,
    /// Sums of observed/expected.
    pub sum: Vec<f64>,
    /// Numbers of pixels summed.
    pub count: Vec<f64>,
}

/// The cis saddle of `pixels` (balanced with `weights`) for the classes of `digitized`, each
/// region of `view` with its own expected values per diagonal (`expected[r][d]`, the
/// `balanced.avg` of cooltools' `expected_cis` over the same view).
///
/// # Examples
///
/// A flat map is its own expected: every observed/expected is 1, so each class pair's sum is
/// its count, and the strength is 1 at every extent. Twenty bins give `20 x 20` ordered pairs,
/// less the 94 closer than `min_diag = 3`, counted twice (cooltools adds the transpose).
///
/// ```
/// use contactmap::compartments::saddle::{digitize, saddle_cis, saddle_strength, Binning, SaddleParams};
/// use contactmap::expected::{expected_cis, CisParams};
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 20_000)], 1_000)?;
/// let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
/// for i in 0..20u64 {
///     for j in i..20 {
///         builder.push(i, j, 1.0)?;
///     }
/// }
/// let matrix = InMemory::new("flat".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// let weights = vec![1.0; 20];
/// let view = View::chromosomes(&bins);
/// let expected = expected_cis(&pixels, Some(&weights), &view, &CisParams::default())?;
/// let track: Vec<f64> = (0..20).map(|i| (i % 7) as f64).collect();
/// let params = SaddleParams {
///     n_bins: 4,
///     binning: Binning::Values(0.5, 5.5), // every class holds bins, the outer two included
///     min_diag: 3,
///     max_diag: None,
/// };
/// let digitized = digitize(&track, params.n_bins, params.binning)?;
/// let saddle = saddle_cis(&pixels, &weights, &digitized, &view, &expected.average_by_region(), &params)?;
/// assert_eq!(saddle.n_classes, 6);
/// assert_eq!(saddle.sum, saddle.count);
/// assert_eq!(saddle.count.iter().sum::<f64>(), 2.0 * (400.0 - 94.0));
/// assert!(saddle_strength(&saddle)[1..].iter().all(|s| (s - 1.0).abs() < 1e-12));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn saddle_cis<S: PixelSource>(
    pixels: &S,
    weights: &[f64],
    digitized: &Digitized,
    view: &View,
    expected: &[Vec<f64>],
    params: &SaddleParams,
) -> Result<Saddle> {
    params.check()?;
    let n_bins = pixels.bins().n_bins();
    check_lengths(n_bins, weights, digitized)?;
    if expected.len() != view.len() {
        return Err(Error::Data(format!(
            "{} expected curves for {} regions",
            expected.len(),
            view.len()
        )));
    }
    let n = digitized.edges.len() + 1;
    let class = weighted_classes(digitized, weights);
    let allowed = |region: usize, d: usize| {
        d >= params.min_diag
            && params.max_diag.is_none_or(|m| d <= m)
            && expected[region]
                .get(d)
                .is_some_and(|e| e.is_finite() && *e != 0.0)
    };
    let mut count = vec![0.0f64; n * n];
    for (r, region) in view.regions().iter().enumerate() {
        let bins = region.bins.clone();
        let len = bins.len();
        let excluded: Vec<usize> = (0..len).filter(|&d| !allowed(r, d)).collect();
        let add_distance = |d: usize, sign: f64, count: &mut [f64]| {
            for i in bins.start..bins.end - d {
                let (a, b) = (class[i], class[i + d]);
                if a < 0 || b < 0 {
                    continue;
                }
                let (a, b) = (a as usize, b as usize);
                count[a * n + b] += sign;
                if d > 0 {
                    count[b * n + a] += sign;
                }
            }
        };
        if excluded.len() * 2 <= len {
            // every pair, less those at excluded distances
            let mut sizes = vec![0.0f64; n];
            for &c in &class[bins.clone()] {
                if c >= 0 {
                    sizes[c as usize] += 1.0;
                }
            }
            for a in 0..n {
                for b in 0..n {
                    count[a * n + b] += sizes[a] * sizes[b];
                }
            }
            for &d in &excluded {
                add_distance(d, -1.0, &mut count);
            }
        } else {
            for d in (0..len).filter(|&d| allowed(r, d)) {
                add_distance(d, 1.0, &mut count);
            }
        }
    }
    // cooltools' cis blocks are whole (symmetric) matrices: a pixel off the diagonal counts in
    // both orders
    let sum = class_pair_sums(pixels, weights, &class, view, n, |i, j, ri, rj| {
        (ri == rj && allowed(ri, j - i)).then(|| (expected[ri][j - i], true))
    })?;
    Ok(Saddle::symmetrised(n, &sum, &count))
}

/// Sums of `count * w_i * w_j / E` over the stored pixels `(i, j)` by class pair, for the pixels
/// to which `term(i, j, region of i, region of j)` gives an expected value `E` (and whether the
/// pixel also counts as `(j, i)`); pixels of bins without a class or a region, and non-finite
/// values, are left out.
fn class_pair_sums<S: PixelSource>(
    pixels: &S,
    weights: &[f64],
    class: &[i32],
    view: &View,
    n: usize,
    term: impl Fn(usize, usize, usize, usize) -> Option<(f64, bool)> + Sync,
) -> Result<Vec<f64>> {
    let region_of = view.bin_regions(pixels.bins().n_bins());
    pixels.pass(
        || vec![0.0f64; n * n],
        |mut acc, slice: PixelSlice<'_>| {
            for k in 0..slice.len() {
                let (i, j) = (slice.bin1[k] as usize, slice.bin2[k] as usize);
                let (Some(ri), Some(rj)) = (region_of[i], region_of[j]) else {
                    continue;
                };
                let (a, b) = (class[i], class[j]);
                if a < 0 || b < 0 {
                    continue;
                }
                let Some((expected, mirrored)) = term(i, j, ri, rj) else {
                    continue;
                };
                let value = slice.count[k] * weights[i] * weights[j] / expected;
                if !value.is_finite() {
                    continue;
                }
                let (a, b) = (a as usize, b as usize);
                acc[a * n + b] += value;
                if mirrored && i != j {
                    acc[b * n + a] += value;
                }
            }
            acc
        },
        |mut a, b| {
            for (x, y) in a.iter_mut().zip(&b) {
                *x += y;
            }
            a
        },
    )
}

/// One weight and one class per bin.
fn check_lengths(n_bins: usize, weights: &[f64], digitized: &Digitized) -> Result<()> {
    if weights.len() != n_bins || digitized.classes.len() != n_bins {
        return Err(Error::Data(format!(
            "the weights ({}) and the track ({}) must have one value per bin ({n_bins})",
            weights.len(),
            digitized.classes.len()
        )));
    }
    Ok(())
}

/// Each bin's class, `-1` where it has none or no weight (such a bin takes no part).
fn weighted_classes(digitized: &Digitized, weights: &[f64]) -> Vec<i32> {
    digitized
        .classes
        .iter()
        .zip(weights)
        .map(|(&c, w)| if w.is_finite() { c } else { -1 })
        .collect()
}

impl Saddle {
    /// The arrays plus their transposes, as cooltools returns them.
    fn symmetrised(n: usize, sum: &[f64], count: &[f64]) -> Saddle {
        let symmetric = |m: &[f64]| -> Vec<f64> {
            let mut out = vec![0.0; n * n];
            for a in 0..n {
                for b in 0..n {
                    out[a * n + b] = m[a * n + b] + m[b * n + a];
                }
            }
            out
        };
        Saddle {
            n_classes: n,
            sum: symmetric(sum),
            count: symmetric(count),
        }
    }
}

/// The trans saddle (cooltools' `saddle(contact_type="trans")`): every pair of regions of the
/// view on different chromosomes, in view order, adds `balanced / E` of each of its bin pairs
/// (0 where no pixel is stored) to the pair's class pair, `E` the pair's `balanced.avg`
/// (`expected[r1][r2]`, from `expected_trans` on the same view); a pair whose `E` is not finite
/// or is 0 adds nothing. The arrays are then added to their transposes.
///
/// # Examples
///
/// Two chromosomes whose trans pixels all hold 2: observed/expected is 1 on every trans pair of
/// bins, so each class pair's sum is its count; all `2 x 4 x 3` ordered pairs are counted.
///
/// ```
/// use contactmap::compartments::saddle::{digitize, saddle_trans, Binning};
/// use contactmap::expected::expected_trans;
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 400), Chrom::new("chr2", 300)], 100)?;
/// let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
/// for i in 0..4u64 {
///     for j in 4..7 {
///         builder.push(i, j, 2.0)?;
///     }
/// }
/// let matrix = InMemory::new("example".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// let weights = vec![1.0; 7];
/// let view = View::chromosomes(&bins);
/// let expected = expected_trans(&pixels, Some(&weights), &view)?.average_by_pair(&view);
/// let track = [0.1, 0.5, 0.9, 0.3, 0.7, 0.2, 0.6];
/// let digitized = digitize(&track, 2, Binning::Values(0.0, 1.0))?;
/// let saddle = saddle_trans(&pixels, &weights, &digitized, &view, &expected)?;
/// assert_eq!(saddle.sum, saddle.count);
/// assert_eq!(saddle.count.iter().sum::<f64>(), 24.0);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn saddle_trans<S: PixelSource>(
    pixels: &S,
    weights: &[f64],
    digitized: &Digitized,
    view: &View,
    expected: &[Vec<f64>],
) -> Result<Saddle> {
    let n_bins = pixels.bins().n_bins();
    check_lengths(n_bins, weights, digitized)?;
    let n = digitized.edges.len() + 1;
    let class = weighted_classes(digitized, weights);
    let regions = view.regions();
    let usable = |r1: usize, r2: usize| {
        r1 != r2
            && regions[r1].chrom_id != regions[r2].chrom_id
            && expected
                .get(r1.min(r2))
                .and_then(|row| row.get(r1.max(r2)))
                .is_some_and(|e| e.is_finite() && *e != 0.0)
    };
    let sizes: Vec<Vec<f64>> = regions
        .iter()
        .map(|region| {
            let mut sizes = vec![0.0f64; n];
            for &c in &class[region.bins.clone()] {
                if c >= 0 {
                    sizes[c as usize] += 1.0;
                }
            }
            sizes
        })
        .collect();
    let mut count = vec![0.0f64; n * n];
    for r1 in 0..regions.len() {
        for r2 in r1 + 1..regions.len() {
            if !usable(r1, r2) {
                continue;
            }
            for a in 0..n {
                for b in 0..n {
                    count[a * n + b] += sizes[r1][a] * sizes[r2][b];
                }
            }
        }
    }
    // upper-triangle pixels of a sorted view: the earlier region's bin is the row, as cooltools
    // fetches (region1, region2)
    let sum = class_pair_sums(pixels, weights, &class, view, n, |_, _, ri, rj| {
        usable(ri, rj).then(|| (expected[ri.min(rj)][ri.max(rj)], false))
    })?;
    Ok(Saddle::symmetrised(n, &sum, &count))
}

/// cooltools' `saddle_strength`: for `k` in `1..n`, `(AA + BB) / (AB + BA)` over the `k x k`
/// corners (means of observed/expected); entry 0 is 0.
///
/// # Examples
///
/// Two classes with twice the observed/expected within a class as between: strength 2.
///
/// ```
/// use contactmap::compartments::saddle::{saddle_strength, Saddle};
/// let saddle = Saddle {
///     n_classes: 2,
///     sum: vec![4.0, 1.0, 1.0, 4.0],
///     count: vec![2.0, 1.0, 1.0, 2.0],
/// };
/// assert_eq!(saddle_strength(&saddle), [0.0, 2.0]);
/// ```
pub fn saddle_strength(saddle: &Saddle) -> Vec<f64> {
    let n = saddle.n_classes;
    let block = |m: &[f64], rows: std::ops::Range<usize>, cols: std::ops::Range<usize>| -> f64 {
        rows.flat_map(|a| cols.clone().map(move |b| (a, b)))
            .map(|(a, b)| m[a * n + b])
            .filter(|v| !v.is_nan())
            .sum()
    };
    let mut ratios = vec![0.0; n];
    for (k, ratio) in ratios.iter_mut().enumerate().skip(1) {
        let (low, high) = (0..k, n - k..n);
        let intra = (block(&saddle.sum, low.clone(), low.clone())
            + block(&saddle.sum, high.clone(), high.clone()))
            / (block(&saddle.count, low.clone(), low.clone())
                + block(&saddle.count, high.clone(), high.clone()));
        let inter = (block(&saddle.sum, low.clone(), high.clone())
            + block(&saddle.sum, high.clone(), low.clone()))
            / (block(&saddle.count, low.clone(), high.clone())
                + block(&saddle.count, high.clone(), low.clone()));
        *ratio = intra / inter;
    }
    ratios
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::{BinTable, Chrom};
    use crate::matrix::pixels::Pixels;
    use crate::matrix::{CountType, PixelBlock};

    #[test]
    fn quantile_edges_and_classes_follow_numpy() {
        // np.nanpercentile([1..=10, nan], [0, 25, 50, 75, 100]) = 1, 3.25, 5.5, 7.75, 10
        let track: Vec<f64> = (1..=10).map(f64::from).chain([f64::NAN]).collect();
        let d = digitize(&track, 4, Binning::Quantiles(0.0, 1.0)).unwrap();
        assert_eq!(d.edges, vec![1.0, 3.25, 5.5, 7.75, 10.0]);
        // np.digitize: right-open bins, the maximum in the last open class
        assert_eq!(d.classes, vec![1, 1, 1, 2, 2, 3, 3, 4, 4, 5, -1]);
        let v = digitize(&[-5.0, 0.0, 0.5, 5.0], 2, Binning::Values(0.0, 1.0)).unwrap();
        assert_eq!(v.edges, vec![0.0, 0.5, 1.0]);
        assert_eq!(v.classes, vec![0, 1, 2, 3]);
    }

    /// The saddle against a dense computation as cooltools does it: full matrix, NaN near the
    /// diagonal, every class pair summed, then the transposes added.
    #[test]
    fn sparse_saddle_equals_the_dense_one() {
        let bins = BinTable::fixed(vec![Chrom::new("a", 120), Chrom::new("b", 90)], 10).unwrap();
        let n_bins = bins.n_bins();
        let mut pixels = Pixels::with_capacity(bins.clone(), CountType::Integer, 0).unwrap();
        let mut block = PixelBlock::default();
        let mut dense = vec![vec![0.0f64; n_bins]; n_bins];
        let stored = |i: usize, j: usize| !(i * 7 + j * 3).is_multiple_of(5);
        let value = |i: usize, j: usize| ((i + 2 * j) % 9 + 1) as f64;
        for (i, row) in dense.iter_mut().enumerate() {
            for (j, cell) in row.iter_mut().enumerate() {
                let (a, b) = (i.min(j), i.max(j));
                if stored(a, b) {
                    *cell = value(a, b);
                }
            }
        }
        for i in 0..n_bins {
            for j in (i..n_bins).filter(|&j| stored(i, j)) {
                block.push(i as u64, j as u64, value(i, j));
            }
        }
        pixels.extend(&block).unwrap();
        let weights: Vec<f64> = (0..n_bins)
            .map(|k| {
                if k == 4 {
                    f64::NAN
                } else {
                    0.5 + (k % 4) as f64 / 4.0
                }
            })
            .collect();
        let track: Vec<f64> = (0..n_bins)
            .map(|k| {
                if k == 7 {
                    f64::NAN
                } else {
                    ((k * 37) % 11) as f64 - 5.0
                }
            })
            .collect();
        let view = View::chromosomes(&bins);
        let expected: Vec<Vec<f64>> = view
            .regions()
            .iter()
            .map(|r| {
                (0..r.n_bins())
                    .map(|d| if d == 5 { f64::NAN } else { 1.0 + d as f64 })
                    .collect()
            })
            .collect();
        let params = SaddleParams {
            n_bins: 3,
            binning: Binning::Quantiles(0.1, 0.9),
            min_diag: 2,
            max_diag: None,
        };
        let digitized = digitize(&track, 3, params.binning).unwrap();
        let got = saddle_cis(&pixels, &weights, &digitized, &view, &expected, &params).unwrap();
        let n = 5;
        let (mut sum, mut count) = (vec![0.0; n * n], vec![0.0; n * n]);
        for (r, region) in view.regions().iter().enumerate() {
            for i in region.bins.clone() {
                for j in region.bins.clone() {
                    let d = i.abs_diff(j);
                    let (a, b) = (digitized.classes[i], digitized.classes[j]);
                    if d < 2 || a < 0 || b < 0 {
                        continue;
                    }
                    let value = dense[i][j] * weights[i] * weights[j] / expected[r][d];
                    if value.is_finite() {
                        sum[a as usize * n + b as usize] += value;
                        count[a as usize * n + b as usize] += 1.0;
                    }
                }
            }
        }
        for a in 0..n {
            for b in 0..n {
                let (s, c) = (
                    sum[a * n + b] + sum[b * n + a],
                    count[a * n + b] + count[b * n + a],
                );
                assert_eq!(got.count[a * n + b], c, "{a} {b}");
                assert!(
                    (got.sum[a * n + b] - s).abs() <= 1e-12 * s.abs().max(1.0),
                    "{a} {b}"
                );
            }
        }
        let strength = saddle_strength(&got);
        assert_eq!(strength.len(), n);
        assert_eq!(strength[0], 0.0);
        assert!(strength[1..].iter().all(|s| s.is_finite()));
    }
}
