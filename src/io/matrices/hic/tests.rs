//! Tests of the `.hic` reader: the real fixtures against hictkpy's figures, synthetic files from
//! [`super::synthetic`] against the pixels they were written from, and corrupt files.

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use super::synthetic::{synthetic, write_hic};
use super::*;
use crate::error::Result;
use crate::genome::BinTable;
use crate::io::MatrixReader;
use crate::matrix::CountType;

const TEST_FILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/hic_test_file.hic");

type Triplets = Vec<(u64, u64, f64)>;

/// Every pixel of `rows x cols`, checking the stream's order and triangle on the way.
fn dump(reader: &HicReader, rows: Range<usize>, cols: Range<usize>) -> Triplets {
    let mut out: Triplets = Vec::new();
    reader
        .read_pixels(rows, cols, &mut |block| {
            assert!(!block.is_empty());
            for k in 0..block.len() {
                out.push((block.bin1[k], block.bin2[k], block.count[k]));
            }
            Ok(())
        })
        .unwrap();
    for pair in out.windows(2) {
        assert!(
            (pair[0].0, pair[0].1) < (pair[1].0, pair[1].1),
            "not sorted: {pair:?}"
        );
    }
    assert!(out.iter().all(|p| p.0 <= p.1));
    out
}

fn filter(all: &Triplets, rows: &Range<usize>, cols: &Range<usize>) -> Triplets {
    all.iter()
        .copied()
        .filter(|p| rows.contains(&(p.0 as usize)) && cols.contains(&(p.1 as usize)))
        .collect()
}

fn test_file() -> HicReader {
    HicReader::open(Path::new(TEST_FILE), None).unwrap()
}

#[test]
fn reads_the_bin_table_and_metadata() {
    let reader = test_file();
    let bins = reader.bins();
    // hictkpy.File(path, 100000): nbins 1380, nchroms 8, chromosomes() in this order
    assert_eq!(bins.n_bins(), 1380);
    let names: Vec<&str> = bins.chroms().iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "chr2L", "chr2R", "chr3L", "chr3R", "chr4", "chrX", "chrY", "chrM"
        ]
    );
    assert_eq!(bins.chroms()[0].length_bp, 23_513_712);
    assert_eq!(
        bins.chrom_offsets(),
        &[0, 236, 489, 771, 1092, 1106, 1342, 1379, 1380]
    );
    assert_eq!(bins.resolution(), Some(100_000));
    assert_eq!(reader.resolutions(), &[100_000]);
    assert_eq!(reader.version(), 9);
    assert_eq!(reader.count_type(), CountType::Integer);
    assert_eq!(reader.weight_names(), ["ICE"]);
    let info = reader.info();
    assert_eq!(info.format, "hic (version 9)");
    assert_eq!(info.resolutions, [100_000]);
    assert!(info.notes[0].contains("divisive"));
    assert!(
        info.attributes
            .iter()
            .any(|(k, v)| k == "software" && v.as_str() == Some("Juicer Tools Version 3.30.00"))
    );
}

#[test]
fn whole_genome_totals_match_hictkpy() {
    // hictkpy.File(path, 100000).fetch(): nnz() 890384, sum() 119208613
    let reader = test_file();
    let all = dump(&reader, 0..1380, 0..1380);
    assert_eq!(all.len(), 890_384);
    assert_eq!(all.iter().map(|p| p.2).sum::<f64>(), 119_208_613.0);
    assert_eq!(reader.totals().unwrap(), (890_384, 119_208_613.0));
}

#[test]
fn chromosome_query_matches_hictkpy() {
    // hictkpy: f.fetch("chr2L"): nnz() 27733, sum() 19968156
    let reader = test_file();
    let chr2l = reader.bins().parse_region_bins("chr2L").unwrap();
    let pixels = dump(&reader, chr2l.clone(), chr2l);
    assert_eq!(pixels.len(), 27_733);
    assert_eq!(pixels.iter().map(|p| p.2).sum::<f64>(), 19_968_156.0);
}

