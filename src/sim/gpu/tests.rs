//! Checks of the GPU backend against the CPU model (forces, noise) and against physics.
//!
//! They run on any Vulkan / Metal / DX12 adapter, Mesa's lavapipe included (CI installs it).
//! Without one they print why they were skipped, unless `CONTACTMAP_REQUIRE_GPU` is set (as
//! `.ci/run` does after installing lavapipe), in which case a missing GPU fails them.

use std::sync::OnceLock;

use super::system::GpuSystem;
use super::*;
use crate::sim::analysis::{
    contact_probability, gaussian_contact_probability, loglog_slope, mean_square_bond_length,
};
use crate::sim::noise::{bead_normals, bead_words};
use crate::sim::polymer::{
    Attraction, BondModel, Confinement, PolymerParams, Repulsion, box_side, sphere_radius,
};

/// The GPU, or `None` (with the reason printed) when there is none and none is required.
fn test_gpu() -> Option<&'static Gpu> {
    static GPU: OnceLock<Result<Gpu, String>> = OnceLock::new();
    let gpu = GPU.get_or_init(|| {
        let gpu = Gpu::open(true);
        if let Err(reason) = &gpu {
            if std::env::var_os("CONTACTMAP_REQUIRE_GPU").is_none() {
                // Straight to the standard error stream, past the test harness's capture, once.
                use std::io::Write;
                let _ = writeln!(
                    std::io::stderr(),
                    "sim::gpu tests skipped: {reason} (set CONTACTMAP_REQUIRE_GPU to fail instead)"
                );
            }
        }
        gpu
    });
    match gpu {
        Ok(gpu) => Some(gpu),
        Err(reason) => {
            if std::env::var_os("CONTACTMAP_REQUIRE_GPU").is_some() {
                panic!("CONTACTMAP_REQUIRE_GPU is set but there is no GPU: {reason}");
            }
            None
        }
    }
}

/// A polymer's positions rounded to single precision (what the GPU holds).
fn rounded(polymer: &Polymer) -> Vec<[f64; 3]> {
    polymer
        .positions()
        .iter()
        .map(|p| p.map(|x| x as f32 as f64))
        .collect()
}

#[test]
fn the_shader_noise_is_the_cpu_noise() {
    let Some(gpu) = test_gpu() else { return };
    let params = PolymerParams {
        chains: vec![300],
        repulsion: Repulsion::None,
        ..PolymerParams::default()
    };
    let keys = [[0x1234_5678, 0x9abc_def0], [7, 0xffff_ffff]];
    let mut system = GpuSystem::new(gpu, &params, &keys, (1.0, 0.1), 0, 8).unwrap();
    let positions = vec![[0.0; 3]; 600];
    for step in [0u64, 12_345, (3u64 << 32) + 17] {
        system.set_positions(&positions, step);
        let words = system.noise_words().unwrap();
        for (bead, got) in words.iter().enumerate() {
            let (replica, local) = (bead / 300, bead % 300);
            assert_eq!(
                *got,
                bead_words(keys[replica], step, local as u32),
                "step {step} bead {bead}"
            );
        }
    }
}

