//! Residue contact frequencies over a trajectory, with MDTraj's contact schemes
//! (`mdtraj.compute_contacts`), so that a predictor can be scored against an MD ensemble.
//!
//! The pairs are those of MDTraj's `contacts="all"`: residues with an atom named `CA`, in the
//! same chain, at least three residues apart by index (`j >= i + 3`; [`FrequencySpec::
//! min_separation`] changes the 3). A residue pair is in contact in a frame when its distance
//! is below the cutoff, the distance being, by [`Scheme`]:
//!
//! - `ca`: between the residues' `CA` atoms; `cb`: between their `CB` atoms (`CA` for glycine,
//!   CASP's definition; not an MDTraj scheme: MDTraj's `compute_distances` on those atoms);
//! - `closest` / `closest-heavy`: the closest pair of atoms (non-hydrogen atoms);
//! - `sidechain` / `sidechain-heavy`: the closest pair of side-chain atoms (MDTraj's
//!   `is_sidechain`: a protein atom not named `C CA N O HA H`; heavy atoms only, except glycine,
//!   whose side chain is its hydrogen).
//!
//! Atom and residue names are read as MDTraj standardises them for these tests (`HN`, `HT1`,
//! `H1` ... are `H`; `OT1`, `OC1` ... are `O`; `HSD`, `HIE` ... are `HIS`), and a residue is
//! protein when its name is an amino acid (or one of its MD force-field variants) or it has
//! `N`, `CA` and `C` atoms.
//!
//! Distances are computed as MDTraj computes them, so that frequencies are equal, not close:
//! coordinates in nanometres as single-precision floats (Angstrom files scaled by `0.1f32`),
//! the displacement, its squared length summed `x, y, z` and its square root in single
//! precision, compared with the cutoff (in nm, single precision). With a periodic cell and
//! [`FrequencySpec::periodic`], the minimum image: a rectangular box by rounding each component
//! (ties to even), a triclinic one by MDTraj's reduced box vectors and the 27 nearest images.
//!
//! Speed: without a cell, a residue pair whose bounding spheres (centre and radius of its
//! atoms, double precision, with a margin of 1e-3 nm) are farther apart than the cutoff cannot
//! be in contact and its atom pairs are not measured; with one, a cell list under the minimum
//! image (module `cells`) finds the atom pairs that can be in contact, which alone are measured
//! (MDTraj's formula, over batches of pairs in vector instructions: module `distance`), except for
//! `ca` / `cb` in a rectangular box, whose pairs of up to some hundreds of residues are cheaper
//! all measured in vector instructions. A chunk's frames are measured in parallel while the
//! next chunk is read (memory bounded by two chunks).

mod cells;
mod distance;
mod frame;

use rayon::prelude::*;

use distance::{boxed, norm2, plain, sqrt_threshold, triclinic};
use frame::{Cell, Frame};

use crate::error::{Error, Result};
use crate::io::frequencies::FREQUENCY_HEADER;
use crate::io::topology::Topology;
use crate::io::trajectory::{
    AtomSelection, Conformation, LengthUnit, for_each_chunk, open_trajectories,
};

/// How the distance between two residues is measured (MDTraj's schemes, and CASP's Cb).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// Ca - Ca.
    Ca,
    /// Cb - Cb, Ca for glycine (CASP).
    Cb,
    /// The closest pair of atoms.
    Closest,
    /// The closest pair of non-hydrogen atoms.
    ClosestHeavy,
    /// The closest pair of side-chain atoms.
    Sidechain,
    /// The closest pair of side-chain heavy atoms (glycine: its side-chain hydrogens).
    SidechainHeavy,
}

impl Scheme {
    /// The scheme's name (MDTraj's, and `cb`).
    pub fn name(self) -> &'static str {
        match self {
            Scheme::Ca => "ca",
            Scheme::Cb => "cb",
            Scheme::Closest => "closest",
            Scheme::ClosestHeavy => "closest-heavy",
            Scheme::Sidechain => "sidechain",
            Scheme::SidechainHeavy => "sidechain-heavy",
        }
    }
}

/// What [`contact_frequencies`] computes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrequencySpec {
    /// The distance measured.
    pub scheme: Scheme,
    /// A contact is a distance below this, in Angstrom.
    pub cutoff_angstrom: f64,
    /// The smallest index separation `j - i` of the pairs (MDTraj: 3).
    pub min_separation: usize,
    /// Minimum-image distances when a frame has a periodic cell (MDTraj's default).
    pub periodic: bool,
    /// Every `stride`-th frame is measured, from the first.
    pub stride: usize,
}

