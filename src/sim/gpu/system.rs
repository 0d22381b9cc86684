//! A batch of independent polymers (replicas) on the GPU: buffers, pipelines and the recording
//! of many Brownian steps per submission.
//!
//! Positions are single precision (`vec4<f32>`, ping-ponged between two buffers). The cell list
//! is rebuilt every step with a fixed number of slots per cell; a step whose cell overflows is
//! detected after its batch, and the batch is re-run from a saved copy of the positions with
//! more slots (the noise is counter-based and the pair forces are summed in fixed point, so the
//! re-run gives exactly what the batch would have given).

use std::num::NonZeroU64;

use super::context::{Gpu, block_on};
use crate::error::{Error, Result};
use crate::sim::polymer::{BondModel, Confinement, PolymerParams, Repulsion};

/// Steps recorded in one submission at most.
pub(crate) const MAX_BATCH: usize = 512;
/// Invocations per workgroup (`WORKGROUP` of the shader).
const WORKGROUP: u32 = 128;
/// Bytes of one bead's position (`vec4<f32>`).
const POSITION_BYTES: u64 = 16;

const SHADER: &str = concat!(
    include_str!("shaders/noise.wgsl"),
    "\n",
    include_str!("shaders/step.wgsl")
);

fn gpu_error(what: &str, err: impl std::fmt::Display) -> Error {
    Error::Invalid(format!("GPU: {what}: {err}"))
}

/// How the space is cut into cells.
#[derive(Clone, Copy, Debug)]
struct Grid {
    /// 0: hashed cells (free space); 1: a periodic cube; 2: a bounded cube (sphere).
    mode: u32,
    /// Cells per side of the cube.
    per_side: u32,
    /// Lowest corner of the bounded cube.
    origin: f64,
    /// Side of a cell.
    cell: f64,
    /// Cells (periodic: per replica) or buckets (hashed: in all).
    buckets: u64,
    dedupe: bool,
}

impl Grid {
    fn new(params: &PolymerParams, n_total: usize, replicas: usize, range: f64) -> Grid {
        match params.confinement {
            Confinement::Periodic { side } => {
                let per_side = ((side / range).floor() as u32).max(1);
                Grid {
                    mode: 1,
                    per_side,
                    origin: 0.0,
                    cell: side / per_side as f64,
                    buckets: (per_side as u64).pow(3) * replicas as u64,
                    dedupe: per_side < 3,
                }
            }
            Confinement::Sphere { radius, .. } => {
                // The cube holding the sphere and a margin (beads pushed past the wall a little
                // land in the edge cells).
                let half = radius + range + 1.0;
                // Cells at least `range` wide: pairs in range are in neighbouring cells.
                let per_side = ((2.0 * half / range).floor() as u32).max(1);
                Grid {
                    mode: 2,
                    per_side,
                    origin: -half,
                    cell: 2.0 * half / per_side as f64,
                    buckets: (per_side as u64).pow(3) * replicas as u64,
                    dedupe: false,
                }
            }
            Confinement::None => Grid {
                mode: 0,
                per_side: 0,
                origin: 0.0,
                cell: range,
                buckets: (2 * n_total as u64).next_power_of_two().max(64),
                dedupe: true,
            },
        }
    }
}

/// A batch of replicas of one polymer model on the GPU.
pub(crate) struct GpuSystem<'g> {
    gpu: &'g Gpu,
    words: Vec<u32>,
    n_total: usize,
    grid: Grid,
    slots: u32,
    params: wgpu::Buffer,
    clock: wgpu::Buffer,
    tick: wgpu::Buffer,
    tick_stride: u64,
    positions: [wgpu::Buffer; 2],
    saved: wgpu::Buffer,
    info: wgpu::Buffer,
    keys: wgpu::Buffer,
    extra: wgpu::Buffer,
    extra_capacity: usize,
    /// Cell counts, alternating between steps (each with its overflow word at the end).
    counts: [wgpu::Buffer; 2],
    cell_slots: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    bind_groups: Vec<wgpu::BindGroup>,
    bin: wgpu::ComputePipeline,
    advance: wgpu::ComputePipeline,
    /// Checks the shader's noise against the CPU's (tests).
    #[cfg_attr(not(test), allow(dead_code))]
    noise_words: wgpu::ComputePipeline,
    /// Which of `positions` holds the current positions.
    current: usize,
    /// Steps taken (the noise counter).
    step: u64,
}

