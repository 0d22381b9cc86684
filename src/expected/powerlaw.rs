//! Power-law fits of P(s): one exponent over a distance range, and piecewise exponents between
//! breakpoints found automatically.
//!
//! # Data
//!
//! The points are the combined log-binned P(s) ([`super::logbin`]): one point per log bin (10 per
//! decade), at the `n_valid`-weighted mean distance of the bin, kept when that distance (in bp)
//! lies in the fit range. Log binning spaces the points evenly in log s, so that every decade
//! weighs the same in an unweighted least-squares fit (the raw diagonals would give the long
//! distances, where there are many more diagonals, almost all the weight).
//!
//! Each point is placed at its bin's *effective* distance for the fitted exponent
//! ([`CombinedBin::effective_dist`]): P(s) is convex, so a bin's average exceeds the power law at
//! its mean distance by a factor growing with the bin's width (about 0.2% for 10 bins per decade
//! and `alpha = -1`), which would bias the exponent by about 0.001-0.002 where bins change from
//! one diagonal to many. Starting from the mean distances, the fit is repeated at the effective
//! distances for the current exponent ([`EFFECTIVE_DISTANCE_ROUNDS`] times); an exact power law
//! is then recovered exactly. Bins are selected by their mean distance (`dist.avg`), so the set
//! of points does not change between rounds. The piecewise fit uses the effective distances of
//! the single exponent.
//!
//! # Single exponent ([`fit_power_law`])
//!
//! Ordinary least squares of `log10 P = a + alpha * log10 s`: the exponent `alpha`, its standard
//! error `sqrt(s^2 / Sxx)` with `s^2 = RSS / (n - 2)`, the 95% confidence interval
//! `alpha -/+ t(0.975, n - 2) * se` (Student's t, statrs), and `R^2 = 1 - RSS / TSS`. The log-binned
//! points are not independent measurements with Gaussian errors (neighbouring bins share
//! smoothing-free but correlated biology), so the interval describes the scatter around the
//! power law, not every source of uncertainty.
//!
//! # Default range ([`default_fit_range`])
//!
//! From `max(ignore_diags, 2)` bins, the first diagonal cooltools keeps (closer pixels are
//! dominated by the binning itself: a pixel at `d` bins averages separations `d - 1 .. d + 1`,
//! a bias that falls as `1 / d^2`), to a quarter of the median region (chromosome) length: at a
//! separation `s` a region of length `L` has `L - s` pairs of loci, so beyond `L / 4` each
//! region contributes ever fewer pixels, only the longest regions reach the largest distances,
//! and the combined curve mixes fewer and fewer chromosomes.
//!
//! # Piecewise exponents ([`fit_piecewise`])
//!
//! Segmented regression: a continuous broken line in log-log space,
//! `log10 P = a + b * x + sum_k c_k * max(0, x - t_k)` with `x = log10 s`, for 0 to 3 breakpoints
//! `t_k` placed at data points, each segment spanning at least 4 points (its ends included).
//! For each number of breakpoints every placement is tried (linear least squares for each), and
//! the number is chosen by the Bayesian information criterion
//! `BIC = n ln(max(RSS / n, floor^2)) + (2 + 2K) ln n` (`K` breakpoints, each with its position
//! and its slope change as parameters). The variance floor (0.005 in log10 units, about 1%)
//! keeps breakpoints from fitting the tiny systematic wiggles of log binning when the data are
//! a nearly exact power law. Segment exponents carry standard errors and t intervals from the
//! least-squares covariance *given* the breakpoints (their placement uncertainty is not
//! included).

use statrs::distribution::{ContinuousCDF, StudentsT};

use super::compute::expected_cis;
use super::logbin::{CombinedBin, LogBinParams, LogBinned, logbin_expected};
use super::params::CisParams;
use super::result::CisExpected;
use crate::error::{Error, Result};
use crate::genome::View;
use crate::genome::{format_bp, format_distance};
use crate::io::LoadedPixels;

/// A distance range in bp (inclusive).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitRange {
    /// Smallest distance.
    pub min_bp: f64,
    /// Largest distance.
    pub max_bp: f64,
}

impl std::str::FromStr for FitRange {
    type Err = Error;

