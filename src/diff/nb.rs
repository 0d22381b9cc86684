//! The negative binomial of DESeq2 (variance `μ + αμ²`): its negative log-likelihood, the
//! derivative in `log α`, the Cox-Reid adjustment, and the fit of one feature's dispersion
//! (maximum likelihood, or a posterior with a normal prior on `log α`) to machine precision.

use statrs::function::gamma::{digamma, ln_gamma};

use super::linalg::{cholesky, cholesky_inverse, cholesky_log_det, weighted_gram};

/// The negative log-likelihood of integer `counts` with means `mu` and dispersion `alpha`
/// (pydeseq2's `nb_nll`).
pub fn nb_nll(counts: &[f64], mu: &[f64], alpha: f64) -> f64 {
    let r = 1.0 / alpha;
    let n = counts.len() as f64;
    let sum: f64 = counts
        .iter()
        .zip(mu)
        .map(|(&y, &m)| {
            let log_binomial = ln_gamma(y + r) - ln_gamma(y + 1.0) - ln_gamma(r);
            -log_binomial + (y + r) * (r + m).ln() - y * m.ln()
        })
        .sum();
    n * r * alpha.ln() + sum
}

/// `ψ(y + r) - ψ(r)` for an integer `y >= 0`: the finite sum `Σ_{k<y} 1/(r+k)` while `y` is
/// small (exact where `r` is large, that is `α` small, where the difference of digammas loses
/// every digit), the digammas beyond.
fn digamma_difference(y: f64, r: f64) -> f64 {
    if y < 256.0 {
        (0..y as u64).map(|k| 1.0 / (r + k as f64)).sum()
    } else {
        digamma(y + r) - digamma(r)
    }
}

/// `d nll / d log α` at `alpha`.
pub fn nb_nll_slope(counts: &[f64], mu: &[f64], alpha: f64) -> f64 {
    let r = 1.0 / alpha;
    let by_r: f64 = counts
        .iter()
        .zip(mu)
        .map(|(&y, &m)| -digamma_difference(y, r) + (m * alpha).ln_1p() + (y - m) / (r + m))
        .sum();
    // d/dα = -r² d/dr, and d/dlog α = α d/dα = -r d/dr
    -r * by_r
}

/// One feature's dispersion problem: its counts, the means fitted before, the design (rows of
/// `n_coefficients`), and an optional normal prior on `log α` (centre, variance).
pub struct DispersionProblem<'a> {
    /// Counts per sample (integers).
    pub counts: &'a [f64],
    /// Fitted means per sample.
    pub mu: &'a [f64],
    /// The design, row-major, one row per sample.
    pub design: &'a [f64],
    /// Columns of the design.
    pub n_coefficients: usize,
    /// `(log α₀, σ²)`: the prior `log α ~ N(log α₀, σ²)` of the MAP step; `None` for the
    /// maximum-likelihood (gene-wise) step.
    pub prior: Option<(f64, f64)>,
}

impl DispersionProblem<'_> {
    /// The loss pydeseq2 minimises (`fit_alpha_mle`): the negative log-likelihood, the Cox-Reid
    /// adjustment `½ log det(XᵀWX)` with `W = μ / (1 + μα)`, and the prior's term.
    pub fn loss(&self, log_alpha: f64) -> f64 {
        let alpha = log_alpha.exp();
        let p = self.n_coefficients;
        let w: Vec<f64> = self.mu.iter().map(|m| m / (1.0 + m * alpha)).collect();
        let cox_reid = match cholesky(&weighted_gram(self.design, p, &w, 0.0), p) {
            Some(l) => 0.5 * cholesky_log_det(&l, p),
            None => f64::INFINITY,
        };
        let prior = self.prior.map_or(0.0, |(centre, variance)| {
            (log_alpha - centre).powi(2) / (2.0 * variance)
        });
        nb_nll(self.counts, self.mu, alpha) + cox_reid + prior
    }

    /// The loss's derivative in `log α`.
    pub fn slope(&self, log_alpha: f64) -> f64 {
        let alpha = log_alpha.exp();
        let p = self.n_coefficients;
        let w: Vec<f64> = self.mu.iter().map(|m| m / (1.0 + m * alpha)).collect();
        let dw: Vec<f64> = w.iter().map(|w| -w * w).collect();
        let cox_reid = match cholesky(&weighted_gram(self.design, p, &w, 0.0), p) {
            Some(l) => {
                let inverse = cholesky_inverse(&l, p);
                let dgram = weighted_gram(self.design, p, &dw, 0.0);
                0.5 * inverse.iter().zip(&dgram).map(|(a, b)| a * b).sum::<f64>() * alpha
            }
            None => 0.0,
        };
        let prior = self
            .prior
            .map_or(0.0, |(centre, variance)| (log_alpha - centre) / variance);
        nb_nll_slope(self.counts, self.mu, alpha) + cox_reid + prior
    }

    /// The dispersion that minimises the loss within `[min_disp, max_disp]`: the best of 64
    /// log-spaced points, then the root of the slope between its neighbours by Brent's method
    /// to machine precision (or golden sections of the loss where the slope does not change
    /// sign there: next to a bound). pydeseq2 descends with L-BFGS-B from the moments
    /// estimate instead and stops at its default tolerances, or in a local minimum at a bound
    /// (docs/diff.md measures both).
    pub fn fit(&self, min_disp: f64, max_disp: f64) -> f64 {
        const N_GRID: usize = 64;
        let (low, high) = (min_disp.ln(), max_disp.ln());
        let grid: Vec<f64> = (0..N_GRID)
            .map(|k| low + (high - low) * k as f64 / (N_GRID - 1) as f64)
            .collect();
        let values: Vec<f64> = grid.iter().map(|&x| self.loss(x)).collect();
        let best = (0..N_GRID)
            .min_by(|&a, &b| values[a].total_cmp(&values[b]))
            .expect("a grid");
        let (left, right) = (
            grid[best.saturating_sub(1)],
            grid[(best + 1).min(N_GRID - 1)],
        );
        let (slope_left, slope_right) = (self.slope(left), self.slope(right));
        if slope_left < 0.0 && slope_right > 0.0 {
            return brent_root(|x| self.slope(x), left, right).exp();
        }
        let x = golden_section(|x| self.loss(x), left, right);
        if self.loss(x) < values[best] {
            x.exp()
        } else {
            grid[best].exp()
        }
    }
}

