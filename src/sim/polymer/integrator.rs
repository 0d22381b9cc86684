//! The integrator of the polymer: the initial conformation (a random walk, pushed apart under
//! a hard repulsion), the Euler-Maruyama step with counter-based noise, and the threads.

use crate::error::{Error, Result};
use rand::Rng;
use rayon::prelude::*;

use super::chain::{Polymer, Scratch};
use super::params::{Confinement, PolymerParams, Repulsion};
use crate::geometry::cells::{CellList, Space};
use crate::random::SeededRng;
use crate::sim::noise;

/// Below this many beads a polymer is stepped on the calling thread alone (the result is the
/// same bit for bit; splitting a small chain costs more than it saves).
pub(super) const PARALLEL_MIN_BEADS: usize = 4096;

/// Beads per parallel task in the per-bead passes.
pub(super) const BLOCK: usize = 1024;

/// Call `work(offset, block)` on blocks of `data` (the block starting at bead `offset`), in
/// parallel when asked; `work` must treat every bead on its own, so the result is the same.
pub(super) fn for_each_block<T, F>(parallel: bool, data: &mut [T], work: F)
where
    T: Send,
    F: Fn(usize, &mut [T]) + Sync + Send,
{
    if parallel {
        data.par_chunks_mut(BLOCK)
            .enumerate()
            .for_each(|(k, block)| work(k * BLOCK, block));
    } else {
        work(0, data);
    }
}

/// A pair of independent standard normals by Marsaglia's polar method (no trigonometry; 27 %
/// of the uniform pairs are rejected).
#[inline]
pub(super) fn normal_pair(rng: &mut SeededRng) -> (f64, f64) {
    loop {
        let u = 2.0 * rng.r#gen::<f64>() - 1.0;
        let v = 2.0 * rng.r#gen::<f64>() - 1.0;
        let s = u * u + v * v;
        if s < 1.0 && s > 0.0 {
            let factor = (-2.0 * s.ln() / s).sqrt();
            return (u * factor, v * factor);
        }
    }
}

pub(super) fn random_unit(rng: &mut SeededRng) -> [f64; 3] {
    loop {
        let (a, b) = normal_pair(rng);
        let (c, _) = normal_pair(rng);
        let norm = (a * a + b * b + c * c).sqrt();
        if norm > 1e-12 {
            return [a / norm, b / norm, c / norm];
        }
    }
}

/// Beads whose noise [`bead_normals_lanes`] draws at once.
pub(super) const NOISE_LANES: usize = noise::GROUP;

/// [`noise::bead_normals`] of the beads `first..first + NOISE_LANES` (`first` a multiple of
/// [`NOISE_LANES`]), the same bits, from their group's words at once ([`noise::group_normals`]).
#[inline]
pub(super) fn bead_normals_lanes(key: [u32; 2], step: u64, first: u32) -> [[f64; 3]; NOISE_LANES] {
    debug_assert_eq!(first as usize % NOISE_LANES, 0);
    noise::group_normals(key, step, first / NOISE_LANES as u32)
}

impl Polymer {
    /// A polymer whose chains start as random walks of unit steps (kept inside the sphere when
    /// confined; each chain starts at a random point of the sphere or box), with overlaps
    /// pushed off for a hard repulsion (see `push_off`).
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::sim::polymer::{Polymer, PolymerParams};
    /// use contactmap::random::stream_rng;
    /// let params = PolymerParams { chains: vec![50], ..PolymerParams::default() };
    /// let mut polymer = Polymer::new(params, stream_rng(1, 0, 0))?;
    /// polymer.run(100);
    /// assert_eq!((polymer.positions().len(), polymer.steps_taken()), (50, 100));
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn new(params: PolymerParams, mut rng: SeededRng) -> Result<Self> {
        params.check()?;
        let n = params.n_beads();
        let mut positions = Vec::with_capacity(n);
        let mut chain_of = Vec::with_capacity(n);
        for (chain, &length) in params.chains.iter().enumerate() {
            let mut current = match params.confinement {
                Confinement::Sphere { radius, .. } => {
                    let direction = random_unit(&mut rng);
                    let r = radius * rng.r#gen::<f64>().cbrt() * 0.9;
                    direction.map(|x| x * r)
                }
                Confinement::Periodic { side } => [
                    rng.r#gen::<f64>() * side,
                    rng.r#gen::<f64>() * side,
                    rng.r#gen::<f64>() * side,
                ],
                Confinement::None => [0.0; 3],
            };
            for bead in 0..length {
                if bead > 0 {
                    current = loop {
                        let step = random_unit(&mut rng);
                        let next = [
                            current[0] + step[0],
                            current[1] + step[1],
                            current[2] + step[2],
                        ];
                        match params.confinement {
                            Confinement::Sphere { radius, .. }
                                if next.iter().map(|x| x * x).sum::<f64>() > radius * radius => {}
                            _ => break next,
                        }
                    };
                }
                positions.push(current);
                chain_of.push(chain as u32);
            }
        }
        Self::with_positions(params, positions, chain_of, rng)
    }

