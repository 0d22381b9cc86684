//! Matrix balancing: ICE exactly as cooler 0.11 computes it, vanilla coverage (VC, VC_SQRT) and
//! Knight-Ruiz (KR) and SCALE as Juicer computes them.
//!
//! Every method returns weights in cooler's multiplicative convention
//! (`balanced[i, j] = count[i, j] * w[i] * w[j]`), with `NaN` for masked bins, and works on any
//! [`PixelSource`]: an in-memory copy of the pixels or a file streamed on every pass. Each
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

mod kr;
mod scale;
pub mod store;

use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::matrix::{PixelSlice, PixelSource};
use crate::numeric::median;

/// Balancing method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Iterative correction, as cooler.
    Ice,
    /// Vanilla coverage: weights `1 / row sum`, scaled as Juicer.
    Vc,
    /// Square root of vanilla coverage: weights `1 / sqrt(row sum)`, scaled as Juicer.
    VcSqrt,
    /// Knight-Ruiz, as Juicer.
    Kr,
    /// SCALE, Juicer's default normalisation.
    Scale,
}

impl Method {
    /// The name used on the command line and in attributes (`ice`, `vc`, `vc-sqrt`, `kr`).
    pub fn name(self) -> &'static str {
        match self {
            Method::Ice => "ice",
            Method::Vc => "vc",
            Method::VcSqrt => "vc-sqrt",
            Method::Kr => "kr",
            Method::Scale => "scale",
        }
    }

    /// Juicer's name of the method, as a `.hic` stores its vectors (`VC`, `VC_SQRT`, `KR`,
    /// `SCALE`; `ICE` for ours).
    pub fn juicer_name(self) -> &'static str {
        match self {
            Method::Ice => "ICE",
            Method::Vc => "VC",
            Method::VcSqrt => "VC_SQRT",
            Method::Kr => "KR",
            Method::Scale => "SCALE",
        }
    }

    /// The method a Juicer name stands for (case-insensitive, `-` for `_`): `VC`, `VC_SQRT`,
    /// `KR`, `SCALE` or `ICE`.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::balance::Method;
    ///
    /// assert_eq!(Method::from_juicer_name("vc-sqrt"), Some(Method::VcSqrt));
    /// assert_eq!(Method::from_juicer_name("KR").map(Method::juicer_name), Some("KR"));
    /// assert_eq!(Method::from_juicer_name("NONE"), None);
    /// ```
    pub fn from_juicer_name(name: &str) -> Option<Method> {
        let name = name.trim().to_ascii_uppercase().replace('-', "_");
        [
            Method::Ice,
            Method::Vc,
            Method::VcSqrt,
            Method::Kr,
            Method::Scale,
        ]
        .into_iter()
        .find(|m| m.juicer_name() == name)
    }
}

/// Which pixels the balancing works on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scope {
    /// The whole genome-wide matrix (cooler's default; Juicer's GW_ vectors).
    GenomeWide,
    /// Each chromosome on its own intra-chromosomal pixels (cooler `--cis-only`; Juicer's
    /// per-chromosome vectors).
    Cis,
    /// Inter-chromosomal pixels only (cooler `--trans-only`).
    Trans,
}

impl Scope {
    /// `genome-wide`, `cis-only` or `trans-only`.
    pub fn name(self) -> &'static str {
        match self {
            Scope::GenomeWide => "genome-wide",
            Scope::Cis => "cis-only",
            Scope::Trans => "trans-only",
        }
    }
}

