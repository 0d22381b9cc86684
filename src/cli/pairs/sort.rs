//! `contactmap pairs sort`: pairs in pairtools' order, in bounded memory
//! ([`contactmap::io::pairs::sort_pairs`]).

use std::path::PathBuf;

use clap::Args;

use super::shared::{Compression, command_line, open_output, refuse_overwrites};
use crate::cli::progress::spinner;
use contactmap::error::{Error, Result};
use contactmap::io::pairs::{SortOptions, open_pairs, sort_pairs};

/// Arguments of `contactmap pairs sort`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
The order is pairtools sort's: chrom1, then chrom2, as bytes (chr10 before chr2), then pos1 and
pos2 as numbers, then pair_type; records equal on all five keep their input order. The header
gets `#sorted: chr1-chr2-pos1-pos2`.

Records are gathered until --memory is used, sorted on every core, and written to --tmpdir as
compressed runs when the input does not fit; the runs are then merged. Runs are unlinked as soon
as they are made, so nothing is left in --tmpdir whatever happens to the command. Peak memory
is about --memory plus 100 MB.

Examples:
  contactmap pairs sort sample.pairs.gz -o sample.sorted.pairs.gz
  contactmap pairs parse sample.bam -c hg38.sizes \\
      | contactmap pairs sort --memory 8G --tmpdir /scratch -o sorted.pairs.gz")]
pub struct SortArgs {
    /// Pairs file (plain, gzip or BGZF; `-`: standard input).
    #[arg(default_value = "-")]
    pub input: PathBuf,
    /// Output (`.gz`: BGZF); standard output when not given.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub compression: Compression,
    /// Memory for records before they go to disk (K, M, G suffixes).
    #[arg(long, default_value = "2G", value_name = "SIZE")]
    pub memory: String,
    /// Folder for the temporary runs (the system's temporary folder by default).
    #[arg(long, value_name = "DIR")]
    pub tmpdir: Option<PathBuf>,
}

/// Run `contactmap pairs sort`.
pub fn run(args: &SortArgs) -> Result<()> {
    refuse_overwrites(&[&args.input], &[args.output.as_ref()])?;
    let memory_bytes = contactmap::io::parse_memory_size(&args.memory)
        .map_err(|e| Error::Argument(format!("--memory {}: {e}", args.memory)))?;
    let tmpdir = args.tmpdir.clone().unwrap_or_else(std::env::temp_dir);
    if !tmpdir.is_dir() {
        return Err(Error::Argument(format!(
            "--tmpdir {}: not a folder",
            tmpdir.display()
        )));
    }
    let mut reader = open_pairs(&args.input)?;
    let mut header = reader.header().clone();
    header.push_program("contactmap_pairs_sort", &command_line());
    header.mark_sorted();
    let mut output = open_output(args.output.as_deref(), &header, args.compression)?;
    let bar = spinner("pairs read");
    let options = SortOptions {
        memory_bytes,
        tmpdir,
    };
    sort_pairs(
        &mut reader,
        &options,
        &mut |bytes| output.write_all(bytes),
        &mut |n| bar.set_position(n),
    )?;
    bar.finish_and_clear();
    output.finish()
}