    /// `MIN-MAX` in bp, with units: `100k-10M`, `200,000-1.5Mb`. A bad range is an
    /// [`Error::Parameter`] named `fit_range`.
    ///
    /// ```
    /// use contactmap::expected::powerlaw::FitRange;
    /// let range: FitRange = "100k-1.5Mb".parse().unwrap();
    /// assert_eq!((range.min_bp, range.max_bp), (1e5, 1.5e6));
    /// assert!("10M-1M".parse::<FitRange>().is_err());
    /// ```
    fn from_str(text: &str) -> Result<Self> {
        let bad = |why: &str| {
            Error::parameter(
                "fit_range",
                format!("'{text}'"),
                format!("{why} (expected MIN-MAX in bp, e.g. 100k-10M)"),
            )
        };
        let (min, max) = text.split_once('-').ok_or_else(|| bad("no '-'"))?;
        let parse = |part: &str| {
            crate::genome::parse_distance(part)
                .ok_or_else(|| bad(&format!("'{}' is not a distance", part.trim())))
        };
        let range = FitRange {
            min_bp: parse(min)?,
            max_bp: parse(max)?,
        };
        if !(range.min_bp > 0.0 && range.max_bp > range.min_bp && range.max_bp.is_finite()) {
            return Err(bad("MIN must be positive and below MAX"));
        }
        Ok(range)
    }
}

/// The default fit range: `max(ignore_diags, 2)` bins to a quarter of the median region length
/// (see the module documentation).
pub fn default_fit_range(resolution: u64, ignore_diags: usize, median_region_bp: f64) -> FitRange {
    FitRange {
        min_bp: ignore_diags.max(2) as f64 * resolution as f64,
        max_bp: median_region_bp / 4.0,
    }
}

/// Parameters of the fits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitParams {
    /// Distances fitted.
    pub range: FitRange,
    /// Most breakpoints tried by the piecewise fit (default 3).
    pub max_breakpoints: usize,
    /// Fewest points per segment, ends included (default 4).
    pub min_points_per_segment: usize,
    /// Residual standard deviation floor of the BIC, in log10 units (default 0.005).
    pub noise_floor_log10: f64,
}

impl FitParams {
    /// Defaults for `range`.
    pub fn new(range: FitRange) -> Self {
        FitParams {
            range,
            max_breakpoints: 3,
            min_points_per_segment: 4,
            noise_floor_log10: 0.01,
        }
    }

    /// Check the values: a range of positive distances, low first; at least 2 points per
    /// segment; a noise floor that is a number `>= 0`. The fits check them first.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::expected::powerlaw::{FitParams, FitRange};
    ///
    /// let params = FitParams::new(FitRange { min_bp: 2e4, max_bp: 2e6 });
    /// assert!(params.check().is_ok());
    /// let bad = FitParams::new(FitRange { min_bp: 2e6, max_bp: 2e4 });
    /// assert!(bad.check().unwrap_err().to_string().starts_with("range 2000000-20000"));
    /// ```
    pub fn check(&self) -> Result<()> {
        let FitRange { min_bp, max_bp } = self.range;
        if !(min_bp.is_finite() && max_bp.is_finite() && 0.0 < min_bp && min_bp < max_bp) {
            return Err(Error::parameter(
                "range",
                format!("{min_bp}-{max_bp}"),
                "expected distances MIN-MAX in bp with 0 < MIN < MAX",
            ));
        }
        if self.min_points_per_segment < 2 {
            return Err(Error::parameter(
                "min_points_per_segment",
                self.min_points_per_segment,
                "expected at least 2",
            ));
        }
        if !(self.noise_floor_log10.is_finite() && self.noise_floor_log10 >= 0.0) {
            return Err(Error::parameter(
                "noise_floor_log10",
                self.noise_floor_log10,
                "expected a number >= 0",
            ));
        }
        Ok(())
    }
}

/// A single power law `P(s) ~ s^alpha` fitted by least squares in log-log space.
#[derive(Clone, Debug, PartialEq)]
pub struct PowerLawFit {
    /// The exponent.
    pub alpha: f64,
    /// `log10 P` at `s = 1 bp`.
    pub intercept_log10: f64,
    /// Standard error of `alpha`.
    pub stderr: f64,
    /// 95% confidence interval of `alpha` (Student's t with `dof` degrees of freedom).
    pub ci95: (f64, f64),
    /// Coefficient of determination in log-log space.
    pub r_squared: f64,
    /// Residual sum of squares (log10 units).
    pub rss: f64,
    /// Points fitted.
    pub n_points: usize,
    /// Degrees of freedom of the residuals (`n_points - 2`).
    pub dof: usize,
    /// Smallest distance fitted (bp).
    pub first_bp: f64,
    /// Largest distance fitted (bp).
    pub last_bp: f64,
}

