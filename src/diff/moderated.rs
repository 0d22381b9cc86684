//! limma's moderated t-test of two groups (Smyth 2004, *Stat. Appl. Genet. Mol. Biol.* 3:3):
//! for continuous per-feature values (a log2 insulation score, an eigenvector), each feature's
//! residual variance is shrunk towards a prior fitted to all features' variances, and its
//! difference of group means tested against Student's t with the residual and prior degrees of
//! freedom. As limma's `lmFit` with the design `~ group` and `eBayes()` at its defaults (no
//! trend, not robust): `fitFDist`'s moments on `log s²`, `squeezeVar`'s posterior variances,
//! the total degrees of freedom capped at the pooled ones.

use ndarray::ArrayView2;
use statrs::distribution::{ContinuousCDF, Normal, StudentsT};
use statrs::function::gamma::digamma;

use super::special::{trigamma, trigamma_inverse};

/// The moderated test of group B's mean against group A's, per feature (`NaN` where a feature
/// has no value in a group).
#[derive(Clone, Debug, PartialEq)]
pub struct ModeratedT {
    /// Mean of B minus mean of A.
    pub difference: Vec<f64>,
    /// `√(1/n_A + 1/n_B)`: the difference's standard error per unit of residual sd.
    pub std_unscaled: Vec<f64>,
    /// Residual variance `s²` (pooled within groups).
    pub variance: Vec<f64>,
    /// Residual degrees of freedom `n_A + n_B - 2`.
    pub df_residual: Vec<f64>,
    /// The prior's degrees of freedom `d₀` (infinite when the variances vary no more than
    /// sampling explains; 0, no prior, with fewer than two features with a variance).
    pub df_prior: f64,
    /// The prior variance `s₀²`.
    pub variance_prior: f64,
    /// Posterior variance `(d₀ s₀² + d s²) / (d₀ + d)`.
    pub variance_post: Vec<f64>,
    /// Moderated t statistic.
    pub t: Vec<f64>,
    /// Degrees of freedom of the test: `d + d₀`, at most the sum of all features' `d`.
    pub df_total: Vec<f64>,
    /// Two-sided p-value.
    pub p_value: Vec<f64>,
}

impl ModeratedT {
    /// The standard error of the difference, `√s²_post · std_unscaled`.
    pub fn standard_error(&self, feature: usize) -> f64 {
        self.variance_post[feature].sqrt() * self.std_unscaled[feature]
    }
}

