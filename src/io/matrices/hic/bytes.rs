//! The bottom of the `.hic` reader: a bounds-checked sequential reader over the file and the
//! quoting of names read from it, used by the header, footer, index and vector parsers above.

use std::fs::File;
use std::io::ErrorKind;
use std::os::unix::fs::FileExt;
use std::path::Path;

use crate::error::{Error, Result};

/// Bytes fetched per positioned read while parsing the header, footer and indexes.
pub(super) const READ_CHUNK_BYTES: usize = 64 << 10;
/// Longest string (chromosome name, attribute value) accepted.
pub(super) const MAX_STRING_BYTES: usize = 16 << 20;

/// `text` (a name or other bytes read from the file) made safe to quote in a one-line message:
/// control characters (a newline among them) and Unicode line and paragraph separators are
/// escaped as Rust escapes them (`\n`, `\u{1b}`), everything else is kept.
pub(super) fn printable(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() || c == '\u{2028}' || c == '\u{2029}' {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// A sequential little-endian reader over a file, by positioned reads, bounds-checked against the
/// file size so that a corrupt length never reads or allocates past the end of the file.
pub(super) struct SeqReader<'a> {
    pub(super) file: &'a File,
    pub(super) path: &'a Path,
    pub(super) file_len: u64,
    pub(super) pos: u64,
    pub(super) buf: Vec<u8>,
    pub(super) buf_start: u64,
}

impl<'a> SeqReader<'a> {
    pub(super) fn new(file: &'a File, path: &'a Path, file_len: u64, pos: u64) -> Self {
        SeqReader {
            file,
            path,
            file_len,
            pos,
            buf: Vec::new(),
            buf_start: 0,
        }
    }

    pub(super) fn remaining(&self) -> u64 {
        self.file_len.saturating_sub(self.pos)
    }

    pub(super) fn truncated(&self, what: &str) -> Error {
        Error::format(
            self.path,
            format!(
                "truncated while reading {what} at offset {} (the file has {} bytes)",
                self.pos, self.file_len
            ),
        )
    }

    /// Make the buffer hold `n` bytes from the current position.
    pub(super) fn fill(&mut self, n: usize, what: &str) -> Result<()> {
        let buf_end = self.buf_start + self.buf.len() as u64;
        if self.pos >= self.buf_start && self.pos + n as u64 <= buf_end {
            return Ok(());
        }
        if n as u64 > self.remaining() {
            return Err(self.truncated(what));
        }
        let len = (n.max(READ_CHUNK_BYTES) as u64).min(self.remaining()) as usize;
        self.buf.clear();
        self.buf.resize(len, 0);
        if let Err(e) = self.file.read_exact_at(&mut self.buf, self.pos) {
            self.buf.clear();
            return Err(if e.kind() == ErrorKind::UnexpectedEof {
                self.truncated(what)
            } else {
                Error::io(self.path, e)
            });
        }
        self.buf_start = self.pos;
        Ok(())
    }

    pub(super) fn bytes(&mut self, n: usize, what: &str) -> Result<&[u8]> {
        self.fill(n, what)?;
        let start = (self.pos - self.buf_start) as usize;
        self.pos += n as u64;
        Ok(&self.buf[start..start + n])
    }

    pub(super) fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        let mut out = [0u8; N];
        out.copy_from_slice(self.bytes(N, what)?);
        Ok(out)
    }

    pub(super) fn i32(&mut self, what: &str) -> Result<i32> {
        Ok(i32::from_le_bytes(self.array(what)?))
    }

    pub(super) fn i64(&mut self, what: &str) -> Result<i64> {
        Ok(i64::from_le_bytes(self.array(what)?))
    }

    pub(super) fn f32(&mut self, what: &str) -> Result<f32> {
        Ok(f32::from_le_bytes(self.array(what)?))
    }

    pub(super) fn skip(&mut self, n: u64, what: &str) -> Result<()> {
        if n > self.remaining() {
            return Err(self.truncated(what));
        }
        self.pos += n;
        Ok(())
    }

    /// A NUL-terminated string.
    pub(super) fn string(&mut self, what: &str) -> Result<String> {
        let mut text = Vec::new();
        loop {
            if self.remaining() == 0 {
                return Err(self.truncated(what));
            }
            self.fill(1, what)?;
            let start = (self.pos - self.buf_start) as usize;
            let available = &self.buf[start..];
            match available.iter().position(|&b| b == 0) {
                Some(end) => {
                    text.extend_from_slice(&available[..end]);
                    self.pos += end as u64 + 1;
                    return Ok(String::from_utf8_lossy(&text).into_owned());
                }
                None => {
                    text.extend_from_slice(available);
                    self.pos += available.len() as u64;
                }
            }
            if text.len() > MAX_STRING_BYTES {
                return Err(Error::format(
                    self.path,
                    format!(
                        "{what} at offset {}: string longer than {MAX_STRING_BYTES} bytes \
                         (the file is corrupt)",
                        self.pos
                    ),
                ));
            }
        }
    }

    /// Check a count read from the file: not negative, and `n` items of at least
    /// `min_item_bytes` each fit in the rest of the file.
    pub(super) fn count(&self, n: i64, min_item_bytes: u64, what: &str) -> Result<usize> {
        let fits = u64::try_from(n)
            .ok()
            .filter(|&n| n.saturating_mul(min_item_bytes) <= self.remaining());
        match fits {
            Some(n) => Ok(n as usize),
            None => Err(Error::format(
                self.path,
                format!(
                    "{what}: count {n} at offset {} does not fit in the {} bytes left in the \
                     file (the file is truncated or corrupt)",
                    self.pos.saturating_sub(4),
                    self.remaining()
                ),
            )),
        }
    }
}
