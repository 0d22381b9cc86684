//! `contactmap dots`: cooltools 0.7.1's dot caller on the yeast 10 kb map
//! (data/reference/dots, scripts/dots_reference.py), and the refusals of bad inputs.

use super::*;

/// Same rows and columns; numbers to 1e-9 relative.
fn assert_close_tables(ours: &Table, reference: &Table) {
    assert_eq!(ours.header, reference.header);
    assert_eq!(ours.rows.len(), reference.rows.len());
    for (a, b) in ours.rows.iter().zip(&reference.rows) {
        for (c, (x, y)) in a.iter().zip(b).enumerate() {
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(u), Ok(v)) => assert!(
                    u == v || (u - v).abs() <= 1e-9 * u.abs().max(v.abs()),
                    "{}: {x} vs {y}",
                    ours.header[c]
                ),
                _ => assert_eq!(x, y, "{}", ours.header[c]),
            }
        }
    }
}

/// `contactmap dots` on `cool` against cooltools' tables `reference/dots/{prefix}.*.tsv.gz`:
/// the dots, the enriched pixels written by --enriched, and by --no-cluster.
fn assert_dots_equal_cooltools(cool: &str, prefix: &str) {
    let dir = tempfile::tempdir().unwrap();
    let enriched = dir.path().join("enriched.tsv");
    let dots = run_ok(&[
        "dots",
        &data(cool),
        "--enriched",
        &enriched.to_string_lossy(),
    ]);
    assert_close_tables(
        &parse_table(&dots),
        &reference_table(&format!("reference/dots/{prefix}.dots.tsv.gz")),
    );
    let enriched = std::fs::read_to_string(&enriched).unwrap();
    let reference = reference_table(&format!("reference/dots/{prefix}.enriched.tsv.gz"));
    assert_close_tables(&parse_table(&enriched), &reference);
    // --no-cluster: the enriched pixels on the output
    let no_cluster = run_ok(&["dots", &data(cool), "--no-cluster"]);
    assert_close_tables(&parse_table(&no_cluster), &reference);
    assert_eq!(reference.header.len(), 15);
}

#[test]
fn dots_equal_cooltools_on_yeast() {
    assert_dots_equal_cooltools("yeast.10kb.cool", "yeast_10kb");
}

/// A simulated extrusion map at 5 kb (w=7, p=4): loops, nested loops and stripes.
#[test]
fn dots_equal_cooltools_on_a_simulated_extrusion_map() {
    assert_dots_equal_cooltools("sim_extrusion.5kb.cool", "sim_extrusion_5kb");
    // and they are the loops the simulation held
    let dots = run_ok(&["dots", &data("sim_extrusion.5kb.cool")]);
    let dir = tempfile::tempdir().unwrap();
    let calls = write(dir.path(), "dots.bedpe", &dots);
    let truth = data("sim_extrusion.truth_loops.bedpe");
    let score = run_ok(&[
        "score",
        "loops",
        "--truth",
        &truth,
        &calls,
        "--min-fraction",
        "0.2",
    ]);
    let all: Vec<&str> = score.lines().last().unwrap().split('\t').collect();
    assert_eq!((all[0], all[3], all[6]), ("all", "5", "5"), "{score}");
}

#[test]
fn dots_refuse_bad_inputs_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("dots.tsv");
    let out_s = out.to_string_lossy().into_owned();
    // an unbalanced map
    let line = run_err(&[
        "dots",
        &data("hg19.GM12878-MboI.matrix.2000kb.cool"),
        "-o",
        &out_s,
    ]);
    assert!(line.contains("weight"), "{line}");
    // a bin size cooltools has no kernels for (10 Mb)
    let line = run_err(&["dots", &data("CN.mm9.10000kb.cool"), "-o", &out_s]);
    assert!(line.contains("--w and --p"), "{line}");
    // an expected of another resolution (its dist_bp are for 20 kb bins)
    let expected = run_ok(&["expected", &data("yeast.10kb.cool")]);
    let mut table = parse_table(&expected);
    let dist_bp = table.header.iter().position(|h| h == "dist_bp").unwrap();
    let mut text = table.header.join("\t") + "\n";
    for row in &mut table.rows {
        row[dist_bp] = (row[dist_bp].parse::<u64>().unwrap() * 2).to_string();
        text.push_str(&(row.join("\t") + "\n"));
    }
    let other = dir.path().join("exp20kb.tsv");
    std::fs::write(&other, text).unwrap();
    let line = run_err(&[
        "dots",
        &data("yeast.10kb.cool"),
        "--expected",
        &other.to_string_lossy(),
        "-o",
        &out_s,
    ]);
    assert!(line.contains("another resolution"), "{line}");
    // an expected without the view's regions
    let view = dir.path().join("arms.bed");
    std::fs::write(
        &view,
        "chrI\t0\t100000\tleft\nchrI\t100000\t230218\tright\n",
    )
    .unwrap();
    let line = run_err(&[
        "dots",
        &data("yeast.10kb.cool"),
        "--view",
        &view.to_string_lossy(),
        "--expected",
        &data("reference/numerics/dm6_100kb.expected_cis.raw.tsv.gz"),
        "--expected-column",
        "count.avg",
        "-o",
        &out_s,
    ]);
    assert!(line.contains("region 'left'"), "{line}");
    // a view outside its chromosome
    std::fs::write(&view, "chrI\t0\t900000000\n").unwrap();
    let line = run_err(&[
        "dots",
        &data("yeast.10kb.cool"),
        "--view",
        &view.to_string_lossy(),
        "-o",
        &out_s,
    ]);
    assert!(line.contains("arms.bed"), "{line}");
    // --w without --p, a bad FDR
    run_err(&["dots", &data("yeast.10kb.cool"), "--w", "5", "-o", &out_s]);
    let line = run_err(&["dots", &data("yeast.10kb.cool"), "--fdr", "2", "-o", &out_s]);
    assert!(line.contains("--fdr 2"), "{line}");
    assert!(!out.exists(), "no output after an error");
}

