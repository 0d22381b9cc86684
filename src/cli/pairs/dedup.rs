//! `contactmap pairs dedup`: duplicates marked and set apart ([`contactmap::pairs::dedup`]).

use std::path::{Path, PathBuf};

use clap::Args;

use super::shared::{Compression, command_line, open_output, refuse_overwrites, write_stats};
use crate::cli::progress::spinner;
use contactmap::error::Result;
use contactmap::io::output::Output;
use contactmap::io::pairs::open_pairs;
use contactmap::pairs::dedup::{DedupMethod, DedupParams, PairClass, dedup_pairs};
use contactmap::pairs::stats::PairCounter;

/// Arguments of `contactmap pairs dedup`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Two mapped pairs are duplicates when they have the same chromosomes and strands and positions
within --max-mismatch bp: on each side (--method max) or summed over both (--method sum).
Duplicates chain; the first pair of each cluster is kept. Pairs with an unmapped side (`!`) are
never duplicates: they go to --output-unmapped (or nowhere).

The input must be sorted (`contactmap pairs sort`): a record out of order stops the command with
its line. Reading follows pairtools dedup 1.1.2 (chunks of 10,000 lines, the last 100 kept pairs
carried into the next), so the outputs are identical to its own; memory stays that of a chunk,
whatever the file's size. With --mark-dups (the default) duplicates are typed DD.

An output given twice (e.g. --output-dups equal to --output) gets both kinds of pairs, in the
order pairtools writes them.

Examples:
  contactmap pairs dedup sample.sorted.pairs.gz -o sample.nodups.pairs.gz \\
      --output-dups sample.dups.pairs.gz \\
      --output-unmapped sample.unmapped.pairs.gz \\
      --output-stats sample.dedup.stats
  contactmap pairs parse s.bam -c hg38.sizes | contactmap pairs sort \\
      | contactmap pairs dedup \\
      | contactmap convert - s.cool --bin-size 1000 --format pairs")]
pub struct DedupArgs {
    /// Sorted pairs (plain, gzip or BGZF; `-`: standard input).
    #[arg(default_value = "-")]
    pub input: PathBuf,
    /// Output of the kept pairs (`.gz`: BGZF); standard output when not given.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub compression: Compression,
    /// Output of the duplicates.
    #[arg(long, value_name = "FILE")]
    pub output_dups: Option<PathBuf>,
    /// Output of the pairs with an unmapped side.
    #[arg(long, value_name = "FILE")]
    pub output_unmapped: Option<PathBuf>,
    /// Write pairtools' statistics (duplicates counted) to this file.
    #[arg(long, value_name = "FILE")]
    pub output_stats: Option<PathBuf>,
    /// The most bp two duplicates' positions may differ by.
    #[arg(long, default_value_t = 3)]
    pub max_mismatch: u64,
    /// How the two sides' differences are combined: max or sum.
    #[arg(long, default_value = "max", value_parser = ["max", "sum"])]
    pub method: String,
    /// Type duplicates DD (the default).
    #[arg(long, overrides_with = "no_mark_dups")]
    pub mark_dups: bool,
    /// Keep the duplicates' pair types.
    #[arg(long)]
    pub no_mark_dups: bool,
}

/// Which output each kind of pair goes to (indices into the opened outputs).
struct Routes {
    outputs: Vec<Output>,
    unique: Option<usize>,
    duplicate: Option<usize>,
    unmapped: Option<usize>,
}

fn same(a: Option<&Path>, b: Option<&Path>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => a == b || contactmap::io::same_file(a, b),
        _ => false,
    }
}

/// Run `contactmap pairs dedup`.
pub fn run(args: &DedupArgs) -> Result<()> {
    refuse_overwrites(
        &[&args.input],
        &[
            args.output.as_ref(),
            args.output_dups.as_ref(),
            args.output_unmapped.as_ref(),
            args.output_stats.as_ref(),
        ],
    )?;
    let params = DedupParams {
        max_mismatch: args.max_mismatch,
        method: if args.method == "sum" {
            DedupMethod::Sum
        } else {
            DedupMethod::Max
        },
        mark_dups: !args.no_mark_dups,
        ..DedupParams::default()
    };
    let mut reader = open_pairs(&args.input)?;
    let mut header = reader.header().clone();
    header.push_program("contactmap_pairs_dedup", &command_line());

    // Outputs: the kept pairs always (standard output by default); the others when asked,
    // sharing a stream where a path is given twice.
    let mut routes = Routes {
        outputs: vec![open_output(
            args.output.as_deref(),
            &header,
            args.compression,
        )?],
        unique: Some(0),
        duplicate: None,
        unmapped: None,
    };
    let main = args.output.as_deref();
    if let Some(dups) = args.output_dups.as_deref() {
        routes.duplicate = Some(if same(Some(dups), main) || dups == Path::new("-") {
            0
        } else {
            routes
                .outputs
                .push(open_output(Some(dups), &header, args.compression)?);
            routes.outputs.len() - 1
        });
    }
    if let Some(unmapped) = args.output_unmapped.as_deref() {
        routes.unmapped = Some(
            if same(Some(unmapped), main) || unmapped == Path::new("-") {
                0
            } else if same(Some(unmapped), args.output_dups.as_deref()) {
                routes.duplicate.expect("set above")
            } else {
                routes
                    .outputs
                    .push(open_output(Some(unmapped), &header, args.compression)?);
                routes.outputs.len() - 1
            },
        );
    }

    // pairtools dedup's statistics have no chromosome sizes (pairtools stats' have).
    let mut counter = args.output_stats.as_ref().map(|_| PairCounter::new());
    let bar = spinner("pairs deduplicated");
    let mut buffers: Vec<Vec<u8>> = vec![Vec::new(); routes.outputs.len()];
    dedup_pairs(
        &mut reader,
        params,
        counter.as_mut(),
        &mut |marked, n_records| {
            for (record, class) in marked {
                let route = match class {
                    PairClass::Unique => routes.unique,
                    PairClass::Duplicate => routes.duplicate,
                    PairClass::Unmapped => routes.unmapped,
                };
                if let Some(route) = route {
                    buffers[route].extend_from_slice(record.line());
                    buffers[route].push(b'\n');
                }
            }
            for (route, buffer) in buffers.iter_mut().enumerate() {
                routes.outputs[route].write_all(buffer)?;
                buffer.clear();
            }
            bar.set_position(n_records);
            Ok(())
        },
    )?;
    bar.finish_and_clear();
    if let (Some(path), Some(counter)) = (&args.output_stats, &counter) {
        write_stats(Some(path), counter)?;
    }
    for output in routes.outputs {
        output.finish()?;
    }
    Ok(())
}
