//! Sorting pairs in bounded memory, and merging sorted pairs files, in pairtools' order
//! ([`super::order`]).
//!
//! [`sort_pairs`] reads records into a chunk until the memory cap is reached, sorts the chunk on
//! every core (the keys packed into two integers with each record's index, so that an unstable
//! parallel sort gives the stable order; a stable parallel merge sort of the keys themselves
//! where they do not fit: over 65,536 names or a position past 2^40), and, when the input is
//! larger than one chunk, writes it as a run to the temporary folder (deflated at the fastest level). The runs are then
//! merged, ties going to the earlier run, so the whole sort is stable as `sort --stable` is.
//! Run files are unlinked as soon as they are created and read back through their open handle:
//! the system removes them when the command ends, whether it succeeds, fails or is killed.
//!
//! [`merge_sorted`] merges files that are each sorted, checking the order of each as it goes.

use std::fs::File;
use std::io::{BufReader, BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::order::{SortKey, in_sorted_order};
use super::records::{PairColumns, PairRecord, PairsReader, parse_position};
use crate::error::{Error, Result};
use crate::io::plumbing::hash::FastMap;

/// How [`sort_pairs`] may use memory and disk.
#[derive(Clone, Debug)]
pub struct SortOptions {
    /// The most bytes a chunk of records (their text and sort keys) may take before it is
    /// written to disk as a run. Peak memory is about this plus the merge's buffers.
    pub memory_bytes: u64,
    /// Where runs are written (unlinked at once; see the module notes).
    pub tmpdir: PathBuf,
}

impl Default for SortOptions {
    fn default() -> Self {
        SortOptions {
            memory_bytes: 2 << 30,
            tmpdir: std::env::temp_dir(),
        }
    }
}

/// What a sort did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SortSummary {
    /// Records sorted.
    pub n_records: u64,
    /// Runs written to disk (0 when the input fitted in memory).
    pub n_runs: usize,
}

/// The most runs merged at once; more are merged in passes.
const MAX_RUNS_MERGED: usize = 128;
const RUN_BUFFER_BYTES: usize = 256 << 10;

/// One record of a chunk: where its line is and its key (chromosomes and pair type as
/// numbers given in order of first appearance, see [`Names`]).
#[derive(Clone, Copy)]
struct Entry {
    start: u64,
    len: u32,
    chrom1: u32,
    chrom2: u32,
    pair_type: u32,
    pos1: u64,
    pos2: u64,
}

/// How many lines ahead [`Chunk::write`] touches the line it will copy.
const LINES_AHEAD: usize = 16;

const ENTRY_BYTES: u64 = std::mem::size_of::<Entry>() as u64;

/// The distinct chromosome names and pair types of a chunk, numbered as they first appear.
/// Before sorting, each number is given the rank of its name among them all as bytes, so that
/// comparing two records compares integers, not names (a few dozen distinct names among
/// millions of records).
#[derive(Default)]
struct Names {
    ids: FastMap<Vec<u8>, u32>,
    names: Vec<Vec<u8>>,
    /// Bytes held, about.
    bytes: u64,
}

impl Names {
    fn id(&mut self, name: &[u8]) -> u32 {
        if let Some(&id) = self.ids.get(name) {
            return id;
        }
        let id = self.names.len() as u32;
        self.ids.insert(name.to_vec(), id);
        self.names.push(name.to_vec());
        self.bytes += 2 * name.len() as u64 + 64;
        id
    }

    /// Each number's rank among the names in byte order.
    fn ranks(&self) -> Vec<u32> {
        let mut order: Vec<usize> = (0..self.names.len()).collect();
        order.sort_by(|&a, &b| self.names[a].cmp(&self.names[b]));
        let mut ranks = vec![0u32; order.len()];
        for (rank, &id) in order.iter().enumerate() {
            ranks[id] = rank as u32;
        }
        ranks
    }

    fn clear(&mut self) {
        self.ids.clear();
        self.names.clear();
        self.bytes = 0;
    }
}

#[derive(Default)]
struct Chunk {
    bytes: Vec<u8>,
    entries: Vec<Entry>,
    names: Names,
    /// The lines' places in `bytes` (start, length), in sorted order (set by [`Chunk::sort`]).
    lines: Vec<(u64, u32)>,
}