/// The minimum of `f` on `[a, b]` by golden sections, to `1e-12` in `x`.
fn golden_section(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (a, b);
    let mut c = b - ratio * (b - a);
    let mut d = a + ratio * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    while (b - a).abs() > 1e-12 {
        if fc <= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - ratio * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + ratio * (b - a);
            fd = f(d);
        }
    }
    (a + b) / 2.0
}

/// A root of `f` in `[a, b]`, where `f(a)` and `f(b)` have opposite signs (Brent 1973,
/// `zeroin`), to the last representable digits.
pub fn brent_root(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let (mut a, mut b) = (a, b);
    let (mut fa, mut fb) = (f(a), f(b));
    let (mut c, mut fc) = (a, fa);
    let (mut d, mut e) = (b - a, b - a);
    for _ in 0..200 {
        if (fb > 0.0) == (fc > 0.0) {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tolerance = 2.0 * f64::EPSILON * b.abs() + 1e-300;
        let half = 0.5 * (c - b);
        if half.abs() <= tolerance || fb == 0.0 {
            return b;
        }
        if e.abs() >= tolerance && fa.abs() > fb.abs() {
            // inverse quadratic interpolation, or the secant when two points coincide
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * half * s;
                q = 1.0 - s;
            } else {
                let qa = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * half * qa * (qa - r) - (b - a) * (r - 1.0));
                q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * half * q - (tolerance * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = half;
                e = d;
            }
        } else {
            d = half;
            e = d;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tolerance {
            d
        } else {
            tolerance.copysign(half)
        };
        fb = f(b);
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The slope is the loss's derivative: central differences agree (an independent check of
    /// the algebra and of the Cox-Reid and prior terms).
    #[test]
    fn slope_is_the_derivative_of_the_loss() {
        let counts = [3.0, 17.0, 40.0, 0.0, 9.0];
        let mu = [8.0, 12.5, 30.0, 2.0, 11.0];
        let design = [1.0, 0.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0];
        for prior in [None, Some((-1.0, 0.4))] {
            let problem = DispersionProblem {
                counts: &counts,
                mu: &mu,
                design: &design,
                n_coefficients: 2,
                prior,
            };
            for x in [-6.0, -2.0, -0.3, 0.8, 2.0] {
                let h = 1e-5;
                let numeric = (problem.loss(x + h) - problem.loss(x - h)) / (2.0 * h);
                let analytic = problem.slope(x);
                assert!(
                    (numeric - analytic).abs() < 1e-6 * (1.0 + analytic.abs()),
                    "{x}"
                );
            }
            let fitted = problem.fit(1e-8, 10.0).ln();
            assert!(problem.slope(fitted).abs() < 1e-9, "a root of the slope");
        }
    }

    #[test]
    fn the_likelihood_is_the_negative_binomial_mass() {
        // P(Y = y) with size r and mean μ: Γ(y+r)/(Γ(r) y!) (r/(r+μ))^r (μ/(r+μ))^y
        let (y, mu, alpha): (f64, f64, f64) = (4.0, 6.0, 0.5);
        let r = 1.0 / alpha;
        let mass = (ln_gamma(y + r) - ln_gamma(r) - ln_gamma(y + 1.0)).exp()
            * (r / (r + mu)).powf(r)
            * (mu / (r + mu)).powf(y);
        assert!((nb_nll(&[y], &[mu], alpha) + mass.ln()).abs() < 1e-13);
    }

    #[test]
    fn brent_finds_roots_to_the_last_digits() {
        let root = brent_root(|x| x * x - 2.0, 0.0, 2.0);
        assert!((root - 2f64.sqrt()).abs() < 4e-16);
        let root = brent_root(|x: f64| x.cos() - x, 0.0, 1.0);
        assert!((root.cos() - root).abs() < 1e-15);
    }
}
