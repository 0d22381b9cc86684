//! `contactmap pileup` against coolpuppy 1.1.0 (data/reference/pileup,
//! scripts/pileup_reference.py), and its refusals of bad inputs.

use super::*;

#[allow(dead_code)] // the CLI tests read the grids and counts, not the controls
#[path = "../support/pileup_reference.rs"]
mod pileup_reference;
use pileup_reference::reference_case;

/// The truth loops of the simulated map piled up as observed/expected: coolpuppy's grid and
/// scores; the features' format read from the content.
#[test]
fn pileup_of_loops_is_coolpuppy() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("loops").to_string_lossy().into_owned();
    let text = std::fs::read_to_string(data("sim_extrusion.truth_loops.bedpe")).unwrap();
    // a BEDPE named .bed is read as BED, as coolpuppy reads it: the error says so and how to
    // force the other format
    let named_bed = write(dir.path(), "loops.bed", &text);
    let map = data("sim_extrusion.5kb.cool");
    let line = run_err(&["pileup", &map, &named_bed, "--flank", "20k", "-o", &prefix]);
    assert!(
        line.contains(
            "read as BED: its extension is .bed; --features-format bedpe reads it as BEDPE"
        ),
        "{line}"
    );
    // without an extension that decides, a BEDPE read from its content
    let features = write(dir.path(), "loops.txt", &text);
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
    let (n, reference) = reference_group("bedpe_oe", "all");
    assert_eq!(n, 8);
    same_grid(&read_grid(&format!("{prefix}.pileup.tsv")), &reference);
    let scores = scores_table(&format!("{prefix}.scores.tsv"));
    let value = |name: &str| score(&scores, "all", name);
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

/// The scores table: its header and rows.
fn scores_table(path: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text
        .lines()
        .map(|l| l.split('\t').map(str::to_string).collect());
    (lines.next().unwrap(), lines.collect())
}

/// The score `name` of group `group`.
fn score(table: &(Vec<String>, Vec<Vec<String>>), group: &str, name: &str) -> f64 {
    let column = table.0.iter().position(|h| h == name).unwrap();
    let row = table.1.iter().find(|r| r[0] == group).unwrap();
    row[column].parse().unwrap()
}

/// A grid file as written (tab-separated numbers, `nan`).
fn read_grid(path: &str) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| l.split('\t').map(|v| v.parse().unwrap()).collect())
        .collect()
}

/// A reference grid of case NAME of `data/reference/pileup/pileups.tsv.gz` for group `label`
/// (see scripts/pileup_reference.py): its `n` and rows.
fn reference_group(name: &str, label: &str) -> (usize, Vec<Vec<f64>>) {
    let path = data("reference/pileup/pileups.tsv.gz");
    let group = reference_case(path.as_ref(), name)
        .into_iter()
        .find(|g| g.label == label)
        .unwrap();
    (group.n, group.grid)
}

/// Our grid file's rows equal the reference's to 1e-12 relative (NaN where it is NaN).
fn same_grid(ours: &[Vec<f64>], theirs: &[Vec<f64>]) {
    assert_eq!(ours.len(), theirs.len());
    for (a, b) in ours.iter().zip(theirs) {
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(b) {
            assert!(
                (x.is_nan() && y.is_nan()) || (x - y).abs() <= 1e-12 * y.abs(),
                "{x} vs {y}"
            );
        }
    }
}

