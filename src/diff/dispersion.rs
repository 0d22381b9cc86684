//! Dispersions shared across features, as DESeq2 shrinks them (Love, Huber & Anders 2014;
//! pydeseq2 0.5.4's `DeseqDataSet`): rough moment estimates to start from, each feature's
//! Cox-Reid maximum-likelihood dispersion, a trend `a₀ + a₁ / mean` fitted to them by a gamma
//! GLM, the spread of the features about the trend (the prior), and each feature's posterior
//! mode under that prior.

use super::linalg::{cholesky, cholesky_solve, times, transpose_times, weighted_gram};
use super::special::trigamma;
use crate::numeric::median;

/// The least-squares fit of `y` on the design (`n_coefficients` per row): the fitted values.
pub fn least_squares_fit(design: &[f64], n_coefficients: usize, y: &[f64]) -> Vec<f64> {
    let p = n_coefficients;
    let gram = weighted_gram(design, p, &vec![1.0; y.len()], 0.0);
    let l = cholesky(&gram, p).expect("the design has full rank");
    let beta = cholesky_solve(&l, p, &transpose_times(design, p, y));
    times(design, p, &beta)
}

/// The rough starting dispersion of one feature (pydeseq2's `_fit_MoM_dispersions`): the smaller
/// of the residual estimate about the design's least-squares fit of the normalised counts and
/// the moments estimate `(s² - μ mean(1/sᵢ)) / μ²`, within `[min_disp, max_disp]`.
pub fn moments(
    normed: &[f64],
    size_factors: &[f64],
    design: &[f64],
    n_coefficients: usize,
    bounds: (f64, f64),
) -> f64 {
    let n = normed.len() as f64;
    let fitted = least_squares_fit(design, n_coefficients, normed);
    let rough: f64 = normed
        .iter()
        .zip(&fitted)
        .map(|(&y, &f)| {
            let f = f.max(1.0);
            ((y - f).powi(2) - f) / ((n - n_coefficients as f64) * f * f)
        })
        .sum::<f64>()
        .max(0.0);
    let mean_inverse = size_factors.iter().map(|s| 1.0 / s).sum::<f64>() / n;
    let mean = normed.iter().sum::<f64>() / n;
    let variance = normed.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let mut by_moments = (variance - mean_inverse * mean) / (mean * mean);
    if by_moments.is_nan() {
        by_moments = 0.0;
    }
    rough.min(by_moments).clamp(bounds.0, bounds.1)
}

/// The dispersion trend over the features' mean normalised counts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Trend {
    /// `a₀ + a₁ / mean` (DESeq2's `parametric` fit).
    Parametric {
        /// The asymptotic dispersion.
        a0: f64,
        /// The extra Poisson-like dispersion at low means.
        a1: f64,
    },
    /// One value for every feature (the trimmed mean of the dispersions), where the parametric
    /// fit does not converge or a coefficient falls to zero, as DESeq2 then does.
    Mean(f64),
}

impl Trend {
    /// The trend's dispersion at a mean normalised count.
    pub fn at(&self, mean: f64) -> f64 {
        match *self {
            Trend::Parametric { a0, a1 } => a0 + a1 / mean,
            Trend::Mean(value) => value,
        }
    }
}

/// The gamma GLM with identity link of `y` on `[1, x]` (the loss `mean(y/μ + log μ)`, μ = a₀ +
/// a₁x), fitted by Fisher scoring to convergence with step halving that keeps every μ positive
/// and the loss from rising; `None` when it cannot.
fn gamma_identity_fit(x: &[f64], y: &[f64]) -> Option<[f64; 2]> {
    let n = x.len() as f64;
    let loss = |a: [f64; 2]| -> f64 {
        let mut sum = 0.0;
        for (&xi, &yi) in x.iter().zip(y) {
            let mu = a[0] + a[1] * xi;
            if mu <= 0.0 {
                return f64::INFINITY;
            }
            sum += yi / mu + mu.ln();
        }
        sum / n
    };
    let mut a = [1.0, 1.0];
    let mut current = loss(a);
    for _ in 0..1000 {
        let (mut score, mut information) = ([0.0; 2], [0.0; 4]);
        for (&xi, &yi) in x.iter().zip(y) {
            let mu = a[0] + a[1] * xi;
            let residual = (yi / mu - 1.0) / mu;
            score[0] += residual;
            score[1] += residual * xi;
            let w = 1.0 / (mu * mu);
            information[0] += w;
            information[1] += w * xi;
            information[3] += w * xi * xi;
        }
        information[2] = information[1];
        let l = cholesky(&information, 2)?;
        let step = cholesky_solve(&l, 2, &score);
        let mut factor = 1.0;
        let mut accepted = None;
        for _ in 0..60 {
            let next = [a[0] + factor * step[0], a[1] + factor * step[1]];
            let value = loss(next);
            if value <= current {
                accepted = Some((next, value));
                break;
            }
            factor /= 2.0;
        }
        let Some((next, value)) = accepted else {
            // no step lowers the loss: at the minimum to rounding
            return Some(a);
        };
        let moved = (next[0] - a[0]).abs() + (next[1] - a[1]).abs();
        a = next;
        current = value;
        if moved <= 1e-15 * (a[0].abs() + a[1].abs()) {
            return Some(a);
        }
    }
    None
}

/// scipy's `trim_mean(values, cut)`: the mean after dropping `⌊n·cut⌋` values from each end of
/// the sorted values.
pub(super) fn trim_mean(values: &[f64], cut: f64) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_unstable_by(f64::total_cmp);
    let n = sorted.len();
    let drop = (n as f64 * cut) as usize;
    let kept = &sorted[drop..n - drop];
    kept.iter().sum::<f64>() / kept.len() as f64
}

