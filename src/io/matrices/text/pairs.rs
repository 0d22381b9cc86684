//! Read pairs, binned as `cooler cload pairs` bins them.

use rayon::prelude::*;
use std::path::Path;

use super::bins::{bin_table_for, read_chrom_sizes};
use super::lines::{Fields, LineReader, pairs_columns, parse_u64, show};
use super::options::OpenOptions;
use crate::error::{Error, Result};
use crate::genome::{BinTable, Chrom};
use crate::io::plumbing::hash::FastMap;
use crate::matrix::{ContactMatrix, CountType, MatrixBuilder};

/// Assigns pairs to bins.
struct PairBinner {
    bins: BinTable,
    chrom_ids: FastMap<Vec<u8>, usize>,
    /// First bin of each chromosome.
    offsets: Vec<u64>,
    lengths: Vec<u64>,
    /// 1 for 1-based positions (cooler's default), 0 for 0-based ones (`--zero-based`).
    first_position: u64,
}

impl PairBinner {
    fn new(path: &Path, options: &OpenOptions, header_chroms: Vec<Chrom>) -> Result<Self> {
        let bins = if options.bins_bed.is_some() {
            bin_table_for(&path.to_string_lossy(), "a pairs file", options)?
        } else {
            let Some(size) = options.text_resolution else {
                return Err(Error::Argument(format!(
                    "{}: binning pairs needs a bin size: pass --bin-size N (or --bins BED)",
                    path.display()
                )));
            };
            let chroms = match &options.chrom_sizes {
                Some(sizes) => read_chrom_sizes(sizes)?,
                None if !header_chroms.is_empty() => header_chroms,
                None => {
                    return Err(Error::Argument(format!(
                        "{}: the pairs have no '#chromsize:' header lines: pass --chrom-sizes FILE \
                         (or --bins BED) to give the chromosomes",
                        path.display()
                    )));
                }
            };
            BinTable::fixed(chroms, size)?
        };
        let chrom_ids = bins
            .chroms()
            .iter()
            .enumerate()
            .map(|(id, chrom)| (chrom.name.as_bytes().to_vec(), id))
            .collect();
        let offsets = bins.chrom_offsets().iter().map(|&o| o as u64).collect();
        let lengths = bins.chroms().iter().map(|c| c.length_bp).collect();
        Ok(PairBinner {
            bins,
            chrom_ids,
            offsets,
            lengths,
            first_position: if options.pairs_zero_based { 0 } else { 1 },
        })
    }

    /// The chromosome called `name`, trying the previous answer first (pairs are usually sorted).
    #[inline]
    fn chrom(&self, name: &[u8], cache: &mut usize) -> Option<usize> {
        let chroms = self.bins.chroms();
        if *cache < chroms.len() && chroms[*cache].name.as_bytes() == name {
            return Some(*cache);
        }
        let id = *self.chrom_ids.get(name)?;
        *cache = id;
        Some(id)
    }

    /// The bin of position `pos` (1-based, or 0-based with `--zero-based`) of chromosome
    /// `chrom_id`, or a message.
    #[inline]
    fn bin(&self, chrom_id: usize, pos: &[u8], side: u8) -> std::result::Result<u64, String> {
        let Some(pos_bp) = parse_u64(pos) else {
            return Err(format!(
                "pos{side} '{}' is not a position (expected a whole number)",
                show(pos)
            ));
        };
        let length = self.lengths[chrom_id];
        let first = self.first_position;
        if pos_bp < first || pos_bp - first >= length {
            return Err(format!(
                "pos{side} {pos_bp} is outside {} (positions are {}-based, from {first} to {})",
                self.bins.chroms()[chrom_id].name,
                first,
                length - 1 + first
            ));
        }
        let coordinate = pos_bp - first;
        Ok(match self.bins.resolution() {
            Some(size) => self.offsets[chrom_id] + coordinate / size,
            None => self.bins.bin_at(chrom_id, coordinate) as u64,
        })
    }
}

