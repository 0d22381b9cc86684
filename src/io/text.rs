//! Text pixel tables, pairs and dense matrices: readers and writers.
//!
//! # Layouts
//!
//! Columns are separated by tabs; a line without any tab is split on runs of spaces instead. Empty
//! lines and lines starting with `#` are skipped. Every input may be gzip-compressed (recognised by
//! its magic bytes `1f 8b`, whatever its name); `-` is standard input for readers and standard
//! output for writers.
//!
//! | [`TextFormat`] | columns | bin table from |
//! |---|---|---|
//! | [`Bg2`](TextFormat::Bg2) | `chrom1 start1 end1 chrom2 start2 end2 count [ignored...]`, as `cooler dump --join` writes and `cooler load -f bg2` reads | `--bins BED`, or `--chrom-sizes FILE --bin-size N` |
//! | [`Coo`](TextFormat::Coo) | `bin1_id bin2_id count [ignored...]` with 0-based bin ids, as `cooler dump` writes | same |
//! | [`Pairs`](TextFormat::Pairs) | 4DN `.pairs` (`readID chr1 pos1 chr2 pos2 ...`) or any pair text (`--pairs-columns`) | `--bin-size N` with `#chromsize:` header lines, `--chrom-sizes FILE` or `--bins BED` |
//! | [`Dense`](TextFormat::Dense) | a square `n_bins x n_bins` matrix of numbers, one row per line | `--bins BED`, or `--chrom-sizes FILE --bin-size N` |
//!
//! BG2 and COO tables may start with one header line (a first data line whose first position or
//! bin id and whose count are both not numbers is skipped). Each BG2 pixel must name a bin of the table exactly: a known chromosome, a
//! start that is a bin start and the end of that bin. Pixels may come in any order and in either
//! triangle: lower-triangle pixels are mirrored and duplicates summed (see
//! [`MatrixBuilder`]). Counts must be finite and non-negative; the matrix gets
//! [`CountType::Integer`] when every count is a whole number, [`CountType::Float`] otherwise.
//!
//! A dense matrix must be symmetric: its upper triangle is read and every lower-triangle value must
//! equal its mirror (to a relative tolerance of 1e-9, so that matrices printed from floating-point
//! computations pass), else the line is reported.
//!
//! # Binning pairs
//!
//! Pairs are binned exactly as `cooler cload pairs` (cooler 0.11) bins them with its default
//! options:
//!
//! - positions are **1-based** (the 4DN pairs convention and cooler's default without
//!   `--zero-based`, which `OpenOptions::pairs_zero_based` mirrors): a pair at `pos` falls in the bin containing the 0-based coordinate `pos - 1`,
//!   i.e. bin `chrom_offset + (pos - 1) / bin_size_bp` for fixed bins;
//! - pairs with a chromosome that is not in the chromosome table are dropped (cooler drops them
//!   silently); position 0 and positions past the chromosome's length are errors (cooler raises
//!   `BadInputError` for them, except for `pos == length + 1`, which it accepts and bins out of
//!   range: that is an error here too);
//! - each pair counts 1; pairs in the lower triangle are reflected (`unique` copy status), so the
//!   stored count of pixel `(i, j)` is the number of pairs in `(i, j)` plus those in `(j, i)`.
//!
//! The chromosome table is, in order of precedence: `--bins BED` (its bins are used as they are),
//! `--chrom-sizes FILE`, the `#chromsize: name length` header lines. The column layout is
//! `--pairs-columns` (1-based `chrom1,pos1,chrom2,pos2`), else the `#columns:` header line
//! (`chr1 pos1 chr2 pos2`), else the 4DN default `2,3,4,5`. Pairs are streamed: memory is the
//! binned pixel map, not the pairs.
//!
//! # Writing
//!
//! [`write_text`] streams the pixels of any [`MatrixReader`]: BG2 (exactly `cooler dump --join`),
//! COO (exactly `cooler dump`) or the full symmetric dense matrix (at most
//! [`MAX_DENSE_BINS`] bins). Integer counts are printed without a decimal point; real counts with
//! the shortest representation that reads back to the same `f64` (Rust's `{:?}`, which keeps a
//! `.0` on whole numbers as `cooler dump` does). A file is written to a temporary file next to the
//! target and renamed when complete; a name ending in `.gz` is gzip-compressed.
//!
//! # Threads
//!
//! A gzip-compressed input is inflated on one helper thread while the calling thread parses, so
//! that decompression and parsing overlap. Chunks are handed over in order: results never depend
//! on the scheduling.

use std::collections::{HashMap, VecDeque};
use std::fs::File;
use std::hash::{BuildHasherDefault, Hasher};
use std::io::{BufRead, BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::sync::{Arc, Mutex};

use flate2::bufread::MultiGzDecoder;
use flate2::write::GzEncoder;
use flate2::Compression;

use crate::error::{Error, Result};
use crate::genome::{Bin, BinTable, Chrom};
use crate::io::{MatrixReader, OpenOptions};
use crate::matrix::{ContactMatrix, CountType, MatrixBuilder};

/// A text layout (see the [module documentation](self) for the columns of each).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextFormat {
    /// `chrom1 start1 end1 chrom2 start2 end2 count` (`cooler dump --join`).
    Bg2,
    /// `bin1_id bin2_id count`, 0-based bin ids (`cooler dump`), with a separate bin table.
    Coo,
    /// Read pairs (4DN `.pairs` or pair text), binned on the fly.
    Pairs,
    /// A square dense matrix, one row per line.
    Dense,
}

/// The largest number of bins [`write_text`] writes as a dense matrix.
pub const MAX_DENSE_BINS: usize = 20_000;

/// Read buffer size.
const BUFFER_BYTES: usize = 1 << 18;

/// Values per band when writing a dense matrix (32 MB of `f64`).
const DENSE_BAND_VALUES: usize = 1 << 22;

/// Relative tolerance of the symmetry check of dense matrices.
const DENSE_SYMMETRY_TOLERANCE: f64 = 1e-9;

/// Guess the format from the file name (a trailing `.gz` is ignored): `.bg2` / `.bedpe` -> BG2,
/// `.pairs` / `.pairsam` -> pairs, `.coo` / `.pixels` -> COO, `.dense` / `.mat` / `.matrix` ->
/// dense.
pub fn guess_format(path: &str) -> Option<TextFormat> {
    let lower = path.to_ascii_lowercase();
    let name = lower.strip_suffix(".gz").unwrap_or(&lower);
    let (_, extension) = name.rsplit_once('.')?;
    match extension {
        "bg2" | "bedpe" => Some(TextFormat::Bg2),
        "pairs" | "pairsam" => Some(TextFormat::Pairs),
        "coo" | "pixels" => Some(TextFormat::Coo),
        "dense" | "mat" | "matrix" => Some(TextFormat::Dense),
        _ => None,
    }
}

/// Read a text matrix into memory (`path` `-` is standard input).
///
/// The format is `options.text_format`, else guessed from the name ([`guess_format`]), else sniffed
/// from the first lines: a `## pairs format`, `#columns:` or `#chromsize:` header means pairs, a
/// data line of 7 or more columns with numeric columns 2, 3, 5 and 6 means BG2, exactly 3 numeric
/// columns mean COO.
pub fn read_matrix(path: &str, options: &OpenOptions) -> Result<ContactMatrix> {
    let mut lines = LineReader::open(Path::new(path))?;
    let format = match options.text_format.or_else(|| guess_format(path)) {
        Some(format) => format,
        None => lines.sniff_format()?.ok_or_else(|| {
            Error::format(
                path,
                "cannot tell the text format from the name or the first lines: pass --format \
                 (bg2, coo, pairs or dense)",
            )
        })?,
    };
    match format {
        TextFormat::Bg2 => read_bg2(&mut lines, bin_table_for(path, "a BG2 table", options)?),
        TextFormat::Coo => read_coo(&mut lines, bin_table_for(path, "a COO table", options)?),
        TextFormat::Dense => {
            read_dense(&mut lines, bin_table_for(path, "a dense matrix", options)?)
        }
        TextFormat::Pairs => read_pairs(&mut lines, options),
    }
}

/// Read a chromosome sizes file: `name<TAB>length` per line (extra columns ignored, `#` comments
/// skipped, gzip allowed), in the order of the file.
pub fn read_chrom_sizes(path: &Path) -> Result<Vec<Chrom>> {
    let mut lines = LineReader::open(path)?;
    let mut chroms: Vec<Chrom> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    while lines.advance()? {
        let line = lines.current();
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        let mut fields = Fields::new(line);
        let (Some(name), Some(length)) = (fields.next(), fields.next()) else {
            return Err(lines.error(format!(
                "expected 2 columns (name length), found 1: '{}'",
                show(line)
            )));
        };
        let length_bp = match parse_u64(length) {
            Some(0) | None => {
                return Err(lines.error(format!(
                    "length '{}' of '{}' is not a positive whole number",
                    show(length),
                    show(name)
                )))
            }
            Some(n) => n,
        };
        let name = String::from_utf8_lossy(name).into_owned();
        if !seen.insert(name.clone()) {
            return Err(lines.error(format!("chromosome '{name}' appears twice")));
        }
        chroms.push(Chrom::new(name, length_bp));
    }
    if chroms.is_empty() {
        return Err(Error::format(
            path,
            "no chromosome in the chromosome sizes file (expected 'name<TAB>length' lines)",
        ));
    }
    Ok(chroms)
}

