//! Tab-separated tables with a header line, such as cooltools' expected tables
//! (`region1 region2 dist dist_bp n_valid count.sum balanced.sum count.avg balanced.avg ...`).
//!
//! Values are read as text or numbers by column name; `nan`, `NaN`, empty fields and `NA` read as
//! NaN, as pandas writes and reads them.

use std::io::BufRead;

use crate::error::{Error, Result};

/// A whole TSV table held in memory, columns addressed by header name.
#[derive(Clone, Debug)]
pub struct Table {
    path: String,
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// Read `path` (`-` for stdin, gzip detected from the content).
    pub fn read(path: &str) -> Result<Table> {
        let reader = crate::io::open_text(std::path::Path::new(path))?;
        let mut header = None;
        let mut rows = Vec::new();
        for (index, line) in reader.lines().enumerate() {
            let line = line.map_err(|e| Error::io(path, e))?;
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let fields: Vec<String> = line.split('\t').map(str::to_string).collect();
            match &header {
                None => header = Some(fields),
                Some(h) => {
                    if fields.len() != h.len() {
                        return Err(Error::parse(
                            path,
                            index as u64 + 1,
                            format!(
                                "expected {} tab-separated columns (as the header), found {}",
                                h.len(),
                                fields.len()
                            ),
                        ));
                    }
                    rows.push(fields);
                }
            }
        }
        let header = header.ok_or_else(|| Error::format(path, "empty table: no header line"))?;
        Ok(Table {
            path: path.to_string(),
            header,
            rows,
        })
    }

    /// Number of data rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// True when the table has no data row.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
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
        &self.rows[row][column]
    }

    /// The number in column `column` of row `row` (NaN for `nan`, `NA` and empty fields).
    pub fn number(&self, row: usize, column: usize) -> Result<f64> {
        let text = self.rows[row][column].trim();
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

    /// The path the table was read from.
    pub fn path(&self) -> &str {
        &self.path
    }
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
        assert!(table
            .column("count.avg")
            .unwrap_err()
            .to_string()
            .contains("balanced.avg"));
        std::fs::write(&path, "a\tb\n1\n").unwrap();
        let err = Table::read(path.to_str().unwrap()).unwrap_err().to_string();
        assert!(err.contains(":2:") && err.contains("expected 2"), "{err}");
    }
}
