//! ICE, as cooler balances: iterative correction of the marginals to their mean.

use super::compact::CompactRows;
use super::params::{BalanceParams, Scope};
use super::passes::{Layout, marginals, scope_filter};
use super::result::{BalanceResult, GroupStats};
use crate::error::Result;
use crate::matrix::PixelSource;

/// Mean and population variance (numpy's `mean`, `var`) of the nonzero values.
pub(super) fn nonzero_mean_var(values: &[f64]) -> Option<(f64, f64)> {
    let (mut n, mut sum) = (0usize, 0.0);
    for &v in values.iter().filter(|&&v| v != 0.0) {
        n += 1;
        sum += v;
    }
    if n == 0 {
        return None;
    }
    let mean = sum / n as f64;
    let var = values
        .iter()
        .filter(|&&v| v != 0.0)
        .map(|&v| (v - mean) * (v - mean))
        .sum::<f64>()
        / n as f64;
    Some((mean, var))
}

pub(super) fn ice<S: PixelSource>(
    source: &S,
    params: &BalanceParams,
    layout: &Layout,
    masked: Vec<bool>,
) -> Result<BalanceResult> {
    let n = layout.n_bins;
    let mut bias: Vec<f64> = masked.iter().map(|&m| if m { 0.0 } else { 1.0 }).collect();
    // Trans-only: cooler weights each bin by 1 / (1 - n_chrom / n_bins).
    let chrom_weights: Option<Vec<f64>> = (params.scope == Scope::Trans).then(|| {
        (0..n)
            .map(|b| {
                let c = layout.chrom_of[b] as usize;
                let n_c = layout.chrom_offsets[c + 1] - layout.chrom_offsets[c];
                1.0 / (1.0 - n_c as f64 / n as f64)
            })
            .collect()
    });
    let filter = scope_filter(params, layout);
    // pixels held in memory: iterate over a compact copy of the accepted ones
    let compact = source
        .in_memory()
        .map(|all| CompactRows::new(all, n, filter));
    let groups = layout.groups();
    let mut stats: Vec<GroupStats> = groups
        .iter()
        .map(|_| GroupStats {
            scale: f64::NAN,
            var: f64::NAN,
            converged: false,
            n_iterations: 0,
        })
        .collect();
    let mut active: Vec<bool> = vec![true; groups.len()];
    while active.iter().any(|&a| a) {
        crate::interrupt::check()?;
        let mut vector: Vec<f64> = match &chrom_weights {
            Some(cw) => bias.iter().zip(cw).map(|(b, w)| b * w).collect(),
            None => bias.clone(),
        };
        // Groups that are done (cis: their chromosome's pixels only) need no more sums.
        for (range, _) in groups.iter().zip(&active).filter(|&(_, &a)| !a) {
            vector[range.clone()].iter_mut().for_each(|v| *v = 0.0);
        }
        let marg = match &compact {
            Some(rows) => rows.marginals(&vector),
            None => marginals(source, n, filter, &vector, false)?,
        };
        for (g, range) in groups.iter().enumerate() {
            if !active[g] {
                continue;
            }
            let stat = &mut stats[g];
            stat.n_iterations += 1;
            let m = &marg[range.clone()];
            let Some((mean, var)) = nonzero_mean_var(m) else {
                // cooler: no nonzero marginal at all -> NaN weights, var 0, scale NaN.
                bias[range.clone()].iter_mut().for_each(|b| *b = f64::NAN);
                stat.var = 0.0;
                stat.scale = f64::NAN;
                stat.converged = true;
                active[g] = false;
                continue;
            };
            for (b, &mi) in bias[range.clone()].iter_mut().zip(m) {
                let normalised = mi / mean;
                *b /= if normalised == 0.0 { 1.0 } else { normalised };
            }
            stat.var = var;
            stat.scale = mean;
            stat.converged = var < params.tol;
            if stat.converged || stat.n_iterations >= params.max_iters {
                active[g] = false;
            }
        }
    }
    for (range, stat) in groups.iter().zip(&stats) {
        for b in &mut bias[range.clone()] {
            if *b == 0.0 {
                *b = f64::NAN;
            }
            if params.rescale_marginals {
                *b /= stat.scale.sqrt();
            }
        }
    }
    Ok(BalanceResult::from_groups(bias, params.scope, stats))
}
