//! The header of a `.pairs` file (4DN pairs format v1.0, as pairtools writes it): lines that
//! start with `#`, before the first record.
//!
//! Kept as the lines themselves, in order, so that a command passes on what it does not know
//! (`#samheader:` lines, a tool's own keys); the keys pairtools reads and writes have accessors:
//! `#columns:`, `#chromsize:`, `#sorted:`, `#shape:`, `#genome_assembly:`.

use std::io::BufRead;

use crate::error::{Error, Result};

/// The format line every pairs file starts with.
pub const FORMAT_LINE: &str = "## pairs format v1.0.0";

/// The chromosome of an unmapped side (pairtools' `UNMAPPED_CHROM`).
pub const UNMAPPED_CHROM: &str = "!";

/// The `#sorted:` line pairtools writes for its order.
pub const SORTED_LINE: &str = "#sorted: chr1-chr2-pos1-pos2";

/// The columns of a pairs file without extra columns, in pairtools' order.
pub const STANDARD_COLUMNS: [&str; 8] = [
    "readID",
    "chrom1",
    "pos1",
    "chrom2",
    "pos2",
    "strand1",
    "strand2",
    "pair_type",
];

/// A pairs header: its lines without their line ends, `#columns:` among them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PairsHeader {
    /// Every header line, in order.
    pub lines: Vec<String>,
}

impl PairsHeader {
    /// A new header as `pairtools parse` starts one: format, shape, assembly (`unknown` when
    /// none is given), one `#chromsize:` per chromosome, the columns.
    pub fn standard(
        assembly: Option<&str>,
        chromsizes: &[(String, u64)],
        columns: &[String],
        upper_triangle: bool,
    ) -> PairsHeader {
        let mut lines = vec![
            FORMAT_LINE.to_string(),
            format!(
                "#shape: {}",
                if upper_triangle {
                    "upper triangle"
                } else {
                    "whole matrix"
                }
            ),
            format!("#genome_assembly: {}", assembly.unwrap_or("unknown")),
        ];
        for (chrom, length) in chromsizes {
            lines.push(format!("#chromsize: {chrom} {length}"));
        }
        lines.push(format!("#columns: {}", columns.join(" ")));
        PairsHeader { lines }
    }

    /// Read the header lines (those starting with `#`) from the start of `input`, leaving it
    /// at the first record. `path` names the input in errors.
    pub fn read(input: &mut dyn BufRead, path: &str) -> Result<(PairsHeader, u64)> {
        let lines = read_marked_lines(input, b'#', path)?;
        let n_lines = lines.len() as u64;
        Ok((PairsHeader { lines }, n_lines))
    }

    /// The header as text, one line each, every line ended by `\n`.
    pub fn to_text(&self) -> String {
        let mut text = String::new();
        for line in &self.lines {
            text.push_str(line);
            text.push('\n');
        }
        text
    }

    /// The values of the lines `#KEY: value` (the text after `#KEY:`, trimmed).
    pub fn values<'a>(&'a self, key: &'a str) -> impl Iterator<Item = &'a str> + 'a {
        self.lines.iter().filter_map(move |line| {
            line.strip_prefix('#')
                .and_then(|rest| rest.strip_prefix(key))
                .and_then(|rest| rest.strip_prefix(':'))
                .map(str::trim)
        })
    }

    /// The column names of `#columns:` (pairtools' standard columns when the line is absent).
    pub fn columns(&self) -> Vec<String> {
        match self.values("columns").next() {
            Some(value) => value.split_whitespace().map(str::to_string).collect(),
            None => STANDARD_COLUMNS.iter().map(|c| c.to_string()).collect(),
        }
    }

    /// Whether the header has its `#columns:` line.
    pub fn has_columns(&self) -> bool {
        self.values("columns").next().is_some()
    }

    /// Replace the column names (the `#columns:` line, added at the end when absent).
    pub fn set_columns(&mut self, columns: &[String]) {
        let line = format!("#columns: {}", columns.join(" "));
        match self.lines.iter().position(|l| l.starts_with("#columns")) {
            Some(i) => self.lines[i] = line,
            None => self.lines.push(line),
        }
    }

    /// The chromosomes and lengths of the `#chromsize:` lines, in order. `path` names the file
    /// in the error for a line that is not `NAME LENGTH`.
    pub fn chromsizes(&self, path: &str) -> Result<Vec<(String, u64)>> {
        self.values("chromsize")
            .map(|value| {
                let mut words = value.split_whitespace();
                match (
                    words.next(),
                    words.next().map(str::parse::<u64>),
                    words.next(),
                ) {
                    (Some(name), Some(Ok(length)), None) => Ok((name.to_string(), length)),
                    _ => Err(Error::Format {
                        path: path.into(),
                        message: format!(
                            "header line '#chromsize: {value}': expected a chromosome name and \
                             its length"
                        ),
                    }),
                }
            })
            .collect()
    }

    /// Whether the header says the records are sorted (a `#sorted:` line).
    pub fn is_sorted(&self) -> bool {
        self.values("sorted").next().is_some()
    }

    /// Mark the header sorted as `pairtools sort` does: `#sorted: chr1-chr2-pos1-pos2` after
    /// the format line unless a `#sorted:` line is there.
    pub fn mark_sorted(&mut self) {
        if self.is_sorted() {
            return;
        }
        let at = usize::from(self.lines.first().is_some_and(|l| l.starts_with("##")));
        self.lines.insert(at, SORTED_LINE.to_string());
    }

    /// Insert `#samheader: LINE` lines before `#columns:` (at the end when there is none), as
    /// pairtools keeps the aligner's header.
    pub fn insert_sam_header(&mut self, sam_lines: &[String]) {
        let at = self
            .lines
            .iter()
            .position(|l| l.starts_with("#columns"))
            .unwrap_or(self.lines.len());
        let new = sam_lines.iter().map(|l| format!("#samheader: {l}"));
        self.lines.splice(at..at, new);
    }

    /// Record a program as pairtools does: an `@PG` line appended to the `#samheader:` lines,
    /// its `PP` the last program's `ID`, its `ID` made unique with a `-N` suffix.
    pub fn push_program(&mut self, name: &str, command_line: &str) {
        let programs: Vec<String> = self
            .values("samheader")
            .filter(|l| l.starts_with("@PG"))
            .filter_map(|l| {
                l.split('\t')
                    .find_map(|f| f.strip_prefix("ID:"))
                    .map(str::to_string)
            })
            .collect();
        let mut id = name.to_string();
        let mut suffix = 1;
        while programs.contains(&id) {
            id = format!("{name}-{suffix}");
            suffix += 1;
        }
        let mut line = format!("@PG\tID:{id}\tPN:{name}");
        if let Some(previous) = programs.last() {
            line.push_str(&format!("\tPP:{previous}"));
        }
        line.push_str(&format!("\tVN:{}", env!("CARGO_PKG_VERSION")));
        if !command_line.is_empty() {
            line.push_str(&format!("\tCL:{command_line}"));
        }
        let at = self
            .lines
            .iter()
            .rposition(|l| l.starts_with("#samheader"))
            .map(|i| i + 1)
            .or_else(|| self.lines.iter().position(|l| l.starts_with("#columns")))
            .unwrap_or(self.lines.len());
        self.lines.insert(at, format!("#samheader: {line}"));
    }
}