/// limma's moderated t of `values` (one row per feature, one column per sample: the first
/// `n_first` columns are group A, the rest group B). `NaN` values are left out of their
/// feature, as limma leaves out missing values.
///
/// # Examples
///
/// Two features whose variances agree: the prior is that common variance with infinite
/// degrees of freedom, and the t statistics are the differences over its standard error.
///
/// ```
/// use contactmap::diff::moderated::moderated_t;
/// use ndarray::array;
///
/// let values = array![[1.0, 3.0, 5.0, 7.0], [0.0, 2.0, 0.0, 2.0]];
/// let test = moderated_t(values.view(), 2);
/// assert_eq!(test.difference, vec![4.0, 0.0]);
/// assert_eq!(test.variance, vec![2.0, 2.0]);
/// assert!(test.df_prior.is_infinite());
/// assert!((test.t[0] - 4.0 / 2.0f64.sqrt()).abs() < 1e-12);
/// assert_eq!(test.df_total, vec![4.0, 4.0]); // capped at the pooled degrees of freedom
/// ```
pub fn moderated_t(values: ArrayView2<'_, f64>, n_first: usize) -> ModeratedT {
    let n_features = values.nrows();
    let mut difference = vec![f64::NAN; n_features];
    let mut std_unscaled = vec![f64::NAN; n_features];
    let mut variance = vec![f64::NAN; n_features];
    let mut df_residual = vec![0.0; n_features];
    for (f, row) in values.outer_iter().enumerate() {
        let groups = [
            row.slice(ndarray::s![..n_first]),
            row.slice(ndarray::s![n_first..]),
        ];
        let mut means = [0.0; 2];
        let mut counts = [0usize; 2];
        let mut squares = 0.0;
        for (g, group) in groups.iter().enumerate() {
            let valid: Vec<f64> = group.iter().copied().filter(|v| !v.is_nan()).collect();
            counts[g] = valid.len();
            means[g] = valid.iter().sum::<f64>() / valid.len() as f64;
            squares += valid.iter().map(|v| (v - means[g]).powi(2)).sum::<f64>();
        }
        if counts.contains(&0) {
            continue;
        }
        difference[f] = means[1] - means[0];
        std_unscaled[f] = (1.0 / counts[0] as f64 + 1.0 / counts[1] as f64).sqrt();
        let df = (counts[0] + counts[1]) as f64 - 2.0;
        df_residual[f] = df;
        if df > 0.0 {
            variance[f] = squares / df;
        }
    }
    let (variance_prior, df_prior) = match fit_f_distribution(&variance, &df_residual) {
        // fewer than two variances: no prior, each feature's own variance (limma's squeezeVar)
        (_, d) if d.is_nan() => (f64::NAN, 0.0),
        fitted => fitted,
    };
    let df_pooled: f64 = df_residual.iter().sum();
    let mut variance_post = vec![f64::NAN; n_features];
    let mut t = vec![f64::NAN; n_features];
    let mut df_total = vec![f64::NAN; n_features];
    let mut p_value = vec![f64::NAN; n_features];
    for f in 0..n_features {
        if difference[f].is_nan() {
            continue;
        }
        let d = df_residual[f];
        let s2 = if d > 0.0 { variance[f] } else { 0.0 };
        variance_post[f] = if df_prior.is_infinite() {
            variance_prior
        } else if df_prior == 0.0 {
            variance[f]
        } else {
            (d * s2 + df_prior * variance_prior) / (d + df_prior)
        };
        t[f] = difference[f] / std_unscaled[f] / variance_post[f].sqrt();
        df_total[f] = (d + df_prior).min(df_pooled);
        p_value[f] = two_sided_t(t[f], df_total[f]);
    }
    ModeratedT {
        difference,
        std_unscaled,
        variance,
        df_residual,
        df_prior,
        variance_prior,
        variance_post,
        t,
        df_total,
        p_value,
    }
}

/// `2 P(T > |t|)` for Student's t with `df` degrees of freedom (the normal when infinite).
fn two_sided_t(t: f64, df: f64) -> f64 {
    if t.is_nan() || df.is_nan() || df <= 0.0 {
        return f64::NAN;
    }
    if df.is_infinite() {
        return 2.0 * Normal::standard().sf(t.abs());
    }
    match StudentsT::new(0.0, 1.0, df) {
        Ok(dist) => 2.0 * dist.sf(t.abs()),
        Err(_) => f64::NAN,
    }
}

