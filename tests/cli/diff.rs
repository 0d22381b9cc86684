//! `diff loops`: a planted change found and nothing else, a null comparison, bad input refused
//! with one line and no output. The statistics are compared with pydeseq2 in the library's
//! tests (`diff::tests`), the counts with a naive dense sum (`diff::loops::tests`).

use super::*;

/// Splits the map into replicates by binomial thinning (`sample --fraction 0.5`, seeds 1-4);
/// with `planted`, B's replicates (seeds 3, 4) have the counts of the 3 x 3 pixels of loop 1
/// (bins 20 x 50) multiplied by 4, through a bg2 round trip.
fn replicates(dir: &std::path::Path, planted: bool) -> Vec<String> {
    let map = data("sim_extrusion.5kb.cool");
    let mut out = Vec::new();
    for seed in 1..=4 {
        let path = dir.join(format!("r{seed}.cool")).display().to_string();
        run_ok(&[
            "sample",
            &map,
            "--fraction",
            "0.5",
            "--seed",
            &seed.to_string(),
            "-o",
            &path,
        ]);
        if planted && seed >= 3 {
            let text = run_ok(&["dump", &path, "--join"]);
            let changed: String = text
                .lines()
                .map(|line| {
                    let f: Vec<&str> = line.split('\t').collect();
                    let (i, j) = (
                        f[1].parse::<u64>().unwrap() / 5000,
                        f[4].parse::<u64>().unwrap() / 5000,
                    );
                    let count: u64 = f[6].parse().unwrap();
                    let count = if i.abs_diff(20) <= 1 && j.abs_diff(50) <= 1 {
                        4 * count
                    } else {
                        count
                    };
                    format!(
                        "{}\t{}\t{}\t{}\t{}\t{}\t{count}\n",
                        f[0], f[1], f[2], f[3], f[4], f[5]
                    )
                })
                .collect();
            let bg2 = write(dir, &format!("r{seed}.bg2"), &changed);
            let sizes = write(dir, "sizes", "chr1\t1000000\n");
            std::fs::remove_file(&path).unwrap();
            run_ok(&[
                "convert",
                &bg2,
                &path,
                "--format",
                "bg2",
                "--chrom-sizes",
                &sizes,
                "--bin-size",
                "5000",
            ]);
        }
        out.push(path);
    }
    out
}

fn diff_loops(maps: &[String], prefix: &str, extra: &[&str]) -> Vec<Vec<String>> {
    let mut args = vec![
        "diff", "loops", "--a", &maps[0], &maps[1], "--b", &maps[2], &maps[3],
    ];
    let loops = data("sim_extrusion.truth_loops.bedpe");
    args.extend(["--loops", &loops, "-o", prefix]);
    args.extend(extra);
    run_ok(&args);
    std::fs::read_to_string(format!("{prefix}.loops.bedpe"))
        .unwrap()
        .lines()
        .map(|l| l.split('\t').map(str::to_string).collect())
        .collect()
}

#[test]
fn diff_loops_finds_a_planted_change_and_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    let maps = replicates(dir.path(), true);
    let prefix = dir.path().join("planted").display().to_string();
    let table = diff_loops(&maps, &prefix, &[]);
    let header = &table[0];
    assert_eq!(
        header[..16].join(" "),
        "chrom1 start1 end1 chrom2 start2 end2 baseMean log2FoldChange lfc_low lfc_high lfcSE pvalue qvalue mean_A mean_B direction"
    );
    assert_eq!(
        header[16..].join(" "),
        "count_A1 count_A2 count_B1 count_B2"
    );
    assert_eq!(table.len(), 9, "eight loops");
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    let planted = &table[1];
    assert_eq!(
        planted[..6].join(" "),
        "chr1 100000 105000 chr1 250000 255000"
    );
    assert_eq!(planted[column("direction")], "up");
    let lfc: f64 = planted[column("log2FoldChange")].parse().unwrap();
    let (low, high): (f64, f64) = (
        planted[column("lfc_low")].parse().unwrap(),
        planted[column("lfc_high")].parse().unwrap(),
    );
    assert!(
        low < 2.0 && 2.0 < high,
        "the 95% interval holds log2(4): {low} {lfc} {high}"
    );
    for row in &table[2..] {
        assert_eq!(row[column("direction")], "-", "{row:?}");
    }
    // the counts are the sums of the 3 x 3 windows: B's planted one is four times its pixels
    let counts: Vec<f64> = planted[16..].iter().map(|c| c.parse().unwrap()).collect();
    assert!(
        counts[2] > 2.5 * counts[0] && counts[3] > 2.5 * counts[1],
        "{counts:?}"
    );
}