impl Default for FrequencySpec {
    fn default() -> Self {
        FrequencySpec {
            scheme: Scheme::Cb,
            cutoff_angstrom: 8.0,
            min_separation: 3,
            periodic: true,
            stride: 1,
        }
    }
}

/// The residue pairs of a topology and the atoms measured for each residue.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPairs {
    /// The pairs `(i, j)` of residue indices, `i < j`, in MDTraj's order.
    pub pairs: Vec<(usize, usize)>,
    /// For each residue, the atoms whose distances count (empty for residues in no pair).
    pub atoms: Vec<Vec<u32>>,
}

/// Residue contact frequencies: for each pair, the number of frames in contact.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactFrequencies {
    /// The pairs and their atoms.
    pub pairs: ContactPairs,
    /// Frames in contact, per pair.
    pub counts: Vec<u32>,
    /// Frames measured.
    pub frames: usize,
}

impl ContactFrequencies {
    /// The fraction of frames in contact of pair `k`.
    pub fn frequency(&self, k: usize) -> f64 {
        if self.frames == 0 {
            0.0
        } else {
            f64::from(self.counts[k]) / self.frames as f64
        }
    }
}

/// The name MDTraj gives an atom of a protein residue (its PDB-name standardisation, for the
/// names that decide backbone / side chain).
fn standard_atom_name<'a>(residue: &str, name: &'a str) -> &'a str {
    match name {
        "HN" | "H1" | "1H" | "HN1" | "HT1" => "H",
        "O1" | "OT1" | "OCT1" | "OC1" => "O",
        "CA" if residue == "NME" || residue == "NMA" => "C",
        _ => name,
    }
}

/// The name a residue is read by: the parent amino acid of the modified and force-field
/// residues [`crate::io::structure::amino_acid`] knows (`HSD`, `HIE` ... are `HIS`, as MDTraj
/// renames them), `NME` for its alias `NMA`.
fn standard_residue_name(name: &str) -> &str {
    match crate::io::structure::amino_acid(name) {
        Some((parent, _)) => parent,
        None if name == "NMA" => "NME",
        None => name,
    }
}

/// Capping groups and amino acids MDTraj counts as protein that
/// [`crate::io::structure::amino_acid`] does not keep.
const PROTEIN_VARIANTS: &[&str] = &[
    "ACE", "NME", "CYM", "ASH", "GLH", "LYN", "HSH", "HIH", "ASX", "GLX", "SEC", "PYL",
];

