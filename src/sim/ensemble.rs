//! Ensembles of polymer conformations turned into contact maps with a known truth.
//!
//! Each replica is an independent [`Polymer`] with its own random streams: the 3D dynamics take
//! `stream_rng(seed, POLYMER_STREAM, replica)` and the loop extrusion
//! `stream_rng(seed, EXTRUSION_STREAM, replica)`. Replicas run in parallel (rayon), one thread
//! each; their contact counts are integers summed at the end, so the map is bit-identical for a
//! seed whatever the number of threads.
//!
//! A replica equilibrates for `equilibration_steps`, then takes `samples` conformations, one
//! every `sample_every` steps. In each conformation every pair of beads `i < j` closer than
//! `contact_radius` (a cell-list search, minimum image in a periodic box) adds one contact to
//! the pixel of their bins; bins hold `monomers_per_bin` consecutive beads of one chain (the
//! last bin of a chain may hold fewer) and never straddle two chains.
//!
//! With loop extrusion ([`ExtrusionCoupling`]), the 1D model ([`Extruder`]) advances one step
//! every `steps_per_move` 3D steps, and its LEF legs become harmonic bonds of the chain (rest
//! length and wiggle of [`ExtrusionCoupling`]), polychrom's coupling.

use rayon::prelude::*;

use super::extrusion::{Extruder, ExtrusionParams};
use super::polymer::{Polymer, PolymerParams, radius_of_gyration};
use crate::error::{Error, Result};
use crate::geometry::cells::{CellList, Space};
use crate::random::{SeededRng, stream_rng};

/// Stream tag of the 3D dynamics.
pub const POLYMER_STREAM: u64 = 0x5045_4c59; // "PELY"
/// Stream tag of the loop extrusion.
pub const EXTRUSION_STREAM: u64 = 0x4c45_4653; // "LEFS"

/// Loop extrusion coupled to the chain.
#[derive(Clone, Debug, PartialEq)]
pub struct ExtrusionCoupling {
    /// The 1D model.
    pub params: ExtrusionParams,
    /// 3D steps per 1D step.
    pub steps_per_move: usize,
    /// Rest length of a LEF bond.
    pub bond_length: f64,
    /// Wiggle distance of a LEF bond.
    pub bond_wiggle: f64,
}

/// What to simulate and sample.
#[derive(Clone, Debug, PartialEq)]
pub struct EnsembleParams {
    /// The polymer model.
    pub polymer: PolymerParams,
    /// Independent replicas.
    pub replicas: usize,
    /// Steps before the first sample.
    pub equilibration_steps: usize,
    /// Steps between samples.
    pub sample_every: usize,
    /// Samples per replica.
    pub samples: usize,
    /// Two beads closer than this are in contact.
    pub contact_radius: f64,
    /// Beads per bin of the contact map.
    pub monomers_per_bin: usize,
    /// Seed of every random stream.
    pub seed: u64,
    /// Optional loop extrusion.
    pub extrusion: Option<ExtrusionCoupling>,
    /// Keep the sampled conformations.
    pub keep_conformations: bool,
}

impl EnsembleParams {
    /// Check the parameters (the polymer's and the extrusion's too), before any work.
    pub fn check(&self) -> Result<()> {
        self.polymer.check()?;
        if self.replicas == 0 {
            return Err(Error::Argument("at least one replica is needed".into()));
        }
        if self.samples == 0 || self.sample_every == 0 {
            return Err(Error::Argument(
                "samples and steps between samples must be at least 1".into(),
            ));
        }
        if self.monomers_per_bin == 0 {
            return Err(Error::Argument(
                "monomers per bin must be at least 1".into(),
            ));
        }
        if !(self.contact_radius.is_finite() && self.contact_radius > 0.0) {
            return Err(Error::Argument(format!(
                "contact radius must be a positive number, got {}",
                self.contact_radius
            )));
        }
        if let Some(coupling) = &self.extrusion {
            coupling
                .params
                .check()
                .map_err(|err| Error::Argument(format!("loop extrusion: {err}")))?;
            let n = self.polymer.n_beads();
            if coupling.params.n_monomers() != n {
                return Err(Error::Argument(format!(
                    "loop extrusion covers {} monomers, the polymer has {n}",
                    coupling.params.n_monomers()
                )));
            }
            if coupling.params.chains != self.polymer.chain_ranges() {
                return Err(Error::Argument(
                    "loop extrusion chains differ from the polymer's chains".into(),
                ));
            }
            if coupling.steps_per_move == 0 {
                return Err(Error::Argument(
                    "3D steps per extrusion step must be at least 1".into(),
                ));
            }
            if !(coupling.bond_length >= 0.0 && coupling.bond_wiggle > 0.0) {
                return Err(Error::Argument(
                    "LEF bond length must be 0 or more and its wiggle positive".into(),
                ));
            }
        }
        Ok(())
    }

