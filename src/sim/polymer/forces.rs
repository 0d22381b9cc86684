//! The forces of the polymer: the pair terms (repulsion, attraction) over the cell list, the
//! bonds (harmonic, FENE, the extra bonds of loop extrusion), the angles, the confinement, and
//! the potential energy; summed in an order fixed by the conformation alone (see the module
//! doc of [`super`]).

use rayon::prelude::*;

use super::chain::{PlaneBuffers, Polymer, Scratch};
use super::integrator::for_each_block;
use super::params::{Attraction, BondModel, Confinement, Repulsion};
use crate::geometry::cells::split_lengths;

/// The attraction well `(depth, range)` between beads `i` and `j`, when they are of one type.
#[inline]
pub(super) fn same_type_well(
    attraction: Option<&Attraction>,
    i: usize,
    j: usize,
) -> Option<(f64, f64)> {
    attraction
        .filter(|a| a.types[i] == a.types[j])
        .map(|a| (a.energy, a.radius))
}

/// Polynomial repulsion constant `m = 6⁶ / 7⁷`.
pub(super) const POLY_MIN: f64 = 46656.0 / 823543.0;

/// Energy and `-(dE/dr) / r` of a pair at squared distance `r2` (the force on `a` is
/// `factor * (x_a - x_b)`).
#[inline]
pub(in crate::sim) fn pair_terms(
    repulsion: &Repulsion,
    attraction: Option<(f64, f64)>,
    r2: f64,
) -> (f64, f64) {
    let mut energy = 0.0;
    let mut factor = 0.0;
    match *repulsion {
        Repulsion::None => {}
        Repulsion::Polynomial { energy: e, radius } => {
            let sigma2 = radius * radius;
            if r2 < sigma2 {
                let x = 6.0 / 7.0 * r2 / sigma2;
                let x5 = x * x * x * x * x;
                let x6 = x5 * x;
                energy += e * (1.0 + x6 * (x - 1.0) / POLY_MIN);
                // dE/dr = e/m (7 x⁶ - 6 x⁵) dx/dr, dx/dr = 2 (6/7) r / σ².
                factor -= e / POLY_MIN * (7.0 * x6 - 6.0 * x5) * 2.0 * (6.0 / 7.0) / sigma2;
            }
        }
        Repulsion::Wca { epsilon, sigma } => {
            let cut2 = sigma * sigma * 2f64.powf(1.0 / 3.0);
            if r2 < cut2 {
                let s2 = sigma * sigma / r2;
                let s6 = s2 * s2 * s2;
                energy += 4.0 * epsilon * (s6 * s6 - s6) + epsilon;
                // -dE/dr / r = 24 ε (2 s¹² - s⁶) / r².
                factor += 24.0 * epsilon * (2.0 * s6 * s6 - s6) / r2;
            }
        }
    }
    if let Some((depth, radius)) = attraction {
        if r2 < radius * radius {
            if r2 <= 1.0 {
                energy -= depth;
            } else {
                let r = r2.sqrt();
                let phase = std::f64::consts::PI * (r - 1.0) / (radius - 1.0);
                energy -= depth * (1.0 + phase.cos()) / 2.0;
                // dE/dr = depth π sin(phase) / (2 (r_a - 1)) ≥ 0: attractive.
                let slope = depth * std::f64::consts::PI * phase.sin() / (2.0 * (radius - 1.0));
                factor -= slope / r;
            }
        }
    }
    (energy, factor)
}

