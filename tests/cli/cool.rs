//! cooler files: the layouts cooler reads, corrupt metadata, and wrong data refused.

use std::process::Command;
use std::time::{Duration, Instant};

use crate::data;

/// A copy of fixture `name` in `dir` whose first global heap collection (where HDF5 keeps
/// variable-length strings such as cooler's `bin-type` attribute) records an object 0 of size 0:
/// libhdf5 2.2.0's heap parser loops forever on it.
fn looping_heap_copy(name: &str, dir: &std::path::Path) -> String {
    let mut bytes = std::fs::read(data(name)).unwrap();
    let heap = bytes
        .windows(4)
        .position(|w| w == b"GCOL")
        .expect("the fixture has a global heap");
    let object = heap + 16;
    bytes[object..object + 2].fill(0);
    bytes[object + 8..object + 16].fill(0);
    let path = dir.join(format!("looping-heap-{name}"));
    std::fs::write(&path, bytes).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn a_looping_hdf5_heap_fails_within_the_deadline() {
    let dir = tempfile::tempdir().unwrap();
    let path = looping_heap_copy("CN.mm9.10000kb.cool", dir.path());
    let out_file = dir.path().join("out.cool");
    let out = out_file.to_string_lossy().into_owned();
    for args in [
        vec!["info", path.as_str()],
        vec!["dump", path.as_str()],
        vec!["balance", path.as_str()],
        vec!["convert", path.as_str(), out.as_str()],
    ] {
        let started = Instant::now();
        let output = Command::new(env!("CARGO_BIN_EXE_contactmap"))
            .args(&args)
            .env("CONTACTMAP_HDF5_TIMEOUT", "1")
            .output()
            .unwrap();
        let elapsed = started.elapsed();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            elapsed < Duration::from_secs(8),
            "{args:?} took {elapsed:?}"
        );
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.starts_with(&format!("contactmap: error: {path}: HDF5 reading")),
            "{stderr}"
        );
        assert!(!out_file.exists(), "{args:?} left an output");
    }
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporaries left: {leftovers:?}");
}

/// `dump` totals (pixels, sum of counts) of a URI.
fn dump_totals(uri: &str) -> (usize, f64) {
    let text = crate::run_ok(&["dump", uri]);
    let counts: Vec<f64> = text
        .lines()
        .map(|l| l.rsplit('\t').next().unwrap().parse().unwrap())
        .collect();
    (counts.len(), counts.iter().sum())
}

/// Fixtures made by scripts/fixtures/cool_layouts.py with cooler 0.11 from the same pixels as
/// `layouts/base.cool` (written by cooler itself, the reference): each layout must read as it.
#[test]
fn layouts_cooler_reads_give_the_same_pixels_and_weights() {
    let base = data("layouts/base.cool");
    let reference = dump_totals(&base);
    assert_eq!(reference.0, 9159);
    let weights = crate::run_ok(&["balance", &base]);
    // cooltools expected_cis on base.cool: count.sum 3,513,882 over 138 rows (measured).
    let expected = crate::run_ok(&["expected", "--raw", &base]);
    let table = crate::parse_table(&expected);
    let sum_column = table.header.iter().position(|h| h == "count.sum").unwrap();
    let total: f64 = table
        .rows
        .iter()
        .filter_map(|r| r[sum_column].parse::<f64>().ok())
        .filter(|v| !v.is_nan())
        .sum();
    assert_eq!((table.rows.len(), total), (138, 3_513_882.0));
    for uri in [
        data("layouts/hic2cool_offsets.cool"),
        format!("{}::/0", data("layouts/legacy_multires.cool")),
    ] {
        assert_eq!(dump_totals(&uri), reference, "{uri}");
        assert_eq!(crate::run_ok(&["balance", &uri]), weights, "{uri}");
        assert_eq!(
            crate::run_ok(&["expected", "--raw", &uri]),
            expected,
            "{uri}"
        );
    }
    // The legacy level's rows were shuffled: a region query must still give every pixel.
    let region = |uri: &str| crate::run_ok(&["dump", "-r", "chrII", uri]);
    assert_eq!(
        region(&format!("{}::/0", data("layouts/legacy_multires.cool"))),
        region(&base)
    );
}

#[test]
fn a_legacy_multires_file_lists_its_levels() {
    let path = data("layouts/legacy_multires.cool");
    let line = crate::run_err(&["info", &path]);
    assert!(
        line.contains("::/N (available: 0 (10000 bp), 1 (20000 bp))"),
        "{line}"
    );
}

#[test]
fn a_duplicated_pixel_is_refused_not_dropped() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("dup.cool");
    std::fs::copy(data("layouts/base.cool"), &path).unwrap();
    {
        let file = hdf5::File::open_rw(&path).unwrap();
        let dataset = file.dataset("pixels/bin2_id").unwrap();
        let mut bin2: Vec<i64> = dataset.read_raw().unwrap();
        // Row 0 holds several pixels: make its second one repeat its first.
        bin2[1] = bin2[0];
        dataset.write_raw(&bin2).unwrap();
    }
    let path = path.to_string_lossy().into_owned();
    for command in ["dump", "balance"] {
        let line = crate::run_err(&[command, &path]);
        assert!(line.contains("stored twice"), "{line}");
        assert!(line.contains(&path), "{line}");
    }
}

