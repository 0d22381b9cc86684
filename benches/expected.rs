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
use contactmap::matrix::{CountType, PixelSource, Pixels};

mod common;

/// 4 chromosomes x 5,000 bins, diagonals up to 300, one trans pixel a row, weights with every
/// 97th bin masked.
fn synthetic() -> (Pixels, Vec<f64>) {
    let (bins, block) = common::Synthetic {
        n_chroms: 4,
        bins_per_chrom: 5_000,
        max_diagonal: 300,
        dead_every: None,
        trans_per_row: 1,
    }
    .build();
    let n_bins = bins.n_bins();
    let mut pixels = Pixels::with_capacity(bins, CountType::Integer, block.len()).expect("bins");
    pixels.extend(&block).expect("sorted pixels");
    let mut random = common::Lcg::new(777);
    let weights = (0..n_bins)
        .map(|i| {
            if i % 97 == 0 {
                f64::NAN
            } else {
                0.5 + random.next_unit()
            }
        })
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