/// Balancing parameters. [`Default`] gives `cooler balance`'s defaults (ICE).
#[derive(Clone, Debug, PartialEq)]
pub struct BalanceParams {
    /// The method.
    pub method: Method,
    /// Which pixels to balance on.
    pub scope: Scope,
    /// Leave out pixels with `bin2 - bin1 < ignore_diags` (0: none; 1: the main diagonal; 2: the
    /// main diagonal and its neighbours). cooler default 2.
    pub ignore_diags: u64,
    /// MAD-max filter: mask bins whose log marginal is more than `mad_max` median absolute
    /// deviations below the median (0: off). cooler default 5.
    pub mad_max: f64,
    /// Mask bins with fewer nonzero pixels than this (0: off). cooler default 10.
    pub min_nnz: u64,
    /// Mask bins whose marginal count is below this (0: off). cooler default 0.
    pub min_count: f64,
    /// Bins to mask (ids into the bin table).
    pub blacklist: Vec<usize>,
    /// Convergence tolerance: ICE stops when the variance of the nonzero marginals falls below it
    /// (cooler default 1e-5); KR when the squared residual falls below `tol^2` (Juicer: 1e-6).
    pub tol: f64,
    /// Iteration limit: ICE iterations (cooler default 200); KR outer Newton iterations per try.
    pub max_iters: usize,
    /// ICE: divide the weights by `sqrt(scale)` so that balanced rows sum to 1 (cooler default).
    pub rescale_marginals: bool,
}

impl BalanceParams {
    /// Check the values: `tol` a positive number, `max_iters` at least 1, `mad_max` a number
    /// `>= 0`, `min_count` a finite number. [`balance`] checks them first.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::balance::BalanceParams;
    ///
    /// assert!(BalanceParams::default().check().is_ok());
    /// let bad = BalanceParams { tol: 0.0, ..BalanceParams::default() };
    /// assert_eq!(bad.check().unwrap_err().to_string(), "tol 0: expected a positive number");
    /// ```
    pub fn check(&self) -> Result<()> {
        if !(self.tol.is_finite() && self.tol > 0.0) {
            return Err(Error::parameter(
                "tol",
                self.tol,
                "expected a positive number",
            ));
        }
        if self.max_iters == 0 {
            return Err(Error::parameter("max_iters", 0, "expected at least 1"));
        }
        if !(self.mad_max.is_finite() && self.mad_max >= 0.0) {
            return Err(Error::parameter(
                "mad_max",
                self.mad_max,
                "expected a number >= 0 (0: no MAD filter)",
            ));
        }
        if !self.min_count.is_finite() {
            return Err(Error::parameter(
                "min_count",
                self.min_count,
                "expected a finite number",
            ));
        }
        Ok(())
    }
}

impl Default for BalanceParams {
    fn default() -> Self {
        BalanceParams {
            method: Method::Ice,
            scope: Scope::GenomeWide,
            ignore_diags: 2,
            mad_max: 5.0,
            min_nnz: 10,
            min_count: 0.0,
            blacklist: Vec::new(),
            tol: 1e-5,
            max_iters: 200,
            rescale_marginals: true,
        }
    }
}

impl BalanceParams {
    /// Parameters for `method` with its reference tool's defaults: cooler's for ICE, Juicer's for
    /// VC, VC_SQRT, KR and SCALE (no filter, diagonal included, KR tolerance 1e-6, SCALE 5e-4
    /// with 100 iterations per try).
    pub fn for_method(method: Method) -> Self {
        match method {
            Method::Ice => BalanceParams::default(),
            _ => BalanceParams::juicer(method),
        }
    }

    /// Juicer's parameters for `method`: no filter, diagonal included, KR tolerance 1e-6, SCALE
    /// tolerance 5e-4 and 100 iterations per try.
    ///
    /// # Examples
    ///
    /// Juicer's per-chromosome VC vector of the dm6 map, as hic2cool stored it in the `.mcool`:
    ///
    /// ```
    /// use contactmap::balance::{balance, BalanceParams, Method, Scope};
    /// use contactmap::io::{load_pixels_for_balancing, open_matrix, MatrixReader, OpenOptions};
    ///
    /// let uri = "data/cooler_test_file.mcool::/resolutions/100000";
    /// let reader = open_matrix(uri, &OpenOptions::default())?;
    /// let pixels = load_pixels_for_balancing(&*reader, u64::MAX)?;
    /// let params = BalanceParams { scope: Scope::Cis, ..BalanceParams::juicer(Method::Vc) };
    /// assert_eq!(params, BalanceParams { scope: Scope::Cis, ..BalanceParams::for_method(Method::Vc) });
    /// let vc = balance(&pixels, &params)?;
    /// let juicer = reader.weights("VC")?; // divisive in the file, inverted on read
    /// for (ours, theirs) in vc.weights.iter().zip(&juicer.values) {
    ///     assert_eq!(ours.is_nan(), theirs.is_nan());
    ///     assert!(ours.is_nan() || (ours - theirs).abs() <= 1e-9 * theirs.abs());
    /// }
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn juicer(method: Method) -> Self {
        BalanceParams {
            method,
            ignore_diags: 0,
            mad_max: 0.0,
            min_nnz: 0,
            min_count: 0.0,
            tol: match method {
                Method::Kr => 1e-6,
                Method::Scale => scale::SCALE_TOL,
                _ => 1e-5,
            },
            max_iters: match method {
                Method::Scale => scale::SCALE_MAX_ITERS,
                _ => 200,
            },
            ..BalanceParams::default()
        }
    }