/// The model's parameters as the shader's `Params` words.
fn param_words(
    params: &PolymerParams,
    n_total: usize,
    n_per_replica: usize,
    grid: &Grid,
    slots: u32,
    extra_bond: (f64, f64),
) -> Vec<u32> {
    let f = |x: f64| (x as f32).to_bits();
    let range = params.interaction_range();
    let (repulsion, rep_energy, rep_radius) = match params.repulsion {
        Repulsion::None => (0, 0.0, 0.0),
        Repulsion::Polynomial { energy, radius } => (1, energy, radius),
        Repulsion::Wca { epsilon, sigma } => (2, epsilon, sigma),
    };
    let (attraction, att_energy, att_radius) = match &params.attraction {
        Some(a) => (1, a.energy, a.radius),
        None => (0, 0.0, 0.0),
    };
    let (bond, bond_a, bond_b) = match params.bond {
        BondModel::Harmonic { length, wiggle } => (0, length, wiggle),
        BondModel::Fene {
            stiffness,
            max_length,
        } => (1, stiffness, max_length),
    };
    let (sphere, sphere_radius, sphere_k) = match params.confinement {
        Confinement::Sphere { radius, stiffness } => (1, radius, stiffness),
        _ => (0, 0.0, 0.0),
    };
    let side = match params.confinement {
        Confinement::Periodic { side } => side,
        _ => 0.0,
    };
    let table_mask = if grid.mode == 0 {
        (grid.buckets - 1) as u32
    } else {
        0
    };
    vec![
        n_total as u32,
        n_per_replica as u32,
        grid.mode,
        grid.per_side,
        table_mask,
        slots,
        grid.per_side.pow(3),
        grid.dedupe as u32,
        grid.buckets as u32,
        f(1.0 / grid.cell),
        f(side),
        f(range * range),
        f(params.dt),
        f((2.0 * params.dt).sqrt()),
        repulsion,
        f(rep_energy),
        f(rep_radius),
        attraction,
        f(att_energy),
        f(att_radius),
        bond,
        f(bond_a),
        f(bond_b),
        f(params.angle_stiffness),
        sphere,
        f(sphere_radius),
        f(sphere_k),
        f(extra_bond.0),
        f(extra_bond.1),
        params.excluded_neighbours.min(u32::MAX as usize) as u32,
        f(grid.origin),
        0,
    ]
}

/// Index of `slots` in the `Params` words.
const SLOTS_WORD: usize = 5;
/// Index of `cutoff2` (0: no pair forces) in the `Params` words.
const CUTOFF2_WORD: usize = 11;

fn bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

