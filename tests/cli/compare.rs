//! Comparing samples: `hicrep` against hicrep 0.2.6, `sample` (exact totals, seeds, binomial
//! thinning), `coverage` and `virtual4c` against cooltools 0.7.1
//! (`data/reference/compare/`, made by `scripts/compare_references.py`); bad input refused.

use std::collections::HashMap;
use std::io::Read;

use super::*;

/// The gzipped text of `data/reference/compare/NAME`.
fn reference_text(name: &str) -> String {
    let mut text = String::new();
    flate2::read::MultiGzDecoder::new(
        std::fs::File::open(data(&format!("reference/compare/{name}"))).expect("reference file"),
    )
    .read_to_string(&mut text)
    .expect("gzip text");
    text
}

/// A number as the tables write it (`nan` included).
fn number(text: &str) -> f64 {
    if text == "nan" {
        f64::NAN
    } else {
        text.parse()
            .unwrap_or_else(|_| panic!("not a number: {text}"))
    }
}

/// The map's total contacts, from `contactmap info --json`.
fn total_contacts(uri: &str) -> f64 {
    let info: serde_json::Value = serde_json::from_str(&run_ok(&["info", uri, "--json"])).unwrap();
    info["sum"].as_f64().expect("a sum")
}

/// `contactmap sample` of `uri` with `args` into `dir`; the output's path.
fn sampled(dir: &std::path::Path, uri: &str, args: &[&str], name: &str) -> String {
    let out = dir
        .join(format!("{name}.cool"))
        .to_string_lossy()
        .into_owned();
    let mut all = vec!["sample", uri];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", &out]);
    run_ok(&all);
    out
}

#[test]
fn hicrep_scc_equals_hicrep_on_real_maps_and_thinned_copies() {
    let dir = tempfile::tempdir().unwrap();
    let chroms = run_ok(&[
        "dump",
        "-t",
        "chroms",
        &data("hg19.GM12878-MboI.matrix.2000kb.cool"),
    ]);
    let sizes = write(dir.path(), "hg19.sizes", &chroms);
    let pairs = data("hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz");
    let dm6 = data("cooler_test_file.mcool::/resolutions/100000");
    // The second map of each case, as scripts/compare_references.py made it.
    let cases: HashMap<&str, (String, String)> = [
        (
            "gm12878",
            (data("hg19.GM12878-MboI.matrix.2000kb.cool"), pairs),
        ),
        (
            "yeast",
            (
                data("yeast.10kb.cool"),
                sampled(
                    dir.path(),
                    &data("yeast.10kb.cool"),
                    &["--fraction", "0.3", "--seed", "30"],
                    "yeast",
                ),
            ),
        ),
        (
            "mm9",
            (
                data("CN.mm9.10000kb.cool"),
                sampled(
                    dir.path(),
                    &data("CN.mm9.10000kb.cool"),
                    &["--fraction", "0.05", "--seed", "31"],
                    "mm9",
                ),
            ),
        ),
        (
            "dm6",
            (
                dm6.clone(),
                sampled(
                    dir.path(),
                    &dm6,
                    &["--count", "10000000", "--seed", "32"],
                    "dm6",
                ),
            ),
        ),
        (
            "sim",
            (
                data("sim_extrusion.5kb.cool"),
                sampled(
                    dir.path(),
                    &data("sim_extrusion.5kb.cool"),
                    &["--fraction", "0.5", "--seed", "33"],
                    "sim",
                ),
            ),
        ),
    ]
    .into_iter()
    .collect();
    let reference = parse_table(&reference_text("scc.tsv.gz"));
    // (case, h, max distance) -> (chrom, hicrep's SCC) in order
    type Run = ((String, String, String), Vec<(String, String)>);
    let mut runs: Vec<Run> = Vec::new();
    for row in &reference.rows {
        let key = (row[0].clone(), row[1].clone(), row[2].clone());
        match runs.last_mut() {
            Some((k, rows)) if *k == key => rows.push((row[3].clone(), row[4].clone())),
            _ => runs.push((key, vec![(row[3].clone(), row[4].clone())])),
        }
    }
    assert_eq!(runs.len(), 17);
    let mut worst = 0.0f64;
    for ((case, h, max_distance), want) in &runs {
        let (a, b) = &cases[case.as_str()];
        let max = if max_distance == "-1" {
            "all"
        } else {
            max_distance.as_str()
        };
        let mut args = vec![
            "hicrep",
            a.as_str(),
            b.as_str(),
            "--h",
            h,
            "--max-distance",
            max,
        ];
        if case == "gm12878" {
            args.extend_from_slice(&[
                "--format",
                "pairs",
                "--pairs-columns",
                "1,2,4,5",
                "--bin-size",
                "2000000",
                "--chrom-sizes",
                &sizes,
            ]);
        }
        let table = parse_table(&run_ok(&args));
        let ours: HashMap<&str, f64> = table
            .rows
            .iter()
            .filter(|r| r[2] != "genome")
            .map(|r| (r[2].as_str(), number(&r[4])))
            .collect();
        for (chrom, value) in want {
            let got = ours[chrom.as_str()];
            if value == "assert" || value == "nan" {
                // hicrep stops on an empty chromosome, or gives NaN: ours is NaN.
                assert!(got.is_nan(), "{case} h {h} {max_distance} {chrom}: {got}");
                continue;
            }
            let want = number(value);
            worst = worst.max((got - want).abs());
            assert!(
                (got - want).abs() <= 1e-9,
                "{case} h {h} max {max_distance} {chrom}: {got} vs hicrep {want}"
            );
        }
    }
    assert!(worst < 1e-9, "{worst}");
}

