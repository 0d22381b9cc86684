//! `contactmap simulate blocks`: a small map, its truth BEDs, reproducibility.

use std::path::Path;

use crate::{run, run_err, run_ok};

/// Simulate 2 chromosomes x 300 bins into `dir` with `seed`; return (cool, domains, boundaries).
fn simulate(dir: &Path, tag: &str, seed: &str, extra: &[&str]) -> (String, String, String) {
    let path = |name: &str| {
        dir.join(format!("{tag}.{name}"))
            .to_string_lossy()
            .into_owned()
    };
    let (cool, domains, boundaries) = (path("cool"), path("domains.bed"), path("bounds.bed"));
    let base = [
        "simulate",
        "blocks",
        "--chroms",
        "2",
        "--bins",
        "300",
        "--depth",
        "2e5",
        "--max-distance",
        "50",
        "--seed",
        seed,
        "-o",
        &cool,
        "--truth-domains",
        &domains,
        "--truth-boundaries",
        &boundaries,
    ];
    run_ok(&[&base[..], extra].concat());
    (cool, domains, boundaries)
}

fn bed_lines(path: &str) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| l.split('\t').map(str::to_string).collect())
        .collect()
}

#[test]
fn simulated_map_has_the_expected_shape_and_truth() {
    let dir = tempfile::tempdir().unwrap();
    let (cool, domains, boundaries) = simulate(dir.path(), "a", "1", &["--nested-fraction", "0.3"]);
    let info: serde_json::Value =
        serde_json::from_str(&run_ok(&["info", "--json", &cool])).unwrap();
    assert_eq!(info["nbins"], 600);
    assert_eq!(info["nchroms"], 2);
    let nnz = info["nnz"].as_u64().unwrap();
    // At most 51 diagonals per chromosome (300 + 299 + ... + 250 pixels each).
    assert!(nnz > 10_000 && nnz <= 2 * (51 * 300 - 50 * 51 / 2), "{nnz}");
    let sum = info["sum"].as_f64().unwrap();
    assert!((sum - 2e5).abs() < 5.0 * 2e5f64.sqrt(), "{sum}");

    let domains = bed_lines(&domains);
    let top: Vec<&Vec<String>> = domains.iter().filter(|f| f[3] == "0").collect();
    assert!(
        domains
            .iter()
            .all(|f| f.len() == 4 && (f[3] == "0" || f[3] == "1"))
    );
    assert!(domains.iter().any(|f| f[3] == "1"), "some nested domains");
    for chrom in ["chr1", "chr2"] {
        let spans: Vec<(u64, u64)> = top
            .iter()
            .filter(|f| f[0] == chrom)
            .map(|f| (f[1].parse().unwrap(), f[2].parse().unwrap()))
            .collect();
        assert_eq!(spans[0].0, 0);
        assert_eq!(spans.last().unwrap().1, 3_000_000);
        assert!(spans.windows(2).all(|w| w[0].1 == w[1].0));
    }
    // Boundaries: one 10 kb bin at each domain start (any level) except chromosome starts.
    let boundaries = bed_lines(&boundaries);
    let mut starts: Vec<(String, u64)> = domains
        .iter()
        .map(|f| (f[0].clone(), f[1].parse().unwrap()))
        .filter(|(_, s)| *s != 0)
        .collect();
    starts.sort();
    starts.dedup();
    let mut got: Vec<(String, u64)> = boundaries
        .iter()
        .map(|f| {
            let (s, e): (u64, u64) = (f[1].parse().unwrap(), f[2].parse().unwrap());
            assert_eq!(e - s, 10_000);
            (f[0].clone(), s)
        })
        .collect();
    got.sort();
    assert_eq!(got, starts);
    // Each boundary scores perfectly against itself.
    let bounds = dir.path().join("a.bounds.bed");
    let bounds = bounds.to_str().unwrap();
    let table = run_ok(&["score", "boundaries", "--truth", bounds, bounds]);
    assert!(
        table.lines().nth(1).unwrap().ends_with("\t1\t1\t1"),
        "{table}"
    );
}

