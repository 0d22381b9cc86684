//! An off-lattice bead-spring polymer under overdamped Langevin (Brownian) dynamics.
//!
//! Units: lengths in bond lengths (`b = 1`), energies in `kT = 1`, the friction coefficient of a
//! bead is 1, so a bead diffuses with `D = 1` and time is in `b² ζ / kT`.
//!
//! **Energy** (every term optional except the bonds):
//!
//! - bonds between consecutive beads of a chain: harmonic, `E = ((r - r0) / w)²` (polychrom's
//!   convention: a stretch by the "wiggle distance" `w` costs 1 kT), or FENE,
//!   `E = -K R0² / 2 · ln(1 - (r / R0)²)` (Kremer-Grest: `K = 30`, `R0 = 1.5`, with WCA);
//! - angle stiffness between consecutive bonds, `E = k (1 - cos θ)` (θ = 0 for a straight chain);
//! - excluded volume between non-bonded beads, cut off at a finite range:
//!   - polychrom's polynomial repulsion of height `e` and radius `σ`:
//!     `E = e (1 + x⁶ (x - 1) / m)` with `x = (6/7) (r/σ)²` and `m = 6⁶ / 7⁷`, equal to `e` at
//!     contact, 0 with zero slope at `r = σ` (soft: chains can cross when `e` is a few kT);
//!   - WCA: `E = 4 ε ((σ/r)¹² - (σ/r)⁶) + ε` for `r < 2^(1/6) σ` (hard);
//! - block-copolymer attraction between beads of the same type (`types`): a smooth well
//!   `E = -ε` below `r = 1`, rising as `-ε (1 + cos(π (r - 1) / (r_a - 1))) / 2` to 0 at `r_a`
//!   (added to the repulsion);
//! - confinement: a spherical wall `E = k (|x| - R)²` outside radius `R`, or a periodic cube
//!   (minimum-image interactions, coordinates kept unwrapped);
//! - extra bonds added by the caller (the loops of loop extrusion), harmonic like the chain
//!   bonds, with their own length and wiggle.
//!
//! Bonded neighbours `(i, i + 1)` of a chain do not feel the pair potential (as in polychrom);
//! [`PolymerParams::excluded_neighbours`] widens this to `|i - j| <= k`.
//!
//! **Dynamics**: Euler-Maruyama, `x(t + dt) = x(t) + F dt + sqrt(2 dt) ξ` with ξ standard normal
//! from the counter-based generator of [`super::noise`]: bead `i` at step `t` draws
//! `bead_normals(key, t, i)`, with `key` drawn from the polymer's generator after the initial
//! conformation and `t` counting every step the polymer took ([`Polymer::steps_taken`], the
//! push-off of a hard repulsion included). No generator state passes from bead to bead.
//!
//! **Stability**: the explicit step damps a pair's separation by `1 - 2 k dt` per step, with
//! `k` the curvature of the pair energy, so it is stable only while `k dt < 1`. WCA's
//! curvature `4 ε (156 σ¹² / r¹⁴ - 42 σ⁶ / r⁸)` is 2,333 kT/b² at `r = 0.9 σ`: at
//! `dt = 0.0005` a pair that noise brings within about 0.91 σ is overshot, beads land inside
//! others and the chain explodes (forces of 10⁶, bonds held at the FENE cap, then NaN). Over
//! `t = 0.15` of an 800-bead Kremer-Grest chain at density 0.4 in a periodic box, 2 seeds in
//! 10 blew up at `dt = 0.0005` (seed 3 at step 298: issue 12), none at `dt = 0.0002`.
//!
//! **Pair forces** come from a [`CellList`] rebuilt every step: O(N), never all pairs.
//!
//! **Threads**: one chain uses the threads of the current rayon pool (from 4,096 beads; smaller
//! chains stay on the calling thread), and the trajectory is the same bit for bit whatever their
//! number, because every bead's force is summed in an order fixed by the conformation alone:
//! each plane of cells of the cell list is one task that adds the pair forces of its pairs
//! (Newton's third law) into its own buffer for its slots and a second buffer for the slots of
//! the next plane (the only other plane its pairs reach), and a slot's pair force is then its
//! own-plane sum plus the sum spilled from the plane below; bonds and angles are evaluated once
//! each into per-bead buffers that every bead then sums in a fixed order; extra bonds are added
//! one after the other; the integration and the noise are per bead.
//!
//! With no repulsion ([`Repulsion::None`]) the chain is ideal (a phantom chain: Gaussian statistics
//! at large separations); with a repulsion and no attraction it is a self-avoiding walk in good
//! solvent.

