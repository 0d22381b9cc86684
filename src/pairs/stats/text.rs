//! The stats file: pairtools' flattened `PairCounter`, one `key<TAB>value` line each.

use super::counter::{CIS_KEYS, PairCounter, STRAND_PAIRS, Tally};
use crate::error::{Error, Result};

/// The top-level counts, in pairtools' order (before `pair_types/`).
const TOTAL_KEYS: [&str; 8] = [
    "total",
    "total_unmapped",
    "total_single_sided_mapped",
    "total_mapped",
    "total_dups",
    "total_nodups",
    "cis",
    "trans",
];

impl PairCounter {
    fn totals(&self) -> [u64; 8] {
        [
            self.total,
            self.total_unmapped,
            self.total_single_sided_mapped,
            self.total_mapped,
            self.total_dups,
            self.total_nodups,
            self.cis,
            self.trans,
        ]
    }

    fn totals_mut(&mut self) -> [&mut u64; 8] {
        [
            &mut self.total,
            &mut self.total_unmapped,
            &mut self.total_single_sided_mapped,
            &mut self.total_mapped,
            &mut self.total_dups,
            &mut self.total_nodups,
            &mut self.cis,
            &mut self.trans,
        ]
    }

    /// The stats file's lines as (key, value), in pairtools' order (its `flatten`): the totals,
    /// `pair_types/`, `cis_Nkb+`, `summary/` (computed now), `chrom_freq/`, `dist_freq/` and
    /// `chromsizes/`; an empty section has no lines. The open chunk counts (as if ended).
    pub fn lines(&self) -> Vec<(String, String)> {
        let counter = self.finished();
        let mut lines = Vec::new();
        for (key, count) in TOTAL_KEYS.iter().zip(counter.totals()) {
            lines.push((key.to_string(), count.to_string()));
        }
        for (pair_type, count) in counter.pair_types.iter() {
            lines.push((
                format!("pair_types/{}", String::from_utf8_lossy(pair_type)),
                count.to_string(),
            ));
        }
        for (key, count) in CIS_KEYS.iter().zip(counter.cis_beyond) {
            lines.push((key.to_string(), count.to_string()));
        }
        for (key, value) in counter.summary_lines() {
            lines.push((format!("summary/{key}"), value));
        }
        for (chroms, count) in counter.chrom_freq.iter() {
            let chroms = String::from_utf8_lossy(chroms).replacen('\t', "/", 1);
            lines.push((format!("chrom_freq/{chroms}"), count.to_string()));
        }
        let bins = &counter.dist_bins;
        for (i, edge) in bins.iter().enumerate() {
            let range = match bins.get(i + 1) {
                Some(next) => format!("{edge}-{next}"),
                None => format!("{edge}+"),
            };
            for (s, strands) in STRAND_PAIRS.iter().enumerate() {
                lines.push((
                    format!("dist_freq/{range}/{strands}"),
                    counter.dist_freq[s][i].to_string(),
                ));
            }
        }
        for (chrom, size) in &counter.chromsizes {
            lines.push((format!("chromsizes/{chrom}"), size.to_string()));
        }
        lines
    }

    /// The stats file pairtools writes (`key<TAB>value` lines, see [`PairCounter::lines`]).
    pub fn to_text(&self) -> String {
        let mut text = String::new();
        for (key, value) in self.lines() {
            text.push_str(&key);
            text.push('\t');
            text.push_str(&value);
            text.push('\n');
        }
        text
    }

