//! `contactmap validate`: each defect class planted (from Rust, through the `hdf5` crate) into a
//! copy of a real fixture is found at its location; pristine fixtures are valid; `--repair`
//! writes a copy that is valid and, where the defect was a reordering, holds the original pixels.

use std::path::{Path, PathBuf};
use std::process::Output;

use crate::{data, run, run_err, run_ok};

/// A copy of fixture `name` in a fresh temporary folder.
fn copy(name: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(Path::new(name).file_name().unwrap());
    std::fs::copy(data(name), &path).unwrap();
    (dir, path)
}

fn open_rw(path: &Path) -> hdf5::File {
    let mut builder = hdf5::File::with_options();
    builder.fapl().file_locking(false);
    builder.open_rw(path).unwrap()
}

/// Read dataset `name` as i64, let `edit` change it (same length), write it back.
fn edit_ints(path: &Path, name: &str, edit: impl FnOnce(&mut Vec<i64>)) {
    let file = open_rw(path);
    let dataset = file.dataset(name).unwrap();
    let mut values = dataset.read_raw::<i64>().unwrap();
    edit(&mut values);
    dataset.write_raw(&values).unwrap();
}

/// Replace dataset `name` by a new chunked one holding `values`.
fn replace<T: hdf5::H5Type>(path: &Path, name: &str, values: &[T]) {
    let file = open_rw(path);
    file.unlink(name).unwrap();
    file.new_dataset_builder()
        .with_data(values)
        .chunk(values.len().clamp(1, 1000))
        .deflate(6)
        .create(name)
        .unwrap();
}

fn validate_json(path: &Path) -> (Option<i32>, serde_json::Value) {
    let out = run(&["validate", "--json", path.to_str().unwrap()]);
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (
        out.status.code(),
        serde_json::from_slice(&out.stdout).expect("one JSON document"),
    )
}

/// The (class, group, location) of every finding.
fn findings(json: &serde_json::Value) -> Vec<(String, String, String)> {
    json["findings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            (
                f["class"].as_str().unwrap().to_string(),
                f["group"].as_str().unwrap().to_string(),
                f["location"].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

/// Exit 1 with exactly the findings `expected`.
fn assert_findings(path: &Path, expected: &[(&str, &str, &str)]) -> serde_json::Value {
    let (code, json) = validate_json(path);
    let found = findings(&json);
    let expected: Vec<(String, String, String)> = expected
        .iter()
        .map(|(c, g, l)| (c.to_string(), g.to_string(), l.to_string()))
        .collect();
    assert_eq!(found, expected, "{json:#}");
    let errors = json["errors"].as_u64().unwrap();
    assert_eq!(code, Some(if errors > 0 { 1 } else { 0 }), "{json:#}");
    assert_eq!(json["valid"], errors == 0);
    json
}

fn repair(input: &Path, output: &Path) -> Output {
    run(&[
        "validate",
        input.to_str().unwrap(),
        "--repair",
        output.to_str().unwrap(),
    ])
}

fn repair_ok(input: &Path, output: &Path) -> String {
    let out = repair(input, output);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let (code, json) = validate_json(output);
    assert_eq!(code, Some(0), "{json:#}");
    assert_eq!(json["findings"].as_array().unwrap().len(), 0, "{json:#}");
    String::from_utf8(out.stdout).unwrap()
}

fn dump(uri: &str) -> String {
    run_ok(&["dump", uri])
}

/// Rows of the pixel table: (bin1, bin2, count) as text fields, from `contactmap dump`.
fn pixel_rows(uri: &str) -> Vec<(u64, u64, i64)> {
    dump(uri)
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("bin1"))
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            (
                f[0].parse().unwrap(),
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
            )
        })
        .collect()
}

const CN: &str = "CN.mm9.10000kb.cool";

fn read_pixels(path: &Path) -> (Vec<i64>, Vec<i64>, Vec<i64>) {
    let file = open_rw(path);
    let read = |name: &str| file.dataset(name).unwrap().read_raw::<i64>().unwrap();
    (
        read("pixels/bin1_id"),
        read("pixels/bin2_id"),
        read("pixels/count"),
    )
}

/// A pixel row `k > 0` whose predecessor is in the same bin1 row.
fn same_row_pair(bin1: &[i64]) -> usize {
    (100..bin1.len()).find(|&k| bin1[k] == bin1[k - 1]).unwrap()
}

