//! `contactmap zoomify`: levels that keep the counts, balanced as `cooler zoomify --balance`.

use super::*;

#[test]
fn levels_keep_the_counts_and_balance_as_cooler_zoomify() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("y.mcool");
    let out = out.to_string_lossy().into_owned();
    let yeast = data("yeast.10kb.cool");
    run_ok(&[
        "zoomify",
        &yeast,
        "-r",
        "10000,20000,40000",
        "--balance",
        "-o",
        &out,
    ]);
    run_ok(&["validate", &out]);
    let totals = |uri: &str| -> (u64, f64) {
        let v: serde_json::Value = serde_json::from_str(&run_ok(&["info", uri, "--json"])).unwrap();
        (v["nnz"].as_u64().unwrap(), v["sum"].as_f64().unwrap())
    };
    let (base_nnz, base_sum) = totals(&yeast);
    for r in [10000, 20000, 40000] {
        let (nnz, sum) = totals(&format!("{out}::/resolutions/{r}"));
        assert_eq!(sum, base_sum, "{r}");
        assert!(nnz <= base_nnz);
    }
    // The 20 kb weights equal those cooler zoomify --balance stored.
    let stored = run_ok(&[
        "dump",
        "-t",
        "bins",
        "-H",
        "--float-format",
        ".17g",
        &format!("{out}::/resolutions/20000"),
    ]);
    let reference =
        std::fs::read_to_string(data("reference/yeast_20kb.zoomify_balance.weight.tsv")).unwrap();
    let (a, b): (Vec<&str>, Vec<&str>) = (stored.lines().collect(), reference.lines().collect());
    assert_eq!(a.len(), b.len());
    assert_eq!(a[0], b[0]);
    for (x, y) in a[1..].iter().zip(&b[1..]) {
        let (x, y): (Vec<&str>, Vec<&str>) = (x.split('\t').collect(), y.split('\t').collect());
        assert_eq!(x[..3], y[..3]);
        // `dump -t bins` leaves NaN empty, as cooler dump does.
        let number = |t: &str| {
            if t.is_empty() {
                f64::NAN
            } else {
                t.parse::<f64>().unwrap()
            }
        };
        let (wx, wy) = (number(x[3]), number(y[3]));
        assert_eq!(wx.is_nan(), wy.is_nan(), "{x:?} {y:?}");
        if !wy.is_nan() {
            assert!((wx - wy).abs() <= 1e-12 * wy, "{x:?} {y:?}");
        }
    }
}

#[test]
fn bad_resolutions_and_outputs_fail_with_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("z.mcool");
    let out_text = out.to_string_lossy().into_owned();
    let yeast = data("yeast.10kb.cool");
    let message = run_err(&["zoomify", &yeast, "-r", "15000", "-o", &out_text]);
    assert!(
        message.contains("15000 is not a multiple of the input's bin size 10000"),
        "{message}"
    );
    assert!(!out.exists());
    let message = run_err(&["zoomify", &yeast, "-o", "z.cool"]);
    assert!(message.contains("zoomify writes an .mcool"), "{message}");
}
