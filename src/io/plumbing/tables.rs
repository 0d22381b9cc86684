//! Tab-separated tables with a header line, such as cooltools' expected tables
//! (`region1 region2 dist dist_bp n_valid count.sum balanced.sum count.avg balanced.avg ...`).
//!
//! Values are read as text or numbers by column name; `nan`, `NaN`, empty fields and `NA` read as
//! NaN, as pandas writes and reads them. Numbers are written as cooltools' tables print them
//! ([`write_real`]: the shortest digits that read back the same value, `nan`), and tables of
//! region pairs by [`region_table`].

use std::io::{BufRead, Read};

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::genome::BinTable;

/// A whole TSV table held in memory, columns addressed by header name: the file's text in one
/// string and each field's bounds in it (no string per field: an expected table of a 5 kb
/// genome has tens of millions of fields).
#[derive(Clone, Debug)]
pub struct Table {
    path: String,
    header: Vec<String>,
    text: String,
    /// Per row, per column: the field's `(start, end)` in `text`.
    fields: Vec<(usize, usize)>,
    n_rows: usize,
}

impl Table {
    /// Whether `uri` names a table whose header (the first line that is neither blank nor a
    /// `#` comment) starts with column `column`: a text file, as bytes, of which only the first
    /// 64 KiB are looked at (a `.cool` file is not text; a URI with `::` names an HDF5 group).
    ///
    /// ```
    /// use contactmap::io::tables::Table;
    /// let cis = "data/reference/numerics/dm6_100kb.expected_cis.raw.tsv.gz";
    /// assert!(Table::starts_with_column(cis, "region1")?);
    /// assert!(!Table::starts_with_column("data/yeast.10kb.cool", "region1")?);
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn starts_with_column(uri: &str, column: &str) -> Result<bool> {
        let path = std::path::Path::new(uri);
        if uri.contains("::") || !path.is_file() {
            return Ok(false);
        }
        let mut head = Vec::new();
        crate::io::plumbing::input::open_text(path)?
            .take(64 << 10)
            .read_to_end(&mut head)
            .map_err(|e| Error::io(path, e))?;
        let named = format!("{column}\t");
        Ok(head
            .split(|&b| b == b'\n')
            .find(|line| !(line.iter().all(u8::is_ascii_whitespace) || line.starts_with(b"#")))
            .is_some_and(|line| line.starts_with(named.as_bytes())))
    }

    /// Read `path` (`-` for stdin, gzip detected from the content).
    pub fn read(path: &str) -> Result<Table> {
        // The whole text read once; the fields' bounds point into it (no copy per line).
        let mut text = String::new();
        crate::io::plumbing::input::open_text(std::path::Path::new(path))?
            .read_to_string(&mut text)
            .map_err(|e| Error::io(path, e))?;
        let mut header: Option<Vec<String>> = None;
        let (mut fields, mut n_rows) = (Vec::new(), 0);
        let mut offset = 0;
        for (index, raw) in text.split_inclusive('\n').enumerate() {
            let line_start = offset;
            offset += raw.len();
            let line = raw.strip_suffix('\n').unwrap_or(raw);
            let line = line.strip_suffix('\r').unwrap_or(line);
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let Some(h) = &header else {
                let names: Vec<String> = line.split('\t').map(str::to_string).collect();
                // room for every line's fields at once (a count of the lines is cheap)
                let n_lines = text[offset..].bytes().filter(|&b| b == b'\n').count() + 1;
                fields.reserve(n_lines * names.len());
                header = Some(names);
                continue;
            };
            let before = fields.len();
            let mut start = line_start;
            for (k, byte) in line.bytes().enumerate() {
                if byte == b'\t' {
                    fields.push((start, line_start + k));
                    start = line_start + k + 1;
                }
            }
            fields.push((start, line_start + line.len()));
            let found = fields.len() - before;
            if found != h.len() {
                return Err(Error::parse(
                    path,
                    index as u64 + 1,
                    format!(
                        "expected {} tab-separated columns (as the header), found {found}",
                        h.len()
                    ),
                ));
            }
            n_rows += 1;
        }
        let header = header.ok_or_else(|| Error::format(path, "empty table: no header line"))?;
        Ok(Table {
            path: path.to_string(),
            header,
            text,
            fields,
            n_rows,
        })
    }

    /// Number of data rows.
    pub fn len(&self) -> usize {
        self.n_rows
    }