#[test]
fn same_seed_same_files() {
    let dir = tempfile::tempdir().unwrap();
    let a = simulate(
        dir.path(),
        "a",
        "5",
        &["--bias-sd", "0.3", "--dead-bins", "0.05"],
    );
    let b = simulate(
        dir.path(),
        "b",
        "5",
        &["--bias-sd", "0.3", "--dead-bins", "0.05"],
    );
    let c = simulate(
        dir.path(),
        "c",
        "6",
        &["--bias-sd", "0.3", "--dead-bins", "0.05"],
    );
    assert_eq!(std::fs::read(&a.1).unwrap(), std::fs::read(&b.1).unwrap());
    assert_eq!(std::fs::read(&a.2).unwrap(), std::fs::read(&b.2).unwrap());
    let (dump_a, dump_b, dump_c) = (
        run_ok(&["dump", &a.0]),
        run_ok(&["dump", &b.0]),
        run_ok(&["dump", &c.0]),
    );
    assert!(!dump_a.is_empty());
    assert_eq!(dump_a, dump_b);
    assert_ne!(dump_a, dump_c);
    // Dead bins have no pixels: the bin table shows them with empty rows.
    let dead = dump_a
        .lines()
        .filter(|l| !l.is_empty())
        .flat_map(|l| {
            l.split('\t')
                .take(2)
                .map(|b| b.parse::<usize>().unwrap())
                .collect::<Vec<_>>()
        })
        .collect::<std::collections::HashSet<_>>();
    assert_eq!(600 - dead.len(), 30, "round(0.05 x 600) dead bins");
}

