//! The header, the footer's master index, and the bounds-checked sequential reader they are parsed
//! with.

use std::collections::HashMap;
use std::fs::File;
use std::io::ErrorKind;
use std::os::unix::fs::FileExt;
use std::path::Path;

use super::norms::{read_norm_index, skip_expected_values, NormVector};
use crate::error::{Error, Result};
use crate::genome::Chrom;

/// The first four bytes of every `.hic` file.
pub(super) const MAGIC: &[u8; 4] = b"HIC\0";
/// Bytes fetched per positioned read while parsing the header, footer and indexes.
pub(super) const READ_CHUNK_BYTES: usize = 64 << 10;
/// Longest string (chromosome name, attribute value) accepted.
pub(super) const MAX_STRING_BYTES: usize = 16 << 20;

/// Longest chromosome accepted, in base pairs: hictk keeps chromosome lengths as 32-bit unsigned
/// integers, and version 8 files store them as 32-bit signed ones.
pub(super) const MAX_CHROM_LENGTH_BP: i64 = u32::MAX as i64;

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

/// The parsed header.
pub(super) struct Header {
    pub(super) version: i32,
    pub(super) footer_position: u64,
    pub(super) genome_id: String,
    pub(super) norm_vector_index: Option<(i64, i64)>,
    pub(super) attributes: Vec<(String, String)>,
    pub(super) chroms: Vec<Chrom>,
    pub(super) resolutions: Vec<u64>,
}

