//! Trajectories: sets of 3D conformations of a polymer (or of any chain of beads), read one
//! conformation at a time so that a trajectory of any length streams in bounded memory.
//!
//! Formats:
//!
//! - **polychrom** ([`polychrom`]): the HDF5 trajectories of polychrom's `HDF5Reporter`
//!   (`polychrom/hdf5_format.py`): files `blocks_X-Y.h5` holding blocks X to Y as groups `/X`
//!   .. `/Y`, each with a dataset `pos` (`N x 3`). An input is a trajectory folder (every
//!   `blocks_*-*.h5` in it, by block number), one blocks file, or one block as polychrom's URI
//!   `blocks_1-50.h5::42`.
//! - **conformations tables** ([`table`]): what `contactmap simulate polymer --conformations`
//!   writes, `replica sample chain bead x y z` (TSV, `.gz` too): one conformation per
//!   `(replica, sample)`, its chains one after the other.
//! - **XYZ** ([`xyz`]): frames of `N`, a comment line and `N` lines `name x y z`.
//! - **DCD** ([`dcd`]): CHARMM / NAMD / OpenMM binary frames (Angstrom), with their unit cell.
//! - **XTC** ([`xtc`]): GROMACS compressed frames (nanometres), with their box.
//! - **multi-model PDB / mmCIF** ([`models`]): every `MODEL` (or `pdbx_PDB_model_num`) a
//!   frame of all its atoms, in file order (Angstrom).
//!
//! Every conformation is checked as it is read: a non-finite coordinate, a truncated frame or an
//! empty block is an error naming the file and the conformation.

pub mod dcd;
pub mod models;
pub mod polychrom;
pub mod table;
pub mod xtc;
pub mod xyz;

use std::path::Path;
use std::sync::Arc;

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

/// The trajectory formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrajectoryFormat {
    /// polychrom's HDF5 blocks (a folder, a blocks file, or a `file::block` URI).
    Polychrom,
    /// contactmap's conformations table (`replica sample chain bead x y z`).
    Table,
    /// XYZ frames.
    Xyz,
    /// DCD frames.
    Dcd,
    /// XTC frames.
    Xtc,
    /// The models of a PDB or mmCIF file.
    Models,
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

impl TrajectoryFormat {
    /// The format of `input`: a folder or an HDF5 file (by its signature, `::` URIs too) is
    /// polychrom's; `.xyz` is XYZ, `.dcd` DCD, `.xtc` XTC, `.pdb` / `.ent` / `.cif` / `.mmcif`
    /// (optionally `.gz`) models; anything else a conformations table.
    pub fn detect(input: &str) -> Result<TrajectoryFormat> {
        let path = Path::new(input.split("::").next().unwrap_or(input));
        if path.is_dir() || input.contains("::") {
            return Ok(TrajectoryFormat::Polychrom);
        }
        if crate::io::detect_kind(&path.to_string_lossy())? == crate::io::FileKind::Hdf5 {
            return Ok(TrajectoryFormat::Polychrom);
        }
        let name = path.to_string_lossy().to_ascii_lowercase();
        let name = name.strip_suffix(".gz").unwrap_or(&name);
        let extension = name.rsplit_once('.').map_or("", |(_, extension)| extension);
        Ok(match extension {
            "xyz" => TrajectoryFormat::Xyz,
            "dcd" => TrajectoryFormat::Dcd,
            "xtc" => TrajectoryFormat::Xtc,
            "pdb" | "ent" | "cif" | "mmcif" => TrajectoryFormat::Models,
            _ => TrajectoryFormat::Table,
        })
    }
}

/// The conformations of `inputs`, one after the other, each read when asked for: an iterator of
/// `Result<Conformation>` (the first error ends it).
pub struct Trajectories {
    inputs: std::collections::VecDeque<String>,
    current: Option<Box<dyn Iterator<Item = Result<Conformation>>>>,
    failed: bool,
    selection: Option<Arc<AtomSelection>>,
}

/// Some atoms of every frame of an MD trajectory whose frames have a topology's atoms: the
/// others are read (each frame is checked whole) but not kept ([`Trajectories::select`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AtomSelection {
    /// The topology's atom count: every frame must have it.
    pub atoms: usize,
    /// The atoms kept, ascending, each below `atoms`.
    pub keep: Vec<u32>,
}