/// The pairs and atoms of `topology` for `spec`.
pub fn contact_pairs(topology: &Topology, spec: &FrequencySpec) -> Result<ContactPairs> {
    let n = topology.residues.len();
    let mut atoms = vec![Vec::new(); n];
    let mut has_ca = vec![false; n];
    for (r, residue) in topology.residues.iter().enumerate() {
        let name = standard_residue_name(&residue.name);
        let names: Vec<&str> = residue
            .atoms
            .clone()
            .map(|a| standard_atom_name(name, &topology.atoms[a].name))
            .collect();
        has_ca[r] = names.iter().any(|n| n.eq_ignore_ascii_case("CA"));
        let protein = crate::io::structure::amino_acid(name).is_some()
            || PROTEIN_VARIANTS.contains(&name)
            || ["N", "CA", "C"].iter().all(|n| names.contains(n));
        let hydrogen = |a: usize| topology.atoms[a].element == "H";
        let sidechain = |k: usize| protein && !["C", "CA", "N", "O", "HA", "H"].contains(&names[k]);
        let select = |keep: &dyn Fn(usize, usize) -> bool| -> Vec<u32> {
            residue
                .atoms
                .clone()
                .enumerate()
                .filter(|&(k, a)| keep(k, a))
                .map(|(_, a)| a as u32)
                .collect()
        };
        atoms[r] = match spec.scheme {
            Scheme::Ca => select(&|k, _| names[k].eq_ignore_ascii_case("CA")),
            Scheme::Cb => {
                let wanted = if name == "GLY" { "CA" } else { "CB" };
                select(&|k, _| names[k] == wanted)
            }
            Scheme::Closest => select(&|_, _| true),
            Scheme::ClosestHeavy => select(&|_, a| !hydrogen(a)),
            Scheme::Sidechain => select(&|k, _| sidechain(k)),
            Scheme::SidechainHeavy if name == "GLY" => select(&|k, _| sidechain(k)),
            Scheme::SidechainHeavy => select(&|k, a| sidechain(k) && !hydrogen(a)),
        };
    }
    let describe = |r: usize| {
        let residue = &topology.residues[r];
        format!(
            "residue {} {} (index {r}, chain '{}')",
            residue.name,
            residue.label(),
            topology.chains[residue.chain]
        )
    };
    let separation = spec.min_separation.max(1);
    let mut pairs = Vec::new();
    for i in (0..n).filter(|&i| has_ca[i]) {
        for j in (i + separation..n).filter(|&j| has_ca[j]) {
            if topology.residues[i].chain != topology.residues[j].chain {
                continue;
            }
            match spec.scheme {
                // MDTraj skips residues without the one atom; CASP's Cb likewise (unobserved)
                Scheme::Ca | Scheme::Cb if atoms[i].len() != 1 || atoms[j].len() != 1 => {
                    for r in [i, j] {
                        if atoms[r].len() > 1 {
                            return Err(Error::Data(format!(
                                "{} has {} atoms named {}",
                                describe(r),
                                atoms[r].len(),
                                if spec.scheme == Scheme::Ca {
                                    "CA"
                                } else {
                                    "CB"
                                }
                            )));
                        }
                    }
                    continue;
                }
                _ => {}
            }
            for r in [i, j] {
                if atoms[r].is_empty() {
                    return Err(Error::Data(format!(
                        "{} has no atom for the {} scheme",
                        describe(r),
                        spec.scheme.name()
                    )));
                }
            }
            pairs.push((i, j));
        }
    }
    if pairs.is_empty() {
        return Err(Error::Data(
            "no residue pair to measure: the topology has no chain of residues with a CA atom \
             three or more residues apart"
                .into(),
        ));
    }
    let mut used = vec![false; n];
    for &(i, j) in &pairs {
        used[i] = true;
        used[j] = true;
    }
    for (r, atoms) in atoms.iter_mut().enumerate() {
        if !used[r] {
            atoms.clear();
        }
    }
    Ok(ContactPairs { pairs, atoms })
}

/// Pairs `first .. first + len` of a one-atom-per-residue scheme (ca, cb): atom `p` with atoms
/// `q .. q + len` (MDTraj's order makes each residue's pairs one run).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Run {
    first: usize,
    p: u32,
    q: u32,
    len: usize,
}

/// `single` (the atoms of each pair) as runs.
fn runs(single: &[(u32, u32)]) -> Vec<Run> {
    let mut runs: Vec<Run> = Vec::new();
    for (k, &(p, q)) in single.iter().enumerate() {
        match runs.last_mut() {
            Some(run) if run.p == p && run.q + run.len as u32 == q => run.len += 1,
            _ => runs.push(Run {
                first: k,
                p,
                q,
                len: 1,
            }),
        }
    }
    runs
}

/// The pairs' atoms as runs when every residue of a pair has one atom (ca, cb).
fn single_runs(pairs: &ContactPairs) -> Option<Vec<Run>> {
    pairs
        .pairs
        .iter()
        .map(|&(i, j)| match (&pairs.atoms[i][..], &pairs.atoms[j][..]) {
            ([p], [q]) => Some((*p, *q)),
            _ => None,
        })
        .collect::<Option<Vec<(u32, u32)>>>()
        .map(|single| runs(&single))
}