#[test]
fn pixel_values_match_hictkpy() {
    let reader = test_file();
    let all = dump(&reader, 0..1380, 0..1380);
    let get = |i: u64, j: u64| {
        all.iter()
            .find(|p| p.0 == i && p.1 == j)
            .map_or(0.0, |p| p.2)
    };
    // f.fetch("chr2L:0-300000").to_numpy() = [[101360 29915 4996] [29915 145946 29754] ...]
    assert_eq!(get(0, 0), 101_360.0);
    assert_eq!(get(0, 1), 29_915.0);
    assert_eq!(get(0, 2), 4_996.0);
    assert_eq!(get(1, 1), 145_946.0);
    assert_eq!(get(2, 2), 115_171.0);
    // f.fetch("chr2L:0-200000", "chr3R:1000000-1200000").to_numpy() = [[11 4] [11 10]];
    // chr3R starts at bin 771
    assert_eq!(get(0, 781), 11.0);
    assert_eq!(get(0, 782), 4.0);
    assert_eq!(get(1, 781), 11.0);
    assert_eq!(get(1, 782), 10.0);
}

#[test]
fn region_queries_equal_filtering_the_full_dump() {
    let reader = test_file();
    let all = dump(&reader, 0..1380, 0..1380);
    let bins = reader.bins();
    let region = |r: &str| bins.parse_region_bins(r).unwrap();
    let queries = [
        (region("chr2L:1M-5M"), region("chr2L:1M-5M")),
        (region("chr2L:3M-4M"), region("chr3R:10M-20M")),
        (region("chr3R:10M-20M"), region("chr2L:3M-4M")),
        (region("chrX"), region("chrX:5M-6M")),
        (10..800, 300..1200),
        (1000..1380, 0..1380),
        (500..501, 0..1380),
        (1379..1380, 1379..1380),
        (700..700, 0..1380),
    ];
    for (rows, cols) in queries {
        let expected = filter(&all, &rows, &cols);
        assert_eq!(
            dump(&reader, rows.clone(), cols.clone()),
            expected,
            "{rows:?} x {cols:?}"
        );
    }
}

#[test]
fn ice_weights_match_hictkpy_and_the_mcool() {
    let reader = test_file();
    let weights = reader.weights("ICE").unwrap();
    assert_eq!(weights.values.len(), 1380);
    assert!(weights.provenance.as_deref().unwrap().contains("divisive"));
    // hictkpy f.weights("ICE")[[0, 1, 2, 500, 1000, 1370]] (divisive):
    let divisive = [
        382.85430908,
        446.75976562,
        349.08926392,
        209.37458801,
        161.76849365,
        0.93698156,
    ];
    // cooler_test_file.mcool::/resolutions/100000 bins/weight at the same bins (multiplicative):
    let mcool = [
        0.00261196, 0.00223834, 0.0028646, 0.00477613, 0.00618167, 1.06725689,
    ];
    for (k, &bin) in [0usize, 1, 2, 500, 1000, 1370].iter().enumerate() {
        let w = weights.values[bin];
        assert!((w * divisive[k] - 1.0).abs() < 1e-7, "bin {bin}: {w}");
        assert!((w / mcool[k] - 1.0).abs() < 1e-5, "bin {bin}: {w}");
    }
    // chrM (bin 1379) has no ICE vector; hictkpy gives NaN for 61 bins
    assert!(weights.values[1379].is_nan());
    assert_eq!(weights.values.iter().filter(|w| w.is_nan()).count(), 61);
    assert!(
        reader
            .weights("KR")
            .unwrap_err()
            .to_string()
            .contains("available: ICE")
    );
}

#[test]
fn resolution_choice_is_checked() {
    let error = HicReader::open(Path::new(TEST_FILE), Some(5_000)).unwrap_err();
    let message = error.to_string();
    assert!(message.contains("hic_test_file.hic"), "{message}");
    assert!(
        message.contains("5000") && message.contains("100000"),
        "{message}"
    );
    let reader = HicReader::open(Path::new(TEST_FILE), Some(100_000)).unwrap();
    assert_eq!(reader.resolution(), 100_000);
    assert_eq!(
        HicReader::list_resolutions(Path::new(TEST_FILE)).unwrap(),
        [100_000]
    );
}

/// Open, stream every pixel and read every weight vector.
fn read_everything(path: &Path) -> Result<()> {
    let reader = HicReader::open(path, None)?;
    let n = reader.bins().n_bins();
    reader.read_pixels(0..n, 0..n, &mut |_| Ok(()))?;
    reader.totals()?;
    if n < 10_000_000 {
        for name in reader.weight_names() {
            reader.weights(&name)?;
        }
    }
    Ok(())
}

