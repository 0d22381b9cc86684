//! The parameters of the cis expected, with cooltools' defaults.

use crate::error::{Error, Result};

/// Parameters of [`expected_cis`](super::expected_cis), with the defaults of `cooltools.expected_cis`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CisParams {
    /// Diagonals `0..ignore_diags` get NaN sums (default 2).
    pub ignore_diags: usize,
    /// Add the `*.avg.smoothed` column (default true).
    pub smooth: bool,
    /// Add the `*.avg.smoothed.agg` column, smoothed over all regions together (default true;
    /// needs `smooth`).
    pub aggregate_smoothed: bool,
    /// Standard deviation of the smoothing kernel in log10(distance) (default 0.1).
    pub smooth_sigma_log10: f64,
}

impl CisParams {
    /// Check the values: with smoothing, `smooth_sigma_log10` a positive number.
    /// [`expected_cis`](super::expected_cis) checks them first.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::expected::CisParams;
    ///
    /// assert!(CisParams::default().check().is_ok());
    /// let bad = CisParams { smooth_sigma_log10: -1.0, ..CisParams::default() };
    /// assert!(bad.check().unwrap_err().to_string().starts_with("smooth_sigma_log10 -1"));
    /// ```
    pub fn check(&self) -> Result<()> {
        if self.smooth && !(self.smooth_sigma_log10.is_finite() && self.smooth_sigma_log10 > 0.0) {
            return Err(Error::parameter(
                "smooth_sigma_log10",
                self.smooth_sigma_log10,
                "expected a positive number (the kernel's width in log10 distance)",
            ));
        }
        Ok(())
    }
}

impl Default for CisParams {
    fn default() -> Self {
        CisParams {
            ignore_diags: 2,
            smooth: true,
            aggregate_smoothed: true,
            smooth_sigma_log10: 0.1,
        }
    }
}

/// Width of the smoothing window, in kernel sigmas (cooltools' `window_sigma`).
pub const SMOOTH_WINDOW_SIGMAS: f64 = 5.0;
/// Kernel evaluations per sigma before interpolation (cooltools' `points_per_sigma`).
pub const SMOOTH_POINTS_PER_SIGMA: usize = 10;