/// The 0-based `[chrom1, pos1, chrom2, pos2]` columns named in a `#columns:` header line.
fn columns_from_header(lines: &LineReader, header: &[u8]) -> Result<[usize; 4]> {
    let names: Vec<&[u8]> = header
        .split(|b| b.is_ascii_whitespace())
        .filter(|f| !f.is_empty())
        .collect();
    let find = |wanted: &[&[u8]]| names.iter().position(|n| wanted.contains(n));
    match (
        find(&[b"chr1", b"chrom1"]),
        find(&[b"pos1"]),
        find(&[b"chr2", b"chrom2"]),
        find(&[b"pos2"]),
    ) {
        (Some(c1), Some(p1), Some(c2), Some(p2)) => Ok([c1, p1, c2, p2]),
        _ => Err(lines.error(
            "the '#columns:' header does not name chr1, pos1, chr2 and pos2: pass --pairs-columns",
        )),
    }
}

/// Bytes of whole lines parsed as one task.
const CHUNK_BYTES: usize = 4 << 20;

/// Read the pairs of `lines` and bin them.
///
/// The header lines (`#chromsize:`, `#columns:`) come first and are read in order; the pairs
/// after them are read in chunks of whole lines ([`CHUNK_BYTES`]), a few chunks per thread at a
/// time, each parsed on its own core into its sorted pixel keys with their counts. The chunks'
/// runs are merged pairwise as they accumulate (runs of similar sizes, so each pixel is merged
/// `O(log n)` times), 16 bytes per distinct pixel. The first bad line in file order is the one
/// reported, whatever the threads; the result does not depend on them.
pub(super) fn read_pairs(lines: &mut LineReader, options: &OpenOptions) -> Result<ContactMatrix> {
    let mut columns: Option<[usize; 4]> = match options.pairs_columns {
        Some(one_based) => {
            if one_based.contains(&0) {
                return Err(Error::Argument(format!(
                    "pairs columns {one_based:?} must be 1-based (chrom1,pos1,chrom2,pos2)"
                )));
            }
            Some(one_based.map(|c| c - 1))
        }
        None => None,
    };
    let mut header_chroms: Vec<Chrom> = Vec::new();
    while lines.advance()? {
        let line = lines.current();
        if line.is_empty() {
            continue;
        }
        if line[0] != b'#' {
            lines.unread_current();
            break;
        }
        if let Some(rest) = line.strip_prefix(b"#chromsize:") {
            let mut fields = rest
                .split(|b| b.is_ascii_whitespace())
                .filter(|f| !f.is_empty());
            match (fields.next(), fields.next().and_then(parse_u64)) {
                (Some(name), Some(length)) if length > 0 => {
                    let name = String::from_utf8_lossy(name);
                    if header_chroms.iter().any(|c| c.name == name) {
                        return Err(lines.error(format!(
                            "chromosome '{name}' has a second '#chromsize:' line"
                        )));
                    }
                    header_chroms.push(Chrom::new(name, length))
                }
                _ => {
                    return Err(lines
                        .error("expected '#chromsize: name length' with a positive whole length"));
                }
            }
        } else if let Some(rest) = line.strip_prefix(b"#columns:") {
            if options.pairs_columns.is_none() {
                columns = Some(columns_from_header(lines, rest)?);
            }
        }
    }
    // Without --pairs-columns or a `#columns:` header, the layout of the first line (a
    // headerless file), else the 4DN default.
    if columns.is_none() && lines.advance()? {
        let fields: Vec<&[u8]> = Fields::new(lines.current()).collect();
        columns = pairs_columns(&fields);
        lines.unread_current();
    }
    let layout = Layout::new(columns.unwrap_or([1, 2, 3, 4]));
    let binner = PairBinner::new(&lines.path, options, header_chroms)?;
    let mut runs: Vec<Run> = Vec::new();
    let mut n_dropped = 0u64;
    let mut first_dropped: Option<String> = None;
    let chunks_per_batch = 2 * rayon::current_num_threads().max(1);
    loop {
        let mut chunks = Vec::with_capacity(chunks_per_batch);
        while chunks.len() < chunks_per_batch {
            match lines.next_chunk(CHUNK_BYTES)? {
                Some(chunk) => chunks.push(chunk),
                None => break,
            }
        }
        if chunks.is_empty() {
            break;
        }
        let parsed: Vec<ParsedChunk> = chunks
            .par_iter()
            .map(|(bytes, first_line)| parse_chunk(&binner, &layout, bytes, *first_line))
            .collect();
        for chunk in parsed {
            if let Some((line, message)) = chunk.error {
                return Err(Error::parse(&lines.path, line, message));
            }
            n_dropped += chunk.n_dropped;
            if first_dropped.is_none() {
                first_dropped = chunk.first_dropped;
            }
            runs.push(chunk.run);
            while runs.len() >= 2 && runs[runs.len() - 2].len() <= 2 * runs[runs.len() - 1].len() {
                let (b, a) = (runs.pop().expect("two runs"), runs.pop().expect("two runs"));
                runs.push(Run::merge(a, b));
            }
        }
    }
    let mut merged = Run::default();
    while let Some(run) = runs.pop() {
        merged = Run::merge(run, merged);
    }
    if merged.keys.is_empty() && n_dropped > 0 {
        return Err(Error::format(
            &lines.path,
            format!(
                "none of the {n_dropped} pairs is on a chromosome of the chromosome table (the \
                 first unknown name is '{}'): check the chromosome names and --pairs-columns",
                first_dropped.unwrap_or_default()
            ),
        ));
    }
    MatrixBuilder::from_sorted(
        binner.bins,
        CountType::Integer,
        merged
            .keys
            .iter()
            .zip(&merged.counts)
            .map(|(&key, &count)| (key >> 32, key & 0xFFFF_FFFF, count as f64)),
    )
}