use super::noise;
use crate::error::{Error, Result};
use crate::geometry::cells::{CellList, Space, split_lengths};
use crate::random::SeededRng;

mod forces;
mod integrator;
#[cfg(test)]
mod tests;

pub(in crate::sim) use forces::{bond_terms, pair_terms};
use integrator::*;

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
    /// measured by [`super::reference`] are 0.59 ± 0.01 from N = 16 to 256, whereas
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

fn positive(value: f64, what: &str) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::Invalid(format!(
            "{what} must be a positive number, got {value}"
        )))
    }
}

fn non_negative(value: f64, what: &str) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Error::Invalid(format!(
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
            return Err(Error::Invalid(
                "every chain needs at least one bead".to_string(),
            ));
        }
        if self.n_beads() > u32::MAX as usize / 2 {
            return Err(Error::Invalid(format!(
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
                return Err(Error::Invalid(format!(
                    "{} bead types for {} beads",
                    attraction.types.len(),
                    self.n_beads()
                )));
            }
            positive(attraction.energy, "attraction energy")?;
            if !(attraction.radius.is_finite() && attraction.radius > 1.0) {
                return Err(Error::Invalid(format!(
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
                    return Err(Error::Invalid(format!(
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
            return Err(Error::Invalid(format!(
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

    fn space(&self) -> Space {
        match self.confinement {
            Confinement::Periodic { side } => Space::Periodic(side),
            _ => Space::Open,
        }
    }
}

/// A polymer and its integrator state.
#[derive(Clone, Debug)]
pub struct Polymer {
    params: PolymerParams,
    positions: Vec<[f64; 3]>,
    forces: Vec<[f64; 3]>,
    chain_of: Vec<u32>,
    extra_bonds: Vec<(u32, u32)>,
    extra_bond: (f64, f64),
    cells: CellList,
    noise_key: [u32; 2],
    steps_taken: u64,
    time: f64,
    scratch: Scratch,
}

/// Work buffers of the force evaluation, kept between steps.
#[derive(Clone, Debug, Default)]
struct Scratch {
    /// Pair forces by slot of the cell list, from the pairs found in the slot's own plane.
    own: Vec<[f64; 3]>,
    /// Pair forces by slot, from the pairs found in the plane below the slot's.
    spill: Vec<[f64; 3]>,
    /// Per bead `i`: the force of the bond `(i, i + 1)` on `i`, and its energy.
    bonds: Vec<[f64; 4]>,
    /// Per bead `i`: the forces of the angle centred on `i` on beads `i - 1`, `i`, `i + 1`,
    /// and its energy.
    angles: Vec<[f64; 10]>,
}

/// A plane's force buffers: its own slots, and the next plane's slots it spills into.
type PlaneBuffers<'a> = (&'a mut [[f64; 3]], &'a mut [[f64; 3]]);

/// The radius of gyration of `positions`.
pub fn radius_of_gyration(positions: &[[f64; 3]]) -> f64 {
    let n = positions.len() as f64;
    if positions.is_empty() {
        return 0.0;
    }
    let mut centre = [0.0; 3];
    for p in positions {
        for k in 0..3 {
            centre[k] += p[k] / n;
        }
    }
    let sum: f64 = positions
        .iter()
        .map(|p| (0..3).map(|k| (p[k] - centre[k]).powi(2)).sum::<f64>())
        .sum();
    (sum / n).sqrt()
}
