//! `contactmap saddle`: the cis saddle of the phased E1 of dm6 at 100 kb equals cooltools 0.7.1's
//! (data/reference/compartments, scripts/fixtures/compartments_reference.py).

use super::*;

/// The phased E1 that cooltools computed, on the map's bins, as a track file.
fn e1_track(dir: &std::path::Path, uri: &str) -> String {
    let bins = run_ok(&["dump", "-t", "bins", uri]);
    let vecs = reference_table("reference/compartments/dm6_100kb.eigs_cis_phased.vecs.tsv.gz");
    let e1 = vecs.header.iter().position(|h| h == "E1").unwrap();
    let mut text = String::from("chrom\tstart\tend\tE1\n");
    let lines: Vec<&str> = bins.lines().collect();
    assert_eq!(lines.len(), vecs.rows.len());
    for (line, row) in lines.iter().zip(&vecs.rows) {
        let fields: Vec<&str> = line.split('\t').collect();
        text.push_str(&format!(
            "{}\t{}\t{}\t{}\n",
            fields[0], fields[1], fields[2], row[e1]
        ));
    }
    let path = dir.join("e1.tsv");
    std::fs::write(&path, text).unwrap();
    path.to_string_lossy().into_owned()
}

fn number(text: &str) -> f64 {
    text.parse().unwrap()
}

#[test]
fn saddle_equals_cooltools() {
    let dir = tempfile::tempdir().unwrap();
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    let track = format!("{}:E1", e1_track(dir.path(), &uri));
    let prefix = dir.path().join("dm6").to_string_lossy().into_owned();
    run_ok(&[
        "saddle",
        &uri,
        "--track",
        &track,
        "--n-bins",
        "10",
        "--qrange",
        "0.025,0.975",
        "-o",
        &prefix,
    ]);
    let read =
        |suffix: &str| parse_table(&std::fs::read_to_string(format!("{prefix}.{suffix}")).unwrap());
    let got = read("saddle.tsv");
    let want = reference_table("reference/compartments/dm6_100kb.saddle.tsv.gz");
    assert_eq!(got.header, want.header);
    assert_eq!(got.rows.len(), 144);
    for (g, w) in got.rows.iter().zip(&want.rows) {
        assert_eq!(g[..2], w[..2]);
        // the same digitisation: every count equal
        assert_eq!(number(&g[3]), number(&w[3]), "{g:?} {w:?}");
        // sums to the reference's 10 digits
        let (gs, ws) = (number(&g[2]), number(&w[2]));
        assert!((gs - ws).abs() <= 1e-9 * ws.abs(), "{g:?} {w:?}");
    }
    let edges = read("edges.tsv");
    let want_edges = reference_table("reference/compartments/dm6_100kb.saddle_edges.tsv.gz");
    for (g, w) in edges.rows.iter().zip(&want_edges.rows) {
        assert!((number(&g[0]) - number(&w[0])).abs() <= 1e-9, "{g:?} {w:?}");
    }
    let strength = read("strength.tsv");
    let want_strength = reference_table("reference/compartments/dm6_100kb.saddle_strength.tsv.gz");
    // cooltools' first entry (k = 0) is a placeholder 0; ours starts at k = 1
    assert_eq!(strength.rows.len() + 1, want_strength.rows.len());
    for (g, w) in strength.rows.iter().zip(&want_strength.rows[1..]) {
        assert_eq!(g[0], w[0]);
        let (gs, ws) = (number(&g[1]), number(&w[1]));
        assert!((gs - ws).abs() <= 1e-9 * ws.abs(), "{g:?} {w:?}");
    }
    let digitized = read("digitized.tsv");
    assert_eq!(digitized.header[3], "E1.d");
    assert_eq!(digitized.rows.len(), 1380);
}

#[test]
fn a_track_on_other_bins_or_a_bad_range_exits_2_without_files() {
    let dir = tempfile::tempdir().unwrap();
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    let prefix = dir.path().join("x").to_string_lossy().into_owned();
    let coarse = dir.path().join("coarse.bedgraph");
    std::fs::write(
        &coarse,
        "chr2L\t0\t1000000\t0.5\nchr2L\t1000000\t2000000\t-0.5\n",
    )
    .unwrap();
    let line = run_err(&[
        "saddle",
        &uri,
        "--track",
        &format!("{}:4", coarse.display()),
        "-o",
        &prefix,
    ]);
    assert!(
        line.contains("chr2L:0-1000000 is not a bin of the map"),
        "{line}"
    );
    let track = format!("{}:E1", e1_track(dir.path(), &uri));
    let line = run_err(&[
        "saddle", &uri, "--track", &track, "--qrange", "0.9,0.1", "-o", &prefix,
    ]);
    assert!(line.contains("quantile range"), "{line}");
    let line = run_err(&[
        "saddle", &uri, "--track", &track, "--qrange", "0.1", "-o", &prefix,
    ]);
    assert!(line.contains("two numbers"), "{line}");
    let outputs: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('x') || n.starts_with(".x"))
        .collect();
    assert!(outputs.is_empty(), "{outputs:?}");
}

