//! BED interval files: reading records and writing lines.
//!
//! Coordinates are 0-based, half-open, as the UCSC BED specification. The reader accepts plain or
//! gzip-compressed files (recognised by their magic bytes), fields separated by tabs or runs of
//! whitespace, and skips blank lines, `#` comments and `track` / `browser` lines. Only the first
//! five columns are interpreted (chrom, start, end, name, score); further columns are ignored.
//! A score of `.` means "no score".

use std::io::{BufRead, Write};
use std::path::Path;

use crate::error::{Error, Result};

/// One BED record (the first six columns).
#[derive(Clone, Debug, PartialEq)]
pub struct BedRecord {
    /// Chromosome name.
    pub chrom: String,
    /// Start, 0-based.
    pub start: u64,
    /// End, exclusive.
    pub end: u64,
    /// The 4th column, when present.
    pub name: Option<String>,
    /// The 5th column, when present and not `.`.
    pub score: Option<f64>,
    /// The 6th column (strand), when it is `+` or `-`.
    pub strand: Option<char>,
}

impl BedRecord {
    /// A record with only `chrom start end`.
    pub fn new(chrom: impl Into<String>, start: u64, end: u64) -> Self {
        BedRecord {
            chrom: chrom.into(),
            start,
            end,
            name: None,
            score: None,
            strand: None,
        }
    }

    /// Width in bp (`end - start`).
    pub fn width(&self) -> u64 {
        self.end - self.start
    }
}

/// Read every record of the BED file at `path` (plain or gzip), in file order.
///
/// Errors name the file and the 1-based line: fewer than 3 fields, a coordinate that is not a
/// non-negative integer, `start > end`, or a 5th column that is neither `.` nor a number.
pub fn read_bed(path: &Path) -> Result<Vec<BedRecord>> {
    let reader = crate::io::open_text(path)?;
    let mut records = Vec::new();
    for (index, line) in reader.lines().enumerate() {
        let line_no = index as u64 + 1;
        let line = line.map_err(|e| Error::io(path, e))?;
        if let Some(record) = parse_line(&line).map_err(|m| Error::parse(path, line_no, m))? {
            records.push(record);
        }
    }
    Ok(records)
}

/// One BEDPE record: a pair of intervals (a loop: `chrom1 start1 end1 chrom2 start2 end2 ...`).
#[derive(Clone, Debug, PartialEq)]
pub struct BedpeRecord {
    /// First anchor.
    pub first: BedRecord,
    /// Second anchor.
    pub second: BedRecord,
}

/// Read the BEDPE file at `path` (plain or gzip): the first six columns of each line; a header
/// line whose coordinates are not numbers (`chrom1 start1 end1 ...`, as HiCCUPS and cooltools
/// write) and `#` comments are skipped. Errors name the file and the 1-based line.
pub fn read_bedpe(path: &Path) -> Result<Vec<BedpeRecord>> {
    let reader = crate::io::open_text(path)?;
    let mut records = Vec::new();
    for (index, line) in reader.lines().enumerate() {
        let line_no = index as u64 + 1;
        let line = line.map_err(|e| Error::io(path, e))?;
        let line = line.trim_end_matches('\r');
        let trimmed = line.trim_start();
        if trimmed.is_empty() || trimmed.starts_with('#') || trimmed.starts_with("track") {
            continue;
        }
        let fields: Vec<&str> = if line.contains('\t') {
            line.split('\t').map(str::trim).collect()
        } else {
            line.split_whitespace().collect()
        };
        if fields.len() < 6 {
            return Err(Error::parse(
                path,
                line_no,
                format!(
                    "expected at least 6 columns (chrom1 start1 end1 chrom2 start2 end2), found {}",
                    fields.len()
                ),
            ));
        }
        if records.is_empty()
            && fields[1].parse::<u64>().is_err()
            && fields[4].parse::<u64>().is_err()
        {
            continue; // header line
        }
        let anchor =
            |chrom: &str, start: &str, end: &str| -> std::result::Result<BedRecord, String> {
                let coordinate = |what: &str, text: &str| {
                    text.parse::<u64>()
                        .map_err(|_| format!("{what} '{text}' is not a non-negative whole number"))
                };
                let (start, end) = (coordinate("start", start)?, coordinate("end", end)?);
                if start > end {
                    return Err(format!("start {start} is after end {end}"));
                }
                Ok(BedRecord::new(chrom, start, end))
            };
        let first =
            anchor(fields[0], fields[1], fields[2]).map_err(|m| Error::parse(path, line_no, m))?;
        let second =
            anchor(fields[3], fields[4], fields[5]).map_err(|m| Error::parse(path, line_no, m))?;
        records.push(BedpeRecord { first, second });
    }
    Ok(records)
}

