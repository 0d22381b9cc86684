//! DCD trajectories (CHARMM / NAMD / OpenMM / LAMMPS): Fortran unformatted records, either
//! byte order, read one frame at a time.
//!
//! Written here rather than taken from a crate: no maintained Rust crate reads DCD alone (the
//! ones that do are whole molecular-modelling toolkits, or chemfiles' C++ library, which would
//! be built with cmake into every binary), and the format is three fixed header records and
//! then fixed-size frames. The rules are those of VMD's dcdplugin, which MDTraj and MDAnalysis
//! use: the header's frame count is not trusted (writers leave it stale), frames are read until
//! the end of the file; a CHARMM file (version field non-zero) may carry a unit cell record
//! (six doubles `A, gamma, B, beta, alpha, C`, angles in degrees or as cosines) and a fourth
//! coordinate (skipped) per frame. Files with fixed atoms (`NAMNF > 0`) and 64-bit record
//! markers are refused with a message. Coordinates are single precision, in Angstrom.

use std::io::{BufReader, Read, Seek};
use std::path::{Path, PathBuf};

use std::sync::Arc;

use super::buffers::positions_buffer;
use super::frame::{Conformation, LengthUnit, checked, non_finite};
use super::selection::AtomSelection;
use crate::error::{Error, Result};

/// The frames of a DCD file.
pub struct DcdFrames {
    path: PathBuf,
    file: BufReader<std::fs::File>,
    big_endian: bool,
    natoms: usize,
    cell: bool,
    fourth: bool,
    frame: usize,
    remaining: u64,
    buffer: Vec<u8>,
    decoded: Vec<f32>,
    selection: Option<Arc<AtomSelection>>,
}

impl DcdFrames {
    /// Open the DCD file at `path` and read its header.
    pub fn open(path: &Path) -> Result<DcdFrames> {
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
        let length = file.metadata().map_err(|e| Error::io(path, e))?.len();
        let mut file = BufReader::new(file);
        let mut first = [0u8; 4];
        file.read_exact(&mut first)
            .map_err(|_| Error::format(path, "not a DCD file (shorter than its first record)"))?;
        let big_endian = if i32::from_le_bytes(first) == 84 {
            false
        } else if i32::from_be_bytes(first) == 84 {
            true
        } else {
            return Err(Error::format(
                path,
                "not a DCD file (its first record is not the 84-byte CORD header; 64-bit \
                 record markers are not supported)",
            ));
        };
        let mut frames = DcdFrames {
            path: path.to_path_buf(),
            file,
            big_endian,
            natoms: 0,
            cell: false,
            fourth: false,
            frame: 0,
            remaining: 0,
            buffer: Vec::new(),
            decoded: Vec::new(),
            selection: None,
        };
        let mut header = [0u8; 84];
        frames.read_bytes(&mut header, "header")?;
        frames.marker(84, "header")?;
        if &header[..4] != b"CORD" {
            let message = if header[..4] == [0; 4] && &header[4..8] == b"CORD" {
                "64-bit record markers are not supported (write the DCD with 32-bit markers)"
            } else {
                "not a DCD file (no CORD signature)"
            };
            return Err(Error::format(path, message));
        }
        let control = |k: usize| frames.int(header[4 + 4 * k..8 + 4 * k].try_into().unwrap());
        let charmm = control(19) != 0;
        let fixed = control(8);
        let (cell, fourth) = (charmm && control(10) != 0, charmm && control(11) != 0);
        frames.cell = cell;
        frames.fourth = fourth;
        if fixed != 0 {
            return Err(Error::format(
                path,
                format!("DCD with {fixed} fixed atoms (NAMNF) is not supported"),
            ));
        }
        // the title record: its length, a count of 80-character lines, the lines
        let length_title = frames.read_i32("title")?;
        if length_title < 4 || (length_title - 4) % 80 != 0 {
            return Err(Error::format(
                path,
                format!("DCD title record of {length_title} bytes (expected 4 + 80 x lines)"),
            ));
        }
        // 96 bytes read so far; the title, its end marker and the atom count's record follow
        if length_title as u64 + 4 + 12 > length.saturating_sub(96) {
            return Err(Error::format(
                path,
                format!(
                    "DCD title record of {length_title} bytes in a file of {length} bytes \
                     (truncated or corrupt)"
                ),
            ));
        }
        let mut title = vec![0u8; length_title as usize];
        frames.read_bytes(&mut title, "title")?;
        frames.marker(length_title, "title")?;
        let lines = frames.int(title[..4].try_into().expect("four bytes"));
        if lines as i64 != (length_title as i64 - 4) / 80 {
            return Err(Error::format(
                path,
                format!(
                    "DCD title record of {length_title} bytes says it holds {lines} lines \
                     (expected {})",
                    (length_title - 4) / 80
                ),
            ));
        }
        frames.marker(4, "atom count")?;
        let natoms = frames.read_i32("atom count")?;
        frames.marker(4, "atom count")?;
        if natoms <= 0 {
            return Err(Error::format(path, format!("DCD atom count {natoms}")));
        }
        frames.natoms = natoms as usize;
        let position = frames
            .file
            .stream_position()
            .map_err(|e| Error::io(path, e))?;
        frames.remaining = length.saturating_sub(position);
        Ok(frames)
    }

