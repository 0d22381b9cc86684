//! The trajectory formats, and the format of an input.

use std::path::Path;

use crate::error::Result;
use crate::io::matrices::kind::{FileKind, detect_kind};

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

impl TrajectoryFormat {
    /// The format of `input`: a folder or an HDF5 file (by its signature, `::` URIs too) is
    /// polychrom's; `.xyz` is XYZ, `.dcd` DCD, `.xtc` XTC, `.pdb` / `.ent` / `.cif` / `.mmcif`
    /// (optionally `.gz`) models; anything else a conformations table.
    pub fn detect(input: &str) -> Result<TrajectoryFormat> {
        let path = Path::new(input.split("::").next().unwrap_or(input));
        if path.is_dir() || input.contains("::") {
            return Ok(TrajectoryFormat::Polychrom);
        }
        if detect_kind(&path.to_string_lossy())? == FileKind::Hdf5 {
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