    /// True when the table has no data row.
    pub fn is_empty(&self) -> bool {
        self.n_rows == 0
    }

    /// The header names.
    pub fn header(&self) -> &[String] {
        &self.header
    }

    /// Index of column `name`, or an error listing the columns.
    pub fn column(&self, name: &str) -> Result<usize> {
        self.header.iter().position(|h| h == name).ok_or_else(|| {
            Error::format(
                &self.path,
                format!("no column '{name}' (columns: {})", self.header.join(", ")),
            )
        })
    }

    /// The text of column `column` in row `row`.
    pub fn text(&self, row: usize, column: usize) -> &str {
        let (start, end) = self.fields[row * self.header.len() + column];
        &self.text[start..end]
    }

    /// The number in column `column` of row `row` (NaN for `nan`, `NA` and empty fields).
    pub fn number(&self, row: usize, column: usize) -> Result<f64> {
        let text = self.text(row, column).trim();
        if text.is_empty() || text.eq_ignore_ascii_case("nan") || text == "NA" {
            return Ok(f64::NAN);
        }
        text.parse().map_err(|_| {
            Error::parse(
                &self.path,
                // +2: 1-based, and the header line (comments and blank lines aside)
                row as u64 + 2,
                format!(
                    "'{text}' in column '{}' is not a number",
                    self.header[column]
                ),
            )
        })
    }

    /// The numbers of the columns `names`, row by row (an error names a missing column or the
    /// line of a field that is not a number).
    pub fn numbers(&self, names: &[&str]) -> Result<Vec<Vec<f64>>> {
        let columns: Vec<usize> = names
            .iter()
            .map(|name| self.column(name))
            .collect::<Result<_>>()?;
        (0..self.n_rows)
            .map(|row| columns.iter().map(|&c| self.number(row, c)).collect())
            .collect()
    }

    /// The path the table was read from.
    pub fn path(&self) -> &str {
        &self.path
    }
}

/// One row of a track: an interval and a value.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackRow {
    /// Chromosome.
    pub chrom: String,
    /// Start in bp.
    pub start: u64,
    /// End in bp.
    pub end: u64,
    /// The value (NaN for `nan`, `NA`, empty).
    pub value: f64,
}

/// Read a per-bin track: a table whose first three columns are `chrom start end` (a cooltools
/// insulation table, a `contactmap tads` output, a bedGraph) and the value in `column`, named by
/// its header or given as a 1-based number. A file whose first line has numeric 2nd and 3rd
/// fields has no header (bedGraph; `column` must then be a number).
pub fn read_track(path: &std::path::Path, column: &str) -> Result<Vec<TrackRow>> {
    let label = path.display().to_string();
    let reader = crate::io::plumbing::input::open_text(path)?;
    let mut index: Option<usize> = None;
    let mut rows = Vec::new();
    let numbered = column
        .parse::<usize>()
        .ok()
        .filter(|&n| n >= 1)
        .map(|n| n - 1);
    for (line_index, line) in reader.lines().enumerate() {
        let line_no = line_index as u64 + 1;
        let line = line.map_err(|e| Error::io(path, e))?;
        let line = line.trim_end_matches('\r');
        if line.trim().is_empty() || line.starts_with('#') || line.starts_with("track") {
            continue;
        }
        let fields: Vec<&str> = line.split('\t').collect();
        if index.is_none() {
            let headerless = fields.len() >= 3
                && fields[1].trim().parse::<u64>().is_ok()
                && fields[2].trim().parse::<u64>().is_ok();
            if headerless {
                index = Some(numbered.ok_or_else(|| {
                    Error::format(
                        path,
                        format!(
                            "has no header line: give the track column as a number (e.g. {label}:4)"
                        ),
                    )
                })?);
            } else {
                let found = fields.iter().position(|h| h.trim() == column).or(numbered);
                index = Some(found.ok_or_else(|| {
                    Error::format(
                        path,
                        format!("no column '{column}' (columns: {})", fields.join(", ")),
                    )
                })?);
                continue;
            }
        }
        let at = index.expect("set above");
        if fields.len() <= at.max(2) {
            return Err(Error::parse(
                path,
                line_no,
                format!(
                    "expected at least {} tab-separated fields, found {}",
                    at.max(2) + 1,
                    fields.len()
                ),
            ));
        }
        let coordinate = |text: &str| {
            text.trim().parse::<u64>().map_err(|_| {
                Error::parse(path, line_no, format!("'{text}' is not a position in bp"))
            })
        };
        let text = fields[at].trim();
        let value = if text.is_empty() || text.eq_ignore_ascii_case("nan") || text == "NA" {
            f64::NAN
        } else {
            text.parse().map_err(|_| {
                Error::parse(
                    path,
                    line_no,
                    format!("'{text}' in the track column is not a number"),
                )
            })?
        };
        rows.push(TrackRow {
            chrom: fields[0].trim().to_string(),
            start: coordinate(fields[1])?,
            end: coordinate(fields[2])?,
            value,
        });
    }
    Ok(rows)
}

