//! Knight-Ruiz (KR) as Juicer computes it: `bnewt` (Newton's method with a conjugate-gradient
//! inner iteration) as a state machine, one problem per group sharing the passes over the
//! pixels, and Juicer's rules for dropping rows and retrying (see the parent module).

use std::cmp::Ordering;

use super::params::BalanceParams;
use super::passes::{
    Layout, Product, ProductGroup, row_sums, scope_filter, solve_groups, sum_factor,
};
use super::result::{BalanceResult, GroupStats};
use crate::error::Result;
use crate::matrix::PixelSource;

/// Knight-Ruiz `bnewt` (Juicer's port), as a state machine that asks for one matrix-vector
/// product at a time, so that many independent problems (one per chromosome) can share passes.
///
/// Vectors are indexed by the problem's own rows (`rows`, bin ids).
struct Bnewt {
    x: Vec<f64>,
    v: Vec<f64>,
    rk: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    rho_km1: f64,
    rho_km2: f64,
    rout: f64,
    rold: f64,
    eta: f64,
    innertol: f64,
    k: usize,
    not_changing: usize,
    n_outer: usize,
    n_products: usize,
    tol: f64,
    max_outer: usize,
    phase: BnewtPhase,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum BnewtPhase {
    /// Needs `A x` for the initial residual.
    Start,
    /// Needs `A (x .* p)` for a conjugate-gradient step.
    Inner,
    /// Needs `A x` after a Newton step.
    Outer,
    /// Converged.
    Converged,
    /// Stalled (Juicer's 100 unchanged outer iterations) or over the iteration limit.
    Failed,
}

/// bnewt's constants, as Juicer: distance to the cone boundary, and the forcing-term controls.
const KR_DELTA: f64 = 0.1;
const KR_G: f64 = 0.9;
const KR_ETAMAX: f64 = 0.1;

impl Bnewt {
    fn new(n: usize, tol: f64, max_outer: usize) -> Self {
        Bnewt {
            x: vec![1.0; n],
            v: vec![0.0; n],
            rk: vec![0.0; n],
            y: vec![1.0; n],
            z: vec![0.0; n],
            p: vec![0.0; n],
            rho_km1: 0.0,
            rho_km2: 0.0,
            rout: 0.0,
            rold: 0.0,
            eta: KR_ETAMAX,
            innertol: 0.0,
            k: 0,
            not_changing: 0,
            n_outer: 0,
            n_products: 0,
            tol,
            max_outer,
            phase: BnewtPhase::Start,
        }
    }

    fn is_done(&self) -> bool {
        matches!(self.phase, BnewtPhase::Converged | BnewtPhase::Failed)
    }

    /// The vector whose product with the matrix is needed next.
    fn request(&self) -> Vec<f64> {
        match self.phase {
            BnewtPhase::Inner => self.x.iter().zip(&self.p).map(|(x, p)| x * p).collect(),
            _ => self.x.clone(),
        }
    }

    /// Take the product asked for by [`Bnewt::request`] and advance to the next request.
    fn feed(&mut self, product: &[f64]) {
        self.n_products += 1;
        let rt = self.tol * self.tol;
        match self.phase {
            BnewtPhase::Start => {
                self.set_residual(product);
                self.rout = self.rho_km1;
                self.rold = self.rout;
                self.begin_outer(rt);
            }
            BnewtPhase::Inner => {
                let w: Vec<f64> = (0..self.x.len())
                    .map(|i| self.x[i] * product[i] + self.v[i] * self.p[i])
                    .collect();
                let pw: f64 = self.p.iter().zip(&w).map(|(p, w)| p * w).sum();
                let alpha = self.rho_km1 / pw;
                let ynew: Vec<f64> = self
                    .y
                    .iter()
                    .zip(&self.p)
                    .map(|(y, p)| y + alpha * p)
                    .collect();
                let min_ynew = ynew.iter().copied().fold(f64::MAX, f64::min);
                if min_ynew <= KR_DELTA {
                    // Step back to the boundary of the cone and end the inner iteration.
                    let mut gamma = f64::MAX;
                    for i in 0..self.p.len() {
                        let ap = alpha * self.p[i];
                        if ap < 0.0 {
                            gamma = gamma.min((KR_DELTA - self.y[i]) / ap);
                        }
                    }
                    for i in 0..self.y.len() {
                        self.y[i] += gamma * alpha * self.p[i];
                    }
                    self.end_inner();
                    return;
                }
                self.rho_km2 = self.rho_km1;
                self.y = ynew;
                let mut rho = 0.0;
                for (((rk, z), v), w) in self.rk.iter_mut().zip(&mut self.z).zip(&self.v).zip(&w) {
                    *rk -= alpha * w;
                    *z = *rk / v;
                    rho += *rk * *z;
                }
                self.rho_km1 = rho;
                self.inner_step();
            }
            BnewtPhase::Outer => {
                self.set_residual(product);
                if (self.rho_km1 - self.rout).abs() < 1e-6 || self.rho_km1.is_infinite() {
                    self.not_changing += 1;
                }
                self.rout = self.rho_km1;
                let rat = self.rout / self.rold;
                self.rold = self.rout;
                let r_norm = self.rout.sqrt();
                let eta_o = self.eta;
                self.eta = KR_G * rat;
                if KR_G * eta_o * eta_o > 0.1 {
                    self.eta = self.eta.max(KR_G * eta_o * eta_o);
                }
                self.eta = self.eta.min(KR_ETAMAX).max(0.5 * self.tol / r_norm);
                self.n_outer += 1;
                self.begin_outer(rt);
            }
            BnewtPhase::Converged | BnewtPhase::Failed => {}
        }
    }