/// One segment of a piecewise fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    /// Start of the segment (bp): the first point or a breakpoint.
    pub start_bp: f64,
    /// End of the segment (bp): a breakpoint or the last point.
    pub end_bp: f64,
    /// The exponent on this segment.
    pub alpha: f64,
    /// Its standard error, given the breakpoints.
    pub stderr: f64,
    /// Its 95% confidence interval, given the breakpoints.
    pub ci95: (f64, f64),
    /// Points in the segment (ends included).
    pub n_points: usize,
}

/// The piecewise power law chosen by BIC.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseFit {
    /// Breakpoints (bp), increasing; empty when one power law is best.
    pub breakpoints_bp: Vec<f64>,
    /// The segments, in order.
    pub segments: Vec<Segment>,
    /// Residual sum of squares of the chosen fit (log10 units).
    pub rss: f64,
    /// BIC of the best fit with 0, 1, 2, ... breakpoints (`None` where there were too few points).
    pub bic_by_breakpoints: Vec<Option<f64>>,
}

/// The fits of a log-binned P(s).
#[derive(Clone, Debug, PartialEq)]
pub struct PowerLawReport {
    /// The range asked for.
    pub range: FitRange,
    /// One exponent over the range.
    pub fit: PowerLawFit,
    /// Piecewise exponents.
    pub piecewise: PiecewiseFit,
    /// The points fitted: `(effective distance in bp, P)`.
    pub points: Vec<(f64, f64)>,
}

/// The two-sided 95% quantile of Student's t with `dof` degrees of freedom.
fn t_quantile_95(dof: usize) -> f64 {
    if dof == 0 {
        return f64::NAN;
    }
    StudentsT::new(0.0, 1.0, dof as f64)
        .map(|t| t.inverse_cdf(0.975))
        .unwrap_or(f64::NAN)
}

/// Fit `P(s) ~ s^alpha` to points `(s_bp, P)` (both positive).
pub fn fit_power_law(points: &[(f64, f64)]) -> Result<PowerLawFit> {
    let (x, y) = log_points(points)?;
    let n = x.len();
    if n < 3 {
        return Err(Error::Data(format!(
            "a power-law fit needs at least 3 points, got {n}"
        )));
    }
    let mean_x = x.iter().sum::<f64>() / n as f64;
    let mean_y = y.iter().sum::<f64>() / n as f64;
    let sxx: f64 = x.iter().map(|v| (v - mean_x) * (v - mean_x)).sum();
    let sxy: f64 = x
        .iter()
        .zip(&y)
        .map(|(a, b)| (a - mean_x) * (b - mean_y))
        .sum();
    let syy: f64 = y.iter().map(|v| (v - mean_y) * (v - mean_y)).sum();
    if sxx <= 0.0 {
        return Err(Error::Data(
            "a power-law fit needs points at different distances".into(),
        ));
    }
    let alpha = sxy / sxx;
    let intercept = mean_y - alpha * mean_x;
    let rss: f64 = x
        .iter()
        .zip(&y)
        .map(|(a, b)| {
            let r = b - (intercept + alpha * a);
            r * r
        })
        .sum();
    let dof = n - 2;
    let stderr = (rss / dof as f64 / sxx).sqrt();
    let t = t_quantile_95(dof);
    Ok(PowerLawFit {
        alpha,
        intercept_log10: intercept,
        stderr,
        ci95: (alpha - t * stderr, alpha + t * stderr),
        r_squared: if syy > 0.0 { 1.0 - rss / syy } else { 1.0 },
        rss,
        n_points: n,
        dof,
        first_bp: points[0].0,
        last_bp: points[n - 1].0,
    })
}

fn log_points(points: &[(f64, f64)]) -> Result<(Vec<f64>, Vec<f64>)> {
    if let Some(bad) = points
        .iter()
        .find(|(s, p)| !(s.is_finite() && *s > 0.0 && p.is_finite() && *p > 0.0))
    {
        return Err(Error::Data(format!(
            "power-law fits need positive distances and values, got ({}, {})",
            bad.0, bad.1
        )));
    }
    if points.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err(Error::Data(
            "power-law fit points must be sorted by increasing distance".into(),
        ));
    }
    Ok(points.iter().map(|(s, p)| (s.log10(), p.log10())).unzip())
}

