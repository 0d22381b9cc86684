//! `contactmap contacts --trajectory` against MDTraj's `compute_contacts` (data/reference/mdtraj,
//! scripts/md_contacts_reference.py) and bad trajectories.

use super::*;
use std::collections::HashMap;

const SCHEMES: [(&str, &str); 6] = [
    ("ca", "8"),
    ("cb", "8"),
    ("closest", "4.5"),
    ("closest-heavy", "4.5"),
    ("sidechain", "4.5"),
    ("sidechain-heavy", "4.5"),
];

/// MDTraj's pairs count, frames and the frames in contact of the pairs in contact.
fn reference(name: &str) -> (usize, usize, HashMap<(usize, usize), u32>) {
    use std::io::Read as _;
    let file = std::fs::File::open(data(&format!("reference/mdtraj/{name}.tsv.gz"))).unwrap();
    let mut text = String::new();
    flate2::read::GzDecoder::new(file)
        .read_to_string(&mut text)
        .unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split('\t').collect();
    let (pairs, frames) = (head[1].parse().unwrap(), head[3].parse().unwrap());
    lines.next();
    let contacts = lines
        .map(|line| {
            let f: Vec<usize> = line.split('\t').map(|x| x.parse().unwrap()).collect();
            ((f[0], f[1]), f[2] as u32)
        })
        .collect();
    (pairs, frames, contacts)
}

/// A frequency table: (index1, index2) -> (contact frames, frequency).
type Frequencies = HashMap<(usize, usize), (u32, f64)>;

/// Our table, and the rows' author numbers.
fn ours(text: &str) -> (Frequencies, Vec<(String, String)>) {
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "chain\tresidue1\tresidue2\tname1\tname2\tindex1\tindex2\tcontact_frames\tfrequency"
    );
    let mut table = HashMap::new();
    let mut numbers = Vec::new();
    for line in lines {
        let f: Vec<&str> = line.split('\t').collect();
        assert_eq!(f.len(), 9, "{line}");
        let key = (f[5].parse().unwrap(), f[6].parse().unwrap());
        table.insert(key, (f[7].parse().unwrap(), f[8].parse().unwrap()));
        numbers.push((f[1].to_string(), f[2].to_string()));
    }
    (table, numbers)
}

#[test]
fn frequencies_equal_mdtrajs_compute_contacts() {
    let dir = tempfile::tempdir().unwrap();
    for (name, trajectory) in [("adk", "md/adk.xtc"), ("cobrotoxin", "md/cobrotoxin.dcd")] {
        for (scheme, cutoff) in SCHEMES {
            let out = dir.path().join(format!("{name}.{scheme}.tsv"));
            let topology = data(&format!("md/{name}.pdb.gz"));
            run_ok(&[
                "contacts",
                "--trajectory",
                &data(trajectory),
                "--topology",
                &topology,
                "--definition",
                scheme,
                "--cutoff",
                cutoff,
                "-o",
                &out.to_string_lossy(),
            ]);
            let (table, _) = ours(&std::fs::read_to_string(&out).unwrap());
            let (pairs, frames, contacts) = reference(&format!("{name}.{scheme}"));
            assert_eq!(
                table.len(),
                pairs,
                "{name} {scheme}: the pairs of MDTraj's 'all'"
            );
            assert!(contacts.len() > 50, "{name} {scheme}: a test with contacts");
            for (pair, &(n, frequency)) in &table {
                let expected = contacts.get(pair).copied().unwrap_or(0);
                assert_eq!(n, expected, "{name} {scheme} pair {pair:?}");
                assert_eq!(frequency, f64::from(n) / frames as f64);
            }
        }
    }
}

