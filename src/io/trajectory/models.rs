//! Multi-model PDB / mmCIF files as trajectories (NMR ensembles, MD frames written as PDB):
//! each model a frame of all its atoms (waters and ligands too), in file order, with the
//! reading rules of [`crate::io::protein::structure`] (first alternate location of an atom, Angstrom).
//! The file is read whole (such files hold tens of models); every model must have the first
//! one's atoms.

use std::collections::VecDeque;
use std::path::Path;

use super::frame::{Conformation, LengthUnit, checked};
use crate::error::{Error, Result};
use crate::io::protein::structure::{for_each_atom_site, structure_text};

/// The models of a PDB or mmCIF file.
pub struct ModelFrames {
    frames: VecDeque<Result<Conformation>>,
}

impl ModelFrames {
    /// Read the models of the file at `path`.
    pub fn open(path: &Path) -> Result<ModelFrames> {
        let text = structure_text(path)?;
        let mut models: Vec<Vec<[f64; 3]>> = Vec::new();
        for_each_atom_site(&text, path, &|_| true, &mut |site| {
            if models.len() <= site.model {
                models.push(Vec::new());
            }
            models.last_mut().expect("pushed").push(site.atom.xyz);
            Ok(true)
        })?;
        let first = models.first().map_or(0, Vec::len);
        let mut frames = VecDeque::new();
        for (k, positions) in models.into_iter().enumerate() {
            let label = format!("{}:model {}", path.display(), k + 1);
            if positions.len() != first {
                frames.push_back(Err(Error::Data(format!(
                    "{label}: {} atoms, the first model has {first}",
                    positions.len()
                ))));
                break;
            }
            frames.push_back(checked(label, positions, None, LengthUnit::Angstrom));
        }
        if frames.is_empty() {
            return Err(Error::format(path, "no ATOM / HETATM record (no model)"));
        }
        Ok(ModelFrames { frames })
    }
}

impl Iterator for ModelFrames {
    type Item = Result<Conformation>;

    fn next(&mut self) -> Option<Result<Conformation>> {
        self.frames.pop_front()
    }
}
