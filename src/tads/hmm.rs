//! Domains from the directionality index by a three-state Gaussian hidden Markov model.
//!
//! Reference: Dixon JR, Selvaraj S, Yue F, Kim A, Li Y, Shen Y, Hu M, Liu JS, Ren B. "Topological
//! domains in mammalian genomes identified by analysis of chromatin interactions." Nature
//! 485:376-380 (2012), Methods "Directionality index" and "Hidden Markov model".
//!
//! The directionality index (DI) of a bin is positive when the bin contacts its downstream
//! (higher-coordinate) neighbours more than its upstream ones. Dixon et al. model the DI with a
//! hidden Markov model whose three hidden states are *upstream biased*, *no bias* and *downstream
//! biased*; a domain starts where downstream bias starts and ends where the last upstream bias
//! before the next downstream-biased run ends.
//!
//! Model ([`GaussianHmm`]): three states, an initial distribution, a 3 x 3 transition matrix and
//! **one Gaussian per state with a variance shared by the three states** (Dixon et al. used a
//! mixture of Gaussians per state and chose the number of components by AIC). The shared variance
//! makes the states differ by the direction of the bias: with a free variance per state, the fit
//! on a real or simulated index, which is heavy-tailed, tends to give one state to the large
//! values of both signs and another to the small ones, and the upstream / downstream labels lose
//! their meaning. Fitting ([`GaussianHmm::fit`]) is Baum-Welch (EM) with scaled
//! forward-backward, jointly over all tracks (one per chromosome / region: they share the
//! parameters, each has its own chain). NaN observations are missing: their emission probability
//! is 1, so the chain runs through them on the transitions alone.
//!
//! Conventions and defaults ([`HmmParams`]):
//! - deterministic initialisation: the finite DI values are sorted and split in thirds; each
//!   state starts with the mean of one third and the mean of the thirds' variances, uniform
//!   initial probabilities and a transition matrix with 0.9 on the diagonal;
//! - variances are floored at `1e-6` times the variance of all DI values (and at `1e-12`) so that
//!   a state cannot collapse onto one value;
//! - EM stops when the log-likelihood changes by less than `tolerance` (default `1e-6`) relative
//!   to `max(1, |log-likelihood|)`, or after `max_iterations` (default 500) iterations;
//! - after fitting, states are ordered by their emission mean: the most negative is
//!   [`DiState::Upstream`], the middle one [`DiState::Neutral`], the most positive
//!   [`DiState::Downstream`];
//! - domains ([`di_domains`]): from the Viterbi path, a domain opens at the first bin of a
//!   downstream-biased state and stays open through downstream and neutral states; it closes at
//!   the end of the last upstream-biased state seen before the next downstream-biased state, which
//!   opens the next domain. A domain that never sees an upstream-biased state (at the end of the
//!   track) is dropped, as are domains shorter than `min_domain_bins` (default 3). Boundaries are
//!   the domain starts. Bins are genome-wide (`first_bin + local index`).

use super::directionality::DirectionalityTable;
use super::domains::{Boundary, Domain, region_rows};
use crate::error::{Error, Result};

/// Parameters of the fit and of the domain calls.
#[derive(Clone, Debug, PartialEq)]
pub struct HmmParams {
    /// Maximum number of Baum-Welch iterations (default 500).
    pub max_iterations: usize,
    /// Convergence threshold on the relative change of the log-likelihood (default 1e-6).
    pub tolerance: f64,
    /// Domains shorter than this many bins are dropped (default 3).
    pub min_domain_bins: usize,
}

impl HmmParams {
    /// Check the values: at least one iteration, a tolerance that is a number `>= 0`.
    /// [`GaussianHmm::fit`] checks them first.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::tads::hmm::HmmParams;
    ///
    /// assert!(HmmParams::default().check().is_ok());
    /// let bad = HmmParams { tolerance: f64::NAN, ..HmmParams::default() };
    /// assert!(bad.check().is_err());
    /// ```
    pub fn check(&self) -> Result<()> {
        if self.max_iterations == 0 {
            return Err(Error::parameter("max_iterations", 0, "expected at least 1"));
        }
        if self.tolerance.is_nan() || self.tolerance < 0.0 {
            return Err(Error::parameter(
                "tolerance",
                self.tolerance,
                "expected a number >= 0",
            ));
        }
        Ok(())
    }
}