/// Read a bin table from a BED file: `chrom start end` per line (extra columns ignored, gzip
/// allowed; `#`, `track` and `browser` lines and one header line skipped).
///
/// Bins must be grouped by chromosome and tile each chromosome from 0; a chromosome's length is the
/// end of its last bin. A table of equal-size bins becomes a fixed table ([`BinTable::from_bins`]).
pub fn read_bins_bed(path: &Path) -> Result<BinTable> {
    let mut lines = LineReader::open(path)?;
    let mut chroms: Vec<Chrom> = Vec::new();
    let mut ids: HashMap<Vec<u8>, usize> = HashMap::new();
    let mut bins: Vec<Bin> = Vec::new();
    let mut first_data_line = true;
    while lines.advance()? {
        let line = lines.current();
        if line.is_empty()
            || line[0] == b'#'
            || line.starts_with(b"track")
            || line.starts_with(b"browser")
        {
            continue;
        }
        let fields: Vec<&[u8]> = Fields::new(line).take(3).collect();
        if fields.len() < 3 {
            return Err(lines.error(format!(
                "expected 3 columns (chrom start end), found {}",
                fields.len()
            )));
        }
        let (start, end) = match (parse_u64(fields[1]), parse_u64(fields[2])) {
            (Some(start), Some(end)) => (start, end),
            _ if first_data_line => {
                first_data_line = false;
                continue;
            }
            _ => {
                return Err(lines.error(format!(
                    "start '{}' and end '{}' must be whole numbers",
                    show(fields[1]),
                    show(fields[2])
                )))
            }
        };
        first_data_line = false;
        let chrom_id = match ids.get(fields[0]) {
            Some(&id) => id,
            None => {
                let id = chroms.len();
                ids.insert(fields[0].to_vec(), id);
                chroms.push(Chrom::new(String::from_utf8_lossy(fields[0]), 0));
                id
            }
        };
        let expected_start = match bins.last() {
            Some(last) if last.chrom_id == chrom_id => last.end,
            Some(_) if chroms[chrom_id].length_bp > 0 => {
                return Err(lines.error(format!(
                    "chromosome '{}' appears again after other chromosomes: bins must be grouped \
                     by chromosome",
                    chroms[chrom_id].name
                )))
            }
            _ => 0,
        };
        if start != expected_start || end <= start {
            return Err(lines.error(format!(
                "bin {}:{start}-{end} does not continue the tiling of '{}': expected a bin starting \
                 at {expected_start} and ending after it",
                chroms[chrom_id].name, chroms[chrom_id].name
            )));
        }
        chroms[chrom_id].length_bp = end;
        bins.push(Bin {
            chrom_id,
            start,
            end,
        });
    }
    if bins.is_empty() {
        return Err(Error::format(
            path,
            "no bin in the bins BED file (expected 'chrom start end' lines)",
        ));
    }
    BinTable::from_bins(chroms, &bins, None).map_err(|e| Error::format(path, e.to_string()))
}

/// Write the matrix of `reader` to `path` (`-` for standard output; a name ending in `.gz` is
/// gzip-compressed) in `format`, streaming its pixels.
///
/// A file is first written next to the target under a temporary name, then renamed, so that a
/// failure never leaves a partial output. Pairs cannot be written (a matrix does not hold read
/// pairs) and dense output is refused above [`MAX_DENSE_BINS`] bins: both are
/// [`Error::Invalid`]. A closed standard output comes back as an [`Error::Io`] of kind
/// `BrokenPipe`.
pub fn write_text(reader: &dyn MatrixReader, path: &str, format: TextFormat) -> Result<()> {
    let n_bins = reader.bins().n_bins();
    match format {
        TextFormat::Pairs => {
            return Err(Error::Invalid(format!(
                "{path}: cannot write pairs: a contact matrix does not hold read pairs (write bg2, \
                 coo or dense instead)"
            )))
        }
        TextFormat::Dense if n_bins > MAX_DENSE_BINS => {
            return Err(Error::Invalid(format!(
                "{path}: a dense matrix of {n_bins} x {n_bins} bins is too large to write as text \
                 (at most {MAX_DENSE_BINS} bins): write bg2 or coo, or select a coarser resolution"
            )))
        }
        _ => {}
    }
    if path == "-" {
        let mut out = BufWriter::with_capacity(1 << 16, std::io::stdout().lock());
        write_body(reader, format, &mut out, path)?;
        return out.flush().map_err(|e| Error::io(path, e));
    }
    let (pending, file) = PendingOutput::create(Path::new(path))?;
    let buffered = BufWriter::with_capacity(BUFFER_BYTES, file);
    let buffered = if path.ends_with(".gz") {
        let mut encoder = GzEncoder::new(buffered, Compression::default());
        write_body(reader, format, &mut encoder, path)?;
        encoder.finish().map_err(|e| Error::io(path, e))?
    } else {
        let mut buffered = buffered;
        write_body(reader, format, &mut buffered, path)?;
        buffered
    };
    buffered
        .into_inner()
        .map_err(|e| Error::io(path, e.into_error()))?;
    pending.persist()
}

// ---------------------------------------------------------------------------------------------
// Input: lines of a plain or gzip-compressed file or of standard input.

/// Lines of an input, with their 1-based numbers, for parse errors.
struct LineReader {
    input: Box<dyn BufRead>,
    /// The path as shown in messages (`-` for standard input).
    path: PathBuf,
    line: Vec<u8>,
    /// Length of the current line without its terminator and trailing blanks.
    len: usize,
    /// Lines read while sniffing the format, handed out again before the input.
    replay: VecDeque<Vec<u8>>,
    line_number: u64,
}

impl LineReader {
    /// Open `path` (`-` for standard input), decompressing gzip transparently.
    fn open(path: &Path) -> Result<Self> {
        let mut raw: Box<dyn BufRead + Send> = if path == Path::new("-") {
            Box::new(BufReader::with_capacity(BUFFER_BYTES, std::io::stdin()))
        } else {
            let file = File::open(path).map_err(|e| Error::io(path, e))?;
            Box::new(BufReader::with_capacity(BUFFER_BYTES, file))
        };
        let head = raw.fill_buf().map_err(|e| Error::io(path, e))?;
        let input: Box<dyn BufRead> = if head.starts_with(&[0x1f, 0x8b]) {
            Decompressed::spawn(MultiGzDecoder::new(raw))
        } else {
            raw
        };
        Ok(LineReader {
            input,
            path: path.to_path_buf(),
            line: Vec::with_capacity(256),
            len: 0,
            replay: VecDeque::new(),
            line_number: 0,
        })
    }

    /// Move to the next line; false at the end of the input.
    fn advance(&mut self) -> Result<bool> {
        if let Some(line) = self.replay.pop_front() {
            self.line = line;
        } else {
            self.line.clear();
            let n = self
                .input
                .read_until(b'\n', &mut self.line)
                .map_err(|e| Error::io(&self.path, e))?;
            if n == 0 {
                return Ok(false);
            }
        }
        self.line_number += 1;
        let mut len = self.line.len();
        while len > 0 && matches!(self.line[len - 1], b'\n' | b'\r' | b' ' | b'\t') {
            len -= 1;
        }
        self.len = len;
        Ok(true)
    }

    /// The current line, without its terminator and trailing blanks.
    fn current(&self) -> &[u8] {
        &self.line[..self.len]
    }

    /// A parse error at the current line.
    fn error(&self, message: impl Into<String>) -> Error {
        Error::parse(&self.path, self.line_number, message)
    }

    /// Look at the first lines to recognise the format, then rewind to the start.
    fn sniff_format(&mut self) -> Result<Option<TextFormat>> {
        let mut seen = Vec::new();
        let mut format = None;
        let mut n_data_lines = 0;
        while self.advance()? {
            let line = self.current().to_vec();
            seen.push(line.clone());
            if line.starts_with(b"## pairs format")
                || line.starts_with(b"#columns:")
                || line.starts_with(b"#chromsize:")
            {
                format = Some(TextFormat::Pairs);
                break;
            }
            if line.is_empty() || line[0] == b'#' {
                continue;
            }
            n_data_lines += 1;
            let fields: Vec<&[u8]> = Fields::new(&line).collect();
            let numeric = |k: usize| fields.get(k).is_some_and(|f| parse_number(f).is_some());
            if fields.len() >= 7 && [1, 2, 4, 5].into_iter().all(numeric) {
                format = Some(TextFormat::Bg2);
                break;
            }
            if fields.len() == 3 && (0..3).all(numeric) {
                format = Some(TextFormat::Coo);
                break;
            }
            // The first data line may be a header: look at one more.
            if n_data_lines >= 2 {
                break;
            }
        }
        seen.extend(self.replay.drain(..));
        self.replay = seen.into();
        self.line_number = 0;
        Ok(format)
    }
}

/// Bytes decompressed per chunk by the decompression thread.
const CHUNK_BYTES: usize = 1 << 20;

