//! Fixtures and helpers shared by the tests of the text readers and writers.

use std::fs::File;
use std::io::{Read, Write};
use std::path::PathBuf;

use flate2::Compression;
use flate2::write::GzEncoder;
use tempfile::TempDir;

use super::format::TextFormat;
use super::options::OpenOptions;
use super::read::read_matrix;
use crate::error::{Error, Result};
use crate::matrix::{ContactMatrix, CountType};

pub(crate) const BG2: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/hg19.GM12878-MboI.matrix.2000kb.bg2.gz"
);
pub(crate) const BINS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/hg19.bins.2000kb.bed.gz");
pub(crate) const PAIRS: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz"
);

/// Chromosome sizes of the small synthetic table: 10 + 5 bins of 10 bp.
pub(crate) const SMALL_SIZES: &str = "chr1\t100\nchr2\t50\n";

pub(crate) fn gunzip(path: &str) -> String {
    let mut text = String::new();
    flate2::read::MultiGzDecoder::new(File::open(path).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    text
}

pub(crate) fn write_plain(dir: &TempDir, name: &str, content: &str) -> PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, content).unwrap();
    path
}

pub(crate) fn write_gz(dir: &TempDir, name: &str, content: &str) -> PathBuf {
    let path = dir.path().join(name);
    let mut encoder = GzEncoder::new(File::create(&path).unwrap(), Compression::fast());
    encoder.write_all(content.as_bytes()).unwrap();
    encoder.finish().unwrap();
    path
}

pub(crate) fn bins_options() -> OpenOptions {
    OpenOptions {
        bins_bed: Some(BINS.into()),
        ..OpenOptions::default()
    }
}

/// Options for the small table, with the chromosome sizes written into `dir`.
pub(crate) fn small_options(dir: &TempDir, format: TextFormat) -> OpenOptions {
    OpenOptions {
        text_format: Some(format),
        chrom_sizes: Some(write_plain(dir, "small.sizes", SMALL_SIZES)),
        text_resolution: Some(10),
        ..OpenOptions::default()
    }
}

pub(crate) fn read_str(
    dir: &TempDir,
    content: &str,
    options: &OpenOptions,
) -> Result<ContactMatrix> {
    let path = write_plain(dir, "input.txt", content);
    read_matrix(path.to_str().unwrap(), options)
}

pub(crate) fn parse_error<T: std::fmt::Debug>(result: Result<T>) -> (u64, String) {
    match result {
        Err(Error::Parse { line, message, .. }) => (line, message),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

pub(crate) fn argument_message<T: std::fmt::Debug>(result: Result<T>) -> String {
    match result {
        Err(Error::Argument(message)) => message,
        other => panic!("expected an Argument error, got {other:?}"),
    }
}

pub(crate) fn fixture_matrix() -> ContactMatrix {
    read_matrix(BG2, &bins_options()).unwrap()
}

// Reference figures for the fixtures, computed with cooler 0.11.0 (/work/venv):
//   awk '{print $1 "\t" $3}' of the last bin of each chromosome of hg19.bins.2000kb.bed.gz
//     > hg19.chrom.sizes
//   cooler cload pairs -c1 1 -p1 2 -c2 4 -p2 5 hg19.chrom.sizes:2000000 \
//     hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz out.cool
//   cooler info out.cool            -> nbins 1561, nnz 38156, sum 100000
//   cooler dump --join out.cool     -> byte-identical to the decompressed BG2 fixture
//   cooler dump -t pixels out.cool  -> identical to `cooler dump` of the .cool fixture;
//                                      pixels (0,0)=25, (0,1)=2, (0,1560)=3, (60,1482)=2,
//                                      (866,866)=82, (1235,1235)=149
//   zcat hg19.GM12878-MboI.matrix.2000kb.bg2.gz | awk '{s+=$7} END {print NR, s}'
//                                   -> 38156 100000
pub(crate) const FIXTURE_PIXELS: [(usize, usize, f64); 6] = [
    (0, 0, 25.0),
    (0, 1, 2.0),
    (0, 1560, 3.0),
    (60, 1482, 2.0),
    (866, 866, 82.0),
    (1235, 1235, 149.0),
];

pub(crate) fn assert_fixture_figures(matrix: &ContactMatrix) {
    assert_eq!(matrix.bins().n_bins(), 1561);
    assert_eq!(matrix.bins().resolution(), Some(2_000_000));
    assert_eq!(matrix.nnz(), 38156);
    assert_eq!(matrix.sum(), 100000.0);
    assert_eq!(matrix.count_type(), CountType::Integer);
    for (i, j, count) in FIXTURE_PIXELS {
        assert_eq!(matrix.get(i, j), count, "pixel ({i}, {j})");
    }
}
