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
pub mod topology;
pub mod xtc;
pub mod xyz;

mod buffers;
mod chunks;
mod format;
mod frame;
mod selection;
mod stream;

pub use chunks::for_each_chunk;
pub use format::TrajectoryFormat;
pub use frame::{Conformation, LengthUnit, ReadFrame};
pub use selection::AtomSelection;
pub use stream::{Trajectories, open_trajectories};

#[cfg(test)]
mod mutant_tests;