/// Shifted controls with a seed, rescaled domains, distance groups: coolpuppy's pileups, the
/// groups' grids in PREFIX.groups.tsv, their scores one line per group.
#[test]
fn pileup_options_give_coolpuppys_pileups() {
    let dir = tempfile::tempdir().unwrap();
    let sim = data("sim_extrusion.5kb.cool");
    // shifts: same seed, same file; coolpuppy's pileup
    let mut outputs = Vec::new();
    for k in 0..2 {
        let prefix = dir
            .path()
            .join(format!("shifts{k}"))
            .to_string_lossy()
            .into_owned();
        let args = [
            "pileup",
            &sim,
            &data("reference/pileup/anchors.bed"),
            "--nshifts",
            "5",
            "--seed",
            "7",
            "--flank",
            "30k",
            "-o",
            &prefix,
        ];
        let out = run(&args);
        assert!(out.status.success());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("shifted controls (seed 7)"), "{stderr}");
        outputs.push(std::fs::read(format!("{prefix}.pileup.tsv")).unwrap());
        let scores = scores_table(&format!("{prefix}.scores.tsv"));
        assert_eq!(score(&scores, "all", "control_n"), 39.0);
        same_grid(
            &read_grid(&format!("{prefix}.pileup.tsv")),
            &reference_group("bed_shifts", "all").1,
        );
    }
    assert_eq!(outputs[0], outputs[1]);
    // rescaled local domains
    let prefix = dir.path().join("domains").to_string_lossy().into_owned();
    let out = run(&[
        "pileup",
        &sim,
        &data("reference/pileup/domains.bed"),
        "--local",
        "--rescale",
        "--rescale-size",
        "33",
        "-o",
        &prefix,
    ]);
    assert!(out.status.success());
    same_grid(
        &read_grid(&format!("{prefix}.pileup.tsv")),
        &reference_group("bed_local_rescale_oe", "all").1,
    );
    let scores = scores_table(&format!("{prefix}.scores.tsv"));
    assert!(score(&scores, "all", "domain_score") > 1.0);
    // by distance: a grid per band in PREFIX.groups.tsv
    let prefix = dir.path().join("bands").to_string_lossy().into_owned();
    let out = run(&[
        "pileup",
        &sim,
        &data("reference/pileup/anchors.bed"),
        "--flank",
        "20k",
        "--mindist",
        "100k",
        "--by-distance",
        "-o",
        &prefix,
    ]);
    assert!(out.status.success());
    let groups = std::fs::read_to_string(format!("{prefix}.groups.tsv")).unwrap();
    let band: Vec<Vec<f64>> = groups
        .lines()
        .filter(|l| l.starts_with("0.2Mb-0.4Mb\t"))
        .map(|l| l.split('\t').skip(2).map(|v| v.parse().unwrap()).collect())
        .collect();
    let (n, want) = reference_group("bed_by_distance_oe", "0.2Mb-0.4Mb");
    same_grid(&band, &want);
    let scores = scores_table(&format!("{prefix}.scores.tsv"));
    assert_eq!(score(&scores, "0.2Mb-0.4Mb", "n"), n as f64);
    assert_eq!(scores.1.last().unwrap()[0], "all");
    // coverage normalisation: raw counts only (as coolpuppy); with --raw, coolpuppy's
    let line = run_err(&[
        "pileup",
        &sim,
        &data("reference/pileup/anchors.bed"),
        "--coverage-norm",
        "-o",
        &prefix,
    ]);
    assert!(line.contains("--raw"), "{line}");
    let prefix = dir.path().join("cov").to_string_lossy().into_owned();
    let out = run(&[
        "pileup",
        &sim,
        &data("reference/pileup/anchors.bed"),
        "--coverage-norm",
        "--raw",
        "--no-expected",
        "--flank",
        "30k",
        "-o",
        &prefix,
    ]);
    assert!(out.status.success());
    same_grid(
        &read_grid(&format!("{prefix}.pileup.tsv")),
        &reference_group("bed_covnorm", "all").1,
    );
    // shifts and an expected are two normalisations
    let line = run_err(&[
        "pileup",
        &sim,
        &data("reference/pileup/anchors.bed"),
        "--nshifts",
        "2",
        "--no-expected",
        "-o",
        &prefix,
    ]);
    assert!(
        line.contains("--no-expected") && line.contains("--nshifts"),
        "{line}"
    );
    let line = run_err(&[
        "pileup",
        &sim,
        &data("reference/pileup/domains.bed"),
        "--local",
        "--rescale",
        "--rescale-size",
        "32",
        "-o",
        &dir.path().join("even").to_string_lossy(),
    ]);
    assert!(line.contains("--rescale-size 32"), "{line}");
}

