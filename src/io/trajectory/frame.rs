//! A frame: one conformation as every reader hands it out (its beads' positions, periodic cell
//! and length unit), the checks every reader makes on it, and the readers of one frame at a time.

use crate::error::{Error, Result};

/// One conformation: its beads' positions and where it was read (`file::block`,
/// `file:replica/sample`, `file:frame`), for messages.
#[derive(Clone, Debug, PartialEq)]
pub struct Conformation {
    /// Where it was read.
    pub label: String,
    /// The beads' positions, in the file's units.
    pub positions: Vec<[f64; 3]>,
    /// The periodic cell's three box vectors (rows), in the same units, when the frame has one
    /// (DCD unit cells, XTC boxes).
    pub cell: Option<[[f64; 3]; 3]>,
    /// The unit of the positions, by the file's format.
    pub unit: LengthUnit,
}

/// The length unit of a trajectory format's coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LengthUnit {
    /// Angstrom (DCD, PDB / mmCIF, XYZ).
    Angstrom,
    /// Nanometres (XTC).
    Nanometre,
    /// Whatever the writer used (polychrom's and our own polymer conformations: bead units).
    Model,
}

/// A reader of one frame at a time: `Ok(None)` at the end.
pub trait ReadFrame {
    /// The next frame.
    fn read_frame(&mut self) -> Result<Option<Conformation>>;
}

/// The frames of a [`ReadFrame`] as an iterator, ended by the end of the file or by the first
/// error (returned once).
pub(super) struct Frames<R> {
    reader: R,
    done: bool,
}

impl<R: ReadFrame> Frames<R> {
    pub(super) fn boxed(reader: R) -> Box<dyn Iterator<Item = Result<Conformation>>>
    where
        R: 'static,
    {
        Box::new(Frames {
            reader,
            done: false,
        })
    }
}

impl<R: ReadFrame> Iterator for Frames<R> {
    type Item = Result<Conformation>;

    fn next(&mut self) -> Option<Result<Conformation>> {
        if self.done {
            return None;
        }
        let frame = self.reader.read_frame();
        self.done = !matches!(frame, Ok(Some(_)));
        frame.transpose()
    }
}

/// The error of point `index` (0-based) of conformation `label` at the non-finite position
/// `p`: named an atom in molecular formats, a bead in polymer ones (by `unit`), counted from 1
/// as frames are.
pub(crate) fn non_finite(label: &str, index: usize, p: [f64; 3], unit: LengthUnit) -> Error {
    let noun = match unit {
        LengthUnit::Model => "bead",
        LengthUnit::Angstrom | LengthUnit::Nanometre => "atom",
    };
    Error::Data(format!(
        "{label}: {noun} {} has a non-finite coordinate ({}, {}, {})",
        index + 1,
        p[0],
        p[1],
        p[2]
    ))
}

/// A conformation's positions checked: at least one bead, every coordinate finite.
pub(crate) fn checked(
    label: String,
    positions: Vec<[f64; 3]>,
    cell: Option<[[f64; 3]; 3]>,
    unit: LengthUnit,
) -> Result<Conformation> {
    if positions.is_empty() {
        return Err(Error::Data(format!(
            "{label}: an empty conformation (no bead)"
        )));
    }
    if let Some(bead) = positions
        .iter()
        .position(|p| !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite()))
    {
        return Err(non_finite(&label, bead, positions[bead], unit));
    }
    if let Some(cell) = cell {
        let [a, b, c] = cell;
        let volume = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]);
        if !(volume.is_finite() && volume.abs() > 0.0) {
            return Err(Error::Data(format!(
                "{label}: corrupt unit cell (box vectors {a:?}, {b:?}, {c:?}: volume {volume})"
            )));
        }
    }
    Ok(Conformation {
        label,
        positions,
        cell,
        unit,
    })
}

/// Three coordinates from their text (the message names the one that is not a number).
pub(crate) fn coordinates(fields: &[&str]) -> std::result::Result<[f64; 3], String> {
    let mut xyz = [0.0; 3];
    for (x, text) in xyz.iter_mut().zip(fields) {
        *x = text
            .parse()
            .map_err(|_| format!("coordinate '{text}' is not a number"))?;
    }
    Ok(xyz)
}
