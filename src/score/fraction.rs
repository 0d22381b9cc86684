//! The fraction the scores report (a precision, a recall): a count over a count.

/// `numerator / denominator`, or 0 when the denominator is 0 (a precision without calls, a recall
/// without truth).
pub(super) fn ratio(numerator: usize, denominator: usize) -> f64 {
    if denominator == 0 {
        0.0
    } else {
        numerator as f64 / denominator as f64
    }
}
