//! The negative-binomial GLM of one feature with its dispersion fixed (pydeseq2's
//! `irls_solver`): log link, per-sample offsets (size factors), a ridge of 1e-6 on every
//! coefficient; and Cook's distances of its samples.

use super::dispersion::trim_mean;
use super::linalg::{
    cholesky, cholesky_inverse, cholesky_solve, times, transpose_times, weighted_gram,
};
use super::nb::nb_nll;

/// The ridge pydeseq2 adds to `XᵀWX` in every fit and test.
pub const RIDGE: f64 = 1e-6;

/// Coefficients may not leave `[-30, 30]` (natural log).
const MAX_BETA: f64 = 30.0;

/// One feature's GLM fit.
#[derive(Debug, Clone)]
pub struct GlmFit {
    /// Coefficients, natural log.
    pub beta: Vec<f64>,
    /// Fitted means `sᵢ exp(xᵢβ)` per sample.
    pub mu: Vec<f64>,
    /// Diagonal of the hat matrix per sample.
    pub hat: Vec<f64>,
    /// Whether IRLS converged (otherwise the coefficients come from a bounded Newton fit).
    pub converged: bool,
}

/// The means `sᵢ exp(xᵢβ)` of the design's rows (`n_coefficients` each) with offsets `sᵢ`.
pub fn means(design: &[f64], n_coefficients: usize, beta: &[f64], offsets: &[f64]) -> Vec<f64> {
    times(design, n_coefficients, beta)
        .iter()
        .zip(offsets)
        .map(|(eta, s)| s * eta.exp())
        .collect()
}

/// The fit by iteratively reweighted least squares: from the least-squares fit of
/// `log(count/s + 0.1)`, until the deviance changes by less than `beta_tol` relative; means are
/// kept at `min_mu` or above while fitting. When a coefficient leaves `[-30, 30]` or 250
/// iterations pass, the penalised likelihood is minimised directly within those bounds
/// (pydeseq2 uses L-BFGS-B there, and a grid when that fails).
pub fn irls(
    counts: &[f64],
    size_factors: &[f64],
    design: &[f64],
    n_coefficients: usize,
    disp: f64,
    min_mu: f64,
    beta_tol: f64,
) -> GlmFit {
    let p = n_coefficients;
    let clamped_means = |beta: &[f64]| -> Vec<f64> {
        means(design, p, beta, size_factors)
            .into_iter()
            .map(|m| m.max(min_mu))
            .collect()
    };
    let start: Vec<f64> = counts
        .iter()
        .zip(size_factors)
        .map(|(c, s)| (c / s + 0.1).ln())
        .collect();
    let gram = weighted_gram(design, p, &vec![1.0; counts.len()], 0.0);
    let l = cholesky(&gram, p).expect("the design has full rank");
    let beta_init = cholesky_solve(&l, p, &transpose_times(design, p, &start));
    let mut beta = beta_init.clone();
    let mut mu = clamped_means(&beta);
    let (mut deviance, mut ratio) = (1000.0, 1.0);
    let mut converged = true;
    let mut iteration = 0;
    while ratio > beta_tol {
        let w: Vec<f64> = mu.iter().map(|m| m / (1.0 + m * disp)).collect();
        let z: Vec<f64> = mu
            .iter()
            .zip(size_factors)
            .zip(counts)
            .map(|((m, s), c)| (m / s).ln() + (c - m) / m)
            .collect();
        let wz: Vec<f64> = w.iter().zip(&z).map(|(a, b)| a * b).collect();
        let next = cholesky(&weighted_gram(design, p, &w, RIDGE), p)
            .map(|l| cholesky_solve(&l, p, &transpose_times(design, p, &wz)));
        iteration += 1;
        let next = match next {
            Some(next) if next.iter().all(|b| b.abs() <= MAX_BETA) && iteration < 250 => next,
            _ => {
                beta = bounded_newton(counts, size_factors, design, p, disp, &beta_init);
                mu = clamped_means(&beta);
                converged = false;
                break;
            }
        };
        beta = next;
        mu = clamped_means(&beta);
        let old = deviance;
        deviance = -2.0 * nb_nll(counts, &mu, disp);
        ratio = (deviance - old).abs() / (deviance.abs() + 0.1);
    }
    let w: Vec<f64> = mu.iter().map(|m| m / (1.0 + m * disp)).collect();
    let l = cholesky(&weighted_gram(design, p, &w, RIDGE), p).expect("positive weights");
    let inverse = cholesky_inverse(&l, p);
    let hat = design
        .chunks_exact(p)
        .zip(&w)
        .map(|(row, weight)| weight * super::linalg::bilinear(row, &inverse, row))
        .collect();
    let mu = means(design, p, &beta, size_factors);
    GlmFit {
        beta,
        mu,
        hat,
        converged,
    }
}

