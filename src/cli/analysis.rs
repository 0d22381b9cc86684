//! P(s) helpers shared by the subcommands that fit power laws (`expected --fit / --logbin`,
//! `plot expected`): the `--fit-range` syntax and the one-line and multi-line reports of
//! [`contactmap::expected::powerlaw::power_law`].

use contactmap::error::{Error, Result};
use contactmap::expected::powerlaw::{FitRange, PowerLawReport};
use contactmap::genome::{format_bp, format_distance};

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
