//! `contactmap validate`: check a .cool / .mcool / .hic file end to end, and optionally write a
//! repaired copy of a cooler.
//!
//! Exit status: 0 when the file is valid (warnings may be printed), 1 when problems were found
//! (they are the report, on standard output, not an error line), 2 when the file cannot be checked
//! (not a matrix file, unreadable). With `--repair OUT`: 0 when a corrected copy was written (and
//! passes the checks itself), 1 when the defects cannot be repaired (nothing is written).

use std::path::PathBuf;

use clap::Args;
use serde_json::json;

use crate::cli::output::Output;
use crate::cli::output::{refuse_overwrites, uri_file};
use crate::cli::status::Status;
use contactmap::error::{Error, Result};
use contactmap::validate::{self, RepairOutcome};

/// Arguments of `contactmap validate`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Checks: the cooler schema (groups, datasets, types, lengths); attributes against the data
(nbins, nchroms, nnz, bin-size, storage-mode, sum); chromosome names and lengths; the bin table
(contiguous per chromosome, ordered, fixed sizes); indexes/chrom_offset and indexes/bin1_offset;
pixels (bin ids in range, upper triangle, sorted, no duplicates, counts finite and >= 0); weight
columns; every coarser resolution of an .mcool against the coarsening of the base resolution.
A .hic file has its header, footer and master index read and every resolution's pixels streamed.

Exit status: 0 valid (warnings allowed), 1 problems found (listed on standard output), 2 the file
cannot be checked. With --repair: 0 a corrected copy was written, 1 the defects cannot be repaired.

Examples:
  contactmap validate data/cooler_test_file.mcool
  contactmap validate data/hic_test_file.hic --json
  contactmap validate broken.cool --repair fixed.cool")]
pub struct ValidateArgs {
    /// File to check: file.cool, file.mcool[::/resolutions/N], file.hic[::/resolutions/N].
    pub uri: String,
    /// Print one JSON document instead of text.
    #[arg(long)]
    pub json: bool,
    /// Write a corrected copy of a cooler here (never the input): pixels resorted, duplicates
    /// summed, lower-triangle pixels transposed, indexes and attributes rebuilt, .mcool zoom
    /// levels regenerated from the base resolution.
    #[arg(long, value_name = "OUT")]
    pub repair: Option<PathBuf>,
    /// Write the report to this file instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Run `contactmap validate`: [`Status::Invalid`] (exit code 1, after writing the report) when
/// the file is invalid or cannot be repaired.
pub fn run(args: &ValidateArgs) -> Result<Status> {
    refuse_overwrites(
        &[uri_file(&args.uri)],
        &[args.repair.as_deref(), args.out.as_deref()],
    )?;
    let report = validate::validate(&args.uri)?;
    let mut text = String::new();
    let mut json = report.to_json();
    let mut success = report.is_valid();
    if !args.json {
        text.push_str(&report.to_text());
    }
    if let Some(out) = &args.repair {
        let outcome = validate::repair(&args.uri, &report, out)?;
        match outcome {
            RepairOutcome::Refused(reasons) => {
                success = false;
                if !args.json {
                    text.push_str(&format!(
                        "repair refused, nothing written to {}:\n",
                        out.display()
                    ));
                    for reason in &reasons {
                        text.push_str(&format!("  {reason}\n"));
                    }
                }
                json["repair"] = json!({
                    "written": false,
                    "output": out.display().to_string(),
                    "refused": reasons,
                });
            }
            RepairOutcome::Written(actions) => {
                let copy = validate::validate(&out.to_string_lossy())?;
                if !copy.is_valid() {
                    return Err(Error::Invalid(format!(
                        "{}: the repaired copy still has {} problems (first: {}); please report this",
                        out.display(),
                        copy.n_errors(),
                        copy.findings
                            .first()
                            .map_or(String::new(), |f| f.message.clone())
                    )));
                }
                success = true;
                if !args.json {
                    text.push_str(&format!(
                        "repaired copy written to {} (it passes validate):\n",
                        out.display()
                    ));
                    if actions.is_empty() {
                        text.push_str("  no change was needed: the copy holds the same data\n");
                    }
                    for action in &actions {
                        text.push_str(&format!("  {action}\n"));
                    }
                }
                json["repair"] = json!({
                    "written": true,
                    "output": out.display().to_string(),
                    "actions": actions,
                    "output_valid": copy.is_valid(),
                });
            }
        }
    }
    if args.json {
        text = serde_json::to_string_pretty(&json).unwrap_or_default();
        text.push('\n');
    }
    let mut output = Output::open(args.out.as_deref())?;
    output.write_all(text.as_bytes())?;
    output.finish()?;
    Ok(if success {
        Status::Success
    } else {
        Status::Invalid
    })
}