    /// Read a stats file written by pairtools or [`PairCounter::to_text`] (pairtools'
    /// `PairCounter.from_file`, with the default 8 distance bins per decade). `path` names the
    /// file in errors, which give the line: a line that is not `key<TAB>value`, a count that is
    /// not a non-negative integer, a `dist_freq/` bin or strand pair that is not pairtools', a
    /// `chrom_freq/` key without two chromosomes.
    ///
    /// `summary/` lines are skipped (they are recomputed) and so are keys pairtools' table
    /// does not hold for the `no_filter` statistics; blank lines are skipped. Chromosome pairs
    /// are listed grouped by their first chromosome, as pairtools' reading nests them; a key
    /// given twice keeps its last value.
    pub fn from_text(text: &str, path: &str) -> Result<PairCounter> {
        let mut counter = PairCounter::new();
        // chrom_freq by first chromosome, in order of first appearance (pairtools nests them).
        let mut chrom_freq_groups: Vec<(String, Tally)> = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let number = i as u64 + 1;
            let error = |message: String| Error::parse(path, number, message);
            let line = line.trim();
            if line.is_empty() {
                continue;
            }
            let fields: Vec<&str> = line.split('\t').collect();
            let [key, value] = fields[..] else {
                return Err(error(format!(
                    "{} tab-separated fields where a stats line has 2 (key, value)",
                    fields.len()
                )));
            };
            let (section, rest) = key.split_once('/').unwrap_or((key, ""));
            if section == "summary" {
                continue;
            }
            let count = || {
                value
                    .parse::<u64>()
                    .ok()
                    .filter(|_| value.bytes().all(|b| b.is_ascii_digit()))
                    .ok_or_else(|| {
                        error(format!(
                            "'{value}' for '{key}' where a count (a non-negative integer) \
                             was expected"
                        ))
                    })
            };
            if let Some(k) = TOTAL_KEYS.iter().position(|&k| k == key) {
                *counter.totals_mut()[k] = count()?;
            } else if let Some(k) = CIS_KEYS.iter().position(|&k| k == key) {
                counter.cis_beyond[k] = count()?;
            } else if section == "pair_types" && !rest.is_empty() {
                counter.pair_types.set(rest.as_bytes(), count()?);
            } else if section == "chrom_freq" {
                let chroms: Vec<&str> = rest.split('/').collect();
                let [chrom1, chrom2] = chroms[..] else {
                    return Err(error(format!(
                        "'{key}': a chrom_freq line names two chromosomes \
                         (chrom_freq/CHROM1/CHROM2)"
                    )));
                };
                let n = count()?;
                let group = match chrom_freq_groups.iter().position(|(c, _)| c == chrom1) {
                    Some(g) => g,
                    None => {
                        chrom_freq_groups.push((chrom1.to_string(), Tally::default()));
                        chrom_freq_groups.len() - 1
                    }
                };
                chrom_freq_groups[group].1.set(chrom2.as_bytes(), n);
            } else if section == "dist_freq" {
                let (bin, strands) = counter.dist_freq_slot(rest).ok_or_else(|| {
                    error(format!(
                        "'{key}' is not one of pairtools' dist_freq lines \
                         (dist_freq/LO-HI/STRANDS with its 8 bins per decade)"
                    ))
                })?;
                counter.dist_freq[strands][bin] = count()?;
            } else if section == "chromsizes" && !rest.is_empty() {
                let size = count()?;
                match counter.chromsizes.iter_mut().find(|(c, _)| c == rest) {
                    Some(entry) => entry.1 = size,
                    None => counter.chromsizes.push((rest.to_string(), size)),
                }
            }
        }
        let mut key = Vec::new();
        for (chrom1, group) in &chrom_freq_groups {
            for (chrom2, n) in group.iter() {
                super::counter::chrom_pair_key(&mut key, chrom1.as_bytes(), chrom2);
                counter.chrom_freq.add(&key, n);
            }
        }
        Ok(counter)
    }

    /// The (bin, strand pair) of a `dist_freq/` key's `LO-HI/STRANDS` or `LO+/STRANDS` part:
    /// pairtools reads the bin by its left edge.
    fn dist_freq_slot(&self, rest: &str) -> Option<(usize, usize)> {
        let (range, strands) = rest.split_once('/')?;
        let strands = STRAND_PAIRS.iter().position(|&s| s == strands)?;
        let left = match range.strip_suffix('+') {
            Some(left) => left,
            None => range.split_once('-')?.0,
        };
        let left: u64 = left.parse().ok()?;
        let bin = self.dist_bins.binary_search(&left).ok()?;
        Some((bin, strands))
    }
}