    /// The beads holding a boundary element, sorted, each once (none without extrusion).
    pub fn boundary_beads(&self) -> Vec<usize> {
        let mut beads: Vec<usize> = self
            .extrusion
            .iter()
            .flat_map(|coupling| coupling.params.elements.iter().map(|e| e.position))
            .collect();
        beads.sort_unstable();
        beads.dedup();
        beads
    }

    /// The true domains: for each chain (by index), the bead ranges between its consecutive
    /// boundary elements and its ends, counted from the chain's first bead.
    pub fn true_domains(&self) -> Vec<(usize, std::ops::Range<usize>)> {
        let elements = self.boundary_beads();
        let mut domains = Vec::new();
        for (chain, range) in self.polymer.chain_ranges().into_iter().enumerate() {
            let mut cuts = vec![0];
            cuts.extend(
                elements
                    .iter()
                    .filter(|bead| range.contains(bead))
                    .map(|bead| bead - range.start),
            );
            cuts.push(range.len());
            cuts.dedup();
            domains.extend(cuts.windows(2).map(|pair| (chain, pair[0]..pair[1])));
        }
        domains
    }

    /// The bin of every bead and the number of bins of every chain.
    pub fn bins(&self) -> (Vec<u32>, Vec<usize>) {
        let mut bead_bin = Vec::with_capacity(self.polymer.n_beads());
        let mut per_chain = Vec::with_capacity(self.polymer.chains.len());
        let mut offset = 0;
        for &length in &self.polymer.chains {
            let n_bins = length.div_ceil(self.monomers_per_bin);
            for bead in 0..length {
                bead_bin.push((offset + bead / self.monomers_per_bin) as u32);
            }
            per_chain.push(n_bins);
            offset += n_bins;
        }
        (bead_bin, per_chain)
    }

    /// With bead types (`polymer.attraction`): per bin of the map, how many of its beads have
    /// each type (`counts[bin][type]`, types `0..n_types`).
    pub fn bin_type_counts(&self, n_types: usize) -> Option<Vec<Vec<usize>>> {
        let types = &self.polymer.attraction.as_ref()?.types;
        let (bead_bin, per_chain) = self.bins();
        let mut counts = vec![vec![0usize; n_types]; per_chain.iter().sum()];
        for (&bin, &t) in bead_bin.iter().zip(types) {
            counts[bin as usize][t as usize] += 1;
        }
        Some(counts)
    }
}

/// The result of [`run_ensemble`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Ensemble {
    /// Bins of each chain.
    pub bins_per_chain: Vec<usize>,
    /// `(bin1, bin2, contacts)`, `bin1 <= bin2`, sorted, non-zero.
    pub pixels: Vec<(u32, u32, u64)>,
    /// Conformations sampled (replicas × samples).
    pub n_conformations: usize,
    /// Radius of gyration of each chain of each sample, replica after replica.
    pub radii_of_gyration: Vec<Vec<f64>>,
    /// The sampled conformations, when kept.
    pub conformations: Vec<Vec<[f64; 3]>>,
    /// With loop extrusion: `(bin1, bin2, samples)`, `bin1 <= bin2`, sorted: the bins of
    /// boundary-element pairs held bridged by a LEF (both legs captured) and the number of
    /// samples (conformations) in which at least one such pair of these bins was held.
    pub held_loops: Vec<(u32, u32, u64)>,
}

