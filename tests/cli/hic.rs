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
    // The .hic stores Juicer-style divisive ICE; the mcool's `weight` is cooler's multiplicative
    // ICE of the same contacts. After inversion they agree to float32 precision (.hic v9 vectors).
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
    for (a, b) in ice.iter().zip(&weight) {
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
    let bins = ["-t", "bins", "--float-format", ".17g"];
    assert_eq!(
        run_ok(&[&["dump", cool][..], &bins[..]].concat()),
        run_ok(&[&["dump", &hic][..], &bins[..]].concat())
    );
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