/// The groups' grids in PREFIX.npz (numpy's layout, read back here from the archive) and their
/// picture: one panel per group.
#[test]
fn pileup_npz_and_picture() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("g").to_string_lossy().into_owned();
    let out = run(&[
        "pileup",
        &data("sim_extrusion.5kb.cool"),
        &data("reference/pileup/anchors.stranded.bed"),
        "--flank",
        "20k",
        "--mindist",
        "100k",
        "--by-strand",
        "--npz",
        "-o",
        &prefix,
    ]);
    assert!(out.status.success());
    let bytes = std::fs::read(format!("{prefix}.npz")).unwrap();
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
    let mut names: Vec<String> = archive.file_names().map(str::to_string).collect();
    names.sort();
    assert_eq!(names, ["data.npy", "group.npy", "n.npy", "num.npy"]);
    let mut data = Vec::new();
    std::io::Read::read_to_end(&mut archive.by_name("data.npy").unwrap(), &mut data).unwrap();
    let header_len = u16::from_le_bytes([data[8], data[9]]) as usize;
    let header = std::str::from_utf8(&data[10..10 + header_len]).unwrap();
    // four strand pairs and all, 9 x 9 each
    assert!(header.contains("'shape': (5, 9, 9)"), "{header}");
    let values: Vec<f64> = data[10 + header_len..]
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    // the last grid is the pileup of all, as PREFIX.pileup.tsv holds it
    let grid: Vec<f64> = std::fs::read_to_string(format!("{prefix}.pileup.tsv"))
        .unwrap()
        .split(['\t', '\n'])
        .filter(|v| !v.is_empty())
        .map(|v| v.parse().unwrap())
        .collect();
    for (a, b) in values[4 * 81..].iter().zip(&grid) {
        assert!(a == b || (a.is_nan() && b.is_nan()));
    }
    let png = dir.path().join("g.png").to_string_lossy().into_owned();
    let out = run(&["plot", "pileup", &prefix, "-o", &png, "--width", "6"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    assert_eq!(u32::from_be_bytes(bytes[16..20].try_into().unwrap()), 600);
    let svg = run(&["plot", "pileup", &prefix, "-o", "-", "--to", "svg"]);
    let text = String::from_utf8_lossy(&svg.stdout);
    // five panels and the colour bar
    assert_eq!(text.matches("<image").count(), 6);
    assert!(text.contains(">+-<") && text.contains(">all<"));
    let line = run_err(&["plot", "pileup", &prefix, "--vmax", "0.5", "-o", &png]);
    assert!(line.contains("--vmax 0.5"), "{line}");
    let missing = dir.path().join("none").to_string_lossy().into_owned();
    let line = run_err(&["plot", "pileup", &missing, "-o", &png]);
    assert!(line.contains("none.pileup.tsv"), "{line}");
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
    // nothing piled up: refused (exit 2), nothing written
    let far = write(dir.path(), "far.bed", "chr1\t0\t5000\n");
    let empty = dir.path().join("empty").to_string_lossy().into_owned();
    let out = run(&["pileup", &sim, &far, "--local", "-o", &empty]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("no snippet to pile up") && stderr.contains("1 too close to an edge"),
        "{stderr}"
    );
    assert!(!std::path::Path::new(&format!("{empty}.pileup.tsv")).exists());
}

/// --groupby and --trans: coolpuppy's grids, the groups in PREFIX.groups.tsv; an unknown
/// grouping column refused in one line.
#[test]
fn pileup_groupby_and_trans_are_coolpuppy() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("grouped").to_string_lossy().into_owned();
    let grouped = data("reference/pileup/anchors.grouped.bed");
    let args = [
        "pileup",
        &data("sim_extrusion.5kb.cool"),
        &grouped,
        "--groupby",
        "name1,name2",
        "--flank",
        "20k",
        "--mindist",
        "100k",
        "-o",
        &prefix,
    ];
    let out = run(&args);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("4 groups beside the one of all"),
        "{stderr}"
    );
    same_grid(
        &read_grid(&format!("{prefix}.pileup.tsv")),
        &reference_group("bed_groupby_oe", "all").1,
    );
    let groups = std::fs::read_to_string(format!("{prefix}.groups.tsv")).unwrap();
    let b_a: Vec<Vec<f64>> = groups
        .lines()
        .filter(|l| l.starts_with("B,A\t"))
        .map(|l| l.split('\t').skip(2).map(|v| v.parse().unwrap()).collect())
        .collect();
    same_grid(&b_a, &reference_group("bed_groupby_oe", "B,A").1);
    let scores = scores_table(&format!("{prefix}.scores.tsv"));
    assert_eq!(score(&scores, "A,A", "n"), 20.0);
    // between chromosomes: every chrII anchor with every chrIV one, over the trans expected
    let prefix = dir.path().join("trans").to_string_lossy().into_owned();
    let out = run(&[
        "pileup",
        &data("yeast.10kb.cool"),
        &data("reference/pileup/yeast_anchors.bed"),
        "--trans",
        "--flank",
        "30k",
        "-o",
        &prefix,
    ]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("pileup of 406 snippets (7 x 7 bins, between chromosomes)"),
        "{stderr}"
    );
    same_grid(
        &read_grid(&format!("{prefix}.pileup.tsv")),
        &reference_group("yeast_trans_oe", "all").1,
    );
    // a grouping column the file lacks: one line naming the columns it has
    let line = run_err(&[
        "pileup",
        &data("sim_extrusion.5kb.cool"),
        &grouped,
        "--groupby",
        "class1",
        "-o",
        &prefix,
    ]);
    assert!(
        line.contains("--groupby class1") && line.contains("chrom, start, end, name"),
        "{line}"
    );
}

