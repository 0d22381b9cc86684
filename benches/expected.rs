//! Criterion benches of cis / trans expected on a synthetic in-memory matrix (deterministic: a
//! power-law decay with a fixed linear congruential noise, a few masked bins, 4 chromosomes x
//! 5,000 bins, diagonals up to 300, sparse trans; about 6 M pixels).
//!
//! Run: `cargo bench --bench expected`. The end-to-end timing on the 25 M pixel file against
//! cooltools is in docs/performance.md.

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

use contactmap::expected::{expected_cis, expected_trans, CisParams, View};
use contactmap::genome::{BinTable, Chrom};
use contactmap::matrix::{CountType, PixelBlock, PixelSource, Pixels};

const BINS_PER_CHROM: u64 = 5_000;
const MAX_DIAG: u64 = 300;

fn synthetic() -> (Pixels, Vec<f64>) {
    let chroms = (1..=4)
        .map(|k| Chrom::new(format!("chr{k}"), BINS_PER_CHROM * 10_000))
        .collect();
    let bins = BinTable::fixed(chroms, 10_000).expect("valid bins");
    let n_bins = bins.n_bins() as u64;
    let mut state = 12345u64;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) as f64 / (1u64 << 31) as f64
    };
    let mut block = PixelBlock::with_capacity(7_000_000);
    for i in 0..n_bins {
        let chrom_end = (i / BINS_PER_CHROM + 1) * BINS_PER_CHROM;
        for j in i..(i + MAX_DIAG).min(chrom_end) {
            let d = (j - i + 1) as f64;
            let count = (1000.0 * d.powf(-1.08) * (0.5 + next())).floor();
            if count > 0.0 {
                block.push(i, j, count);
            }
        }
        // A sparse trans pixel every 10 bins.
        if i % 10 == 0 && chrom_end < n_bins {
            block.push(i, chrom_end + (i * 7919) % (n_bins - chrom_end), 1.0);
        }
    }
    let mut pixels = Pixels::with_capacity(bins, CountType::Integer, block.len()).expect("bins");
    // Trans pixels were pushed out of order within rows: sort the block first.
    let mut order: Vec<usize> = (0..block.len()).collect();
    order.sort_unstable_by_key(|&k| (block.bin1[k], block.bin2[k]));
    let mut sorted = PixelBlock::with_capacity(block.len());
    for k in order {
        sorted.push(block.bin1[k], block.bin2[k], block.count[k]);
    }
    pixels.extend(&sorted).expect("sorted pixels");
    let weights = (0..n_bins)
        .map(|i| if i % 97 == 0 { f64::NAN } else { 0.5 + next() })
        .collect();
    (pixels, weights)
}

fn bench_expected(c: &mut Criterion) {
    let (pixels, weights) = synthetic();
    let view = View::chromosomes(pixels.bins());
    let mut group = c.benchmark_group("expected");
    group.throughput(Throughput::Elements(pixels.len() as u64));
    group.sample_size(10);
    let params = CisParams::default();
    group.bench_function("cis_raw", |b| {
        b.iter(|| expected_cis(&pixels, None, &view, &params).expect("cis"))
    });
    group.bench_function("cis_balanced", |b| {
        b.iter(|| expected_cis(&pixels, Some(&weights), &view, &params).expect("cis"))
    });
    let unsmoothed = CisParams {
        smooth: false,
        aggregate_smoothed: false,
        ..CisParams::default()
    };
    group.bench_function("cis_balanced_unsmoothed", |b| {
        b.iter(|| expected_cis(&pixels, Some(&weights), &view, &unsmoothed).expect("cis"))
    });
    group.bench_function("trans_balanced", |b| {
        b.iter(|| expected_trans(&pixels, Some(&weights), &view).expect("trans"))
    });
    group.finish();
}

criterion_group!(benches, bench_expected);
criterion_main!(benches);
