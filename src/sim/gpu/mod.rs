//! The polymer simulator on a GPU: the model of [`crate::sim::polymer`] in WGSL compute shaders
//! (wgpu: Vulkan, Metal or DX12, the driver loaded at run time, so the binary runs where no GPU
//! exists and falls back to the CPU).
//!
//! - **Replicas in one system**: the replicas of an ensemble are stepped together as one batch
//!   of independent chains (no interactions between replicas), so 64 chains of 10,000 beads
//!   fill the GPU as one 640,000-bead system would.
//! - **A step** is two dispatches: `bin` puts every bead into the slots of its cell (a periodic
//!   grid in a periodic box, a grid over the confining sphere, hashed cells in free space),
//!   `advance` has every bead sum its own
//!   forces (chain and extra bonds, angles, wall, and pair forces over the 27 neighbour cells)
//!   and move by Euler-Maruyama with counter-based noise ([`crate::sim::noise`], the same
//!   Threefry words as the CPU). Up to 512 steps are recorded per submission.
//! - **Determinism**: each bead's pair forces are summed in fixed point (1/4096 kT/b; one pair's
//!   force capped at 1,000 kT/b per axis, reached only by deeply overlapping WCA beads), so the
//!   sum does not depend on the order beads land in their cells: the same seed gives the same
//!   map on the same GPU and driver. CPU and GPU agree statistically, not bitwise (single
//!   precision, another noise stream).
//! - **Contacts**: at sample times the positions are read back and counted on the CPU with the
//!   CPU backend's own cell lists ([`crate::sim::ensemble`]), so both backends define a contact
//!   the same way. Loop-extrusion legs are advanced on the CPU and uploaded as extra bonds
//!   every `steps_per_move` steps.
//! - **Set-up**: initial conformations come from the CPU ([`Polymer::new`], including the soft
//!   push-off of overlaps under WCA).

mod context;
mod system;

pub use context::Gpu;

use rayon::prelude::*;

use super::ensemble::{
    Ensemble, EnsembleParams, POLYMER_STREAM, Sampler, assemble, replica_extrusion,
};
use super::noise::noise_key;
use super::polymer::Polymer;
use crate::error::Result;
use crate::random::stream_rng;
use system::GpuSystem;

/// Stream tag of the GPU's noise keys.
pub const GPU_NOISE_STREAM: u64 = 0x4750_554e; // "GPUN"

/// Beads of one GPU batch at most (the replicas of a larger ensemble run in several batches).
const MAX_BATCH_BEADS: usize = 1 << 24;

/// Where to run an ensemble, as asked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Device {
    /// The GPU when a hardware one is usable, else the CPU.
    Auto,
    /// Every CPU core (rayon's pool).
    Cpu,
    /// The GPU, software drivers (lavapipe) included; an error when there is none.
    Gpu,
}

/// The backend chosen for a [`Device`]: the CPU, or an opened GPU.
pub enum Backend {
    /// [`run_ensemble`](super::ensemble::run_ensemble) on rayon's current pool.
    Cpu,
    /// [`run_ensemble_gpu`] on this GPU.
    Gpu(Box<Gpu>),
}

impl Backend {
    /// Open the backend for `device`: [`Device::Gpu`] without a usable GPU is an
    /// [`Error::Parameter`](crate::Error::Parameter) named `device`.
    ///
    /// ```
    /// use contactmap::sim::gpu::{Backend, Device};
    /// let backend = Backend::open(Device::Cpu)?;
    /// assert!(backend.description().starts_with("on the CPU"));
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn open(device: Device) -> Result<Backend> {
        Ok(match device {
            Device::Cpu => Backend::Cpu,
            Device::Gpu => Backend::Gpu(Box::new(Gpu::open(true).map_err(|reason| {
                crate::error::Error::parameter("device", "gpu", format!("no usable GPU: {reason}"))
            })?)),
            Device::Auto => {
                Gpu::open(false).map_or(Backend::Cpu, |gpu| Backend::Gpu(Box::new(gpu)))
            }
        })
    }

    /// Where the ensemble runs, for the user: `on the GPU: ...` or `on the CPU (N threads)` (the
    /// threads of the current rayon pool).
    pub fn description(&self) -> String {
        match self {
            Backend::Cpu => format!("on the CPU ({} threads)", rayon::current_num_threads()),
            Backend::Gpu(gpu) => format!("on the GPU: {}", gpu.description()),
        }
    }

