//! `diff loops`: a planted change found and nothing else, a null comparison, bad input refused
//! with one line and no output. The statistics are compared with pydeseq2 in the library's
//! tests (`diff::tests`), the counts with a naive dense sum (`diff::loops::tests`).

use super::*;

/// Splits the map into replicates by binomial thinning (`sample --fraction 0.5`, seeds 1-4);
/// with `planted`, B's replicates (seeds 3, 4) have the counts of the 3 x 3 pixels of loop 1
/// (bins 20 x 50) multiplied by 4, through a bg2 round trip.
fn replicates(dir: &std::path::Path, planted: bool) -> Vec<String> {
    let loop_one = |i: u64, j: u64, count: u64| {
        if i.abs_diff(20) <= 1 && j.abs_diff(50) <= 1 {
            4 * count
        } else {
            count
        }
    };
    let change: Option<&dyn Fn(u64, u64, u64) -> u64> =
        if planted { Some(&loop_one) } else { None };
    replicates_changed(dir, change, false)
}

/// Four replicates of the map by `sample --fraction 0.5` (seeds 1-4); B's (seeds 3, 4) counts
/// changed by `change(bin1, bin2, count)` through a bg2 round trip; with `balance`, each
/// balanced (`balance --store`).
fn replicates_changed(
    dir: &std::path::Path,
    change: Option<&dyn Fn(u64, u64, u64) -> u64>,
    balance: bool,
) -> Vec<String> {
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
        if let (Some(change), true) = (change, seed >= 3) {
            let text = run_ok(&["dump", &path, "--join"]);
            let changed: String = text
                .lines()
                .map(|line| {
                    let f: Vec<&str> = line.split('\t').collect();
                    let (i, j) = (
                        f[1].parse::<u64>().unwrap() / 5000,
                        f[4].parse::<u64>().unwrap() / 5000,
                    );
                    let count = change(i, j, f[6].parse().unwrap());
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
        if balance {
            run_ok(&["balance", &path, "--store"]);
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
    // maps too sparse for dots: the condition is named, --loops suggested
    let sparse = dir.path().join("sparse.cool").display().to_string();
    run_ok(&[
        "sample",
        &map,
        "--fraction",
        "0.002",
        "--seed",
        "1",
        "-o",
        &sparse,
    ]);
    let message = run_err(&[
        "diff", "loops", "--a", &sparse, &sparse, "--b", &map, &map, "-o", &prefix,
    ]);
    assert!(
        message.contains("condition A") && message.contains("--loops"),
        "{message}"
    );
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

/// The rows of a table with a header line, split at tabs.
fn rows(path: &str) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| l.split('\t').map(str::to_string).collect())
        .collect()
}

/// The boundaries changed at q < `alpha` between replicates 1, 2 and 3, 4: (start, status).
fn changed_boundaries(dir: &std::path::Path, maps: &[String], alpha: &str) -> Vec<(u64, String)> {
    let prefix = dir.join(format!("b{alpha}")).display().to_string();
    run_ok(&[
        "diff",
        "boundaries",
        "--a",
        &maps[0],
        &maps[1],
        "--b",
        &maps[2],
        &maps[3],
        "--window",
        "25k",
        "--alpha",
        alpha,
        "-o",
        &prefix,
    ]);
    let table = rows(&format!("{prefix}.boundaries.tsv"));
    assert!(table.len() > 5, "every boundary is tested");
    let column = |name: &str| table[0].iter().position(|h| h == name).unwrap();
    let (start, status) = (column("start"), column("status"));
    table[1..]
        .iter()
        .filter(|r| r[status] != "-")
        .map(|r| (r[start].parse().unwrap(), r[status].clone()))
        .collect()
}

/// B's replicates lose the boundary at 270 kb (bin 54: its counts across it, up to 10 bins
/// apart, tripled): that boundary is lost or weaker in B (the element 20 kb upstream may then
/// be called in B instead: gained), and no boundary farther away changes; the same replicates
/// without the planted change call nothing.
#[test]
fn diff_boundaries_finds_a_planted_change() {
    let dir = tempfile::tempdir().unwrap();
    let fill = |i: u64, j: u64, count: u64| {
        if i < 54 && j >= 54 && j - i <= 10 {
            3 * count
        } else {
            count
        }
    };
    let planted_dir = dir.path().join("planted");
    std::fs::create_dir(&planted_dir).unwrap();
    let maps = replicates_changed(&planted_dir, Some(&fill), true);
    let changed = changed_boundaries(&planted_dir, &maps, "0.05");
    assert!(
        changed
            .iter()
            .any(|(s, status)| s.abs_diff(270_000) <= 5_000
                && ["lost", "weaker"].contains(&status.as_str())),
        "{changed:?}"
    );
    let null_dir = dir.path().join("null");
    std::fs::create_dir(&null_dir).unwrap();
    let maps = replicates_changed(&null_dir, None, true);
    let null = changed_boundaries(&null_dir, &maps, "0.05");
    assert!(null.is_empty(), "{null:?}");
    assert!(
        changed.iter().all(|(s, _)| s.abs_diff(270_000) <= 25_000),
        "{changed:?}"
    );
}

#[test]
fn diff_boundaries_and_compartments_refuse_bad_input_with_one_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let balanced = data("sim_extrusion.5kb.cool");
    let raw = dir.path().join("raw.cool").display().to_string();
    run_ok(&[
        "sample",
        &balanced,
        "--fraction",
        "0.5",
        "--seed",
        "1",
        "-o",
        &raw,
    ]);
    let prefix = dir.path().join("bad").display().to_string();
    for command in ["boundaries", "compartments"] {
        let message = run_err(&[
            "diff", command, "--a", &balanced, "--b", &raw, "-o", &prefix,
        ]);
        assert!(
            message.contains("raw.cool") && message.contains("no weights"),
            "{command}: {message}"
        );
        let other = data("CN.mm9.10000kb.cool");
        let message = run_err(&[
            "diff", command, "--a", &balanced, "--b", &other, "-o", &prefix,
        ]);
        assert!(
            message.contains("other chromosomes than"),
            "{command}: {message}"
        );
    }
    let message = run_err(&[
        "diff", "regions", "--a", &balanced, &balanced, "--b", &balanced, "--window", "150k", "-o",
        &prefix,
    ]);
    assert!(message.contains("one map per condition"), "{message}");
    let message = run_err(&[
        "diff", "regions", "--a", &balanced, "--b", &raw, "--window", "150k", "-o", &prefix,
    ]);
    assert!(message.contains("no weights"), "{message}");
    let pairs = write(
        dir.path(),
        "pairs.bedpe",
        "chr1\t0\t150000\tchr9\t0\t150000\t0\t.\t+\t+\n",
    );
    let message = run_err(&[
        "diff", "regions", "--a", &balanced, "--b", &balanced, "--pairs", &pairs, "-o", &prefix,
    ]);
    assert!(
        message.contains("line 1") && message.contains("chr9"),
        "{message}"
    );
    let entries: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|name| name.starts_with("bad"))
        .collect();
    assert!(entries.is_empty(), "no output left: {entries:?}");
}

/// A map against itself: every window identical (ssim 1); a replicate against one whose domain
/// 60-89 (300-450 kb) is tripled, raw counts: the least similar window is over it.
#[test]
fn diff_regions_ranks_a_changed_domain_lowest() {
    let dir = tempfile::tempdir().unwrap();
    let map = data("sim_extrusion.5kb.cool");
    let prefix = dir.path().join("same").display().to_string();
    run_ok(&[
        "diff", "regions", "--a", &map, "--b", &map, "--window", "150k", "--step", "25k", "-o",
        &prefix,
    ]);
    let table = rows(&format!("{prefix}.regions.tsv"));
    assert_eq!(&table[0][..4], ["ID", "SN", "ssim", "z_ssim"]);
    assert_eq!(table.len() - 1, 35, "windows of 150 kb every 25 kb on 1 Mb");
    assert!(
        table[1..].iter().all(|r| r[2] == "1.0"),
        "identical windows"
    );

    let tripled = |i: u64, j: u64, count: u64| {
        if (60..90).contains(&i) && (60..90).contains(&j) {
            3 * count
        } else {
            count
        }
    };
    let maps = replicates_changed(dir.path(), Some(&tripled), false);
    let prefix = dir.path().join("changed").display().to_string();
    run_ok(&[
        "diff", "regions", "--a", &maps[0], "--b", &maps[2], "--window", "150k", "--step", "25k",
        "--raw", "-o", &prefix,
    ]);
    let table = rows(&format!("{prefix}.regions.tsv"));
    let lowest = table[1..]
        .iter()
        .min_by(|a, b| {
            a[2].parse::<f64>()
                .unwrap()
                .total_cmp(&b[2].parse().unwrap())
        })
        .unwrap();
    let start: u64 = lowest[5].parse().unwrap();
    assert!(start.abs_diff(300_000) <= 50_000, "{lowest:?}");
    assert!(lowest[3].parse::<f64>().unwrap() < -1.5, "{lowest:?}");
}

/// Replicates of one map compared: no compartment switch, a warning that no track orients E1.
#[test]
fn diff_compartments_of_replicates_of_one_map_switch_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let maps = replicates_changed(dir.path(), None, true);
    let prefix = dir.path().join("c").display().to_string();
    run_ok(&[
        "diff",
        "compartments",
        "--a",
        &maps[0],
        &maps[1],
        "--b",
        &maps[2],
        &maps[3],
        "-o",
        &prefix,
    ]);
    let table = rows(&format!("{prefix}.compartments.tsv"));
    assert_eq!(table.len() - 1, 200);
    let switch = table[0].iter().position(|h| h == "switch").unwrap();
    assert!(table[1..].iter().all(|r| r[switch] == "-"));
    assert_eq!(
        rows(&format!("{prefix}.switches.bed")).len(),
        1,
        "a header, no segment"
    );
}