/// Solve the least-squares problem for `design` (rows of `p` columns) and `y`: coefficients,
/// residual sum of squares and `(X^T X)^-1`. `None` when the design is singular.
fn least_squares(design: &[Vec<f64>], y: &[f64]) -> Option<(Vec<f64>, f64, Vec<Vec<f64>>)> {
    let p = design.first()?.len();
    let mut xtx = vec![vec![0.0; p]; p];
    let mut xty = vec![0.0; p];
    for (row, &target) in design.iter().zip(y) {
        for a in 0..p {
            xty[a] += row[a] * target;
            for b in 0..p {
                xtx[a][b] += row[a] * row[b];
            }
        }
    }
    let inverse = invert_spd(&xtx)?;
    let beta: Vec<f64> = (0..p)
        .map(|a| (0..p).map(|b| inverse[a][b] * xty[b]).sum())
        .collect();
    let rss = design
        .iter()
        .zip(y)
        .map(|(row, &target)| {
            let fitted: f64 = row.iter().zip(&beta).map(|(x, b)| x * b).sum();
            (target - fitted) * (target - fitted)
        })
        .sum();
    Some((beta, rss, inverse))
}

/// Inverse of a small symmetric positive-definite matrix (Cholesky); `None` if not positive
/// definite.
fn invert_spd(matrix: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let p = matrix.len();
    let mut lower = vec![vec![0.0; p]; p];
    for i in 0..p {
        for j in 0..=i {
            let sum = matrix[i][j] - (0..j).map(|k| lower[i][k] * lower[j][k]).sum::<f64>();
            if i == j {
                if sum <= 1e-12 * matrix[i][i].abs().max(1e-300) {
                    return None;
                }
                lower[i][i] = sum.sqrt();
            } else {
                lower[i][j] = sum / lower[j][j];
            }
        }
    }
    // Column c of the inverse: solve L z = e_c, then L^T x = z.
    let columns: Vec<Vec<f64>> = (0..p)
        .map(|column| {
            let mut z = vec![0.0; p];
            for i in 0..p {
                let unit = if i == column { 1.0 } else { 0.0 };
                z[i] = (unit - (0..i).map(|k| lower[i][k] * z[k]).sum::<f64>()) / lower[i][i];
            }
            let mut x = vec![0.0; p];
            for i in (0..p).rev() {
                x[i] = (z[i] - (i + 1..p).map(|k| lower[k][i] * x[k]).sum::<f64>()) / lower[i][i];
            }
            x
        })
        .collect();
    // The inverse is symmetric: its columns are its rows.
    Some(columns)
}

/// The design matrix of a broken line with breakpoints at `x[indices]` (x centred for
/// conditioning).
fn hinge_design(x: &[f64], mean_x: f64, indices: &[usize]) -> Vec<Vec<f64>> {
    x.iter()
        .map(|&v| {
            let mut row = vec![1.0, v - mean_x];
            row.extend(indices.iter().map(|&k| (v - x[k]).max(0.0)));
            row
        })
        .collect()
}

/// Every increasing choice of `k` breakpoint indices in `0..n` leaving segments of at least
/// `min_points` points (ends included).
fn placements(n: usize, k: usize, min_points: usize) -> Vec<Vec<usize>> {
    if k == 0 {
        return vec![Vec::new()];
    }
    let gap = min_points.saturating_sub(1).max(1);
    let mut all = Vec::new();
    let mut current = Vec::with_capacity(k);
    fn recurse(
        n: usize,
        k: usize,
        gap: usize,
        start: usize,
        current: &mut Vec<usize>,
        all: &mut Vec<Vec<usize>>,
    ) {
        if current.len() == k {
            if current.last().is_some_and(|&last| last + gap < n) {
                all.push(current.clone());
            }
            return;
        }
        let remaining = k - current.len();
        // Room for the remaining breakpoints and the last segment.
        let mut index = start;
        while index + remaining * gap < n {
            current.push(index);
            recurse(n, k, gap, index + gap, current, all);
            current.pop();
            index += 1;
        }
    }
    if n > gap {
        recurse(n, k, gap, gap, &mut current, &mut all);
    }
    all
}

/// The best placement of a number of breakpoints.
struct Candidate {
    bic: f64,
    indices: Vec<usize>,
    beta: Vec<f64>,
    rss: f64,
    inverse: Vec<Vec<f64>>,
}