impl AtomSelection {
    /// The selection of atoms `keep` (sorted and deduplicated here) of frames of `atoms` atoms.
    pub fn new(atoms: usize, mut keep: Vec<u32>) -> Result<AtomSelection> {
        keep.sort_unstable();
        keep.dedup();
        if keep.last().is_some_and(|&last| last as usize >= atoms) {
            return Err(Error::Invalid(format!(
                "atom {} selected from frames of {atoms} atoms",
                keep[keep.len() - 1]
            )));
        }
        Ok(AtomSelection { atoms, keep })
    }

    /// The error of a frame `label` of `atoms` atoms when it has not the topology's count.
    fn check_count(&self, label: &str, atoms: usize) -> Result<()> {
        if atoms == self.atoms {
            return Ok(());
        }
        Err(Error::Invalid(format!(
            "{label}: {atoms} atoms, the topology has {}",
            self.atoms
        )))
    }

    /// The selected atoms of a whole frame; polymer conformations (no topology: bead units)
    /// pass whole, for their consumer to refuse.
    fn apply(&self, mut conformation: Conformation) -> Result<Conformation> {
        if conformation.unit == LengthUnit::Model {
            return Ok(conformation);
        }
        self.check_count(&conformation.label, conformation.positions.len())?;
        let mut positions = positions_buffer(self.keep.len());
        positions.extend(
            self.keep
                .iter()
                .map(|&a| conformation.positions[a as usize]),
        );
        conformation.positions = positions;
        Ok(conformation)
    }
}

impl Trajectories {
    /// Keep only `selection`'s atoms of every frame (frames must have its atom count: an error
    /// names the first that has not). The DCD reader converts only those atoms' coordinates.
    pub fn select(mut self, selection: AtomSelection) -> Trajectories {
        self.selection = Some(Arc::new(selection));
        self
    }
}

/// Open the trajectories `inputs` (each a folder, a file or a polychrom URI; the format detected
/// by [`TrajectoryFormat::detect`]). Nothing but the inputs' listing is read before the first
/// conformation is asked for.
///
/// ```
/// use contactmap::io::trajectory::open_trajectories;
/// let dir = std::env::temp_dir().join(format!("traj-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("two.xyz");
/// std::fs::write(&path, "2\nframe 1\nC 0 0 0\nC 1 0 0\n2\nframe 2\nC 0 0 0\nC 0 2 0\n")?;
/// let frames: Vec<_> = open_trajectories(&[path.to_string_lossy().into_owned()])?
///     .collect::<Result<_, _>>()?;
/// assert_eq!(frames.len(), 2);
/// assert_eq!(frames[1].positions[1], [0.0, 2.0, 0.0]);
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn open_trajectories(inputs: &[String]) -> Result<Trajectories> {
    if inputs.is_empty() {
        return Err(Error::Invalid("no trajectory given".into()));
    }
    for input in inputs {
        let path = Path::new(input.split("::").next().unwrap_or(input));
        // the system's own words, as the other readers give them ("No such file or directory")
        std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    }
    Ok(Trajectories {
        inputs: inputs.iter().cloned().collect(),
        current: None,
        failed: false,
        selection: None,
    })
}

type Conformations = Box<dyn Iterator<Item = Result<Conformation>>>;

fn open_one(input: &str, selection: Option<&Arc<AtomSelection>>) -> Result<Conformations> {
    let frames: Conformations = match TrajectoryFormat::detect(input)? {
        TrajectoryFormat::Dcd => {
            // the DCD reader selects while it converts
            let selection = selection.cloned();
            return Ok(Frames::boxed(
                dcd::DcdFrames::open(Path::new(input))?.selecting(selection),
            ));
        }
        TrajectoryFormat::Polychrom => Box::new(polychrom::PolychromBlocks::open(input)?),
        TrajectoryFormat::Table => Box::new(table::TableConformations::open(Path::new(input))?),
        TrajectoryFormat::Xyz => Frames::boxed(xyz::XyzFrames::open(Path::new(input))?),
        TrajectoryFormat::Xtc => Frames::boxed(xtc::XtcFrames::open(Path::new(input))?),
        TrajectoryFormat::Models => Box::new(models::ModelFrames::open(Path::new(input))?),
    };
    Ok(match selection {
        None => frames,
        Some(selection) => {
            let selection = Arc::clone(selection);
            Box::new(frames.map(move |frame| frame.and_then(|c| selection.apply(c))))
        }
    })
}

impl Iterator for Trajectories {
    type Item = Result<Conformation>;

