//! The records of a `.pairs` file: one line each, tab-separated, the columns named by the
//! header's `#columns:` line.
//!
//! [`PairsReader`] hands out each line as a [`PairRecord`] (its bytes and where its fields
//! start), with its line number for errors; [`PairColumns`] finds the columns the pairs
//! commands read (chromosomes, positions, strands, pair type) by name.

use std::io::BufRead;

use super::header::PairsHeader;
use crate::error::{Error, Result};

/// One record: the line's bytes (without its line end) and its tab-separated fields.
#[derive(Clone, Debug, Default)]
pub struct PairRecord {
    line: Vec<u8>,
    /// The start of each field; a field ends one byte before the next starts (or at the end).
    starts: Vec<u32>,
    /// 1-based line number in its file.
    number: u64,
}

impl PairRecord {
    /// A record from a line (tab-separated, without its line end).
    pub fn from_line(line: &[u8], number: u64) -> PairRecord {
        let mut record = PairRecord {
            line: line.to_vec(),
            starts: Vec::new(),
            number,
        };
        record.index_fields();
        record
    }

    /// Read the next line of `input` into this record (line number 0); `false` at the end.
    pub fn read_line(&mut self, input: &mut dyn BufRead) -> std::io::Result<bool> {
        self.line.clear();
        if input.read_until(b'\n', &mut self.line)? == 0 {
            return Ok(false);
        }
        while matches!(self.line.last(), Some(b'\n' | b'\r')) {
            self.line.pop();
        }
        self.number = 0;
        self.index_fields();
        Ok(true)
    }

    fn index_fields(&mut self) {
        self.starts.clear();
        self.starts.push(0);
        for (i, &byte) in self.line.iter().enumerate() {
            if byte == b'\t' {
                self.starts.push(i as u32 + 1);
            }
        }
    }

    /// The line, without its line end.
    pub fn line(&self) -> &[u8] {
        &self.line
    }

    /// Its 1-based line number in the file it was read from.
    pub fn number(&self) -> u64 {
        self.number
    }

    /// The number of fields.
    pub fn len(&self) -> usize {
        self.starts.len()
    }

    /// Whether the line is empty (it still has one, empty, field).
    pub fn is_empty(&self) -> bool {
        self.line.is_empty()
    }

    /// Field `i` (0-based); empty when the line has fewer fields.
    pub fn field(&self, i: usize) -> &[u8] {
        match self.starts.get(i) {
            Some(&start) => {
                let end = self
                    .starts
                    .get(i + 1)
                    .map_or(self.line.len(), |&next| next as usize - 1);
                &self.line[start as usize..end]
            }
            None => &[],
        }
    }

    /// Replace field `i` (which must exist) by `value`.
    pub fn set_field(&mut self, i: usize, value: &[u8]) {
        let start = self.starts[i] as usize;
        let end = self
            .starts
            .get(i + 1)
            .map_or(self.line.len(), |&next| next as usize - 1);
        self.line.splice(start..end, value.iter().copied());
        self.index_fields();
    }
}

/// Reads the records of a pairs file after its header.
pub struct PairsReader {
    input: Box<dyn BufRead + Send>,
    path: String,
    header: PairsHeader,
    /// The number of the last line read.
    line_number: u64,
    buffer: Vec<u8>,
}

impl PairsReader {
    /// Read the header of `input` (named `path` in errors) and stand at its first record.
    pub fn new(mut input: Box<dyn BufRead + Send>, path: &str) -> Result<PairsReader> {
        let (header, n_lines) = PairsHeader::read(&mut input, path)?;
        Ok(PairsReader {
            input,
            path: path.to_string(),
            header,
            line_number: n_lines,
            buffer: Vec::new(),
        })
    }

    /// The header.
    pub fn header(&self) -> &PairsHeader {
        &self.header
    }

    /// The input's name, as errors give it.
    pub fn path(&self) -> &str {
        &self.path
    }