impl<'g> GpuSystem<'g> {
    /// One replica of the polymer `params` per noise key, the extra bonds with rest length and
    /// wiggle `extra_bond` (at most `max_extra_bonds` per replica), `slots` bead slots per cell
    /// to start with.
    pub(crate) fn new(
        gpu: &'g Gpu,
        params: &PolymerParams,
        keys: &[[u32; 2]],
        extra_bond: (f64, f64),
        max_extra_bonds: usize,
        slots: u32,
    ) -> Result<Self> {
        let replicas = keys.len();
        let n_per_replica = params.n_beads();
        let n_total = n_per_replica * replicas;
        if n_total as u64 >= u32::MAX as u64 / 2 {
            return Err(Error::Unsupported(format!(
                "{n_total} beads in one GPU batch is more than the GPU backend handles"
            )));
        }
        let range = params.interaction_range();
        let grid = Grid::new(params, n_total, replicas, range.max(1e-3));
        let device = &gpu.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage,
                mapped_at_creation: false,
            })
        };
        let words = param_words(params, n_total, n_per_replica, &grid, slots, extra_bond);
        let params_buffer = buffer(
            "params",
            words.len() as u64 * 4,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let clock = buffer(
            "clock",
            16,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let tick_stride = (gpu.limits.min_uniform_buffer_offset_alignment as u64).max(16);
        let tick = buffer(
            "tick",
            tick_stride * MAX_BATCH as u64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let position_usage = storage | wgpu::BufferUsages::COPY_SRC;
        let positions = [
            buffer(
                "positions a",
                n_total as u64 * POSITION_BYTES,
                position_usage,
            ),
            buffer(
                "positions b",
                n_total as u64 * POSITION_BYTES,
                position_usage,
            ),
        ];
        let saved = buffer("saved", n_total as u64 * POSITION_BYTES, position_usage);
        let info = buffer("info", n_total as u64 * 16, storage);
        let keys_buffer = buffer("keys", replicas as u64 * 8, storage);
        let extra_capacity = n_total + 1 + 2 * max_extra_bonds * replicas;
        let extra = buffer("extra bonds", extra_capacity as u64 * 4, storage);
        let counts = [0, 1].map(|_| {
            buffer(
                "cell counts",
                (grid.buckets + 1) * 4,
                storage | wgpu::BufferUsages::COPY_SRC,
            )
        });
        let cell_slots = buffer(
            "cell slots",
            grid.buckets * slots as u64 * 4,
            wgpu::BufferUsages::STORAGE,
        );
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("polymer step"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let entry =
            |binding: u32, ty: wgpu::BufferBindingType, dynamic: bool| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty,
                    has_dynamic_offset: dynamic,
                    min_binding_size: None,
                },
                count: None,
            };
        let read = wgpu::BufferBindingType::Storage { read_only: true };
        let write = wgpu::BufferBindingType::Storage { read_only: false };
        let uniform = wgpu::BufferBindingType::Uniform;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("polymer step"),
            entries: &[
                entry(0, uniform, false),
                entry(1, uniform, false),
                entry(2, uniform, true),
                entry(3, read, false),
                entry(4, write, false),
                entry(5, write, false),
                entry(6, read, false),
                entry(7, read, false),
                entry(8, write, false),
                entry(9, write, false),
                entry(10, write, false),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("polymer step"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = |entry_point: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry_point),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry_point),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            })
        };
        let (bin, advance, noise_words) = (
            pipeline("bin"),
            pipeline("advance"),
            pipeline("noise_words"),
        );
        let mut system = GpuSystem {
            gpu,
            words,
            n_total,
            grid,
            slots,
            bind_groups: Vec::new(),
            params: params_buffer,
            clock,
            tick,
            tick_stride,
            positions,
            saved,
            info,
            keys: keys_buffer,
            extra,
            extra_capacity,
            counts,
            cell_slots,
            layout,
            bin,
            advance,
            noise_words,
            current: 0,
            step: 0,
        };
        if let Some(err) = block_on(validation.pop()) {
            return Err(gpu_error("setting up the simulation", err));
        }
        if let Some(err) = block_on(scope.pop()) {
            return Err(gpu_error(
                &format!("out of GPU memory for {n_total} beads"),
                err,
            ));
        }
        system.rebuild_bind_groups();
        system.upload_static(params, keys);
        Ok(system)
    }

    /// The bind groups of the two step parities: positions `from` -> `1 - from`, counting
    /// into counts `from` and zeroing counts `1 - from`.
    fn rebuild_bind_groups(&mut self) {
        fn whole(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry {
                binding,
                resource: buffer.as_entire_binding(),
            }
        }
        let make = |from: usize| {
            self.gpu
                .device
                .create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("polymer step"),
                    layout: &self.layout,
                    entries: &[
                        whole(0, &self.params),
                        whole(1, &self.clock),
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                                buffer: &self.tick,
                                offset: 0,
                                size: NonZeroU64::new(16),
                            }),
                        },
                        whole(3, &self.positions[from]),
                        whole(4, &self.positions[1 - from]),
                        whole(5, &self.info),
                        whole(6, &self.keys),
                        whole(7, &self.extra),
                        whole(8, &self.counts[from]),
                        whole(9, &self.cell_slots),
                        whole(10, &self.counts[1 - from]),
                    ],
                })
        };
        self.bind_groups = vec![make(0), make(1)];
    }

    /// Bead flags and chains, noise keys, the step numbers of a batch, no extra bonds.
    fn upload_static(&mut self, params: &PolymerParams, keys: &[[u32; 2]]) {
        let queue = &self.gpu.queue;
        queue.write_buffer(&self.params, 0, &bytes(&self.words));
        let types = params.attraction.as_ref().map(|a| &a.types);
        let mut info = Vec::with_capacity(4 * self.n_total);
        let n_chains = params.chains.len() as u32;
        for replica in 0..keys.len() as u32 {
            let mut bead = 0usize;
            for (chain, &length) in params.chains.iter().enumerate() {
                for k in 0..length {
                    let mut flags = 0u32;
                    if k > 0 {
                        flags |= 1;
                    }
                    if k + 1 < length {
                        flags |= 2;
                    }
                    if let Some(types) = types {
                        flags |= (types[bead] as u32) << 8;
                    }
                    info.push(flags);
                    info.extend([replica * n_chains + chain as u32, 0, 0]);
                    bead += 1;
                }
            }
        }
        queue.write_buffer(&self.info, 0, &bytes(&info));
        let key_words: Vec<u32> = keys.iter().flatten().copied().collect();
        queue.write_buffer(&self.keys, 0, &bytes(&key_words));
        let mut ticks = vec![0u32; (self.tick_stride / 4) as usize * MAX_BATCH];
        for k in 0..MAX_BATCH {
            ticks[k * (self.tick_stride / 4) as usize] = k as u32;
        }
        queue.write_buffer(&self.tick, 0, &bytes(&ticks));
        self.set_extra_bonds(&[]);
    }

    /// Replace the extra bonds by `bonds` (bead indices in the batch, both orders allowed).
    pub(crate) fn set_extra_bonds(&mut self, bonds: &[(u32, u32)]) {
        let n = self.n_total;
        let mut degree = vec![0u32; n + 1];
        for &(i, j) in bonds {
            degree[i as usize] += 1;
            degree[j as usize] += 1;
        }
        let mut words = Vec::with_capacity(n + 1 + 2 * bonds.len());
        let mut offset = (n + 1) as u32;
        for d in &degree {
            words.push(offset);
            offset += d;
        }
        let start = words.len();
        words.resize(start + 2 * bonds.len(), 0);
        let mut fill = vec![0u32; n];
        for &(i, j) in bonds {
            for (a, b) in [(i, j), (j, i)] {
                let at = (words[a as usize] - (n + 1) as u32 + fill[a as usize]) as usize;
                words[start + at] = b;
                fill[a as usize] += 1;
            }
        }
        debug_assert!(words.len() <= self.extra_capacity);
        self.gpu.queue.write_buffer(&self.extra, 0, &bytes(&words));
    }

    /// Set the positions of every bead (replica after replica) and the step counter.
    pub(crate) fn set_positions(&mut self, positions: &[[f64; 3]], step: u64) {
        let words: Vec<u32> = positions
            .iter()
            .flat_map(|p| [p[0] as f32, p[1] as f32, p[2] as f32, 0.0].map(f32::to_bits))
            .collect();
        self.current = 0;
        self.gpu
            .queue
            .write_buffer(&self.positions[0], 0, &bytes(&words));
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        for counts in &self.counts {
            encoder.clear_buffer(counts, 0, None);
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.step = step;
    }

    fn set_clock(&self) {
        let words = [self.step as u32, (self.step >> 32) as u32, 0, 0];
        self.gpu.queue.write_buffer(&self.clock, 0, &bytes(&words));
    }

    fn dispatch(&self, pass: &mut wgpu::ComputePass<'_>) {
        let groups = (self.n_total as u32).div_ceil(WORKGROUP);
        let x = groups.min(self.gpu.limits.max_compute_workgroups_per_dimension);
        pass.dispatch_workgroups(x, groups.div_ceil(x), 1);
    }

    /// Read the largest cell occupancy recorded past the slots (0: none).
    fn overflow(&self) -> Result<u32> {
        let offset = self.grid.buckets * 4;
        Ok(self.read_words(&self.counts[0], offset, 4)?[0]
            .max(self.read_words(&self.counts[1], offset, 4)?[0]))
    }

    fn read_words(&self, buffer: &wgpu::Buffer, offset: u64, size: u64) -> Result<Vec<u32>> {
        let device = &self.gpu.device;
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("read back"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(buffer, offset, &staging, 0, size);
        self.gpu.queue.submit([encoder.finish()]);
        let (sender, receiver) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |result| {
            let _ = sender.send(result);
        });
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|err| gpu_error("waiting for the device", err))?;
        receiver
            .recv()
            .map_err(|err| gpu_error("reading back", err))?
            .map_err(|err| gpu_error("reading back", err))?;
        let words = {
            let view = staging
                .get_mapped_range(..)
                .map_err(|err| gpu_error("reading back", err))?;
            view.chunks_exact(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect()
        };
        staging.unmap();
        Ok(words)
    }

    /// Record and submit `steps` (at most [`MAX_BATCH`]) steps from the current positions.
    fn submit_batch(&mut self, steps: usize) {
        let device = &self.gpu.device;
        self.set_clock();
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(
            &self.positions[self.current],
            0,
            &self.saved,
            0,
            self.n_total as u64 * POSITION_BYTES,
        );
        let mut current = self.current;
        let pairs = self.words[CUTOFF2_WORD] != 0;
        let mut pass = encoder.begin_compute_pass(&Default::default());
        for k in 0..steps {
            pass.set_bind_group(
                0,
                &self.bind_groups[current],
                &[(k as u64 * self.tick_stride) as u32],
            );
            if pairs {
                pass.set_pipeline(&self.bin);
                self.dispatch(&mut pass);
            }
            pass.set_pipeline(&self.advance);
            self.dispatch(&mut pass);
            current = 1 - current;
        }
        drop(pass);
        self.gpu.queue.submit([encoder.finish()]);
    }

    /// Advance every replica by `steps` steps (many per submission; a batch whose cells
    /// overflowed is re-run with more slots).
    pub(crate) fn run(&mut self, mut steps: usize) -> Result<()> {
        while steps > 0 {
            let batch = steps.min(MAX_BATCH);
            loop {
                self.submit_batch(batch);
                let needed = self.overflow()?;
                if needed == 0 {
                    break;
                }
                self.grow_slots(needed)?;
            }
            if batch % 2 == 1 {
                self.current = 1 - self.current;
            }
            self.step += batch as u64;
            steps -= batch;
        }
        Ok(())
    }

    /// Restore the positions saved at the start of the batch and make room for `needed` beads
    /// per cell.
    fn grow_slots(&mut self, needed: u32) -> Result<()> {
        let slots = needed.next_power_of_two().max(2 * self.slots);
        let size = self.grid.buckets * slots as u64 * 4;
        let limit = self
            .gpu
            .limits
            .max_storage_buffer_binding_size
            .min(self.gpu.limits.max_buffer_size);
        if size > limit {
            return Err(Error::Unsupported(format!(
                "GPU: {needed} beads crowd into one cell, more than the GPU's buffers hold \
                 ({slots} slots x {} cells > {limit} bytes); lower the density",
                self.grid.buckets
            )));
        }
        let device = &self.gpu.device;
        self.cell_slots = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("cell slots"),
            size,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        self.slots = slots;
        self.words[SLOTS_WORD] = slots;
        let queue = &self.gpu.queue;
        queue.write_buffer(&self.params, 0, &bytes(&self.words));
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(
            &self.saved,
            0,
            &self.positions[self.current],
            0,
            self.n_total as u64 * POSITION_BYTES,
        );
        for counts in &self.counts {
            encoder.clear_buffer(counts, 0, None);
        }
        queue.submit([encoder.finish()]);
        self.rebuild_bind_groups();
        Ok(())
    }

    /// The current positions, replica after replica.
    pub(crate) fn positions(&self) -> Result<Vec<[f64; 3]>> {
        let words = self.read_words(
            &self.positions[self.current],
            0,
            self.n_total as u64 * POSITION_BYTES,
        )?;
        Ok(words
            .chunks_exact(4)
            .map(|w| [0, 1, 2].map(|k| f32::from_bits(w[k]) as f64))
            .collect())
    }

    /// The four noise words of every bead at the current step (for checking the shader's
    /// generator against [`crate::sim::noise`]).
    #[cfg(test)]
    pub(crate) fn noise_words(&mut self) -> Result<Vec<[u32; 4]>> {
        self.set_clock();
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_bind_group(0, &self.bind_groups[self.current], &[0]);
            pass.set_pipeline(&self.noise_words);
            self.dispatch(&mut pass);
        }
        self.gpu.queue.submit([encoder.finish()]);
        let words = self.read_words(
            &self.positions[1 - self.current],
            0,
            self.n_total as u64 * POSITION_BYTES,
        )?;
        Ok(words
            .chunks_exact(4)
            .map(|w| [w[0], w[1], w[2], w[3]])
            .collect())
    }

    /// Slots per cell now (grown on overflow).
    #[cfg(test)]
    pub(crate) fn slots(&self) -> u32 {
        self.slots
    }
}
