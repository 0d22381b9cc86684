//! The simulator's parameters as a user gives them (the command line's options, the Python
//! API's keywords): chains, physics, ensemble and loop extrusion in their units, turned into
//! [`EnsembleParams`] by [`SimulationSpec::params`] (confinement radius from the density, the
//! default time step of soft and hard potentials, equilibration in Rouse times ...).

use std::path::PathBuf;

use crate::error::{Error, Result};
use crate::io::bed::BedRecord;
use crate::sim::ensemble::{EnsembleParams, ExtrusionCoupling};
use crate::sim::extrusion::ExtrusionParams;
use crate::sim::files::{
    boundary_elements_from_bed, boundary_elements_from_list, parse_type_pattern,
};
use crate::sim::polymer::{
    Attraction, BondModel, Confinement, PolymerParams, Repulsion, box_side, chain_ranges,
    sphere_radius,
};
use crate::sim::relaxation::{Relaxation, parse_steps};

/// Where the boundary elements of loop extrusion are (`--ctcf`).
#[derive(Clone, Debug, PartialEq)]
pub enum BoundarySites {
    /// Bead indices, each with an optional orientation (`500+,1000-,1500`).
    Beads(String),
    /// The sites of a BED file (its path named in messages).
    Bed {
        /// The file.
        path: PathBuf,
        /// Its records.
        records: Vec<BedRecord>,
    },
}

impl BoundarySites {
    /// The sites `value` names: the records of a BED file of that name when there is one
    /// (`bed`, as [`read_bed_if_file`](crate::io::bed::read_bed_if_file) reads it), else a list of
    /// beads.
    ///
    /// ```
    /// use contactmap::sim::spec::BoundarySites;
    /// let sites = BoundarySites::new("500+,1000-", None);
    /// assert_eq!(sites, BoundarySites::Beads("500+,1000-".into()));
    /// ```
    pub fn new(value: &str, bed: Option<Vec<BedRecord>>) -> Self {
        match bed {
            Some(records) => BoundarySites::Bed {
                path: PathBuf::from(value),
                records,
            },
            None => BoundarySites::Beads(value.to_string()),
        }
    }
}

/// Bond models.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BondKind {
    /// Harmonic, E = ((r - 1) / wiggle)^2 (polychrom).
    Harmonic,
    /// FENE, K = 30, R0 = 1.5 (Kremer-Grest; with WCA repulsion).
    Fene,
}

/// Excluded volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RepulsionKind {
    /// polychrom's soft polynomial repulsion.
    Polynomial,
    /// Weeks-Chandler-Andersen (hard, sigma 1, epsilon 1).
    Wca,
    /// None (a phantom chain).
    None,
}

/// Confinement.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConfinementKind {
    /// A soft sphere at the density.
    Sphere,
    /// A periodic box at the density.
    Box,
    /// Free space.
    None,
}