/// limma's `fitFDist` without a covariate: the scale `s₀²` and degrees of freedom `d₀` of the
/// scaled F distribution the variances follow, by the moments of `log s²` (variances of
/// features with `d > 0`; zeros raised to 1e-5 times the median); when the variances spread no
/// more than sampling explains, `d₀` is infinite and `s₀²` their mean. `(NaN, NaN)` with fewer
/// than two variances.
pub fn fit_f_distribution(variances: &[f64], df: &[f64]) -> (f64, f64) {
    let kept: Vec<(f64, f64)> = variances
        .iter()
        .zip(df)
        .filter(|(v, d)| !v.is_nan() && **v > -1e-15 && **d > 1e-15)
        .map(|(v, d)| (v.max(0.0), *d))
        .collect();
    let n = kept.len();
    if n <= 1 {
        return (f64::NAN, f64::NAN);
    }
    let mut sorted: Vec<f64> = kept.iter().map(|(v, _)| *v).collect();
    sorted.sort_by(f64::total_cmp);
    let mut median = if n % 2 == 1 {
        sorted[n / 2]
    } else {
        (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0
    };
    if median == 0.0 {
        median = 1.0;
    }
    let e: Vec<f64> = kept
        .iter()
        .map(|(v, d)| v.max(1e-5 * median).ln() - digamma(d / 2.0) + (d / 2.0).ln())
        .collect();
    let mean = e.iter().sum::<f64>() / n as f64;
    let spread = e.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64
        - kept.iter().map(|(_, d)| trigamma(d / 2.0)).sum::<f64>() / n as f64;
    if spread > 0.0 {
        let df_prior = 2.0 * trigamma_inverse(spread);
        let scale = (mean + digamma(df_prior / 2.0) - (df_prior / 2.0).ln()).exp();
        (scale, df_prior)
    } else {
        // the pooled variance, the scale's maximum-likelihood estimate here (limma since 2017)
        let floored = kept.iter().map(|(v, _)| v.max(1e-5 * median));
        (floored.sum::<f64>() / n as f64, f64::INFINITY)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::open_text;
    use ndarray::Array2;
    use std::io::Read;

    fn close(ours: f64, theirs: f64, absolute: f64) -> bool {
        ours == theirs || (ours - theirs).abs() <= 1e-9 * theirs.abs() + absolute
    }

    /// limma's lmFit(~ group) + eBayes through inmoose 0.9.1 (checked against R limma 3.54.1 by
    /// scripts/moderated_references.R) on 2 + 2, 3 + 3 and a case whose prior has infinite
    /// degrees of freedom: every column to 1e-9 relative.
    #[test]
    fn moderated_t_equals_limma() {
        let mut text = String::new();
        open_text(std::path::Path::new("data/diff/moderated.tsv.gz"))
            .unwrap()
            .read_to_string(&mut text)
            .unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split('\t').collect();
        let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split('\t').collect()).collect();
        for case in ["two_by_two", "three_by_three", "equal_variances"] {
            let rows: Vec<&Vec<&str>> = rows.iter().filter(|r| r[0] == case).collect();
            let value = |row: &[&str], name: &str| -> f64 { row[column(name)].parse().unwrap() };
            let groups: Vec<&str> = ["A1", "A2", "A3", "B1", "B2", "B3"]
                .into_iter()
                .filter(|name| !value(rows[0], name).is_nan())
                .collect();
            let n_first = groups.iter().filter(|g| g.starts_with('A')).count();
            let mut values = Array2::zeros((rows.len(), groups.len()));
            for (f, row) in rows.iter().enumerate() {
                for (s, name) in groups.iter().enumerate() {
                    values[[f, s]] = value(row, name);
                }
            }
            let test = moderated_t(values.view(), n_first);
            let first = rows[0];
            assert!(
                close(test.df_prior, value(first, "df_prior"), 0.0),
                "{case}"
            );
            assert!(
                close(test.variance_prior, value(first, "s2_prior"), 0.0),
                "{case}"
            );
            for (f, row) in rows.iter().enumerate() {
                let sigma = value(row, "sigma");
                let checks = [
                    (test.difference[f], value(row, "coefficient"), 1e-12),
                    (test.std_unscaled[f], value(row, "stdev_unscaled"), 0.0),
                    (test.variance[f], sigma * sigma, 1e-15),
                    (test.df_residual[f], value(row, "df_residual"), 0.0),
                    (test.variance_post[f], value(row, "s2_post"), 0.0),
                    (test.df_total[f], value(row, "df_total"), 0.0),
                    (test.t[f], value(row, "t"), 1e-11),
                    (test.p_value[f], value(row, "p_value"), 1e-14),
                ];
                for (k, (ours, theirs, absolute)) in checks.into_iter().enumerate() {
                    assert!(
                        close(ours, theirs, absolute),
                        "{case} feature {f} check {k}: {ours} vs {theirs}"
                    );
                }
            }
        }
    }

    #[test]
    fn missing_values_leave_their_feature_and_an_empty_group_gives_nan() {
        let values = ndarray::array![
            [1.0, 2.0, f64::NAN, 4.0, 6.0],
            [f64::NAN, f64::NAN, f64::NAN, 1.0, 2.0],
            [0.0, 1.0, 2.0, 3.0, 4.0]
        ];
        let test = moderated_t(values.view(), 3);
        assert_eq!(test.difference[0], 5.0 - 1.5);
        assert_eq!(test.df_residual[0], 2.0);
        assert!((test.std_unscaled[0] - 1.0f64).abs() < 1e-15);
        assert!(test.difference[1].is_nan() && test.p_value[1].is_nan());
        assert_eq!(test.difference[2], 2.5);
    }
}
