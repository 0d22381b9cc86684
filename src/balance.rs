//! Matrix balancing: ICE exactly as cooler 0.11 computes it, vanilla coverage (VC, VC_SQRT) and
//! Knight-Ruiz (KR) and SCALE as Juicer computes them.
//!
//! Every method returns weights in cooler's multiplicative convention
//! (`balanced[i, j] = count[i, j] * w[i] * w[j]`), with `NaN` for masked bins, and works on any
//! [`PixelSource`](crate::matrix::PixelSource): an in-memory copy of the pixels or a file streamed on every pass. Each
//! iteration is one parallel map-reduce pass over the pixels; partial results are combined in a
//! fixed order, so the weights do not depend on the number of threads.
//!
//! # ICE (iterative correction; Imakaev et al. 2012, *Nat. Methods* 9:999), as `cooler balance`
//!
//! The steps and defaults of `cooler.balance_cooler` (cooler 0.11):
//!
//! 1. pixels on the first `ignore_diags` diagonals (`|bin2 - bin1| < ignore_diags`, default 2) are
//!    left out of everything below; with [`Scope::Cis`], so are the trans pixels;
//! 2. bins with fewer than `min_nnz` (default 10) nonzero pixels in that matrix are masked;
//! 3. bins whose marginal (row sum, the diagonal counted once) is below `min_count` (default 0,
//!    off) are masked;
//! 4. the MAD-max filter (`mad_max`, default 5): the marginals of each chromosome are divided by the
//!    median of that chromosome's positive marginals; then, over the positive normalised marginals
//!    of the whole genome, bins whose marginal is below `exp(median(log m) - mad_max * MAD(log m))`
//!    are masked (MAD = median absolute deviation, unscaled, as `cooler.util.mad`). The marginals
//!    are those of all bins, including bins already masked by the steps above, as in cooler;
//! 5. blacklisted bins are masked;
//! 6. iterate: marginals `m` of the current balanced matrix; the nonzero ones have mean `s` and
//!    variance `var`; divide each bias by `m / s` (bins with `m == 0` keep their bias); stop when
//!    `var < tol` (default 1e-5) or after `max_iters` (default 200) iterations;
//! 7. masked bins (bias 0) become `NaN`; with `rescale_marginals` (default true) the weights are
//!    divided by `sqrt(scale)`, where `scale` is the `s` of the last iteration, so that the balanced
//!    rows sum to 1.
//!
//! [`Scope::Cis`] balances each chromosome on its own intra-chromosomal matrix (one `scale`,
//! `var`, `converged` per chromosome; a chromosome without any nonzero marginal gets `NaN`
//! weights, `var = 0` and `scale = NaN`, as in cooler). All chromosomes iterate within the same
//! passes; each stops on its own criterion. [`Scope::Trans`] balances on the inter-chromosomal
//! pixels only, weighting each bin's bias by `1 / (1 - n_c / n_bins)` (`n_c`: bins of its
//! chromosome) as cooler does. The filters (steps 2-4) use the matrix without the trans pixels
//! with [`Scope::Cis`] and the whole matrix otherwise, as in cooler.
//!
//! # VC and VC_SQRT (vanilla coverage; Rao et al. 2014), as Juicer
//!
//! The divisive vector is the row sum of the matrix (`VC`) or its square root (`VC_SQRT`), then
//! multiplied by Juicer's sum factor `sqrt(sum(count / (v_i v_j)) / sum(count))` (both sums over the
//! full symmetric matrix, over pixels whose two bins are valid), so that the balanced matrix sums
//! to the raw one. Bins with a zero row sum are masked. The multiplicative weight is `1 / v`.
//! Juicer's `VC` / `VC_SQRT` vectors (hic2cool's `VC`, `VC_SQRT` columns) are computed per
//! chromosome: [`Scope::Cis`] reproduces them; [`Scope::GenomeWide`] gives Juicer's `GW_VC`.
//!
//! # KR (Knight & Ruiz 2013, *IMA J. Numer. Anal.* 33:1029), as Juicer
//!
//! Juicer's `bnewt` (Newton's method with a conjugate-gradient inner iteration, `tol` 1e-6,
//! `delta` 0.1, start at ones) on the rows with a positive row sum, and Juicer's retry rules:
//! when the iteration stalls (or exceeds `max_iters` outer iterations) the rows below the 1st, 2nd,
//! 3rd, 4th percentile of the positive row sums are dropped in turn (the 10th at the fifth try);
//! after a solution, rows whose scaled divisive value is below 0.01 are dropped and the solution
//! recomputed; after six tries the vector is all `NaN` (not converged). The result is scaled by the
//! same sum factor as VC, so the balanced matrix sums to the raw one (Juicer's convention; the
//! balanced rows then all sum to the same value, `sum / n_valid`). `var` reports the final squared
//! residual `||x * (A x) - 1||^2`. [`Scope::Cis`] reproduces Juicer's per-chromosome `KR` vector;
//! [`Scope::GenomeWide`] Juicer's `GW_KR`.
//!
//! # SCALE, as Juicer
//!
//! Juicer's default normalisation, as the Juicer vectors that hic2cool copies were made: from the
//! square root of the scaled VC vector, an alternating row / column scaling until the vector
//! changes by less than 5e-4 and the balanced row sums (measured every tenth iteration) are within
//! 2.5e-3 of 1; stalled attempts leave out the rows with the fewest nonzero pixels and restart.
//! The divisive vector is scaled by the same sum factor as VC.
//! [`Scope::Cis`] reproduces Juicer's per-chromosome `SCALE` vector.
//!
//! The ICE filters also apply to VC, KR and SCALE when set; [`BalanceParams::juicer`] gives Juicer's
//! parameters (no filter at all, the diagonal included).

mod compact;
mod coverage;
mod ice;
mod kr;
mod mask;
mod params;
mod passes;
mod result;
mod run;
mod scale;
pub mod store;

pub use params::{BalanceParams, Method, Scope};
pub use result::{BalanceResult, GroupStats};
pub use run::balance;

#[cfg(test)]
// The naive references index dense matrices the way the formulas read.
#[allow(clippy::needless_range_loop)]
mod tests;
