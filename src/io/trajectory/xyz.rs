//! XYZ trajectories: frames of a line with the number of atoms `N`, a comment line, and `N`
//! lines `name x y z` (extra columns ignored). Plain or gzip.

use std::io::BufRead;
use std::path::{Path, PathBuf};

use super::frame::{Conformation, LengthUnit, checked, coordinates};
use crate::error::{Error, Result};

/// The frames of an XYZ file, read one at a time.
pub struct XyzFrames {
    path: PathBuf,
    lines: std::io::Lines<Box<dyn BufRead + Send>>,
    line_no: u64,
    frame: usize,
}

impl XyzFrames {
    /// Open the XYZ file at `path`.
    pub fn open(path: &Path) -> Result<XyzFrames> {
        Ok(XyzFrames {
            path: path.to_path_buf(),
            lines: crate::io::plumbing::input::open_text(path)?.lines(),
            line_no: 0,
            frame: 0,
        })
    }

    fn line(&mut self) -> Result<Option<String>> {
        match self.lines.next() {
            None => Ok(None),
            Some(line) => {
                self.line_no += 1;
                line.map(Some).map_err(|e| Error::io(&self.path, e))
            }
        }
    }

    fn frame(&mut self) -> Result<Option<Conformation>> {
        // the atom count (blank lines between frames skipped)
        let count = loop {
            match self.line()? {
                None => return Ok(None),
                Some(line) if line.trim().is_empty() => continue,
                Some(line) => break line,
            }
        };
        self.frame += 1;
        let frame = self.frame;
        let n: usize = count.trim().parse().map_err(|_| {
            Error::parse(
                &self.path,
                self.line_no,
                format!("frame {frame}: '{}' is not an atom count", count.trim()),
            )
        })?;
        let path = self.path.clone();
        let truncated = |at: u64| {
            Error::parse(
                &path,
                at,
                format!("frame {frame} is truncated: the file ends before its {n} atoms"),
            )
        };
        if self.line()?.is_none() {
            return Err(truncated(self.line_no));
        }
        let mut positions = Vec::with_capacity(n);
        for _ in 0..n {
            let line = self.line()?.ok_or_else(|| truncated(self.line_no))?;
            let fields: Vec<&str> = line.split_whitespace().collect();
            if fields.len() < 4 {
                return Err(Error::parse(
                    &self.path,
                    self.line_no,
                    format!(
                        "frame {frame}: expected 'name x y z', found '{}'",
                        line.trim()
                    ),
                ));
            }
            let xyz = coordinates(&fields[1..4]).map_err(|m| {
                Error::parse(&self.path, self.line_no, format!("frame {frame}: {m}"))
            })?;
            positions.push(xyz);
        }
        let label = format!("{}:frame {frame}", self.path.display());
        checked(label, positions, None, LengthUnit::Angstrom).map(Some)
    }
}

impl super::frame::ReadFrame for XyzFrames {
    fn read_frame(&mut self) -> Result<Option<Conformation>> {
        self.frame()
    }
}
