//! `contactmap info` against the totals computed by cooler and hictkpy.

use crate::{data, reference_totals, run_ok};

#[test]
fn info_matches_cooler_and_hictkpy_totals() {
    let totals = reference_totals();
    assert!(totals.len() >= 9, "reference table is incomplete");
    for (uri, nbins, nnz, sum) in totals {
        let uri = uri.replacen("data/", &data(""), 1);
        let json: serde_json::Value =
            serde_json::from_str(&run_ok(&["info", "--json", &uri])).expect("valid JSON");
        assert_eq!(json["nbins"], nbins, "{uri}");
        assert_eq!(json["nnz"], nnz, "{uri}");
        assert_eq!(json["sum"].as_f64().unwrap(), sum, "{uri}");
    }
}

#[test]
fn info_lists_the_resolutions_of_an_mcool() {
    let text = run_ok(&["info", &data("toy.symm.upper.2.mcool")]);
    assert!(text.contains("resolutions     5"), "{text}");
    for r in ["2", "4", "8", "16", "32"] {
        assert!(
            text.lines().any(|l| l.split_whitespace().next() == Some(r)),
            "{text}"
        );
    }
}

#[test]
fn info_reports_old_and_string_versioned_coolers() {
    // format-version stored as the string "2", variable-size bins.
    let json: serde_json::Value = serde_json::from_str(&run_ok(&[
        "info",
        "--json",
        &data("cooler_variable_bins_test_file.cool"),
    ]))
    .unwrap();
    assert_eq!(json["file-format"], "cool (format-version 2)");
    assert_eq!(json["bin-type"], "variable");
}

#[test]
fn info_says_divisive_weights_are_inverted() {
    let text = run_ok(&["info", &data("cooler_test_file.mcool::/resolutions/100000")]);
    assert!(text.contains("weight column 'KR' is divisive"), "{text}");
    assert!(
        !text.contains("weight column 'weight' is divisive"),
        "{text}"
    );
}

/// Issue 26: `info --json` shows a cooler's attributes as cooler does (`cooler.Cooler(uri).info`,
/// data/reference/cooler_info.json): string attributes that are JSON decoded (`id` null, not
/// "null"; `metadata` an object, not "{}"), every other value equal; the text report keeps its
/// labels in one column (genome-assembly is the longest).
#[test]
fn info_json_shows_attributes_as_cooler() {
    let reference: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(crate::data("reference/cooler_info.json")).unwrap(),
    )
    .unwrap();
    for (uri, info) in reference.as_object().unwrap() {
        let ours: serde_json::Value =
            serde_json::from_str(&crate::run_ok(&["info", "--json", &crate::data(uri)])).unwrap();
        for (key, value) in info.as_object().unwrap() {
            assert_eq!(&ours[key], value, "{uri}: {key}");
        }
    }
    let text = crate::run_ok(&["info", &crate::data("yeast.10kb.cool")]);
    // Where each line's value starts: after its label and the spaces that follow.
    let value_start = |line: &str| {
        let label = line.split(' ').next().unwrap().len();
        line.len() - line[label..].trim_start().len()
    };
    let columns: Vec<usize> = text.lines().map(value_start).collect();
    assert!(columns.windows(2).all(|w| w[0] == w[1]), "{text}");
}