/// Parse one line; `Ok(None)` for lines that hold no record (blank, comment, track, browser).
fn parse_line(line: &str) -> std::result::Result<Option<BedRecord>, String> {
    let line = line.trim_end_matches('\r');
    let trimmed = line.trim_start();
    if trimmed.is_empty()
        || trimmed.starts_with('#')
        || trimmed.starts_with("track")
        || trimmed.starts_with("browser")
    {
        return Ok(None);
    }
    let fields: Vec<&str> = if line.contains('\t') {
        line.split('\t').map(str::trim).collect()
    } else {
        line.split_whitespace().collect()
    };
    if fields.len() < 3 {
        return Err(format!(
            "expected at least 3 columns (chrom start end), found {}: '{line}'",
            fields.len()
        ));
    }
    let coordinate = |what: &str, text: &str| {
        text.parse::<u64>()
            .map_err(|_| format!("{what} '{text}' is not a non-negative whole number"))
    };
    let start = coordinate("start", fields[1])?;
    let end = coordinate("end", fields[2])?;
    if start > end {
        return Err(format!("start {start} is after end {end}"));
    }
    let name = fields.get(3).map(|s| s.to_string());
    let score = match fields.get(4) {
        None | Some(&".") => None,
        Some(text) => Some(
            text.parse::<f64>()
                .map_err(|_| format!("score '{text}' is neither '.' nor a number"))?,
        ),
    };
    let strand = match fields.get(5) {
        None | Some(&".") => None,
        Some(&"+") => Some('+'),
        Some(&"-") => Some('-'),
        Some(text) => return Err(format!("strand '{text}' is not +, - or .")),
    };
    Ok(Some(BedRecord {
        chrom: fields[0].to_string(),
        start,
        end,
        name,
        score,
        strand,
    }))
}

/// Write `chrom start end` and then `extra` fields, tab-separated, as one line.
pub fn write_bed_line(
    out: &mut impl Write,
    chrom: &str,
    start: u64,
    end: u64,
    extra: &[&str],
) -> std::io::Result<()> {
    write!(out, "{chrom}\t{start}\t{end}")?;
    for field in extra {
        write!(out, "\t{field}")?;
    }
    writeln!(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn reads_records_skipping_headers_and_comments() {
        let dir = tempfile::tempdir().unwrap();
        let path = write(
            dir.path(),
            "a.bed",
            "track name=x\nbrowser position chr1\n# comment\n\nchr1\t0\t100\n\
             chr1 100 200 b1 3.5 + extra\nchr2\t5\t5\tz\t.\r\n",
        );
        let records = read_bed(&path).unwrap();
        assert_eq!(
            records,
            vec![
                BedRecord::new("chr1", 0, 100),
                BedRecord {
                    chrom: "chr1".into(),
                    start: 100,
                    end: 200,
                    name: Some("b1".into()),
                    score: Some(3.5),
                    strand: Some('+'),
                },
                BedRecord {
                    chrom: "chr2".into(),
                    start: 5,
                    end: 5,
                    name: Some("z".into()),
                    score: None,
                    strand: None,
                },
            ]
        );
        assert_eq!(records[1].width(), 100);
    }

    #[test]
    fn reads_gzip() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.bed.gz");
        let mut encoder = flate2::write::GzEncoder::new(
            std::fs::File::create(&path).unwrap(),
            flate2::Compression::default(),
        );
        encoder.write_all(b"chrX\t10\t20\n").unwrap();
        encoder.finish().unwrap();
        assert_eq!(
            read_bed(&path).unwrap(),
            vec![BedRecord::new("chrX", 10, 20)]
        );
    }

    #[test]
    fn bad_lines_name_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        for (text, expected) in [
            ("chr1\t0\t10\nchr1\tx\t10\n", ":2: start 'x'"),
            ("chr1\t0\n", ":1: expected at least 3 columns"),
            ("chr1\t-5\t10\n", ":1: start '-5'"),
            ("chr1\t0\t10.5\n", ":1: end '10.5'"),
            ("#h\nchr1\t20\t10\n", ":2: start 20 is after end 10"),
            ("chr1\t0\t10\tn\tlots\n", ":1: score 'lots'"),
        ] {
            let path = write(dir.path(), "bad.bed", text);
            let message = read_bed(&path).unwrap_err().to_string();
            assert!(
                message.contains(&format!("bad.bed{expected}")),
                "{message} should contain {expected}"
            );
        }
        let missing = read_bed(&dir.path().join("missing.bed")).unwrap_err();
        assert!(missing.to_string().contains("missing.bed"));
    }

    #[test]
    fn writes_lines() {
        let mut out = Vec::new();
        write_bed_line(&mut out, "chr1", 0, 10, &[]).unwrap();
        write_bed_line(&mut out, "chr2", 5, 15, &["0", "x"]).unwrap();
        assert_eq!(out, b"chr1\t0\t10\nchr2\t5\t15\t0\tx\n");
    }
}
