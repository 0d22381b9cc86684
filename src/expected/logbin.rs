//! Log-binned P(s) and its local slope, as cooltools' `logbin_expected` and
//! `combine_binned_expected` (0.7.1) compute them.
//!
//! 1. Diagonals are grouped into log-spaced bins of distance: cooltools' `persistent_log_bins`
//!    (10 per decade by default; integer edges 1, 2, 3, 4, 5, 6, 8, 10, 13, 16, 20, 25, ...,
//!    identical for every dataset, so that curves can be divided by each other). Bin `k` holds
//!    the diagonals `edges[k] ..= edges[k + 1] - 1`; diagonal 0 is in no bin.
//! 2. Per region and bin: the sums of `n_valid`, of the summary (`balanced.sum`, or `count.sum`
//!    for raw tables) and of `count.sum` over the diagonals whose summary is not NaN; the
//!    distance `dist.avg` is the `n_valid`-weighted mean diagonal (not the bin's midpoint), and
//!    P(s) is `summary / n_valid` (sums divided at the end, not averages averaged). Bins with
//!    `n_valid <= 200`, `P = 0` or `count.sum <= 50` are dropped (`min_nvalid`, `min_count`).
//! 3. Per-region slope: d ln P / d ln s between consecutive kept bins, after smoothing both
//!    `ln P` and `ln dist.avg` with [`robust_gauss_filter`] (sigma 2 bins), placed at the
//!    geometric mean of the two distances, with `n_valid` the smaller of the two.
//! 4. Combined over regions (the genome-wide curve): per bin, the `n_valid`-weighted means of P
//!    and `dist.avg`, with a spread `P / e^sd .. P * e^sd` where `sd` is the weighted standard
//!    deviation of `ln P` across regions ("logstd"); the combined slope as in 3 with sigma 1.3,
//!    and its spread `slope -/+ sd` from the weighted standard deviation of the region slopes in
//!    the same bin ("std").
//!
//! Distances here are in bins (diagonals), as in cooltools; multiply by the bin size for bp.

use super::result::CisExpected;
use super::smooth::robust_gauss_filter;
use crate::error::{Error, Result};

/// Parameters of [`logbin_expected`], with cooltools' defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogBinParams {
    /// Log bins per decade of distance (default 10).
    pub bins_per_order_magnitude: usize,
    /// Drop region bins with at most this many valid pixels (default 200).
    pub min_nvalid: u64,
    /// Drop region bins with at most this many raw counts (default 50; 0 keeps all).
    pub min_count: f64,
    /// Smoothing (in bins) of per-region curves before their slopes (default 2).
    pub region_slope_sigma: f64,
    /// Smoothing (in bins) of the combined curve before its slope (default 1.3).
    pub combined_slope_sigma: f64,
}

impl LogBinParams {
    /// Check the values: at least one bin per decade, positive slope-smoothing widths, a
    /// `min_count` that is a number. [`logbin_expected`] checks them first.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::expected::logbin::LogBinParams;
    ///
    /// assert!(LogBinParams::default().check().is_ok());
    /// let bad = LogBinParams { bins_per_order_magnitude: 0, ..LogBinParams::default() };
    /// assert!(bad.check().is_err());
    /// ```
    pub fn check(&self) -> Result<()> {
        if self.bins_per_order_magnitude == 0 {
            return Err(Error::parameter(
                "bins_per_order_magnitude",
                0,
                "expected at least 1",
            ));
        }
        if self.min_count.is_nan() {
            return Err(Error::parameter(
                "min_count",
                self.min_count,
                "expected a number",
            ));
        }
        for (name, sigma) in [
            ("region_slope_sigma", self.region_slope_sigma),
            ("combined_slope_sigma", self.combined_slope_sigma),
        ] {
            if !(sigma.is_finite() && sigma > 0.0) {
                return Err(Error::parameter(name, sigma, "expected a positive number"));
            }
        }
        Ok(())
    }
}

impl Default for LogBinParams {
    fn default() -> Self {
        LogBinParams {
            bins_per_order_magnitude: 10,
            min_nvalid: 200,
            min_count: 50.0,
            region_slope_sigma: 2.0,
            combined_slope_sigma: 1.3,
        }
    }
}

/// One log bin of one region.
#[derive(Clone, Debug, PartialEq)]
pub struct RegionBin {
    /// Index of the region in the expected table's `region_names`.
    pub region: u32,
    /// Index of the log bin.
    pub dist_bin_id: usize,
    /// First diagonal of the bin.
    pub dist_bin_start: u64,
    /// Last diagonal of the bin (inclusive).
    pub dist_bin_end: u64,
    /// `n_valid`-weighted mean diagonal.
    pub dist_avg: f64,
    /// Valid pixels in the bin.
    pub n_valid: u64,
    /// Raw counts in the bin.
    pub count_sum: f64,
    /// Summed values (`balanced.sum` or `count.sum`).
    pub summary_sum: f64,
    /// P(s): `summary_sum / n_valid`.
    pub average: f64,
    /// The rows of the expected table behind this bin (with a non-NaN summary).
    pub rows: Vec<usize>,
}