/// Segmented power-law fit of points `(s_bp, P)` sorted by distance.
pub fn fit_piecewise(points: &[(f64, f64)], params: &FitParams) -> Result<PiecewiseFit> {
    params.check()?;
    let (x, y) = log_points(points)?;
    let n = x.len();
    if n < 3 {
        return Err(Error::Data(format!(
            "a piecewise power-law fit needs at least 3 points, got {n}"
        )));
    }
    let mean_x = x.iter().sum::<f64>() / n as f64;
    let floor = params.noise_floor_log10 * params.noise_floor_log10;
    let bic = |rss: f64, k: usize| {
        n as f64 * (rss / n as f64).max(floor).ln() + (2 + 2 * k) as f64 * (n as f64).ln()
    };
    let mut best: Option<Candidate> = None;
    let mut bic_by_breakpoints = Vec::new();
    for k in 0..=params.max_breakpoints {
        let mut best_k: Option<Candidate> = None;
        for indices in placements(n, k, params.min_points_per_segment) {
            let design = hinge_design(&x, mean_x, &indices);
            if let Some((beta, rss, inverse)) = least_squares(&design, &y) {
                if best_k.as_ref().is_none_or(|b| rss < b.rss) {
                    best_k = Some(Candidate {
                        bic: bic(rss, k),
                        indices,
                        beta,
                        rss,
                        inverse,
                    });
                }
            }
        }
        bic_by_breakpoints.push(best_k.as_ref().map(|b| b.bic));
        if let Some(candidate) = best_k {
            if best.as_ref().is_none_or(|b| candidate.bic < b.bic) {
                best = Some(candidate);
            }
        }
    }
    let Candidate {
        indices,
        beta,
        rss,
        inverse,
        ..
    } = best.ok_or_else(|| Error::Data("no piecewise fit was possible".into()))?;
    let n_parameters = 2 + indices.len();
    let dof = n.saturating_sub(n_parameters);
    let sigma2 = if dof > 0 { rss / dof as f64 } else { f64::NAN };
    let t = t_quantile_95(dof);
    let mut bounds = vec![0];
    bounds.extend(&indices);
    bounds.push(n - 1);
    let segments = (0..=indices.len())
        .map(|segment| {
            // Slope of segment s: b + c_1 + ... + c_s; its variance a^T Cov a.
            let selector: Vec<f64> = (0..n_parameters)
                .map(|p| {
                    if p == 1 || (p >= 2 && p - 2 < segment) {
                        1.0
                    } else {
                        0.0
                    }
                })
                .collect();
            let alpha: f64 = selector.iter().zip(&beta).map(|(a, b)| a * b).sum();
            let variance: f64 = (0..n_parameters)
                .map(|a| {
                    (0..n_parameters)
                        .map(|b| selector[a] * inverse[a][b] * selector[b])
                        .sum::<f64>()
                })
                .sum::<f64>()
                * sigma2;
            let stderr = variance.max(0.0).sqrt();
            Segment {
                start_bp: points[bounds[segment]].0,
                end_bp: points[bounds[segment + 1]].0,
                alpha,
                stderr,
                ci95: (alpha - t * stderr, alpha + t * stderr),
                n_points: bounds[segment + 1] - bounds[segment] + 1,
            }
        })
        .collect();
    Ok(PiecewiseFit {
        breakpoints_bp: indices.iter().map(|&k| points[k].0).collect(),
        segments,
        rss,
        bic_by_breakpoints,
    })
}

/// Rounds of the effective-distance correction (the exponent changes by well under 1e-6
/// after the third on every map tried).
pub const EFFECTIVE_DISTANCE_ROUNDS: usize = 4;

/// The bins of the combined log-binned curve whose mean distance `dist.avg` lies in `range`.
pub fn fit_bins<'a>(binned: &'a LogBinned, range: &FitRange) -> Vec<&'a CombinedBin> {
    let resolution = binned.resolution as f64;
    binned
        .combined
        .iter()
        .filter(|b| {
            let s = b.dist_avg * resolution;
            s >= range.min_bp && s <= range.max_bp && b.average > 0.0 && b.average.is_finite()
        })
        .collect()
}

/// Fit points `(effective distance in bp, P)` of `bins` for the exponent `alpha`.
pub fn fit_points(bins: &[&CombinedBin], resolution: u64, alpha: f64) -> Vec<(f64, f64)> {
    bins.iter()
        .map(|b| (b.effective_dist(alpha) * resolution as f64, b.average))
        .collect()
}