    /// Read the next record into `record`; `false` at the end of the input. Empty lines are
    /// skipped; a `#` line among the records is an error (a header line after the first record
    /// is a sign of files concatenated without their headers merged).
    pub fn read_record(&mut self, record: &mut PairRecord) -> Result<bool> {
        loop {
            self.buffer.clear();
            let n = self
                .input
                .read_until(b'\n', &mut self.buffer)
                .map_err(|e| Error::io(&self.path, e))?;
            if n == 0 {
                return Ok(false);
            }
            self.line_number += 1;
            while matches!(self.buffer.last(), Some(b'\n' | b'\r')) {
                self.buffer.pop();
            }
            if self.buffer.is_empty() {
                continue;
            }
            if self.buffer[0] == b'#' {
                return Err(self.error(
                    self.line_number,
                    "a header line among the records: merge pairs files with \
                     `contactmap pairs merge`, not by concatenating them",
                ));
            }
            std::mem::swap(&mut record.line, &mut self.buffer);
            record.number = self.line_number;
            record.index_fields();
            return Ok(true);
        }
    }

    /// An error at line `line` of this input.
    pub fn error(&self, line: u64, message: impl Into<String>) -> Error {
        Error::Parse {
            path: self.path.clone().into(),
            line,
            message: message.into(),
        }
    }
}

/// Where the columns the pairs commands read stand in a record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PairColumns {
    /// `readID`, when present.
    pub read_id: Option<usize>,
    /// `chrom1`.
    pub chrom1: usize,
    /// `pos1`.
    pub pos1: usize,
    /// `chrom2`.
    pub chrom2: usize,
    /// `pos2`.
    pub pos2: usize,
    /// `strand1`.
    pub strand1: usize,
    /// `strand2`.
    pub strand2: usize,
    /// `pair_type`, when present.
    pub pair_type: Option<usize>,
    /// The number of columns the header names.
    pub n_columns: usize,
}

impl PairColumns {
    /// Find the columns in the header's `#columns:` line (pairtools' standard columns when the
    /// header has none). `source` names the file in the error for a missing column.
    pub fn of(header: &PairsHeader, source: &str) -> Result<PairColumns> {
        let names = header.columns();
        let find = |name: &str| names.iter().position(|c| c == name);
        let need = |name: &str| {
            find(name).ok_or_else(|| Error::Format {
                path: source.into(),
                message: format!(
                    "the header's '#columns:' line has no '{name}' column (it names: {})",
                    names.join(" ")
                ),
            })
        };
        Ok(PairColumns {
            read_id: find("readID"),
            chrom1: need("chrom1")?,
            pos1: need("pos1")?,
            chrom2: need("chrom2")?,
            pos2: need("pos2")?,
            strand1: need("strand1")?,
            strand2: need("strand2")?,
            pair_type: find("pair_type"),
            n_columns: names.len(),
        })
    }

    /// The most fields a record must have for every column read here to exist.
    pub fn n_required(&self) -> usize {
        [
            self.chrom1,
            self.pos1,
            self.chrom2,
            self.pos2,
            self.strand1,
            self.strand2,
            self.pair_type.unwrap_or(0),
            self.read_id.unwrap_or(0),
        ]
        .into_iter()
        .max()
        .unwrap_or(0)
            + 1
    }

