//! `contactmap info`: describe a matrix file.

use std::path::{Path, PathBuf};

use clap::Args;
use serde_json::Value;

use crate::cli::output::Output;
use crate::cli::output::{refuse_overwrites, uri_file};
use crate::cli::InputArgs;
use contactmap::error::Result;
use contactmap::io::info::describe;

/// Arguments of `contactmap info`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Examples:
  contactmap info data/hic_test_file.hic
  contactmap info data/cooler_test_file.mcool   # lists every resolution
  contactmap info data/cooler_test_file.mcool::/resolutions/100000 --json
  # one JSON object per line, per input
  contactmap info samples/*.cool --json > summary.jsonl

With several inputs, one report per input is written as soon as it is read: text reports
separated by a blank line, or with --json one compact JSON object per line (JSON Lines). The
JSON output holds the file's own attributes under the names cooler uses (so `cooler info`
consumers keep working), with nbins, nchroms, nnz and sum computed from the data.")]
pub struct InfoArgs {
    /// Matrix URIs: file.cool, file.mcool[::/resolutions/N], file.hic[::/resolutions/N], text
    /// table (`-`: standard input).
    #[arg(required = true, value_name = "URI")]
    pub uris: Vec<String>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Write to this file instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `contactmap info`.
pub fn run(args: &InfoArgs) -> Result<()> {
    let inputs: Vec<&Path> = args
        .uris
        .iter()
        .map(|uri| uri_file(uri))
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let options = args.input.to_options()?;
    let many = args.uris.len() > 1;
    let mut out = Output::open(args.out.as_deref())?;
    for (k, uri) in args.uris.iter().enumerate() {
        let report = describe(uri, &options)?;
        let text = match (args.json, many) {
            (true, false) => serde_json::to_string_pretty(&report).unwrap_or_default() + "\n",
            (true, true) => serde_json::to_string(&report).unwrap_or_default() + "\n",
            (false, _) => {
                let text = render_text(&report);
                if k > 0 {
                    format!("\n{text}")
                } else {
                    text
                }
            }
        };
        out.write_all(text.as_bytes())?;
        out.flush()?;
    }
    out.finish()
}

fn render_text(report: &Value) -> String {
    let mut lines = Vec::new();
    let get = |key: &str| report.get(key).cloned().unwrap_or(Value::Null);
    let plain = |v: &Value| match v {
        Value::String(s) => s.clone(),
        Value::Null => "-".into(),
        other => other.to_string(),
    };
    // Labels in one column as wide as the longest, `genome-assembly`.
    let row = |label: &str, value: String| format!("{label:<15} {value}");
    lines.push(row("uri", plain(&get("uri"))));
    lines.push(row("format", plain(&get("file-format"))));
    if let Some(levels) = report.get("levels").and_then(|l| l.as_array()) {
        lines.push(row("resolutions", levels.len().to_string()));
        lines.push("  bin-size        nbins            nnz                sum  weights".into());
        for level in levels {
            lines.push(format!(
                "  {:>8} {:>12} {:>14} {:>18}  {}",
                plain(&level["bin-size"]),
                plain(&level["nbins"]),
                plain(&level["nnz"]),
                plain(&level["sum"]),
                level["weights"]
                    .as_array()
                    .map(|w| w.iter().map(&plain).collect::<Vec<_>>().join(","))
                    .unwrap_or_default()
            ));
        }
        return lines.join("\n") + "\n";
    }
    for key in [
        "genome-assembly",
        "bin-type",
        "bin-size",
        "nbins",
        "nchroms",
        "nnz",
        "sum",
        "count-type",
    ] {
        if let Some(v) = report.get(key) {
            lines.push(row(key, plain(v)));
        }
    }
    if let Some(weights) = report.get("weights").and_then(|w| w.as_array()) {
        let names: Vec<String> = weights.iter().map(&plain).collect();
        lines.push(row(
            "weights",
            if names.is_empty() {
                "none".to_string()
            } else {
                names.join(", ")
            },
        ));
    }
    if let Some(resolutions) = report.get("resolutions").and_then(|r| r.as_array()) {
        let list: Vec<String> = resolutions.iter().map(&plain).collect();
        lines.push(row("resolutions", list.join(", ")));
    }
    if let Some(chroms) = report.get("chromosomes").and_then(|c| c.as_array()) {
        let shown: Vec<String> = chroms
            .iter()
            .take(12)
            .map(|c| format!("{}:{}", plain(&c["name"]), plain(&c["length"])))
            .collect();
        let more = if chroms.len() > 12 {
            format!(" ... ({} more)", chroms.len() - 12)
        } else {
            String::new()
        };
        lines.push(row("chromosomes", format!("{}{more}", shown.join(" "))));
    }
    if let Some(notes) = report.get("notes").and_then(|n| n.as_array()) {
        for note in notes {
            lines.push(row("note", plain(note)));
        }
    }
    lines.join("\n") + "\n"
}