/// The runs' pairs in contact in `frame`, added to `counts`: each run's distances over
/// contiguous coordinates, which the compiler turns into vector instructions (the same
/// single-precision values per pair as [`plain`] and [`boxed`], the box's rounding by
/// [`distance::round_even`]).
fn count_runs(frame: &Frame, runs: &[Run], cutoff: f32, counts: &mut [u32]) {
    let below = sqrt_threshold(cutoff);
    let axis = |d: usize| -> Vec<f32> { frame.xyz.iter().map(|p| p[d]).collect() };
    let (x, y, z) = (axis(0), axis(1), axis(2));
    for run in runs {
        let (p, q) = (run.p as usize, run.q as usize);
        let (px, py, pz) = (x[p], y[p], z[p]);
        let range = q..q + run.len;
        let (xs, ys, zs) = (&x[range.clone()], &y[range.clone()], &z[range]);
        let out = &mut counts[run.first..run.first + run.len];
        match &frame.cell {
            None => {
                for (((count, &qx), &qy), &qz) in out.iter_mut().zip(xs).zip(ys).zip(zs) {
                    let r = [qx - px, qy - py, qz - pz];
                    *count += u32::from(norm2(r) < below);
                }
            }
            Some(Cell::Box(e)) => {
                for (((count, &qx), &qy), &qz) in out.iter_mut().zip(xs).zip(ys).zip(zs) {
                    let r = distance::minimum_image_even([qx - px, qy - py, qz - pz], e);
                    *count += u32::from(norm2(r) < below);
                }
            }
            Some(Cell::Triclinic(v, recip)) => {
                for (t, count) in out.iter_mut().enumerate() {
                    let d2 = triclinic(&frame.xyz, v, recip, run.p, run.q + t as u32);
                    *count += u32::from(d2 < below);
                }
            }
        }
    }
}

/// Pairs per measured atom up to which the runs of a one-atom scheme are measured all in a
/// rectangular box rather than through the cell list: a pair costs about 1 ns in vector
/// instructions, the cell list about 0.4 us per atom.
const RUNS_PER_ATOM: usize = 256;

/// The pairs of `pairs` in contact in `frame` (indices into `pairs.pairs`), added to `counts`.
///
/// `single`: the pairs' atoms as runs when every residue has one atom (ca, cb); `periodic`
/// and `workspace`: the cell list of frames with a periodic cell (all of them but the runs of
/// a protein of up to some hundreds of residues in a rectangular box, cheaper measured all).
fn count_frame(
    frame: &Frame,
    pairs: &ContactPairs,
    single: Option<&[Run]>,
    cutoff: f32,
    counts: &mut [u32],
    periodic: &cells::Periodic,
    workspace: &mut cells::Workspace,
) {
    let all_runs = matches!(frame.cell, Some(Cell::Box(_)))
        && single.is_some_and(|_| pairs.pairs.len() <= RUNS_PER_ATOM * frame.xyz.len());
    if frame.cell.is_some() && !all_runs && periodic.count(frame, workspace, counts) {
        return;
    }
    if let Some(runs) = single {
        return count_runs(frame, runs, cutoff, counts);
    }
    let xyz = &frame.xyz;
    match &frame.cell {
        None => count_with(frame, pairs, cutoff, counts, |i, j| plain(xyz, i, j)),
        Some(Cell::Box(e)) => count_with(frame, pairs, cutoff, counts, |i, j| boxed(xyz, e, i, j)),
        Some(Cell::Triclinic(v, r)) => count_with(frame, pairs, cutoff, counts, |i, j| {
            triclinic(xyz, v, r, i, j)
        }),
    }
}

/// [`count_frame`] with the frame's squared distance `distance2`.
fn count_with(
    frame: &Frame,
    pairs: &ContactPairs,
    cutoff: f32,
    counts: &mut [u32],
    distance2: impl Fn(u32, u32) -> f32,
) {
    // `sqrt(d2) < cutoff` exactly when `d2 < below` (the square root is correctly rounded and
    // monotonic): no square root per atom pair
    let below = sqrt_threshold(cutoff);
    // bounding spheres of the residues measured
    let spheres: Vec<([f64; 3], f64)> = pairs
        .atoms
        .iter()
        .map(|atoms| {
            if atoms.len() <= 1 {
                let p = atoms.first().map_or([0.0; 3], |&a| frame.xyz[a as usize]);
                return (p.map(f64::from), 0.0);
            }
            let mut centre = [0.0f64; 3];
            for &a in atoms {
                for (c, x) in centre.iter_mut().zip(frame.xyz[a as usize]) {
                    *c += f64::from(x);
                }
            }
            centre = centre.map(|x| x / atoms.len() as f64);
            let radius = atoms
                .iter()
                .map(|&a| {
                    let p = frame.xyz[a as usize].map(f64::from);
                    ((p[0] - centre[0]).powi(2)
                        + (p[1] - centre[1]).powi(2)
                        + (p[2] - centre[2]).powi(2))
                    .sqrt()
                })
                .fold(0.0, f64::max);
            (centre, radius)
        })
        .collect();
    let reach = f64::from(cutoff) + 1e-3;
    for (k, &(i, j)) in pairs.pairs.iter().enumerate() {
        let (a, b) = (&pairs.atoms[i], &pairs.atoms[j]);
        if a.len() > 1 || b.len() > 1 {
            let (si, sj) = (spheres[i], spheres[j]);
            if frame.separation(si.0, sj.0) - si.1 - sj.1 > reach {
                continue;
            }
        }
        let contact = a
            .iter()
            .any(|&p| b.iter().any(|&q| distance2(p, q) < below));
        if contact {
            counts[k] += 1;
        }
    }
}

