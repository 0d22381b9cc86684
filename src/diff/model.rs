//! The model of [`super`]: a design, its settings, [`fit`] / [`fit_normalized`] and
//! [`results`].

use ndarray::{Array2, ArrayView2};
use rayon::prelude::*;
use statrs::distribution::{ContinuousCDF, FisherSnedecor};

use super::dispersion::{self, Trend};
use super::{glm, nb, size_factors, test};
use crate::error::{Error, Result};

/// Which condition each sample belongs to, as a design matrix with an intercept (the first
/// condition, the reference) and one column per other condition (`condition[T.B]` in
/// pydeseq2's formula `~condition`).
#[derive(Debug, Clone)]
pub struct Design {
    pub(super) matrix: Vec<f64>,
    n_coefficients: usize,
    groups: Vec<usize>,
    names: Vec<String>,
}

impl Design {
    /// The design of samples in conditions `conditions[i]` (indices into `names`; the first
    /// name is the reference). Every condition needs a sample, and some condition more than
    /// one (otherwise no dispersion can be estimated).
    pub fn conditions(conditions: &[usize], names: &[&str]) -> Result<Design> {
        let n_levels = names.len();
        if n_levels < 2 {
            return Err(Error::Argument(
                "a comparison needs two conditions".to_string(),
            ));
        }
        for (level, name) in names.iter().enumerate() {
            if !conditions.contains(&level) {
                return Err(Error::Argument(format!("condition {name} has no sample")));
            }
        }
        if let Some(bad) = conditions.iter().find(|&&c| c >= n_levels) {
            return Err(Error::Argument(format!(
                "condition index {bad} is not a condition"
            )));
        }
        if conditions.len() <= n_levels {
            return Err(Error::Argument(format!(
                "{} samples in {n_levels} conditions: no condition has a replicate, so the \
                 variation between replicates cannot be estimated",
                conditions.len()
            )));
        }
        let mut matrix = Vec::with_capacity(conditions.len() * n_levels);
        for &c in conditions {
            matrix.push(1.0);
            for level in 1..n_levels {
                matrix.push(f64::from(u8::from(c == level)));
            }
        }
        Ok(Design {
            matrix,
            n_coefficients: n_levels,
            groups: conditions.to_vec(),
            names: names.iter().map(|s| s.to_string()).collect(),
        })
    }

    /// Samples.
    pub fn n_samples(&self) -> usize {
        self.groups.len()
    }

    /// Coefficients (the intercept and one per condition beyond the reference).
    pub fn n_coefficients(&self) -> usize {
        self.n_coefficients
    }

    /// The conditions' names, the reference first.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The contrast of condition `level` against the reference: its coefficient.
    pub fn contrast(&self, level: usize) -> Vec<f64> {
        let mut contrast = vec![0.0; self.n_coefficients];
        contrast[level] = 1.0;
        contrast
    }

    /// How many samples share each sample's condition.
    fn replicates(&self) -> Vec<usize> {
        self.groups
            .iter()
            .map(|g| self.groups.iter().filter(|h| *h == g).count())
            .collect()
    }
}

/// The model's settings, pydeseq2's defaults.
#[derive(Debug, Clone)]
pub struct Params {
    /// Fitted means are kept at this or above while fitting (0.5).
    pub min_mu: f64,
    /// Smallest dispersion (1e-8).
    pub min_disp: f64,
    /// Largest dispersion (10, or the number of samples when more).
    pub max_disp: f64,
    /// IRLS stops when the deviance changes by less than this, relative (1e-8).
    pub beta_tol: f64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            min_mu: 0.5,
            min_disp: 1e-8,
            max_disp: 10.0,
            beta_tol: 1e-8,
        }
    }
}