/// A gzip stream inflated on a helper thread, so that decompression overlaps parsing. Chunks
/// arrive in order, so the result does not depend on the threading.
struct Decompressed {
    chunks: Receiver<std::io::Result<Vec<u8>>>,
    chunk: Vec<u8>,
    position: usize,
    finished: bool,
}

impl Decompressed {
    /// Inflate `source` on a helper thread (or in this one when no thread can be started).
    fn spawn<R: Read + Send + 'static>(source: R) -> Box<dyn BufRead> {
        let (sender, chunks) = sync_channel(4);
        let shared = Arc::new(Mutex::new(Some(source)));
        let for_thread = Arc::clone(&shared);
        let spawned = std::thread::Builder::new()
            .name("gzip-reader".into())
            .spawn(move || {
                let source = for_thread.lock().ok().and_then(|mut s| s.take());
                if let Some(source) = source {
                    inflate(source, &sender);
                }
            });
        match spawned {
            Ok(_) => Box::new(Decompressed {
                chunks,
                chunk: Vec::new(),
                position: 0,
                finished: false,
            }),
            Err(_) => match shared.lock().ok().and_then(|mut s| s.take()) {
                Some(source) => Box::new(BufReader::with_capacity(BUFFER_BYTES, source)),
                None => Box::new(std::io::empty()),
            },
        }
    }
}

/// Read `source` to its end in chunks, sending them (and the first error) to `sender`; stop early
/// when the receiving side is gone.
fn inflate<R: Read>(mut source: R, sender: &SyncSender<std::io::Result<Vec<u8>>>) {
    loop {
        let mut chunk = vec![0u8; CHUNK_BYTES];
        let mut filled = 0;
        while filled < chunk.len() {
            match source.read(&mut chunk[filled..]) {
                Ok(0) => break,
                Ok(n) => filled += n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => {
                    let _ = sender.send(Err(e));
                    return;
                }
            }
        }
        chunk.truncate(filled);
        let end = filled == 0;
        if sender.send(Ok(chunk)).is_err() || end {
            return;
        }
    }
}

impl Read for Decompressed {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let available = self.fill_buf()?;
        let n = available.len().min(buf.len());
        buf[..n].copy_from_slice(&available[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl BufRead for Decompressed {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        while self.position == self.chunk.len() && !self.finished {
            match self.chunks.recv() {
                Ok(Ok(chunk)) => {
                    self.finished = chunk.is_empty();
                    self.chunk = chunk;
                    self.position = 0;
                }
                Ok(Err(e)) => {
                    self.finished = true;
                    return Err(e);
                }
                Err(_) => {
                    self.finished = true;
                    return Err(std::io::Error::other(
                        "the decompression thread stopped unexpectedly",
                    ));
                }
            }
        }
        Ok(&self.chunk[self.position..])
    }

    fn consume(&mut self, amount: usize) {
        self.position = (self.position + amount).min(self.chunk.len());
    }
}
/// The columns of a line: split on tabs when the line has one, else on runs of spaces.
struct Fields<'a> {
    rest: &'a [u8],
    tabs: bool,
    done: bool,
}

impl<'a> Fields<'a> {
    fn new(line: &'a [u8]) -> Self {
        Fields {
            rest: line,
            tabs: line.contains(&b'\t'),
            done: false,
        }
    }
}

/// The first `N` fields of `line` and how many there were (at most `N`).
fn first_fields<const N: usize>(line: &[u8]) -> ([&[u8]; N], usize) {
    let mut columns: [&[u8]; N] = [&[]; N];
    let mut n_columns = 0;
    for field in Fields::new(line).take(N) {
        columns[n_columns] = field;
        n_columns += 1;
    }
    (columns, n_columns)
}

impl<'a> Iterator for Fields<'a> {
    type Item = &'a [u8];

    fn next(&mut self) -> Option<&'a [u8]> {
        if self.done {
            return None;
        }
        if self.tabs {
            match self.rest.iter().position(|&b| b == b'\t') {
                Some(k) => {
                    let field = &self.rest[..k];
                    self.rest = &self.rest[k + 1..];
                    Some(field)
                }
                None => {
                    self.done = true;
                    Some(self.rest)
                }
            }
        } else {
            let Some(start) = self.rest.iter().position(|&b| b != b' ') else {
                self.done = true;
                return None;
            };
            let rest = &self.rest[start..];
            let end = rest.iter().position(|&b| b == b' ').unwrap_or(rest.len());
            self.rest = &rest[end..];
            Some(&rest[..end])
        }
    }
}

/// A whole number written with ASCII digits only.
fn parse_u64(field: &[u8]) -> Option<u64> {
    if field.is_empty() {
        return None;
    }
    let mut value: u64 = 0;
    if field.len() < 20 {
        // At most 19 digits: no overflow.
        for &byte in field {
            let digit = byte.wrapping_sub(b'0');
            if digit > 9 {
                return None;
            }
            value = value * 10 + u64::from(digit);
        }
        return Some(value);
    }
    for &byte in field {
        let digit = byte.wrapping_sub(b'0');
        if digit > 9 {
            return None;
        }
        value = value.checked_mul(10)?.checked_add(u64::from(digit))?;
    }
    Some(value)
}

/// Any number Rust's `f64` parser accepts (including `inf` and `nan`, rejected by callers).
fn parse_number(field: &[u8]) -> Option<f64> {
    match parse_u64(field) {
        Some(value) if value < (1 << 53) => Some(value as f64),
        _ => std::str::from_utf8(field).ok()?.parse::<f64>().ok(),
    }
}

/// A field as shown in messages (lossy UTF-8, at most 40 characters).
fn show(field: &[u8]) -> String {
    let text = String::from_utf8_lossy(field);
    match text.char_indices().nth(40) {
        Some((cut, _)) => format!("{}...", &text[..cut]),
        None => text.into_owned(),
    }
}

/// Parse a count: a finite number >= 0.
fn parse_count(lines: &LineReader, field: &[u8]) -> Result<f64> {
    let value = parse_number(field).ok_or_else(|| {
        lines.error(format!(
            "count '{}' is not a number (expected a count >= 0)",
            show(field)
        ))
    })?;
    if !value.is_finite() {
        return Err(lines.error(format!(
            "count '{}' is not finite (expected a count >= 0)",
            show(field)
        )));
    }
    if value < 0.0 {
        return Err(lines.error(format!(
            "count {} is negative (expected a count >= 0)",
            show(field)
        )));
    }
    Ok(value)
}

/// The bin table of a BG2 / COO / dense input: `--bins`, else `--chrom-sizes` with `--bin-size`.
fn bin_table_for(path: &str, what: &str, options: &OpenOptions) -> Result<BinTable> {
    if let Some(bed) = &options.bins_bed {
        let table = read_bins_bed(bed)?;
        if let Some(size) = options.bin_size_bp {
            // A BED cannot tell bin sizes apart when every chromosome is a single bin: the table
            // is the fixed one of the given size when its bins are the same.
            let fixed = BinTable::fixed(table.chroms().to_vec(), size)?;
            if fixed.n_bins() != table.n_bins() || !fixed.iter().eq(table.iter()) {
                return Err(Error::Invalid(format!(
                    "{path}: --bin-size {size} disagrees with the bins of {} ({}): pass one of them",
                    bed.display(),
                    match table.bin_size_bp() {
                        Some(s) => format!("{s} bp bins"),
                        None => "variable-size bins".to_string(),
                    }
                )));
            }
            return Ok(fixed);
        }
        return Ok(table);
    }
    match (&options.chrom_sizes, options.bin_size_bp) {
        (Some(sizes), Some(size)) => BinTable::fixed(read_chrom_sizes(sizes)?, size),
        (Some(_), None) => Err(Error::Invalid(format!(
            "{path}: --chrom-sizes needs a bin size to build the bin table of {what}: pass \
             --bin-size N"
        ))),
        _ => Err(Error::Invalid(format!(
            "{path}: {what} does not carry its bin table: pass --bins BED, or --chrom-sizes FILE \
             --bin-size N"
        ))),
    }
}

/// Push a pixel into `builder`, remembering whether every count so far is whole.
fn push_pixel(
    builder: &mut MatrixBuilder,
    all_whole: &mut bool,
    bin1: u64,
    bin2: u64,
    count: f64,
) -> Result<()> {
    if count.fract() != 0.0 {
        *all_whole = false;
    }
    builder.push(bin1, bin2, count)
}

/// Finish a builder with the count type the counts call for.
fn finish(mut builder: MatrixBuilder, all_whole: bool) -> ContactMatrix {
    builder.set_count_type(if all_whole {
        CountType::Integer
    } else {
        CountType::Float
    });
    builder.build()
}

// ---------------------------------------------------------------------------------------------
// BG2 and COO.

/// Finds the bin of a `(chrom, start, end)` triple, checking that it is exactly a bin.
struct BinLocator<'a> {
    bins: &'a BinTable,
    chrom_ids: HashMap<&'a [u8], usize>,
}

impl<'a> BinLocator<'a> {
    fn new(bins: &'a BinTable) -> Self {
        let chrom_ids = bins
            .chroms()
            .iter()
            .enumerate()
            .map(|(id, chrom)| (chrom.name.as_bytes(), id))
            .collect();
        BinLocator { bins, chrom_ids }
    }

