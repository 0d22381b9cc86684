//! SCALE, as Juicer computes the `SCALE` vectors it stores (juicer_tools' matrix-balancing
//! iteration of Rao et al.; the variant whose vectors hic2cool copies into `.mcool` files), one
//! state machine per group so that all chromosomes share the passes over the pixels, as KR does.
//!
//! Rows: those with fewer nonzero pixels than `low` are left out (target row sum 0); `low` is the
//! nonzero-pixel count at the fraction `p` of the nonzero rows sorted by count (index
//! `floor(n0 * p + 0.5)`), `p` starting at 1e-4 (so only empty rows on all but very large
//! matrices). The start is the square root of Juicer's scaled VC vector `v0`, and the row sums
//! of the start `(A 1) * v0`.
//!
//! Each iteration is an alternating row / column scaling: `dr *= target / row`, `col = (A dr) *
//! dc`, `dc *= target / col`, `row = (A dc) * dr`; the estimate is `b = sqrt(dr * dc)` and its
//! change `ber = max |b - b_prev|` over the rows in use. Every tenth iteration the balanced row
//! sums are measured (one more product): `err = max |(A b) * b - target|`. The iteration goes on
//! while `ber > tol` (5e-4) or `err > 5 tol`, for at most 100 iterations per try (`max_iters`)
//! and three times as many in all.
//! After five iterations, a try fails when none of the last five changes fell by 2% from the one
//! before, when the row-sum error fell by less than a quarter between its last two measures, or
//! at 100 iterations (unless `ber < tol` and the row-sum error halved); then `p` grows by 5e-5,
//! the rows under the new `low` are left out, and the iteration restarts from `dr = dc = 1` when
//! the change grew over the last five iterations, else goes on from where it is. It also stops
//! when `p` passes 0.2.
//!
//! The vector is the last estimate whatever the stop (Juicer stores it), with `NaN` on the rows
//! left out; [`GroupStats::converged`] says whether `ber <= tol` and `err <= 5 tol` at the end.
//! The divisive vector is `1 / b` times Juicer's sum factor, so that the balanced matrix sums to
//! the raw one; the multiplicative weight is its inverse. All arithmetic is in `f64`, as Juicer's
//! (the fraction `p` in `f32`, as Juicer's).

use super::params::BalanceParams;
use super::passes::{Layout, PixelFilter, Product, ProductGroup, solve_groups, sum_factor};
use super::result::GroupStats;
use crate::error::Result;
use crate::matrix::PixelSource;

/// Starting fraction of the nonzero rows (by nonzero-pixel count) left out.
const PERCENT_LOW_START: f32 = 1e-4;
/// Its increase after a failed try.
const PERCENT_LOW_STEP: f32 = PERCENT_LOW_START / 2.0;
/// The largest fraction left out before giving up.
const PERCENT_LOW_MAX: f64 = 0.2;
/// Least relative fall of the change in one of the last five iterations.
const MIN_ERROR_DROP: f64 = 0.02;

/// What the group's next product is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Step {
    /// `A 1`: the row sums.
    RowSums,
    /// `A (1 / r)`: Juicer's VC sum factor, from the product's sums.
    VcFactor,
    /// `A dr`: the column half of an iteration.
    Column,
    /// `A dc`: the row half of an iteration.
    Row,
    /// `A b`: the row-sum error of every tenth iteration.
    RowSumError,
    /// `A b`: the sum factor of the result.
    Final,
    /// Finished.
    Done,
}

/// One group (a chromosome, or the genome) being balanced.
pub(super) struct ScaleGroup {
    range: std::ops::Range<usize>,
    nnz: Vec<u64>,
    /// Nonzero-pixel counts of the nonzero rows, sorted.
    sorted_nnz: Vec<u64>,
    percent_low: f32,
    target: Vec<f64>,
    bad: Vec<bool>,
    row_sums: Vec<f64>,
    current: Vec<f64>,
    b: Vec<f64>,
    dr: Vec<f64>,
    dc: Vec<f64>,
    row: Vec<f64>,
    step: Step,
    ber: f64,
    err: f64,
    /// The change of every iteration, all tries together.
    changes: Vec<f64>,
    /// The row-sum errors of this try.
    row_errors: Vec<f64>,
    iter: usize,
    total_iter: usize,
    tol: f64,
    max_iters: usize,
    /// The outcome: multiplicative weights (NaN where left out), sum factor, converged.
    result: Option<(Vec<f64>, f64, bool)>,
}

