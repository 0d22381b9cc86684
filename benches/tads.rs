//! Criterion benches of the TAD callers on the synthetic in-memory matrix of the expected bench
//! (4 chromosomes x 5,000 bins of 10 kb, diagonals up to 300, about 6 M pixels, every 97th bin
//! masked): insulation with three windows and directionality over all of it, TopDom and Armatus
//! on one chromosome's band.
//!
//! Run: `cargo bench -p contactmap-benches --bench tads`. The end-to-end timing on the 25 M pixel file against cooltools
//! is in docs/performance.md.

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};

use contactmap::genome::View;
use contactmap::matrix::PixelSource;
use contactmap::tads::armatus::{ArmatusParams, armatus};
use contactmap::tads::band::cis_bands;
use contactmap::tads::directionality::{DirectionalityParams, directionality};
use contactmap::tads::insulation::{InsulationParams, insulation};
use contactmap::tads::topdom::{TopDomParams, topdom};

use contactmap_benches as common;

fn bench_tads(c: &mut Criterion) {
    let (pixels, weights) = common::six_million_pixels();
    let view = View::chromosomes(pixels.bins());
    let mut group = c.benchmark_group("tads");
    group.throughput(Throughput::Elements(pixels.len() as u64));
    group.sample_size(10);
    let params = InsulationParams::new(vec![100_000, 200_000, 500_000]);
    group.bench_function("insulation_3_windows", |b| {
        b.iter(|| insulation(&pixels, Some(&weights), &view, &params).expect("insulation"))
    });
    let params = DirectionalityParams::new(500_000);
    group.bench_function("directionality", |b| {
        b.iter(|| directionality(&pixels, Some(&weights), &view, &params).expect("DI"))
    });
    let bands = cis_bands(&pixels, Some(&weights), &view, 101).expect("bands");
    group.throughput(Throughput::Elements(bands[0].n_bins as u64));
    let params = TopDomParams::default();
    group.bench_function("topdom_one_chromosome", |b| {
        b.iter(|| topdom(&bands[0], &params).expect("topdom"))
    });
    let params = ArmatusParams {
        gammas: vec![0.2, 0.5, 1.0],
        max_domain_bins: 100,
    };
    group.bench_function("armatus_one_chromosome_3_gammas", |b| {
        b.iter(|| armatus(&bands[0], &params).expect("armatus"))
    });
    group.finish();
}

criterion_group!(benches, bench_tads);
criterion_main!(benches);