impl Chunk {
    fn push(&mut self, record: &PairRecord, columns: &PairColumns) {
        let start = self.bytes.len() as u64;
        let line = record.line();
        self.bytes.extend_from_slice(line);
        let pair_type = columns.pair_type.map_or(&[][..], |i| record.field(i));
        self.entries.push(Entry {
            start,
            len: line.len() as u32,
            chrom1: self.names.id(record.field(columns.chrom1)),
            chrom2: self.names.id(record.field(columns.chrom2)),
            pair_type: self.names.id(pair_type),
            pos1: parse_position(record.field(columns.pos1)).unwrap_or(0),
            pos2: parse_position(record.field(columns.pos2)).unwrap_or(0),
        });
    }

    /// Bytes held, counting an entry's size again for the sort's keys and the lines' places
    /// (24 bytes a record at most: the packed keys, or the merge sort's order and places).
    fn footprint(&self) -> u64 {
        self.bytes.len() as u64 + 2 * ENTRY_BYTES * self.entries.len() as u64 + self.names.bytes
    }

    fn sort(&mut self) {
        let ranks = self.names.ranks();
        // The numbers become ranks: the chunk is sorted, written and cleared after this.
        self.entries.par_iter_mut().for_each(|e| {
            e.chrom1 = ranks[e.chrom1 as usize];
            e.chrom2 = ranks[e.chrom2 as usize];
            e.pair_type = ranks[e.pair_type as usize];
        });
        let fits = |e: &Entry| e.pos1 < 1 << 40 && e.pos2 < 1 << 40;
        self.lines = if ranks.len() <= 1 << 16 && self.entries.par_iter().all(fits) {
            // The five keys packed into two words (16 + 16 + 40 + 40 + 16 bits) with the
            // entry's index last: every key is distinct, so an unstable sort gives the order
            // a stable one would, comparing three integers and moving 24 bytes.
            let mut keyed: Vec<([u64; 2], usize)> = self
                .entries
                .par_iter()
                .enumerate()
                .map(|(i, e)| {
                    let high = u64::from(e.chrom1) << 48 | u64::from(e.chrom2) << 32 | e.pos1 >> 8;
                    let low = (e.pos1 & 0xff) << 56 | e.pos2 << 16 | u64::from(e.pair_type);
                    ([high, low], i)
                })
                .collect();
            keyed.par_sort_unstable();
            // In place: the keys' allocation becomes the lines'.
            let entries = &self.entries;
            keyed
                .into_iter()
                .map(|(_, i)| (entries[i].start, entries[i].len))
                .collect()
        } else {
            // Stable: equal keys keep their input order.
            let entries = &self.entries;
            let mut order: Vec<usize> = (0..entries.len()).collect();
            order.par_sort_by_key(|&i| {
                let e = &entries[i];
                (e.chrom1, e.chrom2, e.pos1, e.pos2, e.pair_type)
            });
            order
                .into_iter()
                .map(|i| (entries[i].start, entries[i].len))
                .collect()
        };
    }

    fn write(&self, out: &mut dyn FnMut(&[u8]) -> Result<()>) -> Result<()> {
        let mut buffer = Vec::with_capacity(RUN_BUFFER_BYTES + 4096);
        // The lines are gathered from all over the chunk, each a miss in the cache: the first
        // byte of a line some lines ahead is read early so that its miss overlaps the copies
        // (writing the sorted 10 M pairs of the benchmark took a sixth less time).
        let mut ahead = 0u8;
        for (k, &(start, len)) in self.lines.iter().enumerate() {
            if let Some(&(next, _)) = self.lines.get(k + LINES_AHEAD) {
                ahead ^= self.bytes.get(next as usize).copied().unwrap_or(0);
            }
            let start = start as usize;
            buffer.extend_from_slice(&self.bytes[start..start + len as usize]);
            buffer.push(b'\n');
            if buffer.len() >= RUN_BUFFER_BYTES {
                out(&buffer)?;
                buffer.clear();
            }
        }
        if !buffer.is_empty() {
            out(&buffer)?;
        }
        std::hint::black_box(ahead);
        Ok(())
    }

    fn clear(&mut self) {
        self.bytes.clear();
        self.entries.clear();
        self.names.clear();
        // Freed, not kept: it holds the sort keys' allocation (collected in place), which the
        // next chunk's sort would otherwise find beside its own.
        self.lines = Vec::new();
    }
}

/// A sorted run on disk, unlinked, read back through its handle.
struct Run {
    file: File,
}

