//! What to balance and how: the method, the scope, cooler's filters and the iteration's limits.

use crate::error::{Error, Result};
use crate::genome::BinTable;

/// SCALE: Juicer's tolerance on the change of the vector (and 5 times it on the row sums).
pub const SCALE_TOL: f64 = 5e-4;
/// SCALE: iterations per try (Juicer: 100; `max_iters`), three times as many in all.
pub const SCALE_MAX_ITERS: usize = 100;

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
    /// `>= 0`, `min_count` a finite number. [`balance`](super::balance) checks them first.
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
                Method::Scale => SCALE_TOL,
                _ => 1e-5,
            },
            max_iters: match method {
                Method::Scale => SCALE_MAX_ITERS,
                _ => 200,
            },
            ..BalanceParams::default()
        }
    }

    /// The checks that need the bins: blacklisted bins in range, 32-bit bin ids.
    pub(super) fn check_bins(&self, bins: &BinTable) -> Result<()> {
        if let Some(&bad) = self.blacklist.iter().find(|&&b| b >= bins.n_bins()) {
            return Err(Error::Argument(format!(
                "blacklisted bin {bad} is out of range ({} bins)",
                bins.n_bins()
            )));
        }
        if bins.n_bins() > u32::MAX as usize {
            return Err(Error::Unsupported(format!(
                "{} bins do not fit 32-bit bin ids",
                bins.n_bins()
            )));
        }
        Ok(())
    }
}