    /// The checks that need the bins: blacklisted bins in range, 32-bit bin ids.
    fn check_bins(&self, bins: &BinTable) -> Result<()> {
        if let Some(&bad) = self.blacklist.iter().find(|&&b| b >= bins.n_bins()) {
            return Err(Error::Invalid(format!(
                "blacklisted bin {bad} is out of range ({} bins)",
                bins.n_bins()
            )));
        }
        if bins.n_bins() > u32::MAX as usize {
            return Err(Error::Invalid(format!(
                "{} bins do not fit 32-bit bin ids",
                bins.n_bins()
            )));
        }
        Ok(())
    }
}

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

    fn from_groups(weights: Vec<f64>, scope: Scope, groups: Vec<GroupStats>) -> Self {
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
            let filter = juicer_filter(params, &layout);
            let rows: Vec<f64> = masked.iter().map(|&m| f64::from(u8::from(!m))).collect();
            let nnz = marginals(source, layout.n_bins, filter, &rows, true)?;
            let (weights, stats) = scale::scale(source, params, &layout, filter, &nnz)?;
            Ok(BalanceResult::from_groups(weights, params.scope, stats))
        }
    }
}

/// Bins, chromosomes and groups, as the passes need them.
struct Layout {
    n_bins: usize,
    /// Chromosome of every bin.
    chrom_of: Vec<u32>,
    /// One past the last bin of every bin's chromosome.
    chrom_end: Vec<u32>,
    /// First bin of each chromosome, plus `n_bins`.
    chrom_offsets: Vec<usize>,
    scope: Scope,
}

impl Layout {
    fn new(bins: &BinTable, scope: Scope) -> Self {
        let n_bins = bins.n_bins();
        let mut chrom_of = vec![0u32; n_bins];
        let mut chrom_end = vec![0u32; n_bins];
        for c in 0..bins.n_chroms() {
            let range = bins.chrom_bins(c);
            for b in range.clone() {
                chrom_of[b] = c as u32;
                chrom_end[b] = range.end as u32;
            }
        }
        Layout {
            n_bins,
            chrom_of,
            chrom_end,
            chrom_offsets: bins.chrom_offsets().to_vec(),
            scope,
        }
    }

    /// The groups balanced independently: one per chromosome with cis scope, else the genome.
    fn groups(&self) -> Vec<std::ops::Range<usize>> {
        match self.scope {
            Scope::Cis => self.chrom_offsets.windows(2).map(|w| w[0]..w[1]).collect(),
            _ => std::iter::once(0..self.n_bins).collect(),
        }
    }

    /// Number of groups.
    fn n_groups(&self) -> usize {
        match self.scope {
            Scope::Cis => self.chrom_offsets.len() - 1,
            _ => 1,
        }
    }

    /// Group of a bin.
    #[inline]
    fn group_of(&self, bin: usize) -> usize {
        match self.scope {
            Scope::Cis => self.chrom_of[bin] as usize,
            _ => 0,
        }
    }
}

/// Which pixels a pass keeps.
#[derive(Clone, Copy)]
struct PixelFilter<'a> {
    ignore_diags: usize,
    keep: Keep,
    /// One past the last bin of each bin's chromosome.
    chrom_end: &'a [u32],
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Keep {
    All,
    Cis,
    Trans,
}