/// Where the four fields a pair needs are.
struct Layout {
    /// 0-based columns of chrom1, pos1, chrom2, pos2.
    slots: [usize; 4],
    max_column: usize,
}

impl Layout {
    fn new(slots: [usize; 4]) -> Self {
        Layout {
            slots,
            max_column: slots.into_iter().max().unwrap_or(0),
        }
    }
}

/// Sorted pixel keys (`bin1 << 32 | bin2`, `bin1 <= bin2`) with their pair counts.
#[derive(Default)]
struct Run {
    keys: Vec<u64>,
    counts: Vec<u64>,
}

impl Run {
    fn len(&self) -> usize {
        self.keys.len()
    }

    /// Sort `keys` and count repeats.
    fn from_keys(mut keys: Vec<u64>) -> Run {
        keys.sort_unstable();
        let mut run = Run::default();
        for key in keys {
            if run.keys.last() == Some(&key) {
                *run.counts.last_mut().expect("a key") += 1;
            } else {
                run.keys.push(key);
                run.counts.push(1);
            }
        }
        run
    }

    /// The union of two runs, counts of common keys added.
    fn merge(a: Run, b: Run) -> Run {
        if a.keys.is_empty() {
            return b;
        }
        if b.keys.is_empty() {
            return a;
        }
        let mut out = Run {
            keys: Vec::with_capacity(a.len() + b.len()),
            counts: Vec::with_capacity(a.len() + b.len()),
        };
        let (mut i, mut j) = (0, 0);
        while i < a.len() && j < b.len() {
            match a.keys[i].cmp(&b.keys[j]) {
                std::cmp::Ordering::Less => {
                    out.keys.push(a.keys[i]);
                    out.counts.push(a.counts[i]);
                    i += 1;
                }
                std::cmp::Ordering::Greater => {
                    out.keys.push(b.keys[j]);
                    out.counts.push(b.counts[j]);
                    j += 1;
                }
                std::cmp::Ordering::Equal => {
                    out.keys.push(a.keys[i]);
                    out.counts.push(a.counts[i] + b.counts[j]);
                    i += 1;
                    j += 1;
                }
            }
        }
        out.keys.extend_from_slice(&a.keys[i..]);
        out.counts.extend_from_slice(&a.counts[i..]);
        out.keys.extend_from_slice(&b.keys[j..]);
        out.counts.extend_from_slice(&b.counts[j..]);
        out
    }
}

