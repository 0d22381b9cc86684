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
//! **Pair forces** come from a [`CellList`](crate::geometry::cells::CellList) rebuilt every step: O(N), never all pairs.
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

mod chain;
mod forces;
mod integrator;
mod params;
#[cfg(test)]
mod tests;

pub use chain::{Polymer, radius_of_gyration};
pub(in crate::sim) use forces::{bond_terms, pair_terms};
pub use params::{
    Attraction, BondModel, CLOSE_PACKING_DENSITY, Confinement, PolymerParams, Repulsion, box_side,
    chain_ranges, sphere_radius,
};
