//! A/B compartments: the saddle of a compartment track (cooltools' `saddle`, `digitize` and
//! `saddle_strength`).
//!
//! # Saddle ([`saddle::saddle_cis`])
//!
//! As `cooltools.saddle(clr, expected, track, "cis", n_bins, qrange | vrange, min_diag=3,
//! max_diag=-1)` 0.7.1 computes it, without building a dense matrix:
//!
//! - The track (one value per bin, NaN where missing and at bins without a balancing weight, as
//!   cooltools' `align_track_with_cooler(mask_clr_bad_bins=True)` masks them) is cut into
//!   `n_bins` classes by `n_bins + 1` edges: quantiles of the non-NaN values at
//!   `linspace(qlo, qhi, n_bins + 1)` (numpy's linear interpolation, as `np.nanpercentile`), or
//!   `linspace(vlo, vhi, n_bins + 1)`. A value's class is `np.digitize(value, edges)`: 0 below
//!   the first edge, `n_bins + 1` from the last one on, NaN values in none (`-1`).
//! - Within each region of the view (whole chromosomes by default), every ordered pair of bins
//!   `(i, j)` with classes `a, b`, `|i - j| >= min_diag` (and `<= max_diag` when given) and a
//!   finite, non-zero expected value `E[|i - j|]` (the region's `balanced.avg`) adds
//!   `count * w_i * w_j / E` to `sum[a][b]` (0 where no pixel is stored) and 1 to `count[a][b]`;
//!   then both arrays are added to their transposes, as cooltools does. The counts come from
//!   the class sizes (all pairs, less those at excluded distances), the sums from one parallel
//!   pass over the stored pixels.
//!
//! [`saddle::saddle_strength`] is cooltools' `saddle_strength`: for each extent `k`, the mean of
//! the AA and BB corners (`k x k`) over the mean of the AB and BA corners.
//!
//! # Reference
//!
//! Open2C, cooltools (PLoS Comput. Biol. 2024), `cooltools/api/saddle.py`; compartments as in
//! Lieberman-Aiden et al., Science 2009.

pub mod saddle;
