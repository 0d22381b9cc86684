//! Topologies of molecular-dynamics trajectories: every atom of the first model of a PDB or
//! mmCIF file, in file order (the order of the trajectory's coordinates), grouped into residues
//! and chains as MDTraj's PDB reader groups them.
//!
//! Unlike [`crate::io::protein::structure`], nothing is dropped (waters, ions, ligands, hydrogens stay,
//! so atom `k` here is atom `k` of each frame) and residue names are kept as written (`HSD`,
//! `HIE` ...). Rules: a new residue starts when the chain id, residue number, insertion code or
//! residue name changes; a new chain when the chain id changes or after a `TER` record; later
//! alternate locations are skipped by the shared atom-record reader
//! ([`crate::io::protein::structure::for_each_atom_site`]), in the trajectory readers of PDB models too. Elements come
//! from PDB columns 77-78 (mmCIF `type_symbol`), else from the atom name.

use std::path::Path;

use crate::error::{Error, Result};
use crate::io::protein::structure::for_each_atom_site;

/// One atom of a topology.
#[derive(Clone, Debug, PartialEq)]
pub struct TopologyAtom {
    /// The atom name, e.g. `CA`, `HN`.
    pub name: String,
    /// The element symbol, upper case.
    pub element: String,
    /// Its residue (index into [`Topology::residues`]).
    pub residue: usize,
}

/// One residue of a topology.
#[derive(Clone, Debug, PartialEq)]
pub struct TopologyResidue {
    /// The residue name as written.
    pub name: String,
    /// Its chain (index into [`Topology::chains`]).
    pub chain: usize,
    /// The author residue number.
    pub number: i32,
    /// The insertion code, if any.
    pub insertion: Option<char>,
    /// Its atoms (indices into [`Topology::atoms`]).
    pub atoms: std::ops::Range<usize>,
}

impl TopologyResidue {
    /// Its author number with its insertion code, as PDB files write them (`52`, `52A`).
    pub fn label(&self) -> String {
        match self.insertion {
            Some(code) => format!("{}{code}", self.number),
            None => self.number.to_string(),
        }
    }
}

/// The atoms, residues and chains of a trajectory's topology file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Topology {
    /// Every atom, in file order.
    pub atoms: Vec<TopologyAtom>,
    /// The residues, in file order.
    pub residues: Vec<TopologyResidue>,
    /// The chains' ids, in file order (an id may repeat after a `TER`).
    pub chains: Vec<String>,
}

/// Read the topology of a PDB or mmCIF file (optionally gzipped); see the module docs.
///
/// ```
/// let topology = contactmap::io::topology::read_topology("data/protein/1aapA/1aapA.pdb.gz")?;
/// assert_eq!(topology.residues[0].name, "VAL");
/// assert_eq!(topology.atoms[1].name, "CA");
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn read_topology(path: impl AsRef<Path>) -> Result<Topology> {
    let path = path.as_ref();
    parse_topology(&crate::io::protein::structure::structure_text(path)?, path)
}

/// Parse the topology in `text` (`path` names it in messages).
pub fn parse_topology(text: &str, path: &Path) -> Result<Topology> {
    let mut topology = Topology::default();
    let mut current: Option<(String, i32, Option<char>, String)> = None;
    for_each_atom_site(text, path, &|_| true, &mut |site| {
        if site.model > 0 {
            return Ok(false);
        }
        let key = (
            site.chain.to_string(),
            site.number,
            site.insertion,
            site.residue_name.to_string(),
        );
        let new_chain = site.after_ter
            || current
                .as_ref()
                .is_none_or(|(chain, ..)| chain != site.chain);
        if new_chain {
            topology.chains.push(site.chain.to_string());
        }
        if new_chain || current.as_ref() != Some(&key) {
            let start = topology.atoms.len();
            topology.residues.push(TopologyResidue {
                name: site.residue_name.to_string(),
                chain: topology.chains.len() - 1,
                number: site.number,
                insertion: site.insertion,
                atoms: start..start,
            });
            current = Some(key);
        }
        let residue = topology.residues.len() - 1;
        topology.atoms.push(TopologyAtom {
            name: site.atom.name,
            element: site.atom.element,
            residue,
        });
        topology.residues[residue].atoms.end = topology.atoms.len();
        Ok(true)
    })?;
    if topology.atoms.is_empty() {
        return Err(Error::format(
            path,
            "no ATOM / HETATM record (an empty topology)",
        ));
    }
    Ok(topology)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn residues_and_chains_as_mdtraj_groups_them() {
        let text = "\
ATOM      1  N   ALA A   1       1.000   2.000   3.000  1.00  0.00           N
ATOM      2  CA AALA A   1       1.000   2.000   4.000  0.50  0.00           C
ATOM      3  CA BALA A   1       9.000   9.000   9.000  0.50  0.00           C
ATOM      4  HN  HSD A   2       5.000   5.000   5.000  1.00  0.00
TER
ATOM      5  CA  GLY A   3       5.000   5.000   5.000  1.00  0.00           C
HETATM    6  OH2 TIP3W   1       0.000   0.000   0.000  1.00  0.00           O
HETATM    7  OH2 TIP3W   1       0.000   0.000   1.000  1.00  0.00           O
ENDMDL
ATOM      1  N   ALA A   1       1.000   2.000   3.000  1.00  0.00           N
";
        let topology = parse_topology(text, Path::new("t.pdb")).unwrap();
        let names: Vec<&str> = topology.atoms.iter().map(|a| a.name.as_str()).collect();
        assert_eq!(names, ["N", "CA", "HN", "CA", "OH2"]);
        assert_eq!(topology.atoms[2].element, "H");
        let residues: Vec<(&str, usize, i32)> = topology
            .residues
            .iter()
            .map(|r| (r.name.as_str(), r.chain, r.number))
            .collect();
        assert_eq!(
            residues,
            [("ALA", 0, 1), ("HSD", 0, 2), ("GLY", 1, 3), ("TIP", 2, 1)]
        );
        assert_eq!(topology.chains, ["A", "A", "W"]);
        assert_eq!(topology.residues[1].atoms, 2..3);
    }
}
