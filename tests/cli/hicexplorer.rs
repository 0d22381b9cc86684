//! HiCExplorer `.h5` inputs (`data/hicexplorer/`, cut from HiCExplorer's own test data by
//! `scripts/fixtures/hicexplorer_fixtures.py`): every command reads the `.h5` as cooler and
//! cooltools read the same matrix converted to a cooler as HiCExplorer's `hicConvertFormat` does
//! (`data/reference/hicexplorer/`), and a corrected file's balanced values are the corrected values
//! hicCorrectMatrix stored.

use std::collections::HashMap;
use std::io::Read;

use crate::{Table, data, parse_table, reference_table, run_err, run_ok};

const H5: &str = "hicexplorer/small_test_matrix.h5";
const COOL: &str = "hicexplorer/small_test_matrix.cool";
const ICE: &str = "hicexplorer/ICEcorrected_chr3LHet.h5";

fn gunzip(name: &str) -> String {
    let mut text = String::new();
    flate2::read::MultiGzDecoder::new(std::fs::File::open(data(name)).expect("reference file"))
        .read_to_string(&mut text)
        .expect("gzip text");
    text
}

/// Same header, same rows; reals within `relative` of the reference (NaN where it has NaN),
/// other fields equal.
fn compare(ours: &Table, theirs: &Table, relative: f64) {
    assert_eq!(ours.header, theirs.header, "columns");
    assert_eq!(ours.rows.len(), theirs.rows.len(), "number of rows");
    for (row, (a, b)) in ours.rows.iter().zip(&theirs.rows).enumerate() {
        for (column, name) in theirs.header.iter().enumerate() {
            let (x, y) = (&a[column], &b[column]);
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(x), Ok(y)) => {
                    if y.is_nan() {
                        assert!(x.is_nan(), "row {row} {name}: {x} where the peer has nan");
                    } else {
                        assert!(
                            (x - y).abs() <= relative * y.abs(),
                            "row {row} {name}: {x} vs {y}"
                        );
                    }
                }
                _ => assert_eq!(x, y, "row {row} {name}"),
            }
        }
    }
}

#[test]
fn dump_and_info_equal_cooler_on_the_converted_matrix() {
    let h5 = data(H5);
    // cooler 0.11 `dump --join` of the cooler made as hicConvertFormat does: 466 pixels, sum 494.
    let reference = gunzip("reference/hicexplorer/dump.tsv.gz");
    let pixels = run_ok(&["dump", "--join", &h5]);
    assert_eq!(pixels, reference);
    assert_eq!(pixels.lines().count(), 466);
    let sum: f64 = pixels
        .lines()
        .map(|l| l.split('\t').nth(6).unwrap().parse::<f64>().unwrap())
        .sum();
    assert_eq!(sum, 494.0);
    for table in ["bins", "chroms", "pixels"] {
        assert_eq!(
            run_ok(&["dump", "-t", table, &h5]),
            run_ok(&["dump", "-t", table, &data(COOL)]),
            "{table}"
        );
    }
    assert_eq!(
        run_ok(&["dump", "--join", "-r", "chr4:100,000-900,000", &h5]),
        run_ok(&["dump", "--join", "-r", "chr4:100,000-900,000", &data(COOL)])
    );
    let info = run_ok(&["info", &h5]);
    assert!(info.contains("HiCExplorer h5"), "{info}");
    assert!(info.contains("last bin's end"), "{info}");
    assert!(info.contains("nnz             466"), "{info}");
}

#[test]
fn convert_to_cool_gives_coolers_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("converted.cool");
    let out = out.to_str().unwrap();
    run_ok(&["convert", &data(H5), out]);
    assert_eq!(
        run_ok(&["dump", "--join", out]),
        gunzip("reference/hicexplorer/dump.tsv.gz")
    );
    for table in ["bins", "chroms"] {
        assert_eq!(
            run_ok(&["dump", "-t", table, out]),
            run_ok(&["dump", "-t", table, &data(COOL)]),
            "{table}"
        );
    }
}

#[test]
fn balance_equals_cooler_on_the_converted_matrix() {
    // cooler.balance_cooler(ignore_diags=2, mad_max=0, min_nnz=3, min_count=0, cis_only=True,
    // tol=1e-5, max_iters=1000): 95 bins keep a weight.
    let args = [
        "--cis-only",
        "--mad-max",
        "0",
        "--min-nnz",
        "3",
        "--min-count",
        "0",
        "--tol",
        "1e-5",
        "--max-iters",
        "1000",
    ];
    let ours = run_ok(&[&["balance", &data(H5)], &args[..]].concat());
    assert_eq!(
        ours,
        run_ok(&[&["balance", &data(COOL)], &args[..]].concat())
    );
    let ours = parse_table(&ours);
    let theirs = parse_table(&gunzip("reference/hicexplorer/balance.tsv.gz"));
    assert_eq!(ours.header[..4], theirs.header[..]);
    let mut n_weights = 0;
    for (row, (a, b)) in ours.rows.iter().zip(&theirs.rows).enumerate() {
        assert_eq!(a[..3], b[..3], "row {row}");
        let (x, y): (f64, f64) = (a[3].parse().unwrap(), b[3].parse().unwrap());
        assert_eq!(x.is_nan(), y.is_nan(), "row {row}: {x} vs cooler {y}");
        if !y.is_nan() {
            assert!((x - y).abs() <= 1e-6 * y, "row {row}: {x} vs cooler {y}");
            n_weights += 1;
        }
    }
    assert_eq!(ours.rows.len(), 931);
    assert_eq!(n_weights, 95);
}