/// `plot diff` draws the calls of a `diff loops` table (MA and volcano) and of a boundaries
/// table; `plot map --loops` colours a diff loops table by direction; another table is refused.
#[test]
fn plot_diff_and_plot_map_draw_the_calls() {
    let dir = tempfile::tempdir().unwrap();
    let maps = replicates(dir.path(), true);
    let prefix = dir.path().join("planted").display().to_string();
    let table = diff_loops(&maps, &prefix, &[]);
    let direction = table[0].iter().position(|h| h == "direction").unwrap();
    let n_up = table[1..].iter().filter(|r| r[direction] == "up").count();
    assert_eq!(n_up, 1);
    let loops = format!("{prefix}.loops.bedpe");
    let svg = dir.path().join("ma.svg").display().to_string();
    run_ok(&["plot", "diff", &loops, "-o", &svg]);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("up in B (1)"), "the legend counts the calls");
    assert!(text.contains("not changed (7)"));
    assert!(text.contains("baseMean") || text.contains("mean of normalised counts"));
    let png = dir.path().join("volcano.png").display().to_string();
    run_ok(&["plot", "diff", &loops, "--volcano", "-o", &png]);
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));

    let map = dir.path().join("map.svg").display().to_string();
    run_ok(&[
        "plot",
        "map",
        &maps[0],
        "-r",
        "chr1:0-500000",
        "--raw",
        "--compare",
        &maps[2],
        "--loops",
        &loops,
        "-o",
        &map,
    ]);
    let text = std::fs::read_to_string(&map).unwrap();
    assert!(text.contains("#d62728"), "the loop up in B in red");
    assert!(text.contains("#969696"), "the others in grey");

    let other = write(
        dir.path(),
        "other.tsv",
        "chrom\tstart\tend\tvalue\nchr1\t0\t5000\t1\n",
    );
    let message = run_err(&["plot", "diff", &other, "-o", &png]);
    assert!(
        message.contains("not a table of contactmap diff"),
        "{message}"
    );
}

/// Bins outside 4-28 kb have no recommended kernels: without --loops, --w / --p are needed (the
/// error says so), and with them the dots are called and tested.
#[test]
fn diff_loops_takes_the_kernels_for_other_bin_sizes() {
    let dir = tempfile::tempdir().unwrap();
    let map = format!("{}::/resolutions/100000", data("cooler_test_file.mcool"));
    let prefix = dir.path().join("k").display().to_string();
    let message = run_err(&[
        "diff", "loops", "--a", &map, &map, "--b", &map, &map, "-o", &prefix,
    ]);
    assert!(
        message.contains("4-28 kb") && message.contains("--loops"),
        "{message}"
    );
    run_ok(&[
        "diff", "loops", "--a", &map, &map, "--b", &map, &map, "--w", "3", "--p", "1", "-o",
        &prefix,
    ]);
    let table = rows(&format!("{prefix}.loops.bedpe"));
    let direction = table[0].iter().position(|h| h == "direction").unwrap();
    assert!(table.len() > 1, "dots were called");
    assert!(
        table[1..].iter().all(|r| r[direction] == "-"),
        "one map against itself"
    );
}
