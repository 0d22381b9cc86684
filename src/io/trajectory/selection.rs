//! Atom selections: the atoms of every frame kept when a topology says which ones are measured.

use super::buffers::positions_buffer;
use super::frame::{Conformation, LengthUnit};
use crate::error::{Error, Result};

/// Some atoms of every frame of an MD trajectory whose frames have a topology's atoms: the
/// others are read (each frame is checked whole) but not kept ([`Trajectories::select`]).
///
/// [`Trajectories::select`]: crate::io::trajectory::Trajectories::select
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
            return Err(Error::Argument(format!(
                "atom {} selected from frames of {atoms} atoms",
                keep[keep.len() - 1]
            )));
        }
        Ok(AtomSelection { atoms, keep })
    }

    /// The error of a frame `label` of `atoms` atoms when it has not the topology's count.
    pub(super) fn check_count(&self, label: &str, atoms: usize) -> Result<()> {
        if atoms == self.atoms {
            return Ok(());
        }
        Err(Error::Data(format!(
            "{label}: {atoms} atoms, the topology has {}",
            self.atoms
        )))
    }

    /// The selected atoms of a whole frame; polymer conformations (no topology: bead units)
    /// pass whole, for their consumer to refuse.
    pub(super) fn apply(&self, mut conformation: Conformation) -> Result<Conformation> {
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