/// Add the force of the bond `(i, j)`; return its energy.
#[inline]
pub(super) fn bond_force(
    positions: &[[f64; 3]],
    forces: &mut [[f64; 3]],
    i: usize,
    j: usize,
    bond: BondModel,
) -> f64 {
    let (a, b) = (positions[i], positions[j]);
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let (energy, factor) = bond_terms(bond, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for k in 0..3 {
        forces[i][k] += factor * d[k];
        forces[j][k] -= factor * d[k];
    }
    energy
}

/// Energy and `-(dE/dr) / r` of a bond at squared length `r2`.
#[inline]
pub(in crate::sim) fn bond_terms(bond: BondModel, r2: f64) -> (f64, f64) {
    match bond {
        BondModel::Harmonic { length, wiggle } => {
            let r = r2.sqrt();
            let stretch = r - length;
            let energy = (stretch / wiggle).powi(2);
            // -dE/dr / r; at r = 0 with a zero rest length the force is 0 anyway.
            let factor = if r > 0.0 {
                -2.0 * stretch / (wiggle * wiggle) / r
            } else {
                0.0
            };
            (energy, factor)
        }
        BondModel::Fene {
            stiffness,
            max_length,
        } => {
            // Beyond 99 % of R0 the bond is held at 99 % (the energy would be infinite).
            let ratio2 = (r2 / (max_length * max_length)).min(0.98);
            let energy = -0.5 * stiffness * max_length * max_length * (1.0 - ratio2).ln();
            (energy, -stiffness / (1.0 - ratio2))
        }
    }
}

/// The angle at bead `i` (`E = k (1 - cos θ)`): its forces on beads `i - 1`, `i` and `i + 1`
/// (three components each) and its energy.
#[inline]
pub(super) fn angle_terms(positions: &[[f64; 3]], i: usize, k: f64) -> [f64; 10] {
    let (p0, p1, p2) = (positions[i - 1], positions[i], positions[i + 1]);
    let b1 = [p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]];
    let b2 = [p2[0] - p1[0], p2[1] - p1[1], p2[2] - p1[2]];
    let l1 = (b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2]).sqrt();
    let l2 = (b2[0] * b2[0] + b2[1] * b2[1] + b2[2] * b2[2]).sqrt();
    let mut terms = [0.0; 10];
    if l1 == 0.0 || l2 == 0.0 {
        return terms;
    }
    let cos = (b1[0] * b2[0] + b1[1] * b2[1] + b1[2] * b2[2]) / (l1 * l2);
    // F = k ∇cos θ.
    for axis in 0..3 {
        let d_cos_b1 = b2[axis] / (l1 * l2) - cos * b1[axis] / (l1 * l1);
        let d_cos_b2 = b1[axis] / (l1 * l2) - cos * b2[axis] / (l2 * l2);
        terms[axis] = -k * d_cos_b1;
        terms[3 + axis] = k * (d_cos_b1 - d_cos_b2);
        terms[6 + axis] = k * d_cos_b2;
    }
    terms[9] = k * (1.0 - cos);
    terms
}

impl Polymer {
    /// Compute the forces at the current positions; returns the potential energy.
    pub fn compute_forces(&mut self) -> f64 {
        self.evaluate_forces(true)
    }

    /// Fill `self.forces`; return the potential energy when `with_energy` (else 0). The sum
    /// of every bead's force runs in an order fixed by the conformation alone (see the module
    /// docs), so it is the same bit for bit on any number of threads.
    pub(super) fn evaluate_forces(&mut self, with_energy: bool) -> f64 {
        let parallel = self.parallel();
        let mut energy = self.pair_forces(parallel);
        energy += self.extra_bond_forces();
        energy += self.bonded_forces(parallel, with_energy);
        if with_energy { energy } else { 0.0 }
    }

