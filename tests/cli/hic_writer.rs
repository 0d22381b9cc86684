//! `contactmap convert ... OUT.hic`: the Juicer .hic writer, read back by our reader and compared
//! with the .mcool levels (themselves equal to `cooler zoomify`'s), the normalisations `balance`
//! computes, and the expected values hictk's writer stores (data/CN.mm9.multires.hic).

use std::path::Path;

use contactmap::io::hic::HicReader;

use super::*;

/// The `dump` of `uri` (pixels, or bins with -t bins), as lines.
fn dump(args: &[&str]) -> Vec<String> {
    run_ok(&[&["dump", "-H"], args].concat())
        .lines()
        .map(String::from)
        .collect()
}

#[test]
fn every_resolution_holds_the_mcool_levels_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let hic = dir.path().join("y.hic").to_string_lossy().into_owned();
    let mcool = dir.path().join("y.mcool").to_string_lossy().into_owned();
    let yeast = data("yeast.10kb.cool");
    let resolutions = "10000,20000,50000,200000";
    run_ok(&[
        "convert",
        &yeast,
        &hic,
        "--resolutions",
        resolutions,
        "--normalizations",
        "none",
    ]);
    run_ok(&["convert", &yeast, &mcool, "--resolutions", resolutions]);
    run_ok(&["validate", &hic]);
    for r in resolutions.split(',') {
        let from_hic = dump(&[&format!("{hic}::/resolutions/{r}")]);
        let from_mcool = dump(&[&format!("{mcool}::/resolutions/{r}")]);
        assert!(from_hic.len() > 1000, "{r}: {} pixels", from_hic.len());
        assert_eq!(from_hic, from_mcool, "{r}");
    }
    let info: serde_json::Value = serde_json::from_str(&run_ok(&["info", &hic, "--json"])).unwrap();
    assert_eq!(info["file-format"], "hic (multi-resolution)", "{info}");
    assert_eq!(info["levels"].as_array().unwrap().len(), 4, "{info}");
}

#[test]
fn stored_vectors_are_the_normalisations_balance_computes() {
    let dir = tempfile::tempdir().unwrap();
    let hic = dir.path().join("d.hic").to_string_lossy().into_owned();
    let dm6 = data("cooler_test_file.mcool::/resolutions/100000");
    run_ok(&["convert", &dm6, &hic, "--resolutions", "100000,500000"]);
    for r in ["100000", "500000"] {
        let uri = format!("{hic}::/resolutions/{r}");
        // -t bins shows a .hic's vectors as stored (divisive)
        let bins = parse_table(&run_ok(&[
            "dump",
            "-t",
            "bins",
            "-H",
            "--float-format",
            ".17g",
            &uri,
        ]));
        for (method, column) in [
            ("vc", "VC"),
            ("vc-sqrt", "VC_SQRT"),
            ("kr", "KR"),
            ("scale", "SCALE"),
        ] {
            let col = bins.header.iter().position(|h| h == column).expect(column);
            let table = parse_table(
                &run_ok(&["balance", &uri, "--method", method, "--cis-only", "-o", "-"])
                    .lines()
                    .filter(|l| !l.starts_with('#'))
                    .collect::<Vec<_>>()
                    .join("\n"),
            );
            assert_eq!(table.rows.len(), bins.rows.len());
            let mut n_values = 0;
            for (stored, computed) in bins.rows.iter().zip(&table.rows) {
                let number = |t: &str| {
                    if t.is_empty() || t == "nan" {
                        f64::NAN
                    } else {
                        t.parse::<f64>().unwrap()
                    }
                };
                let (v, w) = (number(&stored[col]), number(&computed[3]));
                if w.is_finite() && w > 0.0 {
                    // float32 of the divisive value 1 / w
                    assert_eq!(v, (1.0 / w) as f32 as f64, "{r} {column} {stored:?}");
                    n_values += 1;
                } else {
                    assert!(v.is_nan(), "{r} {column} {stored:?}");
                }
            }
            assert!(n_values > bins.rows.len() / 2, "{r} {column}");
        }
    }
}