/// What one replica's samples gave.
pub(crate) struct Replica {
    pixels: Vec<(u64, u64)>,
    held: Vec<(u64, u64)>,
    radii: Vec<Vec<f64>>,
    conformations: Vec<Vec<[f64; 3]>>,
}

/// Counts the contacts, radii of gyration and (when kept) conformations of one replica's
/// samples; shared by the CPU and GPU backends so both count contacts the same way.
pub(crate) struct Sampler<'a> {
    params: &'a EnsembleParams,
    bead_bin: &'a [u32],
    n_bins: u64,
    counts: std::collections::HashMap<u64, u64>,
    held: std::collections::HashMap<u64, u64>,
    cells: CellList,
    radii: Vec<Vec<f64>>,
    conformations: Vec<Vec<[f64; 3]>>,
}

impl<'a> Sampler<'a> {
    /// A sampler for bins `bead_bin` (see [`EnsembleParams::bins`]) of `n_bins` bins in all.
    pub(crate) fn new(params: &'a EnsembleParams, bead_bin: &'a [u32], n_bins: u64) -> Self {
        Self {
            params,
            bead_bin,
            n_bins,
            counts: std::collections::HashMap::new(),
            held: std::collections::HashMap::new(),
            cells: CellList::new(),
            radii: Vec::with_capacity(params.samples),
            conformations: Vec::new(),
        }
    }

    /// The key of the pixel of beads `i` and `j` (either order): `bin1 * n_bins + bin2`,
    /// `bin1 <= bin2`.
    fn pixel_key(bead_bin: &[u32], n_bins: u64, i: usize, j: usize) -> u64 {
        let (x, y) = (bead_bin[i] as u64, bead_bin[j] as u64);
        x.min(y) * n_bins + x.max(y)
    }

    /// Count one conformation of the replica and, with loop extrusion, the loops its 1D model
    /// holds at that moment (see [`Self::record_loops`]).
    pub(crate) fn sample(
        &mut self,
        positions: &[[f64; 3]],
        space: Space,
        extruder: Option<&Extruder>,
    ) {
        let (bead_bin, n_bins, counts) = (self.bead_bin, self.n_bins, &mut self.counts);
        self.cells
            .build(positions, self.params.contact_radius, space);
        let order = self.cells.order();
        self.cells.for_each_pair(|a, b, _, _| {
            let key = Self::pixel_key(bead_bin, n_bins, order[a] as usize, order[b] as usize);
            *counts.entry(key).or_insert(0) += 1;
        });
        if let Some(extruder) = extruder {
            self.record_loops(extruder);
        }
        self.radii.push(
            self.params
                .polymer
                .chain_ranges()
                .into_iter()
                .map(|range| radius_of_gyration(&positions[range]))
                .collect(),
        );
        if self.params.keep_conformations {
            self.conformations.push(positions.to_vec());
        }
    }

    /// Record the loops `extruder` holds at this sample: the bin pairs of the LEFs whose two
    /// legs are captured by boundary elements, each bin pair once per sample.
    fn record_loops(&mut self, extruder: &Extruder) {
        let mut keys: Vec<u64> = extruder
            .legs()
            .iter()
            .zip(extruder.captured())
            .filter(|(_, captured)| captured[0] && captured[1])
            .map(|(&(l, r), _)| Self::pixel_key(self.bead_bin, self.n_bins, l, r))
            .collect();
        keys.sort_unstable();
        keys.dedup();
        for key in keys {
            *self.held.entry(key).or_insert(0) += 1;
        }
    }

    /// The replica's result.
    pub(crate) fn finish(self) -> Replica {
        let mut pixels: Vec<(u64, u64)> = self.counts.into_iter().collect();
        pixels.sort_unstable();
        Replica {
            pixels,
            held: self.held.into_iter().collect(),
            radii: self.radii,
            conformations: self.conformations,
        }
    }
}

