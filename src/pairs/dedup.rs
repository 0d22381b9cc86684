//! Duplicate pairs marked as `pairtools dedup` (1.1.2, its default `scipy` backend) marks them.
//!
//! Two mapped pairs are duplicates when they have the same chromosomes and strands and their
//! positions differ by at most `--max-mismatch` bp: on each side (`--method max`, the default)
//! or summed over the two (`--method sum`). Duplicates chain (a cluster is a connected
//! component of that relation), and the first pair of each cluster in the file is kept.
//! Pairs with an unmapped side (`!`) are never duplicates.
//!
//! pairtools reads the sorted pairs in chunks of 10,000 lines and carries the last 100
//! non-duplicates of a chunk into the next, so a duplicate is found only within that reach;
//! within a chunk it writes the pairs with an unmapped side before the mapped ones (which
//! matters only when unmapped and mapped pairs go to the same output). Both are reproduced here,
//! so the outputs are identical; memory stays that of one chunk whatever the file's size.
//!
//! Like pandas, which pairtools reads chunks with, a value pandas takes for missing (`NA`,
//! `None`, `nan`, `NULL` and the like) is written back empty, and an integer extra column with a
//! missing value in a chunk is written as floats (`60.0`) in that chunk.

use super::pandas;
use super::stats::PairCounter;
use crate::error::{Error, Result};
use crate::io::pairs::sort::out_of_order;
use crate::io::pairs::{
    PairColumns, PairRecord, PairsReader, STANDARD_COLUMNS, SortKey, in_sorted_order,
    parse_position,
};

/// How positions are compared (`--method`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DedupMethod {
    /// Each side within the mismatch.
    Max,
    /// The two sides' differences summed within the mismatch.
    Sum,
}

/// The settings of [`Deduplicator`], with pairtools' defaults.
#[derive(Clone, Copy, Debug)]
pub struct DedupParams {
    /// `--max-mismatch` (3 bp).
    pub max_mismatch: u64,
    /// `--method` (max).
    pub method: DedupMethod,
    /// `--mark-dups` (on): duplicates get pair type `DD`.
    pub mark_dups: bool,
    /// Lines per chunk (pairtools' `--chunksize`, 10,000).
    pub chunk_size: usize,
    /// Non-duplicates carried into the next chunk (pairtools' `--carryover`, 100).
    pub carryover: usize,
}

impl Default for DedupParams {
    fn default() -> Self {
        DedupParams {
            max_mismatch: 3,
            method: DedupMethod::Max,
            mark_dups: true,
            chunk_size: 10_000,
            carryover: 100,
        }
    }
}

/// What a pair is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairClass {
    /// A side unmapped (`!`).
    Unmapped,
    /// A duplicate of an earlier pair.
    Duplicate,
    /// Mapped and kept.
    Unique,
}

/// Whether pairtools reads column `name` with a fixed type (its standard columns and the SAM
/// columns); other columns' types pandas guesses per chunk.
fn has_fixed_type(name: &str) -> bool {
    STANDARD_COLUMNS.contains(&name) || name == "sam1" || name == "sam2"
}

/// Marks duplicates chunk by chunk.
pub struct Deduplicator {
    params: DedupParams,
    columns: PairColumns,
    /// The columns pandas types per chunk (those without a fixed type).
    guessed: Vec<usize>,
    carry: Vec<PairRecord>,
}

impl Deduplicator {
    /// A deduplicator for records with these columns (`names`: the header's column names).
    pub fn new(columns: PairColumns, names: &[String], params: DedupParams) -> Deduplicator {
        let guessed = names
            .iter()
            .enumerate()
            .filter(|(_, name)| !has_fixed_type(name))
            .map(|(i, _)| i)
            .collect();
        Deduplicator {
            params,
            columns,
            guessed,
            carry: Vec::new(),
        }
    }

    /// The settings.
    pub fn params(&self) -> &DedupParams {
        &self.params
    }