    /// Keep only `selection`'s atoms of each frame (every atom still checked).
    pub fn selecting(mut self, selection: Option<Arc<AtomSelection>>) -> DcdFrames {
        self.selection = selection;
        self
    }

    fn int(&self, bytes: [u8; 4]) -> i32 {
        if self.big_endian {
            i32::from_be_bytes(bytes)
        } else {
            i32::from_le_bytes(bytes)
        }
    }

    fn read_bytes(&mut self, into: &mut [u8], what: &str) -> Result<()> {
        self.file.read_exact(into).map_err(|e| {
            if e.kind() == std::io::ErrorKind::UnexpectedEof {
                Error::format(&self.path, format!("truncated DCD ({what} cut short)"))
            } else {
                Error::io(&self.path, e)
            }
        })
    }

    fn read_i32(&mut self, what: &str) -> Result<i32> {
        let mut bytes = [0u8; 4];
        self.read_bytes(&mut bytes, what)?;
        Ok(self.int(bytes))
    }

    /// A record marker that must be `expected`.
    fn marker(&mut self, expected: i32, what: &str) -> Result<()> {
        let found = self.read_i32(what)?;
        if found != expected {
            return Err(Error::format(
                &self.path,
                format!("DCD {what} record marker {found}, expected {expected}"),
            ));
        }
        Ok(())
    }

