//! Juicer .hic through the binary: parity with the .mcool of the same data, hictk-written files,
//! conversions, errors.

use crate::{data, run_err, run_ok};

#[test]
fn hic_and_mcool_hold_the_same_pixels() {
    // The README of the fixtures: nnz 890,384, sum 119,208,613 in both files at 100 kb.
    let hic = run_ok(&["dump", &data("hic_test_file.hic")]);
    let mcool = run_ok(&["dump", &data("cooler_test_file.mcool::/resolutions/100000")]);
    assert_eq!(hic.lines().count(), 890_384);
    assert_eq!(hic, mcool);
    let region = [
        "-r",
        "chr2L:5,000,000-9,000,000",
        "--region2",
        "chr3R",
        "--join",
    ];
    let hic_region = run_ok(&[&["dump", &data("hic_test_file.hic")][..], &region[..]].concat());
    let mcool_region = run_ok(
        &[
            &["dump", &data("cooler_test_file.mcool::/resolutions/100000")][..],
            &region[..],
        ]
        .concat(),
    );
    assert!(!hic_region.is_empty());
    assert_eq!(hic_region, mcool_region);
}

fn column(table: &str, name: &str) -> Vec<f64> {
    let mut lines = table.lines();
    let header: Vec<&str> = lines.next().unwrap().split('\t').collect();
    let k = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split('\t').nth(k).unwrap().parse().unwrap_or(f64::NAN))
        .collect()
}

#[test]
fn hic_ice_vector_inverted_equals_coolers_ice_weight() {
    // The .hic stores Juicer-style divisive ICE (`dump -t bins` prints it as stored); the mcool's
    // `weight` is cooler's multiplicative ICE of the same contacts. Inverted, they agree to
    // float32 precision (.hic v9 vectors).
    let args = ["-t", "bins", "-H", "--float-format", ".17g"];
    let hic = run_ok(&[&["dump", &data("hic_test_file.hic")][..], &args[..]].concat());
    let mcool = run_ok(
        &[
            &["dump", &data("cooler_test_file.mcool::/resolutions/100000")][..],
            &args[..],
        ]
        .concat(),
    );
    let (ice, weight) = (column(&hic, "ICE"), column(&mcool, "weight"));
    assert_eq!(ice.len(), 1380);
    let mut compared = 0;
    for (a, b) in ice.iter().map(|v| 1.0 / v).zip(&weight) {
        assert_eq!(a.is_nan(), b.is_nan());
        if !a.is_nan() {
            assert!((a - b).abs() <= 1e-6 * b.abs(), "{a} vs {b}");
            compared += 1;
        }
    }
    assert!(compared > 1300);
}

#[test]
fn hictk_written_multires_hic_equals_hictkpy() {
    let ours = run_ok(&[
        "dump",
        "--join",
        "-r",
        "chr1",
        "--region2",
        "chr2",
        &data("CN.mm9.multires.hic::/resolutions/20000000"),
    ]);
    let reference =
        std::fs::read_to_string(data("reference/CN.mm9.multires.hic.20000000.chr1_chr2.tsv"))
            .unwrap();
    assert_eq!(ours, reference);
    // Its 10 Mb level holds the cooler it was written from.
    assert_eq!(
        run_ok(&["dump", &data("CN.mm9.multires.hic::/resolutions/10000000")]),
        run_ok(&["dump", &data("CN.mm9.10000kb.cool")])
    );
}