#[test]
fn expected_and_insulation_equal_cooltools_on_the_converted_matrix() {
    // The references are written with %.10g: 1e-9 relative is twice the quantisation.
    let expected = run_ok(&["expected", "--raw", &data(H5)]);
    assert_eq!(expected, run_ok(&["expected", "--raw", &data(COOL)]));
    compare(
        &parse_table(&expected),
        &reference_table("reference/hicexplorer/expected_cis.tsv.gz"),
        1e-9,
    );
    let insulation = run_ok(&["tads", &data(H5), "--raw", "--window", "50000"]);
    assert_eq!(
        insulation,
        run_ok(&["tads", &data(COOL), "--raw", "--window", "50000"])
    );
    let insulation = parse_table(&insulation);
    let reference = reference_table("reference/hicexplorer/insulation.tsv.gz");
    let finite = reference
        .rows
        .iter()
        .filter(|r| r[5].parse::<f64>().is_ok_and(f64::is_finite))
        .count();
    assert!(finite > 100, "{finite} finite insulation scores");
    compare(&insulation, &reference, 1e-9);
}

/// `chrom1 start1 chrom2 start2 -> count` from a `dump --join` output.
fn joined(text: &str) -> HashMap<(String, String, String, String), f64> {
    text.lines()
        .map(|line| {
            let f: Vec<&str> = line.split('\t').collect();
            let key = (f[0].into(), f[1].into(), f[3].into(), f[4].into());
            (key, f[6].parse().unwrap())
        })
        .collect()
}

#[test]
fn corrected_file_balances_to_the_stored_values_and_restores_raw_counts() {
    let ice = data(ICE);
    let info = run_ok(&["info", &ice]);
    assert!(info.contains("1 / c"), "{info}");
    // Balanced values with the weight column made from correction_factors are the corrected
    // values hicCorrectMatrix stored (reference written by h5py).
    let balanced = run_ok(&["dump", &ice, "--balanced", "--float-format", ".17g"]);
    let reference =
        std::fs::read_to_string(data("reference/hicexplorer/ice_balanced.tsv")).unwrap();
    let reference: Vec<&str> = reference.lines().skip(1).collect();
    assert_eq!(balanced.lines().count(), reference.len());
    assert_eq!(reference.len(), 24);
    for (ours, theirs) in balanced.lines().zip(reference) {
        let ours: Vec<&str> = ours.split('\t').collect();
        let theirs: Vec<&str> = theirs.split('\t').collect();
        assert_eq!(ours[..2], theirs[..2]);
        let (a, b): (f64, f64) = (ours[3].parse().unwrap(), theirs[2].parse().unwrap());
        assert!((a - b).abs() <= 1e-12 * b, "{ours:?} vs {theirs:?}");
    }
    // The restored counts are the raw counts of the uncorrected matrix at the same loci.
    let raw = joined(&run_ok(&["dump", "--join", &data(H5)]));
    let restored = joined(&run_ok(&["dump", "--join", "--float-format", ".17g", &ice]));
    assert_eq!(restored.len(), 24);
    for (key, count) in restored {
        let original = raw[&key];
        assert!((count - original).abs() <= 1e-9 * original, "{key:?}");
    }
}

#[test]
fn a_shortened_indptr_is_one_error_naming_the_file_and_dataset() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("short.h5");
    std::fs::copy(data(H5), &path).unwrap();
    {
        let file = hdf5::File::open_rw(&path).unwrap();
        let matrix = file.group("matrix").unwrap();
        let mut indptr = matrix.dataset("indptr").unwrap().read_raw::<i64>().unwrap();
        indptr.truncate(indptr.len() - 10);
        matrix.unlink("indptr").unwrap();
        matrix
            .new_dataset_builder()
            .with_data(&indptr)
            .create("indptr")
            .unwrap();
    }
    let path = path.to_str().unwrap();
    for args in [
        vec!["dump", path],
        vec!["info", path],
        vec!["expected", path, "--raw"],
    ] {
        let error = run_err(&args);
        assert!(
            error.contains(path) && error.contains("matrix/indptr"),
            "{error}"
        );
    }
    let out = dir.path().join("never.cool");
    run_err(&["convert", path, out.to_str().unwrap()]);
    assert!(!out.exists());
}

#[test]
fn an_unknown_blosc_compressor_is_one_error_not_a_crash() {
    // hdf5-metno's blosc filter dereferences a null name for a compressor code it does not know
    // (SIGSEGV, found by mutating the fixture): the reader checks each pipeline first.
    let mut bytes = std::fs::read(data(H5)).unwrap();
    // Filter description (HDF5 pipeline message v1): id 32001, name length 8, flags, 7 values,
    // "blosc\0\0\0", then the values; the 7th is the compressor code (0 = blosclz).
    let header = [0x01, 0x7d, 8, 0, 1, 0, 7, 0];
    let at = bytes
        .windows(header.len())
        .position(|w| w == header)
        .expect("a blosc filter message");
    let code = at + header.len() + 8 + 6 * 4;
    assert_eq!(bytes[code..code + 4], [0, 0, 0, 0]);
    bytes[code] = 99;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("codec.h5");
    std::fs::write(&path, bytes).unwrap();
    let path = path.to_str().unwrap();
    for command in ["dump", "info"] {
        let error = run_err(&[command, path]);
        assert!(
            error.contains(path) && error.contains("filter pipeline (invalid blosc complib: 99)"),
            "{error}"
        );
    }
}
