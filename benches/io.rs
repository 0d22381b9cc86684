//! Criterion benches of the cooler reader and writer on a synthetic matrix (deterministic: a
//! power-law decay with a fixed linear congruential noise, 2 chromosomes x 5,000 bins, ~1.5 M pixels).
//!
//! Run: `cargo bench --bench io`. Side-by-side timings against the peer tools on a 25 M pixel file
//! are in docs/performance.md (scripts/bench_peers.sh).

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

use contactmap::genome::{BinTable, Chrom};
use contactmap::io::cool::{write_cool, CoolReader, CoolWriteOptions};
use contactmap::io::{InMemory, MatrixReader};
use contactmap::matrix::{CountType, MatrixBuilder};

fn synthetic() -> InMemory {
    let bins = BinTable::fixed(
        vec![
            Chrom::new("chrA", 50_000_000),
            Chrom::new("chrB", 50_000_000),
        ],
        10_000,
    )
    .expect("valid bins");
    let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
    let mut state = 12345u64;
    for chrom in 0..2 {
        let range = bins.chrom_bins(chrom);
        for i in range.clone() {
            for d in 0..150.min(range.end - i) {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let noise = 0.5 + (state >> 33) as f64 / (1u64 << 31) as f64;
                let count = (1000.0 * ((d + 1) as f64).powf(-1.08) * noise).floor();
                if count > 0.0 {
                    builder
                        .push(i as u64, (i + d) as u64, count)
                        .expect("in range");
                }
            }
        }
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
