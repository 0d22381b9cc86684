//! What the pairs subcommands share: the command line for the @PG line, outputs opened with
//! the header written, statistics files, the check that no output is an input.

use std::path::{Path, PathBuf};

use clap::Args;

use contactmap::error::Result;
use contactmap::io::output::{BGZF_LEVEL, Output};
use contactmap::io::pairs::PairsHeader;
use contactmap::pairs::stats::PairCounter;

/// The command line, for the `@PG` line a pairs command adds to the header.
pub(super) fn command_line() -> String {
    std::env::args().collect::<Vec<_>>().join(" ")
}

/// How `.gz` outputs are compressed (the pairs commands that write pairs share it).
#[derive(Clone, Copy, Debug, Args)]
pub struct Compression {
    /// BGZF compression level of `.gz` outputs, libdeflate's 0 (stored) to 12 (smallest). 7
    /// writes files the size bgzip's default (and so pairtools') writes; the default 6 is 0.8%
    /// larger and cheaper. Other outputs (plain files, standard output) are not compressed.
    #[arg(long, value_name = "N", default_value_t = BGZF_LEVEL,
          value_parser = clap::value_parser!(u8).range(0..=12))]
    pub compress_level: u8,
}

/// Open an output (`None` or `-`: standard output) and write the header.
pub(super) fn open_output(
    path: Option<&Path>,
    header: &PairsHeader,
    compression: Compression,
) -> Result<Output> {
    let mut output = Output::open_blocked(path, compression.compress_level)?;
    output.write_all(header.to_text().as_bytes())?;
    Ok(output)
}

/// The outputs of a command, refused when one is an input.
pub(super) fn refuse_overwrites(inputs: &[&Path], outputs: &[Option<&PathBuf>]) -> Result<()> {
    let outputs: Vec<Option<&Path>> = outputs.iter().map(|o| o.map(PathBuf::as_path)).collect();
    contactmap::io::output::refuse_overwrites(inputs, &outputs)
}

/// Write pairtools' statistics file (`None` or `-`: standard output; `.gz`: BGZF).
pub(super) fn write_stats(path: Option<&Path>, counter: &PairCounter) -> Result<()> {
    let mut output = Output::open_blocked(path, BGZF_LEVEL)?;
    output.write_all(counter.to_text().as_bytes())?;
    output.finish()
}
