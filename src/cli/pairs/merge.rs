//! `contactmap pairs merge`: sorted pairs files merged into one
//! ([`contactmap::io::pairs::merge_sorted`]).

use std::path::PathBuf;

use clap::Args;

use super::shared::{Compression, command_line, open_output, refuse_overwrites};
use contactmap::error::{Error, Result};
use contactmap::io::pairs::{PairsReader, open_pairs};

/// Arguments of `contactmap pairs merge`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Each input must be sorted in pairtools' order (`contactmap pairs sort`); the first record out of
order stops the merge with its file and line. The inputs must have the same chromosomes (the
'#chromsize:' lines) and the same columns. The output's header is the first input's, marked
sorted, with this command's @PG line.

Examples:
  contactmap pairs merge lane1.sorted.pairs.gz lane2.sorted.pairs.gz \\
      -o sample.sorted.pairs.gz")]
pub struct MergeArgs {
    /// Sorted pairs files.
    #[arg(required = true, num_args = 1..)]
    pub inputs: Vec<PathBuf>,
    /// Output (`.gz`: BGZF); standard output when not given.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub compression: Compression,
}

/// Run `contactmap pairs merge`.
pub fn run(args: &MergeArgs) -> Result<()> {
    let inputs: Vec<&std::path::Path> = args.inputs.iter().map(PathBuf::as_path).collect();
    refuse_overwrites(&inputs, &[args.output.as_ref()])?;
    let mut readers: Vec<PairsReader> = args
        .inputs
        .iter()
        .map(|path| open_pairs(path))
        .collect::<Result<_>>()?;
    let first = &readers[0];
    let chroms = first.header().chromsizes(first.path())?;
    let columns = first.header().columns();
    for reader in &readers[1..] {
        if reader.header().chromsizes(reader.path())? != chroms {
            return Err(Error::Argument(format!(
                "{} and {}: different chromosomes in their '#chromsize:' lines; pairs of different \
                 assemblies or chromosome sets cannot be merged",
                first.path(),
                reader.path()
            )));
        }
        if reader.header().columns() != columns {
            return Err(Error::Argument(format!(
                "{} and {}: different columns ('{}' and '{}')",
                first.path(),
                reader.path(),
                columns.join(" "),
                reader.header().columns().join(" ")
            )));
        }
    }
    let mut header = first.header().clone();
    header.push_program("contactmap_pairs_merge", &command_line());
    header.mark_sorted();
    let mut output = open_output(args.output.as_deref(), &header, args.compression)?;
    contactmap::io::pairs::merge_sorted(&mut readers, &mut |bytes| output.write_all(bytes))?;
    output.finish()
}