/// DESeq2's parametric trend (pydeseq2's `_fit_parametric_dispersion_trend`): the gamma GLM
/// of the gene-wise dispersions on `1 / mean`, refitted without the features whose dispersion
/// is below 1e-4 or at least 15 times the fit, until the coefficients settle (`Σ log²(new/old)
/// < 1e-6`); the trimmed mean of the dispersions above `10·min_disp` when that fails.
pub fn fit_trend(genewise: &[f64], means: &[f64], min_disp: f64) -> Trend {
    let mut kept: Vec<usize> = (0..genewise.len())
        .filter(|&k| (1.0 / means[k]).is_finite())
        .collect();
    let mut old: [f64; 2] = [0.1, 0.1];
    let mut coefficients: [f64; 2] = [1.0, 1.0];
    while coefficients.iter().all(|&c| c > 1e-10)
        && (coefficients[0] / old[0]).abs().ln().powi(2)
            + (coefficients[1] / old[1]).abs().ln().powi(2)
            >= 1e-6
    {
        old = coefficients;
        let x: Vec<f64> = kept.iter().map(|&k| 1.0 / means[k]).collect();
        let y: Vec<f64> = kept.iter().map(|&k| genewise[k]).collect();
        match gamma_identity_fit(&x, &y) {
            Some(fitted) if fitted.iter().all(|&c| c > 1e-10) => coefficients = fitted,
            _ => return mean_trend(genewise, min_disp),
        }
        kept.retain(|&k| {
            let ratio = genewise[k] / (coefficients[0] + coefficients[1] / means[k]);
            (1e-4..15.0).contains(&ratio)
        });
    }
    Trend::Parametric {
        a0: coefficients[0],
        a1: coefficients[1],
    }
}

/// The trimmed mean (0.1% from each end) of the dispersions above `10·min_disp`.
pub fn mean_trend(genewise: &[f64], min_disp: f64) -> Trend {
    let above: Vec<f64> = genewise
        .iter()
        .copied()
        .filter(|&d| d > 10.0 * min_disp)
        .collect();
    Trend::Mean(trim_mean(&above, 0.001))
}

/// The normal distribution's 75th percentile, which scales a median absolute deviation to a
/// standard deviation.
const NORMAL_Q75: f64 = 0.674_489_750_196_081_7;

/// The prior on the log dispersions (pydeseq2's `fit_dispersion_prior`): the squared MAD of
/// `log(gene-wise) - log(trend)` over the features whose gene-wise dispersion is at least
/// `100·min_disp`, and the prior variance: that less the sampling variance of a log dispersion
/// with `n_samples - n_coefficients` degrees of freedom (`ψ₁(df/2)`), at least 0.25.
/// Returns `(squared_log_residual, prior_variance)`.
pub fn prior_variance(
    genewise: &[f64],
    fitted: &[f64],
    min_disp: f64,
    residual_df: usize,
) -> (f64, f64) {
    let mut residuals: Vec<f64> = genewise
        .iter()
        .zip(fitted)
        .filter(|&(&g, _)| g >= 100.0 * min_disp)
        .map(|(g, f)| g.ln() - f.ln())
        .collect();
    let centre = median(&mut residuals);
    let mut deviations: Vec<f64> = residuals.iter().map(|r| (r - centre).abs()).collect();
    let mad = median(&mut deviations) / NORMAL_Q75;
    let squared = mad * mad;
    let variance = (squared - trigamma(residual_df as f64 / 2.0)).max(0.25);
    (squared, variance)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_trend_recovers_exact_coefficients_and_falls_back_to_the_mean() {
        // dispersions exactly on a₀ + a₁/mean: the gamma fit has them as its minimum
        let means: Vec<f64> = (1..200).map(|k| 2.0 + 3.0 * k as f64).collect();
        let genewise: Vec<f64> = means.iter().map(|m| 0.05 + 2.0 / m).collect();
        let Trend::Parametric { a0, a1 } = fit_trend(&genewise, &means, 1e-8) else {
            panic!("parametric")
        };
        assert!(
            (a0 - 0.05).abs() < 1e-12 && (a1 - 2.0).abs() < 1e-10,
            "{a0} {a1}"
        );
        // dispersions that fall with the mean faster than 1/mean leave no positive a₀
        let steep: Vec<f64> = means.iter().map(|m| 50.0 / (m * m)).collect();
        assert!(matches!(fit_trend(&steep, &means, 1e-8), Trend::Mean(_)));
    }

    #[test]
    fn trim_mean_drops_whole_values_from_each_end() {
        let mut values: Vec<f64> = (0..2000).map(f64::from).collect();
        values[0] = -1e9;
        values[1999] = 1e9;
        // ⌊2000 · 0.001⌋ = 2 dropped from each end: 2..=1997
        assert_eq!(trim_mean(&values, 0.001), 999.5);
    }

    #[test]
    fn moments_start_from_the_smaller_estimate() {
        // two groups, equal depths: the rough estimate uses the group means (15 and 40), the
        // moments one the overall mean (a larger variance): the rough one is the smaller
        let normed = [10.0, 20.0, 30.0, 50.0];
        let design = [1.0, 0.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let start = moments(&normed, &[1.0; 4], &design, 2, (1e-8, 10.0));
        let rough = 2.0 * (25.0 - 15.0) / (2.0 * 225.0) + 2.0 * (100.0 - 40.0) / (2.0 * 1600.0);
        assert!((start - rough).abs() < 1e-15, "{start} {rough}");
        let by_moments = (875.0 / 3.0 - 27.5) / (27.5 * 27.5);
        assert!(by_moments > rough);
    }
}
