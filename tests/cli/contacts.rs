//! `contactmap score contacts` and `contactmap contacts` on the protein fixtures of
//! `data/protein/` (reference numbers from `data/protein/README.md`).

use crate::{data, parse_table, run_err, run_ok, write};

fn protein(name: &str) -> String {
    data(&format!("protein/{name}"))
}

/// The text of a gzip-compressed fixture of `data/protein/`.
fn protein_text(name: &str) -> String {
    use std::io::Read as _;
    let file = std::fs::File::open(protein(name)).unwrap();
    let mut text = String::new();
    flate2::read::MultiGzDecoder::new(file)
        .read_to_string(&mut text)
        .unwrap();
    text
}

/// `score contacts --tsv` with `args`: rows as (prediction, range, list, tp, n_scored,
/// precision).
fn scores(args: &[&str]) -> Vec<(String, String, String, usize, usize, f64)> {
    scores_in(&run_ok(
        &[&["score", "contacts", "--tsv"][..], args].concat(),
    ))
}

/// The rows of `scores` from a `score contacts --tsv` output.
fn scores_in(text: &str) -> Vec<(String, String, String, usize, usize, f64)> {
    let table = parse_table(text);
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
        &protein("1aapA/1aapA.pdb.gz"),
        &protein("1aapA/1aapA.rr.gz"),
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
        &protein("1aapA/1aapA.pdb.gz"),
        &protein("1aapA/1aapA.rr.gz"),
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
        &protein("toxd/toxd.pdb.gz"),
        &protein("toxd/toxd.mat.gz"),
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
    let apc = protein("1atzA/1atzA.apc.mat.gz");
    let noapc = protein("1atzA/1atzA.noapc.mat.gz");
    let rows = scores(&[
        "--structure",
        &protein("1atzA/1atzA.pdb.gz"),
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
        &protein("1guuA/1guuA.pdb.gz"),
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
        &protein("1guuA/1guuA.pdb.gz"),
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
    // coneva.pl prints percentages with 2 decimals; L = observed residues, k rounded half up.
    let coneva = |inputs: &[&str]| -> Vec<f64> {
        let conventions = [
            "--ranges",
            "long",
            "--length",
            "observed",
            "--rounding",
            "half-up",
        ];
        let rows = scores(&[inputs, &conventions[..]].concat());
        precisions(&rows)
            .iter()
            .map(|p| (p * 10000.0).round() / 100.0)
            .collect()
    };
    let (pdb, rr) = (protein("1aapA/1aapA.pdb.gz"), protein("1aapA/1aapA.rr.gz"));
    assert_close(
        &coneva(&["--structure", &pdb, &rr]),
        &[83.33, 81.82, 46.43, 30.36],
        1e-9,
    );
    let (pdb, mat, fasta) = (
        protein("toxd/toxd.pdb.gz"),
        protein("toxd/toxd.mat.gz"),
        protein("toxd/toxd.fasta"),
    );
    assert_close(
        &coneva(&["--structure", &pdb, &mat, "--fasta", &fasta]),
        &[100.0, 83.33, 58.62, 37.93],
        1e-9,
    );

    // ConKit documentation: toxd, d <= 8, separation >= 5, top 29, 59, 88.
    let rows = scores(&[
        "--structure",
        &protein("toxd/toxd.pdb.gz"),
        &protein("toxd/toxd.mat.gz"),
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
        &protein("1aapA/1aapA.pdb.gz"),
        &protein("1aapA/1aapA.rr.gz"),
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
    let pdb = run_ok(&["contacts", &protein("1a8o/1A8O.pdb.gz")]);
    let cif = run_ok(&["contacts", &protein("1a8o/1A8O.cif.gz")]);
    assert_eq!(pdb, cif);
    // Sequence line, then 77 contacts with separation >= 6 (data/protein/README.md).
    let lines: Vec<&str> = pdb.lines().collect();
    assert!(
        lines[0]
            .ends_with("MDIRQGPKEPFRDYVDRFYKTLRAEQASQEVKNWMTETLLVQNANPDCKTILKALGPGATLEEMMTACQG")
    );
    assert_eq!(lines.len(), 1 + 77);
    assert!(lines[1..].iter().all(|line| line.ends_with(" 0 8 1")));
    let pdb_matrix = run_ok(&["contacts", "--matrix", &protein("1a8o/1A8O.pdb.gz")]);
    let cif_matrix = run_ok(&["contacts", "--matrix", &protein("1a8o/1A8O.cif.gz")]);
    assert_eq!(pdb_matrix, cif_matrix);
    assert_eq!(pdb_matrix.lines().count(), 71);
}

#[test]
fn own_contacts_read_back_score_precision_one() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("toxd.rr");
    run_ok(&[
        "contacts",
        &protein("toxd/toxd.pdb.gz"),
        "-o",
        out.to_str().unwrap(),
    ]);
    let rows = scores(&[
        "--structure",
        &protein("toxd/toxd.pdb.gz"),
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
    let structure = protein("toxd/toxd.pdb.gz");

    let line = run_err(&["contacts", &structure, "--chain", "Z"]);
    assert!(line.contains("no protein chain 'Z'"), "{line}");
    let line = run_err(&[
        "score",
        "contacts",
        "--structure",
        &structure,
        "--chain",
        "Z",
        &protein("toxd/toxd.mat.gz"),
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
        &protein("toxd/toxd.mat.gz"),
        "--fasta",
        &protein("1aapA/1aapA.fasta"),
    ]);
    assert!(line.contains("covers 59 residues"), "{line}");
    let rr = write(dir.path(), "short.rr", "ACDEF\n1 9 0 8 0.5\n");
    let line = run_err(&["score", "contacts", "--structure", &structure, &rr]);
    assert!(line.contains("short.rr"), "{line}");

    for (option, value) in [("--top", "L/0"), ("--ranges", "9-3"), ("--length", "x")] {
        let line = run_err(&[
            "score",
            "contacts",
            "--structure",
            &structure,
            &protein("toxd/toxd.mat.gz"),
            option,
            value,
        ]);
        assert!(line.contains(value), "{line}");
    }
}

/// 1A8O is numbered 151-220; its FASTA from 1. The true contacts written in sequence numbering
/// score precision 1 against the .pdb and the .cif, and the offset is reported.
#[test]
fn register_offset_numbering() {
    let dir = tempfile::tempdir().unwrap();
    let fasta = protein("1a8o/1A8O.fasta");
    let rr = dir.path().join("1a8o.rr");
    let output = crate::run(&[
        "contacts",
        &protein("1a8o/1A8O.cif.gz"),
        "--fasta",
        &fasta,
        "-o",
        rr.to_str().unwrap(),
    ]);
    assert!(output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("positions + 150"), "{stderr}");
    let text = std::fs::read_to_string(&rr).unwrap();
    assert!(text.starts_with("MDIRQGPKEP"));
    assert!(text.lines().nth(1).unwrap().starts_with("1 18 "), "{text}");
    for structure in ["1a8o/1A8O.pdb.gz", "1a8o/1A8O.cif.gz"] {
        let rows = scores(&[
            "--structure",
            &protein(structure),
            rr.to_str().unwrap(),
            "--top",
            "NC",
        ]);
        let counts: Vec<(usize, usize)> = rows.iter().map(|r| (r.3, r.4)).collect();
        assert_eq!(
            counts,
            [(16, 16), (26, 26), (35, 35), (77, 77)],
            "{structure}"
        );
    }
}

/// A structure that covers part of a longer target, with four unresolved residues and its
/// residues renumbered 1..66 (so the numbers hide the gap): the register comes from the
/// alignment, and the true contacts of the full chain, written in the target's numbering,
/// score precision 1 on the 66 residues that remain.
#[test]
fn register_alignment_of_a_gapped_renumbered_domain() {
    let dir = tempfile::tempdir().unwrap();
    let core = "MDIRQGPKEPFRDYVDRFYKTLRAEQASQEVKNWMTETLLVQNANPDCKTILKALGPGATLEEMMTACQG";
    let fasta = write(
        dir.path(),
        "long.fasta",
        &format!(">tagged target\nMGSSHHHHHHSSG{core}LEHHHHHH\n"),
    );
    // The truth in the target's numbering (residue 151 is position 14).
    let truth = dir.path().join("truth.rr");
    let output = crate::run(&[
        "contacts",
        &protein("1a8o/1A8O.pdb.gz"),
        "--fasta",
        &fasta,
        "--min-sep",
        "1",
        "-o",
        truth.to_str().unwrap(),
    ]);
    assert!(output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("positions + 137"));
    // The gapped structure: residues 170-173 removed, the rest renumbered from 1.
    let pdb = protein_text("1a8o/1A8O.pdb.gz");
    let mut renumbered = String::new();
    let (mut last, mut index) = (String::new(), 0);
    for line in pdb.lines() {
        let is_atom = line.starts_with("ATOM  ") || line.starts_with("HETATM");
        if !is_atom {
            renumbered.push_str(line);
            renumbered.push('\n');
            continue;
        }
        let number: i32 = line[22..26].trim().parse().unwrap();
        if (170..=173).contains(&number) {
            continue;
        }
        if line[22..27] != last {
            last = line[22..27].to_string();
            index += 1;
        }
        renumbered.push_str(&format!("{}{index:>4}{}\n", &line[..22], &line[26..]));
    }
    let gapped = write(dir.path(), "gapped.pdb", &renumbered);
    let output = crate::run(&[
        "score",
        "contacts",
        "--tsv",
        "--structure",
        &gapped,
        truth.to_str().unwrap(),
        "--fasta",
        &fasta,
        "--ranges",
        "1+",
        "--top",
        "NC",
    ]);
    assert!(output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("aligned the structure's chain"), "{stderr}");
    assert!(stderr.contains("1-19->14-32, 20-"), "{stderr}");
    let rows = scores_in(&String::from_utf8_lossy(&output.stdout));
    // Every predicted pair between observed residues is a true contact, and all are found.
    let (tp, n_scored) = (rows[0].3, rows[0].4);
    assert_eq!(tp, n_scored);
    let removed = |i: usize| (14 + 19..14 + 23).contains(&i);
    let expected = std::fs::read_to_string(&truth)
        .unwrap()
        .lines()
        .skip(1)
        .filter(|line| {
            let mut fields = line.split_whitespace().map(|f| f.parse::<usize>().unwrap());
            let (i, j) = (fields.next().unwrap(), fields.next().unwrap());
            !removed(i) && !removed(j)
        })
        .count();
    assert_eq!(tp, expected);
    // Taking the numbers as they are scores the same file far worse.
    let rows = scores(&[
        "--structure",
        &gapped,
        truth.to_str().unwrap(),
        "--fasta",
        &fasta,
        "--ranges",
        "long",
        "--top",
        "NC",
        "--register",
        "numbering",
    ]);
    assert!(rows[0].5 < 0.5, "{rows:?}");
}

/// toxd.mat rewritten in every list format (EVfold, GREMLIN, CASP RR mode 2, plmDCA's
/// `i,j,score`, PSICOV's `i j 0 8 score`) scores as the matrix does: method P's 5/5, 9/11,
/// 17/29, 22/59 (data/protein/README.md). The EVfold and GREMLIN files name every residue, so
/// they need no FASTA.
#[test]
fn every_list_format_reproduces_the_matrix() {
    let dir = tempfile::tempdir().unwrap();
    let sequence: String = std::fs::read_to_string(protein("toxd/toxd.fasta"))
        .unwrap()
        .lines()
        .filter(|line| !line.starts_with('>'))
        .collect();
    let letters: Vec<char> = sequence.chars().collect();
    let matrix: Vec<Vec<String>> = protein_text("toxd/toxd.mat.gz")
        .lines()
        .filter(|line| !line.trim().is_empty() && !line.starts_with('#'))
        .map(|line| line.split_whitespace().map(String::from).collect())
        .collect();
    let n = matrix.len();
    let (mut evfold, mut gremlin, mut mode2, mut plmdca, mut psicov) = (
        String::new(),
        String::from("i\tj\ti_id\tj_id\tr_sco\ts_sco\tprob\n"),
        format!("PFRMAT RR\nRMODE 2\nMODEL 1\n{sequence}\n"),
        String::new(),
        String::new(),
    );
    for i in 0..n {
        for j in i + 1..n {
            let (a, b, score) = (i + 1, j + 1, &matrix[i][j]);
            let (x, y) = (letters[i], letters[j]);
            evfold.push_str(&format!("{a} {x} {b} {y} 0 {score}\n"));
            gremlin.push_str(&format!("{a}\t{b}\t{a}_{x}\t{b}_{y}\t{score}\t1.0\t0.5\n"));
            mode2.push_str(&format!(
                "{a} {b} {score} 0.1 0.1 0.1 0.1 0.1 0.1 0.1 0.1 0.1 0.1\n"
            ));
            plmdca.push_str(&format!("{a},{b},{score}\n"));
            psicov.push_str(&format!("{a} {b} 0 8 {score}\n"));
        }
    }
    mode2.push_str("END\n");
    let files = [
        write(dir.path(), "toxd.evfold", &evfold),
        write(dir.path(), "toxd.gremlin", &gremlin),
        write(dir.path(), "toxd.mode2.rr", &mode2),
        write(dir.path(), "toxd.plmdca", &plmdca),
        write(dir.path(), "toxd.psicov", &psicov),
    ];
    let expected = [(5, 5), (9, 11), (17, 29), (22, 59)];
    for file in &files {
        let mut args = vec!["--structure", &*protein("toxd/toxd.pdb.gz")]
            .into_iter()
            .map(String::from)
            .collect::<Vec<_>>();
        args.extend([file.clone(), "--ranges".into(), "long".into()]);
        if file.ends_with("plmdca") || file.ends_with("psicov") {
            args.extend(["--fasta".into(), protein("toxd/toxd.fasta")]);
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let rows = scores(&args);
        let counts: Vec<(usize, usize)> = rows.iter().map(|r| (r.3, r.4)).collect();
        assert_eq!(counts, expected, "{file}");
    }
    // Against each other, the same ranking overlaps completely.
    let text = run_ok(&[
        "score", "overlap", &files[0], &files[1], "--tsv", "--ranges", "long",
    ]);
    let table = parse_table(&text);
    let jaccard = table.header.iter().position(|h| h == "jaccard").unwrap();
    assert!(table.rows.iter().all(|row| row[jaccard] == "1"), "{text}");
}

#[test]
fn overlap_of_two_predictions() {
    // APC and non-APC CCMpred matrices of 1atzA; the naive count is done here from the two
    // ranked lists read independently.
    let read = |name: &str| -> Vec<(usize, usize)> {
        let rows: Vec<Vec<f64>> = protein_text(name)
            .lines()
            .filter(|line| !line.starts_with('#'))
            .map(|line| {
                line.split_whitespace()
                    .map(|v| v.parse().unwrap())
                    .collect()
            })
            .collect();
        let mut pairs: Vec<(usize, usize, f64)> = Vec::new();
        for (i, row) in rows.iter().enumerate() {
            for (j, &score) in row.iter().enumerate().skip(i + 24) {
                pairs.push((i + 1, j + 1, score));
            }
        }
        pairs.sort_by(|a, b| b.2.partial_cmp(&a.2).unwrap());
        pairs.into_iter().map(|(i, j, _)| (i, j)).collect()
    };
    let (apc, noapc) = (
        read("1atzA/1atzA.apc.mat.gz"),
        read("1atzA/1atzA.noapc.mat.gz"),
    );
    let text = run_ok(&[
        "score",
        "overlap",
        &protein("1atzA/1atzA.apc.mat.gz"),
        &protein("1atzA/1atzA.noapc.mat.gz"),
        "--ranges",
        "long",
        "--top",
        "L/5,L,100",
        "--tsv",
    ]);
    let table = parse_table(&text);
    let column = |name: &str| table.header.iter().position(|h| h == name).unwrap();
    for (row, k) in table.rows.iter().zip([15usize, 75, 100]) {
        assert_eq!(row[column("k")], k.to_string());
        let shared = apc[..k].iter().filter(|p| noapc[..k].contains(p)).count();
        assert_eq!(row[column("shared")], shared.to_string());
        let jaccard: f64 = row[column("jaccard")].parse().unwrap();
        assert!((jaccard - shared as f64 / (2 * k - shared) as f64).abs() < 1e-12);
    }
    let line = run_err(&[
        "score",
        "overlap",
        &protein("toxd/toxd.mat.gz"),
        &protein("1atzA/1atzA.apc.mat.gz"),
    ]);
    assert!(
        line.contains("not predictions for the same target"),
        "{line}"
    ); // A matrix (59 residues) against an RR file carrying a 56-residue sequence.
    let line = run_err(&[
        "score",
        "overlap",
        &protein("toxd/toxd.mat.gz"),
        &protein("1aapA/1aapA.rr.gz"),
    ]);
    assert!(line.contains("cover 59 and 56 residues"), "{line}");
}

#[test]
fn non_finite_coordinates_and_huge_npy_shapes_are_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    // toxd.pdb with the CB of PRO 2 at x = nan (line 347): an error, not a missing contact.
    let pdb = protein_text("toxd/toxd.pdb.gz");
    let original = "ATOM      9  CB  PRO A   2      12.617";
    assert!(pdb.contains(original));
    let nan = write(
        dir.path(),
        "nan.pdb",
        &pdb.replace(original, "ATOM      9  CB  PRO A   2         nan"),
    );
    let line = run_err(&["contacts", &nan]);
    assert_eq!(
        line,
        format!(
            "contactmap: error: {nan}:347: x (columns 31-38) of atom CB of PRO 2 chain 'A' is \
             'nan': coordinates must be finite numbers"
        )
    );
    // 1guuA.predicted.npy with a shape whose size overflows (fuzz finding F-NPY-1).
    let mut npy = std::fs::read(protein("1guuA/1guuA.predicted.npy")).unwrap();
    let header = String::from_utf8(npy[10..128].to_vec()).unwrap();
    let max = u64::MAX;
    let huge = format!("({max}, {max}, 1)");
    let mutated = header.replace("(50, 50, 1)", &huge);
    let mutated = mutated.replacen(&" ".repeat(huge.len() - "(50, 50, 1)".len()), "", 1);
    assert_eq!(mutated.len(), header.len());
    npy.splice(10..128, mutated.bytes());
    let path = dir.path().join("huge.npy");
    std::fs::write(&path, &npy).unwrap();
    let path = path.to_string_lossy().into_owned();
    let line = run_err(&[
        "score",
        "contacts",
        "--structure",
        &protein("1guuA/1guuA.pdb.gz"),
        &path,
    ]);
    assert!(
        line.starts_with(&format!("contactmap: error: {path}: .npy shape ["))
            && line.contains("is too large"),
        "{line}"
    );
}

/// Issue 26: without --fasta, a chain numbered 151-220 (1A8O) gives an RR whose sequence line is
/// its 70 residues (not 150 `X` first) and whose residues are numbered from 1 there, the same
/// file as with its FASTA; a note says so; the RR scores precision 1 against the structure.
#[test]
fn a_chain_numbered_from_151_is_written_from_1() {
    let out = crate::run(&["contacts", &protein("1a8o/1A8O.cif.gz")]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        text.lines().next().unwrap(),
        "MDIRQGPKEPFRDYVDRFYKTLRAEQASQEVKNWMTETLLVQNANPDCKTILKALGPGATLEEMMTACQG"
    );
    assert!(text.lines().nth(1).unwrap().starts_with("1 18 "), "{text}");
    assert!(stderr.contains("numbered from 151"), "{stderr}");
    let with_fasta = run_ok(&[
        "contacts",
        &protein("1a8o/1A8O.cif.gz"),
        "--fasta",
        &protein("1a8o/1A8O.fasta"),
    ]);
    assert_eq!(text, with_fasta);
    let dir = tempfile::tempdir().unwrap();
    let rr = dir.path().join("1a8o.rr");
    std::fs::write(&rr, &text).unwrap();
    let rows = scores(&[
        "--structure",
        &protein("1a8o/1A8O.pdb.gz"),
        rr.to_str().unwrap(),
        "--top",
        "NC",
    ]);
    assert!(rows.iter().all(|r| r.3 == r.4), "{rows:?}");
}