/// Fit one and piecewise power laws to the combined log-binned P(s) within `params.range`.
pub fn fit_log_binned(binned: &LogBinned, params: &FitParams) -> Result<PowerLawReport> {
    params.check()?;
    let range = params.range;
    if !(range.min_bp > 0.0 && range.max_bp > range.min_bp) {
        return Err(Error::Argument(format!(
            "the fit range {}-{} bp is empty (it must be positive and increasing)",
            range.min_bp, range.max_bp
        )));
    }
    if binned.combined.len() < 3 {
        return Err(Error::Data(format!(
            "the log-binned P(s) has {} point(s), fewer than the 3 a fit needs: log bins keep only regions with more than 200 valid pixels and 50 counts in them (cooltools' defaults), so the map is too coarse or too sparse",
            binned.combined.len()
        )));
    }
    let bins = fit_bins(binned, &range);
    if bins.len() < 3 {
        return Err(Error::Argument(format!(
            "the fit range {}-{} bp holds {} log-binned P(s) point(s); at least 3 are needed (widen the range)",
            range.min_bp,
            range.max_bp,
            bins.len()
        )));
    }
    // Start at the mean distances (alpha 0), then refit at the effective distances.
    let mut fit = fit_power_law(&fit_points(&bins, binned.resolution, 0.0))?;
    for _ in 0..EFFECTIVE_DISTANCE_ROUNDS {
        fit = fit_power_law(&fit_points(&bins, binned.resolution, fit.alpha))?;
    }
    let points = fit_points(&bins, binned.resolution, fit.alpha);
    Ok(PowerLawReport {
        range,
        piecewise: fit_piecewise(&points, params)?,
        points,
        fit,
    })
}

/// A cis expected table, its log-binned P(s) and the power-law fits: what `contactmap expected
/// --fit` prints and `plot expected --fit` draws. The fit may fail (too few points in the
/// range) while the table and the log bins stand.
pub struct PowerLaw {
    /// The cis table without smoothing (the log binning uses the sums).
    pub table: CisExpected,
    /// Log-binned P(s), per region and combined, with slopes.
    pub binned: LogBinned,
    /// The fits over the asked or default range.
    pub fit: Result<PowerLawReport>,
}

/// The cis table of `pixels` over `view` (without smoothing), its log-binned P(s) and the
/// power-law fits over `fit_range` (default: [`default_fit_range`]).
///
/// # Examples
///
/// ```
/// use contactmap::expected::powerlaw::power_law;
/// use contactmap::expected::CisParams;
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory, MatrixReader};
/// use contactmap::matrix::{CountType, MatrixBuilder};
///
/// // P(s) = 1e6 s^-1 on one 2 Mb chromosome at 1 kb.
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 2_000_000)], 1_000)?;
/// let n = bins.n_bins() as u64;
/// let mut builder = MatrixBuilder::new(bins, CountType::Float);
/// for i in 0..n {
///     for j in (i + 1)..n.min(i + 1_000) {
///         builder.push(i, j, 1e6 / (j - i) as f64)?;
///     }
/// }
/// let matrix = InMemory::new("example".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// let view = View::chromosomes(matrix.bins());
/// let law = power_law(&pixels, None, &view, &CisParams::default(), None)?;
/// let fit = law.fit?.fit;
/// assert!((fit.alpha + 1.0).abs() < 0.01, "alpha {}", fit.alpha);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn power_law(
    pixels: &LoadedPixels<'_>,
    weights: Option<&[f64]>,
    view: &View,
    params: &CisParams,
    fit_range: Option<FitRange>,
) -> Result<PowerLaw> {
    let params = CisParams {
        smooth: false,
        aggregate_smoothed: false,
        ..*params
    };
    let table = expected_cis(pixels, weights, view, &params)?;
    power_law_of_table(
        table,
        params.ignore_diags,
        view.median_length_bp(),
        fit_range,
    )
}

/// Log-bin a cis table and fit its power laws; `median_region_bp` and `ignore_diags` set the
/// default range ([`default_fit_range`]).
pub fn power_law_of_table(
    table: CisExpected,
    ignore_diags: usize,
    median_region_bp: f64,
    fit_range: Option<FitRange>,
) -> Result<PowerLaw> {
    let binned = logbin_expected(&table, &LogBinParams::default())?;
    let range = fit_range
        .unwrap_or_else(|| default_fit_range(table.resolution, ignore_diags, median_region_bp));
    let fit = fit_log_binned(&binned, &FitParams::new(range));
    Ok(PowerLaw { table, binned, fit })
}

