//! The bins masked before balancing: cooler's filters.

use super::params::{BalanceParams, Scope};
use super::passes::{Keep, Layout, PixelFilter, marginals};
use crate::error::Result;
use crate::matrix::PixelSource;
use crate::numeric::median;

/// The bins masked before balancing: cooler's min_nnz, min_count, MAD-max and blacklist filters.
pub(super) fn prefilter<S: PixelSource>(
    source: &S,
    params: &BalanceParams,
    layout: &Layout,
) -> Result<Vec<bool>> {
    let n = layout.n_bins;
    let filter = PixelFilter {
        ignore_diags: params.ignore_diags.min(usize::MAX as u64) as usize,
        keep: if params.scope == Scope::Cis {
            Keep::Cis
        } else {
            Keep::All
        },
        chrom_end: &layout.chrom_end,
    };
    let mut masked = vec![false; n];
    let ones = vec![1.0; n];
    if params.min_nnz > 0 {
        let nnz = marginals(source, n, filter, &ones, true)?;
        for (m, &k) in masked.iter_mut().zip(&nnz) {
            if k < params.min_nnz as f64 {
                *m = true;
            }
        }
    }
    if params.min_count != 0.0 || params.mad_max > 0.0 {
        let mut marg = marginals(source, n, filter, &ones, false)?;
        if params.min_count != 0.0 {
            for (m, &s) in masked.iter_mut().zip(&marg) {
                if s < params.min_count {
                    *m = true;
                }
            }
        }
        if params.mad_max > 0.0 {
            for w in layout.chrom_offsets.windows(2) {
                let chrom = &mut marg[w[0]..w[1]];
                let mut positive: Vec<f64> = chrom.iter().copied().filter(|&m| m > 0.0).collect();
                let med = median(&mut positive);
                chrom.iter_mut().for_each(|m| *m /= med);
            }
            let mut logs: Vec<f64> = marg.iter().filter(|&&m| m > 0.0).map(|m| m.ln()).collect();
            let med = median(&mut logs);
            let mut deviations: Vec<f64> = logs.iter().map(|l| (l - med).abs()).collect();
            let mad = median(&mut deviations);
            let cutoff = (med - params.mad_max * mad).exp();
            for (m, &s) in masked.iter_mut().zip(&marg) {
                if s < cutoff {
                    *m = true;
                }
            }
        }
    }
    for &b in &params.blacklist {
        masked[b] = true;
    }
    Ok(masked)
}