/// Minimises `nll(μ = s exp(Xβ)) + ½·1e-6·|β|²` within `[-30, 30]` for every coefficient, by
/// Newton steps projected on the box with backtracking (the likelihood is convex in `β`).
fn bounded_newton(
    counts: &[f64],
    size_factors: &[f64],
    design: &[f64],
    p: usize,
    disp: f64,
    start: &[f64],
) -> Vec<f64> {
    let r = 1.0 / disp;
    let objective = |beta: &[f64]| -> f64 {
        let mu = means(design, p, beta, size_factors);
        nb_nll(counts, &mu, disp) + 0.5 * RIDGE * beta.iter().map(|b| b * b).sum::<f64>()
    };
    let mut beta: Vec<f64> = start.iter().map(|b| b.clamp(-MAX_BETA, MAX_BETA)).collect();
    let mut value = objective(&beta);
    for _ in 0..500 {
        let mu = means(design, p, &beta, size_factors);
        let residual: Vec<f64> = mu
            .iter()
            .zip(counts)
            .map(|(m, y)| (y + r) * m / (r + m) - y)
            .collect();
        let mut gradient = transpose_times(design, p, &residual);
        for (g, b) in gradient.iter_mut().zip(&beta) {
            *g += RIDGE * b;
        }
        let curvature: Vec<f64> = mu
            .iter()
            .zip(counts)
            .map(|(m, y)| (y + r) * r * m / ((r + m) * (r + m)))
            .collect();
        let Some(l) = cholesky(&weighted_gram(design, p, &curvature, RIDGE), p) else {
            break;
        };
        let step = cholesky_solve(&l, p, &gradient);
        let mut factor = 1.0;
        let mut moved = false;
        for _ in 0..60 {
            let next: Vec<f64> = beta
                .iter()
                .zip(&step)
                .map(|(b, s)| (b - factor * s).clamp(-MAX_BETA, MAX_BETA))
                .collect();
            let next_value = objective(&next);
            if next_value < value {
                moved = next.iter().zip(&beta).any(|(a, b)| a != b);
                beta = next;
                value = next_value;
                break;
            }
            factor /= 2.0;
        }
        if !moved {
            break;
        }
    }
    beta
}

/// The trim and the scale DESeq2 uses for a cell of `n` replicates (`trimmed_cell_variance`).
fn trim_for(n: usize) -> (f64, f64) {
    let n = n as f64;
    if n >= 23.5 {
        (1.0 / 8.0, 1.51)
    } else if n >= 3.5 {
        (1.0 / 4.0, 1.86)
    } else {
        (1.0 / 3.0, 2.04)
    }
}