    /// With a hard repulsion (WCA), separate overlapping beads first: run with a soft
    /// polynomial repulsion of the same range (10 kT) until no two non-bonded beads are closer
    /// than 0.85 σ (at most 20,000 steps), as Kremer-Grest set-ups push overlaps off with a
    /// soft potential.
    pub(super) fn push_off(&mut self) {
        let Repulsion::Wca { sigma, .. } = self.params.repulsion else {
            return;
        };
        let hard = self.params.repulsion;
        self.params.repulsion = Repulsion::Polynomial {
            energy: 10.0,
            radius: hard.range(),
        };
        for _ in 0..200 {
            if !self.has_overlap(0.85 * sigma) {
                break;
            }
            self.run(100);
        }
        self.params.repulsion = hard;
    }

    pub(super) fn has_overlap(&mut self, distance: f64) -> bool {
        self.cells
            .build(&self.positions, distance, self.params.space());
        let order = self.cells.order();
        let mut found = false;
        self.cells.for_each_pair(|a, b, _, _| {
            let (i, j) = (order[a] as usize, order[b] as usize);
            if !self.bonded(i, j) {
                found = true;
            }
        });
        found
    }

    /// A polymer at the given bead positions.
    pub fn from_positions(
        params: PolymerParams,
        positions: Vec<[f64; 3]>,
        rng: SeededRng,
    ) -> Result<Self> {
        params.check()?;
        if positions.len() != params.n_beads() {
            return Err(Error::Argument(format!(
                "{} positions for {} beads",
                positions.len(),
                params.n_beads()
            )));
        }
        let chain_of = params
            .chains
            .iter()
            .enumerate()
            .flat_map(|(chain, &length)| std::iter::repeat_n(chain as u32, length))
            .collect();
        Self::with_positions(params, positions, chain_of, rng)
    }

    pub(super) fn with_positions(
        params: PolymerParams,
        positions: Vec<[f64; 3]>,
        chain_of: Vec<u32>,
        mut rng: SeededRng,
    ) -> Result<Self> {
        let n = positions.len();
        let mut polymer = Self {
            params,
            forces: vec![[0.0; 3]; n],
            positions,
            chain_of,
            extra_bonds: Vec::new(),
            extra_bond: (1.0, 0.1),
            cells: CellList::new(),
            noise_key: noise::noise_key(&mut rng),
            steps_taken: 0,
            time: 0.0,
            scratch: Scratch::default(),
        };
        polymer.push_off();
        polymer.time = 0.0;
        Ok(polymer)
    }

    /// The parameters.
    pub fn params(&self) -> &PolymerParams {
        &self.params
    }

    /// Bead positions (unwrapped in a periodic box).
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }

    /// Simulated time (from the end of the push-off, if any).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The key of this polymer's noise stream ([`noise::bead_normals`]), drawn from its
    /// generator after the initial conformation.
    pub fn noise_key(&self) -> [u32; 2] {
        self.noise_key
    }

    /// Every step this polymer has taken, the push-off of a hard repulsion included: the
    /// counter of the next step's noise.
    pub fn steps_taken(&self) -> u64 {
        self.steps_taken
    }

    /// The space for pair distances (periodic or open).
    pub fn space(&self) -> Space {
        self.params.space()
    }

    /// Replace the extra harmonic bonds (e.g. the loops of loop extrusion) by `bonds`, each
    /// with rest `length` and `wiggle` (see the module docs).
    pub fn set_extra_bonds(&mut self, bonds: &[(usize, usize)], length: f64, wiggle: f64) {
        self.extra_bonds.clear();
        self.extra_bonds
            .extend(bonds.iter().map(|&(i, j)| (i as u32, j as u32)));
        self.extra_bond = (length, wiggle);
    }

    /// Whether `i` and `j` are too close along one chain to feel the pair potential.
    pub(super) fn bonded(&self, i: usize, j: usize) -> bool {
        i.abs_diff(j) <= self.params.excluded_neighbours && self.chain_of[i] == self.chain_of[j]
    }

    /// Whether this polymer is worth splitting across the threads of the current rayon pool.
    pub(super) fn parallel(&self) -> bool {
        self.positions.len() >= PARALLEL_MIN_BEADS && rayon::current_num_threads() > 1
    }

    /// Advance by one time step: Euler-Maruyama with the noise of this step's counter.
    pub fn step(&mut self) {
        self.evaluate_forces(false);
        let parallel = self.parallel();
        let dt = self.params.dt;
        let noise = (2.0 * dt).sqrt();
        let (key, step) = (self.noise_key, self.steps_taken);
        let forces = &self.forces;
        let advance = |p: &mut [f64; 3], f: [f64; 3], xi: [f64; 3]| {
            for axis in 0..3 {
                p[axis] += f[axis] * dt + noise * xi[axis];
            }
        };
        for_each_block(parallel, &mut self.positions, |offset, block| {
            let end = offset + block.len();
            let mut lanes = block.chunks_exact_mut(NOISE_LANES);
            for (k, group) in lanes.by_ref().enumerate() {
                let first = offset + k * NOISE_LANES;
                let normals = bead_normals_lanes(key, step, first as u32);
                for (lane, p) in group.iter_mut().enumerate() {
                    advance(p, forces[first + lane], normals[lane]);
                }
            }
            let rest = lanes.into_remainder();
            let first = end - rest.len();
            for (k, p) in rest.iter_mut().enumerate() {
                let bead = first + k;
                advance(p, forces[bead], noise::bead_normals(key, step, bead as u32));
            }
        });
        self.steps_taken += 1;
        self.time += dt;
    }

    /// Advance by `steps` time steps.
    pub fn run(&mut self, steps: usize) {
        for _ in 0..steps {
            self.step();
        }
    }
}