    /// Mark one chunk of records (at most `chunk_size`, in file order, the file sorted as
    /// [`dedup_pairs`] checks it, chunks in turn): each with its class, in pairtools' output
    /// order (pairs with an unmapped side first), duplicates typed `DD` when marking.
    pub fn mark_chunk(&mut self, chunk: Vec<PairRecord>) -> Vec<Marked> {
        let n_carry = self.carry.len();
        let mut rows: Vec<PairRecord> = std::mem::take(&mut self.carry);
        rows.extend(chunk);
        let c = self.columns;
        let unmapped: Vec<bool> = rows
            .iter()
            .map(|r| r.field(c.chrom1) == b"!" || r.field(c.chrom2) == b"!")
            .collect();
        let duplicate = self.find_duplicates(&rows, &unmapped);
        // pandas' order: unmapped rows, then mapped ones; the carried rows dropped.
        let mut order: Vec<usize> = (n_carry..rows.len()).filter(|&i| unmapped[i]).collect();
        order.extend((n_carry..rows.len()).filter(|&i| !unmapped[i]));
        let mut slots: Vec<Option<PairRecord>> = rows.into_iter().map(Some).collect();
        let mut marked: Vec<(PairRecord, PairClass)> = order
            .iter()
            .map(|&i| {
                let record = slots[i].take().expect("each row once");
                let class = if unmapped[i] {
                    PairClass::Unmapped
                } else if duplicate[i] {
                    PairClass::Duplicate
                } else {
                    PairClass::Unique
                };
                (record, class)
            })
            .collect();
        // The next chunk's carry: the last non-duplicates, in the marked order, before
        // anything is rewritten for output.
        let kept: Vec<&PairRecord> = marked
            .iter()
            .filter(|(_, class)| *class != PairClass::Duplicate)
            .map(|(r, _)| r)
            .collect();
        let from = kept.len().saturating_sub(self.params.carryover);
        self.carry = kept[from..].iter().map(|r| (*r).clone()).collect();
        if self.params.mark_dups
            && let Some(column) = c.pair_type
        {
            for (record, class) in &mut marked {
                if *class == PairClass::Duplicate {
                    record.set_field(column, b"DD");
                }
            }
        }
        self.rewrite_as_pandas(&mut marked);
        marked
    }