/// Frames measured per parallel step (the memory bound: two chunks of frames).
const CHUNK: usize = 32;

/// The contact frequencies of the residue pairs of `topology` over `frames` (MD frames, in
/// Angstrom or nm by their format), every `spec.stride`-th frame; each frame must have the
/// topology's atoms.
pub fn contact_frequencies(
    topology: &Topology,
    frames: impl Iterator<Item = Result<Conformation>>,
    spec: &FrequencySpec,
    progress: impl FnMut(usize) + Send,
) -> Result<ContactFrequencies> {
    check(spec)?;
    let pairs = contact_pairs(topology, spec)?;
    frequencies(topology.atoms.len(), pairs, frames, false, spec, progress)
}

/// [`contact_frequencies`] over the frames of the trajectory files `inputs` (DCD, XTC,
/// multi-model PDB / mmCIF), reading only the atoms the scheme measures: the DCD reader
/// converts only theirs (for `ca`, one atom in fifteen of a solvated protein's).
pub fn contact_frequencies_of(
    topology: &Topology,
    inputs: &[String],
    spec: &FrequencySpec,
    progress: impl FnMut(usize) + Send,
) -> Result<ContactFrequencies> {
    check(spec)?;
    let pairs = contact_pairs(topology, spec)?;
    let selection = AtomSelection::new(topology.atoms.len(), measured_atoms(&pairs))?;
    let frames = open_trajectories(inputs)?.select(selection);
    frequencies(topology.atoms.len(), pairs, frames, true, spec, progress)
}

/// The atoms `pairs` measure, ascending.
fn measured_atoms(pairs: &ContactPairs) -> Vec<u32> {
    let mut used: Vec<u32> = pairs.atoms.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    used
}

/// The cutoff and the stride of `spec` checked.
fn check(spec: &FrequencySpec) -> Result<()> {
    if !(spec.cutoff_angstrom.is_finite() && spec.cutoff_angstrom > 0.0) {
        return Err(Error::parameter(
            "cutoff",
            spec.cutoff_angstrom,
            "a positive distance (angstroms)",
        ));
    }
    if spec.stride == 0 {
        return Err(Error::parameter("stride", 0, "1 or more"));
    }
    Ok(())
}