    /// The record of `length` bytes at `*at` in a frame's `bytes` (between its two markers),
    /// `*at` moved past it.
    fn record<'a>(
        &self,
        bytes: &'a [u8],
        at: &mut usize,
        length: usize,
        what: &str,
    ) -> Result<&'a [u8]> {
        let marker = |k: usize| self.int(bytes[k..k + 4].try_into().unwrap());
        for found in [marker(*at), marker(*at + 4 + length)] {
            if found != length as i32 {
                return Err(Error::format(
                    &self.path,
                    format!("DCD {what} record marker {found}, expected {length}"),
                ));
            }
        }
        let record = &bytes[*at + 4..*at + 4 + length];
        *at += 8 + length;
        Ok(record)
    }

    fn frame_bytes(&self) -> u64 {
        let coordinates = 8 + 4 * self.natoms as u64;
        (if self.cell { 56 } else { 0 }) + coordinates * (3 + u64::from(self.fourth))
    }

    fn next_frame(&mut self) -> Result<Option<Conformation>> {
        if self.remaining == 0 {
            return Ok(None);
        }
        self.frame += 1;
        let label = format!("{}:frame {}", self.path.display(), self.frame);
        if self.remaining < self.frame_bytes() {
            return Err(Error::Data(format!(
                "{label}: truncated frame ({} of its {} bytes)",
                self.remaining,
                self.frame_bytes()
            )));
        }
        self.remaining -= self.frame_bytes();
        // the whole frame in one read, then its records taken apart
        let mut bytes = std::mem::take(&mut self.buffer);
        bytes.resize(self.frame_bytes() as usize, 0);
        let what = format!("frame {}", self.frame);
        self.read_bytes(&mut bytes, &what)?;
        let mut at = 0;
        let cell = if self.cell {
            let record = self.record(&bytes, &mut at, 48, &what)?;
            let value = |k: usize| {
                let b: [u8; 8] = record[8 * k..8 * k + 8].try_into().unwrap();
                if self.big_endian {
                    f64::from_be_bytes(b)
                } else {
                    f64::from_le_bytes(b)
                }
            };
            cell_vectors(
                [value(0), value(2), value(5)],
                [value(4), value(3), value(1)],
            )
        } else {
            None
        };
        let n = self.natoms;
        let mut axes = [&[][..]; 3];
        for axis in &mut axes {
            *axis = self.record(&bytes, &mut at, 4 * n, &what)?;
        }
        // each axis decoded on its own (a loop the compiler vectorises), then interleaved
        let mut decoded = std::mem::take(&mut self.decoded);
        decoded.clear();
        for axis in axes {
            let bytes = axis
                .chunks_exact(4)
                .map(|b| -> [u8; 4] { b.try_into().unwrap() });
            if self.big_endian {
                decoded.extend(bytes.map(f32::from_be_bytes));
            } else {
                decoded.extend(bytes.map(f32::from_le_bytes));
            }
        }
        let (x, rest) = decoded.split_at(n);
        let (y, z) = rest.split_at(n);
        let point = |a: usize| [f64::from(x[a]), f64::from(y[a]), f64::from(z[a])];
        if let Some(selection) = &self.selection {
            selection.check_count(&label, n)?;
        }
        // every atom checked, selected or not
        if !decoded.iter().all(|v| v.is_finite()) {
            let finite = |a: usize| point(a).iter().all(|v| v.is_finite());
            let bead = (0..n).find(|&a| !finite(a)).unwrap_or_default();
            return Err(non_finite(&label, bead, point(bead), LengthUnit::Angstrom));
        }
        let positions = match &self.selection {
            None => {
                let mut positions = positions_buffer(n);
                positions.extend((0..n).map(point));
                positions
            }
            Some(selection) => {
                let mut positions = positions_buffer(selection.keep.len());
                positions.extend(selection.keep.iter().map(|&a| point(a as usize)));
                positions
            }
        };
        self.decoded = decoded;
        if self.fourth {
            self.record(&bytes, &mut at, 4 * n, &what)?;
        }
        self.buffer = bytes;
        checked(label, positions, cell, LengthUnit::Angstrom).map(Some)
    }
}

/// The box vectors (rows) of a cell given by its lengths `A, B, C` and angles `alpha, beta,
/// gamma` (degrees, or cosines when all three are at most 1 in magnitude, as NAMD writes
/// them); `None` for the all-zero cell of non-periodic runs.
fn cell_vectors(lengths: [f64; 3], angles: [f64; 3]) -> Option<[[f64; 3]; 3]> {
    if lengths.iter().all(|&l| l == 0.0) {
        return None;
    }
    let degrees = if angles.iter().all(|a| a.abs() <= 1.0) {
        angles.map(|cosine| 90.0 - cosine.asin().to_degrees())
    } else {
        angles
    };
    let [alpha, beta, gamma] = degrees.map(f64::to_radians);
    let [a, b, c] = lengths;
    let cos = |x: f64| {
        let v = x.cos();
        if v.abs() < 1e-12 { 0.0 } else { v }
    };
    let bx = b * cos(gamma);
    let by = b * gamma.sin();
    let cx = c * cos(beta);
    let cy = c * (cos(alpha) - cos(beta) * cos(gamma)) / gamma.sin();
    let cz = (c * c - cx * cx - cy * cy).max(0.0).sqrt();
    Some([[a, 0.0, 0.0], [bx, by, 0.0], [cx, cy, cz]])
}