#[test]
fn genome_wide_scc_is_the_length_weighted_mean_and_json_agrees() {
    let yeast = data("yeast.10kb.cool");
    let dir = tempfile::tempdir().unwrap();
    let thin = sampled(
        dir.path(),
        &yeast,
        &["--fraction", "0.5", "--seed", "1"],
        "thin",
    );
    let table = parse_table(&run_ok(&[
        "hicrep",
        &yeast,
        &thin,
        "--h",
        "2",
        "--max-distance",
        "500k",
    ]));
    assert_eq!(
        table.header,
        ["sample1", "sample2", "chrom", "length", "scc"]
    );
    let (mut num, mut den) = (0.0, 0.0);
    for row in table.rows.iter().filter(|r| r[2] != "genome") {
        let (length, scc) = (number(&row[3]), number(&row[4]));
        if scc.is_nan() {
            // chr2-micron: one bin, no diagonal to compare; left out of the mean
            continue;
        }
        assert!(scc > 0.5 && scc <= 1.0, "{row:?}");
        num += length * scc;
        den += length;
    }
    let genome = table.rows.last().unwrap();
    assert_eq!(genome[2], "genome");
    assert!((number(&genome[4]) - num / den).abs() < 1e-12);
    let json: serde_json::Value = serde_json::from_str(&run_ok(&[
        "hicrep",
        &yeast,
        &thin,
        "--h",
        "2",
        "--max-distance",
        "500k",
        "--json",
    ]))
    .unwrap();
    let wide = json["pairs"][0]["genome_wide"].as_f64().unwrap();
    assert!((wide - num / den).abs() < 1e-12);
    assert_eq!(json["h"], 2);
}

