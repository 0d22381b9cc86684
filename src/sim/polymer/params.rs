//! What a polymer is: its chains, bonds, repulsion, attraction and confinement, and their checks.

use crate::error::{Error, Result};
use crate::geometry::cells::Space;

/// Density above which beads of unit diameter cannot be packed (`√2`, face-centred cubic).
pub const CLOSE_PACKING_DENSITY: f64 = std::f64::consts::SQRT_2;

/// The bonds along each chain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BondModel {
    /// `E = ((r - length) / wiggle)²`.
    Harmonic {
        /// Rest length.
        length: f64,
        /// Stretch costing 1 kT.
        wiggle: f64,
    },
    /// `E = -K R0² / 2 ln(1 - (r/R0)²)`.
    Fene {
        /// `K` in kT / b².
        stiffness: f64,
        /// `R0`, the largest extension.
        max_length: f64,
    },
}

/// Excluded volume between non-bonded beads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Repulsion {
    /// None: an ideal (phantom) chain.
    None,
    /// polychrom's polynomial repulsion: `energy` at contact, 0 from `radius`.
    Polynomial {
        /// Height in kT.
        energy: f64,
        /// Range.
        radius: f64,
    },
    /// Weeks-Chandler-Andersen.
    Wca {
        /// Depth ε in kT.
        epsilon: f64,
        /// Diameter σ.
        sigma: f64,
    },
}

impl Repulsion {
    /// polychrom's default excluded volume: the polynomial repulsion at 3 kT, radius 1.05.
    pub const POLYCHROM: Repulsion = Repulsion::Polynomial {
        energy: 3.0,
        radius: 1.05,
    };

    /// The excluded volume of the self-avoiding-walk check: a polynomial repulsion of 0.6 kT
    /// and radius 0.8 (with harmonic bonds of wiggle 0.3). Chains reach the swollen
    /// (ν = 0.588) scaling at a few tens of beads because this strength sits near the model's
    /// Domb-Joyce point, where the leading correction to scaling vanishes: local Rg exponents
    /// measured by [`crate::sim::reference`] are 0.59 ± 0.01 from N = 16 to 256, whereas
    /// [`Repulsion::POLYCHROM`] swells short chains too much (0.65 at N = 16-32, 0.61 at
    /// N = 128-256, still converging).
    pub const SAW: Repulsion = Repulsion::Polynomial {
        energy: 0.6,
        radius: 0.8,
    };

    /// This repulsion with the height and range of a polynomial repulsion replaced where given
    /// (other repulsions are returned unchanged).
    pub fn with_polynomial(self, energy: Option<f64>, radius: Option<f64>) -> Self {
        match self {
            Repulsion::Polynomial {
                energy: e,
                radius: r,
            } => Repulsion::Polynomial {
                energy: energy.unwrap_or(e),
                radius: radius.unwrap_or(r),
            },
            other => other,
        }
    }

    /// The range beyond which the repulsion is 0.
    pub fn range(&self) -> f64 {
        match *self {
            Repulsion::None => 0.0,
            Repulsion::Polynomial { radius, .. } => radius,
            Repulsion::Wca { sigma, .. } => sigma * 2f64.powf(1.0 / 6.0),
        }
    }
}

/// Attraction between beads of the same type (block copolymer).
#[derive(Clone, Debug, PartialEq)]
pub struct Attraction {
    /// The type of every bead; beads of equal type attract each other.
    pub types: Vec<u8>,
    /// Well depth ε in kT.
    pub energy: f64,
    /// Range `r_a` (> 1).
    pub radius: f64,
}

/// Where the polymer lives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Confinement {
    /// Free space.
    None,
    /// A soft spherical wall at this radius, centred at the origin.
    Sphere {
        /// Radius.
        radius: f64,
        /// `k` of `E = k (|x| - R)²` outside.
        stiffness: f64,
    },
    /// A periodic cube of this side.
    Periodic {
        /// Side.
        side: f64,
    },
}

/// The bead indices of chains of the given lengths, numbered chain after chain.
pub fn chain_ranges(lengths: &[usize]) -> Vec<std::ops::Range<usize>> {
    let mut start = 0;
    lengths
        .iter()
        .map(|&length| {
            start += length;
            start - length..start
        })
        .collect()
}

/// The radius of a sphere holding `n` beads at number `density`.
pub fn sphere_radius(n: usize, density: f64) -> f64 {
    (3.0 * n as f64 / (4.0 * std::f64::consts::PI * density)).cbrt()
}

/// The side of a cube holding `n` beads at number `density`.
pub fn box_side(n: usize, density: f64) -> f64 {
    (n as f64 / density).cbrt()
}

/// The model and the integration step.
#[derive(Clone, Debug, PartialEq)]
pub struct PolymerParams {
    /// Number of beads of each chain (chromosome); beads are numbered chain after chain.
    pub chains: Vec<usize>,
    /// Chain bonds.
    pub bond: BondModel,
    /// Angle stiffness `k` in kT (0: none).
    pub angle_stiffness: f64,
    /// Excluded volume.
    pub repulsion: Repulsion,
    /// Optional same-type attraction.
    pub attraction: Option<Attraction>,
    /// Confinement.
    pub confinement: Confinement,
    /// Beads at most this far apart along a chain do not feel the pair potential (1: bonded
    /// neighbours only, polychrom's choice).
    pub excluded_neighbours: usize,
    /// Time step.
    pub dt: f64,
}