/// The lines at the start of `input` that start with `marker` (a pairs header's `#`, a SAM
/// header's `@`), without their line ends, leaving `input` at the first other line. `path` names
/// the input in errors.
pub fn read_marked_lines(input: &mut dyn BufRead, marker: u8, path: &str) -> Result<Vec<String>> {
    let mut lines = Vec::new();
    loop {
        let buffer = input.fill_buf().map_err(|e| Error::io(path, e))?;
        if buffer.first() != Some(&marker) {
            return Ok(lines);
        }
        let mut line = Vec::new();
        input
            .read_until(b'\n', &mut line)
            .map_err(|e| Error::io(path, e))?;
        while matches!(line.last(), Some(b'\n' | b'\r')) {
            line.pop();
        }
        let line = String::from_utf8(line).map_err(|_| Error::Parse {
            path: path.into(),
            line: lines.len() as u64 + 1,
            message: "a header line that is not UTF-8 text".into(),
        })?;
        lines.push(line);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(text: &str) -> PairsHeader {
        PairsHeader::read(&mut text.as_bytes(), "h").unwrap().0
    }

    #[test]
    fn a_standard_header_is_written_as_pairtools_parse_writes_it() {
        let columns: Vec<String> = STANDARD_COLUMNS.iter().map(|c| c.to_string()).collect();
        let h = PairsHeader::standard(None, &[("chr1".into(), 100)], &columns, true);
        assert_eq!(
            h.to_text(),
            "## pairs format v1.0.0\n#shape: upper triangle\n#genome_assembly: unknown\n\
             #chromsize: chr1 100\n#columns: readID chrom1 pos1 chrom2 pos2 strand1 strand2 \
             pair_type\n"
        );
    }

    #[test]
    fn reading_stops_at_the_first_record_and_keys_are_read() {
        let text = "## pairs format v1.0.0\n#chromsize: chrA 10\n#chromsize: chrB 20\n\
                    #columns: readID chrom1 pos1\nr1\tchrA\t5\n";
        let mut input = text.as_bytes();
        let (h, n) = PairsHeader::read(&mut input, "h").unwrap();
        assert_eq!(n, 4);
        assert_eq!(input, b"r1\tchrA\t5\n");
        assert_eq!(
            h.chromsizes("h").unwrap(),
            vec![("chrA".to_string(), 10), ("chrB".to_string(), 20)]
        );
        assert_eq!(h.columns(), ["readID", "chrom1", "pos1"]);
        assert!(!h.is_sorted());
    }

    #[test]
    fn marking_sorted_puts_the_line_after_the_format_line_once() {
        let mut h = header("## pairs format v1.0.0\n#columns: a b\n");
        h.mark_sorted();
        h.mark_sorted();
        assert_eq!(h.lines[1], SORTED_LINE);
        assert_eq!(h.lines.len(), 3);
    }

    #[test]
    fn programs_chain_and_get_unique_ids() {
        let mut h = header(
            "## pairs format v1.0.0\n#samheader: @SQ\tSN:c\tLN:5\n\
             #samheader: @PG\tID:bwa\tPN:bwa\n#columns: a b\n",
        );
        h.push_program("contactmap_parse", "");
        h.push_program("contactmap_parse", "");
        let pg: Vec<&str> = h
            .values("samheader")
            .filter(|l| l.starts_with("@PG"))
            .collect();
        assert_eq!(pg.len(), 3);
        assert!(pg[1].starts_with("@PG\tID:contactmap_parse\tPN:contactmap_parse\tPP:bwa"));
        assert!(
            pg[2].starts_with(
                "@PG\tID:contactmap_parse-1\tPN:contactmap_parse\tPP:contactmap_parse"
            )
        );
        assert!(h.lines.last().unwrap().starts_with("#columns"));
    }

    #[test]
    fn a_bad_chromsize_line_is_named() {
        let h = header("#chromsize: chrA ten\n");
        let error = h.chromsizes("f.pairs").unwrap_err().to_string();
        assert!(
            error.contains("f.pairs") && error.contains("chrA ten"),
            "{error}"
        );
    }
}
