//! Throughput of one polymer chain on a given number of threads: the bench's system
//! (polychrom's repulsion 3 kT / 1.05, harmonic bonds of wiggle 0.1, density 0.2) in a periodic
//! box or a sphere, stepped after 200 warm-up steps.
//!
//! Run: `cargo run --release --example polymer_scaling -- N THREADS STEPS [periodic|sphere]`;
//! prints the monomer-steps per second. The positions reached do not depend on THREADS.

use std::time::Instant;

use contactmap::random::stream_rng;
use contactmap::sim::polymer::{Confinement, Polymer, PolymerParams, box_side, sphere_radius};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if !(3..=4).contains(&args.len()) {
        return Err("usage: polymer_scaling N THREADS STEPS [periodic|sphere]".into());
    }
    let n: usize = args[0].parse()?;
    let threads: usize = args[1].parse()?;
    let steps: usize = args[2].parse()?;
    let confinement = match args.get(3).map_or("periodic", String::as_str) {
        "periodic" => Confinement::Periodic {
            side: box_side(n, 0.2),
        },
        "sphere" => Confinement::Sphere {
            radius: sphere_radius(n, 0.2),
            stiffness: 5.0,
        },
        other => return Err(format!("unknown confinement '{other}'").into()),
    };
    let params = PolymerParams {
        chains: vec![n],
        confinement,
        ..PolymerParams::default()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let mut polymer = Polymer::new(params, stream_rng(1, 0, 0))?;
    pool.install(|| {
        polymer.run(200);
        let start = Instant::now();
        polymer.run(steps);
        let seconds = start.elapsed().as_secs_f64();
        println!(
            "N {n} threads {threads} steps {steps}: {:.3} s, {:.2} M monomer-steps/s",
            seconds,
            (n * steps) as f64 / seconds / 1e6
        );
    });
    Ok(())
}