/// The simulator's parameters as given (`contactmap simulate polymer`'s options; its
/// defaults are [`SimulationSpec::default`]). Units: bond length 1, kT 1; beads of
/// `monomer_bp` bp.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulationSpec {
    /// Beads per chain (one chromosome each): `[1000]`.
    pub chains: Vec<usize>,
    /// Base pairs per bead: 1000.
    pub monomer_bp: u64,
    /// Beads per bin of the map: 1.
    pub monomers_per_bin: usize,
    /// Bond model: harmonic.
    pub bonds: BondKind,
    /// Harmonic bonds' wiggle distance: 0.1.
    pub bond_wiggle: f64,
    /// Angle stiffness (kT): 0.
    pub stiffness: f64,
    /// Excluded volume: polynomial.
    pub repulsion: RepulsionKind,
    /// Polynomial repulsion's energy at contact (kT); `None`: 3 (0.6 with `saw`).
    pub repulsion_energy: Option<f64>,
    /// Polynomial repulsion's radius; `None`: 1.05 (0.8 with `saw`).
    pub repulsion_radius: Option<f64>,
    /// Bonded neighbours without repulsion: 1.
    pub exclude_neighbours: usize,
    /// No excluded volume (a phantom chain).
    pub ideal: bool,
    /// Good solvent: weaker repulsion, no confinement (self-avoiding walk checks).
    pub saw: bool,
    /// Bead types, a pattern repeated along each chain (`A200B200`).
    pub types: Option<String>,
    /// Attraction between beads of one type (kT): 0.3.
    pub attraction: f64,
    /// Its radius: 1.5.
    pub attraction_radius: f64,
    /// Beads per unit volume of the confinement; a sphere unless `confinement` says otherwise.
    pub density: Option<f64>,
    /// Confinement; `None`: a sphere with a density, else free space.
    pub confinement: Option<ConfinementKind>,
    /// Time step; `None`: 0.002 (0.0002 with hard potentials: WCA or FENE).
    pub dt: Option<f64>,
    /// Independent chains simulated: 8.
    pub replicas: usize,
    /// Steps before the first sample: steps, `auto` or Rouse times (`2R`): `20000`.
    pub equilibration: String,
    /// Steps between samples, as `equilibration`: `2000`.
    pub sample_every: String,
    /// Samples per replica: 50.
    pub samples: usize,
    /// Beads closer than this are in contact: 1.5.
    pub contact_radius: f64,
    /// The seed: 0.
    pub seed: u64,
    /// Loop extrusion.
    pub extrusion: bool,
    /// Boundary elements: a BED file's sites or bead positions (`500+,1000-`).
    pub ctcf: Option<BoundarySites>,
    /// LEF processivity (beads): 100.
    pub processivity: f64,
    /// Beads per LEF: 200.
    pub separation: f64,
    /// Capture probability at a boundary element: 0.9.
    pub capture: f64,
    /// Release probability per step: 0.005.
    pub release: f64,
    /// 3D steps per 1D extrusion step: 50.
    pub steps_per_move: usize,
    /// Keep the sampled conformations.
    pub keep_conformations: bool,
}

impl Default for SimulationSpec {
    fn default() -> Self {
        SimulationSpec {
            chains: vec![1000],
            monomer_bp: 1000,
            monomers_per_bin: 1,
            bonds: BondKind::Harmonic,
            bond_wiggle: 0.1,
            stiffness: 0.0,
            repulsion: RepulsionKind::Polynomial,
            repulsion_energy: None,
            repulsion_radius: None,
            exclude_neighbours: 1,
            ideal: false,
            saw: false,
            types: None,
            attraction: 0.3,
            attraction_radius: 1.5,
            density: None,
            confinement: None,
            dt: None,
            replicas: 8,
            equilibration: "20000".into(),
            sample_every: "2000".into(),
            samples: 50,
            contact_radius: 1.5,
            seed: 0,
            extrusion: false,
            ctcf: None,
            processivity: 100.0,
            separation: 200.0,
            capture: 0.9,
            release: 0.005,
            steps_per_move: 50,
            keep_conformations: false,
        }
    }
}

fn check_density(density: f64) -> Result<()> {
    if density.is_finite() && density > 0.0 {
        Ok(())
    } else {
        Err(Error::Argument(format!(
            "--density must be a positive number, got {density}"
        )))
    }
}