impl Default for HmmParams {
    fn default() -> Self {
        HmmParams {
            max_iterations: 500,
            tolerance: 1e-6,
            min_domain_bins: 3,
        }
    }
}

/// The hidden state of a bin: the direction of its contact bias.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DiState {
    /// Upstream biased (negative DI): the end of a domain.
    Upstream,
    /// No bias (DI near 0): inside a domain.
    Neutral,
    /// Downstream biased (positive DI): the start of a domain.
    Downstream,
}

impl DiState {
    /// The state of index `k` (0 Upstream, 1 Neutral, 2 Downstream).
    pub fn from_index(k: usize) -> DiState {
        match k {
            0 => DiState::Upstream,
            1 => DiState::Neutral,
            _ => DiState::Downstream,
        }
    }

    /// The index of the state (0 Upstream, 1 Neutral, 2 Downstream).
    pub fn index(self) -> usize {
        match self {
            DiState::Upstream => 0,
            DiState::Neutral => 1,
            DiState::Downstream => 2,
        }
    }
}

/// A three-state hidden Markov model with one Gaussian emission per state. State `k` is
/// [`DiState::from_index`]`(k)`; after [`GaussianHmm::fit`] the means are increasing.
#[derive(Clone, Debug, PartialEq)]
pub struct GaussianHmm {
    /// Initial state probabilities.
    pub initial: [f64; 3],
    /// `transition[i][j]`: probability of state `j` after state `i`.
    pub transition: [[f64; 3]; 3],
    /// Emission mean per state.
    pub means: [f64; 3],
    /// Emission variance per state.
    pub variances: [f64; 3],
}

/// Forward-backward of one track: posteriors, expected transitions and the log-likelihood.
struct ForwardBackward {
    gamma: Vec<[f64; 3]>,
    xi_sum: [[f64; 3]; 3],
    log_likelihood: f64,
}