/// The fitted model: per-sample size factors, per-feature dispersions and coefficients.
#[derive(Debug, Clone)]
pub struct Fit {
    /// Size factors per sample (`NaN` with [`Normalization::Factors`]).
    pub size_factors: Vec<f64>,
    /// The factor of each feature and sample its means are scaled by: the size factors, or the
    /// normalisation factors given.
    pub factors: Array2<f64>,
    /// Mean normalised count per feature (DESeq2's `baseMean`).
    pub base_mean: Vec<f64>,
    /// Rough moments dispersions (the gene-wise fit's start).
    pub moments_dispersions: Vec<f64>,
    /// Cox-Reid maximum-likelihood dispersion per feature.
    pub genewise_dispersions: Vec<f64>,
    /// The trend over the features.
    pub trend: Trend,
    /// The trend at each feature's mean.
    pub fitted_dispersions: Vec<f64>,
    /// The squared MAD of log dispersions about the trend.
    pub squared_log_residual: f64,
    /// The prior variance of log dispersions.
    pub prior_variance: f64,
    /// Posterior-mode dispersion per feature.
    pub map_dispersions: Vec<f64>,
    /// The dispersion used: the posterior mode, or the gene-wise one for a dispersion outlier.
    pub dispersions: Vec<f64>,
    /// Whether a feature's gene-wise dispersion is more than two spreads above the trend.
    pub dispersion_outlier: Vec<bool>,
    /// Coefficients per feature (natural log), one row per feature.
    pub coefficients: Array2<f64>,
    /// Fitted means per feature and sample.
    pub mu: Array2<f64>,
    /// Cook's distances per feature and sample.
    pub cooks: Array2<f64>,
    /// Whether IRLS converged for a feature.
    pub converged: Vec<bool>,
    /// Features with at least one count (the others have no fit).
    pub non_zero: Vec<bool>,
}

/// How samples (and features) are made comparable.
#[derive(Debug, Clone, Copy)]
pub enum Normalization<'a> {
    /// Size factors by the median of ratios (DESeq2's default).
    SizeFactors,
    /// A factor per feature and sample (DESeq2's `normalizationFactors`), in place of size
    /// factors: each feature's expected count in each sample up to a constant per feature
    /// (`diff loops` gives the expected count of each loop's neighbourhood at its distance, so
    /// that depth and a change of P(s) are not called changes of loops).
    Factors(ArrayView2<'a, f64>),
}

/// Fits the model to `counts` (one row per feature, one column per sample, in the design's
/// order; non-negative integers), with size factors ([`fit`]).
pub fn fit(counts: ArrayView2<f64>, design: &Design, params: &Params) -> Result<Fit> {
    fit_normalized(counts, design, params, Normalization::SizeFactors)
}

