//! Criterion benches of matrix balancing on a synthetic matrix held in memory (deterministic: a
//! power-law decay with a fixed linear congruential noise and sparse trans contacts, 4 chromosomes
//! x 2,500 bins, ~1.6 M pixels).
//!
//! Run: `cargo bench --bench balance`. End to end against `cooler balance -p 2`, time
//! `contactmap balance FILE -o weights.tsv` on a large cooler.

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

use contactmap::balance::{balance, BalanceParams, Method, Scope};
use contactmap::genome::{BinTable, Chrom};
use contactmap::matrix::{CountType, PixelBlock, Pixels};

const N_CHROMS: usize = 4;
const BINS_PER_CHROM: u64 = 2_500;
const MAX_DIAGONAL: u64 = 150;

fn synthetic() -> Pixels {
    let chroms = (0..N_CHROMS)
        .map(|c| Chrom::new(format!("chr{}", c + 1), BINS_PER_CHROM * 10_000))
        .collect();
    let bins = BinTable::fixed(chroms, 10_000).expect("valid bins");
    let n = bins.n_bins() as u64;
    let mut state = 12345u64;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) as f64 / (1u64 << 31) as f64
    };
    let mut block = PixelBlock::default();
    for i in 0..n {
        let chrom_end = (i / BINS_PER_CHROM + 1) * BINS_PER_CHROM;
        // Every 97th bin is dead (no contacts), as unmappable regions are.
        let dead = |b: u64| b % 97 == 13;
        for j in i..(i + MAX_DIAGONAL).min(chrom_end) {
            let count = (1000.0 * ((j - i + 1) as f64).powf(-1.08) * (0.5 + next())).floor();
            if count > 0.0 && !dead(i) && !dead(j) {
                block.push(i, j, count);
            }
        }
        // A few trans contacts per row, to later chromosomes (sorted: one per third of the span).
        if chrom_end < n {
            let step = ((n - chrom_end) / 3).max(1);
            for k in 0..3 {
                let j = chrom_end + k * step + (i * 7919) % step;
                if j < n && !dead(i) && !dead(j) {
                    block.push(i, j, 1.0 + (next() * 3.0).floor());
                }
            }
        }
    }
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
