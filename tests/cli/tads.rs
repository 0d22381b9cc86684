//! `contactmap tads` against cooltools 0.7.1 (`data/reference/tads/`, see `data/README.md`), on
//! synthetic block maps with known boundaries, and on bad input.
//!
//! The references are written with `%.10g`, so reals are compared with
//! `|ours - reference| <= 1e-9 * |reference|` (twice the quantisation; the acceptance bound is
//! 1e-8), integers and booleans exactly, NaN must be NaN in both.

use crate::{Table, data, parse_table, reference_table, run, run_err, run_ok};

const DM6: &str = "cooler_test_file.mcool::/resolutions/100000";
const YEAST: &str = "yeast.10kb.cool";

fn reference(name: &str) -> Table {
    reference_table(&format!("reference/tads/{name}"))
}

/// Compare every column of `theirs` with the same-named column of `ours`; returns the largest
/// relative difference seen over the real-valued columns.
fn compare(ours: &Table, theirs: &Table) -> f64 {
    assert_eq!(ours.rows.len(), theirs.rows.len(), "number of rows");
    let mut worst = 0.0f64;
    for name in &theirs.header {
        let column_of = |t: &Table| {
            t.header
                .iter()
                .position(|h| h == name)
                .unwrap_or_else(|| panic!("no column {name}"))
        };
        let (a, b) = (column_of(ours), column_of(theirs));
        for (row, (x, y)) in ours.rows.iter().zip(&theirs.rows).enumerate() {
            let (x, y) = (&x[a], &y[b]);
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(x), Ok(y)) if !["start", "end"].contains(&name.as_str()) => {
                    if y.is_nan() {
                        assert!(x.is_nan(), "row {row} {name}: {x} where cooltools has nan");
                        continue;
                    }
                    let difference = (x - y).abs();
                    assert!(
                        difference <= 1e-9 * y.abs(),
                        "row {row} {name}: {x} vs cooltools {y}"
                    );
                    if y != 0.0 {
                        worst = worst.max(difference / y.abs());
                    }
                }
                _ => assert_eq!(x, y, "row {row} {name}"),
            }
        }
    }
    worst
}

#[test]
fn insulation_equals_cooltools_on_dm6_and_yeast() {
    for (uri, windows, key) in [
        (DM6, "300000,500000,1000000", "dm6_100kb"),
        (YEAST, "30000,50000,100000", "yeast_10kb"),
    ] {
        let ours = run_ok(&["tads", &data(uri), "--window", windows]);
        let worst = compare(
            &parse_table(&ours),
            &reference(&format!("{key}.insulation.Li.tsv.gz")),
        );
        assert!(worst <= 1e-9, "{key}: {worst}");
    }
}

#[test]
fn directionality_equals_cooltools_on_dm6_and_yeast() {
    for (uri, window, key) in [(DM6, "500000", "dm6_100kb"), (YEAST, "50000", "yeast_10kb")] {
        let ours = run_ok(&[
            "tads",
            &data(uri),
            "--method",
            "directionality",
            "--window",
            window,
        ]);
        compare(
            &parse_table(&ours),
            &reference(&format!("{key}.directionality_{window}.tsv.gz")),
        );
    }
}

#[test]
fn boundary_bed_lists_the_called_bins_of_the_chosen_window() {
    let dir = tempfile::tempdir().unwrap();
    let bed = dir.path().join("b.bed");
    let domains = dir.path().join("d.bed");
    let track = run_ok(&[
        "tads",
        &data(YEAST),
        "--window",
        "30k,50k",
        "--bed-window",
        "50k",
        "--boundaries",
        bed.to_str().unwrap(),
        "--domains",
        domains.to_str().unwrap(),
    ]);
    let table = parse_table(&track);
    let flag = table
        .header
        .iter()
        .position(|h| h == "is_boundary_50000")
        .unwrap();
    let strength = table
        .header
        .iter()
        .position(|h| h == "boundary_strength_50000")
        .unwrap();
    let expected: Vec<String> = table
        .rows
        .iter()
        .filter(|r| r[flag] == "True")
        .map(|r| {
            format!(
                "{}\t{}\t{}\tinsulation_50000\t{}",
                r[0], r[1], r[2], r[strength]
            )
        })
        .collect();
    let written: Vec<String> = std::fs::read_to_string(&bed)
        .unwrap()
        .lines()
        .map(String::from)
        .collect();
    assert!(!expected.is_empty());
    assert_eq!(written, expected);
    // Domains tile each chromosome between consecutive boundaries.
    let domain_lines = std::fs::read_to_string(&domains).unwrap();
    let n_chroms = 18;
    assert_eq!(domain_lines.lines().count(), expected.len() + n_chroms);
}