/// Fits the model to `counts` with the given [`Normalization`].
pub fn fit_normalized(
    counts: ArrayView2<f64>,
    design: &Design,
    params: &Params,
    normalization: Normalization,
) -> Result<Fit> {
    let (n_features, n_samples) = counts.dim();
    if n_samples != design.n_samples() {
        return Err(Error::Argument(format!(
            "{n_samples} samples in the counts, {} in the design",
            design.n_samples()
        )));
    }
    if let Some(((feature, sample), value)) = counts
        .indexed_iter()
        .find(|(_, v)| !(v.is_finite() && **v >= 0.0 && v.fract() == 0.0))
    {
        return Err(Error::Data(format!(
            "feature {}, sample {}: count {value} is not a non-negative integer",
            feature + 1,
            sample + 1
        )));
    }
    let p = design.n_coefficients();
    let x = &design.matrix;
    let min_disp = params.min_disp;
    let max_disp = params.max_disp.max(n_samples as f64);
    let (size_factors, factors) = match normalization {
        Normalization::SizeFactors => {
            let size_factors = size_factors::median_of_ratios(counts)
                .unwrap_or_else(|| size_factors::positive_counts(counts));
            let factors = Array2::from_shape_fn((n_features, n_samples), |(_, j)| size_factors[j]);
            (size_factors, factors)
        }
        Normalization::Factors(given) => {
            if given.dim() != counts.dim() {
                return Err(Error::Argument(format!(
                    "normalisation factors for {:?} features x samples, counts for {:?}",
                    given.dim(),
                    counts.dim()
                )));
            }
            if let Some(((feature, sample), value)) = given
                .indexed_iter()
                .find(|(_, v)| !(v.is_finite() && **v > 0.0))
            {
                return Err(Error::Data(format!(
                    "feature {}, sample {}: normalisation factor {value} is not positive",
                    feature + 1,
                    sample + 1
                )));
            }
            (vec![f64::NAN; n_samples], given.to_owned())
        }
    };
    let normed = Array2::from_shape_fn((n_features, n_samples), |(g, j)| {
        counts[[g, j]] / factors[[g, j]]
    });
    let base_mean: Vec<f64> = normed
        .rows()
        .into_iter()
        .map(|row| row.sum() / n_samples as f64)
        .collect();
    let non_zero: Vec<bool> = counts
        .rows()
        .into_iter()
        .map(|r| r.iter().any(|&c| c > 0.0))
        .collect();
    let kept: Vec<usize> = (0..n_features).filter(|&g| non_zero[g]).collect();
    if kept.is_empty() {
        return Err(Error::Data("every count is zero".to_string()));
    }
    let row = |a: &Array2<f64>, g: usize| a.row(g).to_vec();
    let count_row = |g: usize| counts.row(g).to_vec();

    // gene-wise dispersions, from the moments estimates and the means of the design's fit
    let per_feature: Vec<(f64, Vec<f64>, f64)> = kept
        .par_iter()
        .map(|&g| {
            let y = count_row(g);
            let offsets = row(&factors, g);
            let start = dispersion::moments(&row(&normed, g), &offsets, x, p, (min_disp, max_disp));
            let fitted = dispersion::least_squares_fit(x, p, &row(&normed, g));
            let mu: Vec<f64> = fitted
                .iter()
                .zip(&offsets)
                .map(|(f, s)| (s * f).max(params.min_mu))
                .collect();
            let problem = nb::DispersionProblem {
                counts: &y,
                mu: &mu,
                design: x,
                n_coefficients: p,
                prior: None,
            };
            let genewise = problem.fit(min_disp, max_disp).clamp(min_disp, max_disp);
            (start, mu, genewise)
        })
        .collect();
    let mut moments_dispersions = vec![f64::NAN; n_features];
    let mut genewise_dispersions = vec![f64::NAN; n_features];
    for (&g, (start, _, genewise)) in kept.iter().zip(&per_feature) {
        moments_dispersions[g] = *start;
        genewise_dispersions[g] = *genewise;
    }
    let kept_genewise: Vec<f64> = kept.iter().map(|&g| genewise_dispersions[g]).collect();
    let kept_means: Vec<f64> = kept.iter().map(|&g| base_mean[g]).collect();
    let trend = dispersion::fit_trend(&kept_genewise, &kept_means, min_disp);
    let mut fitted_dispersions = vec![f64::NAN; n_features];
    for &g in &kept {
        fitted_dispersions[g] = trend.at(base_mean[g]);
    }
    let kept_fitted: Vec<f64> = kept.iter().map(|&g| fitted_dispersions[g]).collect();
    let residual_df = n_samples - p;
    let (squared_log_residual, prior_variance) =
        dispersion::prior_variance(&kept_genewise, &kept_fitted, min_disp, residual_df);

    // posterior modes, then the dispersions used
    let maps: Vec<f64> = kept
        .par_iter()
        .zip(&per_feature)
        .map(|(&g, (_, mu, _))| {
            let y = count_row(g);
            let centre = fitted_dispersions[g];
            let problem = nb::DispersionProblem {
                counts: &y,
                mu,
                design: x,
                n_coefficients: p,
                prior: Some((centre.ln(), prior_variance)),
            };
            problem.fit(min_disp, max_disp).clamp(min_disp, max_disp)
        })
        .collect();
    let mut map_dispersions = vec![f64::NAN; n_features];
    let mut dispersions = vec![f64::NAN; n_features];
    let mut dispersion_outlier = vec![false; n_features];
    for (&g, &map) in kept.iter().zip(&maps) {
        map_dispersions[g] = map;
        let outlier = genewise_dispersions[g].ln()
            > fitted_dispersions[g].ln() + 2.0 * squared_log_residual.sqrt();
        dispersion_outlier[g] = outlier;
        dispersions[g] = if outlier {
            genewise_dispersions[g]
        } else {
            map
        };
    }

    // the GLM of each feature and its Cook's distances
    let fits: Vec<(glm::GlmFit, Vec<f64>)> = kept
        .par_iter()
        .map(|&g| {
            let y = count_row(g);
            let fitted = glm::irls(
                &y,
                &row(&factors, g),
                x,
                p,
                dispersions[g],
                params.min_mu,
                params.beta_tol,
            );
            let robust = glm::robust_dispersion(&row(&normed, g), &design.groups);
            let cooks = glm::cooks_distances(&y, &fitted, robust, p);
            (fitted, cooks)
        })
        .collect();
    let mut coefficients = Array2::from_elem((n_features, p), f64::NAN);
    let mut mu = Array2::from_elem((n_features, n_samples), f64::NAN);
    let mut cooks = Array2::from_elem((n_features, n_samples), f64::NAN);
    let mut converged = vec![false; n_features];
    for (&g, (fitted, distances)) in kept.iter().zip(fits) {
        for (k, b) in fitted.beta.iter().enumerate() {
            coefficients[[g, k]] = *b;
        }
        for j in 0..n_samples {
            mu[[g, j]] = fitted.mu[j];
            cooks[[g, j]] = distances[j];
        }
        converged[g] = fitted.converged;
    }
    Ok(Fit {
        size_factors,
        factors,
        base_mean,
        moments_dispersions,
        genewise_dispersions,
        trend,
        fitted_dispersions,
        squared_log_residual,
        prior_variance,
        map_dispersions,
        dispersions,
        dispersion_outlier,
        coefficients,
        mu,
        cooks,
        converged,
        non_zero,
    })
}

