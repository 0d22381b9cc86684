//! What the comparisons' tables share: how a number is written.

/// A value as the diff tables write it: 7 significant digits in scientific notation, `nan`
/// for a missing one.
pub fn number(value: f64) -> String {
    if value.is_nan() {
        "nan".to_string()
    } else {
        format!("{value:.6e}")
    }
}
