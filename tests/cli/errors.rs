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
        line.contains("no weight column 'ICE' (it has weight)"),
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

/// Issue 26: every command that needs balanced values says "this map has no weights" the same
/// way, with the command that makes them (`balance --store` for a cooler, a .cool copy for a
/// .hic or a text table), and offers --raw only where the command has it.
#[test]
fn a_map_without_weights_gets_one_wording_and_a_hint_that_works() {
    let dir = tempfile::tempdir().unwrap();
    let hg19 = data("hg19.GM12878-MboI.matrix.2000kb.cool");
    let out = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let track = out("t.tsv");
    std::fs::write(&track, "chrom\tstart\tend\tE1\nchr1\t0\t2000000\t1\n").unwrap();
    let track = format!("{track}:E1");
    let cases: Vec<(Vec<String>, bool)> = vec![
        (
            vec!["dump".into(), "--balanced".into(), hg19.clone()],
            false,
        ),
        (vec!["expected".into(), hg19.clone()], true),
        (
            vec!["tads".into(), hg19.clone(), "-o".into(), out("i.tsv")],
            true,
        ),
        (vec!["normalize".into(), hg19.clone(), out("n.cool")], true),
        (
            vec!["compartments".into(), hg19.clone(), "-o".into(), out("c")],
            false,
        ),
        (
            vec![
                "saddle".into(),
                hg19.clone(),
                "--track".into(),
                track,
                "-o".into(),
                out("s"),
            ],
            false,
        ),
        (
            vec![
                "plot".into(),
                "map".into(),
                hg19.clone(),
                "-r".into(),
                "chr21".into(),
                "-o".into(),
                out("m.png"),
            ],
            true,
        ),
        (
            vec![
                "plot".into(),
                "expected".into(),
                hg19.clone(),
                "-o".into(),
                out("e.png"),
            ],
            true,
        ),
    ];
    for (args, has_raw) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let line = run_err(&args);
        assert!(line.contains("this map has no weights"), "{args:?}: {line}");
        assert!(
            line.contains(&format!("`contactmap balance {hg19} --store`")),
            "{args:?}: {line}"
        );
        assert_eq!(line.contains("--raw"), has_raw, "{args:?}: {line}");
    }
    // A .hic file: its normalisations are named; the route to ICE weights goes through a .cool.
    let line = run_err(&[
        "expected",
        &data("hic_test_file.hic"),
        "--weight-name",
        "KR",
    ]);
    assert!(
        line.contains("no weight column 'KR' (it has ICE)"),
        "{line}"
    );
    assert!(
        line.contains("choose one with --weight-name NAME"),
        "{line}"
    );
    assert!(line.contains("copy.cool --store --name KR"), "{line}");
    // The hint works: the balanced copy has the weights the command asked for.
    let copy = out("copy.cool");
    std::fs::copy(&hg19, &copy).unwrap();
    crate::run_ok(&["balance", &copy, "--store"]);
    crate::run_ok(&["expected", &copy, "-o", &out("e.tsv")]);
}

/// Issue 26: a file named `.cool` / `.mcool` / `.h5` that is not HDF5 (text, empty) says so,
/// instead of asking for a text --format; a `.hic` name without the .hic magic too.
#[test]
fn binary_names_that_are_not_binary_files_say_so() {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes, expected) in [
        (
            "text.cool",
            &b"chr1\t0\t100\n"[..],
            "not an HDF5 file: its 11 bytes start with",
        ),
        ("empty.cool", &b""[..], "not an HDF5 file: it is empty"),
        ("empty.mcool", &b""[..], "not an HDF5 file: it is empty"),
        ("text.h5", &b"hello"[..], "not an HDF5 file"),
        ("text.hic", &b"hello"[..], "not a .hic file"),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        for command in ["info", "dump", "balance"] {
            let line = run_err(&[command, path.to_str().unwrap()]);
            assert!(line.contains(expected), "{command} {name}: {line}");
            assert!(!line.contains("--format"), "{line}");
        }
    }
}

/// Issue 26: `file.mcool::N` is short for `file.mcool::/resolutions/N`, as for .hic files.
#[test]
fn an_mcool_resolution_can_be_named_by_its_bin_size_alone() {
    let mcool = data("cooler_test_file.mcool");
    for resolution in ["100000", "1000000"] {
        let short = crate::run_ok(&["dump", &format!("{mcool}::{resolution}"), "--join"]);
        let long = crate::run_ok(&[
            "dump",
            &format!("{mcool}::/resolutions/{resolution}"),
            "--join",
        ]);
        assert!(!short.is_empty());
        assert_eq!(short, long);
    }
    let line = run_err(&["dump", &format!("{mcool}::5000")]);
    assert!(line.contains("available: 100000, 1000000"), "{line}");
}

/// Issue 26: argument errors are one `contactmap: error:` line like every other error (with the
/// usage and where to read more), and a negative number reaches the option: accepted where it
/// means something, refused with the real reason elsewhere (not read as an unknown flag `-5`).
#[test]
fn argument_errors_are_one_line_and_negative_numbers_reach_their_option() {
    let yeast = data("yeast.10kb.cool");
    let line = run_err(&["dump"]);
    assert!(line.contains("not provided: <URI>"), "{line}");
    assert!(line.contains("see `contactmap dump --help`"), "{line}");
    let line = run_err(&["tads", &yeast, "--windw", "50k"]);
    assert!(
        line.contains("a similar argument exists: '--window'"),
        "{line}"
    );
    let line = run_err(&["tads", &yeast, "--method", "foo"]);
    assert!(line.contains("[possible values: insulation"), "{line}");
    let line = run_err(&["frobnicate"]);
    assert!(
        line.contains("unrecognized subcommand 'frobnicate'"),
        "{line}"
    );
    // Negative values: the option's own reason.
    let line = run_err(&["tads", &yeast, "--window", "-50k"]);
    assert!(line.contains("--window: '-50k' is negative"), "{line}");
    let line = run_err(&["expected", &yeast, "--ignore-diags", "-1"]);
    assert!(
        line.contains("'--ignore-diags <N>': a number of 0 or more is expected"),
        "{line}"
    );
    let line = run_err(&["balance", &yeast, "--tol", "-1e-5"]);
    assert!(line.contains("--tol must be a positive number"), "{line}");
    // ... and used where they mean something: a diverging colour range.
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("oe.png");
    crate::run_ok(&[
        "plot",
        "map",
        &yeast,
        "-r",
        "chrIV",
        "--oe",
        "--linear",
        "--vmin",
        "-2",
        "--vmax",
        "2",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(png.exists());
    // Help and version still print in full, with exit 0.
    let help = crate::run(&["dump", "--help"]);
    assert!(help.status.success());
    assert!(String::from_utf8_lossy(&help.stdout).contains("Usage: contactmap dump"));
}