#[test]
fn diff_loops_of_replicates_of_one_map_calls_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let maps = replicates(dir.path(), false);
    let prefix = dir.path().join("null").display().to_string();
    let table = diff_loops(&maps, &prefix, &["--alpha", "0.1"]);
    let direction = table[0].iter().position(|h| h == "direction").unwrap();
    assert!(table[1..].iter().all(|row| row[direction] == "-"));
}

#[test]
fn diff_loops_refuses_bad_input_with_one_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let map = data("sim_extrusion.5kb.cool");
    let loops = data("sim_extrusion.truth_loops.bedpe");
    let prefix = dir.path().join("bad").display().to_string();
    let output = format!("{prefix}.loops.bedpe");
    let other = data("CN.mm9.10000kb.cool");
    let message = run_err(&[
        "diff", "loops", "--a", &map, &map, "--b", &other, "--loops", &loops, "-o", &prefix,
    ]);
    assert!(
        message.contains("other chromosomes than") && message.contains("CN.mm9"),
        "{message}"
    );
    let message = run_err(&[
        "diff", "loops", "--a", &map, "--b", &map, "--loops", &loops, "-o", &prefix,
    ]);
    assert!(
        message.contains("no condition has a replicate"),
        "{message}"
    );
    for (name, text, wanted) in [
        (
            "outside",
            "chr1\t100000\t105000\tchr1\t995000\t1005000\n",
            ["loop 1", "outside chr1"],
        ),
        (
            "unknown",
            "chr1\t0\t5000\tchr1\t50000\t55000\nchrX\t0\t5000\tchrX\t50000\t55000\n",
            ["loop 2", "chrX is not a chromosome"],
        ),
        (
            "trans",
            "chr1\t0\t5000\tchr2\t50000\t55000\n",
            ["loop 1", "two chromosomes"],
        ),
    ] {
        let bedpe = write(dir.path(), &format!("{name}.bedpe"), text);
        let message = run_err(&[
            "diff", "loops", "--a", &map, &map, "--b", &map, &map, "--loops", &bedpe, "-o", &prefix,
        ]);
        assert!(
            wanted.iter().all(|w| message.contains(w)),
            "{name}: {message}"
        );
    }
    assert!(!std::path::Path::new(&output).exists(), "no output left");
}

/// The two anchors' starts (columns 2 and 5) of each line of a table with a header line.
fn anchor_starts(path: &str) -> Vec<(u64, u64)> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            (f[1].parse().unwrap(), f[4].parse().unwrap())
        })
        .collect()
}

/// Without --loops: the loops tested are the dots `merge`, `balance --store` and `dots` find on
/// each condition's summed replicates (the same dots, by another road), pooled: every dot of A,
/// and every dot of B within 20 kb of a loop tested.
#[test]
fn diff_loops_without_loops_tests_the_dots_of_each_condition() {
    let dir = tempfile::tempdir().unwrap();
    let maps = replicates(dir.path(), false);
    let mut args = vec![
        "diff", "loops", "--a", &maps[0], &maps[1], "--b", &maps[2], &maps[3],
    ];
    let prefix = dir.path().join("called").display().to_string();
    args.extend(["-o", &prefix]);
    run_ok(&args);
    let tested = anchor_starts(&format!("{prefix}.loops.bedpe"));
    let dots = |pair: &[String], name: &str| -> Vec<(u64, u64)> {
        let merged = dir
            .path()
            .join(format!("{name}.cool"))
            .display()
            .to_string();
        run_ok(&["merge", &pair[0], &pair[1], "-o", &merged]);
        run_ok(&["balance", &merged, "--store"]);
        let table = dir
            .path()
            .join(format!("{name}.dots.tsv"))
            .display()
            .to_string();
        run_ok(&["dots", &merged, "-o", &table]);
        anchor_starts(&table)
    };
    let (a, b) = (dots(&maps[..2], "a"), dots(&maps[2..], "b"));
    assert!(!a.is_empty() && !b.is_empty());
    for dot in &a {
        assert!(tested.contains(dot), "A's dot {dot:?} is tested");
    }
    for dot in &b {
        let near = tested
            .iter()
            .any(|t| t.0.abs_diff(dot.0) <= 20_000 && t.1.abs_diff(dot.1) <= 20_000);
        assert!(
            near,
            "B's dot {dot:?} is tested or within 20 kb of a loop tested"
        );
    }
    assert!(tested.len() <= a.len() + b.len() && tested.len() >= a.len());
}
