//! The vocabulary of contact-list scoring: separation ranges (`short`, `medium`, `long`, `all`,
//! `MIN-MAX`, `MIN+`), list sizes (`L/5`, `0.5L`, a count, `NC`) and what L is (the sequence,
//! the observed residues, a number), parsed from the text users write (CASP's, ConKit's,
//! ConEVA's and DISTEVAL's names).

use super::contacts::{ListSize, Prediction, SeparationRange, TargetLength};
use crate::error::{Error, Result};

/// A list size with its label as written (`L/5`, `NC`, ...).
pub type LabelledSize = (String, ListSize);

/// A named separation range.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedRange {
    /// The range as written, lower case (`long`, `12-23`, `6+`).
    pub name: String,
    /// The range.
    pub range: SeparationRange,
}

/// Parse a separation range: short, medium, long, all, MIN-MAX or MIN+.
///
/// # Examples
///
/// ```
/// use contactmap::score::contacts::SeparationRange;
/// use contactmap::score::lists::parse_range;
///
/// assert_eq!(parse_range("long")?.range, SeparationRange::LONG);
/// assert_eq!(parse_range("12-23")?.range, SeparationRange::new(12, Some(23)));
/// assert!(parse_range("9-3").is_err());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn parse_range(token: &str) -> Result<NamedRange> {
    let token = token.trim();
    let bad = || {
        Error::Argument(format!(
            "bad separation range '{token}' (expected short, medium, long, all, MIN-MAX or MIN+)"
        ))
    };
    let number = |text: &str| text.trim().parse::<u32>().map_err(|_| bad());
    let range = match token.to_ascii_lowercase().as_str() {
        "short" => SeparationRange::SHORT,
        "medium" => SeparationRange::MEDIUM,
        "long" => SeparationRange::LONG,
        "all" => SeparationRange::ALL,
        other => {
            if let Some(min) = other.strip_suffix('+') {
                SeparationRange::new(number(min)?, None)
            } else if let Some((min, max)) = other.split_once('-') {
                let (min, max) = (number(min)?, number(max)?);
                if max < min {
                    return Err(bad());
                }
                SeparationRange::new(min, Some(max))
            } else {
                return Err(bad());
            }
        }
    };
    Ok(NamedRange {
        name: token.to_ascii_lowercase(),
        range,
    })
}

/// Parse a list size: L/10, L, 0.3L, a count N or NC; returns it with its label as written.
///
/// # Examples
///
/// ```
/// use contactmap::score::contacts::ListSize;
/// use contactmap::score::lists::parse_list_size;
///
/// assert_eq!(parse_list_size("L/5")?, ("L/5".to_string(), ListSize::Fraction(0.2)));
/// assert_eq!(parse_list_size("NC")?.1, ListSize::TrueContacts);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn parse_list_size(token: &str) -> Result<(String, ListSize)> {
    let token = token.trim();
    let bad = || {
        Error::Argument(format!(
            "bad list size '{token}' (expected L/10, L, 0.3L, a count N, or NC)"
        ))
    };
    let upper = token.to_ascii_uppercase();
    let size = if upper == "NC" {
        ListSize::TrueContacts
    } else if upper == "L" {
        ListSize::Fraction(1.0)
    } else if let Some(divisor) = upper.strip_prefix("L/") {
        let divisor: f64 = divisor.parse().map_err(|_| bad())?;
        if !(divisor.is_finite() && divisor > 0.0) {
            return Err(bad());
        }
        ListSize::Fraction(1.0 / divisor)
    } else if let Some(fraction) = upper.strip_suffix('L') {
        let fraction: f64 = fraction.trim_end_matches('*').parse().map_err(|_| bad())?;
        if !(fraction.is_finite() && fraction >= 0.0) {
            return Err(bad());
        }
        ListSize::Fraction(fraction)
    } else {
        ListSize::Count(token.parse().map_err(|_| bad())?)
    };
    Ok((token.to_string(), size))
}

/// What L is, as asked on the command line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LengthChoice {
    /// The sequence when the prediction has one, else the size of its matrix, else the
    /// observed residues.
    Auto,
    /// As given.
    Fixed(TargetLength),
}

impl LengthChoice {
    /// What L is for `prediction`, and where it comes from (`sequence`, `matrix size`,
    /// `observed`, `given`).
    pub fn resolve(self, prediction: &Prediction) -> (TargetLength, &'static str) {
        match self {
            LengthChoice::Auto if prediction.sequence.is_some() => {
                (TargetLength::Sequence, "sequence")
            }
            LengthChoice::Auto => match prediction.length {
                Some(n) => (TargetLength::Residues(n), "matrix size"),
                None => (TargetLength::Observed, "observed"),
            },
            LengthChoice::Fixed(TargetLength::Sequence) => (TargetLength::Sequence, "sequence"),
            LengthChoice::Fixed(TargetLength::Observed) => (TargetLength::Observed, "observed"),
            LengthChoice::Fixed(fixed) => (fixed, "given"),
        }
    }
}

/// Parse `--length`: sequence, observed or a positive number (`None`: [`LengthChoice::Auto`]).
pub fn parse_length(text: Option<&str>) -> Result<LengthChoice> {
    Ok(match text.map(str::trim) {
        None => LengthChoice::Auto,
        Some(text) => match text.to_ascii_lowercase().as_str() {
            "sequence" | "seq" => LengthChoice::Fixed(TargetLength::Sequence),
            "observed" => LengthChoice::Fixed(TargetLength::Observed),
            other => match other.parse::<usize>() {
                Ok(n) if n > 0 => LengthChoice::Fixed(TargetLength::Residues(n)),
                _ => {
                    return Err(Error::Argument(format!(
                        "bad --length '{text}' (expected sequence, observed or a positive number)"
                    )));
                }
            },
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_list_size_and_length_parsing() {
        assert_eq!(parse_range("long").unwrap().range, SeparationRange::LONG);
        assert_eq!(
            parse_range("12-23").unwrap().range,
            SeparationRange::new(12, Some(23))
        );
        assert_eq!(
            parse_range("5+").unwrap().range,
            SeparationRange::new(5, None)
        );
        for bad in ["", "9-3", "x", "5", "-3"] {
            assert!(parse_range(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_list_size("L/5").unwrap().1, ListSize::Fraction(0.2));
        assert_eq!(parse_list_size("L").unwrap().1, ListSize::Fraction(1.0));
        assert_eq!(parse_list_size("1.5L").unwrap().1, ListSize::Fraction(1.5));
        assert_eq!(parse_list_size("30").unwrap().1, ListSize::Count(30));
        assert_eq!(parse_list_size("nc").unwrap().1, ListSize::TrueContacts);
        for bad in ["L/0", "xL", "-1", "L/"] {
            assert!(parse_list_size(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_length(None).unwrap(), LengthChoice::Auto);
        assert_eq!(
            parse_length(Some("observed")).unwrap(),
            LengthChoice::Fixed(TargetLength::Observed)
        );
        assert_eq!(
            parse_length(Some("70")).unwrap(),
            LengthChoice::Fixed(TargetLength::Residues(70))
        );
        assert!(parse_length(Some("0")).is_err());
    }
}
