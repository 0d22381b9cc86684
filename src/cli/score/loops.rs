//! `contactmap score loops`: dot calls against true loops ([`contactmap::score::loops`]).

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::input::bp_option;
use crate::cli::output::{Output, refuse_overwrites};
use contactmap::error::{Error, Result};
use contactmap::io::bed::read_bedpe;
use contactmap::score::loops::{Loop, LoopScoreParams, loop_score_table, score_loops};

/// Arguments of `contactmap score loops`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Each loop (a BEDPE record: chrom1 start1 end1 chrom2 start2 end2 ..., truth or call; a header
line is skipped) is placed at the midpoints of its two anchors. A call matches a truth loop on
the same chromosomes when both anchors are at most --tolerance apart; matching is one-to-one and
maximum.

With --min-fraction F the truth needs a 7th column, the fraction of samples that held each loop
(`simulate polymer --truth-loops` writes it): loops held less often are weak. Recall counts only
the others; a call that matches no strong loop but lies near a weak one is left out of precision
(neither true nor false). precision = calls_matched / (n_calls - n_weak_calls), recall =
truth_matched / n_truth, f1 their harmonic mean; per distance class (the anchors' separation:
of the truth loop for recall, of the call for precision), then `trans`, then all.

Output: a tab-separated table with a header line:
  class tolerance_bp min_fraction n_truth n_calls n_weak_calls truth_matched calls_matched
  precision recall f1

Examples:
  contactmap simulate polymer -o loops.cool --chains 4000 --density 0.2 \\
      --extrusion --ctcf 500+,1000-,1500+,2000- --monomers-per-bin 10 \\
      --truth-loops truth.bedpe
  contactmap balance loops.cool --store
  contactmap dots loops.cool --w 3 --p 1 -o dots.bedpe
  contactmap score loops --truth truth.bedpe dots.bedpe --tolerance 20k \\
      --min-fraction 0.2")]
pub struct LoopsScoreArgs {
    /// True loops (BEDPE; with --min-fraction its 7th column is each loop's fraction of samples).
    #[arg(long, value_name = "BEDPE")]
    pub truth: PathBuf,
    /// Called loops (BEDPE, e.g. `contactmap dots` or cooltools dots output; plain or gzip).
    #[arg(value_name = "CALLS.bedpe")]
    pub calls: PathBuf,
    /// A call matches a truth loop when both anchors are at most this far apart (bp; 10k, 1M).
    #[arg(long, default_value = "20k", value_name = "BP")]
    pub tolerance: String,
    /// Truth loops held in a smaller fraction of samples are weak (needs the 7th column).
    #[arg(long, value_name = "F")]
    pub min_fraction: Option<f64>,
    /// Edges of the distance classes (bp, from 0, increasing).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0,100k,1M",
        value_name = "BP,..."
    )]
    pub distance_classes: Vec<String>,
    /// Write the table here instead of standard output (.gz compresses).
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Run `contactmap score loops`.
pub fn run(args: &LoopsScoreArgs) -> Result<()> {
    refuse_overwrites(
        &[args.truth.as_path(), args.calls.as_path()],
        &[args.out.as_deref()],
    )?;
    let params = LoopScoreParams {
        tolerance_bp: bp_option("--tolerance", &args.tolerance)?,
        min_fraction: args.min_fraction.unwrap_or(0.0),
        distance_edges: args
            .distance_classes
            .iter()
            .map(|text| bp_option("--distance-classes", text))
            .collect::<Result<_>>()?,
    };
    let read = |path: &PathBuf, weighted: bool| -> Result<Vec<Loop>> {
        let source = path.display().to_string();
        read_bedpe(path)?
            .iter()
            .map(|record| Loop::from_record(record, weighted, &source))
            .collect()
    };
    let truth = read(&args.truth, args.min_fraction.is_some())?;
    let calls = read(&args.calls, false)?;
    check_shared_chroms(&truth, &calls, &args.truth, &args.calls)?;
    let rows = score_loops(&truth, &calls, &params)?;
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(loop_score_table(&rows, params.tolerance_bp, params.min_fraction).as_bytes())?;
    out.finish()
}

/// An error when the calls and the truth share no chromosome name (nothing could match: a
/// `chr` prefix on one side only, say), naming both files' chromosomes and the prefix.
fn check_shared_chroms(
    truth: &[Loop],
    calls: &[Loop],
    truth_path: &Path,
    calls_path: &Path,
) -> Result<()> {
    let names = |loops: &[Loop]| -> Vec<String> {
        let mut names: Vec<String> = Vec::new();
        for l in loops {
            for chrom in [&l.chrom1, &l.chrom2] {
                if !names.contains(chrom) {
                    names.push(chrom.clone());
                }
            }
        }
        names
    };
    let (in_truth, in_calls) = (names(truth), names(calls));
    if in_truth.is_empty() || in_calls.is_empty() || in_calls.iter().any(|c| in_truth.contains(c)) {
        return Ok(());
    }
    let bare = |name: &str| name.strip_prefix("chr").unwrap_or(name).to_string();
    let prefix = in_calls
        .iter()
        .any(|c| in_truth.iter().any(|t| bare(t) == bare(c)));
    let hint = if prefix {
        ": the names differ by the 'chr' prefix (rename them in one file, e.g. with sed \
         's/^chr//')"
    } else {
        ""
    };
    let show = |names: &[String]| names.iter().take(5).cloned().collect::<Vec<_>>().join(", ");
    Err(Error::Data(format!(
        "{} and {} share no chromosome ({} against {}), so no call can match{hint}",
        calls_path.display(),
        truth_path.display(),
        show(&in_calls),
        show(&in_truth)
    )))
}