#[test]
fn a_pixel_out_of_range_or_below_the_diagonal_is_refused() {
    // the reader checks a sorted row by its first and last columns: a fault at either end
    let bins = {
        let file = hdf5::File::open(data("layouts/base.cool")).unwrap();
        file.dataset("bins/start").unwrap().size() as i64
    };
    for (what, at_end) in [("past the last bin", true), ("below the diagonal", false)] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.cool");
        std::fs::copy(data("layouts/base.cool"), &path).unwrap();
        {
            let file = hdf5::File::open_rw(&path).unwrap();
            let offsets: Vec<i64> = file
                .dataset("indexes/bin1_offset")
                .unwrap()
                .read_raw()
                .unwrap();
            let dataset = file.dataset("pixels/bin2_id").unwrap();
            let mut bin2: Vec<i64> = dataset.read_raw().unwrap();
            // the first row from 1 holding two pixels or more
            let row = (1..offsets.len() - 1)
                .find(|&r| offsets[r + 1] - offsets[r] >= 2)
                .unwrap();
            if at_end {
                bin2[offsets[row + 1] as usize - 1] = bins;
            } else {
                bin2[offsets[row] as usize] = row as i64 - 1;
            }
            dataset.write_raw(&bin2).unwrap();
        }
        let path = path.to_string_lossy().into_owned();
        let line = crate::run_err(&["dump", &path]);
        assert!(line.contains("is out of range for"), "{what}: {line}");
        assert!(line.contains(&path), "{what}: {line}");
    }
}

/// Every column of `theirs` (a cooler / cooltools table written with `%.10g`) in `ours`, row by
/// row: numbers within `relative` (+ 1e-9 absolute; NaN where they have NaN), the rest exactly (`True` / `False`
/// as cooltools writes booleans, `true` / `false` as we do).
fn assert_table_matches(ours: &crate::Table, theirs: &crate::Table, relative: f64, what: &str) {
    assert_eq!(ours.rows.len(), theirs.rows.len(), "{what}: rows");
    for (column, name) in theirs.header.iter().enumerate() {
        let index = ours
            .header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("{what}: no column {name} in {:?}", ours.header));
        for (row, (a, b)) in ours.rows.iter().zip(&theirs.rows).enumerate() {
            let (x, y) = (&a[index], &b[column]);
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(x), Ok(y)) if y.is_nan() => {
                    assert!(x.is_nan(), "{what} row {row} {name}: {x}, reference nan")
                }
                // Plus 1e-9 absolute: log2 scores near 0 carry the weights' error absolutely.
                (Ok(x), Ok(y)) => assert!(
                    (x - y).abs() <= relative * y.abs() + 1e-9,
                    "{what} row {row} {name}: {x}, reference {y}"
                ),
                _ => assert_eq!(
                    x.to_ascii_lowercase(),
                    y.to_ascii_lowercase(),
                    "{what} row {row} {name}"
                ),
            }
        }
    }
}

/// `balance` (printed and stored), `expected` raw and balanced and insulation of a layout
/// fixture against cooler / cooltools (scripts/fixtures/cool_layouts_reference.py). References
/// are `%.10g`, our weights converge like cooler's (same iterations): 1e-8 relative.
fn check_layout_against_cooltools(name: &str, balance_options: &[&str]) {
    let reference =
        |what: &str| crate::reference_table(&format!("layouts/reference/{name}.{what}.tsv.gz"));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("{name}.cool"));
    std::fs::copy(data(&format!("layouts/{name}.cool")), &path).unwrap();
    let path = path.to_string_lossy().into_owned();
    let mut args = vec!["balance", path.as_str()];
    args.extend(balance_options);
    let weights = crate::parse_table(&crate::run_ok(&args));
    assert_table_matches(&weights, &reference("weights"), 1e-8, name);
    args.push("--store");
    crate::run_ok(&args);
    for (what, extra) in [
        ("expected_raw", vec!["--raw"]),
        ("expected_balanced", vec![]),
    ] {
        let mut args = vec!["expected", path.as_str()];
        args.extend(extra);
        let ours = crate::parse_table(&crate::run_ok(&args));
        assert_table_matches(&ours, &reference(what), 1e-8, &format!("{name} {what}"));
    }
    let ours = crate::parse_table(&crate::run_ok(&["tads", &path, "--window", "30000,50000"]));
    assert_table_matches(
        &ours,
        &reference("insulation"),
        1e-8,
        &format!("{name} insulation"),
    );
}