    /// Check that `record` has the fields these columns need and that its positions are
    /// integers; the error names the line and what was found.
    pub fn check(&self, reader: &PairsReader, record: &PairRecord) -> Result<()> {
        if record.len() < self.n_required() {
            return Err(reader.error(
                record.number(),
                format!(
                    "{} tab-separated fields where the header's columns need {}",
                    record.len(),
                    self.n_required()
                ),
            ));
        }
        for column in [self.pos1, self.pos2] {
            if parse_position(record.field(column)).is_none() {
                return Err(reader.error(
                    record.number(),
                    format!(
                        "position '{}' is not a non-negative integer",
                        String::from_utf8_lossy(record.field(column))
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// A position field as an integer (`None` when it is not one).
pub fn parse_position(field: &[u8]) -> Option<u64> {
    if field.is_empty() || field.len() > 19 {
        return None;
    }
    let mut value = 0u64;
    for &byte in field {
        if !byte.is_ascii_digit() {
            return None;
        }
        value = value * 10 + u64::from(byte - b'0');
    }
    Some(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reader(text: &'static str) -> PairsReader {
        PairsReader::new(Box::new(text.as_bytes()), "t.pairs").unwrap()
    }

    #[test]
    fn fields_are_split_at_tabs_and_replaced() {
        let mut record = PairRecord::from_line(b"r\tchr1\t10\t\tx", 3);
        assert_eq!(record.len(), 5);
        assert_eq!(record.field(1), b"chr1");
        assert_eq!(record.field(3), b"");
        assert_eq!(record.field(4), b"x");
        assert_eq!(record.field(9), b"");
        record.set_field(1, b"chr22");
        assert_eq!(record.line(), b"r\tchr22\t10\t\tx");
        assert_eq!(record.field(2), b"10");
    }

    #[test]
    fn records_come_with_their_line_numbers() {
        let mut r = reader(
            "## pairs format v1.0.0\n#columns: readID chrom1 pos1 chrom2 pos2 strand1 strand2 pair_type\n.\tc\t1\tc\t2\t+\t-\tUU\n\n.\tc\t3\tc\t4\t+\t-\tUU\n",
        );
        let columns = PairColumns::of(r.header(), "t.pairs").unwrap();
        assert_eq!(columns.pair_type, Some(7));
        let mut record = PairRecord::default();
        assert!(r.read_record(&mut record).unwrap());
        assert_eq!(record.number(), 3);
        assert!(r.read_record(&mut record).unwrap());
        assert_eq!(record.number(), 5);
        assert_eq!(record.field(2), b"3");
        assert!(!r.read_record(&mut record).unwrap());
    }

    #[test]
    fn short_lines_and_bad_positions_are_named_by_line() {
        let mut r = reader(
            "#columns: readID chrom1 pos1 chrom2 pos2 strand1 strand2 pair_type\n.\tc\t1\tc\n.\tc\tx\tc\t2\t+\t-\tUU\n",
        );
        let columns = PairColumns::of(r.header(), "t.pairs").unwrap();
        let mut record = PairRecord::default();
        r.read_record(&mut record).unwrap();
        let error = columns.check(&r, &record).unwrap_err().to_string();
        assert!(
            error.starts_with("t.pairs:2: 4 tab-separated fields"),
            "{error}"
        );
        r.read_record(&mut record).unwrap();
        let error = columns.check(&r, &record).unwrap_err().to_string();
        assert!(error.starts_with("t.pairs:3: position 'x'"), "{error}");
    }

    #[test]
    fn a_header_line_among_records_is_refused() {
        let mut r = reader("#columns: a\nx\n#columns: a\n");
        let mut record = PairRecord::default();
        r.read_record(&mut record).unwrap();
        let error = r.read_record(&mut record).unwrap_err().to_string();
        assert!(
            error.starts_with("t.pairs:3: a header line among the records"),
            "{error}"
        );
    }

    #[test]
    fn a_missing_column_is_named() {
        let r = reader("#columns: readID chrom1 pos1\n");
        let error = PairColumns::of(r.header(), "t.pairs")
            .unwrap_err()
            .to_string();
        assert!(error.contains("no 'chrom2' column"), "{error}");
    }

    #[test]
    fn positions_are_plain_integers() {
        assert_eq!(parse_position(b"0"), Some(0));
        assert_eq!(parse_position(b"123456789"), Some(123456789));
        for bad in [&b""[..], b"-1", b"1.5", b" 1", b"99999999999999999999"] {
            assert_eq!(parse_position(bad), None);
        }
    }
}