    fn next(&mut self) -> Option<Result<Conformation>> {
        if self.failed {
            return None;
        }
        loop {
            if let Some(current) = &mut self.current {
                match current.next() {
                    Some(Ok(conformation)) => return Some(Ok(conformation)),
                    Some(Err(error)) => {
                        self.failed = true;
                        return Some(Err(error));
                    }
                    None => self.current = None,
                }
            }
            let input = self.inputs.pop_front()?;
            match open_one(&input, self.selection.as_ref()) {
                Ok(opened) => self.current = Some(opened),
                Err(error) => {
                    self.failed = true;
                    return Some(Err(error));
                }
            }
        }
    }
}

/// Read `frames` a chunk of `size` frames at a time and give each chunk to `work` on another
/// thread while this one reads the next, so that reading overlaps the work. `keep(index, frame)`
/// sees every frame as it is read (`index` counts from 0): an error stops everything, `false`
/// leaves the frame out of the chunks (a stride). Returns the number of frames worked on.
pub fn for_each_chunk(
    frames: &mut dyn Iterator<Item = Result<Conformation>>,
    size: usize,
    mut keep: impl FnMut(usize, &Conformation) -> Result<bool>,
    mut work: impl FnMut(&[Conformation]) + Send,
) -> Result<usize> {
    let mut index = 0;
    let mut read = || -> Result<Vec<Conformation>> {
        let mut chunk = Vec::with_capacity(size);
        while chunk.len() < size.max(1) {
            let Some(frame) = frames.next() else { break };
            let frame = frame?;
            index += 1;
            if keep(index - 1, &frame)? {
                chunk.push(frame);
            }
        }
        Ok(chunk)
    };
    let mut total = 0;
    let mut chunk = read()?;
    while !chunk.is_empty() {
        let next = std::thread::scope(|scope| {
            let working = scope.spawn(|| work(&chunk));
            let next = read();
            working.join().expect("the work on a chunk does not panic");
            next
        })?;
        total += chunk.len();
        recycle(std::mem::replace(&mut chunk, next));
    }
    Ok(total)
}

/// Position buffers of conformations worked on, for the next frames read: a trajectory's frames
/// all have the same size, and a buffer used again costs no page faults (80 kB a frame of an
/// all-atom protein; fresh memory made page faults half the time of a `ca` measure).
static SPARE_POSITIONS: std::sync::Mutex<Vec<Vec<[f64; 3]>>> = std::sync::Mutex::new(Vec::new());

/// At most this many positions are kept in [`SPARE_POSITIONS`] (32 MB).
const SPARE_COORDINATES: usize = (32 << 20) / std::mem::size_of::<[f64; 3]>();

/// Whether a reader took a buffer from [`SPARE_POSITIONS`] (the text readers do not: nothing
/// is kept for them).
static SPARE_DRAWN: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Keep the position buffers of `chunk` for [`positions_buffer`], up to [`SPARE_COORDINATES`],
/// once a reader draws from them.
fn recycle(chunk: Vec<Conformation>) {
    if !SPARE_DRAWN.load(std::sync::atomic::Ordering::Relaxed) {
        return;
    }
    let Ok(mut spare) = SPARE_POSITIONS.lock() else {
        return;
    };
    let mut held: usize = spare.iter().map(Vec::capacity).sum();
    for conformation in chunk {
        let mut positions = conformation.positions;
        if held + positions.capacity() > SPARE_COORDINATES {
            break;
        }
        held += positions.capacity();
        positions.clear();
        spare.push(positions);
    }
}

/// An empty position buffer with room for `n` beads: a recycled one when there is one.
pub(crate) fn positions_buffer(n: usize) -> Vec<[f64; 3]> {
    SPARE_DRAWN.store(true, std::sync::atomic::Ordering::Relaxed);
    let recycled = SPARE_POSITIONS
        .lock()
        .ok()
        .and_then(|mut spare| spare.pop());
    let mut positions = recycled.unwrap_or_default();
    positions.reserve(n);
    positions
}

/// A reader of one frame at a time: `Ok(None)` at the end.
pub trait ReadFrame {
    /// The next frame.
    fn read_frame(&mut self) -> Result<Option<Conformation>>;
}

/// The frames of a [`ReadFrame`] as an iterator, ended by the end of the file or by the first
/// error (returned once).
struct Frames<R> {
    reader: R,
    done: bool,
}

impl<R: ReadFrame> Frames<R> {
    fn boxed(reader: R) -> Box<dyn Iterator<Item = Result<Conformation>>>
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
    Error::Invalid(format!(
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
        return Err(Error::Invalid(format!(
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
            return Err(Error::Invalid(format!(
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

#[cfg(test)]
mod mutant_tests;
