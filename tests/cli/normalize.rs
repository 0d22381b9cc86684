//! `contactmap normalize` against cooltools' observed/expected.

use std::collections::HashMap;

use crate::{data, run_err, run_ok};

fn pixels(text: &str) -> HashMap<(u64, u64), f64> {
    text.lines()
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            (
                (f[0].parse().unwrap(), f[1].parse().unwrap()),
                f[2].parse().unwrap(),
            )
        })
        .collect()
}

fn normalize(args: &[&str]) -> HashMap<(u64, u64), f64> {
    let base = [
        "normalize",
        &data("CN.mm9.10000kb.cool"),
        "-",
        "--to",
        "coo",
    ];
    pixels(&run_ok(&[&base[..], args].concat()))
}

#[test]
fn oe_equals_cooltools_obs_over_exp_on_cis_pixels() {
    let reference =
        pixels(&std::fs::read_to_string(data("reference/CN.mm9.10000kb.cis_oe.tsv")).unwrap());
    let ours = normalize(&[]);
    assert_eq!(ours.len(), reference.len());
    for (key, value) in &reference {
        let got = ours
            .get(key)
            .unwrap_or_else(|| panic!("pixel {key:?} missing"));
        assert!(
            (got - value).abs() <= 1e-10 * value.abs(),
            "{key:?}: {got} vs {value}"
        );
    }
}

#[test]
fn log2oe_is_the_log_of_oe_and_expected_can_be_read_back() {
    let oe = normalize(&[]);
    let log2 = normalize(&["--method", "log2oe"]);
    assert_eq!(oe.len(), log2.len());
    for (key, value) in &oe {
        assert!((log2[key] - value.log2()).abs() < 1e-12);
    }
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("expected.tsv");
    run_ok(&[
        "expected",
        &data("CN.mm9.10000kb.cool"),
        "-o",
        table.to_str().unwrap(),
    ]);
    let from_file = normalize(&["--expected", table.to_str().unwrap()]);
    assert_eq!(from_file.len(), oe.len());
    for (key, value) in &oe {
        assert!((from_file[key] - value).abs() <= 1e-12 * value.abs());
    }
}

#[test]
fn zscore_and_cool_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("z.cool");
    let out = out.to_str().unwrap();
    run_ok(&[
        "normalize",
        &data("CN.mm9.10000kb.cool"),
        out,
        "--method",
        "zscore",
    ]);
    let info: serde_json::Value = serde_json::from_str(&run_ok(&["info", "--json", out])).unwrap();
    assert_eq!(info["count-type"], "float");
    let z = pixels(&run_ok(&["dump", out, "--float-format", ".17g"]));
    let oe = normalize(&[]);
    // z is undefined where a diagonal has no spread (e.g. the last diagonals, one valid pixel)
    assert!(
        z.len() <= oe.len() && z.len() + 40 >= oe.len(),
        "{} of {}",
        z.len(),
        oe.len()
    );
    // above-average pixels have positive z-scores and vice versa
    for (key, value) in &z {
        assert_eq!(*value > 0.0, oe[key] > 1.0, "{key:?}");
    }
}

#[test]
fn normalize_errors_are_clear() {
    let line = run_err(&[
        "normalize",
        &data("hg19.GM12878-MboI.matrix.2000kb.cool"),
        "-",
        "--to",
        "coo",
    ]);
    assert!(line.contains("this map has no weights"), "{line}");
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.tsv");
    std::fs::write(
        &bad,
        "region1\tregion2\tdist\tn_valid\tbalanced.avg\nchrZ\tchrZ\t0\t1\t1.0\n",
    )
    .unwrap();
    let line = run_err(&[
        "normalize",
        &data("CN.mm9.10000kb.cool"),
        "-",
        "--to",
        "coo",
        "--expected",
        bad.to_str().unwrap(),
    ]);
    assert!(line.contains("chrZ"), "{line}");
}