impl Run {
    fn create(tmpdir: &Path) -> Result<Run> {
        for attempt in 0..1000u32 {
            let path = tmpdir.join(format!(
                ".contactmap-sort-{}-{}-{attempt}",
                std::process::id(),
                RUN_COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
            ));
            match File::options()
                .read(true)
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(file) => {
                    std::fs::remove_file(&path).map_err(|e| Error::io(&path, e))?;
                    return Ok(Run { file });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => {
                    return Err(Error::Argument(format!(
                        "--tmpdir {}: cannot write a temporary run there: {e}",
                        tmpdir.display()
                    )));
                }
            }
        }
        Err(Error::Argument(format!(
            "--tmpdir {}: no free name for a temporary run",
            tmpdir.display()
        )))
    }

    fn writer(&self) -> Result<flate2::write::DeflateEncoder<BufWriter<File>>> {
        let file = self.file.try_clone().map_err(|e| run_error(&e))?;
        Ok(flate2::write::DeflateEncoder::new(
            BufWriter::with_capacity(RUN_BUFFER_BYTES, file),
            flate2::Compression::fast(),
        ))
    }

    fn reader(&self) -> Result<RunReader> {
        let mut file = self.file.try_clone().map_err(|e| run_error(&e))?;
        file.seek(SeekFrom::Start(0)).map_err(|e| run_error(&e))?;
        Ok(RunReader {
            input: BufReader::with_capacity(
                RUN_BUFFER_BYTES,
                flate2::read::DeflateDecoder::new(BufReader::with_capacity(RUN_BUFFER_BYTES, file)),
            ),
        })
    }
}

static RUN_COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

fn run_error(e: &std::io::Error) -> Error {
    Error::Invalid(format!("a temporary run of the sort: {e}"))
}

/// Where merged records come from: a run, or a sorted input file.
trait Source {
    /// Read the next record; `false` at the end.
    fn next(&mut self, record: &mut PairRecord) -> Result<bool>;
}

struct RunReader {
    input: BufReader<flate2::read::DeflateDecoder<BufReader<File>>>,
}

impl Source for RunReader {
    fn next(&mut self, record: &mut PairRecord) -> Result<bool> {
        record.read_line(&mut self.input).map_err(|e| run_error(&e))
    }
}

/// A sorted input of [`merge_sorted`], checked as it is read.
struct SortedInput<'a> {
    reader: &'a mut PairsReader,
    columns: PairColumns,
    previous: Option<PairRecord>,
}

impl Source for SortedInput<'_> {
    fn next(&mut self, record: &mut PairRecord) -> Result<bool> {
        if !self.reader.read_record(record)? {
            return Ok(false);
        }
        self.columns.check(self.reader, record)?;
        if let Some(previous) = &self.previous {
            let (a, b) = (
                SortKey::of(previous, &self.columns),
                SortKey::of(record, &self.columns),
            );
            if !in_sorted_order(&a, &b) {
                return Err(out_of_order(self.reader, record));
            }
        }
        self.previous = Some(record.clone());
        Ok(true)
    }
}

/// The error for a record that comes before the one above it.
pub fn out_of_order(reader: &PairsReader, record: &PairRecord) -> Error {
    reader.error(
        record.number(),
        "this record comes before the one above it in pairtools' order (chrom1, chrom2, pos1, \
         pos2): the input is not sorted; sort it first with `contactmap pairs sort`",
    )
}

/// How records equal on the five keys are ordered in a merge.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Ties {
    /// The earlier source first (a stable sort's runs).
    EarlierSource,
    /// By the whole line as bytes, as `sort --merge` without `--stable` (pairtools merge).
    WholeLine,
}