#[test]
fn bad_parameters_fail_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.cool");
    let out = out.to_str().unwrap();
    let line = run_err(&[
        "simulate",
        "blocks",
        "-o",
        out,
        "--min-domain",
        "80",
        "--max-domain",
        "60",
    ]);
    assert!(line.contains("minimum domain size"), "{line}");
    let line = run_err(&["simulate", "blocks", "-o", out, "--depth", "0"]);
    assert!(line.contains("depth"), "{line}");
    let line = run_err(&["simulate", "blocks", "-o", out, "--bins", "5"]);
    assert!(line.contains("cannot hold"), "{line}");
    assert!(!Path::new(out).exists());
    // Another format's name: a cooler named .hic (or .mcool) would fool Juicebox and cooler.
    for name in ["x.hic", "x.mcool", "x.bg2"] {
        let other = dir.path().join(name);
        for command in ["blocks", "polymer"] {
            let line = run_err(&["simulate", command, "-o", other.to_str().unwrap()]);
            assert!(
                line.contains("names another format"),
                "{command} {name}: {line}"
            );
            assert!(line.contains("contactmap convert"), "{line}");
            assert!(!other.exists());
        }
    }
    let help = run(&["simulate", "blocks", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    for text in ["--truth-domains", "[default: 2000]", "Examples:", "--seed"] {
        assert!(help.contains(text), "help lacks {text}: {help}");
    }
}

/// `simulate polymer` with two chains, loop extrusion and boundary elements: the .cool's
/// chromosomes and bins, the truth BEDs, and the same files for the same seed whatever the
/// number of threads.
#[test]
fn polymer_ensemble_files_and_reproducibility() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let simulate = |tag: &str, threads: &str| {
        let cool = path(&format!("{tag}.cool"));
        let args = [
            "simulate",
            "polymer",
            "-o",
            &cool,
            "--chains",
            "120,80",
            "--monomer-bp",
            "2000",
            "--monomers-per-bin",
            "10",
            "--density",
            "0.3",
            "--extrusion",
            "--ctcf",
            "40+,80-,150.",
            "--processivity",
            "30",
            "--separation",
            "40",
            "--steps-per-move",
            "20",
            "--replicas",
            "3",
            "--equilibration",
            "500",
            "--sample-every",
            "100",
            "--samples",
            "4",
            "--seed",
            "3",
            "--truth-boundaries",
            &path(&format!("{tag}.truth.bed")),
            "--truth-domains",
            &path(&format!("{tag}.domains.bed")),
            "--stats",
            &path(&format!("{tag}.stats.tsv")),
            "--truth-loops",
            &path(&format!("{tag}.loops.bedpe")),
        ];
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_contactmap"))
            .args(args)
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        cool
    };
    let cool = simulate("a", "1");
    let info = run_ok(&["info", &cool]);
    assert!(info.contains("nbins           20"), "{info}");
    assert!(info.contains("bin-size        20000"), "{info}");
    let dump = run_ok(&["dump", &cool, "--header"]);
    assert!(dump.lines().count() > 20);
    // No bin straddles the chains: chr1 has 12 bins, chr2 8.
    let chroms = run_ok(&["dump", &cool, "--table", "chroms"]);
    assert_eq!(chroms, "chr1\t240000\nchr2\t160000\n");
    assert_eq!(
        std::fs::read_to_string(path("a.truth.bed")).unwrap(),
        "chr1\t80000\t100000\nchr1\t160000\t180000\nchr2\t60000\t80000\n"
    );
    assert_eq!(
        std::fs::read_to_string(path("a.domains.bed")).unwrap(),
        "chr1\t0\t80000\nchr1\t80000\t160000\nchr1\t160000\t240000\n\
         chr2\t0\t60000\nchr2\t60000\t160000\n"
    );
    let stats = std::fs::read_to_string(path("a.stats.tsv")).unwrap();
    assert_eq!(stats.lines().count(), 1 + 3 * 4 * 2);
    let again = simulate("b", "2");
    assert_eq!(
        run_ok(&["dump", &cool, "--join"]),
        run_ok(&["dump", &again, "--join"])
    );
    assert_eq!(stats, std::fs::read_to_string(path("b.stats.tsv")).unwrap());
    // the held loops: bin pairs of element bins, fraction = samples / (3 replicas x 4 samples)
    let loops = std::fs::read_to_string(path("a.loops.bedpe")).unwrap();
    let mut lines = loops.lines();
    assert_eq!(
        lines.next(),
        Some("chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tfraction\tsamples")
    );
    let element_bins = ["chr1\t80000", "chr1\t160000", "chr2\t60000"];
    for line in lines {
        let f: Vec<&str> = line.split('\t').collect();
        assert!(
            element_bins.contains(&format!("{}\t{}", f[0], f[1]).as_str()),
            "{line}"
        );
        assert!(
            element_bins.contains(&format!("{}\t{}", f[3], f[4]).as_str()),
            "{line}"
        );
        let samples: f64 = f[7].parse().unwrap();
        assert_eq!(f[6].parse::<f64>().unwrap(), samples / 12.0, "{line}");
    }
    assert_eq!(
        loops,
        std::fs::read_to_string(path("b.loops.bedpe")).unwrap()
    );
}

/// Bad parameters are refused before any work, with one error line and no output file.
#[test]
fn polymer_bad_parameters() {
    let dir = tempfile::tempdir().unwrap();
    let cool = dir.path().join("x.cool");
    let cool = cool.to_str().unwrap();
    for (extra, expected) in [
        (&["--density", "2.0"][..], "close packing"),
        (&["--extrusion", "--ctcf", "40,5000"][..], "5000"),
        (&["--replicas", "0"][..], "replica"),
        (&["--types", "A-B"][..], "--types"),
        (
            &["--repulsion", "wca", "--repulsion-energy", "2"][..],
            "polynomial repulsion",
        ),
        (&["--repulsion-radius", "0"][..], "repulsion radius"),
    ] {
        let args = [
            &["simulate", "polymer", "-o", cool, "--chains", "100"][..],
            extra,
        ]
        .concat();
        let line = run_err(&args);
        assert!(line.contains(expected), "{extra:?}: {line}");
        assert!(!Path::new(cool).exists());
    }
    let _ = run(&["simulate", "polymer", "--help"]);
}