impl PixelFilter<'_> {
    /// The accepted columns `lo..hi` of row `bin1` (pixels are upper-triangle: `bin2 >= bin1`,
    /// and a row's cis columns are those before the end of its chromosome).
    #[inline]
    fn columns(&self, bin1: usize) -> (usize, usize) {
        let lo = bin1.saturating_add(self.ignore_diags);
        let chrom_end = self.chrom_end[bin1] as usize;
        match self.keep {
            Keep::All => (lo, usize::MAX),
            Keep::Cis => (lo, chrom_end),
            Keep::Trans => (lo.max(chrom_end), usize::MAX),
        }
    }
}

/// Per-bin sums accumulated over one slice of pixels: a dense window starting at the slice's first
/// row (which holds every row sum and the near-diagonal column sums), and a list of the column
/// contributions that fall outside it. A slice's partial result therefore stays small whatever
/// the number of bins; the list turns into a dense genome-wide vector when that is smaller.
#[derive(Clone, Debug, Default)]
struct BinSums {
    start: usize,
    dense: Vec<f64>,
    far_bins: Vec<u32>,
    far_values: Vec<f64>,
    n_bins: usize,
}

/// Bins past a slice's last row covered by its dense window.
const WINDOW_EXTRA_BINS: usize = 4096;

impl BinSums {
    /// Sums for the pixels of `slice` (empty when the slice is).
    fn for_slice(slice: &PixelSlice<'_>, n_bins: usize) -> Self {
        if slice.is_empty() {
            return BinSums::default();
        }
        let start = slice.bin1[0] as usize;
        let end = (slice.bin1[slice.len() - 1] as usize + 1 + WINDOW_EXTRA_BINS).min(n_bins);
        BinSums {
            start,
            dense: vec![0.0; end - start],
            far_bins: Vec::new(),
            far_values: Vec::new(),
            n_bins,
        }
    }

    fn is_unset(&self) -> bool {
        self.n_bins == 0
    }

    fn is_full(&self) -> bool {
        self.start == 0 && self.dense.len() == self.n_bins
    }

    #[inline]
    fn add(&mut self, bin: usize, value: f64) {
        let k = bin.wrapping_sub(self.start);
        if k < self.dense.len() {
            self.dense[k] += value;
        } else {
            self.far_bins.push(bin as u32);
            self.far_values.push(value);
            if self.far_bins.len() * 3 > self.n_bins * 2 {
                self.make_full();
            }
        }
    }

    /// Turn into a dense genome-wide vector.
    fn make_full(&mut self) {
        if self.is_full() && self.far_bins.is_empty() {
            return;
        }
        let mut dense = vec![0.0; self.n_bins];
        dense[self.start..self.start + self.dense.len()].copy_from_slice(&self.dense);
        for (&b, &v) in self.far_bins.iter().zip(&self.far_values) {
            dense[b as usize] += v;
        }
        self.start = 0;
        self.dense = dense;
        self.far_bins = Vec::new();
        self.far_values = Vec::new();
    }

    /// Combine two partial results (the left one first, always in the same order).
    fn merge(mut self, other: BinSums) -> BinSums {
        if other.is_unset() {
            return self;
        }
        if self.is_unset() {
            return other;
        }
        self.make_full();
        let window = &mut self.dense[other.start..other.start + other.dense.len()];
        for (a, b) in window.iter_mut().zip(&other.dense) {
            *a += b;
        }
        for (&b, &v) in other.far_bins.iter().zip(&other.far_values) {
            self.dense[b as usize] += v;
        }
        self
    }

    /// The genome-wide vector of sums.
    fn into_vec(mut self, n_bins: usize) -> Vec<f64> {
        if self.is_unset() {
            return vec![0.0; n_bins];
        }
        self.make_full();
        self.dense
    }
}

