//! Text and pairs inputs through the binary: stdin, gzip, bad lines.

use std::io::Write;
use std::process::{Command, Stdio};

use crate::{data, run_err, run_ok};

#[test]
fn bg2_from_stdin_equals_the_cooler() {
    let bed = data("hg19.bins.2000kb.bed.gz");
    let mut text = Vec::new();
    use std::io::Read;
    flate2::read::MultiGzDecoder::new(
        std::fs::File::open(data("hg19.GM12878-MboI.matrix.2000kb.bg2.gz")).unwrap(),
    )
    .read_to_end(&mut text)
    .unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_contactmap"))
        .args(["dump", "-", "--format", "bg2", "--bins", &bed])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let writer = std::thread::spawn(move || stdin.write_all(&text));
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap().unwrap();
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8(out.stdout).unwrap(),
        run_ok(&["dump", &data("hg19.GM12878-MboI.matrix.2000kb.cool")])
    );
}

/// A chrom.sizes file for hg19, from the 2 Mb cooler's chromosome table.
fn hg19_sizes(dir: &std::path::Path) -> std::path::PathBuf {
    let sizes = dir.join("hg19.sizes");
    let table = run_ok(&[
        "dump",
        "-t",
        "chroms",
        &data("hg19.GM12878-MboI.matrix.2000kb.cool"),
    ]);
    std::fs::write(&sizes, table).unwrap();
    sizes
}

#[test]
fn pairs_binned_like_cooler_cload() {
    // cooler cload pairs -c1 1 -p1 2 -c2 4 -p2 5 hg19.sizes:2000000 pairs.txt.gz out.cool gives
    // exactly the 2 Mb cooler of the same library (see src/io/matrices/text.rs tests).
    let dir = tempfile::tempdir().unwrap();
    let sizes = hg19_sizes(dir.path());
    let out = dir.path().join("pairs.cool");
    run_ok(&[
        "convert",
        &data("hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz"),
        out.to_str().unwrap(),
        "--format",
        "pairs",
        "--bin-size",
        "2000000",
        "--chrom-sizes",
        sizes.to_str().unwrap(),
        "--pairs-columns",
        "1,2,4,5",
    ]);
    assert_eq!(
        run_ok(&["dump", out.to_str().unwrap()]),
        run_ok(&["dump", &data("hg19.GM12878-MboI.matrix.2000kb.cool")])
    );
}

/// Issue 26: the README's route, `convert PAIRS OUT --bin-size --chrom-sizes` without --format
/// or --pairs-columns, on the repository's own headerless pairs file (chrom pos strand chrom pos
/// strand): the layout is recognised from the content and gives cooler's cooler.
#[test]
fn headerless_pairs_are_recognised_by_their_content() {
    let dir = tempfile::tempdir().unwrap();
    let sizes = hg19_sizes(dir.path());
    let out = dir.path().join("pairs.cool");
    run_ok(&[
        "convert",
        &data("hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz"),
        out.to_str().unwrap(),
        "--bin-size",
        "2000000",
        "--chrom-sizes",
        sizes.to_str().unwrap(),
    ]);
    let reference = run_ok(&["dump", &data("hg19.GM12878-MboI.matrix.2000kb.cool")]);
    assert_eq!(run_ok(&["dump", out.to_str().unwrap()]), reference);
    // The same pairs in the 4DN body layout and in Juicer's short format, headerless.
    let text = run_ok(&[
        "dump",
        &data("hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz"),
        "--format",
        "pairs",
        "--pairs-columns",
        "1,2,4,5",
        "--bin-size",
        "2000000",
        "--chrom-sizes",
        sizes.to_str().unwrap(),
    ]);
    assert_eq!(text, reference);
    let pairs = {
        use std::io::Read;
        let mut text = String::new();
        flate2::read::MultiGzDecoder::new(
            std::fs::File::open(data("hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz")).unwrap(),
        )
        .read_to_string(&mut text)
        .unwrap();
        text
    };
    let mut four_dn = String::new();
    let mut juicer = String::new();
    for (k, line) in pairs.lines().enumerate() {
        let f: Vec<&str> = line.split('\t').collect();
        let strand = |flag: &str| if flag == "16" { "-" } else { "+" };
        four_dn.push_str(&format!(
            "read{k}\t{}\t{}\t{}\t{}\t{}\t{}\n",
            f[0],
            f[1],
            f[3],
            f[4],
            strand(f[2]),
            strand(f[5])
        ));
        juicer.push_str(&format!(
            "{}\t{}\t{}\t0\t{}\t{}\t{}\t1\n",
            f[2], f[0], f[1], f[5], f[3], f[4]
        ));
    }
    for (name, body) in [("4dn.txt", four_dn), ("juicer.txt", juicer)] {
        let path = dir.path().join(name);
        std::fs::write(&path, body).unwrap();
        let dumped = run_ok(&[
            "dump",
            path.to_str().unwrap(),
            "--bin-size",
            "2000000",
            "--chrom-sizes",
            sizes.to_str().unwrap(),
        ]);
        assert_eq!(dumped, reference, "{name}");
    }
}