impl Default for PolymerParams {
    /// One chain of 1,000 beads, harmonic bonds (wiggle 0.1), polychrom's repulsion (3 kT,
    /// 1.05), free space, `dt = 0.002`.
    fn default() -> Self {
        Self {
            chains: vec![1000],
            bond: BondModel::Harmonic {
                length: 1.0,
                wiggle: 0.1,
            },
            angle_stiffness: 0.0,
            repulsion: Repulsion::Polynomial {
                energy: 3.0,
                radius: 1.05,
            },
            attraction: None,
            confinement: Confinement::None,
            excluded_neighbours: 1,
            dt: 0.002,
        }
    }
}

pub(super) fn positive(value: f64, what: &str) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::Argument(format!(
            "{what} must be a positive number, got {value}"
        )))
    }
}

pub(super) fn non_negative(value: f64, what: &str) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Error::Argument(format!(
            "{what} must be 0 or more, got {value}"
        )))
    }
}

impl PolymerParams {
    /// Total number of beads.
    pub fn n_beads(&self) -> usize {
        self.chains.iter().sum()
    }

    /// The bead indices of each chain ([`chain_ranges`]).
    pub fn chain_ranges(&self) -> Vec<std::ops::Range<usize>> {
        chain_ranges(&self.chains)
    }

    /// Check every parameter, with a message naming the bad one.
    pub fn check(&self) -> Result<()> {
        if self.chains.is_empty() || self.chains.contains(&0) {
            return Err(Error::Argument(
                "every chain needs at least one bead".to_string(),
            ));
        }
        if self.n_beads() > u32::MAX as usize / 2 {
            return Err(Error::Unsupported(format!(
                "{} beads is more than this simulator handles",
                self.n_beads()
            )));
        }
        match self.bond {
            BondModel::Harmonic { length, wiggle } => {
                non_negative(length, "bond length")?;
                positive(wiggle, "bond wiggle distance")?;
            }
            BondModel::Fene {
                stiffness,
                max_length,
            } => {
                positive(stiffness, "FENE stiffness")?;
                positive(max_length, "FENE maximum length")?;
            }
        }
        non_negative(self.angle_stiffness, "angle stiffness")?;
        match self.repulsion {
            Repulsion::None => {}
            Repulsion::Polynomial { energy, radius } => {
                positive(energy, "repulsion energy")?;
                positive(radius, "repulsion radius")?;
            }
            Repulsion::Wca { epsilon, sigma } => {
                positive(epsilon, "WCA epsilon")?;
                positive(sigma, "WCA sigma")?;
            }
        }
        if let Some(attraction) = &self.attraction {
            if attraction.types.len() != self.n_beads() {
                return Err(Error::Argument(format!(
                    "{} bead types for {} beads",
                    attraction.types.len(),
                    self.n_beads()
                )));
            }
            positive(attraction.energy, "attraction energy")?;
            if !(attraction.radius.is_finite() && attraction.radius > 1.0) {
                return Err(Error::Argument(format!(
                    "attraction radius must be above 1 (the bead diameter), got {}",
                    attraction.radius
                )));
            }
        }
        match self.confinement {
            Confinement::None => {}
            Confinement::Sphere { radius, stiffness } => {
                positive(radius, "confinement radius")?;
                positive(stiffness, "confinement stiffness")?;
            }
            Confinement::Periodic { side } => {
                positive(side, "box side")?;
                if side < 2.0 * self.interaction_range() {
                    return Err(Error::Argument(format!(
                        "the periodic box ({side:.3}) must be at least twice the interaction \
                         range ({:.3}) wide",
                        self.interaction_range()
                    )));
                }
            }
        }
        let density = match self.confinement {
            Confinement::Sphere { radius, .. } => {
                self.n_beads() as f64 / (4.0 / 3.0 * std::f64::consts::PI * radius.powi(3))
            }
            Confinement::Periodic { side } => self.n_beads() as f64 / side.powi(3),
            Confinement::None => 0.0,
        };
        if density > CLOSE_PACKING_DENSITY {
            return Err(Error::Argument(format!(
                "density {density:.3} beads per unit volume is above close packing ({:.3})",
                CLOSE_PACKING_DENSITY
            )));
        }
        positive(self.dt, "time step")?;
        Ok(())
    }

    /// The longest range of a pair interaction (0 for an ideal chain without attraction).
    pub fn interaction_range(&self) -> f64 {
        let attraction = self.attraction.as_ref().map_or(0.0, |a| a.radius);
        self.repulsion.range().max(attraction)
    }

    pub(super) fn space(&self) -> Space {
        match self.confinement {
            Confinement::Periodic { side } => Space::Periodic(side),
            _ => Space::Open,
        }
    }
}