impl PowerLawReport {
    /// The single power law in one line (what `expected --logbin` and `plot expected --fit`
    /// print): exponent, its 95% interval, R², the distances fitted and the range asked for.
    ///
    /// ```
    /// use contactmap::expected::powerlaw::power_law;
    /// use contactmap::expected::CisParams;
    /// use contactmap::genome::View;
    /// use contactmap::io::{load_pixels, open_matrix, OpenOptions};
    /// let reader = open_matrix("data/yeast.10kb.cool", &OpenOptions::default())?;
    /// let weights = reader.weights("weight")?.values;
    /// let pixels = load_pixels(reader.as_ref(), u64::MAX)?;
    /// let view = View::chromosomes(reader.bins());
    /// let range = "20k-200k".parse()?;
    /// let report = power_law(&pixels, Some(&weights), &view, &CisParams::default(), Some(range))?.fit?;
    /// assert!(report.headline().starts_with("P(s) ~ s^-"));
    /// assert!(report.headline().ends_with("in 20 kb - 200 kb)"));
    /// let text = report.summary_text();
    /// assert!(text.starts_with(&report.headline()) && text.contains("piecewise: "));
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn headline(&self) -> String {
        let fit = &self.fit;
        format!(
            "P(s) ~ s^{:.2} [95% CI {:.2}, {:.2}], R² {:.3}, fitted {} - {} ({} log bins in {} - {})",
            fit.alpha,
            fit.ci95.0,
            fit.ci95.1,
            fit.r_squared,
            format_distance(fit.first_bp),
            format_distance(fit.last_bp),
            fit.n_points,
            format_bp(self.range.min_bp),
            format_bp(self.range.max_bp),
        )
    }

    /// The headline, then the piecewise fit: its breakpoints and one line per segment (what
    /// `expected --fit` writes).
    pub fn summary_text(&self) -> String {
        let mut text = self.headline();
        text.push('\n');
        let piecewise = &self.piecewise;
        let breaks: Vec<String> = piecewise
            .breakpoints_bp
            .iter()
            .map(|&b| format_bp(b))
            .collect();
        text.push_str(&match breaks.len() {
            0 => "piecewise: no breakpoint (one power law is best by BIC)\n".to_string(),
            n => format!(
                "piecewise: {n} breakpoint{} by BIC, at {}\n",
                if n == 1 { "" } else { "s" },
                breaks.join(", ")
            ),
        });
        for segment in &piecewise.segments {
            text.push_str(&format!(
                "  {} - {}: s^{:.2} [95% CI {:.2}, {:.2}], {} log bins\n",
                format_bp(segment.start_bp),
                format_bp(segment.end_bp),
                segment.alpha,
                segment.ci95.0,
                segment.ci95.1,
                segment.n_points
            ));
        }
        text
    }