#[test]
fn truncated_files_are_errors() {
    let bytes = std::fs::read(TEST_FILE).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let len = bytes.len();
    for n in [
        0,
        3,
        10,
        100,
        283,
        1000,
        343_990,
        len / 2,
        len - 5_000,
        len - 100,
        len - 1,
    ] {
        let path = dir.path().join(format!("truncated_{n}.hic"));
        std::fs::write(&path, &bytes[..n]).unwrap();
        let error = read_everything(&path).expect_err(&format!("{n} bytes"));
        let message = error.to_string();
        assert!(message.contains(&format!("truncated_{n}.hic")), "{message}");
    }
}

#[test]
fn corrupt_bytes_never_panic() {
    let bytes = std::fs::read(TEST_FILE).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("corrupt.hic");
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for _ in 0..40 {
        let mut copy = bytes.clone();
        for _ in 0..4 {
            let at = (next() % copy.len() as u64) as usize;
            copy[at] = next() as u8;
        }
        std::fs::write(&path, &copy).unwrap();
        let _ = read_everything(&path);
    }
}

fn write_temp(dir: &tempfile::TempDir, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn as_triplets(pixels: &BTreeMap<(u64, u64), f32>) -> Triplets {
    pixels
        .iter()
        .map(|(&(i, j), &v)| (i, j, f64::from(v)))
        .collect()
}

#[test]
fn synthetic_files_round_trip_at_every_resolution() {
    let dir = tempfile::tempdir().unwrap();
    for version in [8, 9] {
        let s = synthetic(version);
        let path = write_temp(&dir, &format!("v{version}.hic"), &write_hic(&s));
        let error = HicReader::open(&path, None).unwrap_err().to_string();
        assert!(error.contains("2 resolutions (10, 20)"), "{error}");
        assert_eq!(HicReader::list_resolutions(&path).unwrap(), [10, 20]);
        for (resolution, pixels, norms) in &s.levels {
            let reader = HicReader::open(&path, Some(*resolution)).unwrap();
            assert_eq!(reader.version(), version);
            assert_eq!(reader.resolutions(), &[10, 20]);
            let n = reader.bins().n_bins();
            assert_eq!(
                n,
                if *resolution == 10 {
                    37 + 23 + 5
                } else {
                    19 + 12 + 3
                }
            );
            let expected = as_triplets(pixels);
            assert!(expected.len() > 150, "{}", expected.len());
            assert_eq!(
                dump(&reader, 0..n, 0..n),
                expected,
                "v{version} at {resolution}"
            );
            // Bands of one block row: rotated blocks deep off the diagonal span many bands.
            let mut banded = HicReader::open(&path, Some(*resolution)).unwrap();
            banded.band_budget_bytes = 1;
            assert_eq!(dump(&banded, 0..n, 0..n), expected);
            let mut n_calls = 0;
            banded
                .read_pixels(0..n, 0..n, &mut |_| {
                    n_calls += 1;
                    Ok(())
                })
                .unwrap();
            assert!(n_calls >= n / 4, "{n_calls} bands");
            let sum: f64 = expected.iter().map(|p| p.2).sum();
            assert_eq!(reader.totals().unwrap(), (expected.len() as u64, sum));

            let mut names: Vec<&str> = norms.iter().map(|v| v.0).collect();
            names.dedup();
            assert_eq!(reader.weight_names(), names);
            for name in names {
                let weights = reader.weights(name).unwrap();
                let mut expected = Vec::new();
                for chrom in 0..3 {
                    let n_bins = reader.bins().chrom_bins(chrom).len();
                    match norms.iter().find(|v| v.0 == name && v.1 == chrom) {
                        Some(v) => expected.extend(v.2.iter().map(|&d| {
                            if d > 0.0 {
                                1.0 / f64::from(d as f32)
                            } else {
                                f64::NAN
                            }
                        })),
                        None => expected.extend(std::iter::repeat_n(f64::NAN, n_bins)),
                    }
                }
                assert_eq!(weights.values.len(), expected.len());
                for (w, e) in weights.values.iter().zip(&expected) {
                    let both_nan = w.is_nan() && e.is_nan();
                    assert!(both_nan || (w / e - 1.0).abs() < 1e-12, "{w} {e}");
                }
            }
        }
    }
}

/// A chromosome pair listed in the master index with no matrix at the open resolution (its
/// pixels only at another resolution) beside a pair that has one: the band planner once aligned
/// on the empty matrix's grid of zero bins and divided by zero (issue 26, in `dump` and
/// `validate` of fuzzed files).
#[test]
fn a_pair_without_a_matrix_at_the_resolution_is_read() {
    let dir = tempfile::tempdir().unwrap();
    for version in [8, 9] {
        let mut s = synthetic(version);
        let fine = BinTable::fixed(s.chroms.clone(), 10).unwrap();
        let c1 = fine.chrom_bins(0);
        let inside = |b: u64| c1.contains(&(b as usize));
        // c1 x c1 only at 20 bp; c1 x c2 at both resolutions.
        s.levels[0].1.retain(|&(i, j), _| !(inside(i) && inside(j)));
        assert!(s.levels[0].1.keys().any(|&(i, j)| inside(i) && !inside(j)));
        let path = write_temp(&dir, &format!("v{version}.hic"), &write_hic(&s));
        let reader = HicReader::open(&path, Some(10)).unwrap();
        let n = reader.bins().n_bins();
        assert_eq!(dump(&reader, 0..n, 0..n), as_triplets(&s.levels[0].1));
        let rows = c1.clone();
        assert_eq!(
            dump(&reader, rows.clone(), 0..n),
            filter(&as_triplets(&s.levels[0].1), &rows, &(0..n))
        );
    }
}

#[test]
fn synthetic_files_hold_every_block_layout() {
    // The writer's choices that the round-trip tests rely on: several blocks per matrix,
    // rotated blocks at several depths (version 9), dense and list-of-rows blocks.
    let dir = tempfile::tempdir().unwrap();
    for version in [8, 9] {
        let path = write_temp(&dir, "layout.hic", &write_hic(&synthetic(version)));
        let reader = HicReader::open(&path, Some(10)).unwrap();
        let intra = reader.matrix_index(0, 0).unwrap().unwrap();
        let inter = reader.matrix_index(0, 1).unwrap().unwrap();
        assert_eq!(intra.block_bin_count, 4);
        assert_eq!(intra.block_column_count, 10);
        for index in [&intra, &inter] {
            assert!(index.blocks.len() > 8);
            assert!(index.blocks.iter().any(|b| b.number % 4 == 1)); // dense
            assert!(index.blocks.iter().any(|b| b.number % 4 == 2)); // list of rows
        }
        let depths: std::collections::BTreeSet<u64> =
            intra.blocks.iter().map(|b| b.number / 10).collect();
        if version == 9 {
            assert_eq!(depths.into_iter().collect::<Vec<_>>(), [0, 1, 2]);
        } else {
            assert!(depths.len() >= 9); // grid rows
        }
        assert!(reader.matrix_index(0, 2).unwrap().is_some());
    }
}

#[test]
fn synthetic_region_queries_match_a_naive_filter() {
    use proptest::test_runner::{Config, TestRunner};
    let dir = tempfile::tempdir().unwrap();
    for (version, budget) in [
        (8, BAND_BUDGET_BYTES),
        (8, 1),
        (9, BAND_BUDGET_BYTES),
        (9, 1),
    ] {
        let s = synthetic(version);
        let path = write_temp(&dir, &format!("v{version}.hic"), &write_hic(&s));
        let mut reader = HicReader::open(&path, Some(10)).unwrap();
        reader.band_budget_bytes = budget; // 1: bands of one block row (4 bins)
        let all = as_triplets(&s.levels[0].1);
        let n = reader.bins().n_bins();
        let mut runner = TestRunner::new(Config::with_cases(150));
        runner
            .run(&(0..=n, 0..=n, 0..=n, 0..=n), |(a, b, c, d)| {
                let rows = a.min(b)..a.max(b);
                let cols = c.min(d)..c.max(d);
                let got = dump(&reader, rows.clone(), cols.clone());
                proptest::prop_assert_eq!(got, filter(&all, &rows, &cols));
                Ok(())
            })
            .unwrap();
    }
}

#[test]
fn other_versions_are_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = write_hic(&synthetic(8));
    bytes[4..8].copy_from_slice(&7i32.to_le_bytes());
    let path = write_temp(&dir, "v7.hic", &bytes);
    let message = HicReader::open(&path, None).unwrap_err().to_string();
    assert!(
        message.contains("version 7") && message.contains("v7.hic"),
        "{message}"
    );
    let path = write_temp(&dir, "text.hic", b"chr1\t0\t100\n");
    assert!(HicReader::open(&path, None).is_err());
}