/// A slope between two consecutive log bins (of one region, or combined).
#[derive(Clone, Debug, PartialEq)]
pub struct Slope {
    /// Index of the region in `region_names` (`None` for the combined curve).
    pub region: Option<u32>,
    /// Log bin of the left point.
    pub dist_bin_id: usize,
    /// Geometric mean of the two distances (in bins).
    pub dist_avg: f64,
    /// d ln P / d ln s.
    pub slope: f64,
    /// The smaller `n_valid` of the two bins.
    pub n_valid: u64,
    /// Lower end of the spread across regions (combined slopes only; NaN when unknown).
    pub low_err: f64,
    /// Upper end of the spread across regions (combined slopes only; NaN when unknown).
    pub high_err: f64,
}

/// One log bin of the combined (genome-wide) curve.
#[derive(Clone, Debug, PartialEq)]
pub struct CombinedBin {
    /// Index of the log bin.
    pub dist_bin_id: usize,
    /// First diagonal of the bin.
    pub dist_bin_start: u64,
    /// Last diagonal of the bin (inclusive).
    pub dist_bin_end: u64,
    /// `n_valid`-weighted mean of the regions' `dist_avg`.
    pub dist_avg: f64,
    /// Valid pixels in the bin, all regions.
    pub n_valid: u64,
    /// `n_valid`-weighted mean of the regions' P(s).
    pub average: f64,
    /// `average / e^sd`, `sd` the weighted standard deviation of ln P(s) across regions.
    pub low_err: f64,
    /// `average * e^sd`.
    pub high_err: f64,
    /// The diagonals behind the bin and their valid pixels summed over the regions kept in it,
    /// `(dist, n_valid)`: for the effective distance of a power-law fit.
    pub diagonals: Vec<(u64, u64)>,
}

impl CombinedBin {
    /// The distance (in bins) at which a power law `s^alpha` takes the bin's average value:
    /// `(sum n_valid(d) d^alpha / sum n_valid(d))^(1 / alpha)`. P(s) is convex, so the mean of
    /// `d^alpha` over a bin exceeds `dist_avg^alpha`; fitting at this distance removes that bias.
    /// `dist_avg` when `alpha` is 0 or not finite.
    pub fn effective_dist(&self, alpha: f64) -> f64 {
        let total: f64 = self.diagonals.iter().map(|&(_, n)| n as f64).sum();
        if !(alpha.is_finite() && alpha != 0.0) || total <= 0.0 {
            return self.dist_avg;
        }
        let mean: f64 = self
            .diagonals
            .iter()
            .map(|&(d, n)| n as f64 * (d as f64).powf(alpha))
            .sum::<f64>()
            / total;
        mean.powf(1.0 / alpha)
    }
}

/// Log-binned P(s): per region and combined, with slopes.
#[derive(Clone, Debug, PartialEq)]
pub struct LogBinned {
    /// Bin size of the matrix in bp.
    pub resolution: u64,
    /// `balanced` or `count`: which average P(s) is.
    pub prefix: &'static str,
    /// Region names (as in the expected table).
    pub region_names: Vec<String>,
    /// Per-region bins, by region (view order) then bin.
    pub by_region: Vec<RegionBin>,
    /// Per-region slopes, by region then bin.
    pub region_slopes: Vec<Slope>,
    /// The combined curve, by bin.
    pub combined: Vec<CombinedBin>,
    /// Slopes of the combined curve, by bin (one fewer than `combined`).
    pub slopes: Vec<Slope>,
}

/// cooltools' `persistent_log_bins(end, bins_per_order_magnitude)`: integer bin edges from 1 to
/// `10^end`, log-spaced, with non-decreasing gaps.
///
/// # Examples
///
/// ```
/// use contactmap::expected::logbin::persistent_log_bins;
///
/// let edges = persistent_log_bins(2, 10);
/// let cooltools = [1, 2, 3, 4, 5, 6, 8, 10, 13, 16, 20, 25, 32, 40, 50, 63, 79, 100];
/// assert_eq!(edges, cooltools);
/// // the same first edges whatever the last decade
/// assert_eq!(persistent_log_bins(5, 10)[..12], cooltools[..12]);
/// ```
pub fn persistent_log_bins(end: u32, bins_per_order_magnitude: usize) -> Vec<u64> {
    let n = end as usize * bins_per_order_magnitude + 1;
    let step = f64::from(end) / (n - 1) as f64;
    let mut rounded: Vec<u64> = (0..n)
        .map(|i| {
            let exponent = if i == n - 1 {
                f64::from(end)
            } else {
                i as f64 * step
            };
            10f64.powf(exponent).round_ties_even() as u64
        })
        .collect();
    rounded.dedup();
    let mut gaps: Vec<u64> = std::iter::once(1)
        .chain(rounded.windows(2).map(|w| w[1] - w[0]))
        .collect();
    gaps.sort_unstable();
    gaps.iter()
        .scan(0u64, |total, gap| {
            *total += gap;
            Some(*total)
        })
        .collect()
}