#[test]
fn otsu_works_where_cooltools_crashes() {
    let ours = run_ok(&[
        "tads",
        &data(DM6),
        "--window",
        "500k",
        "--threshold",
        "otsu",
    ]);
    let table = parse_table(&ours);
    let strength = table
        .header
        .iter()
        .position(|h| h == "boundary_strength_500000")
        .unwrap();
    let flag = table
        .header
        .iter()
        .position(|h| h == "is_boundary_500000")
        .unwrap();
    let strengths: Vec<f64> = table
        .rows
        .iter()
        .map(|r| r[strength].parse().unwrap())
        .collect();
    assert!(strengths.iter().any(|s| s.is_nan()));
    let called: Vec<f64> = table
        .rows
        .iter()
        .zip(&strengths)
        .filter(|(r, _)| r[flag] == "True")
        .map(|(_, s)| *s)
        .collect();
    let rejected_max = table
        .rows
        .iter()
        .zip(&strengths)
        .filter(|(r, s)| r[flag] == "False" && !s.is_nan())
        .map(|(_, s)| *s)
        .fold(f64::MIN, f64::max);
    assert!(!called.is_empty());
    // A cutoff: every call is stronger than every finite rejected strength.
    assert!(called.iter().all(|&s| s > rejected_max));
}

#[test]
fn bad_windows_and_missing_weights_are_clear_errors() {
    let message = run_err(&["tads", &data(YEAST), "--window", "25000"]);
    assert!(
        message.contains(
            "--window 25000: window 25000 bp is not a positive multiple of the bin size 10000 bp"
        ),
        "{message}"
    );
    let message = run_err(&["tads", &data(YEAST), "--window", "0"]);
    assert!(message.contains("multiple of the bin size"), "{message}");
    let message = run_err(&["tads", &data(YEAST), "--window", "abc"]);
    assert!(message.contains("--window"), "{message}");
    let message = run_err(&["tads", &data("hg19.GM12878-MboI.matrix.2000kb.cool")]);
    assert!(message.contains("this map has no weights"), "{message}");
    assert!(message.contains("--raw"), "{message}");
    let message = run_err(&["tads", &data(YEAST), "--threshold", "median"]);
    assert!(message.contains("--threshold"), "{message}");
    let message = run_err(&[
        "tads",
        &data(YEAST),
        "--method",
        "directionality",
        "--window",
        "30k,50k",
    ]);
    assert!(message.contains("single window"), "{message}");
}

#[test]
fn a_region_shorter_than_the_window_is_an_error_or_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let view = dir.path().join("view.bed");
    std::fs::write(&view, "chrI\t0\t50000\n").unwrap();
    let message = run_err(&[
        "tads",
        &data(YEAST),
        "--window",
        "100k",
        "--view",
        view.to_str().unwrap(),
    ]);
    assert!(message.contains("chrI"), "{message}");
    assert!(
        message.contains("shorter than the 100000 bp window"),
        "{message}"
    );
    // Genome-wide, chrMito (86 kb) is shorter than 100 kb: computed as cooltools, with a warning.
    let out = run(&["tads", &data(YEAST), "--window", "100k"]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("warning: chrMito"), "{stderr}");
    // A map whose every chromosome is shorter than the window.
    let message = run_err(&["tads", &data(YEAST), "--window", "2000k"]);
    assert!(
        message.contains("shorter than the 2000000 bp window"),
        "{message}"
    );
}