/// A view of whole chromosomes under other names: the same dots, named by the view.
#[test]
fn dots_on_a_named_view_name_their_regions() {
    let dir = tempfile::tempdir().unwrap();
    let chroms = run_ok(&["dump", "-t", "chroms", &data("yeast.10kb.cool")]);
    let bed: String = chroms
        .lines()
        .map(|l| {
            let (name, length) = l.split_once('\t').unwrap();
            format!("{name}\t0\t{length}\tv_{name}\n")
        })
        .collect();
    let view = dir.path().join("view.bed");
    std::fs::write(&view, bed).unwrap();
    let dots = parse_table(&run_ok(&[
        "dots",
        &data("yeast.10kb.cool"),
        "--view",
        &view.to_string_lossy(),
    ]));
    let mut reference = reference_table("reference/dots/yeast_10kb.dots.tsv.gz");
    for column in ["region", "region1", "region2"] {
        let c = reference.header.iter().position(|h| h == column).unwrap();
        for row in &mut reference.rows {
            row[c] = format!("v_{}", row[c]);
        }
    }
    assert_close_tables(&dots, &reference);
}

/// Nothing enriched (an FDR no pixel can meet): the header alone, in the column order of
/// cooltools' empty result.
#[test]
fn no_enriched_pixel_gives_cooltools_empty_table() {
    let out = run_ok(&["dots", &data("yeast.10kb.cool"), "--fdr", "1e-300"]);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 1, "{out}");
    assert!(
        lines[0].ends_with(
            "la_exp.lowleft.qval\tregion\tregion1\tregion2\tc_label\tc_size\tcstart1\tcstart2"
        ),
        "{out}"
    );
}

/// `dots-merge` on hand-made lists, each rule of HiCCUPS' merge worked out by hand; bad inputs.
#[test]
fn dots_merge_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    let head = "chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tcount\tnote\n";
    let list = |name: &str, width: u64, rows: &[(u64, u64, u32, &str)]| {
        let mut text = head.to_string();
        for &(s1, s2, count, note) in rows {
            text.push_str(&format!(
                "chr1\t{s1}\t{}\tchr1\t{s2}\t{}\t{count}\t{note}\n",
                s1 + width,
                s2 + width
            ));
        }
        write(dir.path(), name, &text)
    };
    let five = list(
        "d5.bedpe",
        5_000,
        &[
            (1_000_000, 1_500_000, 40, "confirmed"), // a 10 kb call 20 kb away
            (2_000_000, 2_600_000, 30, "unconfirmed"), // nothing near: dropped
            (3_000_000, 3_105_000, 20, "near-diagonal"),
            (4_000_000, 4_800_000, 101, "strong"),
            (5_000_000, 5_900_000, 100, "not-strong"), // 100 is not above 100
        ],
    );
    let ten = list(
        "d10.bedpe",
        10_000,
        &[
            (1_020_000, 1_500_000, 50, "at-5kb"), // confirms the first 5 kb call: dropped
            (6_000_000, 6_500_000, 60, "only-10kb"),
        ],
    );
    let coarse = list(
        "d25.bedpe",
        25_000,
        &[
            (6_050_000, 6_500_000, 70, "near-kept"), // 50 kb from a kept call: dropped
            (8_000_000, 8_500_000, 80, "only-25kb"),
        ],
    );
    let out = run_ok(&["dots-merge", &five, &format!("{ten}@10k"), &coarse]);
    let table = parse_table(&out);
    assert_eq!(table.header.last().unwrap(), "resolution");
    let got: Vec<String> = table
        .rows
        .iter()
        .map(|r| format!("{} {}", r[7], r[8]))
        .collect();
    assert_eq!(
        got,
        [
            "confirmed 5000",
            "near-diagonal 5000",
            "strong 5000",
            "only-10kb 10000",
            "only-25kb 25000"
        ]
    );
    // only 5 and 25 kb: all 5 kb calls, the 25 kb ones far from them
    let out = run_ok(&["dots-merge", &five, &coarse, "--strong", "1000"]);
    assert_eq!(parse_table(&out).rows.len(), 7);
    // bad inputs: one error line each, exit 2, no output written
    let out_path = dir.path().join("merged.bedpe");
    let out_s = out_path.to_string_lossy().into_owned();
    let line = run_err(&["dots-merge", &format!("{five}@20k"), &ten, "-o", &out_s]);
    assert!(line.contains("20000 bp"), "{line}");
    let line = run_err(&["dots-merge", &five, &format!("{five}@5000"), "-o", &out_s]);
    assert!(
        line.contains("are both at 5000 bp: give one list per resolution"),
        "{line}"
    );
    let bare = write(
        dir.path(),
        "bare.bedpe",
        "chr1\t0\t5000\tchr1\t50000\t55000\n",
    );
    let line = run_err(&["dots-merge", &bare, "-o", &out_s]);
    assert!(
        line.contains("bare.bedpe") && line.contains("count"),
        "{line}"
    );
    let bad = write(
        dir.path(),
        "bad.bedpe",
        &format!("{head}chr1\t0\t5000\tchr1\t50000\t55000\tmany\tx\n"),
    );
    let line = run_err(&["dots-merge", &bad, "-o", &out_s]);
    assert!(
        line.contains("bad.bedpe:2") && line.contains("many"),
        "{line}"
    );
    let empty = write(dir.path(), "empty.bedpe", head);
    let line = run_err(&["dots-merge", &empty, "-o", &out_s]);
    assert!(line.contains("@RESOLUTION"), "{line}");
    let other = write(
        dir.path(),
        "other.bedpe",
        "chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tcount\n\
         chr1\t0\t10000\tchr1\t50000\t60000\t3\n",
    );
    let line = run_err(&["dots-merge", &five, &other, "-o", &out_s]);
    assert!(line.contains("different columns"), "{line}");
    assert!(!out_path.exists(), "no output after an error");
}