    /// Which mapped rows are duplicates: connected components of the "within the mismatch"
    /// relation among rows of the same chromosomes and strands, all but the first row of each.
    ///
    /// The mapped rows are in sorted order (the carried rows first, then the chunk's), so rows
    /// of the same chromosomes come together with `pos1` rising: each row looks back over its
    /// run only as far as `pos1` is within the mismatch.
    fn find_duplicates(&self, rows: &[PairRecord], unmapped: &[bool]) -> Vec<bool> {
        let c = self.columns;
        let r = self.params.max_mismatch;
        let mapped: Vec<usize> = (0..rows.len()).filter(|&i| !unmapped[i]).collect();
        let position = |i: usize, column: usize| parse_position(rows[i].field(column)).unwrap_or(0);
        let positions: Vec<(u64, u64)> = mapped
            .iter()
            .map(|&i| (position(i, c.pos1), position(i, c.pos2)))
            .collect();
        let mut parent: Vec<usize> = (0..rows.len()).collect();
        fn find(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        let same =
            |i: usize, j: usize, column: usize| rows[i].field(column) == rows[j].field(column);
        let mut run_start = 0;
        for (j, &rj) in mapped.iter().enumerate() {
            if j > 0 && !(same(rj, mapped[j - 1], c.chrom1) && same(rj, mapped[j - 1], c.chrom2)) {
                run_start = j;
            }
            let (p1, p2) = positions[j];
            for k in (run_start..j).rev() {
                let (q1, q2) = positions[k];
                debug_assert!(q1 <= p1, "rows sorted by pos1 within their chromosomes");
                let (d1, d2) = (p1.saturating_sub(q1), p2.abs_diff(q2));
                if d1 > r {
                    break;
                }
                let ri = mapped[k];
                let close = match self.params.method {
                    DedupMethod::Max => d2 <= r,
                    DedupMethod::Sum => d1 + d2 <= r,
                };
                if close && same(rj, ri, c.strand1) && same(rj, ri, c.strand2) {
                    let (a, b) = (find(&mut parent, rj), find(&mut parent, ri));
                    if a != b {
                        // The root is the earlier row, the one kept.
                        let (keep, join) = if a < b { (a, b) } else { (b, a) };
                        parent[join] = keep;
                    }
                }
            }
        }
        (0..rows.len())
            .map(|i| !unmapped[i] && find(&mut parent, i) != i)
            .collect()
    }

    /// Write values back as pandas would (see the module notes).
    fn rewrite_as_pandas(&self, marked: &mut [(PairRecord, PairClass)]) {
        let n_fields = marked.iter().map(|(r, _)| r.len()).max().unwrap_or(0);
        for column in 0..n_fields {
            let guessed = self.guessed.contains(&column);
            let has_na = marked.iter().any(|(r, _)| pandas::is_na(r.field(column)));
            if !has_na {
                continue;
            }
            let integers_with_na = guessed
                && marked.iter().all(|(r, _)| {
                    let v = r.field(column);
                    pandas::is_na(v) || is_integer(v)
                })
                && marked.iter().any(|(r, _)| is_integer(r.field(column)));
            for (record, _) in marked.iter_mut() {
                if column >= record.len() {
                    continue;
                }
                let value = record.field(column);
                if pandas::is_na(value) {
                    if !value.is_empty() {
                        record.set_field(column, b"");
                    }
                } else if integers_with_na {
                    let mut float = value.to_vec();
                    float.extend_from_slice(b".0");
                    record.set_field(column, &float);
                }
            }
        }
    }
}

/// A record and what it is.
pub type Marked = (PairRecord, PairClass);

/// Mark the duplicates of a sorted pairs file as `pairtools dedup` does, chunk by chunk:
/// `on_chunk` is given each chunk's records with their classes, in pairtools' output order,
/// and the number of records read so far; each record is counted in `counter` when given (as
/// `dedup --output-stats`).
///
/// Records are checked as they are read: the fields the columns need, integer positions, and
/// the order (`#sorted: chr1-chr2-pos1-pos2`); the first record out of order is an error naming
/// its line. One thread reads and checks the next chunks while the calling thread marks,
/// counts and hands out the current one.
pub fn dedup_pairs(
    reader: &mut PairsReader,
    params: DedupParams,
    mut counter: Option<&mut PairCounter>,
    on_chunk: &mut dyn FnMut(&[Marked], u64) -> Result<()>,
) -> Result<()> {
    let columns = PairColumns::of(reader.header(), reader.path())?;
    let mut dedup = Deduplicator::new(columns, &reader.header().columns(), params);
    let path = reader.path().to_string();
    let (full_tx, full_rx) = std::sync::mpsc::sync_channel::<Result<Vec<PairRecord>>>(2);
    let (spare_tx, spare_rx) = std::sync::mpsc::channel::<Vec<PairRecord>>();
    std::thread::scope(|scope| {
        scope.spawn(move || read_chunks(reader, &columns, params.chunk_size, &full_tx, &spare_rx));
        // Returning drops the receiver, which stops the reading thread.
        let full = full_rx;
        let mut n_records = 0u64;
        while let Ok(chunk) = full.recv() {
            let chunk = chunk?;
            n_records += chunk.len() as u64;
            let marked = dedup.mark_chunk(chunk);
            if let Some(counter) = counter.as_deref_mut() {
                for (record, class) in &marked {
                    counter
                        .add_record(record, &columns, Some(*class == PairClass::Duplicate))
                        .map_err(|message| Error::parse(&path, record.number(), message))?;
                }
                counter.end_chunk();
            }
            on_chunk(&marked, n_records)?;
            // The records go back to the reading thread, their buffers reused (a fresh record
            // grows its line and field list from nothing: a tenth of the time).
            let _ = spare_tx.send(marked.into_iter().map(|(record, _)| record).collect());
            crate::interrupt::check()?;
        }
        Ok(())
    })
}

/// Read `reader` in chunks of `chunk_size` checked records (the last one shorter), sent
/// through `full` (an error ends the stream); records sent back through `spare` are reused.
fn read_chunks(
    reader: &mut PairsReader,
    columns: &PairColumns,
    chunk_size: usize,
    full: &std::sync::mpsc::SyncSender<Result<Vec<PairRecord>>>,
    spare: &std::sync::mpsc::Receiver<Vec<PairRecord>>,
) {
    let mut pool: Vec<PairRecord> = Vec::new();
    // The last record of the previous chunk, and the last record's positions as parsed when
    // it was read, to check the order.
    let mut previous: Option<PairRecord> = None;
    let mut last_positions = (0u64, 0u64);
    loop {
        while let Ok(records) = spare.try_recv() {
            pool.extend(records);
        }
        let mut chunk: Vec<PairRecord> = Vec::with_capacity(chunk_size);
        let mut record = pool.pop().unwrap_or_default();
        let mut read = || -> Result<()> {
            while chunk.len() < chunk_size && reader.read_record(&mut record)? {
                columns.check(reader, &record)?;
                let key = SortKey::of(&record, columns);
                if let Some(last) = chunk.last().or(previous.as_ref()) {
                    let last_key = SortKey {
                        chrom1: last.field(columns.chrom1),
                        chrom2: last.field(columns.chrom2),
                        pos1: last_positions.0,
                        pos2: last_positions.1,
                        pair_type: &[],
                    };
                    if !in_sorted_order(&last_key, &key) {
                        return Err(out_of_order(reader, &record));
                    }
                }
                last_positions = (key.pos1, key.pos2);
                let next = pool.pop().unwrap_or_default();
                chunk.push(std::mem::replace(&mut record, next));
            }
            Ok(())
        };
        if let Err(e) = read() {
            let _ = full.send(Err(e));
            return;
        }
        if chunk.is_empty() {
            return;
        }
        let done = chunk.len() < chunk_size;
        previous.clone_from(&chunk.last().cloned());
        if full.send(Ok(chunk)).is_err() || done {
            return;
        }
    }
}

fn is_integer(value: &[u8]) -> bool {
    let digits = value.strip_prefix(b"-").unwrap_or(value);
    !digits.is_empty() && digits.iter().all(u8::is_ascii_digit)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::pairs::PairsHeader;
    use rand::{Rng, SeedableRng};

    fn columns() -> (PairColumns, Vec<String>) {
        let header = PairsHeader::default();
        (PairColumns::of(&header, "t").unwrap(), header.columns())
    }

    /// The naive clustering: every pair of mapped rows compared, components by repeated
    /// relabelling.
    fn naive(rows: &[(String, u64, String, u64, char, char)], r: u64, sum: bool) -> Vec<bool> {
        let n = rows.len();
        let mut label: Vec<usize> = (0..n).collect();
        let mapped = |i: usize| rows[i].0 != "!" && rows[i].2 != "!";
        loop {
            let mut changed = false;
            for i in 0..n {
                for j in 0..n {
                    let (a, b) = (&rows[i], &rows[j]);
                    if i == j || !mapped(i) || !mapped(j) {
                        continue;
                    }
                    let same = a.0 == b.0 && a.2 == b.2 && a.4 == b.4 && a.5 == b.5;
                    let (d1, d2) = (a.1.abs_diff(b.1), a.3.abs_diff(b.3));
                    let close = if sum {
                        d1 + d2 <= r
                    } else {
                        d1 <= r && d2 <= r
                    };
                    if same && close && label[j] > label[i] {
                        label[j] = label[i];
                        changed = true;
                    }
                }
            }
            if !changed {
                break;
            }
        }
        (0..n).map(|i| mapped(i) && label[i] != i).collect()
    }

    fn random_rows(n: usize, seed: u64) -> Vec<(String, u64, String, u64, char, char)> {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let chroms = ["!", "chr1", "chr2"];
        let mut rows: Vec<_> = (0..n)
            .map(|_| {
                (
                    chroms[rng.gen_range(0..3)].to_string(),
                    rng.gen_range(0..60u64),
                    chroms[rng.gen_range(0..3)].to_string(),
                    rng.gen_range(0..60u64),
                    if rng.gen_bool(0.5) { '+' } else { '-' },
                    if rng.gen_bool(0.5) { '+' } else { '-' },
                )
            })
            .collect();
        rows.sort_by(|a, b| (&a.0, &a.2, a.1, a.3).cmp(&(&b.0, &b.2, b.1, b.3)));
        rows
    }

    fn records(rows: &[(String, u64, String, u64, char, char)]) -> Vec<PairRecord> {
        rows.iter()
            .enumerate()
            .map(|(i, (c1, p1, c2, p2, s1, s2))| {
                PairRecord::from_line(
                    format!("r{i}\t{c1}\t{p1}\t{c2}\t{p2}\t{s1}\t{s2}\tUU").as_bytes(),
                    i as u64,
                )
            })
            .collect()
    }

    #[test]
    fn one_chunk_marks_what_a_naive_clustering_marks() {
        let (c, names) = columns();
        for (seed, sum) in [(1, false), (2, true), (3, false)] {
            let rows = random_rows(400, seed);
            let expected = naive(&rows, 3, sum);
            let params = DedupParams {
                method: if sum {
                    DedupMethod::Sum
                } else {
                    DedupMethod::Max
                },
                ..DedupParams::default()
            };
            let mut dedup = Deduplicator::new(c, &names, params);
            let marked = dedup.mark_chunk(records(&rows));
            let mut found = vec![false; rows.len()];
            for (record, class) in &marked {
                let i: usize = std::str::from_utf8(&record.field(0)[1..])
                    .unwrap()
                    .parse()
                    .unwrap();
                found[i] = *class == PairClass::Duplicate;
                if *class == PairClass::Duplicate {
                    assert_eq!(record.field(7), b"DD");
                }
            }
            assert_eq!(found, expected, "seed {seed}");
            // Unmapped rows first.
            let first_mapped = marked
                .iter()
                .position(|(_, k)| *k != PairClass::Unmapped)
                .unwrap();
            assert!(
                marked[first_mapped..]
                    .iter()
                    .all(|(_, k)| *k != PairClass::Unmapped)
            );
        }
    }

    #[test]
    fn duplicates_across_chunks_are_found_through_the_carry() {
        let (c, names) = columns();
        let line = |i: u64, p: u64| {
            PairRecord::from_line(
                format!("r{i}\tchr1\t{p}\tchr1\t{p}\t+\t+\tUU").as_bytes(),
                i,
            )
        };
        let mut dedup = Deduplicator::new(c, &names, DedupParams::default());
        let first = dedup.mark_chunk(vec![line(0, 100), line(1, 500)]);
        assert!(first.iter().all(|(_, k)| *k == PairClass::Unique));
        let second = dedup.mark_chunk(vec![line(2, 502), line(3, 900)]);
        let classes: Vec<PairClass> = second.iter().map(|(_, k)| *k).collect();
        assert_eq!(classes, [PairClass::Duplicate, PairClass::Unique]);
    }

    fn reader_of(rows: &[(String, u64, String, u64, char, char)]) -> PairsReader {
        let mut text = String::from("## pairs format v1.0.0\n#sorted: chr1-chr2-pos1-pos2\n");
        text.push_str("#columns: readID chrom1 pos1 chrom2 pos2 strand1 strand2 pair_type\n");
        for record in records(rows) {
            text.push_str(std::str::from_utf8(record.line()).unwrap());
            text.push('\n');
        }
        PairsReader::new(Box::new(std::io::Cursor::new(text.into_bytes())), "t.pairs").unwrap()
    }

    #[test]
    fn the_threaded_reading_hands_out_what_marking_each_chunk_in_turn_gives() {
        let (c, names) = columns();
        let rows = random_rows(1000, 4);
        let params = DedupParams {
            chunk_size: 37,
            carryover: 5,
            ..DedupParams::default()
        };
        // The reference: the file cut into chunks by hand, marked one after the other.
        let mut dedup = Deduplicator::new(c, &names, params);
        let mut expected = Vec::new();
        for chunk in records(&rows).chunks(37) {
            expected.extend(
                dedup
                    .mark_chunk(chunk.to_vec())
                    .into_iter()
                    .map(|(r, k)| (r.line().to_vec(), k)),
            );
        }
        let mut got = Vec::new();
        let mut counts = Vec::new();
        dedup_pairs(&mut reader_of(&rows), params, None, &mut |marked, n| {
            got.extend(marked.iter().map(|(r, k)| (r.line().to_vec(), *k)));
            counts.push(n);
            Ok(())
        })
        .unwrap();
        assert_eq!(got, expected);
        assert_eq!(counts.len(), 1000usize.div_ceil(37));
        assert_eq!(counts.last(), Some(&1000));
        assert!(expected.iter().any(|(_, k)| *k == PairClass::Duplicate));
    }

    #[test]
    fn a_record_out_of_order_past_a_chunk_is_named_by_its_line() {
        let mut rows = random_rows(100, 5);
        // Row 50 moved first on its chromosomes: out of order unless it ties.
        rows[50].1 = 0;
        rows[50].3 = 0;
        let params = DedupParams {
            chunk_size: 8,
            ..DedupParams::default()
        };
        let error = dedup_pairs(&mut reader_of(&rows), params, None, &mut |_, _| Ok(()))
            .unwrap_err()
            .to_string();
        // Three header lines: row 50 (0-based) is line 54.
        assert!(error.starts_with("t.pairs:54: "), "{error}");
    }

    #[test]
    fn missing_values_are_written_back_as_pandas_writes_them() {
        let header = PairsHeader {
            lines: vec!["#columns: readID chrom1 pos1 chrom2 pos2 strand1 strand2 pair_type read_side1 cigar1".into()],
        };
        let c = PairColumns::of(&header, "t").unwrap();
        let mut dedup = Deduplicator::new(c, &header.columns(), DedupParams::default());
        let marked = dedup.mark_chunk(vec![
            PairRecord::from_line(b"a\t!\t0\t!\t0\t-\t-\tXX\t\tNone", 1),
            PairRecord::from_line(b"b\tchr1\t5\tchr1\t9\t+\t+\tUU\t1\t50M", 2),
        ]);
        assert_eq!(marked[0].0.line(), b"a\t!\t0\t!\t0\t-\t-\tXX\t\t");
        assert_eq!(
            marked[1].0.line(),
            b"b\tchr1\t5\tchr1\t9\t+\t+\tUU\t1.0\t50M"
        );
    }
}
