//! Bad input: one clear error line naming the file and the problem, exit code 2, no panic, no
//! partial output.

use crate::{data, run_err};

/// Write the first `keep` bytes of fixture `name` to a temporary file.
fn truncated(name: &str, keep: usize, dir: &std::path::Path) -> String {
    let bytes = std::fs::read(data(name)).unwrap();
    let path = dir.join(format!("truncated-{keep}-{name}"));
    std::fs::write(&path, &bytes[..keep.min(bytes.len())]).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn truncated_coolers_fail_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "CN.mm9.10000kb.cool",
        "cooler_test_file.mcool",
        "cooler_variable_bins_test_file.cool",
    ] {
        let size = std::fs::metadata(data(name)).unwrap().len() as usize;
        for keep in [10, 600, 4096, size / 2, size - 100] {
            let path = truncated(name, keep, dir.path());
            let uri = if name.ends_with(".mcool") {
                format!("{path}::/resolutions/100000")
            } else {
                path.clone()
            };
            for args in [vec!["info", uri.as_str()], vec!["dump", uri.as_str()]] {
                let line = run_err(&args);
                assert!(line.contains(&path), "error should name the file: {line}");
            }
        }
    }
}

#[test]
fn unknown_region_is_named() {
    let line = run_err(&["dump", "-r", "chrZ:1-100", &data("CN.mm9.10000kb.cool")]);
    assert!(
        line.contains("chrZ") && line.contains("no chromosome"),
        "{line}"
    );
    let line = run_err(&[
        "dump",
        "-r",
        "chr1:0-999,999,999,999",
        &data("CN.mm9.10000kb.cool"),
    ]);
    assert!(line.contains("past the length"), "{line}");
    let line = run_err(&["dump", "-r", "chr1:xyz-100", &data("CN.mm9.10000kb.cool")]);
    assert!(line.contains("not a position"), "{line}");
}

#[test]
fn missing_resolution_lists_the_available_ones() {
    let mcool = data("cooler_test_file.mcool");
    let line = run_err(&["dump", &format!("{mcool}::/resolutions/5000")]);
    assert!(
        line.contains("/resolutions/5000") && line.contains("100000, 1000000"),
        "{line}"
    );
    let line = run_err(&["dump", &mcool]);
    assert!(
        line.contains("multi-resolution") && line.contains("100000, 1000000"),
        "{line}"
    );
}

#[test]
fn missing_weight_column_is_named() {
    let line = run_err(&["dump", "--balanced=ICE", &data("CN.mm9.10000kb.cool")]);
    assert!(
        line.contains("no weight column 'ICE'") && line.contains("weight"),
        "{line}"
    );
}

#[test]
fn missing_file_is_named() {
    let line = run_err(&["info", "/nonexistent/file.cool"]);
    assert!(line.contains("/nonexistent/file.cool"), "{line}");
}

#[test]
fn failed_conversion_leaves_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.mcool");
    // 1500 is not a multiple of the input's 100 kb bins.
    let line = run_err(&[
        "convert",
        &data("cooler_test_file.mcool::/resolutions/100000"),
        out.to_str().unwrap(),
        "--resolutions",
        "150000",
    ]);
    assert!(line.contains("not a multiple"), "{line}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

/// Outputs that are not regular files (`/dev/null`, a named pipe) are written in place: the
/// temporary-then-rename of regular files would replace them with a file (as root, even
/// `/dev/null`, which then fed other programs' output to everything reading it).
#[test]
fn a_named_pipe_output_is_written_in_place_not_replaced() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("out.fifo");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let uri = data("CN.mm9.10000kb.cool");
    crate::run_ok(&["expected", &uri, "-o", fifo.to_str().unwrap()]);
    let through_pipe = reader.join().unwrap();
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    assert_eq!(through_pipe, crate::run_ok(&["expected", &uri]));
    // Formats written whole (a .cool) refuse a special file instead of replacing it.
    let message = crate::run_err(&["convert", &uri, fifo.to_str().unwrap(), "--to", "cool"]);
    assert!(message.contains("not a regular file"), "{message}");
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
}