#[test]
fn stride_periodic_box_and_a_pdb_model_as_a_frame() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let topology = data("md/cobrotoxin.pdb.gz");
    let dcd = data("md/cobrotoxin.dcd");
    let args = |extra: &[&str], o: &str| {
        let mut a = vec![
            "contacts",
            "--trajectory",
            &dcd,
            "--topology",
            &topology,
            "--definition",
            "closest",
            "--cutoff",
            "4.5",
            "-o",
        ];
        a.push(o);
        a.extend_from_slice(extra);
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let run_args = |a: Vec<String>| {
        let refs: Vec<&str> = a.iter().map(String::as_str).collect();
        run_ok(&refs);
    };
    // every 2nd frame: frames 1 and 3, frequencies over 2
    run_args(args(&["--stride", "2"], &out("s2.tsv")));
    let (s2, _) = ours(&std::fs::read_to_string(out("s2.tsv")).unwrap());
    assert!(s2.values().all(|&(n, f)| n <= 2 && f == f64::from(n) / 2.0));
    // the three frames counted one by one add up to the whole
    run_args(args(&[], &out("all.tsv")));
    let (all, _) = ours(&std::fs::read_to_string(out("all.tsv")).unwrap());
    assert!(all.values().any(|&(n, _)| n == 3));
    // without the box: cobrotoxin is whole in its box, so no contact changes except across it
    run_args(args(&["--no-periodic"], &out("plain.tsv")));
    let (plain, _) = ours(&std::fs::read_to_string(out("plain.tsv")).unwrap());
    assert!(plain.iter().all(|(k, v)| v.0 <= all[k].0));

    // the topology's own coordinates as a one-frame trajectory: its Cb contacts are the
    // structure's (`contacts STRUCTURE`, a different reader and code path)
    let adk = data("md/adk.pdb.gz");
    run_ok(&[
        "contacts",
        "--trajectory",
        &adk,
        "--topology",
        &adk,
        "--min-sep",
        "6",
        "-o",
        &out("one.tsv"),
    ]);
    let (one, numbers) = ours(&std::fs::read_to_string(out("one.tsv")).unwrap());
    let rr = run_ok(&["contacts", &adk]);
    let mut expected: Vec<(String, String)> = rr
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f[0].to_string(), f[1].to_string())
        })
        .collect();
    let text = std::fs::read_to_string(out("one.tsv")).unwrap();
    let mut found: Vec<(String, String)> = text
        .lines()
        .skip(1)
        .filter(|l| l.split('\t').nth(7) == Some("1"))
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            (f[1].to_string(), f[2].to_string())
        })
        .collect();
    expected.sort();
    found.sort();
    assert!(expected.len() > 100);
    assert_eq!(found, expected);
    assert_eq!(one.len(), numbers.len());
}

#[test]
fn bad_trajectories_are_one_line_errors_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("freq.tsv");
    let out_s = out.to_string_lossy().into_owned();
    let topology = data("md/cobrotoxin.pdb.gz");
    let check = |trajectory: &str, topology: &str, what: &str| {
        let line = run_err(&[
            "contacts",
            "--trajectory",
            trajectory,
            "--topology",
            topology,
            "-o",
            &out_s,
        ]);
        assert!(line.contains(what), "{line}");
        assert!(!out.exists());
    };
    let dcd = std::fs::read(data("md/cobrotoxin.dcd")).unwrap();
    // a truncated last frame
    let cut = write_bytes(dir.path(), "cut.dcd", &dcd[..dcd.len() - 100]);
    check(&cut, &topology, "cut.dcd:frame 3: truncated frame");
    // a NaN coordinate in frame 2 (its first x: after the header, frame 1 and frame 2's cell)
    let natoms = dcd_atoms(&dcd);
    let frame = 56 + 3 * (8 + 4 * natoms);
    let mut nan = dcd.clone();
    let at = header_bytes(&dcd) + frame + 56 + 4;
    nan[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let nan = write_bytes(dir.path(), "nan.dcd", &nan);
    check(
        &nan,
        &topology,
        "nan.dcd:frame 2: atom 1 has a non-finite coordinate",
    );
    // a topology of another protein
    check(
        &data("md/cobrotoxin.dcd"),
        &data("md/adk.pdb.gz"),
        "cobrotoxin.dcd:frame 1:",
    );
    check(
        &data("md/cobrotoxin.dcd"),
        &data("md/adk.pdb.gz"),
        "atoms, the topology has 3341",
    );
    // a truncated XTC, a corrupt XTC, an empty file
    let xtc = std::fs::read(data("md/adk.xtc")).unwrap();
    let adk = data("md/adk.pdb.gz");
    let cut = write_bytes(dir.path(), "cut.xtc", &xtc[..xtc.len() - 1000]);
    check(&cut, &adk, "cut.xtc:frame 3: truncated frame");
    let mut bad = xtc.clone();
    bad[4..8].copy_from_slice(&77u32.to_be_bytes());
    let bad = write_bytes(dir.path(), "bad.xtc", &bad);
    check(&bad, &adk, "bad.xtc:frame 1: atom count 77 / 3341");
    let empty = write_bytes(dir.path(), "empty.dcd", b"");
    check(&empty, &topology, "empty.dcd: not a DCD file");
    // polymer conformations are not an MD trajectory
    check(&data("polychrom/traj"), &topology, "not an MD trajectory");
}

