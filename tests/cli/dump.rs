//! `contactmap dump` against `cooler dump` output.

use crate::{data, run_ok};

fn reference(name: &str) -> String {
    std::fs::read_to_string(data(&format!("reference/{name}"))).expect("reference file")
}

#[test]
fn region_box_balanced_and_joined_equals_cooler_dump() {
    let ours = run_ok(&[
        "dump",
        "--join",
        "--header",
        "--balanced",
        "-r",
        "chr2L:1,000,000-3,000,000",
        "--region2",
        "chr2L:2,000,000-5,000,000",
        &data("cooler_test_file.mcool::/resolutions/100000"),
    ]);
    assert_eq!(ours, reference("dm6_100kb.chr2L_box.balanced.join.tsv"));
}

#[test]
fn trans_box_equals_cooler_dump() {
    let ours = run_ok(&[
        "dump",
        "-r",
        "chrX",
        "--range2",
        "chrY",
        &data("cooler_test_file.mcool::/resolutions/100000"),
    ]);
    assert_eq!(ours, reference("dm6_100kb.chrX_chrY.tsv"));
}

#[test]
fn bin_table_with_weights_equals_cooler_dump() {
    let ours = run_ok(&["dump", "-t", "bins", "-H", &data("CN.mm9.10000kb.cool")]);
    assert_eq!(ours, reference("CN.mm9.10000kb.bins.tsv"));
}

#[test]
fn variable_bins_equal_cooler_dump() {
    let pixels = run_ok(&["dump", "-H", &data("cooler_variable_bins_test_file.cool")]);
    assert_eq!(pixels, reference("variable_bins.pixels.tsv"));
    let bins = run_ok(&[
        "dump",
        "-t",
        "bins",
        &data("cooler_variable_bins_test_file.cool"),
    ]);
    assert_eq!(bins, reference("variable_bins.bins.tsv"));
}

#[test]
fn mcool_level_joined_equals_cooler_dump() {
    let ours = run_ok(&[
        "dump",
        "--join",
        &data("toy.symm.upper.2.mcool::/resolutions/4"),
    ]);
    assert_eq!(ours, reference("toy_4.join.tsv"));
}

#[test]
fn the_resolution_option_reads_the_level_the_uri_names() {
    // an .mcool and a .hic named alone, the level given apart (hictk's --resolution)
    for (file, level) in [
        ("toy.symm.upper.2.mcool", "4"),
        ("CN.mm9.multires.hic", "10000000"),
    ] {
        let by_uri = run_ok(&[
            "dump",
            "--join",
            &data(&format!("{file}::/resolutions/{level}")),
        ]);
        let by_option = run_ok(&["dump", "--join", &data(file), "--resolution", level]);
        assert_eq!(by_option, by_uri, "{file}");
    }
    assert_eq!(
        run_ok(&[
            "dump",
            "--join",
            &data("toy.symm.upper.2.mcool"),
            "--resolution",
            "4"
        ]),
        reference("toy_4.join.tsv")
    );
    // a level the file lacks, or another than the URI's: exit 2, the levels named
    let out = crate::run(&["dump", &data("toy.symm.upper.2.mcool"), "--resolution", "3"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("has no resolution 3: it has"), "{stderr}");
    let uri = data("toy.symm.upper.2.mcool::/resolutions/4");
    let out = crate::run(&["dump", &uri, "--resolution", "2"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_region_dump_is_the_filtered_full_dump() {
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    let full = run_ok(&["dump", &uri]);
    // The bins of chr3L, from the bin table.
    let bins = run_ok(&["dump", "-t", "bins", &uri]);
    let chr3l: Vec<usize> = bins
        .lines()
        .enumerate()
        .filter(|(_, l)| l.starts_with("chr3L\t"))
        .map(|(i, _)| i)
        .collect();
    let (lo, hi) = (chr3l[0], chr3l[chr3l.len() - 1] + 1);
    let expected: String = full
        .lines()
        .filter(|l| {
            let mut f = l.split('\t').map(|x| x.parse::<usize>().unwrap());
            let (i, j) = (f.next().unwrap(), f.next().unwrap());
            (lo..hi).contains(&i) && (lo..hi).contains(&j)
        })
        .map(|l| format!("{l}\n"))
        .collect();
    assert_eq!(run_ok(&["dump", "-r", "chr3L", &uri]), expected);
}

#[test]
fn output_to_gzip_file_is_complete() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pixels.tsv.gz");
    let uri = data("cooler_test_file.mcool::/resolutions/1000000");
    run_ok(&["dump", &uri, "-o", out.to_str().unwrap()]);
    let mut text = String::new();
    use std::io::Read;
    flate2::read::MultiGzDecoder::new(std::fs::File::open(&out).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    assert_eq!(text, run_ok(&["dump", &uri]));
}

#[test]
fn a_closed_output_pipe_is_success() {
    // `contactmap dump ... | head -1`: the reader goes away after one line.
    use std::io::{BufRead, BufReader};
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_contactmap"))
        .args(["dump", &data("cooler_test_file.mcool::/resolutions/100000")])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    assert_eq!(first, "0\t0\t101360\n");
    // stdout is dropped here: later writes hit a closed pipe
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "exit status {:?}", out.status);
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
