//! Equilibrium radius of gyration of a free bead-spring chain by Monte Carlo
//! ([`contactmap::sim::reference::ChainSampler`]), for choosing and checking the excluded volume
//! of `contactmap simulate polymer`.
//!
//! usage: cargo run --release --example saw_reference -- ENERGY RADIUS SWEEPS N... [--wiggle W]
//!
//! Harmonic bonds of wiggle 0.3 (as scripts/sim_physics.py; `--wiggle 0.1` for the default of
//! `simulate polymer`), polychrom's polynomial repulsion of
//! height ENERGY (kT) and range RADIUS between beads two or more apart. For each N: `<Rg²>` with
//! its standard error over 16 independent chains of SWEEPS sweeps (after SWEEPS / 5 of burn-in),
//! the local exponent `ν = ln(Rg²(N) / Rg²(N')) / (2 ln(N / N'))` from the previous N, and (for
//! N ≥ 96) the log-log slope of the interior contact probability P(s) over s = 10..40, for pairs
//! at least N/4 beads from the chain ends in contact below a distance of 1.5 (as
//! scripts/sim_physics.py measures it on the dynamics).

use contactmap::random::SeededRng;
use contactmap::sim::analysis::{contact_probability, loglog_slope};
use contactmap::sim::polymer::{BondModel, Repulsion, radius_of_gyration};
use contactmap::sim::reference::ChainSampler;
use rand::SeedableRng;
use rayon::prelude::*;

const CHAINS: u64 = 16;

const CONTACT_RADIUS: f64 = 1.5;
const MAX_S: usize = 40;

/// `<Rg²>` of one chain and its interior contact probability `P(s)`, `s = 0..=MAX_S` (pairs at
/// least N/4 beads from the ends; empty when the interior is not longer than `MAX_S`).
fn sample(
    n: usize,
    repulsion: Repulsion,
    wiggle: f64,
    sweeps: usize,
    seed: u64,
) -> (f64, Vec<f64>) {
    let bond = BondModel::Harmonic {
        length: 1.0,
        wiggle,
    };
    let rng = SeededRng::seed_from_u64(seed);
    let mut sampler = ChainSampler::new(n, bond, repulsion, 1, rng).expect("at least 3 beads");
    for _ in 0..sweeps / 5 {
        sampler.sweep();
    }
    let interior = n / 4..n - n / 4;
    let with_interior = interior.len() > MAX_S;
    let mut rg2 = 0.0;
    let mut probability = vec![0.0; if with_interior { MAX_S + 1 } else { 0 }];
    for _ in 0..sweeps {
        sampler.sweep();
        let x = sampler.positions();
        rg2 += radius_of_gyration(x).powi(2) / sweeps as f64;
        if with_interior {
            let part = [x[interior.clone()].to_vec()];
            let p = contact_probability(&part, &[interior.len()], CONTACT_RADIUS, MAX_S);
            for (total, value) in probability.iter_mut().zip(p) {
                *total += value / sweeps as f64;
            }
        }
    }
    (rg2, probability)
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut wiggle = 0.3;
    if let Some(at) = args.iter().position(|a| a == "--wiggle") {
        wiggle = args
            .get(at + 1)
            .and_then(|w| w.parse().ok())
            .filter(|w: &f64| *w > 0.0)
            .unwrap_or_else(|| {
                eprintln!("--wiggle takes a positive number");
                std::process::exit(2)
            });
        args.drain(at..at + 2);
    }
    let numbers: Option<Vec<f64>> = args.iter().map(|a| a.parse().ok()).collect();
    let Some(numbers) = numbers.filter(|v| v.len() >= 4) else {
        eprintln!("usage: saw_reference ENERGY RADIUS SWEEPS N... [--wiggle W]");
        std::process::exit(2);
    };
    let repulsion = Repulsion::Polynomial {
        energy: numbers[0],
        radius: numbers[1],
    };
    let sweeps = numbers[2] as usize;
    println!("N\tRg2\tstandard_error\tlocal_nu\tlocal_nu_error\tinterior_ps_slope");
    let mut previous: Option<(f64, f64, f64)> = None;
    for &n in &numbers[3..] {
        let n_beads = n as usize;
        let samples: Vec<(f64, Vec<f64>)> = (0..CHAINS)
            .into_par_iter()
            .map(|chain| sample(n_beads, repulsion, wiggle, sweeps, chain))
            .collect();
        let means: Vec<f64> = samples.iter().map(|s| s.0).collect();
        let slope = if samples[0].1.is_empty() {
            String::new()
        } else {
            let points: Vec<(f64, f64)> = (10..=MAX_S)
                .map(|s| (s as f64, samples.iter().map(|x| x.1[s]).sum::<f64>()))
                .collect();
            format!("{:.3}", loglog_slope(&points))
        };
        let mean = means.iter().sum::<f64>() / CHAINS as f64;
        let error = (means.iter().map(|m| (m - mean).powi(2)).sum::<f64>()
            / ((CHAINS - 1) * CHAINS) as f64)
            .sqrt();
        let (nu, nu_error) = match previous {
            Some((m, rg2, e)) => {
                let log_ratio = (n / m).ln();
                let relative = ((error / mean).powi(2) + (e / rg2).powi(2)).sqrt();
                (
                    format!("{:.4}", (mean / rg2).ln() / log_ratio / 2.0),
                    format!("{:.4}", relative / log_ratio / 2.0),
                )
            }
            None => (String::new(), String::new()),
        };
        println!("{n}\t{mean:.4}\t{error:.4}\t{nu}\t{nu_error}\t{slope}");
        previous = Some((n, mean, error));
    }
}
