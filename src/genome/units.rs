//! Base pairs for people: distances written (`250 kb`) and read (`1.5M`, `1,000,000`).

/// A distance for people: `250 kb`, `1.2 Mb`, `800 bp` (at most two decimals, trailing zeros
/// dropped).
pub fn format_bp(value: f64) -> String {
    let (scaled, unit) = in_units(value);
    let digits = format!("{scaled:.2}");
    let trimmed = digits.trim_end_matches('0').trim_end_matches('.');
    format!("{trimmed} {unit}")
}

/// `value` bp in the largest of Mb, kb and bp that keeps it at least 1.
fn in_units(value: f64) -> (f64, &'static str) {
    if value.abs() >= 1e6 {
        (value / 1e6, "Mb")
    } else if value.abs() >= 1e3 {
        (value / 1e3, "kb")
    } else {
        (value, "bp")
    }
}

/// A distance that is not a round number of bins (the effective distance of a log bin) to three
/// significant digits: `10.9 kb`, `892 kb`, `4.43 Mb`.
pub fn format_distance(value: f64) -> String {
    let (scaled, unit) = in_units(value);
    let decimals = if scaled.abs() >= 100.0 {
        0
    } else if scaled.abs() >= 10.0 {
        1
    } else {
        2
    };
    let digits = format!("{scaled:.decimals$}");
    let trimmed = if digits.contains('.') {
        digits.trim_end_matches('0').trim_end_matches('.')
    } else {
        &digits
    };
    format!("{trimmed} {unit}")
}

/// The number and unit multiplier of a distance such as `1,000,000`, `1.5M` or `200kb`: digit
/// separators (`,` `_`) removed, lower-cased, a `gb` / `mb` / `kb` / `bp` / `g` / `m` / `k`
/// suffix split off.
fn split_unit(text: &str) -> (String, f64) {
    let lower: String = text
        .trim()
        .chars()
        .filter(|&c| c != ',' && c != '_')
        .collect::<String>()
        .to_ascii_lowercase();
    [
        ("gb", 1e9),
        ("mb", 1e6),
        ("kb", 1e3),
        ("bp", 1.0),
        ("g", 1e9),
        ("m", 1e6),
        ("k", 1e3),
    ]
    .iter()
    .find_map(|(suffix, m)| {
        lower
            .strip_suffix(suffix)
            .map(|n| (n.trim().to_string(), *m))
    })
    .unwrap_or((lower.clone(), 1.0))
}

/// Parse a distance in bp that need not be whole, such as `1.5Mb`, `200,000` or `2.5k`.
///
/// ```
/// use contactmap::genome::parse_distance;
/// assert_eq!(parse_distance("1.5Mb"), Some(1.5e6));
/// assert_eq!(parse_distance("2.5k"), Some(2500.0));
/// assert_eq!(parse_distance("ten"), None);
/// ```
pub fn parse_distance(text: &str) -> Option<f64> {
    let (number, multiplier) = split_unit(text);
    number.parse::<f64>().ok().map(|value| value * multiplier)
}

/// Parse a base-pair position such as `1,000,000`, `1_000_000`, `1.5M`, `200kb`.
pub fn parse_bp(text: &str) -> std::result::Result<u64, String> {
    let (number, multiplier) = split_unit(text);
    let number = number.as_str();
    if number.is_empty() {
        return Err(format!("'{text}' is not a position"));
    }
    if number.starts_with('-') && number[1..].parse::<f64>().is_ok() {
        return Err(format!(
            "'{text}' is negative: base-pair positions and sizes are 0 or more"
        ));
    }
    if multiplier == 1.0 {
        return number.parse::<u64>().map_err(|_| {
            format!("'{text}' is not a position (expected a whole number of base pairs)")
        });
    }
    let value: f64 = number
        .parse()
        .map_err(|_| format!("'{text}' is not a position"))?;
    let bp = value * multiplier;
    if !(bp >= 0.0 && bp.fract() == 0.0 && bp < 9.0e18) {
        return Err(format!("'{text}' is not a whole number of base pairs"));
    }
    Ok(bp as u64)
}
