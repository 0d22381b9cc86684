//! Criterion benches of cis / trans expected on a synthetic in-memory matrix (deterministic: a
//! power-law decay with a fixed linear congruential noise, a few masked bins, 4 chromosomes x
//! 5,000 bins, diagonals up to 300, sparse trans; about 6 M pixels).
//!
//! Run: `cargo bench -p contactmap-benches --bench expected`. The end-to-end timing on the 25 M pixel file against
//! cooltools is in docs/performance.md.

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};

use contactmap::expected::{CisParams, expected_cis, expected_trans};

use contactmap::genome::View;
use contactmap::matrix::PixelSource;

use contactmap_benches as common;

fn bench_expected(c: &mut Criterion) {
    let (pixels, weights) = common::six_million_pixels();
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