/// What one chunk of lines gave.
struct ParsedChunk {
    run: Run,
    n_dropped: u64,
    first_dropped: Option<String>,
    /// The first bad line: its number and the message.
    error: Option<(u64, String)>,
}

/// Parse the pairs of a chunk of whole lines whose first is line `first_line`.
fn parse_chunk(binner: &PairBinner, layout: &Layout, bytes: &[u8], first_line: u64) -> ParsedChunk {
    let mut keys = Vec::with_capacity(bytes.len() / 48);
    let (mut cache1, mut cache2) = (0usize, 0usize);
    let mut n_dropped = 0u64;
    let mut first_dropped: Option<String> = None;
    let slots = layout.slots;
    let max_column = layout.max_column;
    let mut error = None;
    let body = bytes.strip_suffix(b"\n").unwrap_or(bytes);
    for (k, raw) in body.split(|&b| b == b'\n').enumerate() {
        let mut len = raw.len();
        while len > 0 && matches!(raw[len - 1], b'\r' | b' ' | b'\t') {
            len -= 1;
        }
        let line = &raw[..len];
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        let line_number = first_line + k as u64;
        let mut fields: [&[u8]; 4] = [&[]; 4];
        let mut n_columns = 0usize;
        for (column, field) in Fields::new(line).enumerate() {
            for (slot, &wanted) in slots.iter().enumerate() {
                if wanted == column {
                    fields[slot] = field;
                }
            }
            n_columns = column + 1;
            if column == max_column {
                break;
            }
        }
        if n_columns <= max_column {
            error = Some((
                line_number,
                format!(
                    "expected at least {} columns (chrom1, pos1, chrom2, pos2 in columns {}, {}, \
                     {}, {}), found {n_columns}",
                    max_column + 1,
                    slots[0] + 1,
                    slots[1] + 1,
                    slots[2] + 1,
                    slots[3] + 1
                ),
            ));
            break;
        }
        let (Some(chrom1), Some(chrom2)) = (
            binner.chrom(fields[0], &mut cache1),
            binner.chrom(fields[2], &mut cache2),
        ) else {
            n_dropped += 1;
            if first_dropped.is_none() {
                let unknown = if binner.chrom(fields[0], &mut cache1).is_none() {
                    fields[0]
                } else {
                    fields[2]
                };
                first_dropped = Some(show(unknown));
            }
            continue;
        };
        let bins = binner
            .bin(chrom1, fields[1], 1)
            .and_then(|b1| binner.bin(chrom2, fields[3], 2).map(|b2| (b1, b2)));
        match bins {
            Ok((bin1, bin2)) => keys.push((bin1.min(bin2) << 32) | bin1.max(bin2)),
            Err(message) => {
                error = Some((line_number, message));
                break;
            }
        }
    }
    ParsedChunk {
        run: Run::from_keys(keys),
        n_dropped,
        first_dropped,
        error,
    }
}

#[cfg(test)]
mod tests {
    use tempfile::TempDir;

    use super::super::test_support::*;
    use super::super::{TextFormat, read_matrix};
    use super::CHUNK_BYTES;
    use crate::error::Error;
    use crate::io::OpenOptions;
    use crate::matrix::CountType;