fn write_bytes(dir: &std::path::Path, name: &str, bytes: &[u8]) -> String {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path.to_string_lossy().into_owned()
}

/// The bytes of a little-endian DCD's three header records.
fn header_bytes(dcd: &[u8]) -> usize {
    let int = |at: usize| i32::from_le_bytes(dcd[at..at + 4].try_into().unwrap()) as usize;
    let title = int(92);
    92 + 4 + title + 4 + 12
}

/// The atom count of a little-endian DCD.
fn dcd_atoms(dcd: &[u8]) -> usize {
    let at = header_bytes(dcd) - 8;
    i32::from_le_bytes(dcd[at..at + 4].try_into().unwrap()) as usize
}

/// `score contacts --frequencies` with a one-frame ensemble (the structure itself) scores as the
/// structure does.
#[test]
fn a_one_frame_ensemble_scores_as_its_structure() {
    let dir = tempfile::tempdir().unwrap();
    let (structure, rr) = (
        data("protein/1aapA/1aapA.pdb.gz"),
        data("protein/1aapA/1aapA.rr.gz"),
    );
    let table = dir.path().join("freq.tsv").to_string_lossy().into_owned();
    run_ok(&[
        "contacts",
        "--trajectory",
        &structure,
        "--topology",
        &structure,
        "-o",
        &table,
    ]);
    let score = |extra: &[&str]| {
        let mut args = vec!["score", "contacts", "--structure", &structure, &rr, "--tsv"];
        args.extend_from_slice(extra);
        run_ok(&args)
    };
    let plain = score(&[]);
    assert!(plain.lines().count() > 10);
    for threshold in ["0.5", "1", "0.01"] {
        let ensemble = score(&["--frequencies", &table, "--truth-frequency", threshold]);
        assert_eq!(ensemble, plain, "threshold {threshold}");
    }
    // residues numbered from 101, placed on the sequence (positions 1-56): the table's
    // residues follow the register
    let mut text = String::new();
    std::io::Read::read_to_string(
        &mut flate2::read::MultiGzDecoder::new(std::fs::File::open(&structure).unwrap()),
        &mut text,
    )
    .unwrap();
    let shifted: String = text
        .lines()
        .map(|line| match line.get(..6) {
            Some("ATOM  " | "HETATM") => {
                let number: i32 = line[22..26].trim().parse().unwrap();
                format!("{}{:>4}{}\n", &line[..22], number + 100, &line[26..])
            }
            _ => format!("{line}\n"),
        })
        .collect();
    let shifted = write(dir.path(), "shifted.pdb", &shifted);
    let table = dir
        .path()
        .join("shifted.tsv")
        .to_string_lossy()
        .into_owned();
    run_ok(&[
        "contacts",
        "--trajectory",
        &shifted,
        "--topology",
        &shifted,
        "-o",
        &table,
    ]);
    assert!(
        std::fs::read_to_string(&table)
            .unwrap()
            .contains("\t101\t104\t")
    );
    let fasta = data("protein/1aapA/1aapA.fasta");
    for register in ["auto", "align"] {
        let args = [
            "score",
            "contacts",
            "--structure",
            &shifted,
            &rr,
            "--tsv",
            "--fasta",
            &fasta,
        ];
        let plain = run_ok(&[&args[..], &["--register", register]].concat());
        let with = ["--register", register, "--frequencies", &table];
        assert_eq!(run_ok(&[&args[..], &with].concat()), plain, "{register}");
    }
}