/// Weighted mean `sum(x * w) / sum(w)` (numpy's `average`).
fn weighted_mean(values: impl Iterator<Item = (f64, f64)> + Clone) -> f64 {
    let total: f64 = values.clone().map(|(_, w)| w).sum();
    values.map(|(x, w)| x * w).sum::<f64>() / total
}

/// Weighted standard deviation around the weighted mean.
fn weighted_sd(values: impl Iterator<Item = (f64, f64)> + Clone) -> f64 {
    let mean = weighted_mean(values.clone());
    weighted_mean(values.map(|(x, w)| ((x - mean) * (x - mean), w))).sqrt()
}

/// Slopes between consecutive points `(id, dist, average, n_valid)` after log smoothing.
fn slopes(points: &[(usize, f64, f64, u64)], sigma: f64, region: Option<u32>) -> Vec<Slope> {
    if points.len() < 2 {
        return Vec::new();
    }
    let log_p: Vec<f64> = points.iter().map(|p| p.2.ln()).collect();
    let log_s: Vec<f64> = points.iter().map(|p| p.1.ln()).collect();
    let smooth_p = robust_gauss_filter(&log_p, sigma);
    let smooth_s = robust_gauss_filter(&log_s, sigma);
    (0..points.len() - 1)
        .map(|k| Slope {
            region,
            dist_bin_id: points[k].0,
            dist_avg: (points[k].1 * points[k + 1].1).sqrt(),
            slope: (smooth_p[k + 1] - smooth_p[k]) / (smooth_s[k + 1] - smooth_s[k]),
            n_valid: points[k].3.min(points[k + 1].3),
            low_err: f64::NAN,
            high_err: f64::NAN,
        })
        .collect()
}