impl super::frame::ReadFrame for DcdFrames {
    fn read_frame(&mut self) -> Result<Option<Conformation>> {
        self.next_frame()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::trajectory::open_trajectories;

    fn frames(path: &str, selection: Option<AtomSelection>) -> Result<Vec<Conformation>> {
        let opened = open_trajectories(&[path.to_string()])?;
        match selection {
            Some(selection) => opened.select(selection).collect(),
            None => opened.collect(),
        }
    }

    /// Selected atoms are the whole frames' atoms, picked; the count and every coordinate are
    /// still checked; other formats are selected after reading.
    #[test]
    fn a_selection_keeps_the_whole_frames_atoms() {
        let whole = frames("data/md/cobrotoxin.dcd", None).unwrap();
        let n = whole[0].positions.len();
        let keep = vec![(n - 1) as u32, 0, 17, 17, 400];
        let selection = AtomSelection::new(n, keep).unwrap();
        assert_eq!(selection.keep, [0, 17, 400, n as u32 - 1]);
        let picked = frames("data/md/cobrotoxin.dcd", Some(selection.clone())).unwrap();
        assert_eq!(picked.len(), whole.len());
        for (a, b) in whole.iter().zip(&picked) {
            let expected: Vec<[f64; 3]> = selection
                .keep
                .iter()
                .map(|&k| a.positions[k as usize])
                .collect();
            assert_eq!(b.positions, expected);
            assert_eq!((&a.label, a.cell, a.unit), (&b.label, b.cell, b.unit));
        }
        // another topology's count
        let other = AtomSelection::new(n + 1, vec![0]).unwrap();
        let error = frames("data/md/cobrotoxin.dcd", Some(other))
            .unwrap_err()
            .to_string();
        assert!(error.ends_with(&format!("frame 1: {n} atoms, the topology has {}", n + 1)));
        assert!(AtomSelection::new(3, vec![3]).is_err());
        // a NaN in an atom not kept is still found
        let mut bytes = std::fs::read("data/md/cobrotoxin.dcd").unwrap();
        let header = bytes.len() - whole.len() * (56 + 3 * (8 + 4 * n));
        let at = header + 56 + 4 + 4 * 5;
        bytes[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nan.dcd");
        std::fs::write(&path, bytes).unwrap();
        let error = frames(&path.to_string_lossy(), Some(selection.clone()))
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("frame 1: atom 6 has a non-finite coordinate (NaN"),
            "{error}"
        );
        // XTC frames: selected after reading
        let whole = frames("data/md/adk.xtc", None).unwrap();
        let n = whole[0].positions.len();
        let selection = AtomSelection::new(n, vec![2, 9]).unwrap();
        let picked = frames("data/md/adk.xtc", Some(selection)).unwrap();
        assert_eq!(
            picked[2].positions,
            [whole[2].positions[2], whole[2].positions[9]]
        );
    }

    #[test]
    fn cells_from_lengths_and_angles() {
        assert_eq!(cell_vectors([0.0; 3], [90.0; 3]), None);
        let cubic = cell_vectors([10.0, 20.0, 30.0], [90.0; 3]).unwrap();
        assert_eq!(
            cubic,
            [[10.0, 0.0, 0.0], [0.0, 20.0, 0.0], [0.0, 0.0, 30.0]]
        );
        // cosines (NAMD) read as the same angles
        assert_eq!(cell_vectors([10.0, 20.0, 30.0], [0.0; 3]).unwrap(), cubic);
        // a rhombic dodecahedron (60, 60, 90): |c| stays its length
        let v = cell_vectors([8.0, 8.0, 8.0], [60.0, 60.0, 90.0]).unwrap();
        let norm = |x: [f64; 3]| (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
        assert!((norm(v[2]) - 8.0).abs() < 1e-12);
        let dot = v[1][0] * v[2][0] + v[1][1] * v[2][1] + v[1][2] * v[2][2];
        assert!((dot / 64.0 - 0.5).abs() < 1e-12, "cos alpha = 1/2");
    }
}