#[test]
fn corrupt_blocks_name_the_block() {
    let dir = tempfile::tempdir().unwrap();
    let s = synthetic(9);
    let clean = write_hic(&s);
    let path = write_temp(&dir, "clean.hic", &clean);
    let reader = HicReader::open(&path, Some(10)).unwrap();
    let index = reader.matrix_index(0, 0).unwrap().unwrap();
    let entry = index.blocks[0];
    let mut bytes = clean.clone();
    for b in &mut bytes[entry.position as usize + 2..(entry.position + entry.size) as usize] {
        *b = !*b;
    }
    let path = write_temp(&dir, "corrupt.hic", &bytes);
    let reader = HicReader::open(&path, Some(10)).unwrap();
    let n = reader.bins().n_bins();
    let message = reader
        .read_pixels(0..n, 0..n, &mut |_| Ok(()))
        .unwrap_err()
        .to_string();
    assert!(
        message.contains(&format!("block {} of c1-c1", entry.number)),
        "{message}"
    );
    assert!(reader.totals().is_err());
}

/// Overwrite the field at `offset` with `value`, `width` bytes little-endian.
fn patch(bytes: &mut [u8], offset: u64, width: usize, value: i64) {
    let at = offset as usize;
    match width {
        4 => bytes[at..at + 4].copy_from_slice(&i32::try_from(value).unwrap().to_le_bytes()),
        8 => bytes[at..at + 8].copy_from_slice(&value.to_le_bytes()),
        _ => unreachable!("fields are 4 or 8 bytes"),
    }
}