/// `dots --resolutions` on a simulated extrusion map at 5, 10 and 25 kb (zoomified): the same
/// table as dots at each level merged by `dots-merge`, and the loops the simulation held in at
/// least 20% of its samples all found.
#[test]
fn dots_at_three_resolutions_find_simulated_loops() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let (cool, mcool, truth) = (path("s.cool"), path("s.mcool"), path("truth.bedpe"));
    run_ok(&[
        "simulate",
        "polymer",
        "-o",
        &cool,
        "--chains",
        "200",
        "--monomer-bp",
        "5000",
        "--density",
        "0.2",
        "--extrusion",
        "--ctcf",
        "20+,50-,54+,84-,88+,118-,122+,152-,156+,186-",
        "--capture",
        "1",
        "--release",
        "0",
        "--processivity",
        "300",
        "--separation",
        "30",
        "--replicas",
        "16",
        "--equilibration",
        "10000",
        "--sample-every",
        "1000",
        "--samples",
        "8",
        "--seed",
        "3",
        "--truth-loops",
        &truth,
    ]);
    run_ok(&[
        "zoomify",
        &cool,
        "-o",
        &mcool,
        "-r",
        "5000,10000,25000",
        "--balance",
    ]);
    let merged = run_ok(&["dots", &mcool, "--resolutions", "5k,10k,25k"]);
    let mut lists = Vec::new();
    for res in ["5000", "10000", "25000"] {
        let out = path(&format!("d{res}.bedpe"));
        run_ok(&["dots", &format!("{mcool}::/resolutions/{res}"), "-o", &out]);
        lists.push(format!("{out}@{res}"));
    }
    let list_args: Vec<&str> = lists.iter().map(String::as_str).collect();
    let by_merge = run_ok(&[&["dots-merge"][..], &list_args].concat());
    assert_eq!(merged, by_merge);
    let merged_path = path("merged.bedpe");
    std::fs::write(&merged_path, &merged).unwrap();
    let score = run_ok(&[
        "score",
        "loops",
        "--truth",
        &truth,
        &merged_path,
        "--min-fraction",
        "0.2",
    ]);
    let all: Vec<&str> = score.lines().last().unwrap().split('\t').collect();
    assert_eq!(all[0], "all");
    assert!(all[3].parse::<u32>().unwrap() >= 4, "{score}");
    assert_eq!(all[3], all[6], "every held loop found: {score}");
    // --resolutions refuses a level in the URI and options that fix one level's kernel
    run_err(&[
        "dots",
        &format!("{mcool}::/resolutions/5000"),
        "--resolutions",
        "5k",
    ]);
    let line = run_err(&[
        "dots",
        &mcool,
        "--resolutions",
        "5k,10k",
        "--w",
        "3",
        "--p",
        "1",
    ]);
    assert!(line.contains("--w"), "{line}");
    let line = run_err(&[
        "dots",
        &mcool,
        "--resolutions",
        "5k,10k",
        "--resolution",
        "5000",
    ]);
    assert!(line.contains("leave out --resolution"), "{line}");
}
