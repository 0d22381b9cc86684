//! Mutation-fuzzing campaign driver: runs mutants of the real fixtures through the `contactmap`
//! binary and prints a table per format (see `docs/reliability.md`).
//!
//! ```text
//! cargo build --release
//! cargo run --release --example fuzz_campaign -- --format hic --mutants 10000 --seed 1 --jobs 2 --out DIR
//! cargo run --release --example fuzz_campaign -- --format all --mutants 500 --out DIR
//! cargo run --release --example fuzz_campaign -- --format hic --seed 1 --only 1234 --out DIR
//! ```
//!
//! Options: `--format NAME[,NAME..]|all`, `--mutants N` (per format, default 500), `--seed S`
//! (default 1), `--jobs J` (default 2), `--out DIR` (failing mutants, their commands and stderr;
//! default `fuzz-out`), `--binary PATH` (default `target/release/contactmap`), `--only I[,I..]` (run
//! these mutant indices only), `--start I` (first index, default 0). Exit status 1 when any run failed.

#[allow(dead_code)]
#[path = "../tests/fuzz/harness.rs"]
mod harness;
#[allow(dead_code)]
#[path = "../tests/fuzz/mutate.rs"]
mod mutate;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use harness::{Class, Format, Outcome};

struct Options {
    formats: Vec<String>,
    mutants: u64,
    seed: u64,
    jobs: usize,
    out: PathBuf,
    binary: PathBuf,
    only: Option<Vec<u64>>,
    start: u64,
}

fn usage(problem: &str) -> ! {
    eprintln!(
        "fuzz_campaign: {problem}\nusage: fuzz_campaign [--format NAME[,NAME..]|all] [--mutants N] [--seed S] [--jobs J] [--out DIR] [--binary PATH] [--only I[,I..]] [--start I]\nformats: {}",
        harness::FORMATS.join(", ")
    );
    std::process::exit(2)
}

fn parse() -> Options {
    let mut options = Options {
        formats: harness::FORMATS.iter().map(|s| s.to_string()).collect(),
        mutants: 500,
        seed: 1,
        jobs: 2,
        out: PathBuf::from("fuzz-out"),
        binary: [
            env!("CARGO_MANIFEST_DIR"),
            "target",
            "release",
            "contactmap",
        ]
        .iter()
        .collect(),
        only: None,
        start: 0,
    };
    let mut args = std::env::args().skip(1);
    while let Some(flag) = args.next() {
        let mut value = || {
            args.next()
                .unwrap_or_else(|| usage(&format!("{flag} takes a value")))
        };
        let number = |s: String| -> u64 {
            s.parse()
                .unwrap_or_else(|_| usage(&format!("not a number: {s}")))
        };
        match flag.as_str() {
            "--format" => {
                let v = value();
                if v != "all" {
                    options.formats = v.split(',').map(str::to_string).collect();
                    for f in &options.formats {
                        if !harness::FORMATS.contains(&f.as_str()) {
                            usage(&format!("unknown format {f}"));
                        }
                    }
                }
            }
            "--mutants" => options.mutants = number(value()),
            "--seed" => options.seed = number(value()),
            "--jobs" => options.jobs = number(value()).max(1) as usize,
            "--out" => options.out = PathBuf::from(value()),
            "--binary" => options.binary = PathBuf::from(value()),
            "--only" => {
                options.only = Some(value().split(',').map(|s| number(s.to_string())).collect())
            }
            "--start" => options.start = number(value()),
            "-h" | "--help" => usage("help"),
            other => usage(&format!("unknown option {other}")),
        }
    }
    if !options.binary.is_file() {
        usage(&format!(
            "no binary at {} (cargo build --release, or --binary PATH)",
            options.binary.display()
        ));
    }
    options
}