impl GaussianHmm {
    /// Fit by Baum-Welch over all `tracks` jointly (see the module doc for the initialisation,
    /// the variance floor and the stopping rule). Errors when there are fewer than 3 finite
    /// observations in all, or when the parameters are not usable.
    pub fn fit(tracks: &[&[f64]], params: &HmmParams) -> Result<GaussianHmm> {
        params.check()?;
        let mut finite: Vec<f64> = tracks
            .iter()
            .flat_map(|t| t.iter().copied())
            .filter(|v| v.is_finite())
            .collect();
        if finite.len() < 3 {
            return Err(Error::Data(format!(
                "HMM: need at least 3 finite observations to fit 3 states, got {}",
                finite.len()
            )));
        }
        finite.sort_by(f64::total_cmp);
        let (_, total_var) = mean_var(&finite);
        let floor = (total_var * 1e-6).max(1e-12);
        let n = finite.len();
        let mut means = [0.0; 3];
        let mut variances = [0.0; 3];
        for k in 0..3 {
            let part = &finite[k * n / 3..(k + 1) * n / 3];
            let (m, v) = mean_var(part);
            means[k] = m;
            variances[k] = v.max(floor);
        }
        let shared = variances.iter().sum::<f64>() / 3.0;
        let variances = [shared; 3];
        let mut model = GaussianHmm {
            initial: [1.0 / 3.0; 3],
            transition: [[0.9, 0.05, 0.05], [0.05, 0.9, 0.05], [0.05, 0.05, 0.9]],
            means,
            variances,
        };

        let mut previous = f64::NEG_INFINITY;
        for _ in 0..params.max_iterations.max(1) {
            let mut init_acc = [0.0; 3];
            let mut n_chains = 0.0;
            let mut trans_acc = [[0.0; 3]; 3];
            let mut weight = [0.0; 3];
            let mut sum_x = [0.0; 3];
            let mut sum_xx = [0.0; 3];
            let mut ll = 0.0;
            for track in tracks {
                if track.is_empty() {
                    continue;
                }
                let fb = model.forward_backward(track);
                ll += fb.log_likelihood;
                for k in 0..3 {
                    init_acc[k] += fb.gamma[0][k];
                    for (acc, xi) in trans_acc[k].iter_mut().zip(&fb.xi_sum[k]) {
                        *acc += xi;
                    }
                }
                n_chains += 1.0;
                for (x, g) in track.iter().zip(&fb.gamma) {
                    if x.is_finite() {
                        for k in 0..3 {
                            weight[k] += g[k];
                            sum_x[k] += g[k] * x;
                            sum_xx[k] += g[k] * x * x;
                        }
                    }
                }
            }
            // M step.
            let mut pooled = 0.0;
            for k in 0..3 {
                model.initial[k] = init_acc[k] / n_chains;
                let row: f64 = trans_acc[k].iter().sum();
                if row > 0.0 {
                    model.transition[k] = trans_acc[k].map(|t| t / row);
                }
                if weight[k] > 0.0 {
                    let m = sum_x[k] / weight[k];
                    model.means[k] = m;
                    pooled += sum_xx[k] - weight[k] * m * m;
                }
            }
            // One variance shared by the three states: the states differ by their mean (the
            // direction of the bias), not by the spread of the index.
            let total: f64 = weight.iter().sum();
            if total > 0.0 {
                model.variances = [(pooled / total).max(floor); 3];
            }
            let converged = (ll - previous).abs() <= params.tolerance * ll.abs().max(1.0);
            previous = ll;
            if converged {
                break;
            }
        }
        if !model
            .means
            .iter()
            .chain(&model.variances)
            .all(|v| v.is_finite())
        {
            return Err(Error::Data(
                "HMM: the fit did not converge to finite parameters".into(),
            ));
        }
        Ok(model.sorted_by_mean())
    }