/// One GPU step from the same positions and noise as the CPU's forces give: every term of the
/// model (harmonic or FENE bonds, extra bonds, angles, polynomial or WCA repulsion, same-type
/// attraction, a sphere or a periodic box).
#[test]
fn one_step_equals_the_cpu_forces_and_noise() {
    let Some(gpu) = test_gpu() else { return };
    let n = 400;
    let types: Vec<u8> = (0..2 * n).map(|i| ((i / 25) % 2) as u8).collect();
    let sphere = PolymerParams {
        chains: vec![n, n],
        angle_stiffness: 1.5,
        attraction: Some(Attraction {
            types,
            energy: 0.8,
            radius: 1.6,
        }),
        confinement: Confinement::Sphere {
            radius: sphere_radius(2 * n, 0.5),
            stiffness: 5.0,
        },
        excluded_neighbours: 2,
        ..PolymerParams::default()
    };
    let periodic = PolymerParams {
        chains: vec![2 * n],
        bond: BondModel::Fene {
            stiffness: 30.0,
            max_length: 1.5,
        },
        repulsion: Repulsion::Wca {
            epsilon: 1.0,
            sigma: 1.0,
        },
        confinement: Confinement::Periodic {
            side: box_side(2 * n, 0.4),
        },
        dt: 0.0002,
        ..PolymerParams::default()
    };
    let free = PolymerParams {
        chains: vec![2 * n],
        repulsion: Repulsion::SAW,
        ..PolymerParams::default()
    };
    for (name, params) in [("sphere", sphere), ("periodic", periodic), ("free", free)] {
        let mut cpu = Polymer::new(params.clone(), stream_rng(3, 0, 0)).unwrap();
        // Relax on the CPU so that the conformation is typical, then start both from it.
        cpu.run(300);
        let start = rounded(&cpu);
        let mut cpu =
            Polymer::from_positions(params.clone(), start.clone(), stream_rng(0, 0, 0)).unwrap();
        let bonds = [(10usize, 90usize), (200, 260), (500, 700)];
        cpu.set_extra_bonds(&bonds, 0.5, 0.2);
        cpu.compute_forces();
        let key = [99, 101];
        let step = 5_000_000_000u64;
        let mut system = GpuSystem::new(gpu, &params, &[key], (0.5, 0.2), bonds.len(), 8).unwrap();
        system.set_positions(&start, step);
        let bonds32: Vec<(u32, u32)> = bonds.iter().map(|&(i, j)| (i as u32, j as u32)).collect();
        system.set_extra_bonds(&bonds32);
        system.run(1).unwrap();
        let moved = system.positions().unwrap();
        let dt = params.dt;
        let mut worst = 0.0f64;
        for (bead, (p, f)) in start.iter().zip(cpu.forces()).enumerate() {
            let z = bead_normals(key, step, bead as u32);
            for k in 0..3 {
                let expected = p[k] + f[k] * dt + (2.0 * dt).sqrt() * z[k];
                // Single precision positions (|x| up to ~15) and forces.
                let tolerance = 2e-5 * (1.0 + p[k].abs()) + 1e-4 * dt * f[k].abs() + 1e-6;
                let error = (moved[bead][k] - expected).abs();
                worst = worst.max(error / tolerance);
                assert!(
                    error <= tolerance,
                    "{name}: bead {bead} axis {k}: GPU {} CPU {expected} (force {})",
                    moved[bead][k],
                    f[k]
                );
            }
        }
        eprintln!("{name}: worst error / tolerance {worst:.3}");
    }
}

/// Replicas in one batch do not see each other: the second replica of a batch moves exactly as
/// it does alone.
#[test]
fn replicas_in_a_batch_are_independent() {
    let Some(gpu) = test_gpu() else { return };
    for confinement in [
        Confinement::Periodic {
            side: box_side(500, 0.5),
        },
        Confinement::Sphere {
            radius: sphere_radius(500, 0.5),
            stiffness: 5.0,
        },
    ] {
        let params = PolymerParams {
            chains: vec![500],
            confinement,
            ..PolymerParams::default()
        };
        let a = Polymer::new(params.clone(), stream_rng(1, 0, 0)).unwrap();
        let b = Polymer::new(params.clone(), stream_rng(1, 0, 1)).unwrap();
        let keys = [[1, 2], [3, 4]];
        let mut both = GpuSystem::new(gpu, &params, &keys, (1.0, 0.1), 0, 8).unwrap();
        let mut start = rounded(&a);
        start.extend(rounded(&b));
        both.set_positions(&start, 0);
        both.run(200).unwrap();
        let mut alone = GpuSystem::new(gpu, &params, &keys[1..], (1.0, 0.1), 0, 8).unwrap();
        alone.set_positions(&start[500..], 0);
        alone.run(200).unwrap();
        let (both, alone) = (both.positions().unwrap(), alone.positions().unwrap());
        assert_eq!(&both[500..], &alone[..], "{confinement:?}");
        assert_ne!(&both[..500], &alone[..], "{confinement:?}");
    }
}