#[test]
fn corrupt_sizes_and_offsets_are_named_errors() {
    use super::synthetic::write_hic_with_offsets;
    let dir = tempfile::tempdir().unwrap();
    for version in [8, 9] {
        let (clean, at) = write_hic_with_offsets(&synthetic(version));
        let long = if version >= 9 { 8 } else { 4 };
        // (field, width, bad value, what the message must say besides the value)
        let mut cases: Vec<(&str, usize, i64, &str)> = vec![
            ("n_attributes", 4, i32::MAX.into(), "header attributes"),
            ("n_chroms", 4, i32::MAX.into(), "chromosome list"),
            ("n_chroms", 4, 0, "number of chromosomes"),
            ("chrom_length", long, -5, "negative length"),
            ("n_resolutions", 4, i32::MAX.into(), "resolution list"),
            ("resolution", 4, 0, "resolution"),
            ("resolution", 4, -3, "resolution"),
            ("footer_position", 8, i64::MAX, "footer position"),
            ("footer_position", 8, -1, "footer position"),
            ("master_n_entries", 4, i32::MAX.into(), "master index"),
            ("master_position", 8, 1 << 40, "outside the file"),
            ("n_levels", 4, i32::MAX.into(), "matrix record"),
            ("block_bin_count", 4, -1, "block bin count"),
            ("block_column_count", 4, 0, "block column count"),
            ("n_blocks", 4, i32::MAX.into(), "matrix record"),
            ("block_number", 4, -7, "block -7"),
            ("block_position", 8, 1 << 40, "past the end of the file"),
            ("block_position", 8, -9, "position -9"),
            ("block_size", 4, i32::MAX.into(), "past the end of the file"),
            (
                "norm_index_n_entries",
                4,
                i32::MAX.into(),
                "normalisation vector index",
            ),
            ("norm_vector_position", 8, 1 << 40, "normalisation vector"),
            (
                "norm_vector_n_values",
                long,
                i32::MAX.into(),
                "normalisation vector",
            ),
        ];
        if version >= 9 {
            cases.push(("chrom_length", 8, 175_921_883_957_872, "chromosome 'c1'"));
        } else {
            // version 9 files point at the vector index; version 8 ones are read past these
            cases.push(("expected_n_vectors", 4, i32::MAX.into(), "expected values"));
            cases.push(("expected_n_values", 4, i32::MAX.into(), "expected values"));
            cases.push(("expected_n_factors", 4, i32::MAX.into(), "expected values"));
            cases.push(("norm_expected_n_vectors", 4, -2, "normalised expected"));
        }
        for (field, width, value, said) in cases {
            let mut bytes = clean.clone();
            patch(&mut bytes, at[field], width, value);
            let name = format!("v{version}_{field}_{value}.hic");
            let path = write_temp(&dir, &name, &bytes);
            let result = HicReader::open(&path, Some(10)).and_then(|reader| {
                let n = reader.bins().n_bins();
                reader.read_pixels(0..n, 0..n, &mut |_| Ok(()))?;
                for name in reader.weight_names() {
                    reader.weights(&name)?;
                }
                Ok(())
            });
            let error = result.expect_err(&name);
            let message = error.to_string();
            assert!(
                matches!(error, crate::error::Error::Format { .. }),
                "{name}: {message}"
            );
            assert!(
                message.contains(&name) && message.contains(&value.to_string()),
                "{name}: {message}"
            );
            assert!(message.contains(said), "{name}: {message}");
        }
    }
}