    /// The same model with the states relabelled so that the means increase.
    fn sorted_by_mean(&self) -> GaussianHmm {
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| self.means[a].total_cmp(&self.means[b]));
        let mut out = self.clone();
        for (new, &old) in order.iter().enumerate() {
            out.initial[new] = self.initial[old];
            out.means[new] = self.means[old];
            out.variances[new] = self.variances[old];
            for (new2, &old2) in order.iter().enumerate() {
                out.transition[new][new2] = self.transition[old][old2];
            }
        }
        out
    }

    /// Log emission densities at `x` (all 0 for a missing observation).
    fn log_emissions(&self, x: f64) -> [f64; 3] {
        if x.is_nan() {
            return [0.0; 3];
        }
        std::array::from_fn(|k| {
            let v = self.variances[k];
            -0.5 * ((x - self.means[k]).powi(2) / v + (2.0 * std::f64::consts::PI * v).ln())
        })
    }

    /// Emissions divided by their maximum, and the log of that maximum (avoids underflow far
    /// from every mean; the factor only shifts the log-likelihood).
    fn emissions(&self, x: f64) -> ([f64; 3], f64) {
        let le = self.log_emissions(x);
        let top = le.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (le.map(|l| (l - top).exp()), top)
    }

    fn forward_backward(&self, track: &[f64]) -> ForwardBackward {
        let n = track.len();
        let mut alpha = vec![[0.0; 3]; n];
        let mut scale = vec![0.0; n];
        let mut emis = Vec::with_capacity(n);
        let mut ll = 0.0;
        for t in 0..n {
            let (b, shift) = self.emissions(track[t]);
            emis.push(b);
            let mut a = [0.0; 3];
            for j in 0..3 {
                let prior = if t == 0 {
                    self.initial[j]
                } else {
                    (0..3)
                        .map(|i| alpha[t - 1][i] * self.transition[i][j])
                        .sum()
                };
                a[j] = prior * b[j];
            }
            let c: f64 = a.iter().sum();
            let c = if c > 0.0 { c } else { f64::MIN_POSITIVE };
            alpha[t] = a.map(|v| v / c);
            scale[t] = c;
            ll += c.ln() + shift;
        }
        let mut beta = vec![[1.0; 3]; n];
        for t in (0..n.saturating_sub(1)).rev() {
            for i in 0..3 {
                beta[t][i] = (0..3)
                    .map(|j| self.transition[i][j] * emis[t + 1][j] * beta[t + 1][j])
                    .sum::<f64>()
                    / scale[t + 1];
            }
        }
        let mut gamma = vec![[0.0; 3]; n];
        let mut xi_sum = [[0.0; 3]; 3];
        for t in 0..n {
            let mut g = [0.0; 3];
            for k in 0..3 {
                g[k] = alpha[t][k] * beta[t][k];
            }
            let s: f64 = g.iter().sum();
            gamma[t] = if s > 0.0 {
                g.map(|v| v / s)
            } else {
                [1.0 / 3.0; 3]
            };
            if t + 1 < n {
                for i in 0..3 {
                    for j in 0..3 {
                        xi_sum[i][j] +=
                            alpha[t][i] * self.transition[i][j] * emis[t + 1][j] * beta[t + 1][j]
                                / scale[t + 1];
                    }
                }
            }
        }
        ForwardBackward {
            gamma,
            xi_sum,
            log_likelihood: ll,
        }
    }

    /// Log-likelihood of one track (scaled forward algorithm; NaN observations are missing).
    pub fn log_likelihood(&self, track: &[f64]) -> f64 {
        if track.is_empty() {
            return 0.0;
        }
        self.forward_backward(track).log_likelihood
    }

    /// The most likely state path (Viterbi, in log space; ties go to the lower state index).
    pub fn viterbi(&self, track: &[f64]) -> Vec<DiState> {
        let n = track.len();
        if n == 0 {
            return Vec::new();
        }
        let log_a = self.transition.map(|row| row.map(f64::ln));
        let mut delta = self.log_emissions(track[0]);
        for (k, d) in delta.iter_mut().enumerate() {
            *d += self.initial[k].ln();
        }
        let mut back = vec![[0u8; 3]; n];
        for t in 1..n {
            let le = self.log_emissions(track[t]);
            let mut next = [0.0; 3];
            for j in 0..3 {
                let mut best = 0;
                for i in 1..3 {
                    if delta[i] + log_a[i][j] > delta[best] + log_a[best][j] {
                        best = i;
                    }
                }
                next[j] = delta[best] + log_a[best][j] + le[j];
                back[t][j] = best as u8;
            }
            delta = next;
        }
        let mut state = 0;
        for k in 1..3 {
            if delta[k] > delta[state] {
                state = k;
            }
        }
        let mut path = vec![DiState::Upstream; n];
        for t in (0..n).rev() {
            path[t] = DiState::from_index(state);
            state = back[t][state] as usize;
        }
        path
    }

    /// Posterior state probabilities per position (forward-backward), indexed by
    /// [`DiState::index`].
    pub fn posterior(&self, track: &[f64]) -> Vec<[f64; 3]> {
        if track.is_empty() {
            return Vec::new();
        }
        self.forward_backward(track).gamma
    }
}

fn mean_var(v: &[f64]) -> (f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0);
    }
    let m = v.iter().sum::<f64>() / v.len() as f64;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len() as f64;
    (m, var)
}

/// Domains of one region's DI track.
#[derive(Clone, Debug, PartialEq)]
pub struct DiDomains {
    /// Viterbi state per local bin; `None` where the index is NaN (a masked bin has no
    /// observation, so no state of its own: the path only runs through it).
    pub states: Vec<Option<DiState>>,
    /// Domains (genome-wide bins, `level` 0, `score` = mean posterior probability of the Viterbi
    /// state over the domain's bins).
    pub domains: Vec<Domain>,
    /// Domain starts (genome-wide bins), strength = posterior probability of
    /// [`DiState::Downstream`] at the start bin.
    pub boundaries: Vec<Boundary>,
}

