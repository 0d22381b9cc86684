//! Summary statistics of a pairs file, as pairtools 1.1.2's `PairCounter` counts and writes
//! them (`pairtools stats`, and the `--output-stats` of `pairtools parse` and `pairtools dedup`):
//! the same lines, in the same order, with the same number formatting.
//!
//! # What is counted
//!
//! Every pair counts towards `total` and towards `pair_types/TYPE` (duplicates too). A pair
//! whose two sides are on the unmapped chromosome `!` is `total_unmapped`; one side on `!` is
//! `total_single_sided_mapped`; the others are `total_mapped`, split into `total_dups` and
//! `total_nodups`. The rest is counted over the mapped pairs that are not duplicates: `cis` and
//! `trans`, `chrom_freq/CHROM1/CHROM2`, and for cis pairs the separation `|pos2 - pos1|`:
//! `cis_Nkb+` (separation at least N kb, N in 1, 2, 4, 10, 20, 40) and `dist_freq/LO-HI/STRANDS`
//! (a histogram by strand pair over log-spaced bins: 0 and `round(10^(i / n))` for
//! `i = 0, 1, ...` up to 10^9, `n` = 8 bins per decade by default, repeated edges dropped;
//! a bin holds `LO <= separation < HI`, the last one `LO+` everything above).
//!
//! Whether a mapped pair is a duplicate comes from the caller: `pairtools stats` reads pair type
//! `DD` as a duplicate ([`PairCounter::add_pair`], and [`PairCounter::add_record`] with
//! `duplicate: None`), `pairtools dedup --output-stats` counts its own marks (`Some(flag)`),
//! before it rewrites their pair type.
//!
//! # Summaries
//!
//! `summary/` lines are derived when the counter is written: the fractions of cis pairs
//! (overall and beyond each `cis_Nkb+` cut-off) among `total_nodups`, `frac_dups`
//! (`total_dups / total_mapped`), `complexity_naive` ([`estimate_library_complexity`]), and
//! `dist_freq_convergence/`: the last distance bin in which one strand pair's count departs by
//! more than 5% from the mean of the four (pairtools' estimate of the distance beyond which
//! the strand pairs no longer tell ligation artefacts), with the counts and fractions of cis
//! pairs below and above it. A fraction with nothing to divide by is written as pairtools
//! writes it: `0` for the top-level fractions, `nan` in `dist_freq_convergence/`.
//!
//! # Order of the lines
//!
//! pairtools writes its dictionaries in insertion order. [`PairCounter::add_pair`] (parse)
//! inserts pair types and chromosome pairs as they first appear. `pairtools stats` and `dedup`
//! count a data frame at a time (chunks of [`STATS_CHUNK_RECORDS`] records for `stats`): a
//! chunk's new keys enter by decreasing count, ties in order of first appearance in the chunk.
//! [`PairCounter::add_record`] collects a chunk; [`PairCounter::end_chunk`] commits it in that
//! order (writing or merging a counter ends its open chunk first).
//!
//! # Merging
//!
//! [`PairCounter::from_text`] reads a stats file back and [`PairCounter::merge`] adds two
//! counters (`pairtools stats --merge`): counts add, summaries are recomputed, chromosome sizes
//! must agree (or one side have none). A file read back lists its chromosome pairs grouped by
//! their first chromosome, as pairtools' reading nests them. Merged pair types come in the
//! first counter's order, then the second's new ones (pairtools' order there follows Python's
//! string hashing, different at every run).
//!
//! # Not matched
//!
//! Only the default `no_filter` statistics and the table format (no `--filter`, no `--yaml`,
//! no `--bytile-dups`). Lines of a stats file this module does not know (pairtools'
//! `dups_by_tile_median`) are dropped when it is read back, and its `summary/` lines are
//! recomputed. A cis pair with a strand other than `+` / `-` is an error, as it is in pairtools.
//! pandas' reading of pair types is followed for missing values (an empty or `NA` pair type is
//! not counted under `pair_types/`), not for chromosome names (pandas would read `NA` as missing
//! and `01` as the number 1).

mod counter;
mod summary;
#[cfg(test)]
mod tests;
mod text;

#[cfg(test)]
use counter::*;
pub use counter::{DEFAULT_DIST_BINS_PER_DECADE, PairCounter, STATS_CHUNK_RECORDS, dist_bin_edges};
pub use summary::{estimate_library_complexity, lambert_w0};
