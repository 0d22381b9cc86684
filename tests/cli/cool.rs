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