/// Dixon's calls over a whole directionality table: states per row, domains and boundaries.
#[derive(Clone, Debug, PartialEq)]
pub struct DixonCalls {
    /// Viterbi state of each row of the table (`None` where the index is NaN).
    pub states: Vec<Option<DiState>>,
    /// Domains of every region, in table order.
    pub domains: Vec<Domain>,
    /// Domain starts of every region, in table order.
    pub boundaries: Vec<Boundary>,
}

/// Dixon's domains for every region of `table`: the HMM is fitted once, genome-wide, to the
/// signed normal scores of the directionality index ([`signed_normal_scores`]); each region is
/// then decoded on its own ([`di_domains`]).
///
/// # Examples
///
/// ```
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
/// use contactmap::tads::directionality::{directionality, DirectionalityParams};
/// use contactmap::tads::hmm::{dixon_domains, HmmParams};
///
/// // four 25-bin domains on a distance decay: boundaries at bins 25, 50 and 75
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 100_000)], 1_000)?;
/// let mut builder = MatrixBuilder::new(bins.clone(), CountType::Float);
/// for i in 0..100u64 {
///     for j in i..100 {
///         let enrichment = if i / 25 == j / 25 { 4.0 } else { 1.0 };
///         builder.push(i, j, enrichment * 100.0 / (j - i + 1) as f64)?;
///     }
/// }
/// let matrix = InMemory::new("domains".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// let view = View::chromosomes(&bins);
/// let table = directionality(&pixels, None, &view, &DirectionalityParams::new(5_000))?;
/// let calls = dixon_domains(&table, &HmmParams::default())?;
/// assert_eq!(calls.states.len(), 100);
/// let starts: Vec<usize> = calls.domains.iter().map(|d| d.start_bin).collect();
/// for truth in [25, 50, 75] {
///     assert!(starts.iter().any(|s| s.abs_diff(truth) <= 2), "{starts:?}");
/// }
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn dixon_domains(table: &DirectionalityTable, params: &HmmParams) -> Result<DixonCalls> {
    let rows = region_rows(&table.region);
    let tracks: Vec<&[f64]> = rows.iter().map(|r| &table.index[r.clone()]).collect();
    let scores = signed_normal_scores(&tracks);
    let score_tracks: Vec<&[f64]> = scores.iter().map(Vec::as_slice).collect();
    let model = GaussianHmm::fit(&score_tracks, params)?;
    let mut calls = DixonCalls {
        states: Vec::with_capacity(table.bins.len()),
        domains: Vec::new(),
        boundaries: Vec::new(),
    };
    for (r, track) in rows.iter().zip(&score_tracks) {
        let called = di_domains(&model, track, table.bins[r.start], params);
        calls.states.extend(called.states);
        calls.domains.extend(called.domains);
        calls.boundaries.extend(called.boundaries);
    }
    Ok(calls)
}

