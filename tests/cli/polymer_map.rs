//! `contactmap polymer-map` against polychrom's own contact maps (data/reference/polychrom,
//! scripts/polychrom_reference.py), the simulator's map through polychrom's format, and bad
//! trajectories.

use super::*;
use contactmap::io::trajectory::polychrom::write_blocks;
use contactmap::io::{OpenOptions, open_matrix};

/// The full symmetric matrix of a .cool's raw counts.
fn dense(path: &str) -> Vec<Vec<u64>> {
    let reader = open_matrix(path, &OpenOptions::default()).unwrap();
    let n = reader.bins().n_bins();
    let mut m = vec![vec![0u64; n]; n];
    reader
        .read_pixels(0..n, 0..n, &mut |block| {
            for k in 0..block.len() {
                let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                m[i][j] = block.count[k] as u64;
                m[j][i] = block.count[k] as u64;
            }
            Ok(())
        })
        .unwrap();
    m
}

/// A polychrom reference: the dense matrix polychrom returns, its diagonal halved (polychrom's
/// `triangle + triangle.T` counts a within-bin contact twice there; a .cool once).
fn reference(name: &str) -> Vec<Vec<u64>> {
    let text = {
        use std::io::Read as _;
        let file = std::fs::File::open(data(&format!("reference/polychrom/{name}"))).unwrap();
        let mut text = String::new();
        flate2::read::GzDecoder::new(file)
            .read_to_string(&mut text)
            .unwrap();
        text
    };
    let mut m: Vec<Vec<u64>> = text
        .lines()
        .map(|l| l.split('\t').map(|v| v.parse().unwrap()).collect())
        .collect();
    for (k, row) in m.iter_mut().enumerate() {
        assert_eq!(row[k] % 2, 0);
        row[k] /= 2;
    }
    m
}

#[test]
fn maps_equal_polychroms() {
    let dir = tempfile::tempdir().unwrap();
    let traj = data("polychrom/traj");
    let mono = dir.path().join("mono.cool").to_string_lossy().into_owned();
    let err = run(&["polymer-map", &traj, "--contact-radius", "1.6", "-o", &mono]);
    assert!(err.status.success());
    let note = String::from_utf8_lossy(&err.stderr);
    assert!(note.contains("7 conformations of 150 beads"), "{note}");
    assert_eq!(dense(&mono), reference("monomer_cutoff1.6.tsv.gz"));
    // binned, two chains: the two files given one by one
    let binned = dir
        .path()
        .join("binned.cool")
        .to_string_lossy()
        .into_owned();
    run_ok(&[
        "polymer-map",
        &format!("{traj}/blocks_0-3.h5"),
        &format!("{traj}/blocks_4-6.h5"),
        "--contact-radius",
        "1.6",
        "--monomers-per-bin",
        "4",
        "--chains",
        "90,60",
        "-o",
        &binned,
    ]);
    assert_eq!(
        dense(&binned),
        reference("binned_4_chains90-60_cutoff1.6.tsv.gz")
    );
    // one block by polychrom's URI: its contacts only
    let one = dir.path().join("one.cool").to_string_lossy().into_owned();
    let out = run(&[
        "polymer-map",
        &format!("{traj}/blocks_4-6.h5::5"),
        "--contact-radius",
        "1.6",
        "-o",
        &one,
    ]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("1 conformations of 150 beads"));
}

/// The simulator's conformations written in polychrom's format give the simulator's own map.
#[test]
fn the_simulators_map_comes_back_through_polychroms_format() {
    let dir = tempfile::tempdir().unwrap();
    let sim = dir.path().join("sim.cool").to_string_lossy().into_owned();
    let traj = dir.path().join("traj").to_string_lossy().into_owned();
    run_ok(&[
        "simulate",
        "polymer",
        "-o",
        &sim,
        "--chains",
        "60,40",
        "--replicas",
        "3",
        "--samples",
        "20",
        "--equilibration",
        "400",
        "--sample-every",
        "100",
        "--seed",
        "5",
        "--density",
        "0.3",
        "--conformations",
        &traj,
        "--conformations-format",
        "polychrom",
    ]);
    assert!(std::path::Path::new(&format!("{traj}/blocks_0-49.h5")).is_file());
    assert!(std::path::Path::new(&format!("{traj}/blocks_50-59.h5")).is_file());
    let back = dir.path().join("back.cool").to_string_lossy().into_owned();
    run_ok(&[
        "polymer-map",
        &traj,
        "--contact-radius",
        "1.5",
        "--chains",
        "60,40",
        "-o",
        &back,
    ]);
    let (a, b) = (dense(&sim), dense(&back));
    assert!(a.iter().flatten().sum::<u64>() > 1000);
    assert_eq!(a, b);
}