/// The parts of the footer the reader keeps.
pub(super) struct Footer {
    pub(super) master: HashMap<(usize, usize), u64>,
    pub(super) norm_vectors: Vec<NormVector>,
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

/// Parse the header at the start of the file.
pub(super) fn read_header(reader: &mut SeqReader) -> Result<Header> {
    let path = reader.path;
    let magic: [u8; 4] = reader.array("the magic bytes")?;
    if &magic != MAGIC {
        return Err(Error::format(
            path,
            "not a .hic file: it does not start with the magic bytes HIC\\0",
        ));
    }
    let version = reader.i32("the version")?;
    if version != 8 && version != 9 {
        return Err(Error::format(
            path,
            format!(
                ".hic version {version} is not supported: this reader reads versions 8 and 9 \
                 (newer Juicer Tools or hictk can convert older files)"
            ),
        ));
    }
    let footer_position = reader.i64("the footer position")?;
    if footer_position <= 0 || footer_position as u64 >= reader.file_len {
        return Err(Error::format(
            path,
            format!(
                "the footer position {footer_position} in the header is outside the file ({} \
                 bytes): the file is truncated or corrupt",
                reader.file_len
            ),
        ));
    }
    let genome_id = reader.string("the genome id")?;
    let norm_vector_index = if version >= 9 {
        let position = reader.i64("the normalisation vector index position")?;
        let length = reader.i64("the normalisation vector index length")?;
        Some((position, length))
    } else {
        None
    };
    let n_attributes = reader.i32("the number of header attributes")?;
    let n_attributes = reader.count(i64::from(n_attributes), 2, "the header attributes")?;
    let mut attributes = Vec::with_capacity(n_attributes);
    for _ in 0..n_attributes {
        let key = reader.string("a header attribute key")?;
        let value = reader.string(&format!(
            "the value of header attribute '{}'",
            printable(&key)
        ))?;
        attributes.push((key, value));
    }
    let n_chroms = reader.i32("the number of chromosomes")?;
    let length_bytes = if version >= 9 { 8 } else { 4 };
    let n_chroms = reader.count(i64::from(n_chroms), 1 + length_bytes, "the chromosome list")?;
    if n_chroms == 0 {
        return Err(Error::format(
            path,
            "the number of chromosomes in the header is 0: the file is corrupt",
        ));
    }
    let mut chroms = Vec::with_capacity(n_chroms);
    for _ in 0..n_chroms {
        let name = reader.string("a chromosome name")?;
        let quoted = printable(&name);
        let what = format!("the length of chromosome '{quoted}'");
        let length = if version >= 9 {
            reader.i64(&what)?
        } else {
            i64::from(reader.i32(&what)?)
        };
        if length < 0 {
            return Err(Error::format(
                path,
                format!("chromosome '{quoted}' has a negative length {length}"),
            ));
        }
        if length > MAX_CHROM_LENGTH_BP {
            return Err(Error::format(
                path,
                format!(
                    "the length of chromosome '{quoted}' in the header, {length} bp, is more than \
                     {MAX_CHROM_LENGTH_BP} (Juicer and hictk hold chromosome lengths in 32 bits): \
                     the file is corrupt"
                ),
            ));
        }
        chroms.push(Chrom::new(name, length as u64));
    }
    let n_resolutions = reader.i32("the number of base-pair resolutions")?;
    let n_resolutions = reader.count(i64::from(n_resolutions), 4, "the resolution list")?;
    let mut resolutions = Vec::with_capacity(n_resolutions);
    for _ in 0..n_resolutions {
        let resolution = reader.i32("a base-pair resolution")?;
        if resolution <= 0 {
            return Err(Error::format(
                path,
                format!("resolution {resolution} in the header is not positive"),
            ));
        }
        resolutions.push(resolution as u64);
    }
    // Fragment resolutions (and the fragment sites after them) are not read.
    let n_fragment = reader.i32("the number of fragment resolutions")?;
    reader.count(i64::from(n_fragment), 4, "the fragment resolution list")?;
    Ok(Header {
        version,
        footer_position: footer_position as u64,
        genome_id,
        norm_vector_index,
        attributes,
        chroms,
        resolutions,
    })
}

/// Parse the footer: master index, expected values (skipped) and the normalisation-vector index
/// (entries at `resolution`, in base pairs).
pub(super) fn read_footer(
    file: &File,
    path: &Path,
    file_len: u64,
    header: &Header,
    resolution: u64,
) -> Result<Footer> {
    let version = header.version;
    let mut reader = SeqReader::new(file, path, file_len, header.footer_position);
    let what = "the footer";
    if version >= 9 {
        reader.i64(what)?; // nBytes of the "version 5" footer
    } else {
        reader.i32(what)?;
    }
    let n_entries = reader.i32("the master index")?;
    // key (>= 4 bytes: "0_0\0"), position (8), size (4)
    let n_entries = reader.count(i64::from(n_entries), 16, "the master index")?;
    let mut master = HashMap::with_capacity(n_entries);
    for _ in 0..n_entries {
        let key = reader.string("a master index key")?;
        let position = reader.i64("the master index")?;
        let size = reader.i32("the master index")?;
        let Some((i, j)) = key
            .split_once('_')
            .and_then(|(a, b)| Some((a.parse::<usize>().ok()?, b.parse::<usize>().ok()?)))
        else {
            continue; // not a chromosome pair: nothing we can look up
        };
        if i >= header.chroms.len() || j >= header.chroms.len() || i > j {
            continue;
        }
        let end = u64::try_from(position)
            .ok()
            .zip(u64::try_from(size).ok())
            .map(|(p, s)| p.saturating_add(s));
        match end {
            Some(end) if end <= file_len => {
                master.insert((i, j), position as u64);
            }
            _ => {
                return Err(Error::format(
                    path,
                    format!(
                        "the matrix record of {}-{} (offset {position}, {size} bytes) lies \
                         outside the file ({file_len} bytes): the file is truncated or corrupt",
                        header.chroms[i].name, header.chroms[j].name
                    ),
                ))
            }
        }
    }

    // Version 9 gives the position of the normalisation vector index; version 8 (and version 9
    // files without it) have it after the expected-value sections.
    let index_position = match header.norm_vector_index {
        Some((position, length)) if position > 0 && length > 0 => {
            if (position as u64).saturating_add(length as u64) > file_len {
                return Err(Error::format(
                    path,
                    format!(
                        "the normalisation vector index (offset {position}, {length} bytes) lies \
                         outside the file ({file_len} bytes): the file is truncated"
                    ),
                ));
            }
            Some(position as u64)
        }
        _ => {
            skip_expected_values(&mut reader, version, false)?;
            if reader.remaining() > 0 {
                skip_expected_values(&mut reader, version, true)?;
            }
            (reader.remaining() > 0).then_some(reader.pos)
        }
    };
    let mut norm_vectors = Vec::new();
    if let Some(position) = index_position {
        reader.pos = position;
        norm_vectors = read_norm_index(&mut reader, header, resolution)?;
    }
    Ok(Footer {
        master,
        norm_vectors,
    })
}