#[test]
fn bad_text_line_names_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("bad.bg2");
    std::fs::write(
        &table,
        "chr1\t0\t2000000\tchr1\t0\t2000000\t5\nchr1\t0\t2000000\tchr1\t2000000\n",
    )
    .unwrap();
    let line = run_err(&[
        "dump",
        table.to_str().unwrap(),
        "--bins",
        &data("hg19.bins.2000kb.bed.gz"),
    ]);
    assert!(line.contains(&format!("{}:2:", table.display())), "{line}");
    assert!(line.contains("expected 7"), "{line}");
}

#[test]
fn bin_out_of_range_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("bad.coo");
    std::fs::write(&table, "0\t1\t3\n5\t99999\t1\n").unwrap();
    let line = run_err(&[
        "info",
        table.to_str().unwrap(),
        "--bins",
        &data("hg19.bins.2000kb.bed.gz"),
    ]);
    assert!(line.contains(&format!("{}:2:", table.display())), "{line}");
    assert!(line.contains("99999") && line.contains("1561"), "{line}");
}

#[test]
fn text_without_a_bin_table_says_what_to_pass() {
    let line = run_err(&[
        "info",
        &data("hg19.GM12878-MboI.matrix.2000kb.bg2.gz"),
        "--format",
        "bg2",
    ]);
    assert!(
        line.contains("--bins") && line.contains("--chrom-sizes"),
        "{line}"
    );
}

#[test]
fn truncated_gzip_text_fails_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let sizes = hg19_sizes(dir.path());
    let bed = data("hg19.bins.2000kb.bed.gz");
    let cases: [(&str, Vec<&str>); 2] = [
        (
            "hg19.GM12878-MboI.matrix.2000kb.bg2.gz",
            vec!["--format", "bg2", "--bins", &bed],
        ),
        (
            "hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz",
            vec![
                "--format",
                "pairs",
                "--bin-size",
                "2000000",
                "--chrom-sizes",
                sizes.to_str().unwrap(),
                "--pairs-columns",
                "1,2,4,5",
            ],
        ),
    ];
    for (name, options) in cases {
        let bytes = std::fs::read(data(name)).unwrap();
        for keep in [5, 100, bytes.len() / 2, bytes.len() - 10] {
            let path = dir.path().join(format!("cut-{keep}-{name}"));
            std::fs::write(&path, &bytes[..keep]).unwrap();
            let path = path.to_str().unwrap();
            let line = run_err(&[&["info", path][..], &options[..]].concat());
            assert!(line.contains(path), "{line}");
        }
    }
}

#[test]
fn bg2_zero_counts_survive_conversion_to_cool_as_in_cooler_load() {
    // data/text/bg2_zeros.cooler-dump.coo is `cooler dump` of `cooler load -f bg2` of the input:
    // 715 pixels, 179 of them with a count of 0.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("zeros.cool");
    let out = out.to_str().unwrap();
    run_ok(&[
        "convert",
        &data("text/bg2_zeros.bg2.gz"),
        out,
        "--bins",
        &data("hg19.bins.2000kb.bed.gz"),
    ]);
    let expected = std::fs::read_to_string(data("text/bg2_zeros.cooler-dump.coo")).unwrap();
    assert_eq!(run_ok(&["dump", out]), expected);
}
