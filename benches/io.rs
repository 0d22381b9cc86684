//! Criterion benches of the cooler reader and writer on a synthetic matrix (deterministic: a
//! power-law decay with a fixed linear congruential noise, 2 chromosomes x 5,000 bins, ~1.5 M pixels).
//!
//! Run: `cargo bench -p contactmap-benches --bench io`. Side-by-side timings against the peer tools on a 25 M pixel file
//! are in docs/performance.md (scripts/bench_peers.sh).

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};

use contactmap::io::cool::{CoolReader, CoolWriteOptions, write_cool};
use contactmap::io::{InMemory, MatrixReader};
use contactmap::matrix::{CountType, MatrixBuilder};

use contactmap_benches as common;

/// 2 chromosomes x 5,000 bins, diagonals up to 150, cis only.
fn synthetic() -> InMemory {
    let (bins, block) = common::Synthetic {
        n_chroms: 2,
        bins_per_chrom: 5_000,
        max_diagonal: 150,
        dead_every: None,
        trans_per_row: 0,
    }
    .build();
    let mut builder = MatrixBuilder::new(bins, CountType::Integer);
    for k in 0..block.len() {
        builder
            .push(block.bin1[k], block.bin2[k], block.count[k])
            .expect("in range");
    }
    InMemory::new("synthetic".into(), builder.build())
}

fn bench_io(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("bench.cool");
    let matrix = synthetic();
    let (nnz, _) = matrix.totals().expect("totals");
    let mut group = c.benchmark_group("cool");
    group.throughput(Throughput::Elements(nnz));
    group.sample_size(10);
    // written once outside the timing too: a filter (`cargo test --all-targets NAME`) may skip
    // the write benchmark, and the reads need the file
    write_cool(&matrix, &path, &CoolWriteOptions::default()).expect("write");
    group.bench_function("write", |b| {
        b.iter(|| write_cool(&matrix, &path, &CoolWriteOptions::default()).expect("write"))
    });
    let reader = CoolReader::open(path.to_str().expect("utf-8 path")).expect("open");
    assert!(reader.reads_in_parallel());
    let n = reader.bins().n_bins();
    group.bench_function("read_all_pixels", |b| {
        b.iter(|| {
            let mut seen = 0usize;
            reader
                .read_pixels(0..n, 0..n, &mut |block| {
                    seen += block.len();
                    Ok(())
                })
                .expect("read");
            assert_eq!(seen as u64, nnz);
        })
    });
    group.finish();
}

criterion_group!(benches, bench_io);
criterion_main!(benches);
