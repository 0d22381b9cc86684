//! Tests of a contrast and the false-discovery rate: DESeq2's Wald test (pydeseq2's
//! `wald_test`) and Benjamini-Hochberg (scipy's `false_discovery_control(method="bh")`).

use statrs::distribution::{ContinuousCDF, Normal};

use super::glm::RIDGE;
use super::linalg::{bilinear, cholesky, cholesky_inverse, matrix_vector, weighted_gram};

/// The Wald test of `contrast · β = 0` for one feature: `(statistic, p-value, standard error)`,
/// natural-log scale; the standard error is `√(cᵀ H M H c)` with `M = XᵀWX` and `H = (M +
/// 1e-6 I)⁻¹`, the two-sided p-value `2 Φ(-|z|)`.
pub fn wald(
    design: &[f64],
    disp: f64,
    beta: &[f64],
    mu: &[f64],
    contrast: &[f64],
) -> (f64, f64, f64) {
    let p = contrast.len();
    let w: Vec<f64> = mu.iter().map(|m| m / (1.0 + m * disp)).collect();
    let m = weighted_gram(design, p, &w, 0.0);
    let Some(l) = cholesky(&weighted_gram(design, p, &w, RIDGE), p) else {
        return (f64::NAN, f64::NAN, f64::NAN);
    };
    let h = cholesky_inverse(&l, p);
    let hc = matrix_vector(&h, contrast);
    let se = bilinear(&hc, &m, &hc).sqrt();
    let estimate: f64 = contrast.iter().zip(beta).map(|(c, b)| c * b).sum();
    let statistic = estimate / se;
    let normal = Normal::standard();
    let p_value = 2.0 * normal.sf(statistic.abs());
    (statistic, p_value, se)
}

/// Benjamini-Hochberg adjusted p-values (q-values) of `p_values`; `NaN` stays `NaN` and is not
/// counted among the tests.
pub fn benjamini_hochberg(p_values: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..p_values.len())
        .filter(|&i| !p_values[i].is_nan())
        .collect();
    order.sort_by(|&a, &b| p_values[a].total_cmp(&p_values[b]));
    let m = order.len() as f64;
    let mut adjusted = vec![f64::NAN; p_values.len()];
    let mut running = f64::INFINITY;
    for (rank, &i) in order.iter().enumerate().rev() {
        let value = p_values[i] * (m / (rank + 1) as f64);
        running = running.min(value);
        adjusted[i] = running.clamp(0.0, 1.0);
    }
    adjusted
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn benjamini_hochberg_by_hand() {
        // sorted p: 0.01 0.02 0.03 0.5 with m = 4: 0.04 0.04 0.04 0.5, the NaN left out
        let q = benjamini_hochberg(&[0.03, f64::NAN, 0.5, 0.01, 0.02]);
        let want = [0.04, f64::NAN, 0.5, 0.04, 0.04];
        for (a, b) in q.iter().zip(want) {
            assert!((a.is_nan() && b.is_nan()) || (a - b).abs() < 1e-15, "{q:?}");
        }
    }

    #[test]
    fn the_wald_standard_error_is_the_inverse_information_without_the_ridge() {
        // one coefficient per group: M is diagonal-by-group and the variance of the difference
        // of two log means is 1/Σ₁W + 1/Σ₂W (the ridge changes it by ~1e-6 relative)
        let design = [1.0, 0.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let mu = [10.0, 12.0, 30.0, 24.0];
        let disp = 0.1;
        let w: Vec<f64> = mu.iter().map(|m| m / (1.0 + m * disp)).collect();
        let (z, p, se) = wald(&design, disp, &[2.3, 0.9], &mu, &[0.0, 1.0]);
        let want = (1.0 / (w[0] + w[1]) + 1.0 / (w[2] + w[3])).sqrt();
        assert!((se - want).abs() < 1e-5 * want, "{se} {want}");
        assert!((z - 0.9 / se).abs() < 1e-12);
        assert!((p - 2.0 * Normal::standard().sf(z.abs())).abs() < 1e-15);
    }
}
