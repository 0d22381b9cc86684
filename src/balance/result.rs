//! What balancing returns: the weights, with the convergence of each group (a chromosome or the genome).

use super::params::Scope;

/// Outcome of balancing one group of bins (the genome, or one chromosome with [`Scope::Cis`]).
#[derive(Clone, Debug, PartialEq)]
pub struct GroupStats {
    /// ICE: mean nonzero marginal of the last iteration (cooler's `scale`); VC / KR: Juicer's sum
    /// factor applied to the divisive vector. `NaN` when the group has no nonzero marginal.
    pub scale: f64,
    /// ICE: variance of the nonzero marginals at the last iteration (cooler's `var`); KR: final
    /// squared residual; VC: 0.
    pub var: f64,
    /// ICE: `var < tol` (as cooler); KR: a solution was found; VC: always.
    pub converged: bool,
    /// Iterations (ICE) or matrix-vector products (KR) spent on this group.
    pub n_iterations: usize,
}

/// Balancing weights and how they were reached.
#[derive(Clone, Debug, PartialEq)]
pub struct BalanceResult {
    /// One multiplicative weight per bin; `NaN` for masked bins.
    pub weights: Vec<f64>,
    /// True when every group converged.
    pub converged: bool,
    /// Genome-wide `scale` (see [`GroupStats::scale`]); `NaN` with [`Scope::Cis`] (see `per_chrom`).
    pub scale: f64,
    /// Genome-wide `var` (see [`GroupStats::var`]); `NaN` with [`Scope::Cis`].
    pub var: f64,
    /// Iterations of the longest group.
    pub n_iterations: usize,
    /// Per chromosome, in chromosome-table order: only with [`Scope::Cis`].
    pub per_chrom: Option<Vec<GroupStats>>,
}

impl BalanceResult {
    /// Number of masked (`NaN`) bins.
    pub fn n_masked(&self) -> usize {
        self.weights.iter().filter(|w| w.is_nan()).count()
    }

    pub(super) fn from_groups(weights: Vec<f64>, scope: Scope, groups: Vec<GroupStats>) -> Self {
        let converged = groups.iter().all(|g| g.converged);
        let n_iterations = groups.iter().map(|g| g.n_iterations).max().unwrap_or(0);
        if scope == Scope::Cis {
            BalanceResult {
                weights,
                converged,
                scale: f64::NAN,
                var: f64::NAN,
                n_iterations,
                per_chrom: Some(groups),
            }
        } else {
            let g = &groups[0];
            BalanceResult {
                weights,
                converged,
                scale: g.scale,
                var: g.var,
                n_iterations,
                per_chrom: None,
            }
        }
    }
}