#[test]
fn hic_to_cool_and_mcool_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let cool = dir.path().join("from_hic.cool");
    let cool = cool.to_str().unwrap();
    let hic = data("hic_test_file.hic");
    run_ok(&["convert", &hic, cool]);
    assert_eq!(run_ok(&["dump", cool]), run_ok(&["dump", &hic]));
    // The .cool holds ICE multiplicative (cooler multiplies by columns not named KR / VC /
    // VC_SQRT), the .hic divisive, each printed as stored: one is the other's inverse.
    let bins = ["-t", "bins", "-H", "--float-format", ".17g"];
    let ice_cool = column(&run_ok(&[&["dump", cool][..], &bins[..]].concat()), "ICE");
    let ice_hic = column(&run_ok(&[&["dump", &hic][..], &bins[..]].concat()), "ICE");
    assert_eq!(ice_cool.len(), ice_hic.len());
    for (a, b) in ice_cool.iter().zip(&ice_hic) {
        assert_eq!(a.is_nan(), b.is_nan() || *b == 0.0, "{a} vs divisive {b}");
        if !a.is_nan() {
            assert!((a * b - 1.0).abs() < 1e-12, "{a} vs divisive {b}");
        }
    }
    let mcool = dir.path().join("from_hic.mcool");
    let mcool = mcool.to_str().unwrap();
    run_ok(&["convert", &hic, mcool, "--resolutions", "100000,1000000"]);
    // Juicer's own 1 Mb level (in the mcool made by hic2cool) equals our coarsening of the .hic.
    assert_eq!(
        run_ok(&["dump", &format!("{mcool}::/resolutions/1000000")]),
        run_ok(&[
            "dump",
            &data("cooler_test_file.mcool::/resolutions/1000000")
        ])
    );
}

#[test]
fn hic_errors_are_clean() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = std::fs::read(data("hic_test_file.hic")).unwrap();
    for keep in [3, 10, 100, 5000, bytes.len() / 2, bytes.len() - 100] {
        let path = dir.path().join(format!("cut-{keep}.hic"));
        std::fs::write(&path, &bytes[..keep]).unwrap();
        let path = path.to_str().unwrap();
        for command in ["info", "dump"] {
            let line = run_err(&[command, path]);
            assert!(line.contains(path), "{line}");
        }
    }
    let line = run_err(&["dump", &data("hic_test_file.hic::/resolutions/5000")]);
    assert!(line.contains("5000") && line.contains("100000"), "{line}");
    let line = run_err(&["dump", &data("CN.mm9.multires.hic")]);
    assert!(
        line.contains("10000000") && line.contains("50000000"),
        "{line}"
    );
    let line = run_err(&["dump", "--balanced=KR", &data("hic_test_file.hic")]);
    assert!(line.contains("KR") && line.contains("ICE"), "{line}");
}

/// A `data/hic_layouts/` reference table of `bin1_id bin2_id count` (hictkpy's fetch, with a
/// header line), as dump prints it.
fn layout_pixels(name: &str) -> String {
    let text = std::fs::read_to_string(data(&format!("hic_layouts/{name}"))).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("bin1_id\tbin2_id\tcount"));
    lines.map(|l| format!("{l}\n")).collect()
}

/// nnz and sum of a `bin1_id bin2_id count` dump.
fn totals(dump: &str) -> (usize, f64) {
    let sum = dump
        .lines()
        .map(|l| l.split('\t').nth(2).unwrap().parse::<f64>().unwrap())
        .sum();
    (dump.lines().count(), sum)
}

fn info_field(info: &str, key: &str) -> String {
    info.lines()
        .find_map(|l| l.strip_prefix(key).filter(|rest| rest.starts_with(' ')))
        .unwrap_or_else(|| panic!("no {key} in {info}"))
        .trim()
        .to_string()
}

#[test]
fn hic_storing_both_triangles_is_read_once() {
    // scripts/fixtures/hic_layouts.py: intra matrices hold every off-diagonal pixel twice, the
    // lower record with 1000 more; the reference is hictkpy 1.4 on the same pixels stored once
    // (equal to hictkpy's bin1 <= bin2 pixels of this file).
    let path = data("hic_layouts/both_triangles.hic");
    let reference = layout_pixels("both_triangles.pixels.tsv");
    let out = crate::run(&["dump", &path]);
    assert!(out.status.success() && out.stderr.is_empty());
    let dump = String::from_utf8(out.stdout).unwrap();
    assert_eq!(dump, reference);
    let (nnz, sum) = totals(&reference);
    assert_eq!(nnz, 378);
    let info = run_ok(&["info", &path]);
    assert_eq!(info_field(&info, "nnz"), nnz.to_string());
    assert_eq!(info_field(&info, "sum").parse::<f64>().unwrap(), sum);
    // ICE on it equals cooler's balance of hictkpy's pixels
    let weights = run_ok(&["balance", &path]);
    let ours: Vec<f64> = weights
        .lines()
        .skip(1)
        .map(|l| l.split('\t').nth(3).unwrap().parse().unwrap())
        .collect();
    let text = std::fs::read_to_string(data("hic_layouts/both_triangles.ice.tsv")).unwrap();
    let cooler: Vec<f64> = text.lines().skip(1).map(|l| l.parse().unwrap()).collect();
    assert_eq!(ours.len(), cooler.len());
    assert!(cooler.iter().any(|w| w.is_nan()) && cooler.iter().any(|w| !w.is_nan()));
    for (a, b) in ours.iter().zip(&cooler) {
        assert_eq!(a.is_nan(), b.is_nan(), "{a} vs {b}");
        if !b.is_nan() {
            assert!((a - b).abs() <= 1e-6 * b.abs(), "{a} vs {b}");
        }
    }
}

