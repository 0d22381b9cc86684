//! `contactmap pileup` against coolpuppy 1.1.0 (data/reference/pileup,
//! scripts/pileup_reference.py), and its refusals of bad inputs.

use super::*;

/// The truth loops of the simulated map piled up as observed/expected: coolpuppy's grid and
/// scores; the features' format read from the content.
#[test]
fn pileup_of_loops_is_coolpuppy() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("loops").to_string_lossy().into_owned();
    // a BEDPE named .bed: read as BEDPE from its content
    let features = write(
        dir.path(),
        "loops.bed",
        &std::fs::read_to_string(data("sim_extrusion.truth_loops.bedpe")).unwrap(),
    );
    let out = run(&[
        "pileup",
        &data("sim_extrusion.5kb.cool"),
        &features,
        "--flank",
        "20k",
        "-o",
        &prefix,
    ]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("read 8 BEDPE pairs"), "{stderr}");
    let grid = std::fs::read_to_string(format!("{prefix}.pileup.tsv")).unwrap();
    let reference = reference_table("reference/pileup/bedpe_oe.tsv.gz");
    // the reference's first line (# n=8) is its header
    assert_eq!(reference.header, ["# n=8"]);
    assert_eq!(grid.lines().count(), reference.rows.len());
    for (ours, theirs) in grid.lines().zip(&reference.rows) {
        assert_eq!(ours.split('\t').count(), theirs.len());
        for (x, y) in ours.split('\t').zip(theirs) {
            let (x, y): (f64, f64) = (x.parse().unwrap(), y.parse().unwrap());
            assert!((x - y).abs() <= 1e-12 * y.abs(), "{x} vs {y}");
        }
    }
    let scores = std::fs::read_to_string(format!("{prefix}.scores.tsv")).unwrap();
    let value = |name: &str| -> f64 {
        let line = scores
            .lines()
            .find(|l| l.starts_with(&format!("{name}\t")))
            .unwrap();
        line.split('\t').nth(1).unwrap().parse().unwrap()
    };
    assert_eq!(value("n"), 8.0);
    let table = std::fs::read_to_string(data("reference/pileup/scores.tsv")).unwrap();
    let want: f64 = table
        .lines()
        .find(|l| l.starts_with("bedpe_oe\tenrichment\t3\t"))
        .unwrap()
        .split('\t')
        .nth(3)
        .unwrap()
        .parse()
        .unwrap();
    assert!((value("enrichment_3x3") - want).abs() <= 1e-12 * want);
}

#[test]
fn pileup_refuses_bad_inputs_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("out").to_string_lossy().into_owned();
    let sim = data("sim_extrusion.5kb.cool");
    let anchors = data("reference/pileup/anchors.bed");
    // a flank smaller than a bin, or not a whole number of bins
    let line = run_err(&["pileup", &sim, &anchors, "--flank", "2k", "-o", &prefix]);
    assert!(line.contains("--flank 2000"), "{line}");
    // an unbalanced map without --raw
    let line = run_err(&[
        "pileup",
        &data("hg19.GM12878-MboI.matrix.2000kb.cool"),
        &anchors,
        "-o",
        &prefix,
    ]);
    assert!(line.contains("weight"), "{line}");
    // a BED with start after end
    let bad = write(dir.path(), "bad.bed", "chr1\t500000\t400000\n");
    let line = run_err(&["pileup", &sim, &bad, "-o", &prefix]);
    assert!(
        line.contains("bad.bed:1") && line.contains("after end"),
        "{line}"
    );
    // --local with pairs
    let line = run_err(&[
        "pileup",
        &sim,
        &data("sim_extrusion.truth_loops.bedpe"),
        "--local",
        "-o",
        &prefix,
    ]);
    assert!(line.contains("--local"), "{line}");
    assert!(!std::path::Path::new(&format!("{prefix}.pileup.tsv")).exists());
    // features on a chromosome the map lacks: counted and said, not an error
    let other = write(
        dir.path(),
        "other.bed",
        "chr1\t300000\t305000\nchrX\t300000\t305000\nchr1\t600000\t605000\n",
    );
    let out = run(&["pileup", &sim, &other, "--flank", "20k", "-o", &prefix]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("pileup of 1 snippets"), "{stderr}");
    assert!(
        stderr.contains("1 on chromosomes the map lacks"),
        "{stderr}"
    );
    // reversed anchors: piled up (all NaN) and said; nothing piled up: said
    let reversed = write(
        dir.path(),
        "reversed.bedpe",
        "chr1\t500000\t505000\tchr1\t300000\t305000\n",
    );
    let out = run(&["pileup", &sim, &reversed, "--flank", "20k", "-o", &prefix]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("warning: 1 pairs have anchor 2 upstream"),
        "{stderr}"
    );
    let far = write(dir.path(), "far.bed", "chr1\t0\t5000\n");
    let out = run(&["pileup", &sim, &far, "--local", "-o", &prefix]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("warning: no snippet was piled up"),
        "{stderr}"
    );
}