/// The values of the track `column` of `path` ([`read_track`]) on `bins`: NaN for bins without a
/// row; a row that is not a bin of `bins` is an error naming it.
pub fn track_on_bins(path: &std::path::Path, column: &str, bins: &BinTable) -> Result<Vec<f64>> {
    let rows = read_track(path, column)?;
    let mut values = vec![f64::NAN; bins.n_bins()];
    let chrom_ids: std::collections::HashMap<&str, usize> = bins
        .chroms()
        .iter()
        .enumerate()
        .map(|(k, c)| (c.name.as_str(), k))
        .collect();
    for row in &rows {
        let bin = chrom_ids.get(row.chrom.as_str()).and_then(|&c| {
            let range = bins.chrom_bins(c);
            let at = bins.bin_at(
                c,
                row.start.min(bins.chroms()[c].length_bp.saturating_sub(1)),
            );
            let bin = bins.bin(at);
            (range.contains(&at) && bin.start == row.start && bin.end == row.end).then_some(at)
        });
        let Some(bin) = bin else {
            return Err(Error::format(
                path,
                format!(
                    "track row {}:{}-{} is not a bin of the map{}: the track must be on the map's bins",
                    row.chrom,
                    row.start,
                    row.end,
                    bins.resolution()
                        .map_or(String::new(), |b| format!(" ({b} bp bins)"))
                ),
            ));
        };
        values[bin] = row.value;
    }
    Ok(values)
}