/// A batch whose cells overflow is re-run with more slots and gives exactly what a run with
/// enough slots from the start gives; the same seed gives the same positions.
#[test]
fn cell_overflow_reruns_and_runs_are_reproducible() {
    let Some(gpu) = test_gpu() else { return };
    let params = PolymerParams {
        chains: vec![3000],
        confinement: Confinement::Sphere {
            radius: sphere_radius(3000, 1.2),
            stiffness: 5.0,
        },
        ..PolymerParams::default()
    };
    let start = rounded(&Polymer::new(params.clone(), stream_rng(2, 0, 0)).unwrap());
    let run = |slots: u32| {
        let mut system = GpuSystem::new(gpu, &params, &[[5, 6]], (1.0, 0.1), 0, slots).unwrap();
        system.set_positions(&start, 0);
        system.run(100).unwrap();
        (system.positions().unwrap(), system.slots())
    };
    let (small, grown) = run(2);
    let (large, kept) = run(64);
    assert!(grown > 2, "the dense sphere overflowed 2 slots per cell");
    assert_eq!(kept, 64);
    assert_eq!(small, large);
    assert_eq!(run(64).0, large);
}

/// The ideal chain on the GPU against the CPU backend with the same protocol (128 replicas of
/// 32 beads, two Rouse times of relaxation from a random walk, ten samples half a Rouse time
/// apart): `<Rg²>`, the P(s) slope over s = 5..20 and its amplitude agree; both are near the
/// exact Gaussian-chain values (the residual gap is the slow relaxation from the random-walk
/// start, the same on both backends; `scripts/sim_physics.py --device gpu` measures the
/// acceptance figures with long runs).
#[test]
fn ideal_chain_statistics_match_the_cpu() {
    let Some(gpu) = test_gpu() else { return };
    let n = 32;
    let dt = 0.01;
    // Rouse time N² <b²> / (3 π²), with <b²> ~ 1.235 for wiggle 0.3, in steps.
    let rouse = (n * n) as f64 * 1.235 / (3.0 * std::f64::consts::PI.powi(2)) / dt;
    let params = EnsembleParams {
        polymer: PolymerParams {
            chains: vec![n],
            bond: BondModel::Harmonic {
                length: 1.0,
                wiggle: 0.3,
            },
            repulsion: Repulsion::None,
            dt,
            ..PolymerParams::default()
        },
        replicas: 128,
        equilibration_steps: (2.0 * rouse) as usize,
        sample_every: (0.5 * rouse) as usize,
        samples: 10,
        contact_radius: 1.5,
        monomers_per_bin: 1,
        seed: 5,
        extrusion: None,
        keep_conformations: true,
    };
    let measure = |ensemble: &Ensemble| {
        let b2 = mean_square_bond_length(&ensemble.conformations, &[n]);
        let radii = &ensemble.radii_of_gyration;
        let rg2 = radii.iter().map(|r| r[0] * r[0]).sum::<f64>() / radii.len() as f64;
        let p_s = contact_probability(&ensemble.conformations, &[n], 1.5, 20);
        let points: Vec<(f64, f64)> = (5..=20).map(|s| (s as f64, p_s[s])).collect();
        let mean_log = (5..=20).map(|s| p_s[s].ln()).sum::<f64>() / 16.0;
        (b2, rg2, loglog_slope(&points), mean_log)
    };
    let gpu_run = measure(&run_ensemble_gpu(&params, gpu, &|_| {}).unwrap());
    let cpu_run = measure(&crate::sim::ensemble::run_ensemble(&params, &|_| {}).unwrap());
    eprintln!(
        "ideal N = {n}, (<b²>, <Rg²>, P(s) slope, mean ln P): GPU {gpu_run:?}, CPU {cpu_run:?}"
    );
    let (b2, rg2, slope, mean_log) = gpu_run;
    assert!(
        (b2 / cpu_run.0 - 1.0).abs() < 0.01,
        "<b²> {b2} vs {}",
        cpu_run.0
    );
    assert!(
        (rg2 / cpu_run.1 - 1.0).abs() < 0.06,
        "<Rg²> {rg2} vs {}",
        cpu_run.1
    );
    assert!(
        (slope - cpu_run.2).abs() < 0.12,
        "slope {slope} vs {}",
        cpu_run.2
    );
    let amplitude = (mean_log - cpu_run.3).exp();
    assert!(
        (amplitude - 1.0).abs() < 0.1,
        "P(s) amplitude ratio {amplitude}"
    );
    // Near the Gaussian chain: <Rg²> = <b²>(N² - 1) / 6N, P(s) slope -1.43 over s = 5..20.
    let exact = b2 * (n * n - 1) as f64 / (6 * n) as f64;
    assert!((rg2 / exact - 1.0).abs() < 0.08, "<Rg²> {rg2} vs {exact}");
    let gaussian: Vec<(f64, f64)> = (5..=20)
        .map(|s| {
            (
                s as f64,
                gaussian_contact_probability(s as f64, 1.5, b2.sqrt()),
            )
        })
        .collect();
    let expected = loglog_slope(&gaussian);
    assert!(
        (slope - expected).abs() < 0.2,
        "slope {slope} vs {expected}"
    );
}

