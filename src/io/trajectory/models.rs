//! Multi-model PDB / mmCIF files as trajectories (NMR ensembles, MD frames written as PDB):
//! each model a frame of all its atoms (waters and ligands too), in file order, with the
//! reading rules of [`crate::io::structure`] (first alternate location of an atom, Angstrom).
//! The file is read whole (such files hold tens of models); every model must have the first
//! one's atoms.

use std::collections::VecDeque;
use std::path::Path;

use super::{checked, Conformation, LengthUnit};
use crate::error::{Error, Result};
use crate::io::structure::for_each_atom_site;

/// The models of a PDB or mmCIF file.
pub struct ModelFrames {
    frames: VecDeque<Result<Conformation>>,
}

impl ModelFrames {
    /// Read the models of the file at `path`.
    pub fn open(path: &Path) -> Result<ModelFrames> {
        let mut text = String::new();
        std::io::Read::read_to_string(&mut crate::io::open_text(path)?, &mut text)
            .map_err(|e| Error::io(path, e))?;
        let mut models: Vec<Vec<[f64; 3]>> = Vec::new();
        // the first model's atoms (residue, name) with their alternate locations dropped
        let mut seen = std::collections::HashSet::new();
        let mut frames = VecDeque::new();
        let mut error = None;
        let mut last_model = usize::MAX;
        let result = for_each_atom_site(&text, path, &|_| true, &mut |site| {
            if site.model != last_model {
                last_model = site.model;
                seen.clear();
                models.push(Vec::new());
            }
            let key = (
                site.chain.to_string(),
                site.number,
                site.insertion,
                site.residue_name.to_string(),
                site.atom.name.clone(),
            );
            if seen.insert(key) {
                models.last_mut().expect("pushed").push(site.atom.xyz);
            }
            Ok(true)
        });
        if let Err(e) = result {
            error = Some(e);
        }
        let first = models.first().map_or(0, Vec::len);
        for (k, positions) in models.into_iter().enumerate() {
            let label = format!("{}:model {}", path.display(), k + 1);
            if positions.len() != first {
                frames.push_back(Err(Error::Invalid(format!(
                    "{label}: {} atoms, the first model has {first}",
                    positions.len()
                ))));
                break;
            }
            frames.push_back(checked(label, positions, None, LengthUnit::Angstrom));
        }
        if let Some(error) = error {
            return Err(error);
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