#[test]
fn pristine_fixtures_are_valid() {
    for name in [
        CN,
        "cooler_test_file.mcool",
        "toy.symm.upper.2.mcool",
        "hic_test_file.hic",
        "CN.mm9.multires.hic",
        "yeast.10kb.cool",
        "cooler_variable_bins_test_file.cool",
        "layouts/square.cool",
        "hicexplorer/small_test_matrix.h5",
        "hicexplorer/ICEcorrected_chr3LHet.h5",
    ] {
        let (code, json) = validate_json(Path::new(&data(name)));
        assert_eq!(code, Some(0), "{name}: {json:#}");
        assert_eq!(json["valid"], true, "{name}");
        assert!(json["findings"].as_array().unwrap().is_empty(), "{name}");
    }
    let (_, json) = validate_json(Path::new(&data("toy.symm.upper.2.mcool")));
    assert_eq!(json["checked"].as_array().unwrap().len(), 5);
    let text = run_ok(&["validate", &data(CN)]);
    assert!(
        text.ends_with("valid (cool; checked /): 0 errors, 0 warnings\n"),
        "{text}"
    );
}

#[test]
fn swapped_pixels_are_unsorted_and_repair_restores_the_original() {
    let (dir, path) = copy(CN);
    let (bin1, _, _) = read_pixels(&path);
    let k = same_row_pair(&bin1);
    for column in ["pixels/bin2_id", "pixels/count"] {
        edit_ints(&path, column, |v| v.swap(k - 1, k));
    }
    assert_findings(&path, &[("unsorted", "/", &format!("pixels row {k}"))]);
    let fixed = dir.path().join("fixed.cool");
    let text = repair_ok(&path, &fixed);
    assert!(text.contains("pixels resorted"), "{text}");
    assert_eq!(dump(fixed.to_str().unwrap()), dump(&data(CN)));
    // The input is untouched.
    assert_findings(&path, &[("unsorted", "/", &format!("pixels row {k}"))]);
}

#[test]
fn a_duplicated_pixel_is_found_and_repair_sums_it() {
    let (dir, path) = copy(CN);
    let (bin1, bin2, count) = read_pixels(&path);
    let k = same_row_pair(&bin1);
    edit_ints(&path, "pixels/bin2_id", |v| v[k] = v[k - 1]);
    assert_findings(&path, &[("duplicate", "/", &format!("pixels row {k}"))]);
    let fixed = dir.path().join("fixed.cool");
    let text = repair_ok(&path, &fixed);
    assert!(text.contains("1 duplicate pixels summed"), "{text}");
    // Expected: the original pixels with pixel k's count moved onto pixel k - 1.
    let mut expected: Vec<(u64, u64, i64)> = (0..bin1.len())
        .map(|m| (bin1[m] as u64, bin2[m] as u64, count[m]))
        .collect();
    expected[k - 1].2 += count[k];
    expected.remove(k);
    assert_eq!(pixel_rows(fixed.to_str().unwrap()), expected);
}

#[test]
fn negative_and_nan_counts_are_found_and_not_repaired() {
    let (dir, path) = copy(CN);
    edit_ints(&path, "pixels/count", |v| v[5] = -3);
    assert_findings(&path, &[("count", "/", "pixels row 5")]);
    let fixed = dir.path().join("fixed.cool");
    let out = repair(&path, &fixed);
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("repair refused"), "{text}");
    assert!(!fixed.exists());

    // Float counts with a NaN.
    let (_dir, path) = copy(CN);
    let (_, _, count) = read_pixels(&path);
    let mut floats: Vec<f64> = count.iter().map(|&c| c as f64).collect();
    floats[17] = f64::NAN;
    replace(&path, "pixels/count", &floats);
    assert_findings(&path, &[("count", "/", "pixels row 17")]);
}

#[test]
fn a_broken_bin1_offset_is_found_and_repair_rebuilds_it() {
    let (dir, path) = copy(CN);
    let file = open_rw(&path);
    let offsets = file
        .dataset("indexes/bin1_offset")
        .unwrap()
        .read_raw::<i64>()
        .unwrap();
    drop(file);
    // A row with at least two pixels: moving its start by one puts its first pixel in the row before.
    let row = (1..offsets.len() - 1)
        .find(|&r| offsets[r + 1] - offsets[r] >= 2)
        .unwrap();
    edit_ints(&path, "indexes/bin1_offset", |v| v[row] += 1);
    assert_findings(
        &path,
        &[("bin1-offset", "/", &format!("pixels row {}", offsets[row]))],
    );
    let fixed = dir.path().join("fixed.cool");
    let text = repair_ok(&path, &fixed);
    assert!(text.contains("bin1_offset rebuilt"), "{text}");
    assert_eq!(dump(fixed.to_str().unwrap()), dump(&data(CN)));
}

