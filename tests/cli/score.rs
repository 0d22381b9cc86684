//! `contactmap score boundaries` on hand-made examples.

use crate::{data, run_err, run_ok, write};

/// Bins of 10 kb at these bin indices on chr1, as BED text.
fn bins(indices: &[u64]) -> String {
    indices
        .iter()
        .map(|&i| format!("chr1\t{}\t{}\n", i * 10_000, (i + 1) * 10_000))
        .collect()
}

/// The table's one row as (column, value) pairs.
fn score(args: &[&str]) -> Vec<(String, String)> {
    let text = run_ok(&[&["score", "boundaries"][..], args].concat());
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2, "{text}");
    lines[0]
        .split('\t')
        .zip(lines[1].split('\t'))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

fn value(row: &[(String, String)], name: &str) -> f64 {
    row.iter()
        .find(|(k, _)| k == name)
        .unwrap_or_else(|| panic!("no column {name}: {row:?}"))
        .1
        .parse()
        .unwrap()
}

#[test]
fn known_examples() {
    let dir = tempfile::tempdir().unwrap();
    let truth = write(dir.path(), "truth.bed", &bins(&[10, 20, 30, 40]));
    let perfect = score(&["--truth", &truth, &truth]);
    let columns: Vec<&str> = perfect.iter().map(|(k, _)| k.as_str()).collect();
    assert_eq!(
        columns,
        [
            "tolerance_bp",
            "n_truth",
            "n_calls",
            "true_positives",
            "precision",
            "recall",
            "f1"
        ]
    );
    assert_eq!(value(&perfect, "f1"), 1.0);
    assert_eq!(value(&perfect, "tolerance_bp"), 10_000.0);

    let shifted = write(dir.path(), "shifted.bed", &bins(&[11, 21, 31, 41]));
    assert_eq!(value(&score(&["--truth", &truth, &shifted]), "f1"), 1.0);
    let strict = score(&["--truth", &truth, &shifted, "--tolerance-bins", "0"]);
    assert_eq!(value(&strict, "f1"), 0.0);
    assert_eq!(value(&strict, "true_positives"), 0.0);

    let half = write(dir.path(), "half.bed.gz", "");
    {
        use std::io::Write;
        let mut gz = flate2::write::GzEncoder::new(
            std::fs::File::create(&half).unwrap(),
            flate2::Compression::default(),
        );
        gz.write_all(bins(&[10, 30]).as_bytes()).unwrap();
        gz.finish().unwrap();
    }
    let row = score(&["--truth", &truth, &half]);
    assert_eq!(value(&row, "recall"), 0.5);
    assert_eq!(value(&row, "precision"), 1.0);
    assert!((value(&row, "f1") - 2.0 / 3.0).abs() < 1e-12);

    // Explicit bin size (zero-width calls at the bin midpoints + 2 bins): tolerance 2 bins.
    let points: String = [10u64, 20]
        .iter()
        .map(|i| format!("chr1\t{0}\t{0}\n", i * 10_000 + 5_000 + 20_000))
        .collect();
    let points = write(dir.path(), "points.bed", &points);
    let row = score(&[
        "--truth",
        &truth,
        &points,
        "--bin-size",
        "10000",
        "--tolerance-bins",
        "2",
    ]);
    assert_eq!(value(&row, "true_positives"), 2.0);
    let line = run_err(&["score", "boundaries", "--truth", &truth, &points]);
    assert!(
        line.contains("points.bed") && line.contains("--bin-size"),
        "{line}"
    );

    // Output to a file.
    let out = dir.path().join("score.tsv");
    run_ok(&[
        "score",
        "boundaries",
        "--truth",
        &truth,
        &truth,
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(
        std::fs::read_to_string(&out)
            .unwrap()
            .starts_with("tolerance_bp\t")
    );
}

#[test]
fn domain_scores() {
    let dir = tempfile::tempdir().unwrap();
    let truth = write(dir.path(), "truth.bed", &bins(&[10, 20]));
    let tads = write(
        dir.path(),
        "tads.bed",
        "chr1\t0\t100000\t0\nchr1\t100000\t200000\t0\n",
    );
    let merged = write(dir.path(), "merged.bed", "chr1\t0\t200000\n");
    let nested = write(
        dir.path(),
        "nested.bed",
        "chr1\t0\t200000\nchr1\t0\t100000\n",
    );
    let same = score(&[
        "--truth",
        &truth,
        &truth,
        "--truth-domains",
        &tads,
        "--domains",
        &tads,
    ]);
    assert_eq!(value(&same, "mean_best_jaccard_truth"), 1.0);
    assert_eq!(value(&same, "moc"), 1.0);
    let row = score(&[
        "--truth",
        &truth,
        &truth,
        "--truth-domains",
        &tads,
        "--domains",
        &merged,
    ]);
    assert_eq!(value(&row, "mean_best_jaccard_truth"), 0.5);
    assert!(value(&row, "moc").abs() < 1e-12);
    let row = score(&[
        "--truth",
        &truth,
        &truth,
        "--truth-domains",
        &tads,
        "--domains",
        &nested,
    ]);
    assert!(value(&row, "moc").is_nan());
}

#[test]
fn bad_input_names_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let truth = write(dir.path(), "truth.bed", &bins(&[10, 20]));
    let bad = write(
        dir.path(),
        "bad.bed",
        "# calls\nchr1\t100\t200\nchr1\tabc\t300\n",
    );
    let line = run_err(&["score", "boundaries", "--truth", &truth, &bad]);
    assert!(
        line.contains("bad.bed:3:") && line.contains("'abc'"),
        "{line}"
    );
    let reversed = write(dir.path(), "reversed.bed", "chr1\t300\t200\n");
    let line = run_err(&["score", "boundaries", "--truth", &reversed, &truth]);
    assert!(
        line.contains("reversed.bed:1:") && line.contains("after end"),
        "{line}"
    );
    let short = write(dir.path(), "short.bed", "chr1\t300\n");
    let line = run_err(&["score", "boundaries", "--truth", &truth, &short]);
    assert!(line.contains("short.bed:1:"), "{line}");
    let missing = dir.path().join("missing.bed");
    let line = run_err(&[
        "score",
        "boundaries",
        "--truth",
        &truth,
        missing.to_str().unwrap(),
    ]);
    assert!(line.contains("missing.bed"), "{line}");
}

/// Issue 26: without a sequence (no --fasta, none in the file) the prediction's numbers are the
/// structure's: a prediction that cannot be numbered so is refused, one much longer than the
/// structure is scored with a warning, one that fits is scored silently.
#[test]
fn predictions_without_a_sequence_are_checked_against_the_structure() {
    let protein = |name: &str| data(&format!("protein/{name}"));
    // 1A8O is numbered 151-220: a 75-residue matrix cannot use its numbers.
    let line = run_err(&[
        "score",
        "contacts",
        "--structure",
        &protein("1a8o/1A8O.pdb.gz"),
        &protein("1atzA/1atzA.apc.mat.gz"),
    ]);
    assert!(line.contains("numbered 151-220"), "{line}");
    assert!(line.contains("--fasta"), "{line}");
    // toxd has 58 residues: a 75-residue prediction of 1atzA scores, with a warning.
    let out = crate::run(&[
        "score",
        "contacts",
        "--structure",
        &protein("toxd/toxd.pdb.gz"),
        &protein("1atzA/1atzA.apc.mat.gz"),
    ]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.starts_with("contactmap: warning: ")
            && stderr.contains("covers 75 residues")
            && stderr.contains("17 of its residues are not in the structure"),
        "{stderr}"
    );
    // toxd's own prediction (59 residues, the first unobserved): no warning.
    let out = crate::run(&[
        "score",
        "contacts",
        "--structure",
        &protein("toxd/toxd.pdb.gz"),
        &protein("toxd/toxd.mat.gz"),
    ]);
    assert!(out.status.success());
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `score loops` on a hand-made truth (with the fraction of samples) and calls: the counts and
/// ratios per class worked out by hand; the yeast dots scored against themselves; bad inputs.
#[test]
fn score_loops_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    let truth = write(
        dir.path(),
        "truth.bedpe",
        "chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tfraction\tsamples\n\
         chr1\t100000\t105000\tchr1\t200000\t205000\t0.5\t40\n\
         chr1\t300000\t305000\tchr1\t400000\t405000\t0.1\t8\n\
         chr1\t1000000\t1005000\tchr1\t3000000\t3005000\t0.3\t24\n",
    );
    // one near the first loop, one near the weak second, one far from all, one duplicate
    let calls = write(
        dir.path(),
        "calls.bedpe",
        "chr1\t105000\t110000\tchr1\t200000\t205000\n\
         chr1\t300000\t305000\tchr1\t395000\t400000\n\
         chr1\t2000000\t2005000\tchr1\t2500000\t2505000\n\
         chr1\t100000\t105000\tchr1\t195000\t200000\n",
    );
    let text = run_ok(&[
        "score",
        "loops",
        "--truth",
        &truth,
        &calls,
        "--tolerance",
        "10k",
        "--min-fraction",
        "0.2",
    ]);
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split('\t').collect()).collect();
    assert_eq!(rows[0][0], "class");
    // class n_truth n_calls n_weak truth_matched calls_matched precision recall f1
    let got: Vec<String> = rows[1..]
        .iter()
        .map(|r| [r[0], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10]].join(" "))
        .collect();
    assert_eq!(
        got,
        [
            "0bp-100kb 0 3 1 0 1 0.500000 0.000000 0.000000",
            "100kb-1Mb 1 1 0 1 0 0.000000 1.000000 0.000000",
            "1Mb+ 1 0 0 0 0 0.000000 0.000000 0.000000",
            "all 2 4 1 1 1 0.333333 0.500000 0.400000",
        ]
    );
    // without --min-fraction every truth loop counts
    let text = run_ok(&[
        "score",
        "loops",
        "--truth",
        &truth,
        &calls,
        "--tolerance",
        "10k",
    ]);
    let all: Vec<&str> = text.lines().last().unwrap().split('\t').collect();
    assert_eq!(&all[3..8], ["3", "4", "0", "2", "2"]);
    // a map's dots against themselves
    let dots = dir.path().join("dots.tsv");
    run_ok(&[
        "dots",
        &data("yeast.10kb.cool"),
        "-o",
        &dots.to_string_lossy(),
    ]);
    let dots = dots.to_string_lossy().into_owned();
    let text = run_ok(&["score", "loops", "--truth", &dots, &dots]);
    assert!(
        text.lines()
            .last()
            .unwrap()
            .ends_with("\t1.000000\t1.000000\t1.000000"),
        "{text}"
    );
    // bad inputs: one line, exit 2, no file
    let out = dir.path().join("out.tsv");
    let out_s = out.to_string_lossy().into_owned();
    let cases: [(&str, [&str; 2], &str); 3] = [
        (&calls, ["--min-fraction", "0.2"], "7th column"),
        (&truth, ["--tolerance", "ten"], "--tolerance"),
        (&truth, ["--distance-classes", "5k,1M"], "start at 0"),
    ];
    for (truth, [option, value], expected) in cases {
        let line = run_err(&[
            "score", "loops", "--truth", truth, &calls, option, value, "-o", &out_s,
        ]);
        assert!(line.contains(expected), "{option} {value}: {line}");
    }
    assert!(!out.exists());
}
