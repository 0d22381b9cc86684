//! A Metropolis Monte Carlo sampler of one free chain: the equilibrium reference for the
//! Brownian dynamics of [`super::polymer`].
//!
//! The dynamics and this sampler share nothing but the energy (the same bond and pair terms), so
//! agreement of their averages checks the integrator, the forces and the cell lists at once.
//! The sampler is also far faster at equilibrium statistics of long single chains, which is how
//! the excluded volume of the self-avoiding-walk check ([`Repulsion::SAW`]) was chosen.
//!
//! Each sweep makes two pivot moves (Madras & Sokal 1988: the shorter side of the chain beyond a
//! random bead is rotated about it by a uniformly random rotation) and as many single-bead moves
//! as there are beads (a uniform displacement in a cube of side 0.5), each accepted with
//! probability `min(1, exp(-ΔE))`. Energies are summed over all pairs: O(N²) per sweep, meant for
//! chains of up to a few hundred beads.

use rand::Rng;

use super::polymer::{BondModel, Repulsion, bond_terms, pair_terms};
use crate::error::{Error, Result};
use crate::random::SeededRng;

/// One free chain: harmonic or FENE bonds and a pair repulsion between beads more than
/// `excluded_neighbours` apart (no angles, attraction or confinement).
#[derive(Clone, Debug)]
pub struct ChainSampler {
    bond: BondModel,
    repulsion: Repulsion,
    excluded_neighbours: usize,
    positions: Vec<[f64; 3]>,
    trial: Vec<[f64; 3]>,
    rng: SeededRng,
}

fn distance2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
}