/// The ensemble of the replicas' results (in replica order).
pub(crate) fn assemble(
    params: &EnsembleParams,
    bins_per_chain: Vec<usize>,
    replicas: Vec<Replica>,
) -> Ensemble {
    let n_bins: u64 = bins_per_chain.iter().sum::<usize>() as u64;
    // Merge the sorted per-replica pixel lists (integer sums: order does not matter).
    let all: Vec<(u64, u64)> = replicas
        .iter()
        .flat_map(|replica| replica.pixels.iter().copied())
        .collect();
    let pixels = sum_by_key(all, n_bins);
    let held = sum_by_key(
        replicas
            .iter()
            .flat_map(|replica| replica.held.iter().copied())
            .collect(),
        n_bins,
    );
    let mut ensemble = Ensemble {
        bins_per_chain,
        pixels,
        held_loops: held,
        n_conformations: params.replicas * params.samples,
        ..Ensemble::default()
    };
    for replica in replicas {
        ensemble.radii_of_gyration.extend(replica.radii);
        ensemble.conformations.extend(replica.conformations);
    }
    ensemble
}

/// `(bin1 * n_bins + bin2, count)` pairs summed by key, as sorted `(bin1, bin2, count)`.
fn sum_by_key(mut all: Vec<(u64, u64)>, n_bins: u64) -> Vec<(u32, u32, u64)> {
    all.sort_unstable_by_key(|&(key, _)| key);
    let mut summed: Vec<(u32, u32, u64)> = Vec::new();
    for (key, count) in all {
        let (bin1, bin2) = ((key / n_bins) as u32, (key % n_bins) as u32);
        match summed.last_mut() {
            Some(last) if last.0 == bin1 && last.1 == bin2 => last.2 += count,
            _ => summed.push((bin1, bin2, count)),
        }
    }
    summed
}

/// The loop extrusion of one replica: its coupling, 1D model and generator.
pub(crate) type ReplicaExtrusion<'a> = (&'a ExtrusionCoupling, Extruder, SeededRng);

/// The loop extrusion of `replica` (none without extrusion), seeded from its own stream.
pub(crate) fn replica_extrusion(
    params: &EnsembleParams,
    replica: usize,
) -> Result<Option<ReplicaExtrusion<'_>>> {
    match &params.extrusion {
        Some(coupling) => {
            let mut rng = stream_rng(params.seed, EXTRUSION_STREAM, replica as u64);
            let extruder = Extruder::new(&coupling.params, &mut rng)
                .map_err(|err| Error::Argument(format!("loop extrusion: {err}")))?;
            Ok(Some((coupling, extruder, rng)))
        }
        None => Ok(None),
    }
}

/// Run the replicas (in parallel) and accumulate their contacts; `progress(replica)` is called
/// when a replica finishes.
///
/// # Examples
///
/// A tiny chain of 30 beads, two replicas, three samples each: the map is the naive count of
/// the bead pairs closer than the contact radius in the kept conformations, binned by 5 beads.
///
/// ```
/// use std::collections::BTreeMap;
/// use std::sync::atomic::{AtomicUsize, Ordering};
/// use contactmap::sim::ensemble::{run_ensemble, EnsembleParams};
/// use contactmap::sim::polymer::{radius_of_gyration, PolymerParams};
///
/// let params = EnsembleParams {
///     polymer: PolymerParams { chains: vec![30], ..PolymerParams::default() },
///     replicas: 2,
///     equilibration_steps: 200,
///     sample_every: 100,
///     samples: 3,
///     contact_radius: 1.5,
///     monomers_per_bin: 5,
///     seed: 42,
///     extrusion: None,
///     keep_conformations: true,
/// };
/// let done = AtomicUsize::new(0);
/// let ensemble = run_ensemble(&params, &|_| {
///     done.fetch_add(1, Ordering::Relaxed);
/// })?;
/// assert_eq!(done.into_inner(), 2);
/// assert_eq!((ensemble.n_conformations, ensemble.conformations.len()), (6, 6));
/// assert_eq!(ensemble.bins_per_chain, [6]);
/// let mut naive: BTreeMap<(u32, u32), u64> = BTreeMap::new();
/// for positions in &ensemble.conformations {
///     for i in 0..30 {
///         for j in i + 1..30 {
///             let (a, b) = (positions[i], positions[j]);
///             let d2: f64 = (0..3).map(|k| (a[k] - b[k]).powi(2)).sum();
///             if d2 < 1.5 * 1.5 {
///                 *naive.entry(((i / 5) as u32, (j / 5) as u32)).or_default() += 1;
///             }
///         }
///     }
/// }
/// let naive: Vec<(u32, u32, u64)> = naive.into_iter().map(|((a, b), n)| (a, b, n)).collect();
/// assert_eq!(ensemble.pixels, naive);
/// let rg = radius_of_gyration(&ensemble.conformations[0]);
/// assert_eq!(ensemble.radii_of_gyration[0], [rg]);
/// // the same seed, the same ensemble
/// assert_eq!(run_ensemble(&params, &|_| {})?.pixels, ensemble.pixels);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn run_ensemble(
    params: &EnsembleParams,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Ensemble> {
    params.check()?;
    let (bead_bin, bins_per_chain) = params.bins();
    let n_bins: u64 = bins_per_chain.iter().sum::<usize>() as u64;
    let replicas: Vec<Replica> = (0..params.replicas)
        .into_par_iter()
        .map(|replica| {
            let result = run_replica(params, replica, &bead_bin, n_bins);
            progress(replica);
            result
        })
        .collect::<Result<_>>()?;
    Ok(assemble(params, bins_per_chain, replicas))
}