#[test]
fn a_legacy_short_bin1_offset_is_a_warning() {
    let (dir, path) = copy(CN);
    let file = open_rw(&path);
    let mut offsets = file
        .dataset("indexes/bin1_offset")
        .unwrap()
        .read_raw::<i64>()
        .unwrap();
    drop(file);
    offsets.pop();
    replace(&path, "indexes/bin1_offset", &offsets);
    let json = assert_findings(&path, &[("legacy-index", "/", "indexes/bin1_offset")]);
    assert_eq!(json["findings"][0]["severity"], "warning");
    let fixed = dir.path().join("fixed.cool");
    repair_ok(&path, &fixed);
    let file = open_rw(&fixed);
    let rebuilt = file.dataset("indexes/bin1_offset").unwrap();
    assert_eq!(rebuilt.shape(), vec![offsets.len() + 1]);
}

#[test]
fn a_lower_triangle_pixel_is_found_and_repair_transposes_it() {
    let (dir, path) = copy(CN);
    let (bin1, bin2, count) = read_pixels(&path);
    // The first pixel of a row i > 0 becomes (i, i - 1): still sorted, still in its index row.
    let k = (1..bin1.len())
        .find(|&k| bin1[k] != bin1[k - 1] && bin1[k] > 0)
        .unwrap();
    let i = bin1[k];
    edit_ints(&path, "pixels/bin2_id", |v| v[k] = i - 1);
    assert_findings(
        &path,
        &[("lower-triangle", "/", &format!("pixels row {k}"))],
    );
    let fixed = dir.path().join("fixed.cool");
    let text = repair_ok(&path, &fixed);
    assert!(
        text.contains("1 lower-triangle pixels transposed"),
        "{text}"
    );
    // Expected: the original pixels with pixel k moved to (i - 1, i) and summed there.
    let mut expected = std::collections::BTreeMap::new();
    for m in 0..bin1.len() {
        let key = if m == k {
            ((i - 1) as u64, i as u64)
        } else {
            (bin1[m] as u64, bin2[m] as u64)
        };
        *expected.entry(key).or_insert(0) += count[m];
    }
    let expected: Vec<(u64, u64, i64)> =
        expected.into_iter().map(|((a, b), c)| (a, b, c)).collect();
    assert_eq!(pixel_rows(fixed.to_str().unwrap()), expected);
}

#[test]
fn out_of_range_ids_a_broken_bin_table_and_bad_chroms_are_not_repaired() {
    let (dir, path) = copy(CN);
    let (bin1, _, _) = read_pixels(&path);
    let last = bin1.len() - 1;
    edit_ints(&path, "pixels/bin2_id", |v| v[last] = 278);
    assert_findings(&path, &[("bin-id", "/", &format!("pixels row {last}"))]);
    let fixed = dir.path().join("fixed.cool");
    assert_eq!(repair(&path, &fixed).status.code(), Some(1));
    assert!(!fixed.exists());

    let (_dir, path) = copy(CN);
    edit_ints(&path, "bins/start", |v| v[10] += 1);
    let json = assert_findings(&path, &[("bin-table", "/", "bins row 10 (chr1)")]);
    assert!(
        json["findings"][0]["message"]
            .as_str()
            .unwrap()
            .contains("does not follow the previous bin")
    );

    let (_dir, path) = copy(CN);
    edit_ints(&path, "chroms/length", |v| v[2] = 0);
    assert_findings(&path, &[("chroms", "/", "chroms/length[2] (chr3)")]);

    let (_dir, path) = copy(CN);
    {
        // The dataset keeps the file open: both go out of scope before validate reads it.
        let file = open_rw(&path);
        let dataset = file.dataset("bins/weight").unwrap();
        let mut weights = dataset.read_raw::<f64>().unwrap();
        weights[3] = f64::INFINITY;
        weights[4] = -1.0;
        dataset.write_raw(&weights).unwrap();
    }
    assert_findings(
        &path,
        &[
            ("weight", "/", "bins/weight[3]"),
            ("weight", "/", "bins/weight[4]"),
        ],
    );
}

#[test]
fn attributes_and_chrom_offset_are_checked_and_repaired() {
    let (dir, path) = copy(CN);
    {
        let file = open_rw(&path);
        file.attr("nnz").unwrap().write_scalar(&5i64).unwrap();
    }
    edit_ints(&path, "indexes/chrom_offset", |v| v[3] += 1);
    assert_findings(
        &path,
        &[
            ("chrom-offset", "/", "indexes/chrom_offset[3]"),
            ("attribute", "/", "nnz"),
        ],
    );
    let fixed = dir.path().join("fixed.cool");
    repair_ok(&path, &fixed);
    assert_eq!(dump(fixed.to_str().unwrap()), dump(&data(CN)));
}