/// Signed normal scores of the directionality index, the scale the HMM is fitted on: each finite
/// value `x` becomes `sign(x) * Phi^-1((1 + r / (n + 1)) / 2)`, where `r` is the rank of `|x|`
/// among the `n` finite values of all `tracks` (ties share their mean rank) and `Phi^-1` the
/// standard normal quantile; 0 stays 0 and NaN stays NaN.
///
/// The index is a chi-square-like statistic whose tails grow with the contact counts: a handful of
/// extreme bins (next to masked bins, at chromosome ends) would otherwise claim the two biased
/// states and leave every other bin neutral. The transform keeps the sign and the order of the
/// index and gives it Gaussian tails, whatever the depth and the balancing.
pub fn signed_normal_scores(tracks: &[&[f64]]) -> Vec<Vec<f64>> {
    let mut magnitudes: Vec<f64> = tracks
        .iter()
        .flat_map(|t| t.iter())
        .filter(|x| x.is_finite())
        .map(|x| x.abs())
        .collect();
    magnitudes.sort_by(f64::total_cmp);
    let n = magnitudes.len() as f64;
    let normal = statrs::distribution::Normal::standard();
    // Mean rank (1-based) of `value` among the sorted magnitudes.
    let rank = |value: f64| {
        let below = magnitudes.partition_point(|&m| m < value) as f64;
        let up_to = magnitudes.partition_point(|&m| m <= value) as f64;
        (below + 1.0 + up_to) / 2.0
    };
    tracks
        .iter()
        .map(|track| {
            track
                .iter()
                .map(|&x| {
                    if !x.is_finite() {
                        f64::NAN
                    } else if x == 0.0 {
                        0.0
                    } else {
                        let p = (1.0 + rank(x.abs()) / (n + 1.0)) / 2.0;
                        x.signum() * statrs::distribution::ContinuousCDF::inverse_cdf(&normal, p)
                    }
                })
                .collect()
        })
        .collect()
}

/// Call Dixon domains on `track` (the DI of one region whose first bin is `first_bin`) with a
/// fitted `model`; see the module doc for the rule.
pub fn di_domains(
    model: &GaussianHmm,
    track: &[f64],
    first_bin: usize,
    params: &HmmParams,
) -> DiDomains {
    let path = model.viterbi(track);
    let posterior = model.posterior(track);
    // Masked bins (NaN) keep no state: they neither open nor close a domain.
    let states: Vec<Option<DiState>> = path
        .iter()
        .zip(track)
        .map(|(&state, x)| (!x.is_nan()).then_some(state))
        .collect();
    let spans = domain_spans(&states, params.min_domain_bins);
    let mut domains = Vec::with_capacity(spans.len());
    let mut boundaries = Vec::with_capacity(spans.len());
    for (s, e) in spans {
        let observed: Vec<f64> = (s..e)
            .filter_map(|t| states[t].map(|state| posterior[t][state.index()]))
            .collect();
        let score = observed.iter().sum::<f64>() / observed.len().max(1) as f64;
        domains.push(Domain {
            start_bin: first_bin + s,
            end_bin: first_bin + e,
            level: 0,
            score,
        });
        boundaries.push(Boundary {
            bin: first_bin + s,
            strength: posterior[s][DiState::Downstream.index()],
        });
    }
    DiDomains {
        states,
        domains,
        boundaries,
    }
}

