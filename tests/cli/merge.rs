//! `contactmap merge`: replicates summed into a valid cooler; maps on other bins refused.

use super::*;

#[test]
fn a_map_merged_with_itself_has_every_count_doubled() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("twice.cool");
    let out = out.to_string_lossy().into_owned();
    let yeast = data("yeast.10kb.cool");
    run_ok(&["merge", &yeast, &yeast, "-o", &out]);
    // The output is a valid cooler (checked end to end) with no weight column.
    run_ok(&["validate", &out]);
    let single = run_ok(&["dump", &yeast]);
    let merged = run_ok(&["dump", &out]);
    let (a, b): (Vec<&str>, Vec<&str>) = (single.lines().collect(), merged.lines().collect());
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        let (x, y): (Vec<&str>, Vec<&str>) = (x.split('\t').collect(), y.split('\t').collect());
        assert_eq!(x[..2], y[..2]);
        let (cx, cy): (u64, u64) = (x[2].parse().unwrap(), y[2].parse().unwrap());
        assert_eq!(cy, 2 * cx, "{x:?} {y:?}");
    }
    let bins = run_ok(&["dump", "-t", "bins", "-H", &out]);
    assert_eq!(bins.lines().next(), Some("chrom\tstart\tend"));
}

#[test]
fn an_mcool_output_sums_then_coarsens() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.mcool");
    let out = out.to_string_lossy().into_owned();
    let dm6 = data("cooler_test_file.mcool::/resolutions/100000");
    run_ok(&[
        "merge",
        &dm6,
        &dm6,
        "-o",
        &out,
        "--resolutions",
        "100000,1000000",
    ]);
    let info = run_ok(&["info", &format!("{out}::/resolutions/1000000"), "--json"]);
    let single = run_ok(&[
        "info",
        &data("cooler_test_file.mcool::/resolutions/1000000"),
        "--json",
    ]);
    let sum = |text: &str| -> f64 {
        let v: serde_json::Value = serde_json::from_str(text).unwrap();
        v["sum"].as_f64().unwrap()
    };
    assert_eq!(sum(&info), 2.0 * sum(&single));
}

#[test]
fn maps_on_other_bins_are_refused_with_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bad.cool");
    let out_text = out.to_string_lossy().into_owned();
    let message = run_err(&[
        "merge",
        &data("yeast.10kb.cool"),
        &data("cooler_test_file.mcool::/resolutions/100000"),
        "-o",
        &out_text,
    ]);
    assert!(
        message.contains("its bins differ from those of"),
        "{message}"
    );
    assert!(message.contains("8 chromosomes instead of 18"), "{message}");
    assert!(!out.exists());
    let message = run_err(&["merge", &data("yeast.10kb.cool"), "-o", "x.txt"]);
    assert!(
        message.contains("merge writes .cool, .mcool or .hic"),
        "{message}"
    );
}
