//! Balancing a map: the checks, the filters, then the method asked for.

use super::coverage::coverage;
use super::ice::ice;
use super::mask::prefilter;
use super::params::{BalanceParams, Method};
use super::passes::{Layout, marginals, scope_filter};
use super::result::BalanceResult;
use super::{kr, scale};
use crate::error::Result;
use crate::matrix::PixelSource;

/// Balance the matrix behind `source` with `params`.
///
/// One pass over the pixels per ICE iteration or KR matrix-vector product, plus one or two for the
/// filters. Fails only on bad parameters or when the source fails to produce its pixels.
///
/// # Examples
///
/// What each method promises, on a small matrix: ICE makes the balanced rows (without the
/// ignored diagonals) sum to 1; KR makes them all equal, the balanced matrix summing to the raw
/// one (Juicer's scale). The mm9 cooler's stored `weight` is what ICE gives with cooler's
/// defaults (see the [crate documentation](crate#balance)).
///
/// ```
/// use contactmap::balance::{balance, BalanceParams, Method};
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 1_000)], 100)?;
/// let mut builder = MatrixBuilder::new(bins, CountType::Integer);
/// for i in 0..10u64 {
///     for j in i..10 {
///         builder.push(i, j, (1 + (7 * i + 3 * j) % 5) as f64 * 10.0)?;
///     }
/// }
/// let matrix = InMemory::new("example".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// // balanced row sums over the full symmetric matrix, leaving out |i - j| < skip
/// let rows = |w: &[f64], skip: usize| -> Vec<f64> {
///     (0..10)
///         .map(|i| {
///             (0..10)
///                 .filter(|&j| i.max(j) - i.min(j) >= skip)
///                 .map(|j| matrix.matrix().get(i, j) * w[i] * w[j])
///                 .sum()
///         })
///         .collect()
/// };
///
/// let ice_params = BalanceParams {
///     min_nnz: 0,
///     mad_max: 0.0,
///     tol: 1e-12,
///     max_iters: 1_000,
///     ..BalanceParams::default()
/// };
/// let ice = balance(&pixels, &ice_params)?;
/// assert!(ice.converged && ice.n_masked() == 0);
/// assert!(rows(&ice.weights, 2).iter().all(|s| (s - 1.0).abs() < 1e-4));
///
/// let kr = balance(&pixels, &BalanceParams::juicer(Method::Kr))?;
/// assert!(kr.converged);
/// let sums = rows(&kr.weights, 0);
/// let raw: f64 = rows(&[1.0; 10], 0).iter().sum();
/// assert!(sums.iter().all(|s| (s - raw / 10.0).abs() < 1e-4 * raw));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn balance(source: &impl PixelSource, params: &BalanceParams) -> Result<BalanceResult> {
    params.check()?;
    let bins = source.bins();
    params.check_bins(bins)?;
    let layout = Layout::new(bins, params.scope);
    let masked = prefilter(source, params, &layout)?;
    match params.method {
        Method::Ice => ice(source, params, &layout, masked),
        Method::Vc => coverage(source, params, &layout, &masked, false),
        Method::VcSqrt => coverage(source, params, &layout, &masked, true),
        Method::Kr => kr::kr(source, params, &layout, &masked),
        Method::Scale => {
            let filter = scope_filter(params, &layout);
            let rows: Vec<f64> = masked.iter().map(|&m| f64::from(u8::from(!m))).collect();
            let nnz = marginals(source, layout.n_bins, filter, &rows, true)?;
            let (weights, stats) = scale::scale(source, params, &layout, filter, &nnz)?;
            Ok(BalanceResult::from_groups(weights, params.scope, stats))
        }
    }
}