/// Save a failing mutant, its commands and their stderr under `dir/<format>/<index>/`.
fn save(dir: &Path, format: &Format, seed: u64, outcome: &Outcome, binary: &Path) {
    let folder = dir.join(format.name).join(format!("{:06}", outcome.index));
    std::fs::create_dir_all(&folder).expect("create the findings folder");
    if let Some(bytes) = &outcome.bytes {
        std::fs::write(folder.join(&outcome.file_name), bytes).expect("save the mutant");
    }
    let scratch = Path::new(&outcome.path)
        .parent()
        .expect("the mutant's folder")
        .to_string_lossy()
        .into_owned();
    let folder_str = folder.to_string_lossy();
    let mut script =
        String::from("#!/bin/sh\n# Re-run the failing commands on the saved mutant.\n");
    for run in outcome.runs.iter().filter(|r| r.class.is_failure()) {
        // The mutant lay in a scratch folder: point the command at the saved copy.
        let args: Vec<String> = run
            .args
            .iter()
            .map(|a| a.replace(&scratch, &folder_str))
            .collect();
        script.push_str(&format!(
            "# {} ({}; {})\n{}\n",
            run.class.name(),
            run.status,
            run.why,
            if run.class == Class::Hang {
                format!("timeout 30 {}", harness::shell_line(binary, &args))
            } else {
                harness::shell_line(binary, &args)
            }
        ));
    }
    std::fs::write(folder.join("command.sh"), script).expect("save the command");
    std::fs::write(
        folder.join("report.txt"),
        harness::describe(format, seed, outcome, binary),
    )
    .expect("save the report");
}

fn main() {
    let options = parse();
    std::fs::create_dir_all(&options.out).expect("create --out");
    let scratch = tempfile::Builder::new()
        .prefix("fuzz-")
        .tempdir()
        .expect("scratch folder");
    let mut rows = Vec::new();
    let mut any_failure = false;
    for name in &options.formats {
        // Companion files (chrom.sizes, a BG2 table) stay with the findings, for the commands.
        let aux = std::fs::canonicalize(&options.out)
            .expect("--out folder")
            .join("aux");
        std::fs::create_dir_all(&aux).expect("create the companions folder");
        let format = harness::format(name, &aux);
        let indices: Vec<u64> = match &options.only {
            Some(list) => list.clone(),
            None => (options.start..options.start + options.mutants).collect(),
        };
        let done = AtomicU64::new(0);
        let total = indices.len() as u64;
        let binary = options.binary.clone();
        let out = options.out.clone();
        let seed = options.seed;
        let progress = |outcome: &Outcome| {
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            if outcome.failed() {
                save(&out, &format, seed, outcome, &binary);
                let classes: Vec<&str> = outcome
                    .runs
                    .iter()
                    .filter(|r| r.class.is_failure())
                    .map(|r| r.class.name())
                    .collect();
                eprintln!(
                    "[{}] mutant {} failed: {}",
                    format.name,
                    outcome.index,
                    classes.join(", ")
                );
            }
            if n.is_multiple_of(500) || n == total {
                eprintln!("[{}] {n}/{total}", format.name);
            }
        };
        let (summary, failures) = harness::campaign(
            &options.binary,
            &format,
            options.seed,
            &indices,
            options.jobs,
            scratch.path(),
            &progress,
        );
        if options.only.is_some() {
            for outcome in &failures {
                print!(
                    "{}",
                    harness::describe(&format, options.seed, outcome, &options.binary)
                );
            }
        }
        any_failure |= !failures.is_empty();
        rows.push((format.name, summary));
    }
    let mut stdout = std::io::stdout().lock();
    let mut header = format!(
        "{:<8} {:>8} {:>8} {:>8}",
        "format", "mutants", "failing", "runs"
    );
    for class in Class::ALL {
        header.push_str(&format!(" {:>11}", class.name()));
    }
    header.push_str(&format!(" {:>9}", "time_s"));
    writeln!(stdout, "{header}").expect("stdout");
    for (name, summary) in &rows {
        let mut line = format!(
            "{:<8} {:>8} {:>8} {:>8}",
            name,
            summary.mutants,
            summary.failing_mutants,
            summary.total_runs()
        );
        for class in Class::ALL {
            line.push_str(&format!(" {:>11}", summary.count(class)));
        }
        line.push_str(&format!(" {:>9.1}", summary.elapsed.as_secs_f64()));
        writeln!(stdout, "{line}").expect("stdout");
    }
    writeln!(
        stdout,
        "seed {} binary {} failing mutants saved under {}",
        options.seed,
        options.binary.display(),
        options.out.display()
    )
    .expect("stdout");
    std::process::exit(i32::from(any_failure));
}