/// The warnings of a successful run, and that they come last on standard error.
fn warnings_of(args: &[&str]) -> Vec<String> {
    let out = crate::run(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{args:?}: {stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    let first = lines.iter().position(|l| l.contains("warning:"));
    let warnings: Vec<String> = lines
        .iter()
        .filter(|l| l.contains("warning:"))
        .map(|l| l.to_string())
        .collect();
    if let Some(first) = first {
        assert_eq!(first + warnings.len(), lines.len(), "{args:?}: {stderr}");
    }
    warnings
}

#[test]
fn hic_records_past_a_chromosome_end_are_dropped_with_one_warning() {
    // Five records past the last bin of chr18 / chr19; hictkpy 1.4 drops them.
    let path = data("hic_layouts/past_end.hic");
    let reference = layout_pixels("past_end.pixels.tsv");
    let out = crate::run(&["dump", &path]);
    assert!(out.status.success());
    assert_eq!(String::from_utf8(out.stdout).unwrap(), reference);
    let dir = tempfile::tempdir().unwrap();
    let cool = dir.path().join("out.cool");
    let cool = cool.to_str().unwrap();
    for args in [
        &["dump", &path][..],
        &["convert", &path, cool],
        &["balance", &path],
        &["expected", "--raw", &path],
        &["tads", "--raw", "--window", "20M", &path],
    ] {
        let warnings = warnings_of(args);
        assert_eq!(warnings.len(), 1, "{args:?}: {warnings:?}");
        assert!(
            warnings[0].starts_with(&format!("contactmap: warning: {path}: dropped "))
                && warnings[0].contains("past the end of a chromosome"),
            "{}",
            warnings[0]
        );
    }
    // the converted file holds hictkpy's pixels
    assert_eq!(run_ok(&["dump", cool]), reference);
    // a clean file warns of nothing
    assert!(warnings_of(&["dump", &data("hic_layouts/both_triangles.hic")]).is_empty());
}

#[test]
fn hic_header_with_a_huge_chromosome_fails_in_one_line() {
    // chr17 of 175,921,883,957,872 bp used to abort with "memory allocation ... failed".
    let path = data("hic_layouts/huge_chrom.hic");
    let dir = tempfile::tempdir().unwrap();
    let cool = dir.path().join("out.cool");
    let cool = cool.to_str().unwrap();
    for args in [
        &["dump", &path][..],
        &["info", &path],
        &["balance", &path],
        &["expected", "--raw", &path],
        &["tads", "--raw", "--window", "20M", &path],
        &["convert", &path, cool],
    ] {
        let line = run_err(args);
        assert!(
            line.contains(&path)
                && line.contains("length of chromosome 'chr17'")
                && line.contains("175921883957872"),
            "{args:?}: {line}"
        );
    }
    assert!(!std::path::Path::new(cool).exists());
}

#[test]
fn fragment_only_hic_is_a_clear_error_in_info_and_dump() {
    let path = data("hic_layouts/fragment_only.hic");
    for command in ["info", "dump"] {
        let line = run_err(&[command, &path]);
        assert!(
            line.contains(&path) && line.contains("no base-pair resolution"),
            "{command}: {line}"
        );
    }
}
