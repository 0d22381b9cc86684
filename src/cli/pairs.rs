//! `contactmap pairs`: from the aligner's SAM / BAM to deduplicated pairs, as pairtools 1.1.2
//! (`parse`, `sort`, `dedup`, `stats`, `select`, `merge`). Every subcommand reads `-` and
//! writes to standard output by default, so they chain in a pipe.

mod dedup;
mod merge;
mod parse;
mod select;
mod shared;
mod sort;
mod stats;

use clap::{Args, Subcommand};

use contactmap::error::Result;

/// Arguments of `contactmap pairs`.
#[derive(Debug, Args)]
pub struct PairsArgs {
    /// What to do.
    #[command(subcommand)]
    pub command: PairsCommand,
}

/// The pairs subcommands.
#[derive(Debug, Subcommand)]
pub enum PairsCommand {
    /// Pairs from read alignments (SAM / BAM grouped by read name, as `bwa mem -SP5M` writes
    /// them), as pairtools parse: pair types, walks policies, flipped to the upper triangle.
    Parse(parse::ParseArgs),
    /// Sort pairs in pairtools' order (chrom1, chrom2, pos1, pos2, pair_type) in bounded memory,
    /// on every core.
    Sort(sort::SortArgs),
    /// Mark duplicates in sorted pairs as pairtools dedup (same chromosomes and strands,
    /// positions within --max-mismatch), in memory independent of the file's size.
    Dedup(dedup::DedupArgs),
    /// pairtools' statistics of pairs (totals, pair types, cis / trans, distances, duplicates,
    /// library complexity), or statistics files summed with --merge.
    Stats(stats::StatsArgs),
    /// The pairs that meet a condition on their columns (pair type, chromosomes, positions,
    /// MAPQ ...), as pairtools select.
    Select(select::SelectArgs),
    /// Merge sorted pairs files into one sorted file (same chromosomes and columns).
    Merge(merge::MergeArgs),
}

/// Run `contactmap pairs`.
pub fn run(args: &PairsArgs) -> Result<()> {
    match &args.command {
        PairsCommand::Parse(args) => parse::run(args),
        PairsCommand::Sort(args) => sort::run(args),
        PairsCommand::Dedup(args) => dedup::run(args),
        PairsCommand::Merge(args) => merge::run(args),
        PairsCommand::Stats(args) => stats::run(args),
        PairsCommand::Select(args) => select::run(args),
    }
}