    /// The bin id, or a message saying what was expected.
    fn locate(
        &self,
        chrom: &[u8],
        start: &[u8],
        end: &[u8],
        side: u8,
    ) -> std::result::Result<u64, String> {
        let Some(&chrom_id) = self.chrom_ids.get(chrom) else {
            let names: Vec<&str> = self
                .bins
                .chroms()
                .iter()
                .take(5)
                .map(|c| c.name.as_str())
                .collect();
            let more = if self.bins.n_chroms() > 5 {
                ", ..."
            } else {
                ""
            };
            return Err(format!(
                "unknown chromosome '{}' in chrom{side} (the bin table has {}{more})",
                show(chrom),
                names.join(", ")
            ));
        };
        let (Some(start_bp), Some(end_bp)) = (parse_u64(start), parse_u64(end)) else {
            return Err(format!(
                "start{side} '{}' and end{side} '{}' must be whole numbers",
                show(start),
                show(end)
            ));
        };
        let chrom = &self.bins.chroms()[chrom_id];
        if start_bp >= chrom.length_bp {
            return Err(format!(
                "start{side} {start_bp} is past the end of {} ({} bp)",
                chrom.name, chrom.length_bp
            ));
        }
        let bin_id = self.bins.bin_at(chrom_id, start_bp);
        let bin = self.bins.bin(bin_id);
        if bin.start != start_bp {
            let rule = match self.bins.bin_size_bp() {
                Some(size) => format!(" (bins of {size} bp start at multiples of {size})"),
                None => String::new(),
            };
            return Err(format!(
                "start{side} {start_bp} is not the start of a bin of {}: expected {}{rule}",
                chrom.name, bin.start
            ));
        }
        if bin.end != end_bp {
            return Err(format!(
                "end{side} {end_bp} is not the end of the bin {}:{}-{}: expected {}",
                chrom.name, bin.start, bin.end, bin.end
            ));
        }
        Ok(bin_id as u64)
    }
}

fn read_bg2(lines: &mut LineReader, bins: BinTable) -> Result<ContactMatrix> {
    let locator = BinLocator::new(&bins);
    let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
    let mut all_whole = true;
    let mut first_data_line = true;
    while lines.advance()? {
        let line = lines.current();
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        let (columns, n_columns) = first_fields::<7>(line);
        if n_columns < 7 {
            return Err(lines.error(format!(
                "expected 7 columns (chrom1 start1 end1 chrom2 start2 end2 count), found \
                 {n_columns}"
            )));
        }
        if std::mem::take(&mut first_data_line)
            && parse_number(columns[1]).is_none()
            && parse_number(columns[6]).is_none()
        {
            continue; // a header line
        }
        let bin1 = locator
            .locate(columns[0], columns[1], columns[2], 1)
            .map_err(|m| lines.error(m))?;
        let bin2 = locator
            .locate(columns[3], columns[4], columns[5], 2)
            .map_err(|m| lines.error(m))?;
        let count = parse_count(lines, columns[6])?;
        push_pixel(&mut builder, &mut all_whole, bin1, bin2, count)?;
    }
    Ok(finish(builder, all_whole))
}

fn read_coo(lines: &mut LineReader, bins: BinTable) -> Result<ContactMatrix> {
    let n_bins = bins.n_bins() as u64;
    let mut builder = MatrixBuilder::new(bins, CountType::Integer);
    let mut all_whole = true;
    let mut first_data_line = true;
    while lines.advance()? {
        let line = lines.current();
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        let (columns, n_columns) = first_fields::<3>(line);
        if n_columns < 3 {
            return Err(lines.error(format!(
                "expected 3 columns (bin1_id bin2_id count), found {n_columns}"
            )));
        }
        if std::mem::take(&mut first_data_line)
            && parse_number(columns[0]).is_none()
            && parse_number(columns[2]).is_none()
        {
            continue; // a header line
        }
        let mut ids = [0u64; 2];
        for (side, id) in ids.iter_mut().enumerate() {
            *id = parse_u64(columns[side]).ok_or_else(|| {
                lines.error(format!(
                    "bin{}_id '{}' is not a bin id (expected a whole number from 0)",
                    side + 1,
                    show(columns[side])
                ))
            })?;
            if *id >= n_bins {
                return Err(lines.error(format!(
                    "bin{}_id {} is out of range: the bin table has {n_bins} bins (ids 0 to {})",
                    side + 1,
                    *id,
                    n_bins.saturating_sub(1)
                )));
            }
        }
        let count = parse_count(lines, columns[2])?;
        push_pixel(&mut builder, &mut all_whole, ids[0], ids[1], count)?;
    }
    Ok(finish(builder, all_whole))
}

// ---------------------------------------------------------------------------------------------
// Dense matrices.

fn read_dense(lines: &mut LineReader, bins: BinTable) -> Result<ContactMatrix> {
    let n_bins = bins.n_bins();
    // The upper triangle read so far, in CSR, to check each lower value against its mirror.
    let mut row_starts: Vec<usize> = vec![0];
    let mut columns: Vec<u32> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    let mut all_whole = true;
    let mut row = 0usize;
    while lines.advance()? {
        let line = lines.current();
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        if row >= n_bins {
            return Err(lines.error(format!(
                "more rows than bins: the matrix must have {n_bins} rows, one per bin"
            )));
        }
        let mut n_columns = 0usize;
        for (column, field) in Fields::new(line).enumerate() {
            n_columns += 1;
            if column >= n_bins {
                continue;
            }
            let value = parse_count(lines, field)?;
            if column < row {
                let (lo, hi) = (row_starts[column], row_starts[column + 1]);
                let mirror = match columns[lo..hi].binary_search(&(row as u32)) {
                    Ok(k) => values[lo + k],
                    Err(_) => 0.0,
                };
                if (value - mirror).abs() > DENSE_SYMMETRY_TOLERANCE * value.abs().max(mirror.abs())
                {
                    return Err(lines.error(format!(
                        "the matrix is not symmetric: value {} at row {}, column {} differs from \
                         {mirror} at row {}, column {} (rows and columns are 1-based)",
                        show(field),
                        row + 1,
                        column + 1,
                        column + 1,
                        row + 1
                    )));
                }
            } else if value != 0.0 {
                if value.fract() != 0.0 {
                    all_whole = false;
                }
                columns.push(column as u32);
                values.push(value);
            }
        }
        if n_columns != n_bins {
            return Err(lines.error(format!(
                "expected {n_bins} columns (one per bin), found {n_columns}"
            )));
        }
        row_starts.push(columns.len());
        row += 1;
    }
    if row != n_bins {
        return Err(Error::format(
            &lines.path,
            format!("expected {n_bins} rows (one per bin), found {row}"),
        ));
    }
    let mut builder = MatrixBuilder::new(bins, CountType::Integer);
    for bin1 in 0..n_bins {
        for k in row_starts[bin1]..row_starts[bin1 + 1] {
            builder.push(bin1 as u64, u64::from(columns[k]), values[k])?;
        }
    }
    Ok(finish(builder, all_whole))
}

// ---------------------------------------------------------------------------------------------
// Pairs.

/// A fast hasher for pixel keys and chromosome names (splitmix64 finaliser; the inputs are not
/// adversarial).
#[derive(Default)]
struct FastHasher(u64);

impl Hasher for FastHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for chunk in &mut chunks {
            let mut word = [0u8; 8];
            word.copy_from_slice(chunk);
            self.write_u64(self.0 ^ u64::from_le_bytes(word));
        }
        let mut word = [0u8; 8];
        word[..chunks.remainder().len()].copy_from_slice(chunks.remainder());
        self.write_u64(self.0 ^ u64::from_le_bytes(word) ^ (bytes.len() as u64) << 56);
    }

    fn write_u64(&mut self, value: u64) {
        let mut z = value.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        self.0 = z ^ (z >> 31);
    }
}

/// Pair counts per pixel, keyed by `bin1 << 32 | bin2`.
type PixelCounts = HashMap<u64, u64, BuildHasherDefault<FastHasher>>;