    /// `v = x .* (A x)`, `rk = 1 - v`, `rho_km1 = rk . rk`.
    fn set_residual(&mut self, ax: &[f64]) {
        let mut rho = 0.0;
        for (((v, rk), x), ax) in self.v.iter_mut().zip(&mut self.rk).zip(&self.x).zip(ax) {
            *v = x * ax;
            *rk = 1.0 - *v;
            rho += *rk * *rk;
        }
        self.rho_km1 = rho;
    }

    fn begin_outer(&mut self, rt: f64) {
        // NaN residuals (a singular problem) count as not converging.
        if self.rout.partial_cmp(&rt) != Some(Ordering::Greater) {
            self.phase = if self.rout.is_nan() {
                BnewtPhase::Failed
            } else {
                BnewtPhase::Converged
            };
            return;
        }
        if self.not_changing >= 100 || self.n_outer >= self.max_outer {
            self.phase = BnewtPhase::Failed;
            return;
        }
        self.k = 0;
        self.y.iter_mut().for_each(|y| *y = 1.0);
        self.rho_km2 = self.rho_km1;
        self.innertol = (self.eta * self.eta * self.rout).max(rt);
        self.inner_step();
    }

    fn inner_step(&mut self) {
        if self.rho_km1.partial_cmp(&self.innertol) != Some(Ordering::Greater) {
            self.end_inner();
            return;
        }
        self.k += 1;
        if self.k == 1 {
            let mut rho = 0.0;
            for i in 0..self.z.len() {
                self.z[i] = self.rk[i] / self.v[i];
                rho += self.rk[i] * self.z[i];
            }
            self.rho_km1 = rho;
            self.p.copy_from_slice(&self.z);
        } else {
            let beta = self.rho_km1 / self.rho_km2;
            for i in 0..self.p.len() {
                self.p[i] = self.p[i] * beta + self.z[i];
            }
        }
        self.phase = BnewtPhase::Inner;
    }

    fn end_inner(&mut self) {
        for (x, y) in self.x.iter_mut().zip(&self.y) {
            *x *= y;
        }
        self.phase = BnewtPhase::Outer;
    }
}

/// Apache Commons Math's default (legacy) percentile, as Juicer uses it: position
/// `p (n + 1) / 100` in the sorted values, interpolated linearly.
pub(super) fn juicer_percentile(values: &mut [f64], percent: f64) -> f64 {
    let n = values.len();
    if n == 0 {
        return f64::NAN;
    }
    if n == 1 {
        return values[0];
    }
    values.sort_unstable_by(f64::total_cmp);
    let pos = percent * (n as f64 + 1.0) / 100.0;
    let floor = pos.floor();
    let dif = pos - floor;
    if pos < 1.0 {
        return values[0];
    }
    if pos >= n as f64 {
        return values[n - 1];
    }
    let lower = values[floor as usize - 1];
    let upper = values[floor as usize];
    lower + dif * (upper - lower)
}

/// One KR problem (the genome, or one chromosome) and Juicer's retry rules around it.
struct KrGroup {
    /// Bins of the group.
    range: std::ops::Range<usize>,
    /// Row sums of the group's matrix (0 for masked bins).
    sums: Vec<f64>,
    /// Rows in the current try (bin ids).
    rows: Vec<usize>,
    /// Try number, 1 to 6 (Juicer).
    attempt: usize,
    state: KrState,
    n_products: usize,
    residual: f64,
    params: BalanceParams,
}

enum KrState {
    Solving(Box<Bnewt>),
    /// A solution `x` (by row) waiting for its sum factor.
    Scaling(Vec<f64>),
    Done {
        weights: Vec<f64>,
        factor: f64,
        converged: bool,
    },
}

impl KrGroup {
    fn new(range: std::ops::Range<usize>, sums: Vec<f64>, params: &BalanceParams) -> Self {
        let mut group = KrGroup {
            range,
            sums,
            rows: Vec::new(),
            attempt: 1,
            state: KrState::Done {
                weights: Vec::new(),
                factor: f64::NAN,
                converged: true,
            },
            n_products: 0,
            residual: f64::NAN,
            params: params.clone(),
        };
        group.rows = group.rows_above(0.0);
        group.start(params);
        group
    }

    /// Juicer's `getOffset(percent)`: rows whose sum is above the percentile of positive sums.
    fn rows_above(&self, percent: f64) -> Vec<usize> {
        let threshold = if percent > 0.0 {
            let mut positive: Vec<f64> = self.sums.iter().copied().filter(|&s| s != 0.0).collect();
            juicer_percentile(&mut positive, percent)
        } else {
            0.0
        };
        self.range
            .clone()
            .filter(|&b| self.sums[b - self.range.start] > threshold)
            .collect()
    }

