//! contactmap's conformations tables (`simulate polymer --conformations`): a header
//! `replica sample chain bead x y z`, then one row per bead; the rows of one `(replica, sample)`
//! are one conformation, its chains one after the other. Plain or gzip.

use std::io::BufRead;
use std::path::{Path, PathBuf};

use super::frame::{Conformation, LengthUnit, checked, coordinates};
use crate::error::{Error, Result};

/// The conformations of a table, read one at a time.
pub struct TableConformations {
    path: PathBuf,
    lines: std::io::Lines<Box<dyn BufRead + Send>>,
    line_no: u64,
    /// The first row of the next conformation, already read: its key and position.
    pending: Option<Row>,
    done: bool,
}

/// A row: its conformation's key (replica, sample) and its bead's position.
type Row = ((String, String), [f64; 3]);

const HEADER: [&str; 7] = ["replica", "sample", "chain", "bead", "x", "y", "z"];

impl TableConformations {
    /// Open the table at `path` and check its header.
    pub fn open(path: &Path) -> Result<TableConformations> {
        let mut lines = crate::io::plumbing::input::open_text(path)?.lines();
        let header = match lines.next() {
            Some(line) => line.map_err(|e| Error::io(path, e))?,
            None => return Err(Error::format(path, "an empty file: no conformation")),
        };
        let fields: Vec<&str> = header.split('\t').map(str::trim).collect();
        if fields != HEADER {
            // the line's first columns: enough to see what the file is
            let mut shown: String = header.trim().chars().take(60).collect();
            if header.trim().chars().count() > 60 {
                shown.push_str("...");
            }
            return Err(Error::parse(
                path,
                1,
                format!(
                    "expected the header '{}' (a conformations table of `simulate polymer \
                     --conformations`), found '{}'",
                    HEADER.join(" "),
                    shown
                ),
            ));
        }
        Ok(TableConformations {
            path: path.to_path_buf(),
            lines,
            line_no: 1,
            pending: None,
            done: false,
        })
    }

    /// The next row: its conformation key and position; `None` at the end.
    fn row(&mut self) -> Result<Option<Row>> {
        loop {
            let Some(line) = self.lines.next() else {
                return Ok(None);
            };
            self.line_no += 1;
            let line = line.map_err(|e| Error::io(&self.path, e))?;
            if line.trim().is_empty() {
                continue;
            }
            let fields: Vec<&str> = line.split('\t').map(str::trim).collect();
            if fields.len() != 7 {
                return Err(Error::parse(
                    &self.path,
                    self.line_no,
                    format!(
                        "expected 7 columns, found {} (a truncated row?)",
                        fields.len()
                    ),
                ));
            }
            let xyz = coordinates(&fields[4..7])
                .map_err(|m| Error::parse(&self.path, self.line_no, m))?;
            return Ok(Some(((fields[0].to_string(), fields[1].to_string()), xyz)));
        }
    }
}

impl Iterator for TableConformations {
    type Item = Result<Conformation>;

    fn next(&mut self) -> Option<Result<Conformation>> {
        if self.done {
            return None;
        }
        let first = match self.pending.take() {
            Some(row) => row,
            None => match self.row() {
                Ok(Some(row)) => row,
                Ok(None) => {
                    self.done = true;
                    return None;
                }
                Err(error) => {
                    self.done = true;
                    return Some(Err(error));
                }
            },
        };
        let (key, position) = first;
        let mut positions = vec![position];
        loop {
            match self.row() {
                Ok(Some((next_key, p))) if next_key == key => positions.push(p),
                Ok(Some(row)) => {
                    self.pending = Some(row);
                    break;
                }
                Ok(None) => {
                    self.done = true;
                    break;
                }
                Err(error) => {
                    self.done = true;
                    return Some(Err(error));
                }
            }
        }
        let label = format!("{}:replica {} sample {}", self.path.display(), key.0, key.1);
        Some(checked(label, positions, None, LengthUnit::Model))
    }
}