#[test]
fn expected_values_equal_those_hictks_writer_stores() {
    let dir = tempfile::tempdir().unwrap();
    let hic = dir.path().join("cn.hic");
    run_ok(&[
        "convert",
        &data("CN.mm9.10000kb.cool"),
        &hic.to_string_lossy(),
        "--resolutions",
        "10000000,20000000,50000000",
        "--normalizations",
        "kr",
    ]);
    let hictk = data("CN.mm9.multires.hic");
    for r in [10_000_000u64, 20_000_000, 50_000_000] {
        let ours = HicReader::open(&hic, Some(r))
            .unwrap()
            .expected_values()
            .unwrap();
        let theirs = HicReader::open(Path::new(&hictk), Some(r))
            .unwrap()
            .expected_values()
            .unwrap();
        // ours: raw then KR; hictk stores the raw vector only
        assert_eq!(ours.len(), 2);
        assert_eq!(ours[1].normalization, "KR");
        assert_eq!(theirs.len(), 1);
        let (a, b) = (&ours[0], &theirs[0]);
        assert_eq!(a.normalization, "NONE");
        assert_eq!(a.values.len(), b.values.len(), "{r}");
        for (x, y) in a.values.iter().zip(&b.values) {
            assert!((x - y).abs() <= 1e-6 * y.abs(), "{r}: {x} {y}");
        }
        assert_eq!(a.chrom_scale_factors.len(), b.chrom_scale_factors.len());
        for (x, y) in a.chrom_scale_factors.iter().zip(&b.chrom_scale_factors) {
            assert_eq!(x.0, y.0);
            assert!((x.1 - y.1).abs() <= 1e-6 * y.1.abs(), "{r}: {x:?} {y:?}");
        }
    }
}

#[test]
fn bad_requests_exit_2_without_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.hic");
    let out_s = out.to_string_lossy().into_owned();
    let yeast = data("yeast.10kb.cool");
    let line = run_err(&["convert", &yeast, &out_s, "--normalizations", "KR,FOO"]);
    assert!(line.contains("'FOO'"), "{line}");
    let line = run_err(&["convert", &yeast, &out_s, "--resolutions", "15000"]);
    assert!(line.contains("15000"), "{line}");
    let line = run_err(&[
        "convert",
        &data("cooler_variable_bins_test_file.cool"),
        &out_s,
    ]);
    assert!(line.contains("fixed"), "{line}");
    assert!(!out.exists());
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "no temporary left"
    );
}

#[test]
fn merge_and_zoomify_write_hic_too() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let yeast = data("yeast.10kb.cool");
    run_ok(&["merge", &yeast, &yeast, "-o", &path("m.hic")]);
    run_ok(&["merge", &yeast, &yeast, "-o", &path("m.cool")]);
    assert_eq!(dump(&[&path("m.hic")]), dump(&[&path("m.cool")]));
    run_ok(&[
        "zoomify",
        &yeast,
        "-r",
        "10000,40000",
        "--balance",
        "-o",
        &path("z.hic"),
    ]);
    run_ok(&[
        "zoomify",
        &yeast,
        "-r",
        "10000,40000",
        "-o",
        &path("z.mcool"),
    ]);
    for r in ["10000", "40000"] {
        assert_eq!(
            dump(&[&format!("{}::/resolutions/{r}", path("z.hic"))]),
            dump(&[&format!("{}::/resolutions/{r}", path("z.mcool"))]),
            "{r}"
        );
    }
    let info: serde_json::Value =
        serde_json::from_str(&run_ok(&["info", &path("z.hic"), "--json"])).unwrap();
    let weights = info["levels"][1]["weights"].to_string();
    for name in ["ICE", "KR", "SCALE", "VC", "VC_SQRT"] {
        assert!(weights.contains(&format!("\"{name}\"")), "{weights}");
    }
}