/// Log-bin the cis expected `table` and combine the regions.
///
/// # Examples
///
/// A pure power law `P(s) = 10^4 / s` on one chromosome of 1,000 bins:
/// the log-binned curve keeps its exponent, every combined slope is -1.
///
/// ```
/// use contactmap::expected::logbin::{logbin_expected, LogBinParams};
/// use contactmap::expected::{expected_cis, CisParams};
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 1_000_000)], 1_000)?;
/// let mut builder = MatrixBuilder::new(bins.clone(), CountType::Float);
/// for i in 0..1_000u64 {
///     for j in (i + 1)..1_000 {
///         builder.push(i, j, 1e4 / (j - i) as f64)?;
///     }
/// }
/// let matrix = InMemory::new("power law".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// let params = CisParams { smooth: false, aggregate_smoothed: false, ..CisParams::default() };
/// let table = expected_cis(&pixels, None, &View::chromosomes(&bins), &params)?;
/// let binned = logbin_expected(&table, &LogBinParams::default())?;
/// assert_eq!(binned.prefix, "count");
/// assert!(binned.combined.len() > 10);
/// for slope in &binned.slopes {
///     assert!((slope.slope + 1.0).abs() < 0.05, "{slope:?}");
/// }
/// // each bin's P(s) is the mean of 10^4 / s over its diagonals
/// let first = &binned.combined[0];
/// assert_eq!((first.dist_bin_start, first.dist_bin_end), (2, 2)); // diagonals 0 and 1 ignored
/// assert!((first.average - 5e3).abs() < 1e-9);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn logbin_expected(table: &CisExpected, params: &LogBinParams) -> Result<LogBinned> {
    params.check()?;
    if params.bins_per_order_magnitude == 0 {
        return Err(Error::Argument(
            "log bins per decade must be positive".into(),
        ));
    }
    let edges = persistent_log_bins(10, params.bins_per_order_magnitude);
    let max_dist = table.dist.iter().copied().max().unwrap_or(0);
    if edges[edges.len() - 1] < max_dist {
        return Err(Error::Data(format!(
            "distances up to {max_dist} bins exceed the log bins (up to {})",
            edges[edges.len() - 1]
        )));
    }
    let summary = table.summary();
    let mut by_region: Vec<RegionBin> = Vec::new();
    let mut row = 0;
    while row < table.n_rows() {
        let region = table.region[row];
        let id = edges.partition_point(|&e| e <= table.dist[row]);
        if id == 0 || summary[row].is_nan() {
            row += 1;
            continue;
        }
        let id = id - 1;
        // The run of rows of this region in log bin `id`.
        let (mut n_valid, mut weighted_dist, mut summary_sum, mut count_sum) =
            (0u64, 0u128, 0.0f64, 0.0f64);
        let mut rows = Vec::new();
        while row < table.n_rows() && table.region[row] == region && table.dist[row] < edges[id + 1]
        {
            if !summary[row].is_nan() {
                n_valid += table.n_valid[row];
                weighted_dist += u128::from(table.dist[row]) * u128::from(table.n_valid[row]);
                summary_sum += summary[row];
                count_sum += table.count_sum[row];
                rows.push(row);
            }
            row += 1;
        }
        let average = summary_sum / n_valid as f64;
        let keep = n_valid > params.min_nvalid
            && average > 0.0
            && (params.min_count == 0.0 || count_sum > params.min_count);
        if keep {
            by_region.push(RegionBin {
                region,
                dist_bin_id: id,
                dist_bin_start: edges[id],
                dist_bin_end: edges[id + 1] - 1,
                dist_avg: weighted_dist as f64 / n_valid as f64,
                n_valid,
                count_sum,
                summary_sum,
                average,
                rows,
            });
        }
    }
    let mut region_slopes = Vec::new();
    let mut start = 0;
    while start < by_region.len() {
        let region = by_region[start].region;
        let end = start + by_region[start..].partition_point(|b| b.region == region);
        let points: Vec<(usize, f64, f64, u64)> = by_region[start..end]
            .iter()
            .map(|b| (b.dist_bin_id, b.dist_avg, b.average, b.n_valid))
            .collect();
        region_slopes.extend(slopes(&points, params.region_slope_sigma, Some(region)));
        start = end;
    }

    let n_ids = by_region
        .iter()
        .map(|b| b.dist_bin_id + 1)
        .max()
        .unwrap_or(0);
    let mut combined = Vec::new();
    for id in 0..n_ids {
        let members: Vec<&RegionBin> = by_region.iter().filter(|b| b.dist_bin_id == id).collect();
        if members.is_empty() {
            continue;
        }
        let weighted = |f: fn(&RegionBin) -> f64| {
            weighted_mean(members.iter().map(move |b| (f(b), b.n_valid as f64)))
        };
        let average = weighted(|b| b.average);
        let spread = weighted_sd(members.iter().map(|b| (b.average.ln(), b.n_valid as f64))).exp();
        let first = edges[id];
        let mut diagonals: Vec<(u64, u64)> = (first..edges[id + 1].min(max_dist + 1))
            .map(|d| (d, 0))
            .collect();
        for member in &members {
            for &row in &member.rows {
                diagonals[(table.dist[row] - first) as usize].1 += table.n_valid[row];
            }
        }
        diagonals.retain(|&(_, n)| n > 0);
        combined.push(CombinedBin {
            dist_bin_id: id,
            dist_bin_start: edges[id],
            dist_bin_end: edges[id + 1] - 1,
            dist_avg: weighted(|b| b.dist_avg),
            n_valid: members.iter().map(|b| b.n_valid).sum(),
            average,
            low_err: average / spread,
            high_err: average * spread,
            diagonals,
        });
    }
    let points: Vec<(usize, f64, f64, u64)> = combined
        .iter()
        .map(|b| (b.dist_bin_id, b.dist_avg, b.average, b.n_valid))
        .collect();
    let mut combined_slopes = slopes(&points, params.combined_slope_sigma, None);
    for slope in &mut combined_slopes {
        let members = region_slopes
            .iter()
            .filter(|s| s.dist_bin_id == slope.dist_bin_id);
        if members.clone().next().is_some() {
            let sd = weighted_sd(members.map(|s| (s.slope, s.n_valid as f64)));
            slope.low_err = slope.slope - sd;
            slope.high_err = slope.slope + sd;
        }
    }
    Ok(LogBinned {
        resolution: table.resolution,
        prefix: table.prefix(),
        region_names: table.region_names.clone(),
        by_region,
        region_slopes,
        combined,
        slopes: combined_slopes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn persistent_bins_match_cooltools() {
        // cooltools.lib.numutils.persistent_log_bins(10, 10)
        let bins = persistent_log_bins(10, 10);
        assert_eq!(bins.len(), 98);
        assert_eq!(
            &bins[..30],
            &[
                1, 2, 3, 4, 5, 6, 8, 10, 13, 16, 20, 25, 32, 40, 50, 63, 79, 100, 126, 158, 200,
                251, 316, 398, 501, 631, 794, 1000, 1259, 1585
            ]
        );
        assert_eq!(
            &bins[93..],
            &[3981071706, 5011872336, 6309573445, 7943282347, 10000000000]
        );
    }
}