    #[test]
    fn pairs_fixture_is_binned_as_cooler_cload_pairs() {
        let options = OpenOptions {
            text_format: Some(TextFormat::Pairs),
            pairs_columns: Some([1, 2, 4, 5]),
            ..bins_options()
        };
        let matrix = read_matrix(PAIRS, &options).unwrap();
        assert_fixture_figures(&matrix);
        // cooler's pixels are exactly those of the BG2 fixture (cmp of the two dumps).
        assert_eq!(matrix, fixture_matrix());
        // Same with chromosome sizes and a bin size, and from the decompressed file.
        let dir = TempDir::new().unwrap();
        let sizes: String = matrix
            .bins()
            .chroms()
            .iter()
            .map(|c| format!("{}\t{}\n", c.name, c.length_bp))
            .collect();
        let options = OpenOptions {
            text_format: Some(TextFormat::Pairs),
            pairs_columns: Some([1, 2, 4, 5]),
            chrom_sizes: Some(write_plain(&dir, "hg19.sizes", &sizes)),
            text_resolution: Some(2_000_000),
            ..OpenOptions::default()
        };
        let plain = write_plain(&dir, "pairs.txt", &gunzip(PAIRS));
        assert_eq!(
            read_matrix(plain.to_str().unwrap(), &options).unwrap(),
            matrix
        );
    }

    #[test]
    fn pairs_on_chromosomes_missing_from_the_sizes_are_dropped_as_cooler_does() {
        // printf 'chr21\t48129895\nchr22\t51304566\nchrX\t155270560\n' > sub.sizes
        // cooler cload pairs -c1 1 -p1 2 -c2 4 -p2 5 sub.sizes:2000000 \
        //   hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz sub.cool
        // cooler info sub.cool -> nbins 129, nnz 1224, sum 5515
        // cooler dump sub.cool -> (46,46)=81, (40,40)=63, (44,44)=58, (11,119)=1
        let dir = TempDir::new().unwrap();
        let options = OpenOptions {
            text_format: Some(TextFormat::Pairs),
            pairs_columns: Some([1, 2, 4, 5]),
            chrom_sizes: Some(write_plain(
                &dir,
                "sub.sizes",
                "chr21\t48129895\nchr22\t51304566\nchrX\t155270560\n",
            )),
            text_resolution: Some(2_000_000),
            ..OpenOptions::default()
        };
        let matrix = read_matrix(PAIRS, &options).unwrap();
        assert_eq!(matrix.bins().n_bins(), 129);
        assert_eq!(matrix.nnz(), 1224);
        assert_eq!(matrix.sum(), 5515.0);
        for (i, j, count) in [
            (46, 46, 81.0),
            (40, 40, 63.0),
            (44, 44, 58.0),
            (11, 119, 1.0),
        ] {
            assert_eq!(matrix.get(i, j), count, "pixel ({i}, {j})");
        }
    }

    #[test]
    fn pairs_positions_are_one_based_as_in_cooler() {
        // printf 'c1\t100\n' > tiny.sizes
        // printf 'c1\t10\t+\tc1\t11\t+\nc1\t1\t+\tc1\t20\t+\nc1\t100\t+\tc1\t50\t+\n' > tiny.pairs
        // cooler cload pairs -c1 1 -p1 2 -c2 4 -p2 5 tiny.sizes:10 tiny.pairs tiny.cool
        // cooler dump tiny.cool -> "0 1 2" and "4 9 1"
        // (with --zero-based, position 10 would fall in bin 1 instead of 0.)
        let dir = TempDir::new().unwrap();
        let options = OpenOptions {
            text_format: Some(TextFormat::Pairs),
            pairs_columns: Some([1, 2, 4, 5]),
            chrom_sizes: Some(write_plain(&dir, "tiny.sizes", "c1\t100\n")),
            text_resolution: Some(10),
            ..OpenOptions::default()
        };
        let pairs = "c1\t10\t+\tc1\t11\t+\nc1\t1\t+\tc1\t20\t+\nc1\t100\t+\tc1\t50\t+\n";
        let matrix = read_str(&dir, pairs, &options).unwrap();
        let pixels = matrix.all_pixels();
        assert_eq!(pixels.bin1, vec![0, 4]);
        assert_eq!(pixels.bin2, vec![1, 9]);
        assert_eq!(pixels.count, vec![2.0, 1.0]);
        assert_eq!(matrix.count_type(), CountType::Integer);
        // cooler rejects position 0 (negative once made 0-based) and positions past the end.
        let (line, message) = parse_error(read_str(&dir, "c1\t0\t+\tc1\t11\t+\n", &options));
        assert_eq!(line, 1);
        assert!(message.contains("pos1 0 is outside c1"), "{message}");
        let (line, message) = parse_error(read_str(
            &dir,
            "c1\t5\t+\tc1\t11\t+\nc1\t5\t+\tc1\t101\t+\n",
            &options,
        ));
        assert_eq!(line, 2);
        assert!(message.contains("pos2 101 is outside c1"), "{message}");
        assert!(message.contains("1-based, from 1 to 100"), "{message}");
        // With --zero-based the same positions shift by one bin at the boundaries.
        let zero = OpenOptions {
            pairs_zero_based: true,
            ..options.clone()
        };
        let matrix = read_str(&dir, "c1\t0\t+\tc1\t10\t+\nc1\t99\t+\tc1\t99\t+\n", &zero).unwrap();
        let pixels = matrix.all_pixels();
        assert_eq!((pixels.bin1, pixels.bin2), (vec![0, 9], vec![1, 9]));
        let (_, message) = parse_error(read_str(&dir, "c1\t5\t+\tc1\t100\t+\n", &zero));
        assert!(message.contains("0-based, from 0 to 99"), "{message}");
    }