#[test]
fn bad_trajectories_are_one_line_errors_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("map.cool");
    let out_s = out.to_string_lossy().into_owned();
    let check = |args: &[&str], what: &str| {
        let line = run_err(args);
        assert!(line.contains(what), "{line}");
        assert!(!out.exists());
    };
    // a NaN coordinate
    let mut conformations = vec![vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]; 3];
    conformations[2][1][2] = f64::NAN;
    let nan = dir.path().join("nan");
    write_blocks(&nan, &conformations).unwrap();
    check(
        &[
            "polymer-map",
            &nan.to_string_lossy(),
            "--contact-radius",
            "1.5",
            "-o",
            &out_s,
        ],
        "blocks_0-2.h5::2: bead 2 has a non-finite coordinate",
    );
    // another number of beads
    let mut uneven = vec![vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]; 2];
    uneven[1].push([2.0, 0.0, 0.0]);
    let uneven_dir = dir.path().join("uneven");
    write_blocks(&uneven_dir, &uneven).unwrap();
    check(
        &[
            "polymer-map",
            &uneven_dir.to_string_lossy(),
            "--contact-radius",
            "1.5",
            "-o",
            &out_s,
        ],
        "::1: 3 beads, where the first conformation has 2",
    );
    // an empty block: pos of 0 x 3
    let empty = dir.path().join("blocks_0-0.h5");
    {
        let file = hdf5::File::create(&empty).unwrap();
        let group = file.create_group("0").unwrap();
        group
            .new_dataset::<f64>()
            .shape((0, 3))
            .create("pos")
            .unwrap();
    }
    check(
        &[
            "polymer-map",
            &empty.to_string_lossy(),
            "--contact-radius",
            "1.5",
            "-o",
            &out_s,
        ],
        "blocks_0-0.h5::0: an empty block",
    );
    // a block the file's name promises but lacks
    let short = dir.path().join("blocks_0-3.h5");
    {
        let file = hdf5::File::create(&short).unwrap();
        let group = file.create_group("0").unwrap();
        let pos = group
            .new_dataset::<f64>()
            .shape((2, 3))
            .create("pos")
            .unwrap();
        pos.write_raw(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0]).unwrap();
    }
    check(
        &[
            "polymer-map",
            &short.to_string_lossy(),
            "--contact-radius",
            "1.5",
            "-o",
            &out_s,
        ],
        "blocks_0-3.h5::1: no block 1 in this file",
    );
    // a block URI on a folder, a missing trajectory, an output in a missing folder
    let folder_uri = format!("{}::0", nan.display());
    check(
        &[
            "polymer-map",
            &folder_uri,
            "--contact-radius",
            "1.5",
            "-o",
            &out_s,
        ],
        "is a folder; a polychrom URI names a blocks file and a block",
    );
    let missing = dir.path().join("missing");
    check(
        &[
            "polymer-map",
            &missing.to_string_lossy(),
            "--contact-radius",
            "1.5",
            "-o",
            &out_s,
        ],
        "missing: No such file or directory",
    );
    let nowhere = dir.path().join("nowhere/map.cool");
    let line = run_err(&[
        "polymer-map",
        &data("polychrom/traj"),
        "--contact-radius",
        "1.5",
        "-o",
        &nowhere.to_string_lossy(),
    ]);
    assert!(
        line.contains("map.cool: cannot be written: the folder")
            && line.contains("nowhere' does not exist"),
        "{line}"
    );
    assert!(!dir.path().join("nowhere").exists());
    // a truncated XYZ frame
    let xyz = write(
        dir.path(),
        "t.xyz",
        "2\nf1\nC 0 0 0\nC 1 0 0\n2\nf2\nC 0 0 0\n",
    );
    check(
        &["polymer-map", &xyz, "--contact-radius", "1.5", "-o", &out_s],
        "frame 2 is truncated",
    );
    // a table row cut short
    let table = write(
        dir.path(),
        "c.tsv",
        "replica\tsample\tchain\tbead\tx\ty\tz\n0\t0\t1\t0\t0\t0\t0\n0\t0\t1\t1\t1\t0\n",
    );
    check(
        &[
            "polymer-map",
            &table,
            "--contact-radius",
            "1.5",
            "-o",
            &out_s,
        ],
        "c.tsv:3: expected 7 columns, found 6",
    );
    // a file of another kind: the header expected, the line's start shown, not all of it
    let line = run_err(&[
        "polymer-map",
        &data("protein/toxd/toxd.mat.gz"),
        "--contact-radius",
        "1.5",
        "-o",
        &out_s,
    ]);
    assert!(line.contains("toxd.mat.gz:1: expected the header 'replica sample chain bead x y z'"));
    // the line's first 60 characters and "...", whatever the path's length
    let shown = line.split("found '").nth(1).unwrap_or_default();
    assert!(shown.ends_with("...'"), "{line}");
    assert_eq!(shown.chars().count(), 60 + "...'".len(), "{line}");
    check(
        &["polymer-map", &xyz, "--contact-radius", "-1", "-o", &out_s],
        "contact-radius",
    );
}