impl SimulationSpec {
    /// The simulator's parameters, checked (an error names the option at fault).
    ///
    /// ```
    /// use contactmap::sim::polymer::{sphere_radius, Confinement};
    /// use contactmap::sim::spec::SimulationSpec;
    ///
    /// let spec = SimulationSpec { chains: vec![100], density: Some(0.2), ..Default::default() };
    /// let params = spec.params()?;
    /// assert_eq!(params.polymer.dt, 0.002);
    /// match params.polymer.confinement {
    ///     Confinement::Sphere { radius, .. } => assert_eq!(radius, sphere_radius(100, 0.2)),
    ///     other => panic!("{other:?}"),
    /// }
    /// let bad = SimulationSpec { density: Some(0.0), ..spec };
    /// assert!(bad.params().unwrap_err().to_string().contains("density"));
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn params(&self) -> Result<EnsembleParams> {
        let n: usize = self.chains.iter().sum();
        let repulsion_kind = if self.ideal {
            RepulsionKind::None
        } else {
            self.repulsion
        };
        if repulsion_kind != RepulsionKind::Polynomial
            && (self.repulsion_energy.is_some() || self.repulsion_radius.is_some())
        {
            return Err(Error::Argument(
                "--repulsion-energy and --repulsion-radius shape the polynomial repulsion: they \
                 do not apply with --repulsion wca or none"
                    .into(),
            ));
        }
        let repulsion = match repulsion_kind {
            RepulsionKind::Polynomial => if self.saw {
                Repulsion::SAW
            } else {
                Repulsion::POLYCHROM
            }
            .with_polynomial(self.repulsion_energy, self.repulsion_radius),
            RepulsionKind::Wca => Repulsion::Wca {
                epsilon: 1.0,
                sigma: 1.0,
            },
            RepulsionKind::None => Repulsion::None,
        };
        let bond = match self.bonds {
            BondKind::Harmonic => BondModel::Harmonic {
                length: 1.0,
                wiggle: self.bond_wiggle,
            },
            BondKind::Fene => BondModel::Fene {
                stiffness: 30.0,
                max_length: 1.5,
            },
        };
        let kind = match (self.confinement, self.density) {
            (Some(kind), _) => kind,
            (None, Some(_)) => ConfinementKind::Sphere,
            (None, None) => ConfinementKind::None,
        };
        let density = || {
            self.density.ok_or_else(|| {
                Error::Argument("--confinement sphere or box needs --density".into())
            })
        };
        let confinement = match kind {
            ConfinementKind::None => Confinement::None,
            ConfinementKind::Sphere => {
                let density = density()?;
                check_density(density)?;
                Confinement::Sphere {
                    radius: sphere_radius(n, density),
                    stiffness: 5.0,
                }
            }
            ConfinementKind::Box => {
                let density = density()?;
                check_density(density)?;
                Confinement::Periodic {
                    side: box_side(n, density),
                }
            }
        };
        let attraction = match &self.types {
            None => None,
            Some(pattern) => {
                let (period, _) = parse_type_pattern(pattern)?;
                let types = self
                    .chains
                    .iter()
                    .flat_map(|&length| (0..length).map(|k| period[k % period.len()]))
                    .collect();
                Some(Attraction {
                    types,
                    energy: self.attraction,
                    radius: self.attraction_radius,
                })
            }
        };
        let hard = matches!(repulsion, Repulsion::Wca { .. }) || self.bonds == BondKind::Fene;
        let polymer = PolymerParams {
            chains: self.chains.clone(),
            bond,
            angle_stiffness: self.stiffness,
            repulsion,
            attraction,
            confinement,
            excluded_neighbours: self.exclude_neighbours,
            dt: self.dt.unwrap_or(if hard { 0.0002 } else { 0.002 }),
        };
        let extrusion = if self.extrusion {
            let chains = chain_ranges(&self.chains);
            let elements = match &self.ctcf {
                Some(BoundarySites::Bed { path, records }) => boundary_elements_from_bed(
                    path,
                    records,
                    &self.chains,
                    self.monomer_bp,
                    self.capture,
                    self.release,
                )?,
                Some(BoundarySites::Beads(text)) => {
                    boundary_elements_from_list(text, self.capture, self.release)?
                }
                None => Vec::new(),
            };
            Some(ExtrusionCoupling {
                params: ExtrusionParams {
                    chains,
                    processivity: self.processivity,
                    separation: self.separation,
                    elements,
                },
                steps_per_move: self.steps_per_move,
                bond_length: 0.5,
                bond_wiggle: 0.2,
            })
        } else {
            None
        };
        let relaxation = Relaxation::new(&polymer);
        let longest = self.chains.iter().copied().max().unwrap_or(0);
        let rouse_steps = relaxation.rouse_time(longest) / polymer.dt;
        let equilibration_steps =
            parse_steps("equilibration", &self.equilibration, 3.0, rouse_steps)?;
        let sample_every = parse_steps("sample_every", &self.sample_every, 0.5, rouse_steps)?;
        let params = EnsembleParams {
            polymer,
            replicas: self.replicas,
            equilibration_steps,
            sample_every,
            samples: self.samples,
            contact_radius: self.contact_radius,
            monomers_per_bin: self.monomers_per_bin,
            seed: self.seed,
            extrusion,
            keep_conformations: self.keep_conformations,
        };
        if self.monomer_bp == 0 {
            return Err(Error::Argument("--monomer-bp must be at least 1".into()));
        }
        params.check()?;
        Ok(params)
    }
}