/// `simulate polymer --threads 1 / 2 / 16` on chains long enough to be split across threads
/// (5,000 and 4,200 beads; extrusion, attraction and angle stiffness on): byte-identical pixel
/// dumps and statistics. `--threads 0` is refused.
#[test]
fn polymer_same_files_on_any_number_of_threads() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let simulate = |threads: &str| {
        let (cool, stats) = (
            path(&format!("{threads}.cool")),
            path(&format!("{threads}.tsv")),
        );
        let args = [
            "simulate",
            "polymer",
            "-o",
            &cool,
            "--chains",
            "5000,4200",
            "--monomers-per-bin",
            "50",
            "--density",
            "0.2",
            "--confinement",
            "box",
            "--stiffness",
            "1",
            "--types",
            "A100B100",
            "--attraction",
            "0.3",
            "--extrusion",
            "--ctcf",
            "1000+,3000-,6000.",
            "--steps-per-move",
            "5",
            "--replicas",
            "2",
            "--equilibration",
            "20",
            "--sample-every",
            "10",
            "--samples",
            "2",
            "--seed",
            "11",
            "--stats",
            &stats,
            "--threads",
            threads,
        ];
        run_ok(&args);
        (
            run_ok(&["dump", &cool, "--join"]),
            std::fs::read_to_string(&stats).unwrap(),
        )
    };
    let (dump, stats) = simulate("1");
    assert!(dump.lines().count() > 100, "{dump}");
    assert_eq!(stats.lines().count(), 1 + 2 * 2 * 2);
    for threads in ["2", "16"] {
        let (other_dump, other_stats) = simulate(threads);
        assert!(other_dump == dump, "--threads {threads}: another map");
        assert_eq!(other_stats, stats, "--threads {threads}");
    }
    let line = run_err(&[
        "simulate",
        "polymer",
        "-o",
        &path("zero.cool"),
        "--threads",
        "0",
    ]);
    assert!(line.contains("--threads"), "{line}");
    assert!(!Path::new(&path("zero.cool")).exists());
}

/// `--device`: the CPU says so; the GPU (lavapipe in CI) writes a map with the same bins, or,
/// where no GPU exists and none is required, fails with exit code 2 and says why.
#[test]
fn polymer_device_choice() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let args = |device: &'static str, cool: &str| {
        let list = [
            "simulate",
            "polymer",
            "-o",
            cool,
            "--chains",
            "80,40",
            "--density",
            "0.3",
            "--replicas",
            "3",
            "--equilibration",
            "200",
            "--sample-every",
            "100",
            "--samples",
            "3",
            "--monomers-per-bin",
            "10",
            "--device",
            device,
        ];
        list.iter().map(|s| s.to_string()).collect::<Vec<_>>()
    };
    let (cpu, gpu) = (path("cpu.cool"), path("gpu.cool"));
    let cpu_args = args("cpu", &cpu);
    let out = run(&cpu_args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("simulate polymer: on the CPU"), "{stderr}");
    let gpu_args = args("gpu", &gpu);
    let out = run(&gpu_args.iter().map(String::as_str).collect::<Vec<_>>());
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.success() {
        assert!(stderr.contains("simulate polymer: on the GPU"), "{stderr}");
        let bins = |cool: &str| run_ok(&["dump", "-t", "bins", cool]);
        assert_eq!(bins(&gpu), bins(&cpu));
        let total = |cool: &str| -> u64 {
            run_ok(&["dump", cool])
                .lines()
                .map(|line| line.split('\t').nth(2).unwrap().parse::<u64>().unwrap())
                .sum()
        };
        assert!(total(&gpu) > 0);
    } else {
        assert!(
            std::env::var_os("CONTACTMAP_REQUIRE_GPU").is_none(),
            "a GPU is required: {stderr}"
        );
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("--device gpu: no usable GPU"), "{stderr}");
        assert!(!Path::new(&gpu).exists());
    }
}

