//! A/B compartments: eigenvectors of the observed/expected map (cooltools' `eigs_cis`) and the
//! saddle of a compartment track (cooltools' `saddle`, `digitize` and `saddle_strength`).
//!
//! # Cis eigenvectors ([`cis::cis_eig`])
//!
//! As `cooltools.eigs_cis(clr, n_eigs=3, ignore_diags, clip_percentile=99.9)` 0.7.1 computes
//! them for each region (whole chromosomes by default), without a dense matrix:
//!
//! - `A` is the region's balanced matrix (0 where no pixel is stored or a bin has no weight).
//!   The valid bins are those whose column of `A` sums above 0. A region of at most
//!   `ignore_diags + 3` bins, or with at most that many valid bins, gets NaN.
//! - The diagonals `|i - j| < ignore_diags` are set to 1. Diagonals are grouped as cooltools'
//!   `observed_over_expected` groups them (`[0] + logbins(1, n, ratio 1.03)`: single diagonals
//!   near the main one, wider groups far from it), and every valid pixel is divided by the mean
//!   of its group over all valid pairs (unstored pairs count as 0).
//! - Values are clipped to `[0, q]`, `q` the `clip_percentile` percentile (numpy's linear
//!   interpolation) of the dense valid block: computed from the stored values, each counted
//!   twice off the diagonal, the band of ignored diagonals, and the zeros.
//! - `M = OE - 1` on valid pairs, 0 elsewhere; rows of `M` that are all zero are left out. The
//!   operator `M x = S x - 1 (1 . x)` (`S` the sparse clipped observed/expected) is applied to
//!   vectors, and the `n_eigs` eigenpairs of largest magnitude are found by a Krylov-Schur
//!   iteration ([`eigen`], faer's matrix-free solver; a dense decomposition below
//!   [`eigen::DENSE_MAX`] bins), ordered by decreasing `|eigenvalue|` (negative eigenvalues
//!   happen, and cooltools keeps them).
//! - Each vector is scaled to norm `sqrt(|eigenvalue|)`. Its sign is arbitrary for the
//!   eigensolver; [`phasing::phase`] makes it correlate positively (Spearman) with a phasing
//!   track, as cooltools does when given one.
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

pub mod cis;
pub mod eigen;
pub mod eigs;
pub mod phasing;
pub mod saddle;
pub mod tables;
pub mod trans;
