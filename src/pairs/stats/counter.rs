//! The counter itself: [`PairCounter`], its tallies and the constants of pairtools' statistics.

use std::borrow::Cow;
use std::collections::HashMap;

use crate::error::{Error, Result};
use crate::io::pairs::{PairColumns, PairRecord, parse_position};
use crate::io::plumbing::hash::FastMap;

/// The records of one data frame of `pairtools stats` (its `pd.read_table(chunksize=...)`):
/// call [`PairCounter::end_chunk`] after each this many records to list pair types and
/// chromosome pairs in pairtools' order.
pub const STATS_CHUNK_RECORDS: usize = 100_000;

/// pairtools' default number of distance bins per decade (`--n-dist-bins-decade`).
pub const DEFAULT_DIST_BINS_PER_DECADE: u32 = 8;

/// The chromosome of an unmapped side.
pub(crate) const UNMAPPED: &[u8] = b"!";

/// The strand pairs in the order pairtools writes `dist_freq/` lines.
pub(crate) const STRAND_PAIRS: [&str; 4] = ["+-", "-+", "--", "++"];

/// The separations of the `cis_Nkb+` counts, in bp.
pub(crate) const CIS_CUTOFFS_BP: [u64; 6] = [1_000, 2_000, 4_000, 10_000, 20_000, 40_000];

/// The `cis_Nkb+` keys, in the order of [`CIS_CUTOFFS_BP`].
pub(crate) const CIS_KEYS: [&str; 6] = [
    "cis_1kb+",
    "cis_2kb+",
    "cis_4kb+",
    "cis_10kb+",
    "cis_20kb+",
    "cis_40kb+",
];

/// One pair's fields as the counts read them.
struct Pair<'a> {
    chrom1: &'a [u8],
    pos1: u64,
    strand1: &'a [u8],
    chrom2: &'a [u8],
    pos2: u64,
    strand2: &'a [u8],
    duplicate: bool,
}

/// Up to how many keys a [`Tally`] looks its keys up one by one.
const FEW_KEYS: usize = 16;

/// Counts by key, keys in the order they were first added (a Python dict of counts).
#[derive(Clone, Debug, Default)]
pub(crate) struct Tally {
    pub(crate) keys: Vec<Vec<u8>>,
    pub(crate) counts: Vec<u64>,
    pub(crate) index: FastMap<Vec<u8>, usize>,
    /// The key added last (records come in runs of the same pair type and chromosomes).
    last: usize,
}

impl Tally {
    /// Add `n` to `key`'s count (a new key goes last).
    pub(crate) fn add(&mut self, key: &[u8], n: u64) {
        if self.keys.get(self.last).is_some_and(|last| last == key) {
            self.counts[self.last] += n;
            return;
        }
        // A few keys (pair types, the chromosome pairs of a small genome) are found faster by
        // looking at each than by hashing.
        let found = if self.keys.len() <= FEW_KEYS {
            self.keys.iter().position(|k| k == key)
        } else {
            self.index.get(key).copied()
        };
        match found {
            Some(i) => {
                self.counts[i] += n;
                self.last = i;
            }
            None => {
                self.last = self.keys.len();
                self.index.insert(key.to_vec(), self.keys.len());
                self.keys.push(key.to_vec());
                self.counts.push(n);
            }
        }
    }

    /// Set `key`'s count (a new key goes last; a known one keeps its place).
    pub(crate) fn set(&mut self, key: &[u8], n: u64) {
        match self.index.get(key) {
            Some(&i) => self.counts[i] = n,
            None => self.add(key, n),
        }
    }

    /// Add every count of `other`, in pandas' `value_counts` order: decreasing count, ties in
    /// `other`'s order.
    pub(crate) fn add_by_count(&mut self, other: &Tally) {
        let mut order: Vec<usize> = (0..other.keys.len()).collect();
        order.sort_by(|&a, &b| other.counts[b].cmp(&other.counts[a]));
        for i in order {
            self.add(&other.keys[i], other.counts[i]);
        }
    }

    /// Add every count of `other`, in `other`'s order.
    pub(crate) fn add_all(&mut self, other: &Tally) {
        for (key, count) in other.iter() {
            self.add(key, count);
        }
    }

    pub(crate) fn iter(&self) -> impl Iterator<Item = (&[u8], u64)> {
        self.keys
            .iter()
            .map(Vec::as_slice)
            .zip(self.counts.iter().copied())
    }

    pub(crate) fn get(&self, key: &[u8]) -> u64 {
        self.index.get(key).map_or(0, |&i| self.counts[i])
    }

    pub(crate) fn clear(&mut self) {
        self.keys.clear();
        self.counts.clear();
        self.index.clear();
    }
}