impl ScaleGroup {
    /// A group over `range` whose rows have `nnz` nonzero pixels.
    pub(super) fn new(
        range: std::ops::Range<usize>,
        nnz: Vec<u64>,
        params: &BalanceParams,
    ) -> Self {
        let n = range.len();
        let mut sorted_nnz: Vec<u64> = nnz.iter().copied().filter(|&k| k > 0).collect();
        sorted_nnz.sort_unstable();
        let mut group = ScaleGroup {
            range,
            nnz,
            sorted_nnz,
            percent_low: PERCENT_LOW_START,
            target: vec![1.0; n],
            bad: vec![false; n],
            row_sums: vec![0.0; n],
            current: vec![0.0; n],
            b: vec![0.0; n],
            dr: vec![0.0; n],
            dc: vec![0.0; n],
            row: vec![0.0; n],
            step: Step::RowSums,
            ber: 10.0 * (1.0 + params.tol),
            err: 10.0 * (1.0 + params.tol),
            changes: Vec::new(),
            row_errors: Vec::new(),
            iter: 0,
            total_iter: 0,
            tol: params.tol,
            max_iters: params.max_iters,
            result: None,
        };
        if group.sorted_nnz.is_empty() {
            group.result = Some((vec![f64::NAN; n], f64::NAN, true));
            group.step = Step::Done;
        } else {
            let low = group.low();
            for i in 0..n {
                if group.nnz[i] < low {
                    group.bad[i] = true;
                    group.target[i] = 0.0;
                }
            }
        }
        group
    }

    /// The least nonzero-pixel count of a row in use, at the current fraction.
    fn low(&self) -> u64 {
        let n0 = self.sorted_nnz.len();
        // Juicer: (int) Math.max(0, n0 * percent + 0.5f), in float.
        let index = (n0 as f32 * self.percent_low + 0.5).max(0.0) as usize;
        self.sorted_nnz[index.min(n0 - 1)]
    }

    /// Put the vector this group needs multiplied into `u` (genome-wide, zero elsewhere).
    fn request_product(&self, u: &mut [f64]) {
        let target = &mut u[self.range.clone()];
        match self.step {
            Step::RowSums => target.fill(1.0),
            Step::VcFactor => {
                for (t, &r) in target.iter_mut().zip(&self.row_sums) {
                    *t = if r > 0.0 { 1.0 / r } else { 0.0 };
                }
            }
            Step::Column => target.copy_from_slice(&self.dr),
            Step::Row => target.copy_from_slice(&self.dc),
            Step::RowSumError => target.copy_from_slice(&self.b),
            Step::Final => {
                for ((t, &b), &bad) in target.iter_mut().zip(&self.b).zip(&self.bad) {
                    *t = if bad { 0.0 } else { b };
                }
            }
            Step::Done => {}
        }
    }

    /// `d *= target / sums`, the sums of rows left out taken as 1.
    fn rescale(d: &mut [f64], sums: &mut [f64], bad: &[bool], target: &[f64]) {
        for i in 0..d.len() {
            if bad[i] {
                sums[i] = 1.0;
            }
            d[i] *= target[i] / sums[i];
        }
    }

    /// The loop condition, checked before each iteration.
    fn keep_iterating(&self) -> bool {
        (self.ber > self.tol || self.err > 5.0 * self.tol)
            && self.iter < self.max_iters
            && self.total_iter < 3 * self.max_iters
            && f64::from(self.percent_low) <= PERCENT_LOW_MAX
    }

    /// Start the next iteration (the `A dr` product), or finish.
    fn next_iteration(&mut self) {
        if !self.keep_iterating() {
            self.step = Step::Final;
            return;
        }
        self.iter += 1;
        self.total_iter += 1;
        let mut row = std::mem::take(&mut self.row);
        Self::rescale(&mut self.dr, &mut row, &self.bad, &self.target);
        self.row = row;
        self.step = Step::Column;
    }

    fn take_product(&mut self, product: &Product, group: usize) {
        let au = &product.au[self.range.clone()];
        match self.step {
            Step::RowSums => {
                self.row_sums.copy_from_slice(au);
                self.step = Step::VcFactor;
            }
            Step::VcFactor => {
                let factor = sum_factor(product.norm_sums[group], product.matrix_sums[group]);
                // The start: sqrt of Juicer's scaled VC vector; row = (A 1) .* start.
                for i in 0..self.current.len() {
                    let vc = self.row_sums[i] * factor;
                    self.current[i] = if vc.is_nan() { 1.0 } else { vc.sqrt() };
                    self.row[i] = self.row_sums[i] * self.current[i];
                }
                self.dr = self.current.clone();
                self.dc = self.current.clone();
                self.next_iteration();
            }
            Step::Column => {
                let mut column: Vec<f64> = au.iter().zip(&self.dc).map(|(a, d)| a * d).collect();
                Self::rescale(&mut self.dc, &mut column, &self.bad, &self.target);
                self.step = Step::Row;
            }
            Step::Row => {
                for ((row, &a), &dr) in self.row.iter_mut().zip(au).zip(&self.dr) {
                    *row = a * dr;
                }
                for ((b, &dr), &dc) in self.b.iter_mut().zip(&self.dr).zip(&self.dc) {
                    *b = (dr * dc).sqrt();
                }
                self.ber = max_over_rows(&self.bad, self.b.iter().zip(&self.current), |(b, c)| {
                    (b - c).abs()
                });
                self.changes.push(self.ber);
                if self.iter.is_multiple_of(10) {
                    self.step = Step::RowSumError;
                } else {
                    self.end_iteration();
                }
            }
            Step::RowSumError => {
                let rows = au.iter().zip(&self.b).zip(&self.target);
                let err = max_over_rows(&self.bad, rows, |((a, b), t)| (a * b - t).abs());
                self.err = err;
                self.row_errors.push(err);
                self.end_iteration();
            }
            Step::Final => self.finish(product, group),
            Step::Done => {}
        }
    }