/// The robust dispersion Cook's distances use (pydeseq2's `robust_method_of_moments_disp`):
/// from the trimmed variance within each group of samples that shares a design row with at
/// least two others (the largest over the groups), or over all samples (trim 1/8, scale 1.51)
/// when there is no such group; `(v - m) / m²`, at least 0.04. `groups[i]` is sample `i`'s
/// design row and `normed` the counts over the size factors.
pub fn robust_dispersion(normed: &[f64], groups: &[usize]) -> f64 {
    let n = normed.len();
    let size_of = |g: usize| groups.iter().filter(|&&h| h == g).count();
    let mut seen: Vec<usize> = Vec::new();
    for &g in groups {
        if size_of(g) >= 3 && !seen.contains(&g) {
            seen.push(g);
        }
    }
    let variance = if seen.is_empty() {
        let centre = trim_mean(normed, 0.125);
        let squared: Vec<f64> = normed.iter().map(|y| (y - centre).powi(2)).collect();
        1.51 * trim_mean(&squared, 0.125)
    } else {
        seen.iter()
            .map(|&g| {
                let cell: Vec<f64> = (0..n)
                    .filter(|&i| groups[i] == g)
                    .map(|i| normed[i])
                    .collect();
                let (trim, scale) = trim_for(cell.len());
                let centre = trim_mean(&cell, trim);
                let squared: Vec<f64> = cell.iter().map(|y| (y - centre).powi(2)).collect();
                scale * trim_mean(&squared, trim)
            })
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let mean = normed.iter().sum::<f64>() / n as f64;
    ((variance - mean) / (mean * mean)).max(0.04)
}

/// Cook's distance of each sample: `(y - μ)² / (μ + αμ²) / p · h / (1 - h)²`.
pub fn cooks_distances(
    counts: &[f64],
    fit: &GlmFit,
    robust_dispersion: f64,
    n_coefficients: usize,
) -> Vec<f64> {
    counts
        .iter()
        .zip(&fit.mu)
        .zip(&fit.hat)
        .map(|((y, m), h)| {
            let pearson = (y - m).powi(2) / (m + robust_dispersion * m * m);
            pearson / n_coefficients as f64 * (h / (1.0 - h).powi(2))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two groups, one coefficient each side: the maximum likelihood means are the groups'
    /// mean normalised counts (closed form), whatever the dispersion; the ridge moves them by
    /// less than 1e-6 relative.
    #[test]
    fn irls_reaches_the_group_means() {
        let counts = [12.0, 20.0, 9.0, 60.0, 75.0, 40.0];
        let size_factors = [0.8, 1.3, 0.9, 1.1, 1.2, 0.7];
        let design = [1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0];
        let fit = irls(&counts, &size_factors, &design, 2, 0.05, 0.5, 1e-12);
        // with a common dispersion the score equations are Σ (y - μ)/(1 + αμ) = 0 per group,
        // μ = s·q: solve for q in each group by bisection (independent of the IRLS code)
        let group = |range: std::ops::Range<usize>| {
            let score = |q: f64| -> f64 {
                range
                    .clone()
                    .map(|i| (counts[i] - size_factors[i] * q) / (1.0 + 0.05 * size_factors[i] * q))
                    .sum()
            };
            super::super::nb::brent_root(score, 1.0, 1000.0)
        };
        let (a, b) = (group(0..3), group(3..6));
        assert!((fit.beta[0] - a.ln()).abs() < 1e-6, "{:?} {a}", fit.beta);
        assert!(
            (fit.beta[1] - (b / a).ln()).abs() < 1e-6,
            "{:?} {b}",
            fit.beta
        );
        assert!(fit.converged);
        // the hat values of a saturated-by-group design sum to the number of coefficients
        let trace: f64 = fit.hat.iter().sum();
        assert!((trace - 2.0).abs() < 1e-5, "{trace}");
    }

    #[test]
    fn a_group_of_zeros_is_fitted_within_the_bounds() {
        let counts = [0.0, 0.0, 30.0, 44.0];
        let design = [1.0, 0.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let fit = irls(&counts, &[1.0; 4], &design, 2, 0.1, 0.5, 1e-8);
        assert!(fit.beta.iter().all(|b| b.abs() <= 30.0));
        assert!(fit.beta[1] > 5.0, "{:?}", fit.beta);
    }
}
