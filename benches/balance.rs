//! Criterion benches of matrix balancing on a synthetic matrix held in memory (deterministic: a
//! power-law decay with a fixed linear congruential noise and sparse trans contacts, 4 chromosomes
//! x 2,500 bins, ~1.6 M pixels).
//!
//! Run: `cargo bench -p contactmap-benches --bench balance`. End to end against `cooler balance -p 2`, time
//! `contactmap balance FILE -o weights.tsv` on a large cooler.

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};

use contactmap::balance::{BalanceParams, Method, Scope, balance};
use contactmap::matrix::{CountType, Pixels};

use contactmap_benches as common;

/// 4 chromosomes x 2,500 bins, diagonals up to 150, every 97th bin dead, 3 trans pixels a row.
fn synthetic() -> Pixels {
    let (bins, block) = common::Synthetic {
        n_chroms: 4,
        bins_per_chrom: 2_500,
        max_diagonal: 150,
        dead_every: Some(97),
        trans_per_row: 3,
    }
    .build();
    let mut pixels = Pixels::with_capacity(bins, CountType::Integer, block.len()).expect("bins");
    pixels.extend(&block).expect("sorted pixels");
    pixels
}

fn bench_balance(c: &mut Criterion) {
    let pixels = synthetic();
    let mut group = c.benchmark_group("balance");
    group.throughput(Throughput::Elements(pixels.len() as u64));
    group.sample_size(10);
    // ICE iterations to the limit (this matrix converges slowly, like real 10 kb maps); KR and VC
    // to convergence.
    for (label, params) in [
        ("ice_genome_wide", BalanceParams::default()),
        (
            "ice_cis",
            BalanceParams {
                scope: Scope::Cis,
                ..BalanceParams::default()
            },
        ),
        ("vc", BalanceParams::juicer(Method::Vc)),
        ("kr", BalanceParams::juicer(Method::Kr)),
    ] {
        group.bench_function(label, |b| {
            b.iter(|| balance(&pixels, &params).expect("balance"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_balance);
criterion_main!(benches);