#[test]
fn a_changed_coarse_count_breaks_the_coarsening_and_repair_regenerates_it() {
    let name = "toy.symm.upper.2.mcool";
    let (dir, path) = copy(name);
    let file = open_rw(&path);
    let level = file.group("resolutions/4").unwrap();
    let bin1 = level
        .dataset("pixels/bin1_id")
        .unwrap()
        .read_raw::<i64>()
        .unwrap();
    let bin2 = level
        .dataset("pixels/bin2_id")
        .unwrap()
        .read_raw::<i64>()
        .unwrap();
    let sum: i64 = level.attr("sum").unwrap().read_scalar().unwrap();
    // Keep the level's own sum attribute consistent: only the coarsening is wrong.
    level.attr("sum").unwrap().write_scalar(&(sum + 1)).unwrap();
    drop(level);
    drop(file);
    edit_ints(&path, "resolutions/4/pixels/count", |v| v[3] += 1);
    let json = assert_findings(
        &path,
        &[(
            "coarsening",
            "/resolutions/4",
            &format!("pixel ({}, {})", bin1[3], bin2[3]),
        )],
    );
    assert!(
        json["findings"][0]["message"]
            .as_str()
            .unwrap()
            .contains("the base resolution's pixels sum to")
    );
    let fixed = dir.path().join("fixed.mcool");
    let text = repair_ok(&path, &fixed);
    assert!(
        text.contains("zoom levels 4, 8, 16, 32 regenerated"),
        "{text}"
    );
    for r in [2, 4, 8, 16, 32] {
        let group = format!("::/resolutions/{r}");
        assert_eq!(
            pixel_rows(&format!("{}{group}", fixed.display())),
            pixel_rows(&format!("{}{group}", data(name))),
            "resolution {r}"
        );
    }
}

#[test]
fn a_corrupt_hic_block_is_reported_with_its_resolution() {
    let (_dir, path) = copy("hic_test_file.hic");
    let mut bytes = std::fs::read(&path).unwrap();
    let middle = bytes.len() / 2;
    for (k, b) in bytes[middle..middle + 40].iter_mut().enumerate() {
        *b = k as u8 + 7;
    }
    std::fs::write(&path, &bytes).unwrap();
    let (code, json) = validate_json(&path);
    assert_eq!(code, Some(1), "{json:#}");
    let found = findings(&json);
    assert_eq!(found.len(), 1, "{json:#}");
    assert_eq!(found[0].0, "hic-read");
    assert_eq!(found[0].1, "/resolutions/100000");
    assert!(
        json["findings"][0]["message"]
            .as_str()
            .unwrap()
            .contains("zlib")
    );
    // A .hic file cannot be repaired.
    let out = repair(&path, &path.with_extension("fixed.hic"));
    assert_eq!(out.status.code(), Some(1));
}

#[test]
fn unreadable_inputs_and_a_repair_over_the_input_exit_2() {
    let line = run_err(&["validate", &data("hg19.bins.2000kb.bed.gz")]);
    assert!(line.contains("not a .cool, .mcool or .hic file"), "{line}");
    let (dir, path) = copy(CN);
    let line = run_err(&[
        "validate",
        path.to_str().unwrap(),
        "--repair",
        path.to_str().unwrap(),
    ]);
    assert!(line.contains("is the input"), "{line}");
    let link = dir.path().join("link.cool");
    std::fs::hard_link(&path, &link).unwrap();
    run_err(&[
        "validate",
        path.to_str().unwrap(),
        "--repair",
        link.to_str().unwrap(),
    ]);
    // A truncated HDF5 file.
    let truncated = dir.path().join("truncated.cool");
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&truncated, &bytes[..bytes.len() / 3]).unwrap();
    let out = run(&["validate", truncated.to_str().unwrap()]);
    assert_ne!(out.status.code(), Some(0));
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
}

#[test]
fn a_cut_out_bin_table_is_a_warning_not_an_error() {
    let json = assert_findings(
        Path::new(&data("layouts/offset_bins.cool")),
        &[
            ("cut-bins", "/", "bins row 0 (chrII)"),
            ("cut-bins", "/", "bins row 50 (chrIII)"),
        ],
    );
    assert_eq!(json["warnings"], 2);
}

#[test]
fn a_negative_count_in_a_hicexplorer_matrix_is_found() {
    let (_dir, path) = copy("hicexplorer/small_test_matrix.h5");
    let data_path = "matrix/data";
    let mut values: Vec<i64> = open_rw(&path)
        .dataset(data_path)
        .unwrap()
        .read_raw()
        .unwrap();
    values[0] = -5;
    replace(&path, data_path, &values);
    let (code, json) = validate_json(&path);
    assert_eq!(code, Some(1), "{json:#}");
    assert_eq!(json["format"], "hicexplorer h5");
    let found = findings(&json);
    assert_eq!(found.len(), 1, "{json:#}");
    assert_eq!(found[0].0, "count");
    assert!(
        json["findings"][0]["message"]
            .as_str()
            .unwrap()
            .contains("count -5")
    );
    // Not repairable: refused, nothing written.
    let out = path.with_file_name("fixed.cool");
    assert_eq!(repair(&path, &out).status.code(), Some(1));
    assert!(!out.exists());
}
