//! `contactmap score contacts` and `contactmap contacts` on the protein fixtures of
//! `data/protein/` (reference numbers from `data/protein/README.md`).

use std::path::Path;

use crate::{data, parse_table, run_err, run_ok};

fn protein(name: &str) -> String {
    data(&format!("protein/{name}"))
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_string_lossy().into_owned()
}

/// `score contacts --tsv` with `args`: rows as (prediction, range, list, tp, n_scored,
/// precision).
fn scores(args: &[&str]) -> Vec<(String, String, String, usize, usize, f64)> {
    let text = run_ok(&[&["score", "contacts", "--tsv"][..], args].concat());
    let table = parse_table(&text);
    let column = |name: &str| {
        table
            .header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"))
    };
    let (prediction, range, list, tp, n_scored, precision) = (
        column("prediction"),
        column("range"),
        column("list"),
        column("tp"),
        column("n_scored"),
        column("precision"),
    );
    table
        .rows
        .iter()
        .map(|row| {
            (
                row[prediction].clone(),
                row[range].clone(),
                row[list].clone(),
                row[tp].parse().unwrap(),
                row[n_scored].parse().unwrap(),
                row[precision].parse().unwrap(),
            )
        })
        .collect()
}

fn precisions(rows: &[(String, String, String, usize, usize, f64)]) -> Vec<f64> {
    rows.iter().map(|row| row.5).collect()
}

fn assert_close(found: &[f64], expected: &[f64], tolerance: f64) {
    assert_eq!(found.len(), expected.len(), "{found:?} vs {expected:?}");
    for (f, e) in found.iter().zip(expected) {
        assert!((f - e).abs() < tolerance, "{found:?} vs {expected:?}");
    }
}

#[test]
fn tsv_header() {
    let text = run_ok(&[
        "score",
        "contacts",
        "--tsv",
        "--structure",
        &protein("1aapA/1aapA.pdb"),
        &protein("1aapA/1aapA.rr"),
    ]);
    let table = parse_table(&text);
    assert_eq!(
        table.header[..12],
        [
            "prediction",
            "range",
            "min_sep",
            "max_sep",
            "list",
            "k",
            "n_scored",
            "tp",
            "precision",
            "recall",
            "f1",
            "mcc"
        ]
    );
    // Default: short, medium, long, all x L/10, L/5, L/2, L.
    assert_eq!(table.rows.len(), 16);
}

#[test]
fn method_p_long_range_precisions() {
    // 1aapA.rr: L from the RR sequence line.
    let rows = scores(&[
        "--structure",
        &protein("1aapA/1aapA.pdb"),
        &protein("1aapA/1aapA.rr"),
        "--ranges",
        "long",
    ]);
    let counts: Vec<(usize, usize)> = rows.iter().map(|r| (r.3, r.4)).collect();
    assert_eq!(counts, [(4, 5), (9, 11), (13, 28), (17, 56)]);
    assert_close(
        &precisions(&rows),
        &[0.8, 0.818182, 0.464286, 0.303571],
        5e-7,
    );

    // toxd.mat (CCMpred matrix) with --fasta.
    let rows = scores(&[
        "--structure",
        &protein("toxd/toxd.pdb"),
        &protein("toxd/toxd.mat"),
        "--fasta",
        &protein("toxd/toxd.fasta"),
        "--ranges",
        "long",
    ]);
    assert_close(
        &precisions(&rows),
        &[1.0, 0.818182, 0.586207, 0.372881],
        5e-7,
    );
}

#[test]
fn many_predictions_in_one_call() {
    let apc = protein("1atzA/1atzA.apc.mat");
    let noapc = protein("1atzA/1atzA.noapc.mat");
    let rows = scores(&[
        "--structure",
        &protein("1atzA/1atzA.pdb"),
        &apc,
        &noapc,
        "--fasta",
        &protein("1atzA/1atzA.fasta"),
        "--min-sep",
        "24",
    ]);
    let of = |path: &str| -> Vec<(usize, usize)> {
        rows.iter()
            .filter(|r| r.0 == path)
            .map(|r| (r.3, r.4))
            .collect()
    };
    assert_eq!(of(&apc), [(6, 7), (12, 15), (21, 37), (30, 75)]);
    assert_eq!(of(&noapc), [(4, 7), (5, 15), (9, 37), (11, 75)]);
}

#[test]
fn npz_and_npy_predictions() {
    let rows = scores(&[
        "--structure",
        &protein("1guuA/1guuA.pdb"),
        &protein("1guuA/1guuA.npz"),
        "--fasta",
        &protein("1guuA/1guuA.fasta"),
        "--ranges",
        "long",
    ]);
    let counts: Vec<(usize, usize)> = rows.iter().map(|r| (r.3, r.4)).collect();
    assert_eq!(counts, [(5, 5), (10, 10), (13, 25), (13, 50)]);

    // DISTEVAL conventions: banker's rounding, separations >= 12 and >= 24, Top-L/5 and NC.
    let rows = scores(&[
        "--structure",
        &protein("1guuA/1guuA.pdb"),
        &protein("1guuA/1guuA.predicted.npy"),
        "--fasta",
        &protein("1guuA/1guuA.fasta"),
        "--rounding",
        "banker",
        "--ranges",
        "12+,24+",
        "--top",
        "L/5,NC",
    ]);
    assert_close(&precisions(&rows), &[0.9, 0.6, 0.5, 0.384615], 5e-6);
}