#[test]
fn header_bins_are_bounded_by_the_file_size() {
    use super::header::MAX_CHROM_LENGTH_BP;
    use super::reader::{BINS_PER_FILE_BYTE, MIN_BIN_ALLOWANCE, max_bins};
    // The bound: never more than the allowance or 16 bins per byte, never past 32-bit bins.
    for len in [0, 1, 1000, 1 << 20, 1 << 30, 1 << 40, u64::MAX] {
        let bound = max_bins(len);
        assert!(bound <= MIN_BIN_ALLOWANCE.max(len.saturating_mul(BINS_PER_FILE_BYTE)));
        assert!((MIN_BIN_ALLOWANCE..=1 << 32).contains(&bound));
    }
    // A small file whose chromosomes are as long as a header may say: refused before any
    // per-bin allocation, naming the bins and the file size.
    let dir = tempfile::tempdir().unwrap();
    for version in [8, 9] {
        // version 8 stores lengths as int32
        let longest = if version >= 9 {
            MAX_CHROM_LENGTH_BP as u64
        } else {
            i32::MAX as u64
        };
        let mut s = synthetic(version);
        for chrom in &mut s.chroms {
            chrom.length_bp = longest;
        }
        let bytes = write_hic(&s);
        let path = write_temp(&dir, "long.hic", &bytes);
        let n_bins = 3 * longest.div_ceil(10);
        assert!(n_bins > max_bins(bytes.len() as u64));
        let message = HicReader::open(&path, Some(10)).unwrap_err().to_string();
        assert!(
            message.contains(&format!("{n_bins} bins"))
                && message.contains(&format!("{} bytes", bytes.len())),
            "{message}"
        );
        // At the coarser resolution of a real genome's worth of bins the same lengths open.
        let mut s = synthetic(version);
        s.chroms[0].length_bp = longest;
        s.levels.retain(|level| level.0 == 20);
        for level in &mut s.levels {
            level.0 = 1_000;
            level.2.clear();
        }
        let path = write_temp(&dir, "long_ok.hic", &write_hic(&s));
        let reader = HicReader::open(&path, None).unwrap();
        assert_eq!(
            reader.bins().n_bins() as u64,
            longest.div_ceil(1_000) + 1 + 1
        );
    }
}

#[test]
fn fragment_only_files_are_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    for version in [8, 9] {
        let (mut bytes, at) = super::synthetic::write_hic_with_offsets(&synthetic(version));
        patch(&mut bytes, at["n_resolutions"], 4, 0);
        // no base-pair resolution: the next field (the first resolution, 10) is read as the
        // number of fragment resolutions, as in a file with fragment resolutions only
        let path = write_temp(&dir, "frag.hic", &bytes);
        for error in [
            HicReader::list_resolutions(&path).unwrap_err(),
            HicReader::open(&path, None).unwrap_err(),
        ] {
            let message = error.to_string();
            assert!(message.contains("no base-pair resolution"), "{message}");
        }
    }
}

#[test]
fn both_triangles_are_read_once_from_the_upper_records() {
    use proptest::test_runner::{Config, TestRunner};
    let dir = tempfile::tempdir().unwrap();
    for (version, budget) in [
        (8, BAND_BUDGET_BYTES),
        (8, 1),
        (9, BAND_BUDGET_BYTES),
        (9, 1),
    ] {
        let mut s = synthetic(version);
        s.intra_lower = false;
        s.both_triangles = true;
        let path = write_temp(&dir, &format!("both_v{version}.hic"), &write_hic(&s));
        for (resolution, pixels, _) in &s.levels {
            let mut reader = HicReader::open(&path, Some(*resolution)).unwrap();
            reader.band_budget_bytes = budget;
            let n = reader.bins().n_bins();
            // each pixel once, with the count of its upper record (the mirrored ones carry
            // MIRROR_EXTRA more)
            let all = as_triplets(pixels);
            assert_eq!(dump(&reader, 0..n, 0..n), all, "v{version} at {resolution}");
            let sum: f64 = all.iter().map(|p| p.2).sum();
            assert_eq!(reader.totals().unwrap(), (all.len() as u64, sum));
            assert!(reader.warnings().is_empty());
            let mut runner = TestRunner::new(Config::with_cases(40));
            runner
                .run(&(0..=n, 0..=n, 0..=n, 0..=n), |(a, b, c, d)| {
                    let rows = a.min(b)..a.max(b);
                    let cols = c.min(d)..c.max(d);
                    let got = dump(&reader, rows.clone(), cols.clone());
                    proptest::prop_assert_eq!(got, filter(&all, &rows, &cols));
                    Ok(())
                })
                .unwrap();
        }
    }
}

