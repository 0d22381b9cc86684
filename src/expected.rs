//! Distance-decay expected P(s): per-diagonal cis expected and block trans expected exactly as
//! cooltools computes them, log-binned P(s) with its local slope, and power-law fits.
//!
//! # Cis expected ([`expected_cis`])
//!
//! As `cooltools.expected_cis` 0.7.1 (`intra_only=True`). For every region of a [`View`](crate::genome::View) (whole
//! chromosomes by default) and every diagonal `dist = bin2 - bin1` in `0..n_bins(region)`:
//!
//! | column | value |
//! |---|---|
//! | `dist`, `dist_bp` | the diagonal, and `dist * resolution` |
//! | `n_total` | pixels on the diagonal: `n_bins - dist` |
//! | `n_valid` | pixels whose two bins have a non-NaN weight (`n_total` for raw counts) |
//! | `count.sum` | sum of the raw counts (balanced mode: of valid pixels only) |
//! | `balanced.sum` | sum of `count * w1 * w2` (balanced mode) |
//! | `count.avg` | `count.sum / n_total` (also in balanced mode, as cooltools) |
//! | `balanced.avg` | `balanced.sum / n_valid` |
//! | `*.avg.smoothed` | Gaussian smoothing over log10(dist) per region ([`smooth::log_smooth`], sigma 0.1) of the sums and pixel counts, then their ratio |
//! | `*.avg.smoothed.agg` | the same on the sums and pixel counts added over all regions |
//! | `contact_frequency` | a copy of the last ("most processed") column |
//!
//! The sums of the first `ignore_diags` diagonals (default 2) are NaN (and count as 0 in the
//! smoothing, whose pixel counts still include them — cooltools' behaviour, kept so the smoothed
//! columns agree). The pixel counts smoothed are `n_total` for raw counts, `n_valid` for balanced.
//! Only pixels whose two bins fall in the same region count; with a BED view, a bin shared by two
//! book-ended regions counts in both regions' `n_total` but its pixels go to the later region, as
//! in cooltools.
//!
//! # Trans expected ([`expected_trans`])
//!
//! As `cooltools.expected_trans`: for every pair of regions on different chromosomes (in view
//! order), `n_valid = (bins1 - masked1) * (bins2 - masked2)`, the sums of valid pixels, and both
//! averages over `n_valid`.
//!
//! # Method and performance
//!
//! One parallel pass over the pixels ([`PixelSource::pass`](crate::matrix::PixelSource::pass)): every slice of pixels accumulates
//! into a per-thread scratch array indexed by `(region, diagonal)` and hands on only the entries it
//! touched; partial results are added entry by entry in slice order, so the sums do not depend on
//! the number of threads. Streaming a .cool file gives bit-identical sums to an in-memory copy
//! (its blocks are whole numbers of slices); other streamed sources cut slices elsewhere, which
//! changes real-valued sums only by rounding (integer counts stay exact). Per-bin region ids (masked bins already excluded) make the per-pixel work two lookups
//! and two additions. `n_valid` comes from the weight mask alone: the number of pairs of good bins
//! at each distance, an autocorrelation computed exactly from the sparser of the good / masked
//! sets (pairwise differences, or 64-bit words and popcounts when that set is dense), in
//! `O(min(m^2, n^2 / 64))` for `m` such bins in a region of `n` bins.
//!
//! Log-binned P(s) and slopes are in [`logbin`], power-law fits in [`powerlaw`].
//!
//! # References
//!
//! Lieberman-Aiden et al., Science 2009 (P(s) ~ s^-1 in human Hi-C, the fractal globule); Mirny,
//! Chromosome Res. 2011 and Fudenberg & Mirny 2012 (P(s) exponents of polymer models); Open2C,
//! cooltools (PLoS Comput. Biol. 2024), `cooltools/api/expected.py`.

mod compute;
pub mod logbin;
mod params;
pub mod powerlaw;
mod result;
pub mod smooth;
pub mod table;

pub use compute::{
    cis_curves, expected_cis, expected_to_divide_by, expected_trans, valid_pairs_per_diagonal,
};
pub use params::{CisParams, SMOOTH_POINTS_PER_SIGMA, SMOOTH_WINDOW_SIGMAS};
pub use result::{CisExpected, TransExpected};

pub use crate::io::tables::Column;

#[cfg(test)]
mod tests;