/// Rows of cells as text with columns aligned (first column left, the others right), two
/// spaces between columns, no trailing blanks.
///
/// ```
/// let rows = vec![
///     vec!["range".to_string(), "TP".to_string()],
///     vec!["long".to_string(), "12".to_string()],
/// ];
/// assert_eq!(contactmap::io::tables::aligned(&rows), "range  TP\nlong   12\n");
/// ```
pub fn aligned(rows: &[Vec<String>]) -> String {
    let columns = rows.iter().map(Vec::len).max().unwrap_or(0);
    let widths: Vec<usize> = (0..columns)
        .map(|c| {
            rows.iter()
                .filter_map(|row| row.get(c))
                .map(|cell| cell.chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut text = String::new();
    for row in rows {
        let cells: Vec<String> = row
            .iter()
            .enumerate()
            .map(|(c, cell)| {
                if c == 0 {
                    format!("{cell:<width$}", width = widths[c])
                } else {
                    format!("{cell:>width$}", width = widths[c])
                }
            })
            .collect();
        text.push_str(cells.join("  ").trim_end());
        text.push('\n');
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_columns_by_name_with_nan() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("e.tsv");
        std::fs::write(
            &path,
            "region1\tdist\tbalanced.avg\nchr1\t0\tnan\nchr1\t1\t0.5\n",
        )
        .unwrap();
        let table = Table::read(path.to_str().unwrap()).unwrap();
        assert_eq!(table.len(), 2);
        let c = table.column("balanced.avg").unwrap();
        assert!(table.number(0, c).unwrap().is_nan());
        assert_eq!(table.number(1, c).unwrap(), 0.5);
        assert_eq!(table.text(1, table.column("region1").unwrap()), "chr1");
        assert!(
            table
                .column("count.avg")
                .unwrap_err()
                .to_string()
                .contains("balanced.avg")
        );
        std::fs::write(&path, "a\tb\n1\n").unwrap();
        let err = Table::read(path.to_str().unwrap()).unwrap_err().to_string();
        assert!(err.contains(":2:") && err.contains("expected 2"), "{err}");
    }
}

/// Append a real number: shortest round-trip digits, `nan` / `inf` / `-inf`, integers without
/// a decimal point, exponent notation for very small or very large magnitudes.
///
/// # Examples
///
/// ```
/// use contactmap::io::tables::write_real;
///
/// let mut text = Vec::new();
/// for value in [894773.0, 0.1 + 0.2, 1.5e-7, f64::NAN] {
///     write_real(&mut text, value);
///     text.push(b' ');
/// }
/// assert_eq!(text, b"894773 0.30000000000000004 1.5e-7 nan ");
/// ```
pub fn write_real(out: &mut Vec<u8>, value: f64) {
    use std::io::Write as _;
    if value.is_nan() {
        out.extend_from_slice(b"nan");
    } else if value.is_infinite() {
        out.extend_from_slice(if value > 0.0 { b"inf" } else { b"-inf" });
    } else if value == 0.0 || (1e-5..1e16).contains(&value.abs()) {
        let _ = write!(out, "{value}");
    } else {
        let _ = write!(out, "{value:e}");
    }
}

/// [`write_real`] as a string.
pub fn real_text(value: f64) -> String {
    let mut out = Vec::new();
    write_real(&mut out, value);
    String::from_utf8(out).expect("ASCII digits")
}

/// Append the decimal digits of `value`.
///
/// # Examples
///
/// ```
/// let mut text = Vec::new();
/// contactmap::io::tables::write_u64(&mut text, 1_000_000);
/// assert_eq!(text, b"1000000");
/// ```
pub fn write_u64(out: &mut Vec<u8>, mut value: u64) {
    let mut digits = [0u8; 20];
    let mut n = 0;
    loop {
        digits[19 - n] = b'0' + (value % 10) as u8;
        n += 1;
        value /= 10;
        if value == 0 {
            break;
        }
    }
    out.extend_from_slice(&digits[20 - n..]);
}

/// A column of a table, for writers.
#[derive(Clone, Copy, Debug)]
pub enum Column<'a> {
    /// Whole numbers.
    Integer(&'a [u64]),
    /// Real numbers (NaN for missing).
    Real(&'a [f64]),
}

impl Column<'_> {
    /// Append the value of `row`.
    pub fn write(&self, out: &mut Vec<u8>, row: usize) {
        match self {
            Column::Integer(values) => write_u64(out, values[row]),
            Column::Real(values) => write_real(out, values[row]),
        }
    }
}

/// Rows formatted per parallel task.
const FORMAT_TASK_ROWS: usize = 4096;

/// The text of a table of region pairs as cooltools writes them: a header
/// `region1 region2 NAME...`, then one line per row (`region1(row) region2(row)` and the
/// columns), rows formatted in parallel.
///
/// # Examples
///
/// ```
/// use contactmap::io::tables::{region_table, Column};
///
/// let (dist, avg) = ([0, 1], [f64::NAN, 0.5]);
/// let columns = [
///     ("dist".to_string(), Column::Integer(&dist)),
///     ("count.avg".to_string(), Column::Real(&avg)),
/// ];
/// let text = region_table(2, &columns, |_| "chr1".into(), |_| "chr1".into());
/// assert_eq!(text, b"region1\tregion2\tdist\tcount.avg\nchr1\tchr1\t0\tnan\nchr1\tchr1\t1\t0.5\n");
/// ```
pub fn region_table(
    n_rows: usize,
    columns: &[(String, Column<'_>)],
    region1: impl Fn(usize) -> String + Sync,
    region2: impl Fn(usize) -> String + Sync,
) -> Vec<u8> {
    let mut text = Vec::with_capacity(64 * (n_rows + 1));
    text.extend_from_slice(b"region1\tregion2");
    for (name, _) in columns {
        text.push(b'\t');
        text.extend_from_slice(name.as_bytes());
    }
    text.push(b'\n');
    let chunks: Vec<Vec<u8>> = (0..n_rows.div_ceil(FORMAT_TASK_ROWS))
        .into_par_iter()
        .map(|chunk| {
            let rows = chunk * FORMAT_TASK_ROWS..((chunk + 1) * FORMAT_TASK_ROWS).min(n_rows);
            let mut part = Vec::with_capacity(100 * rows.len());
            for row in rows {
                part.extend_from_slice(region1(row).as_bytes());
                part.push(b'\t');
                part.extend_from_slice(region2(row).as_bytes());
                for (_, column) in columns {
                    part.push(b'\t');
                    column.write(&mut part, row);
                }
                part.push(b'\n');
            }
            part
        })
        .collect();
    for part in chunks {
        text.extend_from_slice(&part);
    }
    text
}