    /// The checks that close an iteration.
    fn end_iteration(&mut self) {
        self.current.copy_from_slice(&self.b);
        let n_err = self.row_errors.len();
        let halved = n_err < 2 || self.row_errors[n_err - 1] < 0.5 * self.row_errors[n_err - 2];
        if self.ber < self.tol && halved {
            return self.next_iteration();
        }
        if self.iter > 5 {
            let changes = &self.changes;
            let last = changes.len();
            let falling =
                (1..=5).any(|q| changes[last - q] * (1.0 + MIN_ERROR_DROP) < changes[last - q - 1]);
            let mut failed = !falling;
            if n_err >= 2 && self.row_errors[n_err - 1] > 0.75 * self.row_errors[n_err - 2] {
                failed = true;
            }
            if self.iter >= self.max_iters {
                failed = true;
            }
            if failed {
                self.leave_out_more_rows();
            }
        }
        self.next_iteration();
    }

    /// A failed try: leave out the rows under the next fraction, and restart or go on.
    fn leave_out_more_rows(&mut self) {
        self.percent_low += PERCENT_LOW_STEP;
        self.row_errors.clear();
        let low = self.low();
        for i in 0..self.bad.len() {
            if self.nnz[i] < low && self.target[i] > 0.0 {
                self.bad[i] = true;
                self.target[i] = 0.0;
            }
        }
        self.ber = 10.0 * (1.0 + self.tol);
        self.err = self.ber;
        let last = self.changes.len();
        if self.changes[last - 1] > self.changes[last - 6] {
            // Worse than five iterations ago: start again from scratch.
            for i in 0..self.dr.len() {
                self.dr[i] = if self.bad[i] { 0.0 } else { 1.0 };
            }
            self.dc = self.dr.clone();
            self.current = self.dr.clone();
            self.row = self.row_sums.clone();
        } else {
            for i in 0..self.dr.len() {
                if self.bad[i] {
                    self.dr[i] = 0.0;
                    self.dc[i] = 0.0;
                }
            }
        }
        self.iter = 0;
    }

    fn finish(&mut self, product: &Product, group: usize) {
        let converged = self.ber <= self.tol && self.err <= 5.0 * self.tol;
        let factor = sum_factor(product.norm_sums[group], product.matrix_sums[group]);
        let weights = (0..self.range.len())
            .map(|i| {
                if self.bad[i] {
                    f64::NAN
                } else {
                    self.b[i] / factor
                }
            })
            .collect();
        self.result = Some((weights, factor, converged));
        self.step = Step::Done;
    }

    /// The weights, sum factor, convergence and products spent.
    pub(super) fn into_result(self) -> (std::ops::Range<usize>, Vec<f64>, GroupStats) {
        let (weights, factor, converged) = self.result.expect("the group is done");
        (
            self.range,
            weights,
            GroupStats {
                scale: factor,
                var: self.ber,
                converged,
                n_iterations: self.total_iter,
            },
        )
    }
}

impl ProductGroup for ScaleGroup {
    fn is_done(&self) -> bool {
        self.step == Step::Done
    }

    fn request(&self, u: &mut [f64]) {
        self.request_product(u);
    }

    fn feed(&mut self, product: &Product, group: usize) {
        self.take_product(product, group);
    }
}

/// The largest `f(item)` over the rows in use (0 when there is none).
fn max_over_rows<T>(bad: &[bool], items: impl Iterator<Item = T>, f: impl Fn(T) -> f64) -> f64 {
    items
        .zip(bad)
        .filter(|&(_, &bad)| !bad)
        .map(|(item, _)| f(item))
        .fold(0.0, f64::max)
}

/// Balance every group with SCALE, all groups sharing each pass over the pixels.
pub(super) fn scale<S: PixelSource>(
    source: &S,
    params: &BalanceParams,
    layout: &Layout,
    filter: PixelFilter<'_>,
    nnz: &[f64],
) -> Result<(Vec<f64>, Vec<GroupStats>)> {
    let mut groups: Vec<ScaleGroup> = layout
        .groups()
        .into_iter()
        .map(|r| {
            let counts = nnz[r.clone()].iter().map(|&k| k as u64).collect();
            ScaleGroup::new(r, counts, params)
        })
        .collect();
    solve_groups(source, layout, filter, &mut groups)?;
    let mut weights = vec![f64::NAN; layout.n_bins];
    let mut stats = Vec::with_capacity(groups.len());
    for g in groups {
        let (range, w, s) = g.into_result();
        weights[range].copy_from_slice(&w);
        stats.push(s);
    }
    Ok((weights, stats))
}