/// Predictions scored against cobrotoxin's three frames: true positives and true contacts as
/// a naive count over MDTraj's frames in contact (data/reference/mdtraj) gives them.
#[test]
fn ensemble_truth_counts_mdtrajs_frames() {
    let dir = tempfile::tempdir().unwrap();
    let topology = data("md/cobrotoxin.pdb.gz");
    let table = dir.path().join("freq.tsv").to_string_lossy().into_owned();
    run_ok(&[
        "contacts",
        "--trajectory",
        &data("md/cobrotoxin.dcd"),
        "--topology",
        &topology,
        "--definition",
        "cb",
        "-o",
        &table,
    ]);
    // residue numbers of the topology's residue indices (from our table: the names only)
    let text = std::fs::read_to_string(&table).unwrap();
    let (_, numbers) = ours(&text);
    let mut number = HashMap::new();
    for (line, (a, b)) in text.lines().skip(1).zip(&numbers) {
        let f: Vec<&str> = line.split('\t').collect();
        number.insert(f[5].parse::<usize>().unwrap(), a.parse::<i32>().unwrap());
        number.insert(f[6].parse::<usize>().unwrap(), b.parse::<i32>().unwrap());
    }
    let (_, frames, contacts) = reference("cobrotoxin.cb");
    let mdtraj: HashMap<(i32, i32), u32> = contacts
        .iter()
        .map(|(&(i, j), &n)| ((number[&i], number[&j]), n))
        .collect();
    // a prediction: every pair of the table, distinct pseudo-random scores
    let mut pairs: Vec<(i32, i32, f64)> = text
        .lines()
        .skip(1)
        .map(|line| {
            let f: Vec<&str> = line.split('\t').collect();
            let (i, j): (i32, i32) = (f[1].parse().unwrap(), f[2].parse().unwrap());
            let score =
                f64::from((i * 37 + j * 91) % 101) + f64::from(i) * 1e-3 + f64::from(j) * 1e-6;
            (i, j, score)
        })
        .collect();
    let rr: String = pairs
        .iter()
        .map(|(i, j, s)| format!("{i} {j} 0 8 {s}\n"))
        .collect();
    let rr = write(dir.path(), "pred.rr", &rr);
    pairs.sort_by(|a, b| b.2.total_cmp(&a.2));
    let length = number.len();
    for (threshold, least) in [("0.3", 1), ("0.6", 2), ("1", 3)] {
        let out = run_ok(&[
            "score",
            "contacts",
            "--structure",
            &topology,
            &rr,
            "--tsv",
            "--frequencies",
            &table,
            "--truth-frequency",
            threshold,
            "--ranges",
            "6+,24+",
            "--top",
            "L/5,L,NC",
        ]);
        let scored = parse_table(&out);
        assert_eq!(scored.rows.len(), 6);
        for row in &scored.rows {
            let get = |name: &str| {
                let column = scored.header.iter().position(|h| h == name).unwrap();
                row[column].clone()
            };
            let min_sep: i32 = get("min_sep").parse().unwrap();
            let is_true = |i: i32, j: i32| {
                mdtraj
                    .get(&(i, j))
                    .is_some_and(|&n| n >= least && frames == 3)
            };
            let in_range: Vec<&(i32, i32, f64)> =
                pairs.iter().filter(|(i, j, _)| j - i >= min_sep).collect();
            let n_true = in_range.iter().filter(|(i, j, _)| is_true(*i, *j)).count();
            let k = match get("list").as_str() {
                "L/5" => length / 5,
                "L" => length,
                _ => n_true,
            };
            let tp = in_range[..k.min(in_range.len())]
                .iter()
                .filter(|(i, j, _)| is_true(*i, *j))
                .count();
            assert_eq!(get("length"), length.to_string());
            assert_eq!(get("n_true"), n_true.to_string(), "{threshold} {row:?}");
            assert_eq!(get("tp"), tp.to_string(), "{threshold} {row:?}");
            assert!(n_true > 0);
        }
    }
}