    fn start(&mut self, params: &BalanceParams) {
        if self.rows.is_empty() {
            // Nothing to balance: every bin masked (Juicer would give NaN too).
            self.state = KrState::Done {
                weights: vec![f64::NAN; self.range.len()],
                factor: f64::NAN,
                converged: true,
            };
            return;
        }
        self.state = KrState::Solving(Box::new(Bnewt::new(
            self.rows.len(),
            params.tol,
            params.max_iters,
        )));
    }

    /// Put the vector this group needs multiplied into `u` (genome-wide, zero elsewhere).
    fn request_product(&self, u: &mut [f64]) {
        match &self.state {
            KrState::Solving(solver) => {
                for (&b, value) in self.rows.iter().zip(solver.request()) {
                    u[b] = value;
                }
            }
            KrState::Scaling(x) => {
                for (&b, &value) in self.rows.iter().zip(x) {
                    u[b] = value;
                }
            }
            KrState::Done { .. } => {}
        }
    }

    fn finished(&self) -> bool {
        matches!(self.state, KrState::Done { .. })
    }

    /// Move to the next try, or give up after the sixth (all NaN, as Juicer).
    fn retry(&mut self, rows: Vec<usize>, params: &BalanceParams) {
        self.attempt += 1;
        if self.attempt > 6 {
            self.state = KrState::Done {
                weights: vec![f64::NAN; self.range.len()],
                factor: f64::NAN,
                converged: false,
            };
            return;
        }
        self.rows = rows;
        self.start(params);
    }

    fn take_product(&mut self, product: &Product, group: usize, params: &BalanceParams) {
        let state = std::mem::replace(
            &mut self.state,
            KrState::Done {
                weights: Vec::new(),
                factor: f64::NAN,
                converged: false,
            },
        );
        match state {
            KrState::Solving(mut solver) => {
                let local: Vec<f64> = self.rows.iter().map(|&b| product.au[b]).collect();
                solver.feed(&local);
                self.n_products += 1;
                if !solver.is_done() {
                    self.state = KrState::Solving(solver);
                    return;
                }
                self.residual = solver.rout;
                if solver.phase == BnewtPhase::Failed || self.attempt == 5 {
                    let percent = if self.attempt < 5 {
                        self.attempt as f64
                    } else {
                        10.0
                    };
                    let rows = self.rows_above(percent);
                    self.retry(rows, params);
                } else {
                    self.state = KrState::Scaling(solver.x);
                }
            }
            KrState::Scaling(x) => {
                self.n_products += 1;
                let factor = sum_factor(product.norm_sums[group], product.matrix_sums[group]);
                // Juicer: the divisive value 1 / x scaled by the factor must be at least 0.01.
                let keep: Vec<bool> = x.iter().map(|&xi| (1.0 / xi) * factor >= 0.01).collect();
                if keep.iter().all(|&k| k) {
                    let mut weights = vec![f64::NAN; self.range.len()];
                    for (&b, &xi) in self.rows.iter().zip(&x) {
                        weights[b - self.range.start] = xi / factor;
                    }
                    self.state = KrState::Done {
                        weights,
                        factor,
                        converged: true,
                    };
                } else {
                    let rows: Vec<usize> = self
                        .rows
                        .iter()
                        .zip(&keep)
                        .filter(|&(_, &k)| k)
                        .map(|(&b, _)| b)
                        .collect();
                    self.retry(rows, params);
                }
            }
            done @ KrState::Done { .. } => self.state = done,
        }
    }
}

impl ProductGroup for KrGroup {
    fn is_done(&self) -> bool {
        self.finished()
    }

    fn request(&self, u: &mut [f64]) {
        self.request_product(u);
    }

    fn feed(&mut self, product: &Product, group: usize) {
        let params = self.params.clone();
        self.take_product(product, group, &params);
    }
}

pub(super) fn kr<S: PixelSource>(
    source: &S,
    params: &BalanceParams,
    layout: &Layout,
    masked: &[bool],
) -> Result<BalanceResult> {
    let filter = scope_filter(params, layout);
    let sums = row_sums(source, layout, filter, masked)?;
    let ranges = layout.groups();
    let mut groups: Vec<KrGroup> = ranges
        .iter()
        .map(|r| KrGroup::new(r.clone(), sums[r.clone()].to_vec(), params))
        .collect();
    solve_groups(source, layout, filter, &mut groups)?;
    let mut weights = vec![f64::NAN; layout.n_bins];
    let mut stats = Vec::with_capacity(groups.len());
    for g in groups {
        let KrState::Done {
            weights: w,
            factor,
            converged,
        } = g.state
        else {
            unreachable!("every group is done");
        };
        weights[g.range.clone()].copy_from_slice(&w);
        stats.push(GroupStats {
            scale: factor,
            var: g.residual,
            converged,
            n_iterations: g.n_products,
        });
    }
    Ok(BalanceResult::from_groups(weights, params.scope, stats))
}
