//! Criterion bench of the polymer simulator: a 10,000-bead chain with excluded volume
//! (polychrom's polynomial repulsion, 3 kT, radius 1.05; harmonic bonds, wiggle 0.1) at density
//! 0.2 in a periodic box (the system of `../shared/tools/openmm_baseline.py`) and in a sphere;
//! 100 Brownian steps per iteration, in a rayon pool of one thread (one chain would otherwise use
//! every core; `examples/polymer_scaling.rs` measures that). Throughput is in monomer-steps.
//!
//! Run: `cargo bench -p contactmap-benches --bench polymer` (goal: 5 million monomer-steps per second per core).

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};

use contactmap::geometry::cells::CellList;
use contactmap::random::stream_rng;
use contactmap::sim::polymer::{Confinement, Polymer, PolymerParams, box_side, sphere_radius};

const N: usize = 10_000;
const STEPS: usize = 100;

fn bench(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut group = c.benchmark_group("polymer");
    group.sample_size(10);
    group.throughput(Throughput::Elements((N * STEPS) as u64));
    for (name, confinement) in [
        (
            "periodic_density_0.2",
            Confinement::Periodic {
                side: box_side(N, 0.2),
            },
        ),
        (
            "sphere_density_0.2",
            Confinement::Sphere {
                radius: sphere_radius(N, 0.2),
                stiffness: 5.0,
            },
        ),
    ] {
        let params = PolymerParams {
            chains: vec![N],
            confinement,
            ..PolymerParams::default()
        };
        let mut polymer = Polymer::new(params, stream_rng(1, 0, 0)).unwrap();
        pool.install(|| polymer.run(200));
        group.bench_function(name, |b| b.iter(|| pool.install(|| polymer.run(STEPS))));
        // The pair search alone, on the same conformation.
        let positions = polymer.positions().to_vec();
        let space = polymer.space();
        let mut cells = CellList::new();
        group.bench_function(format!("{name}_cell_list_only"), |b| {
            b.iter(|| {
                pool.install(|| {
                    let mut count = 0usize;
                    for _ in 0..STEPS {
                        cells.build(&positions, 1.05, space);
                        cells.for_each_pair(|_, _, _, r2| count += (r2 > 0.5) as usize);
                    }
                    count
                })
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