#[test]
fn trans_saddle_equals_cooltools() {
    // cooltools.saddle(contact_type="trans") on CN.mm9 10 Mb with its eigs_trans E1 and
    // expected_trans, 10 classes, qrange 0.025-0.975
    let dir = tempfile::tempdir().unwrap();
    let uri = data("CN.mm9.10000kb.cool");
    let bins = run_ok(&["dump", "-t", "bins", &uri]);
    let vecs = reference_table("reference/compartments/mm9_10Mb.eigs_trans.vecs.tsv.gz");
    let mut text = String::from("chrom\tstart\tend\tE1\n");
    for (line, row) in bins.lines().zip(&vecs.rows) {
        let f: Vec<&str> = line.split('\t').collect();
        text.push_str(&format!("{}\t{}\t{}\t{}\n", f[0], f[1], f[2], row[0]));
    }
    let track = dir.path().join("e1.tsv");
    std::fs::write(&track, text).unwrap();
    let prefix = dir.path().join("t").to_string_lossy().into_owned();
    let track_arg = format!("{}:E1", track.display());
    run_ok(&[
        "saddle",
        &uri,
        "--track",
        &track_arg,
        "--n-bins",
        "10",
        "--contact-type",
        "trans",
        "-o",
        &prefix,
    ]);
    let got = parse_table(&std::fs::read_to_string(format!("{prefix}.saddle.tsv")).unwrap());
    let want = reference_table("reference/compartments/mm9_10Mb.saddle_trans.tsv.gz");
    assert_eq!(got.rows.len(), 144);
    for (g, w) in got.rows.iter().zip(&want.rows) {
        assert_eq!(g[..2], w[..2]);
        assert_eq!(number(&g[3]), number(&w[3]), "counts {g:?} {w:?}");
        let (gs, ws) = (number(&g[2]), number(&w[2]));
        assert!(
            (gs - ws).abs() <= 1e-9 * ws.abs().max(1e-300),
            "sums {g:?} {w:?}"
        );
    }
}

/// Issue 26: a successful run says what it found and how it oriented it: `compartments`
/// without a phasing track says the sign follows coverage; `saddle` prints its strength (the
/// k = n/5 row of its table); `plot saddle` names the track (E1) on its axes.
#[test]
fn runs_say_their_orientation_and_strength_and_the_picture_names_the_track() {
    let dir = tempfile::tempdir().unwrap();
    let uri = crate::data("cooler_test_file.mcool::100000");
    let prefix = dir.path().join("c");
    let out = crate::run(&["compartments", &uri, "-o", prefix.to_str().unwrap()]);
    assert!(out.status.success());
    let note = String::from_utf8_lossy(&out.stderr);
    assert!(
        note.contains("no phasing track") && note.contains("coverage"),
        "{note}"
    );
    let track = format!("{}.cis.vecs.tsv:E1", prefix.display());
    let saddle = dir.path().join("s");
    let out = crate::run(&[
        "saddle",
        &uri,
        "--track",
        &track,
        "-o",
        saddle.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let note = String::from_utf8_lossy(&out.stderr);
    let table = std::fs::read_to_string(dir.path().join("s.strength.tsv")).unwrap();
    let k10: f64 = table
        .lines()
        .find_map(|l| l.strip_prefix("10\t"))
        .unwrap()
        .parse()
        .unwrap();
    assert!(
        note.contains(&format!("E1 saddle strength {k10:.4}")),
        "{note} vs {k10}"
    );
    let svg = dir.path().join("s.svg");
    crate::run_ok(&[
        "plot",
        "saddle",
        dir.path().join("s.saddle.tsv").to_str().unwrap(),
        "-o",
        svg.to_str().unwrap(),
    ]);
    assert!(
        std::fs::read_to_string(&svg)
            .unwrap()
            .contains("E1 class (low to high)")
    );
}
