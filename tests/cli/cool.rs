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
    for uri in [
        data("layouts/hic2cool_offsets.cool"),
        format!("{}::/0", data("layouts/legacy_multires.cool")),
    ] {
        assert_eq!(dump_totals(&uri), reference, "{uri}");
        assert_eq!(crate::run_ok(&["balance", &uri]), weights, "{uri}");
    }
    // The legacy level's rows were shuffled: a region query must still give every pixel.
    let region = |uri: &str| crate::run_ok(&["dump", "-r", "chrII", uri]);
    assert_eq!(
        region(&format!("{}::/0", data("layouts/legacy_multires.cool"))),
        region(&base)
    );
    // The upper triangle of the square file is base's.
    assert_eq!(dump_totals(&data("layouts/square.cool")), reference);
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