    /// The report as JSON (what `expected --json` prints): the input `uri`, the values
    /// (balanced by `weight_name` or raw), the bin size and fit range, the single power law, the
    /// piecewise fit with its BIC per number of breakpoints, and the points fitted.
    pub fn to_json(
        &self,
        uri: &str,
        weight_name: &str,
        table: &CisExpected,
        binned: &LogBinned,
    ) -> serde_json::Value {
        let report = self;
        use serde_json::json;
        let fit = &report.fit;
        let piecewise = &report.piecewise;
        let points: Vec<serde_json::Value> = fit_bins(binned, &report.range)
            .iter()
            .zip(&report.points)
            .map(|(bin, (s, p))| {
                json!({
                    "dist_bin_id": bin.dist_bin_id,
                    "dist_bp_avg": bin.dist_avg * table.resolution as f64,
                    "dist_bp_effective": s,
                    "p": p,
                    "n_valid": bin.n_valid,
                })
            })
            .collect();
        json!({
            "uri": uri,
            "values": if table.is_balanced() { format!("balanced ({weight_name})") } else { "raw counts".to_string() },
            "bin_size_bp": table.resolution,
            "fit_range_bp": [report.range.min_bp, report.range.max_bp],
            "power_law": {
                "alpha": fit.alpha,
                "intercept_log10": fit.intercept_log10,
                "stderr": fit.stderr,
                "ci95": [fit.ci95.0, fit.ci95.1],
                "r_squared": fit.r_squared,
                "rss_log10": fit.rss,
                "n_points": fit.n_points,
                "dof": fit.dof,
                "first_bp": fit.first_bp,
                "last_bp": fit.last_bp,
            },
            "piecewise": {
                "n_breakpoints": piecewise.breakpoints_bp.len(),
                "breakpoints_bp": piecewise.breakpoints_bp,
                "segments": piecewise.segments.iter().map(|s| json!({
                    "start_bp": s.start_bp,
                    "end_bp": s.end_bp,
                    "alpha": s.alpha,
                    "stderr": s.stderr,
                    "ci95": [s.ci95.0, s.ci95.1],
                    "n_points": s.n_points,
                })).collect::<Vec<_>>(),
                "rss_log10": piecewise.rss,
                "bic_by_breakpoints": piecewise.bic_by_breakpoints,
            },
            "points": points,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_ranges_parse_with_units() {
        let range: FitRange = "100k-10M".parse().unwrap();
        assert_eq!((range.min_bp, range.max_bp), (1e5, 1e7));
        let range: FitRange = "200,000-1.5Mb".parse().unwrap();
        assert_eq!((range.min_bp, range.max_bp), (2e5, 1.5e6));
        for bad in ["10M-1M", "abc", "1x-2M", "0-1M"] {
            let error = bad.parse::<FitRange>().unwrap_err().to_string();
            assert!(
                error.starts_with(&format!("fit_range '{bad}': ")),
                "{error}"
            );
        }
    }

    fn power_law(alpha: f64, n: usize) -> Vec<(f64, f64)> {
        (0..n)
            .map(|i| {
                let s = 1e5 * 10f64.powf(i as f64 / 10.0);
                (s, 3.0 * s.powf(alpha))
            })
            .collect()
    }

    #[test]
    fn exact_power_laws_are_recovered() {
        let fit = fit_power_law(&power_law(-1.08, 20)).unwrap();
        assert!((fit.alpha + 1.08).abs() < 1e-12);
        assert!((fit.r_squared - 1.0).abs() < 1e-12);
        assert!((fit.intercept_log10 - 3f64.log10()).abs() < 1e-9);
        assert_eq!(fit.dof, 18);
        let piecewise = fit_piecewise(
            &power_law(-1.08, 20),
            &FitParams::new(FitRange {
                min_bp: 1.0,
                max_bp: 1e12,
            }),
        )
        .unwrap();
        assert!(piecewise.breakpoints_bp.is_empty());
        assert!((piecewise.segments[0].alpha + 1.08).abs() < 1e-9);
    }

    #[test]
    fn t_interval_matches_tables() {
        // t(0.975) with 10 degrees of freedom is 2.228139.
        assert!((t_quantile_95(10) - 2.228139).abs() < 1e-5);
        // Noisy line: the interval is alpha -/+ t * se.
        let points: Vec<(f64, f64)> = (0..12)
            .map(|i| {
                let s = 10f64.powf(5.0 + i as f64 / 5.0);
                let wiggle = if i % 2 == 0 { 1.02 } else { 0.98 };
                (s, s.powf(-1.0) * wiggle)
            })
            .collect();
        let fit = fit_power_law(&points).unwrap();
        let t = t_quantile_95(10);
        assert!((fit.ci95.1 - fit.alpha - t * fit.stderr).abs() < 1e-12);
        assert!(fit.ci95.0 < -1.0 && fit.ci95.1 > -1.0);
    }

    #[test]
    fn a_broken_line_is_split_at_its_break() {
        let points: Vec<(f64, f64)> = (0..30)
            .map(|i| {
                let x = 5.0 + i as f64 / 10.0;
                let y = if x <= 6.2 {
                    -0.7 * x
                } else {
                    -0.7 * 6.2 - 1.5 * (x - 6.2)
                };
                (10f64.powf(x), 10f64.powf(y))
            })
            .collect();
        let fit = fit_piecewise(
            &points,
            &FitParams::new(FitRange {
                min_bp: 1.0,
                max_bp: 1e12,
            }),
        )
        .unwrap();
        assert_eq!(fit.breakpoints_bp.len(), 1);
        assert!((fit.breakpoints_bp[0].log10() - 6.2).abs() < 1e-9);
        assert!((fit.segments[0].alpha + 0.7).abs() < 1e-9);
        assert!((fit.segments[1].alpha + 1.5).abs() < 1e-9);
        assert_eq!(fit.segments[0].n_points + fit.segments[1].n_points, 31);
    }

    #[test]
    fn placements_respect_segment_sizes() {
        // 7 points, segments of at least 3 points: breakpoints at 2..=4.
        assert_eq!(placements(7, 1, 3), vec![vec![2], vec![3], vec![4]]);
        assert_eq!(placements(7, 2, 3), vec![vec![2, 4]]);
        assert!(placements(7, 3, 3).is_empty());
        assert_eq!(placements(7, 0, 3), vec![Vec::<usize>::new()]);
    }

    #[test]
    fn inverse_of_a_small_matrix() {
        let m = vec![vec![4.0, 2.0], vec![2.0, 3.0]];
        let inv = invert_spd(&m).unwrap();
        assert!((inv[0][0] - 0.375).abs() < 1e-12);
        assert!((inv[0][1] + 0.25).abs() < 1e-12);
        assert!((inv[1][1] - 0.5).abs() < 1e-12);
        assert!(invert_spd(&[vec![1.0, 1.0], vec![1.0, 1.0]]).is_none());
    }
}