#[test]
fn a_warning_never_precedes_the_error_of_a_failed_command() {
    // chrMito is shorter than 100 kb (a warning on success), and --bed-window names no window:
    // the error comes after the length check, yet it is the only line printed (run_err checks).
    let message = run_err(&[
        "tads",
        &data(YEAST),
        "--window",
        "100k",
        "--bed-window",
        "50k",
    ]);
    assert!(
        message.contains("--bed-window 50k is not one of the --window values"),
        "{message}"
    );
    // An output that cannot be written, after a successful computation: its error alone.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("missing").join("insulation.tsv");
    let message = run_err(&[
        "tads",
        &data(YEAST),
        "--window",
        "100k",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(message.contains("missing"), "{message}");
}

/// F1 of `tads ARGS` on a balanced synthetic block map against its true boundaries.
fn synthetic_f1(dir: &std::path::Path, depth: &str, seed: &str, args: &[&str]) -> f64 {
    let map = dir.join(format!("map_{depth}_{seed}.cool"));
    let truth = dir.join(format!("truth_{depth}_{seed}.bed"));
    if !map.exists() {
        run_ok(&[
            "simulate",
            "blocks",
            "-o",
            map.to_str().unwrap(),
            "--truth-boundaries",
            truth.to_str().unwrap(),
            "--chroms",
            "2",
            "--bins",
            "800",
            "--depth",
            depth,
            "--enrichment",
            "1",
            "--bias-sd",
            "0.3",
            "--dead-bins",
            "0.01",
            "--seed",
            seed,
        ]);
        run_ok(&["balance", map.to_str().unwrap(), "--store", "--cis-only"]);
    }
    let calls = dir.join("calls.bed");
    let track = dir.join("track.tsv");
    let mut tads = vec![
        "tads",
        map.to_str().unwrap(),
        "--boundaries",
        calls.to_str().unwrap(),
        "-o",
        track.to_str().unwrap(),
    ];
    tads.extend_from_slice(args);
    run_ok(&tads);
    let score = run_ok(&[
        "score",
        "boundaries",
        "--truth",
        truth.to_str().unwrap(),
        calls.to_str().unwrap(),
        "--bin-size",
        "10000",
    ]);
    let table = parse_table(&score);
    let f1 = table.header.iter().position(|h| h == "f1").unwrap();
    table.rows[0][f1].parse().unwrap()
}

#[test]
fn callers_recover_the_boundaries_of_synthetic_maps() {
    let dir = tempfile::tempdir().unwrap();
    // Moderate depth (about 400 contacts per bin): insulation reaches F1 >= 0.9.
    for seed in ["1", "2"] {
        let f1 = synthetic_f1(dir.path(), "3e5", seed, &["--window", "200k"]);
        assert!(f1 >= 0.9, "insulation F1 {f1} (seed {seed})");
    }
    // Deep maps: every caller finds the blocks (Armatus also reports domain ends next to gaps,
    // which costs it precision).
    for (args, bar) in [
        (&["--window", "200k"][..], 0.95),
        (&["--method", "directionality", "--window", "200k"][..], 0.9),
        (&["--method", "topdom"][..], 0.9),
        (&["--method", "armatus", "--max-domain", "1M"][..], 0.75),
    ] {
        let f1 = synthetic_f1(dir.path(), "1e7", "1", args);
        assert!(f1 >= bar, "{args:?}: F1 {f1} < {bar}");
    }
    // Nothing to find in a map with no contacts to speak of.
    let f1 = synthetic_f1(dir.path(), "3e3", "1", &["--window", "200k"]);
    assert!(f1 < 0.3, "F1 {f1} on an almost empty map");
}

/// Issue 26: bins whose directionality index is NaN (masked: no weight, or too close to one)
/// get no HMM state (`nan`), every other bin one of the three.
#[test]
fn masked_bins_get_no_hmm_state() {
    let table = crate::parse_table(&run_ok(&[
        "tads",
        &data(YEAST),
        "--method",
        "directionality",
        "--window",
        "50k",
    ]));
    let index = table
        .header
        .iter()
        .position(|h| h == "directionality_index_50000")
        .unwrap();
    let state = table.header.iter().position(|h| h == "di_state").unwrap();
    let mut masked = 0;
    for row in &table.rows {
        if row[index] == "nan" {
            masked += 1;
            assert_eq!(row[state], "nan", "{row:?}");
        } else {
            assert!(
                ["upstream", "neutral", "downstream"].contains(&row[state].as_str()),
                "{row:?}"
            );
        }
    }
    assert!(masked > 50, "{masked} masked bins");
}

/// Issue 51: as cooltools 0.7.1, insulation and directionality leave out by default the
/// diagonals that the weights were balanced without (the weight column's `ignore_diags`):
/// insulation that of --weight-name, directionality that of `weight`.
#[test]
fn the_default_ignore_diags_is_the_one_stored_with_the_weights() {
    let dir = tempfile::tempdir().unwrap();
    let copy = dir.path().join("yeast.cool").to_string_lossy().into_owned();
    std::fs::copy(data(YEAST), &copy).unwrap();
    let balance = |name: &str| {
        run_ok(&[
            "balance",
            &copy,
            "--store",
            "--name",
            name,
            "--ignore-diags",
            "1",
            "--force",
        ])
    };
    balance("w1");
    let insulation = |extra: &[&str]| {
        let args = ["tads", &copy, "--window", "50000", "--weight-name", "w1"];
        run_ok(&[&args[..], extra].concat())
    };
    let default = insulation(&[]);
    assert_eq!(default, insulation(&["--ignore-diags", "1"]));
    assert_ne!(default, insulation(&["--ignore-diags", "2"]));
    balance("weight");
    let directionality = |extra: &[&str]| {
        let args = [
            "tads",
            &copy,
            "--method",
            "directionality",
            "--window",
            "50000",
        ];
        run_ok(&[&args[..], extra].concat())
    };
    let default = directionality(&[]);
    assert_eq!(default, directionality(&["--ignore-diags", "1"]));
    assert_ne!(default, directionality(&["--ignore-diags", "2"]));
}
