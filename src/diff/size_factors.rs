//! Size factors: how deep each sample is, from the features themselves.

use ndarray::ArrayView2;

use crate::numeric::median;

/// DESeq2's median-of-ratios size factors (pydeseq2's `deseq2_norm`, `size_factors_fit_type =
/// "ratio"`): each feature's geometric mean over the samples is its reference; a sample's factor
/// is the median, over the features with no zero count, of its count over that reference.
/// `counts` holds one row per feature, one column per sample. `None` when every feature has a
/// zero in some sample (there is then no reference); [`positive_counts`] is for that case.
pub fn median_of_ratios(counts: ArrayView2<f64>) -> Option<Vec<f64>> {
    let n_samples = counts.ncols();
    let usable: Vec<(usize, f64)> = counts
        .rows()
        .into_iter()
        .enumerate()
        .filter_map(|(feature, row)| {
            let log_mean = row.iter().map(|c| c.ln()).sum::<f64>() / n_samples as f64;
            log_mean.is_finite().then_some((feature, log_mean))
        })
        .collect();
    if usable.is_empty() {
        return None;
    }
    Some(
        (0..n_samples)
            .map(|sample| {
                let mut ratios: Vec<f64> = usable
                    .iter()
                    .map(|&(feature, log_mean)| counts[[feature, sample]].ln() - log_mean)
                    .collect();
                median(&mut ratios).exp()
            })
            .collect(),
    )
}

/// DESeq2's `poscounts` size factors (pydeseq2's `"poscounts"`): the reference of a feature is
/// the geometric mean of its positive counts taken over all samples (`Σ log⁺ c / n`); a sample's
/// factor is the median of its positive counts over the references (features whose reference
/// is above zero), scaled so that the factors' geometric mean is 1.
pub fn positive_counts(counts: ArrayView2<f64>) -> Vec<f64> {
    let n_samples = counts.ncols();
    let log_means: Vec<f64> = counts
        .rows()
        .into_iter()
        .map(|row| {
            row.iter()
                .map(|&c| if c > 0.0 { c.ln() } else { 0.0 })
                .sum::<f64>()
                / n_samples as f64
        })
        .collect();
    let factors: Vec<f64> = (0..n_samples)
        .map(|sample| {
            let mut ratios: Vec<f64> = log_means
                .iter()
                .enumerate()
                .filter(|&(feature, &log_mean)| {
                    log_mean > 0.0 && log_mean.is_finite() && counts[[feature, sample]] > 0.0
                })
                .map(|(feature, log_mean)| counts[[feature, sample]].ln() - log_mean)
                .collect();
            median(&mut ratios).exp()
        })
        .collect();
    let log_geometric_mean = factors.iter().map(|f| f.ln()).sum::<f64>() / n_samples as f64;
    factors
        .iter()
        .map(|f| f / log_geometric_mean.exp())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn median_of_ratios_recovers_known_depths() {
        // sample 2 is sample 1 at twice the depth, sample 3 at half: the factors are the depths
        // over their geometric mean, whatever the features' levels
        let counts = array![[10.0, 20.0, 5.0], [40.0, 80.0, 20.0], [6.0, 12.0, 3.0]];
        let factors = median_of_ratios(counts.view()).unwrap();
        for (got, want) in factors.iter().zip([1.0, 2.0, 0.5]) {
            assert!((got - want).abs() < 1e-15);
        }
        let zero_everywhere = array![[0.0, 3.0], [4.0, 0.0], [5.0, 0.0], [0.0, 6.0]];
        assert!(median_of_ratios(zero_everywhere.view()).is_none());
        // references exp(Σ log⁺ c / 2): 3^½, 4^½, 5^½, 6^½; sample 1's ratios 4/2, 5/√5 -> median
        // (ln 2 + ln √5) / 2; sample 2's 3/√3, 6/√6; then scaled to a geometric mean of 1
        let factors = positive_counts(zero_everywhere.view());
        let first = ((2f64.ln() + 5f64.sqrt().ln()) / 2.0).exp();
        let second = ((3f64.sqrt().ln() + 6f64.sqrt().ln()) / 2.0).exp();
        let scale = (first * second).sqrt();
        assert!((factors[0] - first / scale).abs() < 1e-15, "{factors:?}");
        assert!((factors[1] - second / scale).abs() < 1e-15, "{factors:?}");
    }
}
