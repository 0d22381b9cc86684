//! `contactmap compartments`: eigenvectors and eigenvalues equal cooltools 0.7.1's eigs_cis (dm6,
//! 100 kb, with and without a phasing track) and eigs_trans (CN.mm9, 10 Mb)
//! (data/reference/compartments, scripts/fixtures/compartments_reference.py).

use super::*;

fn number(text: &str) -> f64 {
    if text.is_empty() {
        f64::NAN
    } else {
        text.parse().unwrap()
    }
}

fn column(table: &Table, name: &str) -> Vec<f64> {
    let c = table
        .header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {:?}", table.header));
    table.rows.iter().map(|r| number(&r[c])).collect()
}

/// The dm6 100 kb phasing track of the references, as FILE:COLUMN.
fn phasing_track() -> String {
    format!(
        "{}:track",
        data("reference/compartments/dm6_100kb.phasing.tsv.gz")
    )
}

/// `contactmap compartments` on dm6 at 100 kb, phased by [`phasing_track`], to `prefix`.
fn dm6_phased(prefix: &str) {
    run_ok(&[
        "compartments",
        &data("cooler_test_file.mcool::/resolutions/100000"),
        "--phasing-track",
        &phasing_track(),
        "-o",
        prefix,
    ]);
}

fn read(path: &str) -> Table {
    parse_table(&std::fs::read_to_string(path).unwrap())
}

/// Values equal to `tol` (relative to the largest magnitude), NaN at the same places; with
/// `up_to_sign`, each chromosome's vector may be the negated reference.
fn assert_vectors(
    got: &[f64],
    want: &[f64],
    chroms: &[String],
    tol: f64,
    up_to_sign: bool,
    what: &str,
) {
    assert_eq!(got.len(), want.len(), "{what}");
    let scale = want
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |a, v| a.max(v.abs()));
    let mut start = 0;
    while start < got.len() {
        let end = (start..got.len())
            .find(|&k| chroms[k] != chroms[start])
            .unwrap_or(got.len());
        let (g, w) = (&got[start..end], &want[start..end]);
        let diff = |sign: f64| {
            g.iter().zip(w).fold(0.0f64, |m, (a, b)| {
                assert_eq!(
                    a.is_nan(),
                    b.is_nan(),
                    "{what} {}: NaN pattern",
                    chroms[start]
                );
                if a.is_nan() {
                    m
                } else {
                    m.max((a - sign * b).abs())
                }
            })
        };
        let d = if up_to_sign {
            diff(1.0).min(diff(-1.0))
        } else {
            diff(1.0)
        };
        assert!(
            d <= tol * scale,
            "{what} {}: max difference {d}",
            chroms[start]
        );
        start = end;
    }
}

fn eigvals_equal(got: &Table, want: &Table, n: usize) {
    assert_eq!(got.rows.len(), want.rows.len());
    for k in 1..=n {
        let name = format!("eigval{k}");
        for (g, w) in column(got, &name).iter().zip(column(want, &name)) {
            assert_eq!(g.is_nan(), w.is_nan(), "{name}");
            if w.is_finite() {
                assert!((g - w).abs() <= 1e-9 * w.abs(), "{name}: {g} vs {w}");
            }
        }
    }
}

#[test]
fn eigs_cis_equals_cooltools_with_and_without_phasing() {
    let dir = tempfile::tempdir().unwrap();
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    let want_vecs = reference_table("reference/compartments/dm6_100kb.eigs_cis_phased.vecs.tsv.gz");
    let phasing = phasing_track();
    for phased in [false, true] {
        let prefix = dir
            .path()
            .join(if phased { "p" } else { "u" })
            .to_string_lossy()
            .into_owned();
        let mut args = vec!["compartments", uri.as_str(), "-o", prefix.as_str()];
        if phased {
            args.extend(["--phasing-track", phasing.as_str()]);
        }
        run_ok(&args);
        let vecs = read(&format!("{prefix}.cis.vecs.tsv"));
        // cooltools' columns: the bin table's (every weight column, by name), then E1..E3
        assert_eq!(
            vecs.header,
            [
                "chrom", "start", "end", "KR", "SCALE", "VC", "VC_SQRT", "weight", "E1", "E2", "E3"
            ]
        );
        let chroms: Vec<String> = vecs.rows.iter().map(|r| r[0].clone()).collect();
        for name in ["E1", "E2", "E3"] {
            // to 1e-9 of the largest value (the reference keeps 10 significant digits)
            assert_vectors(
                &column(&vecs, name),
                &column(&want_vecs, name),
                &chroms,
                1e-9,
                !phased,
                name,
            );
        }
        let lam = read(&format!("{prefix}.cis.lam.txt"));
        assert_eq!(lam.header[..4], ["chrom", "start", "end", "name"]);
        let want_lam = reference_table(if phased {
            "reference/compartments/dm6_100kb.eigs_cis_phased.vals.tsv.gz"
        } else {
            "reference/compartments/dm6_100kb.eigs_cis.vals.tsv.gz"
        });
        eigvals_equal(&lam, &want_lam, 3);
    }
}