    #[test]
    fn pairs_4dn_headers_give_sizes_and_columns() {
        let dir = TempDir::new().unwrap();
        let pairs = "## pairs format v1.0\n\
                     #shape: upper triangle\n\
                     #chromsize: chr1 100\n\
                     #chromsize: chr2 50\n\
                     #columns: readID chr1 pos1 chr2 pos2 strand1 strand2\n\
                     r1\tchr1\t10\tchr1\t11\t+\t-\n\
                     r2\tchr2\t50\tchr1\t1\t+\t-\n\
                     r3\tchr1\t1\tchr2\t50\t+\t-\n\
                     r4\t!\t0\tchr1\t5\t+\t-\n";
        let options = OpenOptions {
            text_resolution: Some(10),
            ..OpenOptions::default()
        };
        let path = write_gz(&dir, "reads.pairs.gz", pairs);
        let matrix = read_matrix(path.to_str().unwrap(), &options).unwrap();
        assert_eq!(matrix.bins().n_bins(), 15);
        assert_eq!(matrix.get(0, 1), 1.0);
        assert_eq!(matrix.get(0, 14), 2.0);
        assert_eq!(matrix.nnz(), 2);
        // A #columns header in another order is followed.
        let pairs =
            "#chromsize: chr1 100\n#columns: chr1 pos1 chr2 pos2 readID\nchr1\t25\tchr1\t95\tr1\n";
        let matrix = read_str(
            &dir,
            pairs,
            &OpenOptions {
                text_format: Some(TextFormat::Pairs),
                text_resolution: Some(10),
                ..OpenOptions::default()
            },
        )
        .unwrap();
        assert_eq!(matrix.get(2, 9), 1.0);
        // The format is sniffed from the header when the name says nothing.
        let matrix = read_str(&dir, pairs, &options).unwrap();
        assert_eq!(matrix.sum(), 1.0);
        // A chromosome listed twice is named with its line.
        let twice = "#chromsize: chr1 100\n#chromsize: chr2 50\n#chromsize: chr1 100\n\
                     #columns: readID chr1 pos1 chr2 pos2\nr1\tchr1\t25\tchr1\t95\n";
        let (line, message) = parse_error(read_str(&dir, twice, &options));
        assert_eq!(line, 3);
        assert!(
            message.contains("'chr1' has a second '#chromsize:'"),
            "{message}"
        );
    }