#[test]
fn trained_h_is_chosen_once_for_every_pair() {
    // Three samples: h trained on the first two, used for the three pairs.
    let mm9 = data("CN.mm9.10000kb.cool");
    let dir = tempfile::tempdir().unwrap();
    let a = sampled(
        dir.path(),
        &mm9,
        &["--fraction", "0.02", "--seed", "1"],
        "a",
    );
    let b = sampled(
        dir.path(),
        &mm9,
        &["--fraction", "0.02", "--seed", "2"],
        "b",
    );
    let out = run(&[
        "hicrep",
        &mm9,
        &a,
        &b,
        "--max-distance",
        "100M",
        "--h-max",
        "4",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("chosen by training"), "{stderr}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let training = &json["training"];
    let tried: Vec<f64> = training["tried"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["scc"].as_f64().unwrap())
        .collect();
    // hicreppy's rule: stop at the first gain under 0.01, keep the h before it.
    let stop = tried
        .windows(2)
        .position(|w| w[1] - w[0] < 0.01)
        .map(|k| k + 1);
    let want = stop.unwrap_or(3).saturating_sub(1);
    assert_eq!(training["h"].as_u64().unwrap() as usize, want, "{tried:?}");
    assert_eq!(json["h"], training["h"]);
    assert_eq!(json["pairs"].as_array().unwrap().len(), 3);
    // issue 51: a search that ends on the range's last h without levelling off says so
    assert_eq!(training["levelled_off"], serde_json::json!(stop.is_some()));
    assert_eq!(
        stderr.contains("never levelled off"),
        stop.is_none(),
        "{tried:?}: {stderr}"
    );
    // --h-max 2 on maps 2% deep: h = 1 still gains (the SCC of such thin maps rises with h)
    let out = run(&[
        "hicrep",
        &mm9,
        &a,
        "--max-distance",
        "100M",
        "--h-max",
        "2",
        "--json",
    ]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let tried = &json["training"]["tried"];
    let gain = tried[1]["scc"].as_f64().unwrap() - tried[0]["scc"].as_f64().unwrap();
    assert!(gain >= 0.01, "{tried}");
    assert_eq!(json["training"]["levelled_off"], false);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("warning: the training's SCC never levelled off")
            && stderr.contains("--h-max"),
        "{stderr}"
    );
}

/// Issue 51: the genome-wide SCC of a one-chromosome comparison is that chromosome's SCC, to
/// the last digit.
#[test]
fn genome_wide_scc_of_one_chromosome_is_its_scc() {
    let yeast = data("yeast.10kb.cool");
    let dir = tempfile::tempdir().unwrap();
    let thin = sampled(
        dir.path(),
        &yeast,
        &["--fraction", "0.5", "--seed", "3"],
        "thin",
    );
    for chrom in ["chrIV", "chrXII", "chrI"] {
        let table = parse_table(&run_ok(&[
            "hicrep", &yeast, &thin, "--h", "1", "--chroms", chrom,
        ]));
        assert_eq!(table.rows.len(), 2, "{chrom}");
        assert_eq!(table.rows[1][2], "genome");
        assert_eq!(table.rows[0][4], table.rows[1][4], "{chrom}");
    }
}

#[test]
fn samples_have_exact_totals_and_the_same_pixels_for_a_seed() {
    let yeast = data("yeast.10kb.cool");
    let dir = tempfile::tempdir().unwrap();
    let a = sampled(
        dir.path(),
        &yeast,
        &["--count", "100000", "--seed", "7"],
        "a",
    );
    let b = sampled(
        dir.path(),
        &yeast,
        &["--count", "100000", "--seed", "7"],
        "b",
    );
    let c = sampled(
        dir.path(),
        &yeast,
        &["--count", "100000", "--seed", "8"],
        "c",
    );
    assert_eq!(total_contacts(&a), 100000.0);
    run_ok(&["validate", &a]);
    assert_eq!(run_ok(&["dump", &a]), run_ok(&["dump", &b]));
    assert_ne!(run_ok(&["dump", &a]), run_ok(&["dump", &c]));
    // One thread or several: the same sample.
    let out = dir.path().join("one.cool").to_string_lossy().into_owned();
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_contactmap"))
        .args([
            "sample", &yeast, "--count", "100000", "--seed", "7", "-o", &out,
        ])
        .env("RAYON_NUM_THREADS", "1")
        .status()
        .unwrap();
    assert!(status.success());
    assert_eq!(run_ok(&["dump", &out]), run_ok(&["dump", &a]));
    // --fraction --exact: round(F x total).
    let q = sampled(dir.path(), &yeast, &["--fraction", "0.25", "--exact"], "q");
    let want = (0.25 * total_contacts(&yeast)).round_ties_even();
    assert_eq!(total_contacts(&q), want);
}

#[test]
fn thinning_a_real_map_draws_binomial_counts_per_pixel() {
    // Pixels of the yeast map with 20 contacts, thinned to 40%: their kept counts follow
    // Binomial(20, 0.4) (Pearson's chi-square, classes with 5 expected or more).
    let yeast = data("yeast.10kb.cool");
    let dir = tempfile::tempdir().unwrap();
    let thin = sampled(
        dir.path(),
        &yeast,
        &["--fraction", "0.4", "--seed", "3"],
        "thin",
    );
    let pixels = |uri: &str| -> HashMap<(String, String), f64> {
        run_ok(&["dump", uri])
            .lines()
            .map(|l| {
                let f: Vec<&str> = l.split('\t').collect();
                ((f[0].to_string(), f[1].to_string()), f[2].parse().unwrap())
            })
            .collect()
    };
    let (before, after) = (pixels(&yeast), pixels(&thin));
    let n = 20u64;
    let mut observed = vec![0u64; n as usize + 1];
    for (key, &count) in &before {
        if count == n as f64 {
            let kept = after.get(key).copied().unwrap_or(0.0);
            observed[kept as usize] += 1;
        }
    }
    let total: u64 = observed.iter().sum();
    assert!(total > 1000, "{total} pixels of {n}");
    let p = 0.4f64;
    let mut pmf = vec![(1.0 - p).powi(n as i32)];
    for k in 1..=n {
        pmf.push(pmf[k as usize - 1] * (n - k + 1) as f64 / k as f64 * p / (1.0 - p));
    }
    let (mut statistic, mut classes) = (0.0, 0);
    let (mut pooled_e, mut pooled_o) = (0.0, 0.0);
    for k in 0..=n as usize {
        let e = pmf[k] * total as f64;
        if e >= 5.0 {
            statistic += (observed[k] as f64 - e).powi(2) / e;
            classes += 1;
        } else {
            pooled_e += e;
            pooled_o += observed[k] as f64;
        }
    }
    statistic += (pooled_o - pooled_e).powi(2) / pooled_e;
    classes += 1;
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    let p_value = 1.0
        - ChiSquared::new((classes - 1) as f64)
            .unwrap()
            .cdf(statistic);
    assert!(
        p_value > 1e-3,
        "chi-square {statistic} on {classes} classes: p {p_value}; {observed:?}"
    );
}

/// The sections of `cooltools.tsv.gz`: name -> table.
fn cooltools_references() -> HashMap<String, Table> {
    reference_text("cooltools.tsv.gz")
        .split("## ")
        .filter(|s| !s.is_empty())
        .map(|s| {
            let (name, table) = s.split_once('\n').unwrap();
            (name.to_string(), parse_table(table))
        })
        .collect()
}

/// Our table's rows of chr1..chr4 against cooltools' (bins with two rows in cooltools'
/// virtual4c: ours equals one of them).
fn assert_table_matches(ours: &str, reference: &Table, name: &str) {
    let ours = parse_table(ours);
    assert_eq!(ours.header, reference.header, "{name}");
    let mut want: HashMap<(String, String), Vec<Vec<f64>>> = HashMap::new();
    for row in &reference.rows {
        want.entry((row[0].clone(), row[1].clone()))
            .or_default()
            .push(row[3..].iter().map(|v| number(v)).collect());
    }
    let mut compared = 0;
    for row in ours
        .rows
        .iter()
        .filter(|r| ["chr1", "chr2", "chr3", "chr4"].contains(&r[0].as_str()))
    {
        let values: Vec<f64> = row[3..].iter().map(|v| number(v)).collect();
        let candidates = &want[&(row[0].clone(), row[1].clone())];
        let close = |a: &f64, b: &f64| {
            (a.is_nan() && b.is_nan()) || (a - b).abs() <= 1e-12 * b.abs().max(1e-300)
        };
        assert!(
            candidates
                .iter()
                .any(|c| c.iter().zip(&values).all(|(a, b)| close(b, a))),
            "{name} {row:?} vs cooltools {candidates:?}"
        );
        compared += 1;
    }
    assert_eq!(compared, want.len(), "{name}");
}

#[test]
fn coverage_and_virtual4c_equal_cooltools() {
    let mm9 = data("CN.mm9.10000kb.cool");
    let refs = cooltools_references();
    for (name, args) in [
        ("coverage_mm9_raw", vec!["coverage", &mm9]),
        (
            "coverage_mm9_weight",
            vec!["coverage", &mm9, "--weight-name", "weight"],
        ),
        (
            "coverage_mm9_raw0",
            vec!["coverage", &mm9, "--ignore-diags", "0"],
        ),
        (
            "v4c_mm9_weight",
            vec!["virtual4c", &mm9, "--viewpoint", "chr1:50000000-60000000"],
        ),
        (
            "v4c_mm9_raw",
            vec!["virtual4c", &mm9, "--viewpoint", "chr2:35M-55M", "--raw"],
        ),
        (
            "v4c_mm9_partial",
            vec![
                "virtual4c",
                &mm9,
                "--viewpoint",
                "chr3:55,000,000-72,000,000",
            ],
        ),
    ] {
        assert_table_matches(&run_ok(&args), &refs[name], name);
    }
    // The raw coverage sums to twice the contacts off the ignored diagonals.
    let table = parse_table(&run_ok(&["coverage", &mm9, "--ignore-diags", "0"]));
    let total: f64 = table.rows.iter().map(|r| number(&r[4])).sum();
    let sum = total_contacts(&mm9);
    let diagonal: f64 = run_ok(&["dump", &mm9])
        .lines()
        .map(|l| l.split('\t').collect::<Vec<_>>())
        .filter(|f| f[0] == f[1])
        .map(|f| f[2].parse::<f64>().unwrap())
        .sum();
    // a diagonal pixel counts twice for its bin, like any pixel
    assert_eq!(total, 2.0 * sum);
    assert!(diagonal > 0.0);
}

#[test]
fn coverage_is_stored_in_the_cooler_as_cooltools_stores_it() {
    let dir = tempfile::tempdir().unwrap();
    let copy = dir.path().join("mm9.cool").to_string_lossy().into_owned();
    std::fs::copy(data("CN.mm9.10000kb.cool"), &copy).unwrap();
    let refs = cooltools_references();
    // the printed table is unchanged by --store; storing twice replaces the columns
    for _ in 0..2 {
        let table = run_ok(&["coverage", &copy, "--store", "--weight-name", "weight"]);
        assert_table_matches(&table, &refs["coverage_mm9_weight"], "stored");
        run_ok(&["coverage", &copy, "--store"]);
    }
    // the balanced columns read back (float columns are listed with the weights)
    let bins = parse_table(&run_ok(&[
        "dump",
        "-t",
        "bins",
        &copy,
        "-H",
        "--float-format",
        ".17g",
        "--na-rep",
        "nan",
    ]));
    assert_eq!(
        bins.header,
        [
            "chrom",
            "start",
            "end",
            "cov_cis_weight",
            "cov_tot_weight",
            "weight"
        ]
    );
    let reference = &refs["coverage_mm9_weight"];
    let mut compared = 0;
    for (ours, want) in bins.rows.iter().zip(&reference.rows) {
        assert_eq!(ours[..3], want[..3]);
        for k in [3, 4] {
            let (a, b) = (number(&ours[k]), number(&want[k]));
            assert!(
                (a.is_nan() && b.is_nan()) || (a - b).abs() <= 1e-12 * b.abs(),
                "{ours:?} vs {want:?}"
            );
        }
        compared += 1;
    }
    // (the reference holds chr1 to chr4)
    assert!(
        compared == reference.rows.len() && compared > 50,
        "{compared} rows"
    );
    // --store writes into coolers only
    let text = dir.path().join("m.bg2").to_string_lossy().into_owned();
    std::fs::write(&text, "chr1\t0\t10\tchr1\t0\t10\t1\n").unwrap();
    let line = run_err(&["coverage", &text, "--store", "--ignore-diags", "0"]);
    assert!(line.contains("--store writes into .cool"), "{line}");
}

#[test]
fn bad_comparison_inputs_are_refused_in_one_line_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let yeast = data("yeast.10kb.cool");
    let mm9 = data("CN.mm9.10000kb.cool");
    let out = dir.path().join("out.tsv").to_string_lossy().into_owned();
    let cool = dir.path().join("s.cool").to_string_lossy().into_owned();
    let line = run_err(&["hicrep", &yeast, &mm9, "--h", "1", "-o", &out]);
    assert!(line.contains("bins differ"), "{line}");
    let dm6_1m = data("cooler_test_file.mcool::/resolutions/1000000");
    let dm6_100k = data("cooler_test_file.mcool::/resolutions/100000");
    let line = run_err(&["hicrep", &dm6_100k, &dm6_1m, "--h", "1"]);
    assert!(line.contains("bin size"), "{line}");
    for h in ["-1", "1.5", "two"] {
        let line = run_err(&["hicrep", &yeast, &yeast, "--h", h, "-o", &out]);
        assert!(line.contains("non-negative integer"), "{line}");
    }
    let line = run_err(&["hicrep", &yeast, &yeast, "--h", "1", "--max-distance", "5k"]);
    assert!(line.contains("at least one bin"), "{line}");
    let line = run_err(&["hicrep", &yeast, &yeast, "--h", "1", "--chroms", "chrZ"]);
    assert!(line.contains("chrZ"), "{line}");
    for f in ["0", "1.5", "-0.2"] {
        let line = run_err(&["sample", &yeast, "--fraction", f, "-o", &cool]);
        assert!(line.contains("(0, 1]"), "{line}");
    }
    let line = run_err(&["sample", &yeast, "--count", "999999999999", "-o", &cool]);
    assert!(line.contains("at most"), "{line}");
    let line = run_err(&["sample", &yeast, "--count", "10", "-o", &out]);
    assert!(line.contains(".cool"), "{line}");
    for viewpoint in ["chrZ:1-100", "chr1:300M-310M", "chr1:5M-1M"] {
        let line = run_err(&["virtual4c", &mm9, "--viewpoint", viewpoint, "-o", &out]);
        assert!(line.contains("--viewpoint"), "{line}");
    }
    let line = run_err(&[
        "coverage",
        &yeast,
        "--weight-name",
        "nope",
        "--ignore-diags",
        "2",
        "-o",
        &out,
    ]);
    assert!(line.contains("nope"), "{line}");
    let line = run_err(&["coverage", &yeast, "-o", &out]);
    assert!(line.contains("--ignore-diags"), "{line}");
    let hg19 = data("hg19.GM12878-MboI.matrix.2000kb.cool");
    let line = run_err(&["virtual4c", &hg19, "--viewpoint", "chr1:10M-12M"]);
    assert!(line.contains("balance"), "{line}");
    assert!(!std::path::Path::new(&out).exists());
    assert!(!std::path::Path::new(&cool).exists());
}