/// cooler's `_marginalize` of `vector[i] * vector[j] * count` (or of 1 for each nonzero count with
/// `binarize`) over the accepted pixels: each value is added to both of its bins (once for
/// diagonal pixels). Rows whose `vector` entry is 0 contribute nothing and are skipped.
fn marginals<S: PixelSource>(
    source: &S,
    n_bins: usize,
    filter: PixelFilter<'_>,
    vector: &[f64],
    binarize: bool,
) -> Result<Vec<f64>> {
    let sums = source.pass(
        BinSums::default,
        |mut acc: BinSums, slice: PixelSlice<'_>| {
            if acc.is_unset() {
                acc = BinSums::for_slice(&slice, n_bins);
            }
            // Pixels come row by row: the row's weight, accepted columns and sum stay in registers.
            let mut row = usize::MAX;
            let (mut lo, mut hi) = (0, 0);
            let (mut vi, mut row_sum) = (0.0, 0.0);
            for ((&b1, &b2), &count) in slice.bin1.iter().zip(slice.bin2).zip(slice.count) {
                let (i, j) = (b1 as usize, b2 as usize);
                if i != row {
                    if row != usize::MAX {
                        acc.add(row, row_sum);
                    }
                    row = i;
                    row_sum = 0.0;
                    vi = vector[i];
                    (lo, hi) = if vi == 0.0 { (0, 0) } else { filter.columns(i) };
                }
                if j < lo || j >= hi {
                    continue;
                }
                let c = if binarize {
                    f64::from(u8::from(count != 0.0))
                } else {
                    count
                };
                let v = vi * vector[j] * c;
                if i != j {
                    row_sum += v;
                }
                acc.add(j, v);
            }
            if row != usize::MAX {
                acc.add(row, row_sum);
            }
            acc
        },
        BinSums::merge,
    )?;
    Ok(sums.into_vec(n_bins))
}

/// `(A u)` for the accepted pixels (the symmetric matrix, the diagonal once), and per group the
/// sums `sum(count * u_i * u_j)` and `sum(count [u_i > 0 and u_j > 0])` over the full symmetric
/// matrix (Juicer's sum factor).
struct Product {
    au: Vec<f64>,
    norm_sums: Vec<f64>,
    matrix_sums: Vec<f64>,
}

fn product<S: PixelSource>(
    source: &S,
    layout: &Layout,
    filter: PixelFilter<'_>,
    u: &[f64],
) -> Result<Product> {
    let n_bins = layout.n_bins;
    let n_groups = layout.n_groups();
    type Acc = (BinSums, Vec<f64>, Vec<f64>);
    let init = || -> Acc { (BinSums::default(), Vec::new(), Vec::new()) };
    let (sums, norm_sums, matrix_sums) = source.pass(
        init,
        |mut acc: Acc, slice: PixelSlice<'_>| {
            if acc.0.is_unset() {
                acc.0 = BinSums::for_slice(&slice, n_bins);
                acc.1 = vec![0.0; n_groups];
                acc.2 = vec![0.0; n_groups];
            }
            let mut row = usize::MAX;
            let (mut lo, mut hi) = (0, 0);
            let (mut ui, mut row_sum, mut group) = (0.0, 0.0, 0);
            for ((&b1, &b2), &c) in slice.bin1.iter().zip(slice.bin2).zip(slice.count) {
                let (i, j) = (b1 as usize, b2 as usize);
                if i != row {
                    if row != usize::MAX {
                        acc.0.add(row, row_sum);
                    }
                    row = i;
                    row_sum = 0.0;
                    ui = u[i];
                    group = layout.group_of(i);
                    (lo, hi) = filter.columns(i);
                }
                if j < lo || j >= hi {
                    continue;
                }
                let uj = u[j];
                row_sum += c * uj;
                let factor = if i != j {
                    acc.0.add(j, c * ui);
                    2.0
                } else {
                    1.0
                };
                if ui > 0.0 && uj > 0.0 {
                    acc.1[group] += factor * c * ui * uj;
                    acc.2[group] += factor * c;
                }
            }
            if row != usize::MAX {
                acc.0.add(row, row_sum);
            }
            acc
        },
        |a: Acc, b: Acc| {
            let add = |mut x: Vec<f64>, y: Vec<f64>| {
                if x.is_empty() {
                    return y;
                }
                x.iter_mut().zip(&y).for_each(|(p, q)| *p += q);
                x
            };
            (a.0.merge(b.0), add(a.1, b.1), add(a.2, b.2))
        },
    )?;
    Ok(Product {
        au: sums.into_vec(n_bins),
        norm_sums: if norm_sums.is_empty() {
            vec![0.0; n_groups]
        } else {
            norm_sums
        },
        matrix_sums: if matrix_sums.is_empty() {
            vec![0.0; n_groups]
        } else {
            matrix_sums
        },
    })
}