/// A uniformly random rotation matrix (from a uniformly random unit quaternion).
fn random_rotation(rng: &mut SeededRng) -> [[f64; 3]; 3] {
    let q = loop {
        let q: [f64; 4] = std::array::from_fn(|_| 2.0 * rng.r#gen::<f64>() - 1.0);
        let norm2: f64 = q.iter().map(|v| v * v).sum();
        if norm2 < 1.0 && norm2 > 1e-6 {
            break q.map(|v| v / norm2.sqrt());
        }
    };
    let [a, b, c, d] = q;
    [
        [
            a * a + b * b - c * c - d * d,
            2.0 * (b * c - a * d),
            2.0 * (b * d + a * c),
        ],
        [
            2.0 * (b * c + a * d),
            a * a - b * b + c * c - d * d,
            2.0 * (c * d - a * b),
        ],
        [
            2.0 * (b * d - a * c),
            2.0 * (c * d + a * b),
            a * a - b * b - c * c + d * d,
        ],
    ]
}

impl ChainSampler {
    /// A chain of `n` beads, started straight along x with unit spacing.
    pub fn new(
        n: usize,
        bond: BondModel,
        repulsion: Repulsion,
        excluded_neighbours: usize,
        rng: SeededRng,
    ) -> Result<Self> {
        if n < 3 {
            return Err(Error::Argument(format!(
                "the chain sampler needs at least 3 beads, got {n}"
            )));
        }
        let positions: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 0.0, 0.0]).collect();
        Ok(Self {
            bond,
            repulsion,
            excluded_neighbours: excluded_neighbours.max(1),
            trial: positions.clone(),
            positions,
            rng,
        })
    }

    /// The bead positions.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }

    fn pair(&self, i: usize, j: usize, a: [f64; 3], b: [f64; 3]) -> f64 {
        if i.abs_diff(j) <= self.excluded_neighbours {
            0.0
        } else {
            pair_terms(&self.repulsion, None, distance2(a, b)).0
        }
    }

    fn accept(&mut self, delta: f64) -> bool {
        delta <= 0.0 || self.rng.r#gen::<f64>() < (-delta).exp()
    }

    /// Two pivot moves and `n` single-bead moves.
    pub fn sweep(&mut self) {
        for _ in 0..2 {
            self.pivot();
        }
        for _ in 0..self.positions.len() {
            self.local_move();
        }
    }

    fn pivot(&mut self) {
        let n = self.positions.len();
        let k = self.rng.gen_range(1..n - 1);
        let rotation = random_rotation(&mut self.rng);
        // Rotate the shorter side: beads [moved) about bead k.
        let moved = if k < n / 2 { 0..k } else { k + 1..n };
        let origin = self.positions[k];
        for i in moved.clone() {
            let v: [f64; 3] = std::array::from_fn(|a| self.positions[i][a] - origin[a]);
            self.trial[i] = std::array::from_fn(|a| {
                origin[a] + rotation[a][0] * v[0] + rotation[a][1] * v[1] + rotation[a][2] * v[2]
            });
        }
        let mut delta = 0.0;
        for i in moved.clone() {
            for j in (0..moved.start).chain(moved.end..n) {
                delta += self.pair(i, j, self.trial[i], self.positions[j])
                    - self.pair(i, j, self.positions[i], self.positions[j]);
            }
        }
        if self.accept(delta) {
            for i in moved {
                self.positions[i] = self.trial[i];
            }
        }
    }

    fn local_move(&mut self) {
        let n = self.positions.len();
        let i = self.rng.gen_range(0..n);
        let old = self.positions[i];
        let new: [f64; 3] = std::array::from_fn(|a| old[a] + (self.rng.r#gen::<f64>() - 0.5) * 0.5);
        let mut delta = 0.0;
        for j in [i.wrapping_sub(1), i + 1] {
            if j < n {
                let other = self.positions[j];
                delta += bond_terms(self.bond, distance2(new, other)).0
                    - bond_terms(self.bond, distance2(old, other)).0;
            }
        }
        for (j, &other) in self.positions.iter().enumerate() {
            delta += self.pair(i, j, new, other) - self.pair(i, j, old, other);
        }
        if self.accept(delta) {
            self.positions[i] = new;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::ensemble::{EnsembleParams, run_ensemble};
    use crate::sim::polymer::{Confinement, PolymerParams, radius_of_gyration};
    use rand::SeedableRng;

    const BOND: BondModel = BondModel::Harmonic {
        length: 1.0,
        wiggle: 0.3,
    };

    /// `<Rg²>` of the sampler, mean over `chains` chains of `sweeps` sweeps after a burn-in.
    fn sampled_rg2(n: usize, repulsion: Repulsion, chains: u64, sweeps: usize) -> f64 {
        let mut total = 0.0;
        for seed in 0..chains {
            let rng = SeededRng::seed_from_u64(seed);
            let mut sampler = ChainSampler::new(n, BOND, repulsion, 1, rng).unwrap();
            for _ in 0..sweeps / 5 {
                sampler.sweep();
            }
            for _ in 0..sweeps {
                sampler.sweep();
                let rg = radius_of_gyration(sampler.positions());
                total += rg * rg;
            }
        }
        total / (chains as usize * sweeps) as f64
    }

    /// `<b²>` of a harmonic bond, `∫ r⁴ e^-E dr / ∫ r² e^-E dr` by the trapezoid rule.
    fn mean_bond2() -> f64 {
        let (mut num, mut den) = (0.0, 0.0);
        for k in 1..40_000 {
            let r = k as f64 * 1e-4;
            let weight = r * r * (-bond_terms(BOND, r * r).0).exp();
            num += weight * r * r;
            den += weight;
        }
        num / den
    }

    #[test]
    fn ideal_chain_matches_the_closed_form() {
        // Without excluded volume the bonds are independent: <Rg²> = <b²> (N² - 1) / (6 N).
        let n = 24;
        let exact = mean_bond2() * (n * n - 1) as f64 / (6 * n) as f64;
        let sampled = sampled_rg2(n, Repulsion::None, 8, 4000);
        assert!(
            (sampled / exact - 1.0).abs() < 0.03,
            "sampled {sampled}, exact {exact}"
        );
    }

    #[test]
    fn brownian_dynamics_samples_the_same_equilibrium() {
        // polychrom's repulsion swells a 10-bead chain by half over the ideal chain; the dynamics
        // (dt = 0.005, relaxation time about 5) must agree with the sampler. Euler-Maruyama
        // widens the bond-length distribution by O(dt) (about 1.5 % on <Rg²> here).
        let n = 10;
        let sampled = sampled_rg2(n, Repulsion::POLYCHROM, 16, 10_000);
        let ideal = mean_bond2() * (n * n - 1) as f64 / (6 * n) as f64;
        assert!(sampled > 1.4 * ideal, "sampled {sampled}, ideal {ideal}");
        let params = EnsembleParams {
            polymer: PolymerParams {
                chains: vec![n],
                bond: BOND,
                repulsion: Repulsion::POLYCHROM,
                confinement: Confinement::None,
                dt: 0.005,
                ..PolymerParams::default()
            },
            replicas: 48,
            equilibration_steps: 4000,
            sample_every: 400,
            samples: 100,
            contact_radius: 1.5,
            monomers_per_bin: 1,
            seed: 3,
            extrusion: None,
            keep_conformations: false,
        };
        let ensemble = run_ensemble(&params, &|_| {}).unwrap();
        let radii = &ensemble.radii_of_gyration;
        let dynamics = radii.iter().map(|r| r[0] * r[0]).sum::<f64>() / radii.len() as f64;
        assert!(
            (dynamics / sampled - 1.0).abs() < 0.03,
            "dynamics {dynamics}, sampler {sampled}"
        );
    }
}