/// The same seed gives the same map on the GPU, and the map of a small extrusion run holds
/// what the CPU's holds in distribution: every contact within the chains, the total near the
/// CPU's.
#[test]
fn ensembles_are_reproducible_and_agree_with_the_cpu() {
    let Some(gpu) = test_gpu() else { return };
    use crate::sim::ensemble::{ExtrusionCoupling, run_ensemble};
    use crate::sim::extrusion::{BoundaryElement, ExtrusionParams, Orientation};
    let chains = vec![300, 200];
    let polymer = PolymerParams {
        chains: chains.clone(),
        confinement: Confinement::Sphere {
            radius: sphere_radius(500, 0.3),
            stiffness: 5.0,
        },
        ..PolymerParams::default()
    };
    let params = EnsembleParams {
        polymer: polymer.clone(),
        replicas: 8,
        equilibration_steps: 1000,
        sample_every: 500,
        samples: 6,
        contact_radius: 1.5,
        monomers_per_bin: 10,
        seed: 9,
        extrusion: Some(ExtrusionCoupling {
            params: ExtrusionParams {
                chains: polymer.chain_ranges(),
                processivity: 50.0,
                separation: 50.0,
                elements: vec![BoundaryElement::permanent(150, Orientation::Both)],
            },
            steps_per_move: 50,
            bond_length: 0.5,
            bond_wiggle: 0.2,
        }),
        keep_conformations: false,
    };
    // Reproducible: two runs of 600 steps (12 extrusion moves) give the same ensemble (a shorter
    // run than the comparison's below, which lavapipe's many dispatches make slow in CI).
    let short = EnsembleParams {
        equilibration_steps: 200,
        sample_every: 200,
        samples: 2,
        ..params.clone()
    };
    let again = run_ensemble_gpu(&short, gpu, &|_| {}).unwrap();
    assert_eq!(again, run_ensemble_gpu(&short, gpu, &|_| {}).unwrap());
    assert_eq!(again.radii_of_gyration.len(), 16);
    let first = run_ensemble_gpu(&params, gpu, &|_| {}).unwrap();
    let cpu = run_ensemble(&params, &|_| {}).unwrap();
    let total = |e: &Ensemble| e.pixels.iter().map(|p| p.2).sum::<u64>() as f64;
    let ratio = total(&first) / total(&cpu);
    assert!((ratio - 1.0).abs() < 0.1, "GPU / CPU contacts {ratio}");
    assert_eq!(first.bins_per_chain, cpu.bins_per_chain);
    assert_eq!(first.radii_of_gyration.len(), 48);
}
