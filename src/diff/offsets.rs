//! Counts tested against an expected count per feature and sample: the normalisation factor
//! of a feature in a sample is its expected count over the geometric mean of its expected counts
//! across the samples (DESeq2's `normalizationFactors`), so that what the expected explains
//! (depth, the contact law, a chromosome's coverage) is not called a change. What `diff loops`
//! (the expected at each loop's distance) and `diff boundaries` (the flanks of each boundary)
//! share.

use ndarray::{Array2, ArrayView2};

use super::model::{Design, Normalization, Params, Results, fit_normalized, results};
use crate::error::Result;

/// The test of B against A of `observed` counts (one row per feature; the first `n_first`
/// columns A) with `expected` counts of the same shape, every one positive: the Wald test's
/// results and the normalisation factors.
pub fn test_against_expected(
    observed: ArrayView2<'_, f64>,
    expected: ArrayView2<'_, f64>,
    n_first: usize,
    model: &Params,
    cooks_filter: bool,
) -> Result<(Results, Array2<f64>)> {
    let n_samples = observed.ncols();
    let conditions: Vec<usize> = (0..n_samples).map(|s| usize::from(s >= n_first)).collect();
    let design = Design::conditions(&conditions, &["A", "B"])?;
    let mut factors = expected.to_owned();
    for mut row in factors.rows_mut() {
        let log_mean = row.iter().map(|e| e.ln()).sum::<f64>() / row.len() as f64;
        row.mapv_inplace(|e| e / log_mean.exp());
    }
    let fit = fit_normalized(
        observed,
        &design,
        model,
        Normalization::Factors(factors.view()),
    )?;
    let tested = results(observed, &fit, &design, &design.contrast(1), cooks_filter);
    Ok((tested, factors))
}

/// Each feature's mean normalised count in A (column 0) and B (column 1).
pub fn condition_means(
    observed: ArrayView2<'_, f64>,
    factors: ArrayView2<'_, f64>,
    n_first: usize,
) -> Array2<f64> {
    let n_samples = observed.ncols();
    Array2::from_shape_fn((observed.nrows(), 2), |(f, c)| {
        let samples: Vec<usize> = (0..n_samples)
            .filter(|&s| usize::from(s >= n_first) == c)
            .collect();
        samples
            .iter()
            .map(|&s| observed[[f, s]] / factors[[f, s]])
            .sum::<f64>()
            / samples.len() as f64
    })
}
