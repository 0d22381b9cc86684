//! `contactmap pairs stats`: pairtools' statistics of a pairs file, or several statistics files
//! summed ([`contactmap::pairs::stats`]).

use std::path::PathBuf;

use clap::Args;

use super::shared::{refuse_overwrites, write_stats};
use crate::cli::progress::spinner;
use contactmap::error::{Error, Result};
use contactmap::io::pairs::{PairColumns, PairRecord, open_pairs};
use contactmap::pairs::stats::{PairCounter, STATS_CHUNK_RECORDS};

/// Arguments of `contactmap pairs stats`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
The statistics file is pairtools stats 1.1.2's, line for line (tab-separated `key value`):
totals (total, total_unmapped, total_single_sided_mapped, total_mapped, total_dups,
total_nodups, cis, trans), pair_types/..., cis_1kb+ ... cis_40kb+, the distance histogram per
strand orientation (dist_freq/...), chrom_freq/..., the summary (fractions of cis, of cis beyond
each distance, of duplicates, the library complexity estimate, the distance where the four
orientations converge) and the chromosome sizes of the header. Duplicates are the pairs typed
DD (`contactmap pairs dedup` marks them so).

With --merge the inputs are statistics files, summed as pairtools stats --merge sums them (e.g.
the lanes of one library).

Examples:
  contactmap pairs stats sample.nodups.pairs.gz -o sample.stats
  contactmap pairs stats --merge lane1.stats lane2.stats -o sample.stats")]
pub struct StatsArgs {
    /// A pairs file (`-`: standard input), or with --merge statistics files.
    #[arg(required = true, num_args = 1..)]
    pub inputs: Vec<PathBuf>,
    /// Output; standard output when not given.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Sum statistics files instead of counting pairs.
    #[arg(long)]
    pub merge: bool,
    /// Distance bins per decade of the histogram.
    #[arg(long, default_value_t = 8)]
    pub n_dist_bins_decade: u32,
}

/// Run `contactmap pairs stats`.
pub fn run(args: &StatsArgs) -> Result<()> {
    let inputs: Vec<&std::path::Path> = args.inputs.iter().map(PathBuf::as_path).collect();
    refuse_overwrites(&inputs, &[args.output.as_ref()])?;
    let counter = if args.merge {
        let mut total: Option<PairCounter> = None;
        for path in &args.inputs {
            let mut text = String::new();
            std::io::Read::read_to_string(&mut contactmap::io::open_text(path)?, &mut text)
                .map_err(|e| Error::io(path, e))?;
            let counter = PairCounter::from_text(&text, &path.display().to_string())?;
            match &mut total {
                Some(total) => total.merge(&counter)?,
                None => total = Some(counter),
            }
        }
        total.expect("at least one input")
    } else {
        if args.inputs.len() > 1 {
            return Err(Error::Argument(
                "pairs stats counts one pairs file; pass --merge to sum statistics files".into(),
            ));
        }
        let mut reader = open_pairs(&args.inputs[0])?;
        let columns = PairColumns::of(reader.header(), reader.path())?;
        let mut counter = PairCounter::with_dist_bins_per_decade(args.n_dist_bins_decade)?;
        let bar = spinner("pairs counted");
        let mut record = PairRecord::default();
        while reader.read_record(&mut record)? {
            counter
                .add_record(&record, &columns, None)
                .map_err(|message| reader.error(record.number(), message))?;
            if counter.n_chunk_records() == STATS_CHUNK_RECORDS {
                counter.end_chunk();
                bar.inc(STATS_CHUNK_RECORDS as u64);
                contactmap::interrupt::check()?;
            }
        }
        counter.end_chunk();
        bar.finish_and_clear();
        counter.set_chromsizes(reader.header().chromsizes(reader.path())?);
        counter
    };
    write_stats(args.output.as_deref(), &counter)
}