/// The key of a chromosome pair in a [`Tally`]: the two names joined by a tab (which no
/// field holds).
pub(crate) fn chrom_pair_key(buffer: &mut Vec<u8>, chrom1: &[u8], chrom2: &[u8]) {
    buffer.clear();
    buffer.extend_from_slice(chrom1);
    buffer.push(b'\t');
    buffer.extend_from_slice(chrom2);
}

/// The edges of pairtools' distance bins with `n_per_decade` bins per decade: 0, then
/// `round(10^(i / n_per_decade))` (half to even) for `i` from 0 while `i / n_per_decade` is
/// below 9.001, repeated edges dropped (numpy's `unique(r_[0, round(10 ** arange(0, 9.001,
/// 1 / n))])`).
pub fn dist_bin_edges(n_per_decade: u32) -> Vec<u64> {
    let step = 1.0 / f64::from(n_per_decade.max(1));
    let n_steps = (9.001 / step).ceil() as usize;
    let mut edges = vec![0u64];
    edges.extend((0..n_steps).map(|i| 10f64.powf(i as f64 * step).round_ties_even() as u64));
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// The pairs of an open data frame (see the module docs on the order of the lines).
#[derive(Clone, Debug, Default)]
pub(crate) struct Chunk {
    pub(crate) pair_types: Tally,
    pub(crate) chrom_freq: Tally,
    pub(crate) n_records: usize,
}

/// pairtools' `PairCounter` for the `no_filter` statistics: counts pairs, writes and reads the
/// stats file, merges counters. See the module docs for what each line counts.
#[derive(Clone, Debug)]
pub struct PairCounter {
    pub(crate) n_dist_bins_per_decade: u32,
    /// The distance bins' left edges ([`dist_bin_edges`]).
    pub(crate) dist_bins: Vec<u64>,
    pub(crate) total: u64,
    pub(crate) total_unmapped: u64,
    pub(crate) total_single_sided_mapped: u64,
    pub(crate) total_mapped: u64,
    pub(crate) total_dups: u64,
    pub(crate) total_nodups: u64,
    pub(crate) cis: u64,
    pub(crate) trans: u64,
    /// `cis_Nkb+`, in the order of [`CIS_CUTOFFS_BP`].
    pub(crate) cis_beyond: [u64; 6],
    pub(crate) pair_types: Tally,
    /// Keyed by `chrom1 \t chrom2`.
    pub(crate) chrom_freq: Tally,
    /// Counts by strand pair (in the order of [`STRAND_PAIRS`]) and distance bin.
    pub(crate) dist_freq: [Vec<u64>; 4],
    pub(crate) chromsizes: Vec<(String, u64)>,
    pub(crate) chunk: Chunk,
    /// Scratch for chromosome-pair keys.
    pub(crate) key: Vec<u8>,
}

impl Default for PairCounter {
    fn default() -> PairCounter {
        PairCounter::new()
    }
}

impl PairCounter {
    /// An empty counter with pairtools' default distance bins (8 per decade).
    pub fn new() -> PairCounter {
        PairCounter::with_bins(DEFAULT_DIST_BINS_PER_DECADE)
    }

    /// An empty counter with `n_per_decade` distance bins per decade (`pairtools stats
    /// --n-dist-bins-decade`); at least 1.
    pub fn with_dist_bins_per_decade(n_per_decade: u32) -> Result<PairCounter> {
        if n_per_decade == 0 {
            return Err(Error::parameter(
                "n_dist_bins_decade",
                n_per_decade,
                "at least 1",
            ));
        }
        Ok(PairCounter::with_bins(n_per_decade))
    }

    pub(crate) fn with_bins(n_per_decade: u32) -> PairCounter {
        let dist_bins = dist_bin_edges(n_per_decade);
        let n_bins = dist_bins.len();
        PairCounter {
            n_dist_bins_per_decade: n_per_decade,
            dist_bins,
            total: 0,
            total_unmapped: 0,
            total_single_sided_mapped: 0,
            total_mapped: 0,
            total_dups: 0,
            total_nodups: 0,
            cis: 0,
            trans: 0,
            cis_beyond: [0; 6],
            pair_types: Tally::default(),
            chrom_freq: Tally::default(),
            dist_freq: std::array::from_fn(|_| vec![0; n_bins]),
            chromsizes: Vec::new(),
            chunk: Chunk::default(),
            key: Vec::new(),
        }
    }

    /// The number of distance bins per decade.
    pub fn n_dist_bins_per_decade(&self) -> u32 {
        self.n_dist_bins_per_decade
    }

    /// The number of pairs counted (`total`).
    pub fn n_total(&self) -> u64 {
        self.total
    }

    /// The mapped pairs (`total_mapped`), duplicates included.
    pub fn n_mapped(&self) -> u64 {
        self.total_mapped
    }

    /// The mapped pairs counted as duplicates (`total_dups`).
    pub fn n_duplicates(&self) -> u64 {
        self.total_dups
    }

    /// The count of pair type `pair_type` (`pair_types/TYPE`; chunks not yet ended included).
    pub fn n_pair_type(&self, pair_type: &str) -> u64 {
        self.pair_types.get(pair_type.as_bytes()) + self.chunk.pair_types.get(pair_type.as_bytes())
    }

    /// The chromosome sizes written as `chromsizes/` lines (`pairtools stats` writes those of
    /// the pairs header; parse and dedup none).
    pub fn set_chromsizes(&mut self, chromsizes: Vec<(String, u64)>) {
        self.chromsizes = chromsizes;
    }

    /// The strand pair's index in [`STRAND_PAIRS`] (an error message for another).
    pub(crate) fn strand_index(
        strand1: &[u8],
        strand2: &[u8],
    ) -> std::result::Result<usize, String> {
        match (strand1, strand2) {
            (b"+", b"-") => Ok(0),
            (b"-", b"+") => Ok(1),
            (b"-", b"-") => Ok(2),
            (b"+", b"+") => Ok(3),
            _ => Err(format!(
                "strands '{}' and '{}' of a cis pair: expected '+' or '-'",
                String::from_utf8_lossy(strand1),
                String::from_utf8_lossy(strand2)
            )),
        }
    }

    /// Count a cis pair's separation (dist_freq, cis_Nkb+).
    pub(crate) fn add_separation(&mut self, pos1: u64, pos2: u64, strands: usize) {
        let separation = pos1.abs_diff(pos2);
        let bin = self.dist_bins.partition_point(|&edge| edge <= separation) - 1;
        self.dist_freq[strands][bin] += 1;
        for (count, cutoff) in self.cis_beyond.iter_mut().zip(CIS_CUTOFFS_BP) {
            if separation >= cutoff {
                *count += 1;
            }
        }
    }

    /// Count one pair as `pairtools parse` does (its `add_pair`): a mapped pair of type `DD` is
    /// a duplicate; pair types and chromosome pairs are listed as they first appear. The
    /// strands of a cis pair must be `+` or `-` (the error says which were found; nothing is
    /// counted then).
    #[allow(clippy::too_many_arguments)]
    pub fn add_pair(
        &mut self,
        chrom1: &[u8],
        pos1: u64,
        strand1: &[u8],
        chrom2: &[u8],
        pos2: u64,
        strand2: &[u8],
        pair_type: &[u8],
    ) -> std::result::Result<(), String> {
        let pair = Pair {
            chrom1,
            pos1,
            strand1,
            chrom2,
            pos2,
            strand2,
            duplicate: pair_type == b"DD",
        };
        self.count(&pair, false)?;
        self.pair_types.add(pair_type, 1);
        Ok(())
    }

    /// Count one record as pairtools' `add_pairs_from_dataframe` does (`pairtools stats`,
    /// `pairtools dedup --output-stats`), in the open chunk (see [`PairCounter::end_chunk`]).
    ///
    /// `duplicate` is whether a mapped pair is a duplicate: `None` reads it from the pair type
    /// (`DD`, as `pairtools stats` does), `Some(flag)` is dedup's own mark. The error (a bad
    /// position, a strand other than `+` / `-` on a cis pair, no `pair_type` column) is a
    /// message for the caller to name the line with; nothing is counted then.
    pub fn add_record(
        &mut self,
        record: &PairRecord,
        columns: &PairColumns,
        duplicate: Option<bool>,
    ) -> std::result::Result<(), String> {
        let Some(pair_type_column) = columns.pair_type else {
            return Err("the pairs have no 'pair_type' column, which stats count".into());
        };
        let pair_type = record.field(pair_type_column);
        let position = |column: usize| {
            parse_position(record.field(column)).ok_or_else(|| {
                format!(
                    "position '{}' is not a non-negative integer",
                    String::from_utf8_lossy(record.field(column))
                )
            })
        };
        let pair = Pair {
            chrom1: record.field(columns.chrom1),
            pos1: position(columns.pos1)?,
            strand1: record.field(columns.strand1),
            chrom2: record.field(columns.chrom2),
            pos2: position(columns.pos2)?,
            strand2: record.field(columns.strand2),
            duplicate: duplicate.unwrap_or(pair_type == b"DD"),
        };
        self.count(&pair, true)?;
        self.chunk.n_records += 1;
        // pandas' value_counts leaves out a missing pair type.
        if !crate::pairs::pandas::is_na(pair_type) {
            self.chunk.pair_types.add(pair_type, 1);
        }
        Ok(())
    }

    /// The counts both ways of adding share: totals, duplicates, cis / trans, distances and
    /// chromosome pairs (into the open chunk's tally with `in_chunk`, else directly).
    fn count(&mut self, pair: &Pair<'_>, in_chunk: bool) -> std::result::Result<(), String> {
        let mapped1 = pair.chrom1 != UNMAPPED;
        let mapped2 = pair.chrom2 != UNMAPPED;
        let cis = mapped1 && mapped2 && !pair.duplicate && pair.chrom1 == pair.chrom2;
        let strands = if cis {
            Some(Self::strand_index(pair.strand1, pair.strand2)?)
        } else {
            None
        };
        self.total += 1;
        match (mapped1, mapped2) {
            (false, false) => self.total_unmapped += 1,
            (true, true) => {
                self.total_mapped += 1;
                if pair.duplicate {
                    self.total_dups += 1;
                } else {
                    self.total_nodups += 1;
                    chrom_pair_key(&mut self.key, pair.chrom1, pair.chrom2);
                    let tally = if in_chunk {
                        &mut self.chunk.chrom_freq
                    } else {
                        &mut self.chrom_freq
                    };
                    tally.add(&self.key, 1);
                    match strands {
                        Some(strands) => {
                            self.cis += 1;
                            self.add_separation(pair.pos1, pair.pos2, strands);
                        }
                        None => self.trans += 1,
                    }
                }
            }
            _ => self.total_single_sided_mapped += 1,
        }
        Ok(())
    }

    /// The number of records [`PairCounter::add_record`] counted since the last
    /// [`PairCounter::end_chunk`].
    pub fn n_chunk_records(&self) -> usize {
        self.chunk.n_records
    }

    /// End the open chunk: its pair types and chromosome pairs join the counts, new keys in
    /// pandas' `value_counts` order (decreasing count, ties in order of first appearance).
    pub fn end_chunk(&mut self) {
        if self.chunk.n_records == 0 {
            return;
        }
        self.pair_types.add_by_count(&self.chunk.pair_types);
        self.chrom_freq.add_by_count(&self.chunk.chrom_freq);
        self.chunk.pair_types.clear();
        self.chunk.chrom_freq.clear();
        self.chunk.n_records = 0;
    }

    /// This counter with its open chunk ended.
    pub(crate) fn finished(&self) -> Cow<'_, PairCounter> {
        if self.chunk.n_records == 0 {
            Cow::Borrowed(self)
        } else {
            let mut counter = self.clone();
            counter.end_chunk();
            Cow::Owned(counter)
        }
    }

    /// Add `other`'s counts to these (pairtools' `PairCounter.__add__`, what `pairtools stats
    /// --merge` does). Keys new to this counter go after its own, in `other`'s order. The
    /// chromosome sizes are kept when both are equal (as sets) or one is empty; different
    /// sizes, or different distance bins, are an error ([`Error::Data`]).
    pub fn merge(&mut self, other: &PairCounter) -> Result<()> {
        if self.dist_bins != other.dist_bins {
            return Err(Error::Data(format!(
                "cannot merge stats with {} and {} distance bins per decade",
                self.n_dist_bins_per_decade, other.n_dist_bins_per_decade
            )));
        }
        let chromsizes = merged_chromsizes(&self.chromsizes, &other.chromsizes)?;
        self.end_chunk();
        let other = other.finished();
        self.total += other.total;
        self.total_unmapped += other.total_unmapped;
        self.total_single_sided_mapped += other.total_single_sided_mapped;
        self.total_mapped += other.total_mapped;
        self.total_dups += other.total_dups;
        self.total_nodups += other.total_nodups;
        self.cis += other.cis;
        self.trans += other.trans;
        for (count, add) in self.cis_beyond.iter_mut().zip(other.cis_beyond) {
            *count += add;
        }
        self.pair_types.add_all(&other.pair_types);
        self.chrom_freq.add_all(&other.chrom_freq);
        for (counts, adds) in self.dist_freq.iter_mut().zip(&other.dist_freq) {
            for (count, add) in counts.iter_mut().zip(adds) {
                *count += add;
            }
        }
        self.chromsizes = chromsizes;
        Ok(())
    }
}

/// The chromosome sizes of two merged counters: equal ones (as sets), or the one that is not
/// empty.
pub(crate) fn merged_chromsizes(
    a: &[(String, u64)],
    b: &[(String, u64)],
) -> Result<Vec<(String, u64)>> {
    if b.is_empty() {
        return Ok(a.to_vec());
    }
    if a.is_empty() {
        return Ok(b.to_vec());
    }
    let as_map =
        |sizes: &[(String, u64)]| -> HashMap<String, u64> { sizes.iter().cloned().collect() };
    if as_map(a) == as_map(b) {
        Ok(a.to_vec())
    } else {
        Err(Error::Data(
            "cannot merge stats with different chromosome sizes (chromsizes/ lines)".into(),
        ))
    }
}
