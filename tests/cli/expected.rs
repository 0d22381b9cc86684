//! `contactmap expected` against the peer tools' reference outputs.
//!
//! The references (`data/reference/numerics/*.expected_cis.*.tsv.gz`) are cooltools 0.7.1
//! `expected_cis(clr, clr_weight_name=None | "weight", ignore_diags=2, smooth=True,
//! aggregate_smoothed=True, smooth_sigma=0.1)` written with `%.10g` (see `gen_refs.py` there).
//! Ten significant digits quantise a value by at most 5e-10 of itself, so reals are compared
//! with `|ours - reference| <= 1e-9 * |reference|` (twice the quantisation; against cooltools'
//! full-precision output the largest difference seen is about 1e-15), integers exactly, and
//! NaN must be NaN in both.

use std::collections::HashMap;
use std::io::Read;
use std::path::Path;

use contactmap::genome::{BinTable, Chrom};
use contactmap::io::cool::{CoolWriteOptions, write_cool};
use contactmap::io::{InMemory, OpenOptions, load_matrix, open_matrix};
use contactmap::matrix::{CountType, MatrixBuilder};

use crate::{Table, data, parse_table, reference_table, run_err, run_ok};

const DM6: &str = "cooler_test_file.mcool::/resolutions/100000";
const MM9: &str = "CN.mm9.10000kb.cool";
const HG19: &str = "hg19.GM12878-MboI.matrix.2000kb.cool";

fn reference(name: &str) -> Table {
    reference_table(&format!("reference/numerics/{name}"))
}

fn number(field: &str) -> f64 {
    field
        .parse()
        .unwrap_or_else(|_| panic!("'{field}' is not a number"))
}

/// Compare two tables column by column; returns the largest relative difference per column.
fn compare(ours: &Table, theirs: &Table, relative: f64) -> HashMap<String, f64> {
    assert_eq!(ours.header, theirs.header, "columns");
    assert_eq!(ours.rows.len(), theirs.rows.len(), "number of rows");
    let mut worst = HashMap::new();
    for (row, (a, b)) in ours.rows.iter().zip(&theirs.rows).enumerate() {
        for (column, name) in ours.header.iter().enumerate() {
            let (x, y) = (&a[column], &b[column]);
            if name.starts_with("region") {
                assert_eq!(x, y, "row {row} column {name}");
                continue;
            }
            let (x, y) = (number(x), number(y));
            if y.is_nan() {
                assert!(
                    x.is_nan(),
                    "row {row} {name}: {x} where the reference has nan"
                );
                continue;
            }
            let difference = (x - y).abs();
            assert!(
                difference <= relative * y.abs(),
                "row {row} {name}: {x} vs {y}"
            );
            let slot = worst.entry(name.clone()).or_insert(0.0f64);
            if y != 0.0 {
                *slot = slot.max(difference / y.abs());
            }
        }
    }
    worst
}

#[test]
fn cis_expected_equals_cooltools_raw_and_balanced() {
    for (uri, key, balanced) in [
        (DM6, "dm6_100kb", true),
        (MM9, "mm9_CN_10Mb", true),
        (HG19, "gm12878_2Mb", false),
    ] {
        let raw = run_ok(&["expected", "--raw", &data(uri)]);
        compare(
            &parse_table(&raw),
            &reference(&format!("{key}.expected_cis.raw.tsv.gz")),
            1e-9,
        );
        if balanced {
            let ours = run_ok(&["expected", &data(uri)]);
            compare(
                &parse_table(&ours),
                &reference(&format!("{key}.expected_cis.balanced_storedweight.tsv.gz")),
                1e-9,
            );
        }
    }
}