/// storage-mode square: dump prints both stored triangles as cooler dump does (18,187 pixels,
/// sum 14,395,045); balance folds them as cooler's balance does (scale 157,156.6, not base's
/// 79,045.9); expected and insulation read the upper triangle as cooltools does.
#[test]
fn a_square_cooler_behaves_as_cooler_and_cooltools() {
    assert_eq!(
        dump_totals(&data("layouts/square.cool")),
        (18_187, 14_395_045.0)
    );
    // Both triangles: the transposed pixels are there.
    let text = crate::run_ok(&["dump", "-r", "chrII:0-30000", &data("layouts/square.cool")]);
    let pixels: Vec<(u64, u64)> = text
        .lines()
        .map(|l| {
            let f: Vec<u64> = l.split('\t').map(|x| x.parse().unwrap()).collect();
            (f[0], f[1])
        })
        .collect();
    assert!(pixels.iter().any(|&(i, j)| i > j));
    assert!(pixels.iter().all(|&(i, j)| pixels.contains(&(j, i))));
    check_layout_against_cooltools("square", &[]);
}

/// Bins that do not start at 0 (chrII cut to 200-700 kb, chrIII to 50-300 kb): cooler's own
/// weights; expected and insulation as cooltools computes them when it indexes the cut bins right
/// (see the reference script: cooltools' arithmetic extents misplace them on the cut file itself).
#[test]
fn a_cut_out_bin_table_is_read_and_computed_on() {
    let uri = data("layouts/offset_bins.cool");
    assert_eq!(dump_totals(&uri), (2847, 4_945_925.0));
    let bins = crate::run_ok(&["dump", "-t", "bins", &uri]);
    assert!(bins.starts_with("chrII\t200000\t210000\n"), "{bins}");
    // A region before the cut selects nothing; one across its start selects from the first bin.
    assert_eq!(crate::run_ok(&["dump", "-r", "chrII:0-200000", &uri]), "");
    assert_eq!(
        crate::run_ok(&["dump", "-r", "chrII:0-210000", &uri]),
        crate::run_ok(&["dump", "-r", "chrII:200000-210000", &uri])
    );
    check_layout_against_cooltools("offset_bins", &["--max-iters", "1000"]);
}

/// `dump -t bins` prints weight columns as stored (cooler dump prints hic2cool's divisive KR as
/// it is); `--balanced=KR` divides by them.
#[test]
fn bins_dump_prints_divisive_weights_as_stored() {
    let uri = format!("{}::/resolutions/100000", data("cooler_test_file.mcool"));
    let table = crate::parse_table(&crate::run_ok(&[
        "dump",
        "-t",
        "bins",
        "-H",
        "--float-format",
        ".17g",
        &uri,
    ]));
    let file = hdf5::File::open(data("cooler_test_file.mcool")).unwrap();
    let group = file.group("resolutions/100000").unwrap();
    for name in ["KR", "VC", "weight"] {
        let stored: Vec<f64> = group
            .dataset(&format!("bins/{name}"))
            .unwrap()
            .read_raw()
            .unwrap();
        let column = table.header.iter().position(|h| h == name).unwrap();
        for (row, value) in table.rows.iter().zip(&stored) {
            match row[column].as_str() {
                "" => assert!(value.is_nan(), "{name}: empty where the file has {value}"),
                text => assert_eq!(text.parse::<f64>().unwrap(), *value, "{name}"),
            }
        }
    }
    // Balanced with KR: count / (KR1 * KR2), KR as stored.
    let kr: Vec<f64> = group.dataset("bins/KR").unwrap().read_raw().unwrap();
    let line = crate::run_ok(&["dump", "--balanced=KR", "--float-format", ".17g", &uri]);
    let first = line.lines().find(|l| !l.ends_with('\t')).unwrap();
    let f: Vec<f64> = first.split('\t').map(|x| x.parse().unwrap()).collect();
    let expected = f[2] / (kr[f[0] as usize] * kr[f[1] as usize]);
    assert!(
        (f[3] - expected).abs() <= 1e-12 * expected,
        "{first}: {expected}"
    );
}

/// `balance --cis-only` with a chromosome all masked (chrI blacklisted): its weights are NaN and
/// its summary line is what cooler reports for it (scale NaN, var 0, converged), and every other
/// chromosome's weights are those of the same balance without it (cis-only chromosomes are
/// balanced independently).
#[test]
fn an_all_masked_chromosome_in_cis_only_balance_reports_as_cooler() {
    let dir = tempfile::tempdir().unwrap();
    let blacklist = dir.path().join("chrI.bed");
    std::fs::write(&blacklist, "chrI\t0\t230218\n").unwrap();
    let uri = data("yeast.10kb.cool");
    let out = crate::run(&[
        "balance",
        "--cis-only",
        "--blacklist",
        blacklist.to_str().unwrap(),
        &uri,
    ]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("# chrI converged=true n_iterations=1 scale=NaN var=0e0"),
        "{stderr}"
    );
    let masked = crate::parse_table(&String::from_utf8_lossy(&out.stdout));
    let whole = crate::parse_table(&crate::run_ok(&["balance", "--cis-only", &uri]));
    for (a, b) in masked.rows.iter().zip(&whole.rows) {
        if a[0] == "chrI" {
            assert_eq!(a[3], "nan");
        } else {
            assert_eq!(a, b);
        }
    }
}
