//! VC and VC_SQRT, as Juicer computes them: the inverse of each row's sum (or of its square root).

use super::params::BalanceParams;
use super::passes::{Layout, product, row_sums, scope_filter, sum_factor};
use super::result::{BalanceResult, GroupStats};
use crate::error::Result;
use crate::matrix::PixelSource;

pub(super) fn coverage<S: PixelSource>(
    source: &S,
    params: &BalanceParams,
    layout: &Layout,
    masked: &[bool],
    square_root: bool,
) -> Result<BalanceResult> {
    let filter = scope_filter(params, layout);
    let sums = row_sums(source, layout, filter, masked)?;
    // Multiplicative weights before scaling: 1 / v, v = row sum (or its square root).
    let inverse: Vec<f64> = sums
        .iter()
        .map(|&s| {
            if s > 0.0 {
                1.0 / if square_root { s.sqrt() } else { s }
            } else {
                0.0
            }
        })
        .collect();
    let groups = layout.groups();
    let totals = product(source, layout, filter, &inverse)?;
    let mut weights = vec![f64::NAN; layout.n_bins];
    let mut stats = Vec::with_capacity(groups.len());
    for (g, range) in groups.iter().enumerate() {
        let factor = sum_factor(totals.norm_sums[g], totals.matrix_sums[g]);
        for b in range.clone() {
            if inverse[b] > 0.0 {
                weights[b] = inverse[b] / factor;
            }
        }
        stats.push(GroupStats {
            scale: factor,
            var: 0.0,
            converged: true,
            n_iterations: 0,
        });
    }
    Ok(BalanceResult::from_groups(weights, params.scope, stats))
}