/// A TSV of numbers with a header: its columns by name.
fn columns(text: &str) -> std::collections::HashMap<String, Vec<f64>> {
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split('\t')
        .map(String::from)
        .collect();
    let mut out: std::collections::HashMap<String, Vec<f64>> =
        header.iter().map(|h| (h.clone(), Vec::new())).collect();
    for line in lines {
        for (h, v) in header.iter().zip(line.split('\t')) {
            if let Ok(x) = v.parse() {
                out.get_mut(h).unwrap().push(x);
            }
        }
    }
    out
}

fn assert_close(ours: &[f64], theirs: &[f64], rtol: f64, what: &str) {
    assert_eq!(ours.len(), theirs.len(), "{what}");
    for (k, (a, b)) in ours.iter().zip(theirs).enumerate() {
        assert!((a - b).abs() <= rtol * b.abs(), "{what}[{k}]: {a} vs {b}");
    }
}

/// P(s), R^2(s), Rg^2(s) and Rg^2 per conformation against polychrom's polymer_analyses on the
/// same trajectory (scripts/polychrom_reference.py).
#[test]
fn statistics_equal_polychroms() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("s").to_string_lossy().into_owned();
    let out = run(&[
        "polymer-stats",
        &data("polychrom/traj"),
        "--contact-radius",
        "1.6",
        "-o",
        &prefix,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let read = |name: &str| std::fs::read_to_string(name).unwrap();
    let ours = columns(&read(&format!("{prefix}.scaling.tsv")));
    let theirs = columns(&read(&data("reference/polychrom/stats.scaling.tsv")));
    // contact counts are exact, so is P(s)
    assert_eq!(ours["s_mid"], theirs["s_mid"]);
    assert_eq!(ours["contact_probability"], theirs["contact_probability"]);
    let ours = columns(&read(&format!("{prefix}.r2.tsv")));
    let theirs = columns(&read(&data("reference/polychrom/stats.r2.tsv")));
    assert_eq!(ours["s"], theirs["s"]);
    assert_close(&ours["r2"], &theirs["r2"], 1e-12, "r2");
    assert_close(&ours["rg2"], &theirs["rg2"], 1e-12, "rg2(s)");
    // Rg^2: the first file's positions are float32, which polychrom's Rg2 sums in float32
    // (1e-7); the second file's float64 conformations agree to 1e-12
    let ours = columns(&read(&format!("{prefix}.rg2.tsv")));
    let theirs = columns(&read(&data("reference/polychrom/stats.rg2.tsv")));
    assert_close(&ours["rg2"][..4], &theirs["rg2"][..4], 1e-7, "rg2 float32");
    assert_close(&ours["rg2"][4..], &theirs["rg2"][4..], 1e-12, "rg2 float64");
    let text = read(&format!("{prefix}.rg2.tsv"));
    assert!(text.contains("blocks_4-6.h5::6\t"), "{text}");
}

/// `plot polymer-stats` draws the tables of `polymer-stats`: each curve's points are the
/// table's (read back from the SVG's pixels through the decade ticks of its axes).
#[test]
fn statistics_are_drawn_from_their_tables() {
    use super::plot::{plot_fails, plot_svg};
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("traj").to_string_lossy().into_owned();
    run_ok(&[
        "polymer-stats",
        &data("polychrom/traj"),
        "--contact-radius",
        "1.6",
        "-o",
        &prefix,
    ]);
    let svg = plot_svg(&["plot", "polymer-stats", &prefix, &prefix, "--labels", "a,b"]);
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let lines: Vec<Vec<(f64, f64)>> = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .map(|n| {
            n.attribute("points")
                .unwrap()
                .split_whitespace()
                .map(|p| {
                    let (x, y) = p.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect()
        })
        .collect();
    // per sample: P(s), R^2(s), Rg^2(s) and two slopes (lines broken at P(s) = 0 aside)
    assert!(lines.len() >= 10, "{}", lines.len());
    let scaling = std::fs::read_to_string(format!("{prefix}.scaling.tsv")).unwrap();
    let positive = scaling
        .lines()
        .skip(1)
        .filter(|l| l.split('\t').nth(1).unwrap().parse::<f64>().unwrap() > 0.0)
        .count();
    assert_eq!(
        lines[0].len(),
        positive,
        "a P(s) point per positive table row"
    );
    let r2 = std::fs::read_to_string(format!("{prefix}.r2.tsv")).unwrap();
    let r2_rows: Vec<Vec<f64>> = r2
        .lines()
        .skip(1)
        .map(|l| l.split('\t').map(|x| x.parse().unwrap()).collect())
        .collect();
    // the R^2 line (solid) and the Rg^2 line: the same s pixels, R^2 above Rg^2
    // (the P(s) panel holds the two samples' lines first)
    assert_eq!(lines[1], lines[0], "the same tables twice");
    let (r2_line, rg2_line) = (&lines[2], &lines[3]);
    assert_eq!(r2_line.len(), r2_rows.len());
    for ((a, b), row) in r2_line.iter().zip(rg2_line).zip(&r2_rows) {
        assert_eq!(a.0, b.0);
        assert!(a.1 < b.1, "R^2 > Rg^2 at s = {}", row[0]);
    }
    // pixel distances on log axes: ratios of the table's values
    let (first, last) = (r2_line[0], r2_line[r2_line.len() - 1]);
    let x_decades = (r2_rows[r2_rows.len() - 1][0] / r2_rows[0][0]).log10();
    let y_decades = (r2_rows[r2_rows.len() - 1][1] / r2_rows[0][1]).log10();
    let (a, b) = (&r2_rows[3], &r2_rows[9]);
    let predicted_dx = (b[0] / a[0]).log10() / x_decades * (last.0 - first.0);
    assert!((r2_line[9].0 - r2_line[3].0 - predicted_dx).abs() < 0.05);
    let predicted_dy = (b[1] / a[1]).log10() / y_decades * (last.1 - first.1);
    assert!((r2_line[9].1 - r2_line[3].1 - predicted_dy).abs() < 0.05);
    for label in ["a R²(s)", "b Rg²(s)", "separation s (beads)"] {
        assert!(svg.contains(&format!(">{label}</text>")), "{label}");
    }
    // Rg^2 over the conformations: one line per sample, a point per conformation
    let over = plot_svg(&["plot", "polymer-stats", &prefix, "--over-time"]);
    assert_eq!(over.matches("<polyline").count(), 1);
    let rg2 = std::fs::read_to_string(format!("{prefix}.rg2.tsv")).unwrap();
    let points = over
        .split("points=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap();
    assert_eq!(points.split_whitespace().count(), rg2.lines().count() - 1);
    // bad inputs: one line, no figure
    let missing = dir.path().join("none").to_string_lossy().into_owned();
    let line = plot_fails(&["plot", "polymer-stats", &missing], dir.path());
    assert!(line.contains("none.scaling.tsv"), "{line}");
    let line = plot_fails(
        &["plot", "polymer-stats", &prefix, "--labels", "a,b"],
        dir.path(),
    );
    assert!(
        line.contains("--labels gives 2 name(s) for 1 input(s)"),
        "{line}"
    );
    std::fs::write(format!("{prefix}.r2.tsv"), "s\tr2\n4\t1\n").unwrap();
    let line = plot_fails(&["plot", "polymer-stats", &prefix], dir.path());
    assert!(line.contains("traj.r2.tsv: no column 'rg2'"), "{line}");
}