/// Per-feature results of a contrast (DESeq2's results table).
#[derive(Debug, Clone)]
pub struct Results {
    /// Mean normalised count.
    pub base_mean: Vec<f64>,
    /// log2 fold change of the contrast.
    pub log2_fold_change: Vec<f64>,
    /// Its standard error (log2).
    pub lfc_se: Vec<f64>,
    /// The Wald statistic.
    pub stat: Vec<f64>,
    /// Two-sided p-value (`NaN` for a Cook's outlier or a feature of zeros).
    pub p_value: Vec<f64>,
    /// Benjamini-Hochberg q-value.
    pub q_value: Vec<f64>,
    /// Whether a feature's p-value was set aside for a Cook's outlier.
    pub cooks_outlier: Vec<bool>,
}

/// The Wald test of `contrast` (see [`Design::contrast`]) for every feature of `fit`; with
/// `cooks_filter`, a feature's p-value is set aside when one of its samples in a condition of
/// three or more replicates has a Cook's distance above the 99th percentile of `F(p, m - p)`,
/// unless three or more samples have a higher count (DESeq2's rule).
pub fn results(
    counts: ArrayView2<f64>,
    fit: &Fit,
    design: &Design,
    contrast: &[f64],
    cooks_filter: bool,
) -> Results {
    let (n_features, n_samples) = counts.dim();
    let p = design.n_coefficients();
    let tested: Vec<(f64, f64, f64)> = (0..n_features)
        .into_par_iter()
        .map(|g| {
            if !fit.non_zero[g] {
                return (f64::NAN, f64::NAN, f64::NAN);
            }
            let beta = fit.coefficients.row(g).to_vec();
            let mu = glm::means(&design.matrix, p, &beta, &fit.factors.row(g).to_vec());
            test::wald(&design.matrix, fit.dispersions[g], &beta, &mu, contrast)
        })
        .collect();
    let replicates = design.replicates();
    let usable: Vec<usize> = (0..n_samples).filter(|&j| replicates[j] >= 3).collect();
    let cutoff = FisherSnedecor::new(p as f64, (n_samples - p) as f64)
        .map(|f| f.inverse_cdf(0.99))
        .unwrap_or(f64::INFINITY);
    let cooks_outlier: Vec<bool> = (0..n_features)
        .map(|g| {
            if !cooks_filter
                || !fit.non_zero[g]
                || !usable.iter().any(|&j| fit.cooks[[g, j]] > cutoff)
            {
                return false;
            }
            let mut largest = 0;
            for j in 1..n_samples {
                if fit.cooks[[g, j]] > fit.cooks[[g, largest]] {
                    largest = j;
                }
            }
            let above = (0..n_samples)
                .filter(|&j| counts[[g, j]] > counts[[g, largest]])
                .count();
            above < 3
        })
        .collect();
    let p_value: Vec<f64> = tested
        .iter()
        .zip(&cooks_outlier)
        .map(|(&(_, p, _), &outlier)| if outlier { f64::NAN } else { p })
        .collect();
    let q_value = test::benjamini_hochberg(&p_value);
    let log2 = std::f64::consts::LN_2;
    Results {
        base_mean: fit.base_mean.clone(),
        log2_fold_change: (0..n_features)
            .map(|g| {
                fit.coefficients
                    .row(g)
                    .iter()
                    .zip(contrast)
                    .map(|(b, c)| b * c)
                    .sum::<f64>()
                    / log2
            })
            .collect(),
        lfc_se: tested.iter().map(|t| t.2 / log2).collect(),
        stat: tested.iter().map(|t| t.0).collect(),
        p_value,
        q_value,
        cooks_outlier,
    }
}