/// A balancing problem that needs one matrix-vector product at a time (KR, SCALE): one per
/// group, all groups sharing each pass over the pixels.
trait ProductGroup {
    /// Whether the group has its result.
    fn is_done(&self) -> bool;
    /// Put the vector the group needs multiplied into `u` (its bins; zero elsewhere).
    fn request(&self, u: &mut [f64]);
    /// Take the product (the group is number `group` of the layout).
    fn feed(&mut self, product: &Product, group: usize);
}

/// Step every group until all are done, one pass over the pixels per product.
fn solve_groups<S: PixelSource, G: ProductGroup>(
    source: &S,
    layout: &Layout,
    filter: PixelFilter<'_>,
    groups: &mut [G],
) -> Result<()> {
    while groups.iter().any(|g| !g.is_done()) {
        let mut u = vec![0.0; layout.n_bins];
        for g in groups.iter() {
            g.request(&mut u);
        }
        let product = product(source, layout, filter, &u)?;
        for (index, g) in groups.iter_mut().enumerate() {
            if !g.is_done() {
                g.feed(&product, index);
            }
        }
    }
    Ok(())
}

/// The bins masked before balancing: cooler's min_nnz, min_count, MAD-max and blacklist filters.
fn prefilter<S: PixelSource>(
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

/// Mean and population variance (numpy's `mean`, `var`) of the nonzero values.
fn nonzero_mean_var(values: &[f64]) -> Option<(f64, f64)> {
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

fn ice<S: PixelSource>(
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
    let filter = PixelFilter {
        ignore_diags: params.ignore_diags.min(usize::MAX as u64) as usize,
        keep: match params.scope {
            Scope::GenomeWide => Keep::All,
            Scope::Cis => Keep::Cis,
            Scope::Trans => Keep::Trans,
        },
        chrom_end: &layout.chrom_end,
    };
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
        let marg = marginals(source, n, filter, &vector, false)?;
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

/// The pixel filter of VC and KR: the scope's pixels, minus the ignored diagonals.
fn juicer_filter<'a>(params: &BalanceParams, layout: &'a Layout) -> PixelFilter<'a> {
    PixelFilter {
        ignore_diags: params.ignore_diags.min(usize::MAX as u64) as usize,
        keep: match params.scope {
            Scope::GenomeWide => Keep::All,
            Scope::Cis => Keep::Cis,
            Scope::Trans => Keep::Trans,
        },
        chrom_end: &layout.chrom_end,
    }
}

/// Row sums of the matrix restricted to the unmasked bins.
fn row_sums<S: PixelSource>(
    source: &S,
    layout: &Layout,
    filter: PixelFilter<'_>,
    masked: &[bool],
) -> Result<Vec<f64>> {
    let ones: Vec<f64> = masked.iter().map(|&m| if m { 0.0 } else { 1.0 }).collect();
    let mut sums = product(source, layout, filter, &ones)?.au;
    for (s, &m) in sums.iter_mut().zip(masked) {
        if m {
            *s = 0.0;
        }
    }
    Ok(sums)
}

/// Juicer's sum factor `sqrt(norm_sum / matrix_sum)`, or `NaN` when there is nothing to sum.
fn sum_factor(norm_sum: f64, matrix_sum: f64) -> f64 {
    if matrix_sum > 0.0 && norm_sum > 0.0 {
        (norm_sum / matrix_sum).sqrt()
    } else {
        f64::NAN
    }
}

fn coverage<S: PixelSource>(
    source: &S,
    params: &BalanceParams,
    layout: &Layout,
    masked: &[bool],
    square_root: bool,
) -> Result<BalanceResult> {
    let filter = juicer_filter(params, layout);
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

#[cfg(test)]
// The naive references index dense matrices the way the formulas read.
#[allow(clippy::needless_range_loop)]
mod tests;
