//! `contactmap info`: describe a matrix file.

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::args::InputArgs;
use crate::cli::output::Output;
use crate::cli::output::{refuse_overwrites, uri_file};
use contactmap::error::Result;
use contactmap::io::info::{describe, describe_text};

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
                let text = describe_text(&report);
                if k > 0 { format!("\n{text}") } else { text }
            }
        };
        out.write_all(text.as_bytes())?;
        out.flush()?;
    }
    out.finish()
}