#[test]
fn streamed_equals_in_memory_and_files_equal_stdout() {
    for args in [vec!["--raw"], vec![]] {
        let mut streamed = vec!["expected", "--max-memory", "0"];
        streamed.extend(&args);
        let uri = data(DM6);
        streamed.push(&uri);
        let mut memory = streamed.clone();
        memory[2] = "1G";
        // Partial sums are added in the same order either way: the outputs are identical.
        let a = run_ok(&streamed);
        assert_eq!(a, run_ok(&memory));
        let a = parse_table(&a);
        let default = parse_table(&run_ok(&[&["expected"], &args[..], &[&uri]].concat()));
        compare(&default, &a, 0.0);
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("exp.tsv.gz");
    run_ok(&["expected", &data(MM9), "-o", out.to_str().unwrap()]);
    let mut text = String::new();
    flate2::read::MultiGzDecoder::new(std::fs::File::open(&out).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    assert_eq!(text, run_ok(&["expected", &data(MM9)]));
}

fn write_file(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn views_name_regions_and_match_whole_chromosomes() {
    let dir = tempfile::tempdir().unwrap();
    let reader = open_matrix(&data(MM9), &OpenOptions::default()).unwrap();
    let bed: String = reader
        .bins()
        .chroms()
        .iter()
        .map(|c| format!("{}\t0\t{}\n", c.name, c.length_bp))
        .collect();
    let unnamed = write_file(dir.path(), "chroms.bed", &bed);
    let whole = parse_table(&run_ok(&["expected", &data(MM9)]));
    let mut via_bed = parse_table(&run_ok(&["expected", &data(MM9), "--view", &unnamed]));
    // Same numbers; regions named chrom:start-end.
    let first = &reader.bins().chroms()[0];
    assert_eq!(
        via_bed.rows[0][0],
        format!("{}:0-{}", first.name, first.length_bp)
    );
    for row in &mut via_bed.rows {
        for field in &mut row[..2] {
            *field = field.split(':').next().unwrap().to_string();
        }
    }
    compare(&via_bed, &whole, 0.0);
    // Named arms: chr1 split in two at a bin boundary; their diagonals are those of each half.
    let arms = write_file(
        dir.path(),
        "arms.bed",
        "chr1\t0\t90000000\tchr1_p\nchr1\t90000000\t197195432\tchr1_q\nchr2\t0\t181748087\tchr2\n",
    );
    let table = parse_table(&run_ok(&["expected", &data(MM9), "--view", &arms]));
    let rows_of = |name: &str| table.rows.iter().filter(|r| r[0] == name).count();
    assert_eq!(rows_of("chr1_p"), 9);
    assert_eq!(rows_of("chr1_q"), 11);
    assert_eq!(rows_of("chr2"), 19);
    assert!(table.rows.iter().all(|r| r[0] == r[1]));
}

#[test]
fn bad_views_and_weights_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let unknown = write_file(dir.path(), "unknown.bed", "chr1\t0\t1000000\nchrZ\t0\t10\n");
    let message = run_err(&["expected", &data(MM9), "--view", &unknown]);
    assert!(message.contains("unknown.bed"), "{message}");
    assert!(message.contains("no chromosome 'chrZ'"), "{message}");
    let overlapping = write_file(
        dir.path(),
        "overlap.bed",
        "chr1\t0\t50000000\ta\nchr1\t40000000\t90000000\tb\n",
    );
    let message = run_err(&["expected", &data(MM9), "--view", &overlapping]);
    assert!(message.contains("overlaps region 'a'"), "{message}");
    let columns = write_file(dir.path(), "columns.bed", "chr1\t0\n");
    let message = run_err(&["expected", &data(MM9), "--view", &columns]);
    assert!(message.contains("columns.bed:1:"), "{message}");
    let message = run_err(&["expected", &data(HG19)]);
    assert!(message.contains("this map has no weights"), "{message}");
    assert!(message.contains("--raw"), "{message}");
    let message = run_err(&["expected", &data(DM6), "--weight-name", "ICE"]);
    assert!(
        message.contains("no weight column 'ICE' (it has "),
        "{message}"
    );
    assert!(message.contains("weight"), "{message}");
    let message = run_err(&["expected", &data(MM9), "--fit-range", "10M-1M"]);
    assert!(message.contains("--fit-range"), "{message}");
}

#[test]
fn trans_expected_equals_a_naive_sum() {
    for (uri, balanced) in [(MM9, true), (HG19, false)] {
        let reader = open_matrix(&data(uri), &OpenOptions::default()).unwrap();
        let matrix = load_matrix(reader.as_ref()).unwrap();
        let bins = matrix.bins();
        let weights = balanced.then(|| reader.weights("weight").unwrap().values);
        let mut args = vec!["expected", "--trans"];
        if !balanced {
            args.push("--raw");
        }
        let path = data(uri);
        args.push(&path);
        let table = parse_table(&run_ok(&args));
        let mut expected_header = vec!["region1", "region2", "n_valid", "count.sum"];
        if balanced {
            expected_header.push("balanced.sum");
        }
        expected_header.push("count.avg");
        if balanced {
            expected_header.push("balanced.avg");
        }
        assert_eq!(table.header, expected_header);
        let n_chroms = bins.n_chroms();
        assert_eq!(table.rows.len(), n_chroms * (n_chroms - 1) / 2);
        for row in &table.rows {
            let a = bins.chrom_bins(bins.chrom_id(&row[0]).unwrap());
            let b = bins.chrom_bins(bins.chrom_id(&row[1]).unwrap());
            let good = |i: usize| weights.as_ref().is_none_or(|w| !w[i].is_nan());
            let (mut count, mut balanced_sum) = (0.0, 0.0);
            for i in a.clone().filter(|&i| good(i)) {
                for j in b.clone().filter(|&j| good(j)) {
                    let c = matrix.get(i, j);
                    count += c;
                    if let Some(w) = &weights {
                        balanced_sum += c * w[i] * w[j];
                    }
                }
            }
            let n_valid = (a.filter(|&i| good(i)).count() * b.filter(|&j| good(j)).count()) as f64;
            assert_eq!(number(&row[2]), n_valid);
            assert_eq!(number(&row[3]), count);
            if balanced {
                assert!((number(&row[4]) - balanced_sum).abs() <= 1e-12 * balanced_sum);
                assert!(
                    (number(&row[6]) - balanced_sum / n_valid).abs()
                        <= 1e-12 * balanced_sum / n_valid
                );
            } else {
                assert!((number(&row[4]) - count / n_valid).abs() <= 1e-15 * count / n_valid);
            }
        }
    }
}

/// Write a synthetic single-resolution .cool: `n_chroms` chromosomes of `n_bins` 10 kb bins
/// whose pixel at distance `d >= 1` bins has the count `count(d, noise)`.
fn synthetic_cool(
    path: &Path,
    n_chroms: usize,
    n_bins: u64,
    integer: bool,
    count: impl Fn(u64, &mut dyn FnMut() -> f64) -> f64,
) {
    let chroms: Vec<Chrom> = (1..=n_chroms)
        .map(|k| Chrom::new(format!("chr{k}"), n_bins * 10_000))
        .collect();
    let bins = BinTable::fixed(chroms, 10_000).unwrap();
    let count_type = if integer {
        CountType::Integer
    } else {
        CountType::Float
    };
    let mut builder = MatrixBuilder::new(bins, count_type);
    let mut state = 0x9e3779b97f4a7c15u64;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for chrom in 0..n_chroms as u64 {
        let offset = chrom * n_bins;
        for i in 0..n_bins {
            for j in i + 1..n_bins {
                let value = count(j - i, &mut uniform);
                if value > 0.0 {
                    builder.push(offset + i, offset + j, value).unwrap();
                }
            }
        }
    }
    let reader = InMemory::new("synthetic".into(), builder.build());
    write_cool(&reader, path, &CoolWriteOptions::default()).unwrap();
}

/// A Poisson draw with mean `lambda` (inversion below 30, normal approximation above).
fn poisson(lambda: f64, uniform: &mut dyn FnMut() -> f64) -> f64 {
    if lambda < 30.0 {
        let (mut k, mut p, mut cumulative) = (0.0, (-lambda).exp(), (-lambda).exp());
        let u = uniform();
        while u > cumulative && k < 1000.0 {
            k += 1.0;
            p *= lambda / k;
            cumulative += p;
        }
        k
    } else {
        let (u1, u2) = (uniform().max(1e-300), uniform());
        let normal = (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
        (lambda + lambda.sqrt() * normal).round().max(0.0)
    }
}

fn fit_json(path: &Path) -> serde_json::Value {
    let text = run_ok(&["expected", "--raw", "--json", path.to_str().unwrap()]);
    serde_json::from_str(&text).expect("JSON output")
}

/// Three chromosomes of 600 10 kb bins whose pixels are `200 d^alpha` exactly, or Poisson
/// draws with that mean (about 100 counts at 2 bins, 0.1-1.3 at 150 bins, as a shallow Hi-C map).
#[test]
fn power_law_exponents_are_recovered() {
    let dir = tempfile::tempdir().unwrap();
    for alpha in [-0.8, -1.0, -1.5] {
        for poisson_noise in [false, true] {
            let path = dir.path().join(format!("pl{alpha}{poisson_noise}.cool"));
            synthetic_cool(&path, 3, 600, poisson_noise, |d, uniform| {
                let mean = 200.0 * (d as f64).powf(alpha);
                if poisson_noise {
                    poisson(mean, uniform)
                } else {
                    mean
                }
            });
            let report = fit_json(&path);
            let fit = &report["power_law"];
            let fitted = fit["alpha"].as_f64().unwrap();
            let (low, high) = (
                fit["ci95"][0].as_f64().unwrap(),
                fit["ci95"][1].as_f64().unwrap(),
            );
            assert!(
                (fitted - alpha).abs() < 0.02,
                "alpha {alpha} (Poisson {poisson_noise}): fitted {fitted}"
            );
            if poisson_noise {
                assert!(
                    low <= alpha && alpha <= high,
                    "alpha {alpha}: CI [{low}, {high}]"
                );
                assert!(high - low < 0.02, "alpha {alpha}: CI [{low}, {high}]");
            } else {
                // No noise: the effective-distance fit is exact (the interval only measures
                // scatter, which is zero up to rounding here).
                assert!(
                    (fitted - alpha).abs() < 1e-9,
                    "alpha {alpha}: fitted {fitted}"
                );
            }
            assert!(fit["r_squared"].as_f64().unwrap() > 0.99);
            // Default range: 2 bins to a quarter of the chromosome length.
            assert_eq!(report["fit_range_bp"][0].as_f64().unwrap(), 20_000.0);
            assert_eq!(report["fit_range_bp"][1].as_f64().unwrap(), 1_500_000.0);
            assert_eq!(report["piecewise"]["n_breakpoints"].as_u64().unwrap(), 0);
        }
    }
}

#[test]
fn a_known_breakpoint_is_found() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("broken.cool");
    // P(s) ~ s^-0.7 up to 30 bins (300 kb), s^-1.5 beyond, continuous.
    synthetic_cool(&path, 3, 600, false, |d, _| {
        let d = d as f64;
        if d <= 30.0 {
            1e4 * d.powf(-0.7)
        } else {
            1e4 * 30f64.powf(-0.7) * (d / 30.0).powf(-1.5)
        }
    });
    let report = fit_json(&path);
    let piecewise = &report["piecewise"];
    assert_eq!(
        piecewise["n_breakpoints"].as_u64().unwrap(),
        1,
        "{piecewise}"
    );
    let breakpoint = piecewise["breakpoints_bp"][0].as_f64().unwrap();
    assert!(
        (breakpoint / 300_000.0).log10().abs() <= 0.1,
        "breakpoint at {breakpoint} bp"
    );
    let segments = piecewise["segments"].as_array().unwrap();
    assert!(
        (segments[0]["alpha"].as_f64().unwrap() + 0.7).abs() < 0.05,
        "{piecewise}"
    );
    assert!(
        (segments[1]["alpha"].as_f64().unwrap() + 1.5).abs() < 0.05,
        "{piecewise}"
    );
    // The text report says the same in one line per segment.
    let text = run_ok(&["expected", "--raw", "--fit", path.to_str().unwrap()]);
    assert!(text.starts_with("P(s) ~ s^-"), "{text}");
    assert!(text.contains("1 breakpoint by BIC"), "{text}");
}

#[test]
fn logbin_table_has_slopes() {
    let table = parse_table(&run_ok(&["expected", "--logbin", &data(DM6)]));
    assert_eq!(
        table.header[..8],
        [
            "dist_bin_id",
            "balanced.avg",
            "n_valid",
            "dist.avg",
            "dist_bin_start",
            "dist_bin_end",
            "low_err",
            "high_err"
        ]
    );
    assert!(table.rows.len() > 10);
    let slope_column = table.header.iter().position(|h| h == "slope").unwrap();
    // P(s) falls at every scale in this map: every slope but the last (none) is negative.
    for row in &table.rows[..table.rows.len() - 1] {
        assert!(number(&row[slope_column]) < 0.0, "{row:?}");
    }
    assert_eq!(table.rows.last().unwrap()[slope_column], "nan");
}

/// Issue 26: --fit-range without --fit is refused (it used to be ignored), and the headline
/// gives the distances of the points fitted (the first log bin's effective distance lies past
/// the range's start), then the range asked for.
#[test]
fn fit_range_needs_fit_and_the_headline_names_the_points_fitted() {
    let line = run_err(&["expected", &data(DM6), "--fit-range", "200k-5M"]);
    assert!(line.contains("add --fit"), "{line}");
    let line = run_err(&["expected", &data(DM6), "--logbin", "--fit-range", "200k-5M"]);
    assert!(line.contains("add --fit"), "{line}");
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("ps.png");
    let line = run_err(&[
        "plot",
        "expected",
        &data(DM6),
        "--fit-range",
        "200k-5M",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(line.contains("not provided: --fit"), "{line}");
    let json: serde_json::Value = serde_json::from_str(&run_ok(&[
        "expected",
        &data(DM6),
        "--json",
        "--fit-range",
        "200k-5M",
    ]))
    .unwrap();
    let first = json["power_law"]["first_bp"].as_f64().unwrap();
    let last = json["power_law"]["last_bp"].as_f64().unwrap();
    assert!(first >= 200_000.0 && last < 5_000_000.0, "{first} {last}");
    let text = run_ok(&["expected", &data(DM6), "--fit", "--fit-range", "200k-5M"]);
    let headline = text.lines().next().unwrap();
    let fitted = format!(
        "fitted {} - {}",
        contactmap::genome::format_distance(first),
        contactmap::genome::format_distance(last)
    );
    assert!(headline.contains(&fitted), "{headline} vs {fitted}");
    assert!(headline.contains("in 200 kb - 5 Mb)"), "{headline}");
}