/// [`contact_frequencies`] of the `pairs` of a topology of `atoms` atoms; `selected`: each frame
/// holds only the atoms `pairs` measure ([`measured_atoms`]).
fn frequencies(
    atoms: usize,
    pairs: ContactPairs,
    frames: impl Iterator<Item = Result<Conformation>>,
    selected: bool,
    spec: &FrequencySpec,
    mut progress: impl FnMut(usize) + Send,
) -> Result<ContactFrequencies> {
    let cutoff = (spec.cutoff_angstrom / 10.0) as f32;
    // the atoms measured, and the pairs' atoms as indices into them (a frame converts only
    // those: for `ca`, one atom in fifteen)
    let used = measured_atoms(&pairs);
    let measured = ContactPairs {
        pairs: pairs.pairs.clone(),
        atoms: pairs
            .atoms
            .iter()
            .map(|atoms| {
                atoms
                    .iter()
                    .map(|a| used.binary_search(a).unwrap_or_default() as u32)
                    .collect()
            })
            .collect(),
    };
    let single = single_runs(&measured);
    let periodic = cells::Periodic::new(&measured.pairs, &measured.atoms, used.len(), cutoff);
    // the atoms of a frame a measure takes: all of the selected ones, or the used ones
    let gather = (!selected).then_some(&used[..]);
    let mut counts = vec![0u32; pairs.pairs.len()];
    let keep = |index: usize, conformation: &Conformation| {
        if conformation.unit == LengthUnit::Model {
            return Err(Error::Unsupported(format!(
                "{}: not an MD trajectory (give DCD, XTC or multi-model PDB / mmCIF files; \
                 polymer conformations go to `polymer-map`)",
                conformation.label
            )));
        }
        // (selected frames were checked against the topology by their reader)
        if !selected && conformation.positions.len() != atoms {
            return Err(Error::Data(format!(
                "{}: {} atoms, the topology has {atoms}",
                conformation.label,
                conformation.positions.len(),
            )));
        }
        Ok(index.is_multiple_of(spec.stride))
    };
    let mut done = 0;
    // each chunk's frames are measured on the pool while this thread reads the next chunk
    let work = |chunk: &[Conformation]| {
        // one piece of frames per thread, each counted into its own table
        let piece = chunk.len().div_ceil(rayon::current_num_threads()).max(1);
        let partial = chunk
            .par_chunks(piece)
            .map(|frames| {
                let mut local = vec![0u32; pairs.pairs.len()];
                let mut workspace = periodic.workspace(pairs.pairs.len());
                for conformation in frames {
                    let frame = Frame::new(conformation, gather, spec.periodic);
                    count_frame(
                        &frame,
                        &measured,
                        single.as_deref(),
                        cutoff,
                        &mut local,
                        &periodic,
                        &mut workspace,
                    );
                }
                local
            })
            .reduce(
                || vec![0u32; pairs.pairs.len()],
                |mut a, b| {
                    a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
                    a
                },
            );
        counts.iter_mut().zip(partial).for_each(|(x, y)| *x += y);
        done += chunk.len();
        progress(done);
    };
    let mut frames = frames;
    let n_frames = for_each_chunk(&mut frames, CHUNK, keep, work)?;
    if n_frames == 0 {
        return Err(Error::Data("the trajectory has no frame".into()));
    }
    Ok(ContactFrequencies {
        pairs,
        counts,
        frames: n_frames,
    })
}

/// How a blank chain id (a PDB file without chain ids: its one chain, by the PDB's convention) is
/// written in tables: `A`, as the wwPDB's remediation names such chains, so that no column is
/// empty. [`EnsembleTruth::apply`](crate::score::target::EnsembleTruth::apply) reads it back
/// as the blank chain of a structure without a chain `A`.
pub const BLANK_CHAIN: &str = "A";

/// The chain id of chain `chain` of `topology` as tables write it ([`BLANK_CHAIN`] for a blank
/// one).
pub fn chain_column(topology: &Topology, chain: usize) -> &str {
    match topology.chains[chain].as_str() {
        "" => BLANK_CHAIN,
        id => id,
    }
}

/// The frequencies as a TSV table, one row per pair in MDTraj's order: the chain id (a blank
/// one written [`BLANK_CHAIN`]), the residues' author numbers (with insertion codes) and names
/// as written, their 0-based indices, the frames in contact and the fraction of frames.
pub fn frequency_table(topology: &Topology, frequencies: &ContactFrequencies) -> String {
    use crate::io::tables::write_u64;
    let mut text = Vec::with_capacity(48 * frequencies.counts.len());
    text.extend_from_slice(FREQUENCY_HEADER.as_bytes());
    text.push(b'\n');
    // each residue's `number[insertion]`, and each count's frequency, written once
    let numbers: Vec<String> = topology.residues.iter().map(|r| r.label()).collect();
    let mut fractions: std::collections::HashMap<u32, String> = std::collections::HashMap::new();
    for (k, &(i, j)) in frequencies.pairs.pairs.iter().enumerate() {
        let (a, b) = (&topology.residues[i], &topology.residues[j]);
        for field in [
            chain_column(topology, a.chain),
            &numbers[i],
            &numbers[j],
            &a.name,
            &b.name,
        ] {
            text.extend_from_slice(field.as_bytes());
            text.push(b'\t');
        }
        for index in [i, j] {
            write_u64(&mut text, index as u64);
            text.push(b'\t');
        }
        let count = frequencies.counts[k];
        write_u64(&mut text, u64::from(count));
        text.push(b'\t');
        let fraction = fractions
            .entry(count)
            .or_insert_with(|| frequencies.frequency(k).to_string());
        text.extend_from_slice(fraction.as_bytes());
        text.push(b'\n');
    }
    String::from_utf8(text).expect("the table is made of UTF-8 strings")
}
