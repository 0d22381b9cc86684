//! The pileup reference cases of `data/reference/pileup/pileups.tsv.gz` (written by
//! `scripts/pileup_reference.py` from coolpuppy 1.1.0 and cooltools 0.7.1), read for the
//! library's tests (`src/pileup/tests.rs`) and the CLI's (`tests/cli/pileup.rs`), which include
//! this file with `#[path = ...]`; it is not part of the library.
//!
//! Each case starts with a line `## NAME`; each of its groups with a line
//! `# n=N [control_n=M] [group=LABEL]` (no group: the group of all), then the grid's rows,
//! tab-separated.

use std::io::Read;
use std::path::Path;

/// One group of a reference case: its header fields and grid.
pub struct RefGroup {
    /// Snippets piled up.
    pub n: usize,
    /// Shifted controls piled up, where the case has them.
    pub control_n: Option<usize>,
    /// The group's label (`all` for the group of all).
    pub label: String,
    /// The grid, row by row.
    pub grid: Vec<Vec<f64>>,
}

/// The groups of case `name` in the reference file at `path`, in file order.
pub fn reference_case(path: &Path, name: &str) -> Vec<RefGroup> {
    let mut text = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(path).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    let mut groups: Vec<RefGroup> = Vec::new();
    let case = text
        .lines()
        .skip_while(|l| *l != format!("## {name}"))
        .skip(1)
        .take_while(|l| !l.starts_with("## "));
    for line in case {
        if let Some(head) = line.strip_prefix("# ") {
            let field = |key: &str| {
                head.split(' ')
                    .find_map(|f| f.strip_prefix(&format!("{key}=")).map(str::to_string))
            };
            groups.push(RefGroup {
                n: field("n").unwrap().parse().unwrap(),
                control_n: field("control_n").map(|v| v.parse().unwrap()),
                label: field("group").unwrap_or_else(|| "all".into()),
                grid: Vec::new(),
            });
        } else {
            let row = line.split('\t').map(|v| v.parse().unwrap()).collect();
            groups.last_mut().unwrap().grid.push(row);
        }
    }
    assert!(
        !groups.is_empty(),
        "no reference case {name} in {}",
        path.display()
    );
    groups
}