/// Issue 26: a run that succeeds says nothing that reads as an error. Without a desktop
/// session (no XDG_RUNTIME_DIR), Mesa's Vulkan drivers printed "error: XDG_RUNTIME_DIR is invalid
/// or not set" twice while `--device auto` probed the GPU, before the run went on and succeeded.
#[test]
fn a_successful_run_prints_no_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p.cool");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_contactmap"))
        .args([
            "simulate",
            "polymer",
            "-o",
            out.to_str().unwrap(),
            "--chains",
            "40",
            "--replicas",
            "2",
            "--samples",
            "2",
            "--equilibration",
            "100",
            "--sample-every",
            "100",
        ])
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(!stderr.to_lowercase().contains("error"), "{stderr}");
    assert!(stderr.contains("simulate polymer: on the"), "{stderr}");
}

/// Issue 26: the README's route, `simulate blocks` then `balance --store`, works with the
/// defaults (the map has every distance, so ICE converges within cooler's 200 iterations); a
/// map of several chromosomes has no trans contacts, and balance says to use --cis-only, which
/// then converges.
#[test]
fn simulated_block_maps_balance_with_the_defaults() {
    let dir = tempfile::tempdir().unwrap();
    let one = dir.path().join("one.cool");
    run_ok(&["simulate", "blocks", "-o", one.to_str().unwrap()]);
    let summary: serde_json::Value = serde_json::from_str(&run_ok(&[
        "balance",
        one.to_str().unwrap(),
        "--store",
        "--json",
    ]))
    .unwrap();
    assert_eq!(
        summary["converged"],
        serde_json::Value::Bool(true),
        "{summary}"
    );
    let two = dir.path().join("two.cool");
    run_ok(&[
        "simulate",
        "blocks",
        "-o",
        two.to_str().unwrap(),
        "--chroms",
        "2",
        "--bins",
        "500",
    ]);
    let line = run_err(&["balance", two.to_str().unwrap(), "--store"]);
    assert!(
        line.contains("no trans (inter-chromosomal) contacts"),
        "{line}"
    );
    assert!(line.contains("--cis-only"), "{line}");
    run_ok(&["balance", two.to_str().unwrap(), "--store", "--cis-only"]);
}

/// Issue 26: a run says how far it relaxed (s*, the Rouse estimate), warns when the chains were
/// sampled before they relaxed, takes --equilibration / --sample-every in Rouse times (`auto`:
/// 3 and 0.5), and its --stats give each sample's time and relaxed separation.
#[test]
fn runs_say_how_far_the_chains_relaxed() {
    let dir = tempfile::tempdir().unwrap();
    let run_with = |equilibration: &str, sample_every: &str| {
        let out = dir.path().join("p.cool");
        let stats = dir.path().join("stats.tsv");
        let output = run(&[
            "simulate",
            "polymer",
            "-o",
            out.to_str().unwrap(),
            "--chains",
            "30",
            "--replicas",
            "2",
            "--samples",
            "3",
            "--equilibration",
            equilibration,
            "--sample-every",
            sample_every,
            "--device",
            "cpu",
            "--stats",
            stats.to_str().unwrap(),
        ]);
        assert!(output.status.success());
        (
            String::from_utf8_lossy(&output.stderr).into_owned(),
            crate::parse_table(&std::fs::read_to_string(&stats).unwrap()),
        )
    };
    // 200 steps of dt 0.002 (0.4 time units): s* = pi sqrt(3 x 0.404 / <b²>), about 3 beads.
    let (stderr, stats) = run_with("200", "2");
    assert!(
        stderr.contains("relaxed over separations up to s* = 3 beads"),
        "{stderr}"
    );
    assert!(
        stderr.contains("warning: the chains were sampled before they relaxed"),
        "{stderr}"
    );
    assert_eq!(
        stats.header,
        [
            "replica",
            "sample",
            "chain",
            "radius_of_gyration",
            "time",
            "relaxed_separation"
        ]
    );
    assert_eq!(stats.rows[0][4], "0.404");
    // auto: three Rouse times of the 30-bead chain, every separation relaxed, no warning.
    let (stderr, stats) = run_with("auto", "auto");
    assert!(stderr.contains("up to s* = 30 beads"), "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
    assert!(stats.rows.iter().all(|row| row[5] == "30"));
}