#[test]
fn eigs_trans_equals_cooltools() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("t").to_string_lossy().into_owned();
    run_ok(&[
        "compartments",
        &data("CN.mm9.10000kb.cool"),
        "--trans",
        "-o",
        &prefix,
    ]);
    let vecs = read(&format!("{prefix}.trans.vecs.tsv"));
    let want = reference_table("reference/compartments/mm9_10Mb.eigs_trans.vecs.tsv.gz");
    // one genome-wide vector: compared up to one sign
    let genome = vec![String::new(); vecs.rows.len()];
    for name in ["E1", "E2", "E3"] {
        assert_vectors(
            &column(&vecs, name),
            &column(&want, name),
            &genome,
            1e-8,
            true,
            name,
        );
    }
    eigvals_equal(
        &read(&format!("{prefix}.trans.lam.txt")),
        &reference_table("reference/compartments/mm9_10Mb.eigs_trans.vals.tsv.gz"),
        3,
    );
}

#[test]
fn fasta_gc_orients_like_the_same_track() {
    // a genome whose GC content per bin follows the phasing track's ranks: orienting by the
    // FASTA must give the vectors oriented by the track
    let dir = tempfile::tempdir().unwrap();
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    let track = reference_table("reference/compartments/dm6_100kb.phasing.tsv.gz");
    let values = column(&track, "track");
    let max = values.iter().cloned().fold(0.0f64, f64::max);
    let chroms_out = run_ok(&["dump", "-t", "chroms", &uri]);
    let mut fasta = String::new();
    for line in chroms_out.lines() {
        let f: Vec<&str> = line.split('\t').collect();
        let (name, length): (&str, usize) = (f[0], f[1].parse().unwrap());
        fasta.push_str(&format!(">{name} test\n"));
        let mut seq = Vec::with_capacity(length);
        for (row, v) in track.rows.iter().zip(&values) {
            if row[0] != name {
                continue;
            }
            let (start, end): (usize, usize) = (row[1].parse().unwrap(), row[2].parse().unwrap());
            // GC fraction rises with the track value, in steps of 1/1000
            let gc = (v / max * 1000.0).round() as usize;
            for k in start..end {
                seq.push(if k % 1000 < gc { b'G' } else { b'a' });
            }
        }
        for chunk in seq.chunks(60) {
            fasta.push_str(std::str::from_utf8(chunk).unwrap());
            fasta.push('\n');
        }
    }
    let fa = dir.path().join("genome.fa");
    std::fs::write(&fa, fasta).unwrap();
    let by_track = dir.path().join("t").to_string_lossy().into_owned();
    let by_fasta = dir.path().join("f").to_string_lossy().into_owned();
    dm6_phased(&by_track);
    run_ok(&[
        "compartments",
        &uri,
        "--fasta",
        fa.to_str().unwrap(),
        "-o",
        &by_fasta,
    ]);
    let a = read(&format!("{by_track}.cis.vecs.tsv"));
    let b = read(&format!("{by_fasta}.cis.vecs.tsv"));
    let e1a = column(&a, "E1");
    let e1b = column(&b, "E1");
    for (x, y) in e1a.iter().zip(&e1b) {
        assert!(x.is_nan() && y.is_nan() || x == y, "{x} {y}");
    }
    // the FASTA missing a chromosome of the map: one clear error
    let mut short = std::fs::read_to_string(&fa).unwrap();
    let cut = short.find(">chrX").unwrap();
    short.truncate(cut);
    std::fs::write(&fa, short).unwrap();
    let err = run_err(&[
        "compartments",
        &uri,
        "--fasta",
        fa.to_str().unwrap(),
        "-o",
        &by_fasta,
    ]);
    assert!(err.contains("genome.fa") && err.contains("chrX"), "{err}");
}

