//! Lines of a plain or gzip-compressed input (a file or standard input), their fields and the
//! numbers in them.

use std::collections::VecDeque;
use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::sync::{Arc, Mutex};

use flate2::bufread::MultiGzDecoder;

use super::format::TextFormat;
use crate::error::{Error, Result};

/// Read buffer size.
pub(super) const BUFFER_BYTES: usize = 1 << 18;

/// Lines of an input, with their 1-based numbers, for parse errors.
pub(super) struct LineReader {
    input: Box<dyn BufRead>,
    /// The path as shown in messages (`-` for standard input).
    pub(super) path: PathBuf,
    line: Vec<u8>,
    /// Length of the current line without its terminator and trailing blanks.
    len: usize,
    /// Lines read while sniffing the format, handed out again before the input.
    replay: VecDeque<Vec<u8>>,
    line_number: u64,
}

impl LineReader {
    /// Open `path` (`-` for standard input), decompressing gzip transparently.
    pub(super) fn open(path: &Path) -> Result<Self> {
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
    pub(super) fn advance(&mut self) -> Result<bool> {
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

    /// Hand the current line out again at the next [`advance`](Self::advance) or
    /// [`next_chunk`](Self::next_chunk), with its number.
    pub(super) fn unread_current(&mut self) {
        let line = self.current().to_vec();
        self.replay.push_front(line);
        self.line_number -= 1;
    }

    /// The next lines, whole, about `target_bytes` of them (each ending with `\n`), and the
    /// number of the first; `None` at the end of the input. For parsing lines in parallel.
    pub(super) fn next_chunk(&mut self, target_bytes: usize) -> Result<Option<(Vec<u8>, u64)>> {
        let first = self.line_number + 1;
        let mut chunk = Vec::with_capacity(target_bytes + (1 << 12));
        while chunk.len() < target_bytes {
            let Some(line) = self.replay.pop_front() else {
                break;
            };
            chunk.extend_from_slice(&line);
            chunk.push(b'\n');
        }
        while chunk.len() < target_bytes {
            let buffer = self
                .input
                .fill_buf()
                .map_err(|e| Error::io(&self.path, e))?;
            if buffer.is_empty() {
                break;
            }
            let take = buffer.len().min(target_bytes - chunk.len());
            chunk.extend_from_slice(&buffer[..take]);
            self.input.consume(take);
        }
        if chunk.last().is_some_and(|&b| b != b'\n') {
            self.input
                .read_until(b'\n', &mut chunk)
                .map_err(|e| Error::io(&self.path, e))?;
            if chunk.last() != Some(&b'\n') {
                chunk.push(b'\n');
            }
        }
        if chunk.is_empty() {
            return Ok(None);
        }
        self.line_number += chunk.iter().filter(|&&b| b == b'\n').count() as u64;
        Ok(Some((chunk, first)))
    }

    /// The current line, without its terminator and trailing blanks.
    pub(super) fn current(&self) -> &[u8] {
        &self.line[..self.len]
    }

    /// A parse error at the current line.
    pub(super) fn error(&self, message: impl Into<String>) -> Error {
        Error::parse(&self.path, self.line_number, message)
    }

    /// Look at the first lines to recognise the format, then rewind to the start.
    pub(super) fn sniff_format(&mut self) -> Result<Option<TextFormat>> {
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
            if pairs_columns(&fields).is_some() {
                format = Some(TextFormat::Pairs);
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

/// The 0-based columns `chrom1, pos1, chrom2, pos2` of a headerless pairs line, when its
/// layout is one of those read-pair tools write:
///
/// | layout | columns |
/// |---|---|
/// | 4DN `.pairs` body: `readID chrom1 pos1 chrom2 pos2 strand1 strand2 ...` | 2,3,4,5 |
/// | `chrom1 pos1 strand1 chrom2 pos2 strand2` (cooler's test pairs; strands `+`/`-` or SAM flags 0/16) | 1,2,4,5 |
/// | Juicer short: `str1 chrom1 pos1 frag1 str2 chrom2 pos2 frag2 ...` | 2,3,6,7 |
/// | `chrom1 pos1 chrom2 pos2` | 1,2,3,4 |
///
/// (1-based in the table, as `--pairs-columns` takes them.) Strands and the kind of each field
/// tell the layouts apart; chromosome names may be numbers (Ensembl's `1`, `X`).
pub(super) fn pairs_columns(fields: &[&[u8]]) -> Option<[usize; 4]> {
    let int = |k: usize| fields.get(k).and_then(|f| parse_u64(f)).is_some();
    let strand = |k: usize| {
        fields
            .get(k)
            .is_some_and(|f| matches!(*f, b"+" | b"-" | b"0" | b"16"))
    };
    let name = |k: usize| fields.get(k).is_some_and(|f| parse_number(f).is_none());
    let n = fields.len();
    if n >= 7 && int(2) && int(4) && strand(5) && strand(6) {
        return Some([1, 2, 3, 4]);
    }
    if n >= 8 && strand(0) && int(2) && int(3) && strand(4) && int(6) && int(7) {
        return Some([1, 2, 5, 6]);
    }
    if n == 6 && int(1) && strand(2) && int(4) && strand(5) {
        return Some([0, 1, 3, 4]);
    }
    if n == 4 && int(1) && int(3) && !(int(0) && int(2)) {
        return Some([0, 1, 2, 3]);
    }
    if n >= 5 && name(1) && int(2) && name(3) && int(4) {
        return Some([1, 2, 3, 4]);
    }
    None
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
pub(super) struct Fields<'a> {
    rest: &'a [u8],
    tabs: bool,
    done: bool,
}

impl<'a> Fields<'a> {
    pub(super) fn new(line: &'a [u8]) -> Self {
        Fields {
            rest: line,
            tabs: line.contains(&b'\t'),
            done: false,
        }
    }
}

/// The first `N` fields of `line` and how many there were (at most `N`).
pub(super) fn first_fields<const N: usize>(line: &[u8]) -> ([&[u8]; N], usize) {
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
pub(super) fn parse_u64(field: &[u8]) -> Option<u64> {
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
pub(super) fn parse_number(field: &[u8]) -> Option<f64> {
    match parse_u64(field) {
        Some(value) if value < (1 << 53) => Some(value as f64),
        _ => std::str::from_utf8(field).ok()?.parse::<f64>().ok(),
    }
}

/// A field as shown in messages (lossy UTF-8, at most 40 characters).
pub(super) fn show(field: &[u8]) -> String {
    let text = String::from_utf8_lossy(field);
    match text.char_indices().nth(40) {
        Some((cut, _)) => format!("{}...", &text[..cut]),
        None => text.into_owned(),
    }
}

/// Parse a count: a finite number >= 0.
pub(super) fn parse_count(lines: &LineReader, field: &[u8]) -> Result<f64> {
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

#[cfg(test)]
mod tests {
    use tempfile::TempDir;

    use super::super::read_matrix;
    use super::super::test_support::*;
    use crate::error::Error;

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
}