#[test]
fn records_past_a_chromosome_end_are_dropped_with_one_warning() {
    let dir = tempfile::tempdir().unwrap();
    for version in [8, 9] {
        let mut s = synthetic(version);
        // c1 has 37 bins at 10 bp, c2 23, c3 5: each record has a bin one or more past the end
        s.extra_records = vec![
            (0, 0, 35, 37, 3.0),
            (0, 0, 38, 40, 5.0),
            (0, 1, 36, 23, 7.0),
            (1, 2, 22, 5, 11.0),
            (2, 2, 4, 6, 13.0),
        ];
        let path = write_temp(&dir, &format!("past_v{version}.hic"), &write_hic(&s));
        let reader = HicReader::open(&path, Some(10)).unwrap();
        let n = reader.bins().n_bins();
        let all = as_triplets(&s.levels[0].1);
        assert_eq!(dump(&reader, 0..n, 0..n), all);
        let sum: f64 = all.iter().map(|p| p.2).sum();
        // totals decode every block: all five records are seen, and counted once however many
        // times their blocks are decoded
        assert_eq!(reader.totals().unwrap(), (all.len() as u64, sum));
        assert_eq!(reader.totals().unwrap(), (all.len() as u64, sum));
        let warnings = reader.warnings();
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(
            warnings[0].contains(&path.display().to_string())
                && warnings[0]
                    .contains("dropped 5 records past the end of a chromosome in the blocks"),
            "{}",
            warnings[0]
        );
        // the clean file warns of nothing
        let clean = write_temp(&dir, "clean.hic", &write_hic(&synthetic(version)));
        let reader = HicReader::open(&clean, Some(10)).unwrap();
        dump(&reader, 0..n, 0..n);
        reader.totals().unwrap();
        assert!(reader.warnings().is_empty());
    }
}

#[test]
fn file_bytes_quoted_in_messages_are_escaped() {
    let dir = tempfile::tempdir().unwrap();
    for version in [8, 9] {
        let mut s = synthetic(version);
        s.chroms[0].name = "c\n1\u{1b}[31m".into();
        let (mut bytes, at) = super::synthetic::write_hic_with_offsets(&s);
        let long = if version >= 9 { 8 } else { 4 };
        patch(&mut bytes, at["chrom_length"], long, -4);
        let path = write_temp(&dir, "name.hic", &bytes);
        let message = HicReader::open(&path, None).unwrap_err().to_string();
        assert!(
            !message.contains('\n') && !message.contains('\u{1b}'),
            "{message}"
        );
        assert!(message.contains(r"chromosome 'c\n1\u{1b}[31m' has a negative length -4"));
        // names also reach block messages through the pair label
        let mut s = synthetic(version);
        s.chroms[0].name = "c\r1".into(); // the first matrix written is c1-c1
        let (mut bytes, at) = super::synthetic::write_hic_with_offsets(&s);
        patch(&mut bytes, at["block_number"], 4, -7);
        let path = write_temp(&dir, "label.hic", &bytes);
        let reader = HicReader::open(&path, Some(10)).unwrap();
        let n = reader.bins().n_bins();
        let message = reader
            .read_pixels(0..n, 0..n, &mut |_| Ok(()))
            .unwrap_err()
            .to_string();
        assert!(
            !message.contains('\r') && message.contains(r"the block index of c\r1-c\r1: block -7"),
            "{message}"
        );
    }
    assert_eq!(bytes::printable("chr1"), "chr1");
    assert_eq!(bytes::printable("a\u{2028}b\u{85}"), r"a\u{2028}b\u{85}");
}