/// Merge sorted sources, writing each record (with its line end) through `out`.
fn merge_sources(
    sources: &mut [Box<dyn Source + '_>],
    columns: &PairColumns,
    ties: Ties,
    out: &mut dyn FnMut(&[u8]) -> Result<()>,
) -> Result<u64> {
    let mut heads: Vec<PairRecord> = vec![PairRecord::default(); sources.len()];
    let mut heap: Vec<usize> = Vec::with_capacity(sources.len());
    for (i, source) in sources.iter_mut().enumerate() {
        if source.next(&mut heads[i])? {
            heap.push(i);
        }
    }
    let less = |heads: &[PairRecord], a: usize, b: usize| match SortKey::of(&heads[a], columns)
        .cmp(&SortKey::of(&heads[b], columns))
    {
        std::cmp::Ordering::Less => true,
        std::cmp::Ordering::Greater => false,
        std::cmp::Ordering::Equal => match ties {
            Ties::EarlierSource => a < b,
            Ties::WholeLine => (heads[a].line(), a) < (heads[b].line(), b),
        },
    };
    for i in (0..heap.len() / 2).rev() {
        sift_down(&mut heap, i, |a, b| less(&heads, a, b));
    }
    let mut buffer = Vec::with_capacity(RUN_BUFFER_BYTES + 4096);
    let mut n = 0u64;
    while let Some(&top) = heap.first() {
        buffer.extend_from_slice(heads[top].line());
        buffer.push(b'\n');
        n += 1;
        if buffer.len() >= RUN_BUFFER_BYTES {
            out(&buffer)?;
            buffer.clear();
            crate::interrupt::check()?;
        }
        if !sources[top].next(&mut heads[top])? {
            let last = heap.pop().expect("the heap has its top");
            if heap.is_empty() {
                break;
            }
            heap[0] = last;
        }
        sift_down(&mut heap, 0, |a, b| less(&heads, a, b));
    }
    if !buffer.is_empty() {
        out(&buffer)?;
    }
    Ok(n)
}

fn sift_down(heap: &mut [usize], mut i: usize, less: impl Fn(usize, usize) -> bool) {
    loop {
        let (left, right) = (2 * i + 1, 2 * i + 2);
        let mut smallest = i;
        if left < heap.len() && less(heap[left], heap[smallest]) {
            smallest = left;
        }
        if right < heap.len() && less(heap[right], heap[smallest]) {
            smallest = right;
        }
        if smallest == i {
            return;
        }
        heap.swap(i, smallest);
        i = smallest;
    }
}

/// Sort the records of `reader` in pairtools' order, writing them (each with its line end)
/// through `out`; `progress` is told the number of records read so far, now and then.
///
/// Records are checked as they are read (fields the columns need, integer positions): a bad
/// one is an error naming its line.
pub fn sort_pairs(
    reader: &mut PairsReader,
    options: &SortOptions,
    out: &mut dyn FnMut(&[u8]) -> Result<()>,
    progress: &mut dyn FnMut(u64),
) -> Result<SortSummary> {
    let columns = PairColumns::of(reader.header(), reader.path())?;
    let mut chunk = Chunk::default();
    let mut runs: Vec<Run> = Vec::new();
    let mut record = PairRecord::default();
    let mut n_records = 0u64;
    let budget = options.memory_bytes.max(1 << 20);
    while reader.read_record(&mut record)? {
        columns.check(reader, &record)?;
        chunk.push(&record, &columns);
        n_records += 1;
        if n_records.is_multiple_of(1 << 20) {
            progress(n_records);
            crate::interrupt::check()?;
        }
        if chunk.footprint() >= budget {
            chunk.sort();
            runs.push(write_run(&chunk, &options.tmpdir)?);
            chunk.clear();
        }
    }
    progress(n_records);
    chunk.sort();
    if runs.is_empty() {
        chunk.write(out)?;
        return Ok(SortSummary {
            n_records,
            n_runs: 0,
        });
    }
    if !chunk.entries.is_empty() {
        runs.push(write_run(&chunk, &options.tmpdir)?);
    }
    drop(chunk);
    let n_runs = runs.len();
    while runs.len() > MAX_RUNS_MERGED {
        // Merge the earliest runs into one that takes their place first: ties still go to
        // the earlier input.
        let rest = runs.split_off(MAX_RUNS_MERGED / 2);
        let merged = Run::create(&options.tmpdir)?;
        {
            let mut writer = merged.writer()?;
            let mut sources: Vec<Box<dyn Source>> = runs
                .iter()
                .map(|run| run.reader().map(|r| Box::new(r) as Box<dyn Source>))
                .collect::<Result<_>>()?;
            merge_sources(&mut sources, &columns, Ties::EarlierSource, &mut |bytes| {
                writer.write_all(bytes).map_err(|e| run_error(&e))
            })?;
            writer
                .finish()
                .and_then(|mut w| w.flush())
                .map_err(|e| run_error(&e))?;
        }
        runs = std::iter::once(merged).chain(rest).collect();
    }
    let mut sources: Vec<Box<dyn Source>> = runs
        .iter()
        .map(|run| run.reader().map(|r| Box::new(r) as Box<dyn Source>))
        .collect::<Result<_>>()?;
    merge_sources(&mut sources, &columns, Ties::EarlierSource, out)?;
    Ok(SortSummary { n_records, n_runs })
}

fn write_run(chunk: &Chunk, tmpdir: &Path) -> Result<Run> {
    let run = Run::create(tmpdir)?;
    let mut writer = run.writer()?;
    chunk.write(&mut |bytes| writer.write_all(bytes).map_err(|e| run_error(&e)))?;
    writer
        .finish()
        .and_then(|mut w| w.flush())
        .map_err(|e| run_error(&e))?;
    Ok(run)
}

/// Merge pairs files that are each sorted in pairtools' order into one sorted stream, writing
/// records (each with its line end) through `out`; records equal on the five keys are ordered
/// by their whole line, as `pairtools merge` (`sort --merge`) orders them. The readers must have the same columns
/// (checked by the caller, which also merges the headers); each is checked to be sorted as it is
/// read, the first record out of order an error naming its file and line.
pub fn merge_sorted(
    readers: &mut [PairsReader],
    out: &mut dyn FnMut(&[u8]) -> Result<()>,
) -> Result<u64> {
    let Some(first) = readers.first() else {
        return Ok(0);
    };
    let columns = PairColumns::of(first.header(), first.path())?;
    let mut sources: Vec<Box<dyn Source + '_>> = Vec::with_capacity(readers.len());
    for reader in readers.iter_mut() {
        let own = PairColumns::of(reader.header(), reader.path())?;
        sources.push(Box::new(SortedInput {
            reader,
            columns: own,
            previous: None,
        }));
    }
    merge_sources(&mut sources, &columns, Ties::WholeLine, out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::pairs::PairsReader;
    use rand::{Rng, SeedableRng};

    const HEADER: &str = "## pairs format v1.0.0\n#columns: readID chrom1 pos1 chrom2 pos2 strand1 strand2 pair_type\n";

    fn random_pairs(n: usize, seed: u64) -> String {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let chroms = ["chr1", "chr2", "chr10", "chrX", "!"];
        let types = ["UU", "RU", "UR", "NU"];
        let mut text = String::from(HEADER);
        for i in 0..n {
            text.push_str(&format!(
                "r{i}\t{}\t{}\t{}\t{}\t+\t-\t{}\n",
                chroms[rng.gen_range(0..chroms.len())],
                rng.gen_range(0..50),
                chroms[rng.gen_range(0..chroms.len())],
                rng.gen_range(0..50),
                types[rng.gen_range(0..types.len())],
            ));
        }
        text
    }

    /// The naive order: the lines sorted by the five keys, stably (`sort --stable`), or with
    /// the whole line as a last key (`sort` without `--stable`, as `sort --merge` merges).
    fn naive_order(lines: &mut [String], whole_line_last: bool) {
        lines.sort_by_key(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            (
                f[1].as_bytes().to_vec(),
                f[3].as_bytes().to_vec(),
                f[2].parse::<u64>().unwrap(),
                f[4].parse::<u64>().unwrap(),
                f[7].to_string(),
                if whole_line_last {
                    l.clone()
                } else {
                    String::new()
                },
            )
        });
    }

    /// The records of a pairs text in the naive stable order.
    fn naive_sort(text: &str) -> Vec<String> {
        let mut lines: Vec<String> = text
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(str::to_string)
            .collect();
        naive_order(&mut lines, false);
        lines
    }

    fn sorted(text: &str, memory_bytes: u64) -> (Vec<String>, SortSummary) {
        let folder = tempfile::tempdir().unwrap();
        let mut reader = PairsReader::new(
            Box::new(std::io::Cursor::new(text.to_string().into_bytes())),
            "t",
        )
        .unwrap();
        let mut out = Vec::new();
        let options = SortOptions {
            memory_bytes,
            tmpdir: folder.path().to_path_buf(),
        };
        let summary = sort_pairs(
            &mut reader,
            &options,
            &mut |b| {
                out.extend_from_slice(b);
                Ok(())
            },
            &mut |_| {},
        )
        .unwrap();
        // Runs are unlinked at once: nothing is left in the folder.
        assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 0);
        let lines = String::from_utf8(out)
            .unwrap()
            .lines()
            .map(str::to_string)
            .collect();
        (lines, summary)
    }

    /// Pairs whose positions are drawn from `positions` (few values: many ties).
    fn pairs_at(positions: &[u64], n: usize, seed: u64) -> String {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let chroms = ["chr1", "chr2", "!"];
        let mut text = String::from(HEADER);
        for i in 0..n {
            let mut pick = || positions[rng.gen_range(0..positions.len())];
            let (p1, p2) = (pick(), pick());
            text.push_str(&format!(
                "r{i}	{}	{p1}	{}	{p2}	+	-	{}\n",
                chroms[rng.gen_range(0..chroms.len())],
                chroms[rng.gen_range(0..chroms.len())],
                ["UU", "RU"][rng.gen_range(0..2)],
            ));
        }
        text
    }

    #[test]
    fn positions_across_the_packed_keys_bit_fields_sort_as_numbers() {
        // Values either side of the byte that moves from one packed word to the other, and of
        // the 40 bits a packed position has (the last two take the unpacked sort).
        let packed = [
            0,
            1,
            255,
            256,
            257,
            65_535,
            65_536,
            (1 << 32) - 1,
            1 << 32,
            (1 << 39) + 5,
            (1 << 40) - 1,
        ];
        let unpacked = [0, 255, 256, 1 << 40, (1 << 50) + 3];
        for (seed, positions) in [(1, &packed[..]), (2, &unpacked[..])] {
            let text = pairs_at(positions, 3_000, seed);
            let (got, _) = sorted(&text, 1 << 30);
            assert_eq!(got, naive_sort(&text), "seed {seed}");
        }
    }

    #[test]
    fn in_memory_and_spilled_sorts_equal_a_naive_stable_sort() {
        let text = random_pairs(20_000, 7);
        let expected = naive_sort(&text);
        let (in_memory, summary) = sorted(&text, 1 << 30);
        assert_eq!(summary.n_runs, 0);
        assert_eq!(in_memory, expected);
        // A 1 MiB cap spills several runs.
        let (spilled, summary) = sorted(&text, 1 << 20);
        assert!(summary.n_runs >= 2, "{summary:?}");
        assert_eq!(summary.n_records, 20_000);
        assert_eq!(spilled, expected);
    }

    #[test]
    fn merging_sorted_files_equals_sorting_their_union() {
        // `sort` without --stable: the five keys, then the whole line. Inputs sorted that way
        // (as pairtools sort's files are, but for ties) merge into their union sorted that way.
        let full_order = |lines: &mut Vec<String>| naive_order(lines, true);
        let mut a: Vec<String> = random_pairs(3000, 1)
            .lines()
            .skip(2)
            .map(str::to_string)
            .collect();
        let mut b: Vec<String> = random_pairs(3000, 2)
            .lines()
            .skip(2)
            .map(str::to_string)
            .collect();
        full_order(&mut a);
        full_order(&mut b);
        let as_file = |lines: &[String]| {
            let text = format!("{HEADER}{}\n", lines.join("\n"));
            PairsReader::new(Box::new(std::io::Cursor::new(text.into_bytes())), "f").unwrap()
        };
        let mut readers = vec![as_file(&a), as_file(&b)];
        let mut out = Vec::new();
        let n = merge_sorted(&mut readers, &mut |bytes| {
            out.extend_from_slice(bytes);
            Ok(())
        })
        .unwrap();
        assert_eq!(n, 6000);
        let mut expected: Vec<String> = a.iter().chain(&b).cloned().collect();
        full_order(&mut expected);
        let merged: Vec<String> = String::from_utf8(out)
            .unwrap()
            .lines()
            .map(str::to_string)
            .collect();
        assert_eq!(merged, expected);
    }

    #[test]
    fn merging_an_unsorted_file_names_the_line() {
        let text =
            format!("{HEADER}.\tchr1\t5\tchr1\t9\t+\t+\tUU\n.\tchr1\t4\tchr1\t9\t+\t+\tUU\n");
        let mut readers = vec![
            PairsReader::new(Box::new(std::io::Cursor::new(text.into_bytes())), "u.pairs").unwrap(),
        ];
        let error = merge_sorted(&mut readers, &mut |_| Ok(()))
            .unwrap_err()
            .to_string();
        assert!(
            error.starts_with("u.pairs:4: this record comes before"),
            "{error}"
        );
    }

    #[test]
    fn a_bad_record_stops_the_sort_with_its_line() {
        let text = format!("{HEADER}.\tchr1\t5\tchr1\n");
        let mut reader =
            PairsReader::new(Box::new(std::io::Cursor::new(text.into_bytes())), "b.pairs").unwrap();
        let error = sort_pairs(
            &mut reader,
            &SortOptions::default(),
            &mut |_| Ok(()),
            &mut |_| {},
        )
        .unwrap_err()
        .to_string();
        assert!(error.starts_with("b.pairs:3:"), "{error}");
    }
}