#[test]
fn coneva_and_conkit_conventions() {
    let rows = scores(&[
        "--structure",
        &protein("1aapA/1aapA.pdb"),
        &protein("1aapA/1aapA.rr"),
        "--ranges",
        "long",
        "--length",
        "observed",
        "--rounding",
        "half-up",
    ]);
    let percentages: Vec<f64> = precisions(&rows)
        .iter()
        .map(|p| (p * 10000.0).round() / 100.0)
        .collect();
    assert_close(&percentages, &[83.33, 81.82, 46.43, 30.36], 1e-9);
    let rows = scores(&[
        "--structure",
        &protein("toxd/toxd.pdb"),
        &protein("toxd/toxd.mat"),
        "--fasta",
        &protein("toxd/toxd.fasta"),
        "--ranges",
        "long",
        "--length",
        "observed",
        "--rounding",
        "half-up",
    ]);
    let percentages: Vec<f64> = precisions(&rows)
        .iter()
        .map(|p| (p * 10000.0).round() / 100.0)
        .collect();
    assert_close(&percentages, &[100.0, 83.33, 58.62, 37.93], 1e-9);

    // ConKit documentation: toxd, d <= 8, separation >= 5, top 29, 59, 88.
    let rows = scores(&[
        "--structure",
        &protein("toxd/toxd.pdb"),
        &protein("toxd/toxd.mat"),
        "--fasta",
        &protein("toxd/toxd.fasta"),
        "--le",
        "--min-sep",
        "5",
        "--top",
        "0.5L,L,1.5L",
    ]);
    let counts: Vec<(usize, usize)> = rows.iter().map(|r| (r.3, r.4)).collect();
    assert_eq!(counts, [(24, 29), (35, 59), (38, 88)]);
}

#[test]
fn table_and_json_outputs() {
    let args = [
        "score",
        "contacts",
        "--structure",
        &protein("1aapA/1aapA.pdb"),
        &protein("1aapA/1aapA.rr"),
        "--ranges",
        "long",
    ];
    let table = run_ok(&args);
    assert!(table.contains("precision"), "{table}");
    assert!(table.contains("0.8182"), "{table}");
    let json = run_ok(&[&args[..], &["--json"]].concat());
    let value: serde_json::Value = serde_json::from_str(&json).unwrap();
    let lists = &value[0]["ranges"][0]["lists"];
    assert_eq!(lists[1]["list"], "L/5");
    assert_eq!(lists[1]["tp"], 9);
    assert_eq!(value[0]["length"], 56);
    assert_eq!(value[0]["length_source"], "sequence");
}

#[test]
fn true_contacts_pdb_and_cif_identical() {
    let pdb = run_ok(&["contacts", &protein("1a8o/1A8O.pdb")]);
    let cif = run_ok(&["contacts", &protein("1a8o/1A8O.cif")]);
    assert_eq!(pdb, cif);
    // Sequence line, then 77 contacts with separation >= 6 (data/protein/README.md).
    let lines: Vec<&str> = pdb.lines().collect();
    assert!(lines[0]
        .ends_with("MDIRQGPKEPFRDYVDRFYKTLRAEQASQEVKNWMTETLLVQNANPDCKTILKALGPGATLEEMMTACQG"));
    assert_eq!(lines.len(), 1 + 77);
    assert!(lines[1..].iter().all(|line| line.ends_with(" 0 8 1")));
    let pdb_matrix = run_ok(&["contacts", "--matrix", &protein("1a8o/1A8O.pdb")]);
    let cif_matrix = run_ok(&["contacts", "--matrix", &protein("1a8o/1A8O.cif")]);
    assert_eq!(pdb_matrix, cif_matrix);
    assert_eq!(pdb_matrix.lines().count(), 71);
}

#[test]
fn own_contacts_read_back_score_precision_one() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("toxd.rr");
    run_ok(&[
        "contacts",
        &protein("toxd/toxd.pdb"),
        "-o",
        out.to_str().unwrap(),
    ]);
    let rows = scores(&[
        "--structure",
        &protein("toxd/toxd.pdb"),
        out.to_str().unwrap(),
        "--top",
        "NC",
    ]);
    let counts: Vec<(usize, usize)> = rows.iter().map(|r| (r.3, r.4)).collect();
    assert_eq!(counts, [(15, 15), (43, 43), (57, 57), (115, 115)]);
}

#[test]
fn bad_input_is_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    let structure = protein("toxd/toxd.pdb");

    let line = run_err(&["contacts", &structure, "--chain", "Z"]);
    assert!(line.contains("no protein chain 'Z'"), "{line}");
    let line = run_err(&[
        "score",
        "contacts",
        "--structure",
        &structure,
        "--chain",
        "Z",
        &protein("toxd/toxd.mat"),
    ]);
    assert!(line.contains("no protein chain 'Z'"), "{line}");

    let matrix = write(dir.path(), "bad.mat", "0 1 2\n1 0 3\n");
    let line = run_err(&[
        "score",
        "contacts",
        "--structure",
        &structure,
        &matrix,
        "--format",
        "matrix",
    ]);
    assert!(
        line.contains("bad.mat") && line.contains("not square"),
        "{line}"
    );

    // toxd.mat has 59 residues; 1aapA's sequence has 56.
    let line = run_err(&[
        "score",
        "contacts",
        "--structure",
        &structure,
        &protein("toxd/toxd.mat"),
        "--fasta",
        &protein("1aapA/1aapA.fasta"),
    ]);
    assert!(line.contains("beyond the sequence"), "{line}");
    let rr = write(dir.path(), "short.rr", "ACDEF\n1 9 0 8 0.5\n");
    let line = run_err(&["score", "contacts", "--structure", &structure, &rr]);
    assert!(line.contains("short.rr"), "{line}");

    for (option, value) in [("--top", "L/0"), ("--ranges", "9-3"), ("--length", "x")] {
        let line = run_err(&[
            "score",
            "contacts",
            "--structure",
            &structure,
            &protein("toxd/toxd.mat"),
            option,
            value,
        ]);
        assert!(line.contains(value), "{line}");
    }
}
