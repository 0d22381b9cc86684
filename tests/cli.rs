//! Integration tests: the `contactmap` binary run on the real fixtures in `data/`, compared with
//! reference outputs of the peer tools (`data/reference/`, made by `scripts/make_references.sh`).

#[path = "cli/balance.rs"]
mod balance;
#[path = "cli/compare.rs"]
mod compare;
#[path = "cli/compartments.rs"]
mod compartments;
#[path = "cli/contacts.rs"]
mod contacts;
#[path = "cli/convert.rs"]
mod convert;
#[path = "cli/cool.rs"]
mod cool;
#[path = "cli/diff.rs"]
mod diff;
#[path = "cli/dots.rs"]
mod dots;
#[path = "cli/dump.rs"]
mod dump;
#[path = "cli/errors.rs"]
mod errors;
#[path = "cli/expected.rs"]
mod expected;
#[path = "cli/hic.rs"]
mod hic;
#[path = "cli/hic_writer.rs"]
mod hic_writer;
#[path = "cli/hicexplorer.rs"]
mod hicexplorer;
#[path = "cli/info.rs"]
mod info;
#[path = "cli/md_contacts.rs"]
mod md_contacts;
#[path = "cli/merge.rs"]
mod merge;
#[path = "cli/normalize.rs"]
mod normalize;
#[path = "cli/overwrite.rs"]
mod overwrite;
#[path = "cli/pairs.rs"]
mod pairs;
#[path = "cli/pileup.rs"]
mod pileup;
#[path = "cli/plot.rs"]
mod plot;
#[path = "cli/plot_compare.rs"]
mod plot_compare;
#[path = "cli/plot_contacts.rs"]
mod plot_contacts;
#[path = "cli/plot_expected.rs"]
mod plot_expected;
#[path = "cli/polymer_map.rs"]
mod polymer_map;
#[path = "cli/roundtrip.rs"]
mod roundtrip;
#[path = "cli/saddle.rs"]
mod saddle;
#[path = "cli/safety.rs"]
mod safety;
#[path = "cli/score.rs"]
mod score;
#[path = "cli/serve.rs"]
mod serve;
#[path = "cli/shell.rs"]
mod shell;
#[path = "cli/simulate.rs"]
mod simulate;
#[path = "cli/tads.rs"]
mod tads;
#[path = "cli/text.rs"]
mod text;
#[path = "cli/validate.rs"]
mod validate;
#[path = "cli/zoomify.rs"]
mod zoomify;

use std::path::PathBuf;
use std::process::{Command, Output};

/// Path of a fixture under `data/`.
pub fn data(name: &str) -> String {
    let path: PathBuf = [env!("CARGO_MANIFEST_DIR"), "data", name].iter().collect();
    path.to_string_lossy().into_owned()
}

/// Write `text` to `dir/name`; its path.
pub fn write(dir: &std::path::Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_string_lossy().into_owned()
}

/// Run the binary with `args`.
pub fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_contactmap"))
        .args(args)
        .output()
        .expect("the contactmap binary runs")
}

/// Run and require success; return stdout.
pub fn run_ok(args: &[&str]) -> String {
    let out = run(args);
    assert!(
        out.status.success(),
        "contactmap {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("utf-8 output")
}

/// Run and require exit code 2 with exactly one error line; return it.
pub fn run_err(args: &[&str]) -> String {
    let out = run(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(
        out.status.code(),
        Some(2),
        "contactmap {args:?} should fail with exit code 2; stderr: {stderr}"
    );
    assert!(out.stdout.is_empty() || !stderr.is_empty());
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "expected one error line, got: {stderr}");
    assert!(lines[0].starts_with("contactmap: error: "), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    lines[0].to_string()
}

/// The reference totals table: uri -> (nbins, nnz, sum).
pub fn reference_totals() -> Vec<(String, u64, u64, f64)> {
    std::fs::read_to_string(data("reference/totals.tsv"))
        .expect("data/reference/totals.tsv")
        .lines()
        .skip(1)
        .map(|line| {
            let f: Vec<&str> = line.split('\t').collect();
            (
                f[0].to_string(),
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
                f[3].parse().unwrap(),
            )
        })
        .collect()
}

/// A tab-separated table with a header line, as text fields.
pub struct Table {
    /// Column names.
    pub header: Vec<String>,
    /// Rows of fields.
    pub rows: Vec<Vec<String>>,
}

/// Parse a tab-separated table with a header line (empty lines skipped).
pub fn parse_table(text: &str) -> Table {
    let mut lines = text.lines();
    let header = lines
        .next()
        .expect("a header line")
        .split('\t')
        .map(String::from)
        .collect();
    let rows = lines
        .filter(|l| !l.is_empty())
        .map(|l| l.split('\t').map(String::from).collect())
        .collect();
    Table { header, rows }
}

/// A gzipped reference table under `data/` (e.g. `reference/tads/x.tsv.gz`).
pub fn reference_table(name: &str) -> Table {
    use std::io::Read;
    let mut text = String::new();
    flate2::read::MultiGzDecoder::new(std::fs::File::open(data(name)).expect("reference file"))
        .read_to_string(&mut text)
        .expect("gzip text");
    parse_table(&text)
}