fn run_replica(
    params: &EnsembleParams,
    replica: usize,
    bead_bin: &[u32],
    n_bins: u64,
) -> Result<Replica> {
    let mut polymer = Polymer::new(
        params.polymer.clone(),
        stream_rng(params.seed, POLYMER_STREAM, replica as u64),
    )?;
    let mut extrusion = replica_extrusion(params, replica)?;
    let mut steps_done = 0usize;
    let mut advance =
        |polymer: &mut Polymer, extrusion: &mut Option<ReplicaExtrusion<'_>>, steps: usize| {
            for _ in 0..steps {
                if let Some((coupling, extruder, rng)) = extrusion.as_mut() {
                    if steps_done.is_multiple_of(coupling.steps_per_move) {
                        if steps_done > 0 {
                            extruder.step(rng);
                        }
                        polymer.set_extra_bonds(
                            extruder.legs(),
                            coupling.bond_length,
                            coupling.bond_wiggle,
                        );
                    }
                }
                polymer.step();
                steps_done += 1;
            }
        };
    advance(&mut polymer, &mut extrusion, params.equilibration_steps);
    let mut sampler = Sampler::new(params, bead_bin, n_bins);
    for _ in 0..params.samples {
        advance(&mut polymer, &mut extrusion, params.sample_every);
        let extruder = extrusion.as_ref().map(|(_, extruder, _)| extruder);
        sampler.sample(polymer.positions(), polymer.space(), extruder);
    }
    Ok(sampler.finish())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::extrusion::Orientation;
    use crate::sim::polymer::{Confinement, Repulsion};

    fn small(replicas: usize) -> EnsembleParams {
        EnsembleParams {
            polymer: PolymerParams {
                chains: vec![60, 40],
                confinement: Confinement::Sphere {
                    radius: crate::sim::polymer::sphere_radius(100, 0.2),
                    stiffness: 5.0,
                },
                ..PolymerParams::default()
            },
            replicas,
            equilibration_steps: 200,
            sample_every: 50,
            samples: 5,
            contact_radius: 1.5,
            monomers_per_bin: 7,
            seed: 11,
            extrusion: Some(ExtrusionCoupling {
                params: ExtrusionParams {
                    chains: vec![0..60, 60..100],
                    processivity: 20.0,
                    separation: 25.0,
                    elements: vec![],
                },
                steps_per_move: 10,
                bond_length: 0.5,
                bond_wiggle: 0.2,
            }),
            keep_conformations: true,
        }
    }

    /// The pixels equal a naive count over the kept conformations (all pairs), and the bins
    /// never straddle the two chains.
    #[test]
    fn pixels_equal_a_naive_count() {
        let params = small(3);
        let ensemble = run_ensemble(&params, &|_| {}).unwrap();
        assert_eq!(ensemble.bins_per_chain, vec![9, 6]);
        assert_eq!(ensemble.conformations.len(), 15);
        let (bead_bin, _) = params.bins();
        assert_eq!(bead_bin[59], 8);
        assert_eq!(bead_bin[60], 9);
        let mut naive = std::collections::BTreeMap::new();
        for positions in &ensemble.conformations {
            for i in 0..positions.len() {
                for j in i + 1..positions.len() {
                    let d: f64 = (0..3)
                        .map(|k| (positions[i][k] - positions[j][k]).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    if d < params.contact_radius {
                        *naive.entry((bead_bin[i], bead_bin[j])).or_insert(0u64) += 1;
                    }
                }
            }
        }
        let naive: Vec<(u32, u32, u64)> = naive.into_iter().map(|((a, b), c)| (a, b, c)).collect();
        assert_eq!(ensemble.pixels, naive);
        assert_eq!(ensemble.radii_of_gyration.len(), 15);
    }

    /// The held loops are those of the 1D model replayed on its own, step for step on the 3D
    /// schedule (one 1D step at every `steps_per_move`-th 3D step after the first): at each
    /// sample, the bin pairs of the LEFs with both legs captured, once per sample.
    #[test]
    fn held_loops_replay_the_extruder() {
        use crate::sim::extrusion::BoundaryElement;
        let mut params = small(2);
        params.samples = 12;
        let coupling = params.extrusion.as_mut().unwrap();
        coupling.params.processivity = 60.0;
        coupling.params.elements = [(5, Orientation::Both), (30, Orientation::Forward)]
            .into_iter()
            .chain([(50, Orientation::Reverse), (75, Orientation::Both)])
            .chain([(95, Orientation::Both)])
            .map(|(position, orientation)| BoundaryElement {
                position,
                orientation,
                capture: 0.95,
                release: 0.01,
            })
            .collect();
        let ensemble = run_ensemble(&params, &|_| {}).unwrap();
        let (bead_bin, _) = params.bins();
        let spm = params.extrusion.as_ref().unwrap().steps_per_move;
        let mut naive = std::collections::BTreeMap::new();
        for replica in 0..params.replicas {
            let (_, mut extruder, mut rng) = replica_extrusion(&params, replica).unwrap().unwrap();
            let mut moves = 0;
            for k in 0..params.samples {
                let steps_done = params.equilibration_steps + (k + 1) * params.sample_every;
                while moves < (steps_done - 1) / spm {
                    extruder.step(&mut rng);
                    moves += 1;
                }
                let mut pairs = std::collections::BTreeSet::new();
                for (&(l, r), c) in extruder.legs().iter().zip(extruder.captured()) {
                    if c[0] && c[1] {
                        pairs.insert((bead_bin[l], bead_bin[r]));
                    }
                }
                for pair in pairs {
                    *naive.entry(pair).or_insert(0u64) += 1;
                }
            }
        }
        let naive: Vec<(u32, u32, u64)> = naive.into_iter().map(|((a, b), n)| (a, b, n)).collect();
        assert!(!naive.is_empty(), "some loops are held");
        assert_eq!(ensemble.held_loops, naive);
    }

    #[test]
    fn same_seed_same_map_whatever_the_threads() {
        let params = small(4);
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| run_ensemble(&params, &|_| {}).unwrap());
        let two = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap()
            .install(|| run_ensemble(&params, &|_| {}).unwrap());
        assert_eq!(one, two);
    }

    #[test]
    fn bad_parameters_before_any_work() {
        let mut params = small(0);
        assert!(
            run_ensemble(&params, &|_| {})
                .unwrap_err()
                .to_string()
                .contains("replica")
        );
        params.replicas = 1;
        params.polymer.repulsion = Repulsion::Polynomial {
            energy: 3.0,
            radius: 1.05,
        };
        if let Some(coupling) = &mut params.extrusion {
            coupling
                .params
                .elements
                .push(crate::sim::extrusion::BoundaryElement::permanent(
                    500,
                    crate::sim::extrusion::Orientation::Both,
                ));
        }
        let err = run_ensemble(&params, &|_| {}).unwrap_err().to_string();
        assert!(err.contains("500"), "{err}");
    }
}
