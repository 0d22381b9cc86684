//! P(s) helpers shared by the subcommands that fit power laws (`expected --fit / --logbin`,
//! `plot expected`): the `--fit-range` syntax, the log-binning and fits of a cis expected table,
//! and the one-line and multi-line reports.

use crate::error::{Error, Result};
use crate::expected::logbin::{logbin_expected, LogBinParams, LogBinned};
use crate::expected::powerlaw::{
    default_fit_range, fit_log_binned, FitParams, FitRange, PowerLawReport,
};
use crate::expected::{expected_cis, CisExpected, CisParams, View};
use crate::genome::{format_bp, format_distance};
use crate::io::LoadedPixels;

/// A cis expected table, its log-binned P(s) and the power-law fits (the fit may fail: too few
/// points in the range).
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
/// default range.
pub fn power_law_of_table(
    table: CisExpected,
    ignore_diags: usize,
    median_region_bp: f64,
    fit_range: Option<FitRange>,
) -> Result<PowerLaw> {
    let binned = logbin_expected(&table, &LogBinParams::default())?;
    let range = fit_range
        .unwrap_or_else(|| default_fit_range(table.bin_size_bp, ignore_diags, median_region_bp));
    let fit = fit_log_binned(&binned, &FitParams::new(range));
    Ok(PowerLaw { table, binned, fit })
}

/// Parse `--fit-range MIN-MAX` in bp with optional k / kb / M / Mb / G / Gb suffixes
/// (`100k-10M`, `200,000-1.5Mb`).
pub fn parse_fit_range(text: &str) -> Result<FitRange> {
    let bad = |why: &str| {
        Error::Invalid(format!(
            "--fit-range '{text}': {why} (expected MIN-MAX in bp, e.g. 100k-10M)"
        ))
    };
    let (min, max) = text.split_once('-').ok_or_else(|| bad("no '-'"))?;
    let parse = |part: &str| -> Result<f64> {
        let cleaned: String = part
            .trim()
            .chars()
            .filter(|&c| c != ',' && c != '_')
            .collect::<String>()
            .to_ascii_lowercase();
        let (number, multiplier) = [
            ("gb", 1e9),
            ("mb", 1e6),
            ("kb", 1e3),
            ("g", 1e9),
            ("m", 1e6),
            ("k", 1e3),
            ("bp", 1.0),
        ]
        .iter()
        .find_map(|(suffix, m)| cleaned.strip_suffix(suffix).map(|n| (n.to_string(), *m)))
        .unwrap_or((cleaned.clone(), 1.0));
        let value: f64 = number
            .trim()
            .parse()
            .map_err(|_| bad(&format!("'{}' is not a distance", part.trim())))?;
        Ok(value * multiplier)
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

/// The one-line summary: the exponent, its interval, R² and the distances of the points fitted
/// (log bins have effective distances, so the first point lies inside the range asked for:
/// `P(s) ~ s^-1.08 [95% CI -1.10, -1.06], R² 0.998, fitted 126 kb - 8.9 Mb (20 log bins in
/// 100 kb - 10 Mb)`).
pub fn headline(report: &PowerLawReport) -> String {
    let fit = &report.fit;
    format!(
        "P(s) ~ s^{:.2} [95% CI {:.2}, {:.2}], R² {:.3}, fitted {} - {} ({} log bins in {} - {})",
        fit.alpha,
        fit.ci95.0,
        fit.ci95.1,
        fit.r_squared,
        format_distance(fit.first_bp),
        format_distance(fit.last_bp),
        fit.n_points,
        format_bp(report.range.min_bp),
        format_bp(report.range.max_bp),
    )
}

/// The headline and the piecewise exponents, one segment per line.
pub fn fit_text(report: &PowerLawReport) -> String {
    let mut text = headline(report);
    text.push('\n');
    let piecewise = &report.piecewise;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_parse_with_units() {
        let range = parse_fit_range("100k-10M").unwrap();
        assert_eq!((range.min_bp, range.max_bp), (1e5, 1e7));
        let range = parse_fit_range("200,000-1.5Mb").unwrap();
        assert_eq!((range.min_bp, range.max_bp), (2e5, 1.5e6));
        assert!(parse_fit_range("10M-1M").is_err());
        assert!(parse_fit_range("abc").is_err());
        assert!(parse_fit_range("1x-2M").is_err());
    }
}