/// Issue 51: a BEDPE whose chromosomes are named by numbers (Ensembl, NCBI), as `contactmap dots`
/// writes it, is read as BEDPE from its content, whatever its extension says it is not; features
/// on `chr21` against a map of `21` are refused, the prefix named.
#[test]
fn pileup_reads_bedpe_of_numbered_chromosomes() {
    let dir = tempfile::tempdir().unwrap();
    // a 2 Mb map of chromosome 21 at 10 kb: counts decaying with distance, a dot at 500-800 kb
    let sizes = write(dir.path(), "ensembl.sizes", "21\t2000000\n");
    let mut bg2 = String::new();
    for i in 0..200u64 {
        for d in 0..40u64.min(200 - i) {
            let j = i + d;
            let dot = if (i, j) == (50, 80) { 50 } else { 0 };
            let count = 200 / (d + 1) + dot;
            let (a, b) = (i * 10_000, j * 10_000);
            bg2.push_str(&format!(
                "21\t{a}\t{}\t21\t{b}\t{}\t{count}\n",
                a + 10_000,
                b + 10_000
            ));
        }
    }
    let bg2 = write(dir.path(), "ensembl.bg2", &bg2);
    let map = dir
        .path()
        .join("ensembl.cool")
        .to_string_lossy()
        .into_owned();
    run_ok(&[
        "convert",
        &bg2,
        &map,
        "--chrom-sizes",
        &sizes,
        "--bin-size",
        "10000",
    ]);
    let header = "chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tcount\n";
    let dots = format!("{header}21\t500000\t510000\t21\t800000\t810000\t50\n");
    let prefix = dir.path().join("p").to_string_lossy().into_owned();
    for name in ["dots.tsv", "dots.bedpe"] {
        let features = write(dir.path(), name, &dots);
        let args = [
            "pileup",
            &map,
            &features,
            "--raw",
            "--no-expected",
            "--flank",
            "50k",
        ];
        let out = run(&[&args[..], &["-o", &prefix]].concat());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{name}: {stderr}");
        assert!(stderr.contains("read 1 BEDPE pairs"), "{name}: {stderr}");
        // the dot at the centre of the 11 x 11 grid: 200 / 31 + 50 (integer division)
        let grid = read_grid(&format!("{prefix}.pileup.tsv"));
        assert_eq!(grid[5][5], (200 / 31 + 50) as f64, "{name}");
    }
    // chr21 against 21: refused, the names' difference said
    let prefixed = write(
        dir.path(),
        "ucsc.bedpe",
        &dots
            .replace("\n21\t", "\nchr21\t")
            .replace("\t21\t", "\tchr21\t"),
    );
    let out = run(&[
        "pileup",
        &map,
        &prefixed,
        "--raw",
        "--no-expected",
        "--flank",
        "50k",
        "-o",
        &prefix,
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("1 on chromosomes the map lacks (chr21: the matrix names it '21'"),
        "{stderr}"
    );
}