#[test]
fn bad_inputs_are_one_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("x").to_string_lossy().into_owned();
    let dm6 = data("cooler_test_file.mcool::/resolutions/100000");
    // a phasing track on other bins (dm6 100 kb track, mm9 10 Mb map)
    let phasing = phasing_track();
    let err = run_err(&[
        "compartments",
        &data("CN.mm9.10000kb.cool"),
        "--phasing-track",
        &phasing,
        "-o",
        &prefix,
    ]);
    assert!(err.contains("not a bin of the map"), "{err}");
    // a view outside its chromosome
    let view = dir.path().join("view.bed");
    std::fs::write(&view, "chr4\t0\t5000000\tbig\n").unwrap();
    let err = run_err(&[
        "compartments",
        &dm6,
        "--view",
        view.to_str().unwrap(),
        "-o",
        &prefix,
    ]);
    assert!(err.contains("chr4"), "{err}");
    // a map without weights
    let err = run_err(&[
        "compartments",
        &data("toy.symm.upper.2.mcool::/resolutions/2"),
        "-o",
        &prefix,
    ]);
    assert!(err.contains("weight"), "{err}");
    assert!(!std::path::Path::new(&format!("{prefix}.cis.vecs.tsv")).exists());
}

#[test]
fn a_view_computes_its_regions_only() {
    // cooltools eigs_cis over a view equals the chromosome-wide result where the region is the
    // whole chromosome; here the view is two whole chromosomes, named
    let dir = tempfile::tempdir().unwrap();
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    let view = dir.path().join("view.bed");
    std::fs::write(
        &view,
        "chr2L\t0\t23513712\tleft\nchr3R\t0\t32079331\tright\n",
    )
    .unwrap();
    let prefix = dir.path().join("v").to_string_lossy().into_owned();
    run_ok(&[
        "compartments",
        &uri,
        "--view",
        view.to_str().unwrap(),
        "-o",
        &prefix,
    ]);
    let lam = read(&format!("{prefix}.cis.lam.txt"));
    assert_eq!(lam.rows.len(), 2);
    assert_eq!(lam.rows[0][3], "left");
    let want = reference_table("reference/compartments/dm6_100kb.eigs_cis.vals.tsv.gz");
    let w = column(&want, "eigval1");
    let g = column(&lam, "eigval1");
    assert!((g[0] - w[0]).abs() <= 1e-9 * w[0].abs());
    assert!((g[1] - w[3]).abs() <= 1e-9 * w[3].abs());
    let vecs = read(&format!("{prefix}.cis.vecs.tsv"));
    assert!(vecs.rows.iter().all(|r| r[0] == "chr2L" || r[0] == "chr3R"));
}

#[test]
fn simulated_truth_and_score() {
    // the truth of an A/B block copolymer: each bin's majority type and fraction of A
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    run_ok(&[
        "simulate",
        "polymer",
        "-o",
        &path("ab.cool"),
        "--chains",
        "60,40",
        "--types",
        "A6B4",
        "--attraction",
        "0.3",
        "--monomers-per-bin",
        "4",
        "--replicas",
        "1",
        "--equilibration",
        "10",
        "--samples",
        "1",
        "--device",
        "cpu",
        "--truth-compartments",
        &path("truth.bed"),
    ]);
    let truth = std::fs::read_to_string(path("truth.bed")).unwrap();
    let rows: Vec<Vec<&str>> = truth.lines().map(|l| l.split('\t').collect()).collect();
    // chr1: 15 bins of 4 beads over the period AAAAAABBBB: bin 0 = AAAA, bin 1 = AABB (a tie:
    // A, met first), bin 2 = BBAA ...; chr2 restarts the pattern
    assert_eq!(rows.len(), 15 + 10);
    let types: String = rows.iter().map(|r| r[3]).collect();
    assert_eq!(&types[..5], "AAAAB");
    assert_eq!(rows[1][4], "0.5");
    assert_eq!(rows[15][0], "chr2");
    assert_eq!(rows[15][1], "0");
    // a vector right on 3 bins of 4, scored
    let eigs = path("eigs.tsv");
    let mut text = String::from("chrom\tstart\tend\tweight\tE1\n");
    let signs = [1.0, -0.5, 2.0, -1.0];
    for (k, row) in rows.iter().take(4).enumerate() {
        text.push_str(&format!(
            "{}\t{}\t{}\t1\t{}\n",
            row[0], row[1], row[2], signs[k]
        ));
    }
    std::fs::write(&eigs, text).unwrap();
    let score = parse_table(&run_ok(&[
        "score",
        "compartments",
        "--truth",
        &path("truth.bed"),
        &eigs,
    ]));
    assert_eq!(
        score.header,
        [
            "chrom",
            "n_bins",
            "sign_accuracy",
            "sign_accuracy_up_to_sign",
            "pearson"
        ]
    );
    // truth of bins 0-3: A A A A -> signs +, -, +, - : half right
    let all = score.rows.last().unwrap();
    assert_eq!(all[0], "all");
    assert_eq!(all[1], "4");
    let expected = &rows[..4]
        .iter()
        .zip(signs)
        .filter(|(r, s)| (r[3] == "A") == (*s > 0.0))
        .count();
    assert_eq!(number(&all[2]), *expected as f64 / 4.0);
    // a truth on other bins: one clear error
    std::fs::write(path("other.bed"), "chrX\t0\t10\tA\n").unwrap();
    let err = run_err(&[
        "score",
        "compartments",
        "--truth",
        &path("other.bed"),
        &eigs,
    ]);
    assert!(err.contains("other.bed"), "{err}");
    std::fs::write(path("bad.bed"), "chr1\t0\t4000\tC\n").unwrap();
    let err = run_err(&["score", "compartments", "--truth", &path("bad.bed"), &eigs]);
    assert!(err.contains("A, B"), "{err}");
}