/// Assigns pairs to bins.
struct PairBinner {
    bins: BinTable,
    chrom_ids: HashMap<Vec<u8>, usize, BuildHasherDefault<FastHasher>>,
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
            let Some(size) = options.bin_size_bp else {
                return Err(Error::Invalid(format!(
                    "{}: binning pairs needs a bin size: pass --bin-size N (or --bins BED)",
                    path.display()
                )));
            };
            let chroms = match &options.chrom_sizes {
                Some(sizes) => read_chrom_sizes(sizes)?,
                None if !header_chroms.is_empty() => header_chroms,
                None => {
                    return Err(Error::Invalid(format!(
                        "{}: the pairs have no '#chromsize:' header lines: pass --chrom-sizes FILE \
                         (or --bins BED) to give the chromosomes",
                        path.display()
                    )))
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
        Ok(match self.bins.bin_size_bp() {
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

fn read_pairs(lines: &mut LineReader, options: &OpenOptions) -> Result<ContactMatrix> {
    let mut columns: Option<[usize; 4]> = match options.pairs_columns {
        Some(one_based) => {
            if one_based.contains(&0) {
                return Err(Error::Invalid(format!(
                    "pairs columns {one_based:?} must be 1-based (chrom1,pos1,chrom2,pos2)"
                )));
            }
            Some(one_based.map(|c| c - 1))
        }
        None => None,
    };
    let mut header_chroms: Vec<Chrom> = Vec::new();
    let mut binner: Option<PairBinner> = None;
    let mut counts = PixelCounts::default();
    let (mut cache1, mut cache2) = (0usize, 0usize);
    // Runs of pairs in the same pixel are counted before touching the map.
    let (mut run_key, mut run_count) = (u64::MAX, 0u64);
    let mut n_dropped = 0u64;
    let mut first_dropped: Option<String> = None;
    let mut slots = [0usize; 4];
    let mut max_column = 0usize;
    while lines.advance()? {
        let line = lines.current();
        if line.is_empty() {
            continue;
        }
        if line[0] == b'#' {
            if binner.is_none() {
                if let Some(rest) = line.strip_prefix(b"#chromsize:") {
                    let mut fields = rest
                        .split(|b| b.is_ascii_whitespace())
                        .filter(|f| !f.is_empty());
                    match (fields.next(), fields.next().and_then(parse_u64)) {
                        (Some(name), Some(length)) if length > 0 => {
                            header_chroms.push(Chrom::new(String::from_utf8_lossy(name), length))
                        }
                        _ => {
                            return Err(lines.error(
                                "expected '#chromsize: name length' with a positive whole length",
                            ))
                        }
                    }
                } else if let Some(rest) = line.strip_prefix(b"#columns:") {
                    if options.pairs_columns.is_none() {
                        columns = Some(columns_from_header(lines, rest)?);
                    }
                }
            }
            continue;
        }
        if binner.is_none() {
            slots = columns.unwrap_or([1, 2, 3, 4]);
            max_column = slots.into_iter().max().unwrap_or(0);
            binner = Some(PairBinner::new(
                &lines.path,
                options,
                std::mem::take(&mut header_chroms),
            )?);
        }
        let Some(binner) = &binner else { continue };
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
            return Err(lines.error(format!(
                "expected at least {} columns (chrom1, pos1, chrom2, pos2 in columns {}, {}, {}, \
                 {}), found {n_columns}",
                max_column + 1,
                slots[0] + 1,
                slots[1] + 1,
                slots[2] + 1,
                slots[3] + 1
            )));
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
        let bin1 = binner
            .bin(chrom1, fields[1], 1)
            .map_err(|m| lines.error(m))?;
        let bin2 = binner
            .bin(chrom2, fields[3], 2)
            .map_err(|m| lines.error(m))?;
        let key = (bin1.min(bin2) << 32) | bin1.max(bin2);
        if key == run_key {
            run_count += 1;
        } else {
            if run_count > 0 {
                *counts.entry(run_key).or_insert(0) += run_count;
            }
            run_key = key;
            run_count = 1;
        }
    }
    if run_count > 0 {
        *counts.entry(run_key).or_insert(0) += run_count;
    }
    let binner = match binner {
        Some(binner) => binner,
        None => PairBinner::new(&lines.path, options, header_chroms)?,
    };
    if counts.is_empty() && n_dropped > 0 {
        return Err(Error::format(
            &lines.path,
            format!(
                "none of the {n_dropped} pairs is on a chromosome of the chromosome table (the \
                 first unknown name is '{}'): check the chromosome names and --pairs-columns",
                first_dropped.unwrap_or_default()
            ),
        ));
    }
    let mut builder = MatrixBuilder::new(binner.bins, CountType::Integer);
    for (key, count) in counts {
        builder.push(key >> 32, key & 0xFFFF_FFFF, count as f64)?;
    }
    Ok(builder.build())
}

// ---------------------------------------------------------------------------------------------
// Output.

/// A temporary file next to the target, renamed onto it by [`PendingOutput::persist`] and removed
/// if dropped before.
struct PendingOutput {
    temporary: PathBuf,
    target: PathBuf,
    persisted: bool,
}

impl PendingOutput {
    fn create(target: &Path) -> Result<(Self, File)> {
        let temporary = crate::io::temporary_path(target)?;
        let file = File::options()
            .write(true)
            .create_new(true)
            .open(&temporary)
            .map_err(|e| Error::io(target, e))?;
        let pending = PendingOutput {
            temporary,
            target: target.to_path_buf(),
            persisted: false,
        };
        Ok((pending, file))
    }

    fn persist(mut self) -> Result<()> {
        std::fs::rename(&self.temporary, &self.target).map_err(|e| Error::io(&self.target, e))?;
        self.persisted = true;
        Ok(())
    }
}

impl Drop for PendingOutput {
    fn drop(&mut self) {
        if !self.persisted {
            // Best effort: the temporary file is ours and incomplete.
            let _ = std::fs::remove_file(&self.temporary);
        }
    }
}

/// Append the decimal digits of `value`.
fn push_u64(text: &mut Vec<u8>, mut value: u64) {
    let mut digits = [0u8; 20];
    let mut k = digits.len();
    loop {
        k -= 1;
        digits[k] = b'0' + (value % 10) as u8;
        value /= 10;
        if value == 0 {
            break;
        }
    }
    text.extend_from_slice(&digits[k..]);
}

/// Append a count: whole numbers of integer matrices without a decimal point, reals in the
/// shortest form that reads back exactly.
fn push_count(text: &mut Vec<u8>, count: f64, count_type: CountType) -> std::io::Result<()> {
    match count_type {
        CountType::Integer if count.fract() == 0.0 && count.abs() < 1.0e18 => {
            if count < 0.0 {
                text.push(b'-');
            }
            push_u64(text, count.abs() as u64);
            Ok(())
        }
        CountType::Integer => write!(text, "{count}"),
        CountType::Float => write!(text, "{count:?}"),
    }
}

/// Stream the matrix in `format` to `out`; `path` names the output in errors.
fn write_body<W: Write>(
    reader: &dyn MatrixReader,
    format: TextFormat,
    out: &mut W,
    path: &str,
) -> Result<()> {
    let bins = reader.bins();
    let n_bins = bins.n_bins();
    let count_type = reader.count_type();
    let io_error = |e: std::io::Error| Error::io(path, e);
    let mut text: Vec<u8> = Vec::with_capacity(1 << 16);
    match format {
        TextFormat::Bg2 | TextFormat::Coo => {
            reader.read_pixels(0..n_bins, 0..n_bins, &mut |block| {
                text.clear();
                for k in 0..block.len() {
                    let (bin1, bin2) = (block.bin1[k], block.bin2[k]);
                    if bin1 >= n_bins as u64 || bin2 >= n_bins as u64 {
                        return Err(Error::Invalid(format!(
                            "{}: pixel ({bin1}, {bin2}) is out of range: the bin table has \
                             {n_bins} bins",
                            reader.source()
                        )));
                    }
                    if format == TextFormat::Bg2 {
                        for (bin_id, separator) in [(bin1, b'\t'), (bin2, b'\t')] {
                            let bin = bins.bin(bin_id as usize);
                            text.extend_from_slice(bins.chroms()[bin.chrom_id].name.as_bytes());
                            text.push(b'\t');
                            push_u64(&mut text, bin.start);
                            text.push(b'\t');
                            push_u64(&mut text, bin.end);
                            text.push(separator);
                        }
                    } else {
                        push_u64(&mut text, bin1);
                        text.push(b'\t');
                        push_u64(&mut text, bin2);
                        text.push(b'\t');
                    }
                    push_count(&mut text, block.count[k], count_type).map_err(io_error)?;
                    text.push(b'\n');
                }
                out.write_all(&text).map_err(io_error)
            })
        }
        TextFormat::Dense => {
            let band_rows = (DENSE_BAND_VALUES / n_bins.max(1)).max(1);
            let mut band = vec![0.0f64; band_rows.min(n_bins) * n_bins];
            let mut first = 0;
            while first < n_bins {
                let last = (first + band_rows).min(n_bins);
                band.iter_mut().for_each(|v| *v = 0.0);
                let mut place = |i: usize, j: usize, v: f64| {
                    if (first..last).contains(&i) {
                        band[(i - first) * n_bins + j] = v;
                    }
                    if (first..last).contains(&j) {
                        band[(j - first) * n_bins + i] = v;
                    }
                };
                let mut sink = |block: &crate::matrix::PixelBlock| {
                    for k in 0..block.len() {
                        let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                        if i >= n_bins || j >= n_bins {
                            return Err(Error::Invalid(format!(
                                "{}: pixel ({i}, {j}) is out of range: the bin table has \
                                 {n_bins} bins",
                                reader.source()
                            )));
                        }
                        place(i, j, block.count[k]);
                    }
                    Ok(())
                };
                // Rows of the band (upper part), then the band's columns in earlier rows.
                reader.read_pixels(first..last, first..n_bins, &mut sink)?;
                if first > 0 {
                    reader.read_pixels(0..first, first..last, &mut sink)?;
                }
                for row in 0..last - first {
                    text.clear();
                    for (j, &v) in band[row * n_bins..(row + 1) * n_bins].iter().enumerate() {
                        if j > 0 {
                            text.push(b'\t');
                        }
                        push_count(&mut text, v, count_type).map_err(io_error)?;
                    }
                    text.push(b'\n');
                    out.write_all(&text).map_err(io_error)?;
                }
                first = last;
            }
            Ok(())
        }
        TextFormat::Pairs => Err(Error::Invalid(format!(
            "{path}: cannot write pairs: a contact matrix does not hold read pairs"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;
    use tempfile::TempDir;

    use super::*;
    use crate::io::InMemory;
    use crate::matrix::PixelBlock;

    const BG2: &str = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/hg19.GM12878-MboI.matrix.2000kb.bg2.gz"
    );
    const BINS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/hg19.bins.2000kb.bed.gz");
    const PAIRS: &str = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz"
    );

    /// Chromosome sizes of the small synthetic table: 10 + 5 bins of 10 bp.
    const SMALL_SIZES: &str = "chr1\t100\nchr2\t50\n";

    fn gunzip(path: &str) -> String {
        let mut text = String::new();
        flate2::read::MultiGzDecoder::new(File::open(path).unwrap())
            .read_to_string(&mut text)
            .unwrap();
        text
    }

    fn write_plain(dir: &TempDir, name: &str, content: &str) -> PathBuf {
        let path = dir.path().join(name);
        std::fs::write(&path, content).unwrap();
        path
    }

    fn write_gz(dir: &TempDir, name: &str, content: &str) -> PathBuf {
        let path = dir.path().join(name);
        let mut encoder = GzEncoder::new(File::create(&path).unwrap(), Compression::fast());
        encoder.write_all(content.as_bytes()).unwrap();
        encoder.finish().unwrap();
        path
    }

    fn bins_options() -> OpenOptions {
        OpenOptions {
            bins_bed: Some(BINS.into()),
            ..OpenOptions::default()
        }
    }

    /// Options for the small table, with the chromosome sizes written into `dir`.
    fn small_options(dir: &TempDir, format: TextFormat) -> OpenOptions {
        OpenOptions {
            text_format: Some(format),
            chrom_sizes: Some(write_plain(dir, "small.sizes", SMALL_SIZES)),
            bin_size_bp: Some(10),
            ..OpenOptions::default()
        }
    }

    fn read_str(dir: &TempDir, content: &str, options: &OpenOptions) -> Result<ContactMatrix> {
        let path = write_plain(dir, "input.txt", content);
        read_matrix(path.to_str().unwrap(), options)
    }

    fn parse_error<T: std::fmt::Debug>(result: Result<T>) -> (u64, String) {
        match result {
            Err(Error::Parse { line, message, .. }) => (line, message),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    fn invalid_message<T: std::fmt::Debug>(result: Result<T>) -> String {
        match result {
            Err(Error::Invalid(message)) => message,
            other => panic!("expected an Invalid error, got {other:?}"),
        }
    }

    fn fixture_matrix() -> ContactMatrix {
        read_matrix(BG2, &bins_options()).unwrap()
    }

    // Reference figures for the fixtures, computed with cooler 0.11.0 (/work/venv):
    //   awk '{print $1 "\t" $3}' of the last bin of each chromosome of hg19.bins.2000kb.bed.gz
    //     > hg19.chrom.sizes
    //   cooler cload pairs -c1 1 -p1 2 -c2 4 -p2 5 hg19.chrom.sizes:2000000 \
    //     hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz out.cool
    //   cooler info out.cool            -> nbins 1561, nnz 38156, sum 100000
    //   cooler dump --join out.cool     -> byte-identical to the decompressed BG2 fixture
    //   cooler dump -t pixels out.cool  -> identical to `cooler dump` of the .cool fixture;
    //                                      pixels (0,0)=25, (0,1)=2, (0,1560)=3, (60,1482)=2,
    //                                      (866,866)=82, (1235,1235)=149
    //   zcat hg19.GM12878-MboI.matrix.2000kb.bg2.gz | awk '{s+=$7} END {print NR, s}'
    //                                   -> 38156 100000
    const FIXTURE_PIXELS: [(usize, usize, f64); 6] = [
        (0, 0, 25.0),
        (0, 1, 2.0),
        (0, 1560, 3.0),
        (60, 1482, 2.0),
        (866, 866, 82.0),
        (1235, 1235, 149.0),
    ];

    fn assert_fixture_figures(matrix: &ContactMatrix) {
        assert_eq!(matrix.bins().n_bins(), 1561);
        assert_eq!(matrix.bins().bin_size_bp(), Some(2_000_000));
        assert_eq!(matrix.nnz(), 38156);
        assert_eq!(matrix.sum(), 100000.0);
        assert_eq!(matrix.count_type(), CountType::Integer);
        for (i, j, count) in FIXTURE_PIXELS {
            assert_eq!(matrix.get(i, j), count, "pixel ({i}, {j})");
        }
    }

    #[test]
    fn bg2_fixture_matches_cooler_figures() {
        let matrix = fixture_matrix();
        assert_fixture_figures(&matrix);
        let table = read_bins_bed(Path::new(BINS)).unwrap();
        assert_eq!(matrix.bins(), &table);
        assert_eq!(table.chroms()[0], Chrom::new("chr1", 249_250_621));
        assert_eq!(table.chroms()[24], Chrom::new("chrM", 16_571));
    }

    #[test]
    fn bg2_gz_and_plain_give_the_same_matrix() {
        let dir = TempDir::new().unwrap();
        let plain = write_plain(&dir, "plain.bg2", &gunzip(BG2));
        let from_plain = read_matrix(plain.to_str().unwrap(), &bins_options()).unwrap();
        assert_eq!(from_plain, fixture_matrix());
        // The chromosome sizes + bin size route builds the same table.
        let sizes: String = fixture_matrix()
            .bins()
            .chroms()
            .iter()
            .map(|c| format!("{}\t{}\n", c.name, c.length_bp))
            .collect();
        let options = OpenOptions {
            chrom_sizes: Some(write_gz(&dir, "hg19.sizes.gz", &sizes)),
            bin_size_bp: Some(2_000_000),
            ..OpenOptions::default()
        };
        assert_eq!(read_matrix(BG2, &options).unwrap(), from_plain);
    }

    #[test]
    fn a_truncated_gzip_input_is_an_io_error() {
        let dir = TempDir::new().unwrap();
        let bytes = std::fs::read(BG2).unwrap();
        let path = dir.path().join("cut.bg2.gz");
        std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
        match read_matrix(path.to_str().unwrap(), &bins_options()) {
            Err(Error::Io { source, .. }) => {
                assert_eq!(source.kind(), std::io::ErrorKind::UnexpectedEof)
            }
            other => panic!("expected an I/O error, got {other:?}"),
        }
    }

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
            bin_size_bp: Some(2_000_000),
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
            bin_size_bp: Some(2_000_000),
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
            bin_size_bp: Some(10),
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
            bin_size_bp: Some(10),
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
                bin_size_bp: Some(10),
                ..OpenOptions::default()
            },
        )
        .unwrap();
        assert_eq!(matrix.get(2, 9), 1.0);
        // The format is sniffed from the header when the name says nothing.
        let matrix = read_str(&dir, pairs, &options).unwrap();
        assert_eq!(matrix.sum(), 1.0);
    }

    #[test]
    fn pairs_need_a_bin_size_and_chromosomes() {
        let dir = TempDir::new().unwrap();
        let pairs = "r1\tchr1\t10\tchr1\t11\t+\t-\n";
        let path = write_plain(&dir, "reads.pairs", pairs);
        let path = path.to_str().unwrap();
        let message = invalid_message(read_matrix(path, &OpenOptions::default()));
        assert!(message.contains("pass --bin-size N"), "{message}");
        let options = OpenOptions {
            bin_size_bp: Some(10),
            ..OpenOptions::default()
        };
        let message = invalid_message(read_matrix(path, &options));
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

    #[test]
    fn bg2_header_comments_and_whitespace_are_accepted() {
        let dir = TempDir::new().unwrap();
        let options = small_options(&dir, TextFormat::Bg2);
        let text = "chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tcount\n\
                    # a comment\n\
                    chr1\t0\t10\tchr2\t40\t50\t3\tignored\n\
                    chr1 90 100   chr1 0 10 2.5\r\n\
                    \n\
                    chr2\t40\t50\tchr1\t0\t10\t1\n";
        let matrix = read_str(&dir, text, &options).unwrap();
        assert_eq!(matrix.bins().n_bins(), 15);
        assert_eq!(matrix.get(0, 14), 4.0);
        assert_eq!(matrix.get(0, 9), 2.5);
        assert_eq!(matrix.nnz(), 2);
        assert_eq!(matrix.count_type(), CountType::Float);
    }

    #[test]
    fn malformed_bg2_lines_are_reported() {
        let dir = TempDir::new().unwrap();
        let options = small_options(&dir, TextFormat::Bg2);
        let good = "chr1\t0\t10\tchr1\t10\t20\t5\n";
        let cases = [
            (
                "chr1\t0\t10\n",
                "expected 7 columns (chrom1 start1 end1 chrom2 start2 end2 count), found 3",
            ),
            (
                "chr1\t0\t10\tchr1\t10\t20\tmany\n",
                "count 'many' is not a number (expected a count >= 0)",
            ),
            (
                "chr1\t0\t10\tchr1\t10\t20\t-2\n",
                "count -2 is negative (expected a count >= 0)",
            ),
            (
                "chr1\t0\t10\tchr1\t10\t20\tinf\n",
                "count 'inf' is not finite (expected a count >= 0)",
            ),
            (
                "chr1\t0\t10\tchr3\t10\t20\t1\n",
                "unknown chromosome 'chr3' in chrom2 (the bin table has chr1, chr2)",
            ),
            (
                "chr1\t5\t15\tchr1\t10\t20\t1\n",
                "start1 5 is not the start of a bin of chr1: expected 0 (bins of 10 bp start at \
                 multiples of 10)",
            ),
            (
                "chr1\t0\t10\tchr2\t40\t60\t1\n",
                "end2 60 is not the end of the bin chr2:40-50: expected 50",
            ),
            (
                "chr1\t0\t10\tchr2\t50\t60\t1\n",
                "start2 50 is past the end of chr2 (50 bp)",
            ),
            (
                "chr1\tx\t10\tchr1\t10\t20\t1\n",
                "start1 'x' and end1 '10' must be whole numbers",
            ),
        ];
        for (bad, expected) in cases {
            let text = format!("{good}# comment\n{bad}");
            let (line, message) = parse_error(read_str(&dir, &text, &options));
            assert_eq!(line, 3, "{bad}");
            assert_eq!(message, expected);
        }
        // A first line with positions is data, not a header: its bad count is reported.
        let (line, message) = parse_error(read_str(
            &dir,
            "chr1\t0\t10\tchr1\t10\t20\tmany\n",
            &options,
        ));
        assert_eq!((line, message.as_str()), (1, cases[1].1));
    }

    #[test]
    fn bg2_needs_a_bin_table() {
        let dir = TempDir::new().unwrap();
        let path = write_plain(&dir, "m.bg2", "chr1\t0\t10\tchr1\t10\t20\t5\n");
        let message = invalid_message(read_matrix(path.to_str().unwrap(), &OpenOptions::default()));
        assert!(
            message.ends_with(
                "a BG2 table does not carry its bin table: pass --bins BED, or --chrom-sizes \
                 FILE --bin-size N"
            ),
            "{message}"
        );
        let options = OpenOptions {
            chrom_sizes: Some(write_plain(&dir, "s", SMALL_SIZES)),
            ..OpenOptions::default()
        };
        let message = invalid_message(read_matrix(path.to_str().unwrap(), &options));
        assert!(message.contains("pass --bin-size N"), "{message}");
        let options = OpenOptions {
            bin_size_bp: Some(1000),
            ..bins_options()
        };
        let message = invalid_message(read_matrix(path.to_str().unwrap(), &options));
        assert!(message.contains("--bin-size 1000 disagrees"), "{message}");
    }

    #[test]
    fn malformed_coo_lines_are_reported() {
        let dir = TempDir::new().unwrap();
        let options = small_options(&dir, TextFormat::Coo);
        let matrix = read_str(
            &dir,
            "bin1_id\tbin2_id\tcount\n0\t14\t2\n3 1 1.5\n",
            &options,
        )
        .unwrap();
        assert_eq!(matrix.get(14, 0), 2.0);
        assert_eq!(matrix.get(1, 3), 1.5);
        let cases = [
            (
                "0\t15\t1\n",
                "bin2_id 15 is out of range: the bin table has 15 bins (ids 0 to 14)",
            ),
            (
                "-1\t0\t1\n",
                "bin1_id '-1' is not a bin id (expected a whole number from 0)",
            ),
            (
                "0\t1\n",
                "expected 3 columns (bin1_id bin2_id count), found 2",
            ),
            (
                "0\t1\tNaN\n",
                "count 'NaN' is not finite (expected a count >= 0)",
            ),
        ];
        for (bad, expected) in cases {
            let (line, message) = parse_error(read_str(&dir, &format!("0\t0\t1\n{bad}"), &options));
            assert_eq!(line, 2, "{bad}");
            assert_eq!(message, expected);
        }
    }

    #[test]
    fn dense_matrices_must_be_square_and_symmetric() {
        let dir = TempDir::new().unwrap();
        let bins = write_plain(&dir, "b.bed", "a\t0\t10\na\t10\t25\nb\t0\t5\n");
        let options = OpenOptions {
            text_format: Some(TextFormat::Dense),
            bins_bed: Some(bins),
            ..OpenOptions::default()
        };
        let matrix = read_str(&dir, "1 2 0\n2 0 3\n0 3 4\n", &options).unwrap();
        assert_eq!(matrix.bins().bin_size_bp(), None);
        assert_eq!(matrix.nnz(), 4);
        assert_eq!(matrix.get(2, 1), 3.0);
        assert_eq!(matrix.count_type(), CountType::Integer);
        let (line, message) = parse_error(read_str(&dir, "1 2 0\n2 0 3\n0 3.5 4\n", &options));
        assert_eq!(line, 3);
        assert_eq!(
            message,
            "the matrix is not symmetric: value 3.5 at row 3, column 2 differs from 3 at row 2, \
             column 3 (rows and columns are 1-based)"
        );
        let (line, message) = parse_error(read_str(&dir, "1 2 0\n2 0\n", &options));
        assert_eq!(line, 2);
        assert_eq!(message, "expected 3 columns (one per bin), found 2");
        let (line, message) = parse_error(read_str(&dir, "1 2 0\n2 0 3\n0 3 4\n0 0 0\n", &options));
        assert_eq!(line, 4);
        assert!(message.starts_with("more rows than bins"), "{message}");
        match read_str(&dir, "1 2 0\n2 0 3\n", &options) {
            Err(Error::Format { message, .. }) => {
                assert_eq!(message, "expected 3 rows (one per bin), found 2")
            }
            other => panic!("expected a format error, got {other:?}"),
        }
    }

    #[test]
    fn chrom_sizes_and_bins_bed_are_checked() {
        let dir = TempDir::new().unwrap();
        let sizes = write_plain(&dir, "s", "# comment\nchr1\t100\tx\nchr2 50\n");
        assert_eq!(
            read_chrom_sizes(&sizes).unwrap(),
            vec![Chrom::new("chr1", 100), Chrom::new("chr2", 50)]
        );
        let bad = write_plain(&dir, "s", "chr1\t100\nchr1\t50\n");
        assert_eq!(
            parse_error(read_chrom_sizes(&bad)),
            (2, "chromosome 'chr1' appears twice".to_string())
        );
        let bad = write_plain(&dir, "s", "chr1\t1e6\n");
        assert_eq!(
            parse_error(read_chrom_sizes(&bad)),
            (
                1,
                "length '1e6' of 'chr1' is not a positive whole number".to_string()
            )
        );
        let bed = write_plain(
            &dir,
            "b",
            "chrom\tstart\tend\nc\t0\t10\nc\t10\t12\nd\t0\t3\n",
        );
        let table = read_bins_bed(&bed).unwrap();
        assert_eq!(table.n_bins(), 3);
        assert_eq!(table.bin_size_bp(), Some(10));
        assert_eq!(table.chroms()[0], Chrom::new("c", 12));
        let gap = write_plain(&dir, "b", "c\t0\t10\nc\t11\t20\n");
        let (line, message) = parse_error(read_bins_bed(&gap));
        assert_eq!(line, 2);
        assert!(
            message.contains("expected a bin starting at 10"),
            "{message}"
        );
        let regrouped = write_plain(&dir, "b", "c\t0\t10\nd\t0\t10\nc\t10\t20\n");
        let (line, message) = parse_error(read_bins_bed(&regrouped));
        assert_eq!(line, 3);
        assert!(
            message.contains("must be grouped by chromosome"),
            "{message}"
        );
    }

    #[test]
    fn formats_are_guessed_from_names_and_sniffed_from_content() {
        assert_eq!(guess_format("a.bg2"), Some(TextFormat::Bg2));
        assert_eq!(guess_format("a.BEDPE.gz"), Some(TextFormat::Bg2));
        assert_eq!(guess_format("x/y.pairs.gz"), Some(TextFormat::Pairs));
        assert_eq!(guess_format("y.pairsam"), Some(TextFormat::Pairs));
        assert_eq!(guess_format("y.coo"), Some(TextFormat::Coo));
        assert_eq!(guess_format("y.pixels.gz"), Some(TextFormat::Coo));
        assert_eq!(guess_format("y.mat"), Some(TextFormat::Dense));
        assert_eq!(guess_format("y.matrix.gz"), Some(TextFormat::Dense));
        assert_eq!(guess_format("y.dense"), Some(TextFormat::Dense));
        assert_eq!(guess_format("y.txt.gz"), None);
        assert_eq!(guess_format("-"), None);

        let dir = TempDir::new().unwrap();
        let options = OpenOptions {
            text_format: None,
            ..small_options(&dir, TextFormat::Bg2)
        };
        // BG2 with a header, COO, both from a neutral name.
        let bg2 = "chrom1 start1 end1 chrom2 start2 end2 count\nchr1 0 10 chr1 10 20 5\n";
        assert_eq!(read_str(&dir, bg2, &options).unwrap().get(0, 1), 5.0);
        assert_eq!(
            read_str(&dir, "#x\n\n0\t1\t5\n", &options)
                .unwrap()
                .get(0, 1),
            5.0
        );
        match read_str(&dir, "a b c d\n", &options) {
            Err(Error::Format { message, .. }) => {
                assert!(message.contains("pass --format"), "{message}")
            }
            other => panic!("expected a format error, got {other:?}"),
        }
        // Line numbers count from the start of the file after sniffing.
        let (line, _) = parse_error(read_str(&dir, "0\t1\t5\n0\t1\n", &options));
        assert_eq!(line, 2);
    }

    #[test]
    fn bg2_output_of_the_fixture_is_cooler_dump_join() {
        let dir = TempDir::new().unwrap();
        let reader = InMemory::new("fixture".into(), fixture_matrix());
        let out = dir.path().join("out.bg2");
        write_text(&reader, out.to_str().unwrap(), TextFormat::Bg2).unwrap();
        let written = std::fs::read_to_string(&out).unwrap();
        let expected = gunzip(BG2);
        assert_eq!(written.lines().count(), 38156);
        for (k, (a, b)) in written.lines().zip(expected.lines()).enumerate() {
            assert_eq!(a, b, "line {}", k + 1);
        }
        assert_eq!(written, expected);
        // COO is `cooler dump`: 38156 lines, starting "0 0 25", "0 1 2", "0 3 3".
        let out = dir.path().join("out.coo.gz");
        write_text(&reader, out.to_str().unwrap(), TextFormat::Coo).unwrap();
        let coo = gunzip(out.to_str().unwrap());
        assert_eq!(coo.lines().count(), 38156);
        assert!(coo.starts_with("0\t0\t25\n0\t1\t2\n0\t3\t3\n"));
        assert_eq!(
            read_matrix(out.to_str().unwrap(), &bins_options()).unwrap(),
            fixture_matrix()
        );
        // No temporary file is left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
    }

    #[test]
    fn pairs_cannot_be_written_and_large_dense_matrices_are_refused() {
        let dir = TempDir::new().unwrap();
        let reader = InMemory::new("fixture".into(), fixture_matrix());
        let out = dir.path().join("out.pairs");
        let message = invalid_message(write_text(
            &reader,
            out.to_str().unwrap(),
            TextFormat::Pairs,
        ));
        assert!(message.contains("cannot write pairs"), "{message}");
        let bins = BinTable::fixed(vec![Chrom::new("c", 20_001)], 1).unwrap();
        let big = InMemory::new(
            "big".into(),
            MatrixBuilder::new(bins, CountType::Integer).build(),
        );
        let out = dir.path().join("out.dense");
        let message = invalid_message(write_text(&big, out.to_str().unwrap(), TextFormat::Dense));
        assert!(message.contains("too large"), "{message}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    /// A reader that fails after its first block.
    struct Failing(InMemory);

    impl MatrixReader for Failing {
        fn source(&self) -> &str {
            "failing"
        }
        fn bins(&self) -> &BinTable {
            self.0.bins()
        }
        fn count_type(&self) -> CountType {
            self.0.count_type()
        }
        fn weight_names(&self) -> Vec<String> {
            Vec::new()
        }
        fn weights(&self, name: &str) -> Result<crate::matrix::Weights> {
            self.0.weights(name)
        }
        fn info(&self) -> crate::io::MatrixInfo {
            self.0.info()
        }
        fn read_pixels(
            &self,
            rows: std::ops::Range<usize>,
            cols: std::ops::Range<usize>,
            sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
        ) -> Result<()> {
            self.0.read_pixels(rows, cols, sink)?;
            Err(Error::Invalid("disk on fire".into()))
        }
    }

    #[test]
    fn a_failed_write_leaves_no_output() {
        let dir = TempDir::new().unwrap();
        let reader = Failing(InMemory::new("f".into(), fixture_matrix()));
        for name in ["out.bg2", "out.coo.gz"] {
            let out = dir.path().join(name);
            let format = guess_format(name).unwrap();
            let result = write_text(&reader, out.to_str().unwrap(), format);
            assert_eq!(invalid_message(result), "disk on fire");
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    /// A writer whose reader went away.
    struct ClosedPipe;

    impl Write for ClosedPipe {
        fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
            Err(std::io::ErrorKind::BrokenPipe.into())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_closed_pipe_is_an_io_error_of_kind_broken_pipe() {
        let reader = InMemory::new("fixture".into(), fixture_matrix());
        for format in [TextFormat::Bg2, TextFormat::Coo] {
            let error = write_body(&reader, format, &mut ClosedPipe, "-").unwrap_err();
            assert!(error.is_broken_pipe(), "{error:?}");
        }
    }

    #[test]
    fn counts_are_printed_as_integers_or_shortest_reals() {
        let mut text = Vec::new();
        push_count(&mut text, 25.0, CountType::Integer).unwrap();
        text.push(b' ');
        push_count(&mut text, 2.0, CountType::Float).unwrap();
        text.push(b' ');
        push_count(&mut text, 0.1, CountType::Float).unwrap();
        text.push(b' ');
        push_count(&mut text, 1e-7, CountType::Float).unwrap();
        text.push(b' ');
        push_count(&mut text, 0.0, CountType::Integer).unwrap();
        text.push(b' ');
        push_u64(&mut text, u64::MAX);
        assert_eq!(
            String::from_utf8(text).unwrap(),
            "25 2.0 0.1 1e-7 0 18446744073709551615"
        );
    }

    fn chroms(lengths: &[u64]) -> Vec<Chrom> {
        lengths
            .iter()
            .enumerate()
            .map(|(k, &length)| Chrom::new(format!("chr{}", k + 1), length))
            .collect()
    }

    /// Fixed tables, or variable ones cut at random points.
    fn arb_bins() -> impl Strategy<Value = BinTable> {
        let fixed = (prop::collection::vec(1u64..60, 1..4), 1u64..12)
            .prop_map(|(lengths, size)| BinTable::fixed(chroms(&lengths), size).unwrap());
        let variable = prop::collection::vec(
            (1u64..60, prop::collection::btree_set(1u64..60, 0..5)),
            1..4,
        )
        .prop_map(|specs| {
            let lengths: Vec<u64> = specs.iter().map(|s| s.0).collect();
            let mut bins = Vec::new();
            for (chrom_id, (length, cuts)) in specs.iter().enumerate() {
                let mut start = 0;
                for &cut in cuts.iter().filter(|&&c| c < *length) {
                    bins.push(Bin {
                        chrom_id,
                        start,
                        end: cut,
                    });
                    start = cut;
                }
                bins.push(Bin {
                    chrom_id,
                    start,
                    end: *length,
                });
            }
            BinTable::from_bins(chroms(&lengths), &bins, None).unwrap()
        });
        prop_oneof![fixed, variable]
    }

    /// Random matrices with integer or real counts.
    fn arb_matrix() -> impl Strategy<Value = ContactMatrix> {
        arb_bins()
            .prop_flat_map(|bins| {
                let n = bins.n_bins() as u64;
                let count = prop_oneof![
                    (1u32..1000).prop_map(f64::from),
                    1e-9f64..1e9,
                    (1u32..64).prop_map(|k| f64::from(k) / 8.0),
                ];
                (
                    Just(bins),
                    prop::collection::vec((0..n, 0..n, count), 0..40),
                )
            })
            .prop_map(|(bins, pixels)| {
                let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
                for &(i, j, c) in &pixels {
                    builder.push(i, j, c).unwrap();
                }
                let matrix = builder.build();
                if matrix.all_pixels().count.iter().all(|c| c.fract() == 0.0) {
                    return matrix;
                }
                let mut builder = MatrixBuilder::new(bins, CountType::Float);
                for &(i, j, c) in &pixels {
                    builder.push(i, j, c).unwrap();
                }
                builder.build()
            })
    }

    fn bed_of(bins: &BinTable) -> String {
        bins.iter()
            .map(|b| {
                format!(
                    "{}\t{}\t{}\n",
                    bins.chroms()[b.chrom_id].name,
                    b.start,
                    b.end
                )
            })
            .collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        #[test]
        fn text_formats_round_trip(matrix in arb_matrix(), gz in any::<bool>()) {
            let dir = TempDir::new().unwrap();
            let options = OpenOptions {
                bins_bed: Some(write_plain(&dir, "bins.bed", &bed_of(matrix.bins()))),
                bin_size_bp: matrix.bins().bin_size_bp(),
                ..OpenOptions::default()
            };
            let reader = InMemory::new("random".into(), matrix.clone());
            let suffix = if gz { ".gz" } else { "" };
            for (format, name) in [
                (TextFormat::Bg2, "m.bg2"),
                (TextFormat::Coo, "m.coo"),
                (TextFormat::Dense, "m.dense"),
            ] {
                let path = dir.path().join(format!("{name}{suffix}"));
                let path = path.to_str().unwrap();
                write_text(&reader, path, format).unwrap();
                let back = read_matrix(path, &options).unwrap();
                prop_assert_eq!(&back, &matrix, "{:?}", format);
            }
        }
    }
}
