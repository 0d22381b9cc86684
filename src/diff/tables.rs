//! What the comparisons' tables share: how a number is written, how samples are named.

/// A value as the diff tables write it: 7 significant digits in scientific notation, `nan`
/// for a missing one.
pub fn number(value: f64) -> String {
    if value.is_nan() {
        "nan".to_string()
    } else {
        format!("{value:.6e}")
    }
}

/// The samples' names, `A1 .. A<n_first>` then `B1 ..`, for `n_samples` samples.
pub fn sample_names(n_samples: usize, n_first: usize) -> Vec<String> {
    (0..n_samples)
        .map(|s| {
            if s < n_first {
                format!("A{}", s + 1)
            } else {
                format!("B{}", s + 1 - n_first)
            }
        })
        .collect()
}

/// The mean of `values` (one sample per entry) over condition A (`condition` 0: the first
/// `n_first`) or B (1: the rest): over its samples with a value (`NaN` ones left out, as the
/// tests leave them out of the feature), `NaN` when none has one.
pub fn condition_mean(
    values: ndarray::ArrayView1<'_, f64>,
    n_first: usize,
    condition: usize,
) -> f64 {
    let part = if condition == 0 {
        values.slice(ndarray::s![..n_first])
    } else {
        values.slice(ndarray::s![n_first..])
    };
    let (sum, n) = part
        .iter()
        .filter(|v| !v.is_nan())
        .fold((0.0, 0usize), |(sum, n), v| (sum + v, n + 1));
    if n == 0 { f64::NAN } else { sum / n as f64 }
}