#[test]
fn bad_frequency_tables_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let (structure, rr) = (
        data("protein/1aapA/1aapA.pdb.gz"),
        data("protein/1aapA/1aapA.rr.gz"),
    );
    let header =
        "chain\tresidue1\tresidue2\tname1\tname2\tindex1\tindex2\tcontact_frames\tfrequency";
    let score = |table: &str, extra: &[&str]| {
        let mut args = vec![
            "score",
            "contacts",
            "--structure",
            &structure,
            &rr,
            "--frequencies",
            table,
        ];
        args.extend_from_slice(extra);
        run_err(&args)
    };
    let chain_a = write(
        dir.path(),
        "a.tsv",
        &format!("{header}\nA\t1\t5\tVAL\tLYS\t0\t4\t1\t1\n"),
    );
    // a blank chain is written A (the PDB's convention for a file's one chain), so chain A of
    // a table is the blank chain of a structure without chain ids: its residues are checked
    let line = score(&chain_a, &[]);
    assert!(
        line.contains("a.tsv:2: residue 5 is LYS here but CYS in chain (blank)"),
        "{line}"
    );
    let renamed = write(
        dir.path(),
        "n.tsv",
        &format!("{header}\n\t1\t5\tGLY\tLYS\t0\t4\t1\t1\n"),
    );
    let line = score(&renamed, &[]);
    assert!(
        line.contains("n.tsv:2: residue 1 is GLY here but VAL"),
        "{line}"
    );
    let bad = write(
        dir.path(),
        "f.tsv",
        &format!("{header}\n\t1\t5\tVAL\tLYS\t0\t4\t1\t1.5\n"),
    );
    let line = score(&bad, &[]);
    assert!(
        line.contains("f.tsv:2: frequency 1.5 is not a fraction"),
        "{line}"
    );
    let other = write(dir.path(), "o.tsv", "chain\tresidue1\tresidue2\n\t1\t5\n");
    let line = score(&other, &[]);
    assert!(
        line.contains("o.tsv: not a contact frequency table"),
        "{line}"
    );
    let line = score(&chain_a, &["--truth-frequency", "0"]);
    assert!(
        line.contains("--truth-frequency must be a fraction"),
        "{line}"
    );
    let line = run_err(&[
        "score",
        "contacts",
        "--structure",
        &structure,
        &rr,
        "--truth-frequency",
        "0.5",
    ]);
    assert!(line.contains("--frequencies"), "{line}");
}

/// Issue 51: a topology without chain ids (a PDB's one chain) gets chain `A` in the table, as
/// the PDB's convention names it, never an empty column; said on standard error.
#[test]
fn a_blank_chain_is_written_a() {
    let pdb = data("protein/1aapA/1aapA.pdb.gz");
    let out = run(&["contacts", "--trajectory", &pdb, "--topology", &pdb]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = String::from_utf8(out.stdout).unwrap();
    let rows: Vec<&str> = table.lines().skip(1).collect();
    assert!(!rows.is_empty());
    assert!(rows.iter().all(|r| r.starts_with("A\t")), "{}", rows[0]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("has no chain ids: its chain is written A"),
        "{stderr}"
    );
}