    #[test]
    fn pairs_need_a_bin_size_and_chromosomes() {
        let dir = TempDir::new().unwrap();
        let pairs = "r1\tchr1\t10\tchr1\t11\t+\t-\n";
        let path = write_plain(&dir, "reads.pairs", pairs);
        let path = path.to_str().unwrap();
        let message = argument_message(read_matrix(path, &OpenOptions::default()));
        assert!(message.contains("pass --bin-size N"), "{message}");
        let options = OpenOptions {
            text_resolution: Some(10),
            ..OpenOptions::default()
        };
        let message = argument_message(read_matrix(path, &options));
        assert!(message.contains("pass --chrom-sizes FILE"), "{message}");
        // All pairs on unknown chromosomes: probably the wrong columns.
        let options = small_options(&dir, TextFormat::Pairs);
        let result = read_str(&dir, "r1\tchrZ\t10\tchrZ\t11\n", &options);
        match result {
            Err(Error::Format { message, .. }) => {
                assert!(
                    message.contains("first unknown name is 'chrZ'"),
                    "{message}"
                )
            }
            other => panic!("expected a format error, got {other:?}"),
        }
    }

    /// Many chunks of lines: the counts equal a naive count, line by line, and an error deep in
    /// the file names its own line.
    #[test]
    fn chunks_parsed_in_parallel_give_the_naive_counts_and_line_numbers() {
        let dir = TempDir::new().unwrap();
        let options = small_options(&dir, TextFormat::Pairs);
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut next = move |m: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % m
        };
        let lengths = [("chr1", 100u64), ("chr2", 50), ("chrUn", 30)];
        let mut text = String::from("#comment\n");
        let mut naive: std::collections::BTreeMap<(u64, u64), f64> = Default::default();
        let n_lines = 3 * CHUNK_BYTES / 40; // several chunks
        for k in 0..n_lines {
            let (c1, l1) = lengths[next(3) as usize];
            let (c2, l2) = lengths[next(3) as usize];
            let (p1, p2) = (1 + next(l1), 1 + next(l2));
            text.push_str(&format!("r{k}\t{c1}\t{p1}\t{c2}\t{p2}\t+\t-\n"));
            if k % 1000 == 7 {
                text.push_str("#a comment between pairs\n\n");
            }
            if c1 == "chrUn" || c2 == "chrUn" {
                continue;
            }
            let bin = |c: &str, p: u64| (p - 1) / 10 + if c == "chr2" { 10 } else { 0 };
            let (b1, b2) = (bin(c1, p1), bin(c2, p2));
            *naive.entry((b1.min(b2), b1.max(b2))).or_default() += 1.0;
        }
        assert!(text.len() > 2 * CHUNK_BYTES);
        let matrix = read_str(&dir, &text, &options).unwrap();
        let pixels = matrix.all_pixels();
        let got: Vec<((u64, u64), f64)> = (0..pixels.len())
            .map(|k| ((pixels.bin1[k], pixels.bin2[k]), pixels.count[k]))
            .collect();
        let want: Vec<((u64, u64), f64)> = naive.into_iter().collect();
        assert_eq!(got, want);
        // a bad position near the end: its line number counts every line before it
        let n_before = text.lines().count();
        text.push_str("rX\tchr1\t5\tchr2\t51\n");
        let (line, message) = parse_error(read_str(&dir, &text, &options));
        assert_eq!(line, n_before as u64 + 1);
        assert!(message.starts_with("pos2 51 is outside chr2"), "{message}");
    }

    #[test]
    fn malformed_pairs_lines_are_reported() {
        let dir = TempDir::new().unwrap();
        let options = small_options(&dir, TextFormat::Pairs);
        let (line, message) = parse_error(read_str(
            &dir,
            "#comment\nr1\tchr1\t10\tchr1\t11\nr2\tchr1\t10\n",
            &options,
        ));
        assert_eq!(line, 3);
        assert_eq!(
            message,
            "expected at least 5 columns (chrom1, pos1, chrom2, pos2 in columns 2, 3, 4, 5), \
             found 3"
        );
        let (line, message) = parse_error(read_str(&dir, "r1\tchr1\t1e3\tchr1\t11\n", &options));
        assert_eq!(line, 1);
        assert_eq!(
            message,
            "pos1 '1e3' is not a position (expected a whole number)"
        );
    }
}