    /// Run the ensemble `params` here; `progress(replica)` is called as replicas finish.
    pub fn run(
        &self,
        params: &EnsembleParams,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<Ensemble> {
        match self {
            Backend::Cpu => super::ensemble::run_ensemble(params, progress),
            Backend::Gpu(gpu) => run_ensemble_gpu(params, gpu, progress),
        }
    }
}

/// Run the ensemble on `gpu`: the replicas in batches of independent chains; `progress(replica)`
/// is called when a replica finishes. Same result as [`super::ensemble::run_ensemble`] in
/// distribution.
pub fn run_ensemble_gpu(
    params: &EnsembleParams,
    gpu: &Gpu,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Ensemble> {
    params.check()?;
    let (bead_bin, bins_per_chain) = params.bins();
    let n_bins: u64 = bins_per_chain.iter().sum::<usize>() as u64;
    let n = params.polymer.n_beads();
    let per_batch = (MAX_BATCH_BEADS / n).clamp(1, params.replicas);
    let mut replicas = Vec::with_capacity(params.replicas);
    let mut first = 0;
    while first < params.replicas {
        let batch: Vec<usize> = (first..(first + per_batch).min(params.replicas)).collect();
        replicas.extend(run_batch(params, gpu, &batch, &bead_bin, n_bins)?);
        for &replica in &batch {
            progress(replica);
        }
        first += per_batch;
    }
    Ok(assemble(params, bins_per_chain, replicas))
}

/// Run the replicas `batch` together.
fn run_batch(
    params: &EnsembleParams,
    gpu: &Gpu,
    batch: &[usize],
    bead_bin: &[u32],
    n_bins: u64,
) -> Result<Vec<super::ensemble::Replica>> {
    let n = params.polymer.n_beads();
    let starts: Vec<Polymer> = batch
        .par_iter()
        .map(|&replica| {
            Polymer::new(
                params.polymer.clone(),
                stream_rng(params.seed, POLYMER_STREAM, replica as u64),
            )
        })
        .collect::<Result<_>>()?;
    let keys: Vec<[u32; 2]> = batch
        .iter()
        .map(|&replica| {
            noise_key(&mut stream_rng(
                params.seed,
                GPU_NOISE_STREAM,
                replica as u64,
            ))
        })
        .collect();
    let mut extrusions = batch
        .iter()
        .map(|&replica| replica_extrusion(params, replica))
        .collect::<Result<Vec<_>>>()?;
    let (extra_bond, max_bonds) = match &params.extrusion {
        Some(coupling) => (
            (coupling.bond_length, coupling.bond_wiggle),
            extrusions
                .iter()
                .flatten()
                .map(|(_, extruder, _)| extruder.n_lefs())
                .max()
                .unwrap_or(0),
        ),
        None => ((1.0, 0.1), 0),
    };
    let mut system = GpuSystem::new(gpu, &params.polymer, &keys, extra_bond, max_bonds, 8)?;
    let positions: Vec<[f64; 3]> = starts
        .iter()
        .flat_map(|polymer| polymer.positions().iter().copied())
        .collect();
    system.set_positions(&positions, 0);
    let space = starts[0].space();
    let mut samplers: Vec<Sampler> = batch
        .iter()
        .map(|_| Sampler::new(params, bead_bin, n_bins))
        .collect();
    let total = params.equilibration_steps + params.samples * params.sample_every;
    let mut next_sample = params.equilibration_steps + params.sample_every;
    let mut step = 0usize;
    while step < total {
        let mut next = next_sample.min(total);
        if let Some(coupling) = &params.extrusion {
            if step.is_multiple_of(coupling.steps_per_move) {
                let mut bonds = Vec::new();
                for (k, extrusion) in extrusions.iter_mut().enumerate() {
                    let (_, extruder, rng) = extrusion.as_mut().expect("extrusion is on");
                    if step > 0 {
                        extruder.step(rng);
                    }
                    let offset = (k * n) as u32;
                    bonds.extend(
                        extruder
                            .legs()
                            .iter()
                            .map(|&(i, j)| (i as u32 + offset, j as u32 + offset)),
                    );
                }
                system.set_extra_bonds(&bonds);
            }
            next = next.min((step / coupling.steps_per_move + 1) * coupling.steps_per_move);
        }
        system.run(next - step)?;
        step = next;
        if step == next_sample {
            let positions = system.positions()?;
            samplers
                .par_iter_mut()
                .zip(positions.par_chunks(n))
                .zip(extrusions.par_iter())
                .for_each(|((sampler, positions), extrusion)| {
                    let extruder = extrusion.as_ref().map(|(_, extruder, _)| extruder);
                    sampler.sample(positions, space, extruder)
                });
            next_sample += params.sample_every;
        }
    }
    Ok(samplers.into_iter().map(Sampler::finish).collect())
}

#[cfg(test)]
mod tests;