/// Dixon's rule on a state path: local `[start, end)` spans of at least `min_bins` bins;
/// bins without a state (masked) count as neutral.
fn domain_spans(states: &[Option<DiState>], min_bins: usize) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut open: Option<usize> = None;
    let mut last_up_end: Option<usize> = None;
    let mut close = |s: usize, e: usize| {
        if e - s >= min_bins.max(1) {
            spans.push((s, e));
        }
    };
    for (t, &state) in states.iter().enumerate() {
        match state.unwrap_or(DiState::Neutral) {
            DiState::Downstream => match (open, last_up_end) {
                (Some(s), Some(e)) => {
                    close(s, e);
                    open = Some(t);
                    last_up_end = None;
                }
                (None, _) => open = Some(t),
                (Some(_), None) => {}
            },
            DiState::Upstream => {
                if open.is_some() {
                    last_up_end = Some(t + 1);
                }
            }
            DiState::Neutral => {}
        }
    }
    if let (Some(s), Some(e)) = (open, last_up_end) {
        close(s, e);
    }
    spans
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small LCG with Box-Muller normals, for reproducible synthetic data.
    struct Lcg(u64);

    impl Lcg {
        fn uniform(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        }

        fn normal(&mut self) -> f64 {
            let (u1, u2) = (self.uniform(), self.uniform());
            (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
        }
    }

    fn simulate(model: &GaussianHmm, n: usize, rng: &mut Lcg) -> (Vec<usize>, Vec<f64>) {
        let pick = |p: &[f64; 3], u: f64| {
            let mut acc = 0.0;
            for (k, &pk) in p.iter().enumerate() {
                acc += pk;
                if u < acc {
                    return k;
                }
            }
            2
        };
        let mut states = Vec::with_capacity(n);
        let mut obs = Vec::with_capacity(n);
        let mut s = pick(&model.initial, rng.uniform());
        for _ in 0..n {
            states.push(s);
            obs.push(model.means[s] + model.variances[s].sqrt() * rng.normal());
            s = pick(&model.transition[s], rng.uniform());
        }
        (states, obs)
    }

    fn truth() -> GaussianHmm {
        GaussianHmm {
            initial: [0.2, 0.5, 0.3],
            transition: [[0.9, 0.08, 0.02], [0.04, 0.92, 0.04], [0.03, 0.07, 0.9]],
            means: [-2.5, 0.0, 2.0],
            variances: [0.5, 0.5, 0.5],
        }
    }

    #[test]
    fn signed_normal_scores_keep_sign_order_and_zero() {
        let a = [3.0, -0.5, 0.0, f64::NAN, 100.0];
        let b = [-3.0, 0.5];
        let scores = signed_normal_scores(&[&a, &b]);
        // Magnitudes 0.5, 0.5, 3, 3, 100 and 0 (ranks 2.5, 2.5, 4.5, 4.5, 6, 1) among n = 6.
        let z = |rank: f64| {
            let normal = statrs::distribution::Normal::standard();
            statrs::distribution::ContinuousCDF::inverse_cdf(&normal, (1.0 + rank / 7.0) / 2.0)
        };
        assert!((scores[0][0] - z(4.5)).abs() < 1e-12);
        assert!((scores[0][1] + z(2.5)).abs() < 1e-12);
        assert_eq!(scores[0][2], 0.0);
        assert!(scores[0][3].is_nan());
        assert!((scores[0][4] - z(6.0)).abs() < 1e-12);
        assert_eq!(scores[1][0], -scores[0][0]);
        assert_eq!(scores[1][1], -scores[0][1]);
    }

    #[test]
    fn fit_recovers_generating_chain() {
        let model = truth();
        let mut rng = Lcg(42);
        let (s1, mut x1) = simulate(&model, 2500, &mut rng);
        let (s2, x2) = simulate(&model, 1500, &mut rng);
        // Some missing observations.
        for t in (0..x1.len()).step_by(97) {
            x1[t] = f64::NAN;
        }
        let fitted = GaussianHmm::fit(&[&x1, &x2], &HmmParams::default()).unwrap();
        for k in 0..3 {
            assert!(
                (fitted.means[k] - model.means[k]).abs() < 0.15,
                "means {:?}",
                fitted.means
            );
            assert!(
                (fitted.variances[k] / model.variances[k] - 1.0).abs() < 0.25,
                "variances {:?}",
                fitted.variances
            );
            assert!((fitted.transition[k][k] - model.transition[k][k]).abs() < 0.05);
        }
        for (states, x) in [(&s1, &x1), (&s2, &x2)] {
            let path = fitted.viterbi(x);
            let agree = path
                .iter()
                .zip(states.iter())
                .filter(|(p, s)| p.index() == **s)
                .count();
            assert!(
                agree as f64 > 0.9 * x.len() as f64,
                "{agree} of {}",
                x.len()
            );
        }
        // Posteriors are distributions.
        for g in fitted.posterior(&x2) {
            assert!((g.iter().sum::<f64>() - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn forward_log_likelihood_equals_brute_force() {
        let model = truth();
        let track = [0.3, -2.0, f64::NAN, 1.7, 2.4];
        let density = |k: usize, x: f64| {
            if x.is_nan() {
                1.0
            } else {
                let v = model.variances[k];
                (-(x - model.means[k]).powi(2) / (2.0 * v)).exp()
                    / (2.0 * std::f64::consts::PI * v).sqrt()
            }
        };
        let mut total = 0.0;
        for code in 0..3usize.pow(5) {
            let path: Vec<usize> = (0..5).map(|t| code / 3usize.pow(t) % 3).collect();
            let mut p = model.initial[path[0]] * density(path[0], track[0]);
            for t in 1..5 {
                p *= model.transition[path[t - 1]][path[t]] * density(path[t], track[t]);
            }
            total += p;
        }
        let ll = model.log_likelihood(&track);
        assert!((ll - total.ln()).abs() < 1e-10, "{ll} vs {}", total.ln());
        // Far-away observations do not underflow.
        assert!(model.log_likelihood(&[1e3, -1e3]).is_finite());
    }

    #[test]
    fn dixon_rule_on_state_paths() {
        const D: Option<DiState> = Some(DiState::Downstream);
        const N: Option<DiState> = Some(DiState::Neutral);
        const U: Option<DiState> = Some(DiState::Upstream);
        let states = [D, D, N, U, U, N, D, D, U, D, N, N, U, D, N];
        assert_eq!(domain_spans(&states, 3), vec![(0, 5), (6, 9), (9, 13)]);
        assert_eq!(domain_spans(&states, 4), vec![(0, 5), (9, 13)]);
        assert_eq!(
            domain_spans(&[U, N, U, D, N], 1),
            Vec::<(usize, usize)>::new()
        );
        assert_eq!(domain_spans(&[U, D, N, D, U, N], 1), vec![(1, 5)]);
    }

    /// Masked bins (NaN) have no state and neither open nor close a domain (issue 26).
    #[test]
    fn masked_bins_have_no_state() {
        const D: Option<DiState> = Some(DiState::Downstream);
        const U: Option<DiState> = Some(DiState::Upstream);
        // A masked bin inside the run of downstream states changes nothing.
        assert_eq!(
            domain_spans(&[D, None, D, U, None, D, U], 1),
            vec![(0, 4), (5, 7)]
        );
        let mut track = vec![3.0, 2.5, 0.1, 0.0, -2.0, -2.5];
        track.extend(track.clone());
        track[2] = f64::NAN;
        track[8] = f64::NAN;
        let model = GaussianHmm::fit(&[&track], &HmmParams::default()).unwrap();
        let called = di_domains(&model, &track, 10, &HmmParams::default());
        for (t, state) in called.states.iter().enumerate() {
            assert_eq!(state.is_none(), track[t].is_nan(), "bin {t}");
        }
    }

    #[test]
    fn di_domains_on_a_synthetic_track() {
        // Three domains of 20 bins: DI positive at the start, negative at the end.
        let mut track = Vec::new();
        for _ in 0..3 {
            track.extend([3.0, 2.5, 2.8, 2.0]);
            track.extend([
                0.1, -0.2, 0.0, 0.2, -0.1, 0.05, 0.0, -0.05, 0.1, 0.0, -0.1, 0.2,
            ]);
            track.extend([-2.0, -2.6, -3.0, -2.4]);
        }
        let model = GaussianHmm::fit(&[&track], &HmmParams::default()).unwrap();
        assert!(model.means[0] < -1.5 && model.means[2] > 1.5);
        let out = di_domains(&model, &track, 1000, &HmmParams::default());
        let spans: Vec<(usize, usize)> = out
            .domains
            .iter()
            .map(|d| (d.start_bin, d.end_bin))
            .collect();
        assert_eq!(spans, vec![(1000, 1020), (1020, 1040), (1040, 1060)]);
        let starts: Vec<usize> = out.boundaries.iter().map(|b| b.bin).collect();
        assert_eq!(starts, vec![1000, 1020, 1040]);
        assert!(out.domains.iter().all(|d| d.score > 0.5 && d.score <= 1.0));
    }

    #[test]
    fn too_few_observations_is_invalid() {
        assert!(GaussianHmm::fit(&[&[1.0, f64::NAN, 2.0]], &HmmParams::default()).is_err());
    }
}