    /// Set the forces to the pair forces (through the cell list); return their energy.
    ///
    /// Each plane of cells is a task: it visits its pairs ([`CellList::for_each_pair_in_plane`])
    /// in a fixed order and adds both forces of a pair (Newton's third law) into its own
    /// buffers: `own` for the slots of its plane, `spill` for those of the next plane. A
    /// slot's force is then `own + spill`: the same additions in the same order whatever
    /// thread ran which plane.
    pub(super) fn pair_forces(&mut self, parallel: bool) -> f64 {
        let n = self.positions.len();
        let range = self.params.interaction_range();
        if range <= 0.0 {
            for_each_block(parallel, &mut self.forces, |_, block| {
                block.fill([0.0; 3]);
            });
            return 0.0;
        }
        let space = self.params.space();
        self.cells.build(&self.positions, range, space);
        let cells = &self.cells;
        let n_planes = cells.n_planes();
        let Scratch { own, spill, .. } = &mut self.scratch;
        own.resize(n, [0.0; 3]);
        spill.resize(n, [0.0; 3]);
        let plane_lengths = || (0..n_planes).map(|z| cells.plane_slots(z).len());
        let own_parts = split_lengths(own, plane_lengths());
        let mut spill_parts = split_lengths(spill, plane_lengths());
        // Plane z spills into plane z + 1 (the last one into the first).
        spill_parts.rotate_left(1);
        let repulsion = self.params.repulsion;
        let attraction = self.params.attraction.as_ref();
        let chain_of = &self.chain_of;
        let excluded = self.params.excluded_neighbours;
        let order = cells.order();
        let plane = |(z, (own, spill)): (usize, PlaneBuffers)| -> f64 {
            own.fill([0.0; 3]);
            spill.fill([0.0; 3]);
            let own_slots = cells.plane_slots(z);
            let spill_start = cells.plane_slots((z + 1) % n_planes).start;
            let mut energy = 0.0;
            cells.for_each_pair_in_plane(z, |a, b, d, r2| {
                let (i, j) = (order[a] as usize, order[b] as usize);
                if i.abs_diff(j) <= excluded && chain_of[i] == chain_of[j] {
                    return;
                }
                let attract = same_type_well(attraction, i, j);
                let (e, factor) = pair_terms(&repulsion, attract, r2);
                energy += e;
                // d = x_{slot a} - x_{slot b} = x_i - x_j.
                let force = [factor * d[0], factor * d[1], factor * d[2]];
                let on_a = &mut own[a - own_slots.start];
                for k in 0..3 {
                    on_a[k] += force[k];
                }
                let on_b = if own_slots.contains(&b) {
                    &mut own[b - own_slots.start]
                } else {
                    &mut spill[b - spill_start]
                };
                for k in 0..3 {
                    on_b[k] -= force[k];
                }
            });
            energy
        };
        let tasks = own_parts.into_iter().zip(spill_parts).enumerate();
        let energies: Vec<f64> = if parallel {
            tasks
                .collect::<Vec<_>>()
                .into_par_iter()
                .map(plane)
                .collect()
        } else {
            tasks.map(plane).collect()
        };
        let (own, spill) = (&self.scratch.own, &self.scratch.spill);
        let slot_of = self.cells.slot_of();
        for_each_block(parallel, &mut self.forces, |offset, block| {
            for (k, force) in block.iter_mut().enumerate() {
                let slot = slot_of[offset + k] as usize;
                let (a, b) = (own[slot], spill[slot]);
                *force = [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
            }
        });
        energies.iter().sum()
    }

    /// Add the forces of the extra bonds, one after the other in their order; return their
    /// energy.
    pub(super) fn extra_bond_forces(&mut self) -> f64 {
        let (length, wiggle) = self.extra_bond;
        let extra = BondModel::Harmonic { length, wiggle };
        let mut energy = 0.0;
        for &(i, j) in &self.extra_bonds {
            energy += bond_force(
                &self.positions,
                &mut self.forces,
                i as usize,
                j as usize,
                extra,
            );
        }
        energy
    }

    /// Add the forces of the chain bonds, angles and wall; return their energy when
    /// `with_energy` (else 0).
    ///
    /// Every bond (and angle) is evaluated once into a per-bead buffer, then every bead sums
    /// the terms that move it in a fixed order: wall, bond to the previous bead, bond to the
    /// next, then the angles centred on the previous bead, itself and the next.
    pub(super) fn bonded_forces(&mut self, parallel: bool, with_energy: bool) -> f64 {
        let n = self.positions.len();
        let positions = &self.positions;
        let chain_of = &self.chain_of;
        let Scratch { bonds, angles, .. } = &mut self.scratch;
        bonds.resize(n, [0.0; 4]);
        let bond = self.params.bond;
        for_each_block(parallel, bonds, |offset, block| {
            for (k, entry) in block.iter_mut().enumerate() {
                let i = offset + k;
                *entry = if i + 1 < n && chain_of[i] == chain_of[i + 1] {
                    let (a, b) = (positions[i], positions[i + 1]);
                    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
                    let (energy, factor) =
                        bond_terms(bond, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                    [factor * d[0], factor * d[1], factor * d[2], energy]
                } else {
                    [0.0; 4]
                };
            }
        });
        let k_angle = self.params.angle_stiffness;
        if k_angle > 0.0 {
            angles.resize(n, [0.0; 10]);
            for_each_block(parallel, angles, |offset, block| {
                for (k, entry) in block.iter_mut().enumerate() {
                    let i = offset + k;
                    *entry = if i >= 1 && i + 1 < n && chain_of[i - 1] == chain_of[i + 1] {
                        angle_terms(positions, i, k_angle)
                    } else {
                        [0.0; 10]
                    };
                }
            });
        } else {
            angles.clear();
        }
        let (bonds, angles) = (&*bonds, &*angles);
        let wall = match self.params.confinement {
            Confinement::Sphere { radius, stiffness } => Some((radius, stiffness)),
            _ => None,
        };
        for_each_block(parallel, &mut self.forces, |offset, block| {
            for (k, force) in block.iter_mut().enumerate() {
                let i = offset + k;
                if let Some((radius, stiffness)) = wall {
                    let p = positions[i];
                    let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                    if r > radius {
                        let scale = -2.0 * stiffness * (r - radius) / r;
                        for axis in 0..3 {
                            force[axis] += scale * p[axis];
                        }
                    }
                }
                if i > 0 {
                    for axis in 0..3 {
                        force[axis] -= bonds[i - 1][axis];
                    }
                }
                for axis in 0..3 {
                    force[axis] += bonds[i][axis];
                }
                if !angles.is_empty() {
                    for axis in 0..3 {
                        if i > 0 {
                            force[axis] += angles[i - 1][6 + axis];
                        }
                        force[axis] += angles[i][3 + axis];
                        if i + 1 < n {
                            force[axis] += angles[i + 1][axis];
                        }
                    }
                }
            }
        });
        if !with_energy {
            return 0.0;
        }
        let mut energy: f64 = bonds.iter().map(|b| b[3]).sum();
        energy += angles.iter().map(|a| a[9]).sum::<f64>();
        if let Some((radius, stiffness)) = wall {
            for p in positions {
                let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                if r > radius {
                    energy += stiffness * (r - radius).powi(2);
                }
            }
        }
        energy
    }

    /// The forces of the last [`Polymer::compute_forces`].
    pub fn forces(&self) -> &[[f64; 3]] {
        &self.forces
    }
}