#[test]
fn saddle_picture_shows_enriched_corners() {
    let dir = tempfile::tempdir().unwrap();
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    let prefix = dir.path().join("e").to_string_lossy().into_owned();
    dm6_phased(&prefix);
    let saddle = dir.path().join("s").to_string_lossy().into_owned();
    let track = format!("{prefix}.cis.vecs.tsv:E1");
    run_ok(&[
        "saddle", &uri, "--track", &track, "--n-bins", "10", "-o", &saddle,
    ]);
    let table = format!("{saddle}.saddle.tsv");
    let svg = super::plot::plot_svg(&["plot", "saddle", &table]);
    // the heatmap is the widest image (the colour bar is the other)
    let (x, y, w, h) = super::plot::svg_rects(&svg, "image", "", "")
        .into_iter()
        .max_by(|a, b| a.2.total_cmp(&b.2))
        .unwrap();
    assert!((w - h).abs() < 1e-9, "square");
    let png = super::plot::plot_png(&["plot", "saddle", &table]);
    let cell = |r: usize, c: usize| {
        let px = x + (c as f64 + 0.5) * w / 10.0;
        let py = y + (r as f64 + 0.5) * h / 10.0;
        png.at(px as usize, py as usize)
    };
    // B-B and A-A corners enriched (red), A-B depleted (blue)
    for (r, c, red) in [(0, 0, true), (9, 9, true), (0, 9, false), (9, 0, false)] {
        let (pr, _, pb) = cell(r, c);
        assert_eq!(pr > pb, red, "cell ({r}, {c}): {:?}", cell(r, c));
    }
    let err = run_err(&[
        "plot",
        "saddle",
        &format!("{prefix}.cis.lam.txt"),
        "-o",
        "x.png",
    ]);
    assert!(err.contains("lam.txt"), "{err}");
}

#[test]
fn sort_metrics_order_and_orient_as_cooltools() {
    // cooltools eigs_cis(sort_metric=...) with the phasing track: each region's eigenvalue order
    // and, per vector, the sum of its values (its sign)
    let dir = tempfile::tempdir().unwrap();
    let want = reference_table("reference/compartments/dm6_100kb.eigs_cis_sorted.tsv.gz");
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    for metric in ["spearmanr", "pearsonr", "var_explained", "MAD_explained"] {
        let prefix = dir.path().join(metric).to_string_lossy().into_owned();
        let track = phasing_track();
        run_ok(&[
            "compartments",
            &uri,
            "--phasing-track",
            &track,
            "--sort-metric",
            metric,
            "-o",
            &prefix,
        ]);
        let lam = read(&format!("{prefix}.cis.lam.txt"));
        let vecs = read(&format!("{prefix}.cis.vecs.tsv"));
        for row in want.rows.iter().filter(|r| r[0] == metric) {
            let chrom = &row[1];
            let got = lam.rows.iter().find(|r| &r[0] == chrom).unwrap();
            for e in 1..=3 {
                let (g, w) = (number(&got[3 + e]), number(&row[1 + e]));
                assert!(
                    g.is_nan() && w.is_nan() || (g - w).abs() <= 1e-9 * w.abs(),
                    "{metric} {chrom} eigval{e}: {g} vs {w}"
                );
                let c = vecs
                    .header
                    .iter()
                    .position(|h| h == &format!("E{e}"))
                    .unwrap();
                let sum: f64 = vecs
                    .rows
                    .iter()
                    .filter(|r| &r[0] == chrom)
                    .map(|r| number(&r[c]))
                    .filter(|v| v.is_finite())
                    .sum();
                let w = number(&row[4 + e]);
                assert!(
                    (sum - w).abs() <= 1e-7 * w.abs().max(1.0),
                    "{metric} {chrom} E{e}: sum {sum} vs {w}"
                );
            }
        }
    }
    let err = run_err(&["compartments", &uri, "--sort-metric", "pearsonr", "-o", "x"]);
    assert!(err.contains("--phasing-track"), "{err}");
}
