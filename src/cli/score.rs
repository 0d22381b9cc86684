//! `contactmap score`: calls scored against a truth. `score boundaries` compares TAD boundary
//! (and optionally domain) calls with a truth ([`crate::score::boundaries`]). (Protein contact
//! scoring will be other subcommands.)

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};

use crate::cli::output::Output;
use crate::error::{Error, Result};
use crate::io::bed::{read_bed, BedRecord};
use crate::score::boundaries::{domain_overlap, score_boundaries};

/// Arguments of `contactmap score`.
#[derive(Debug, Args)]
pub struct ScoreArgs {
    /// What to score.
    #[command(subcommand)]
    pub command: ScoreCommand,
}

/// The scores.
#[derive(Debug, Subcommand)]
pub enum ScoreCommand {
    /// TAD boundary calls against true boundaries: precision, recall, F1 with a tolerance; with
    /// --truth-domains and --domains also domain Jaccard and the Measure of Concordance.
    Boundaries(BoundariesArgs),
}

/// Arguments of `contactmap score boundaries`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Each boundary (a BED record, truth or call) is placed at its midpoint (start + end) / 2, or at its
start when it is zero-length. A call matches a truth boundary on the same chromosome when they are
at most --tolerance-bins x bin size apart; matching is one-to-one and maximum (a call matches at
most one truth boundary and vice versa). precision = true_positives / n_calls, recall =
true_positives / n_truth, f1 = 2 true_positives / (n_calls + n_truth); a ratio with a zero
denominator is 0.

The bin size is --bin-size, or else the median width of the call intervals (it is needed only when
--tolerance-bins is not 0; zero-width calls cannot give it).

With --truth-domains and --domains (BED: chrom start end, extra columns ignored), three more
columns: mean_best_jaccard_truth (mean over truth domains of the best Jaccard index, in bp, with a
called domain on the same chromosome), mean_best_jaccard_calls (the same from the calls' side) and
moc, the Measure of Concordance of Zufferey et al. 2018 (Genome Biology 19:217), averaged over
chromosomes; moc is `nan` when the domains of either file overlap each other (nested domains:
filter one level first, e.g. `awk '$4 == 0'`).

Output: a tab-separated table with a header line and one row (so that many runs concatenate):
  tolerance_bp n_truth n_calls true_positives precision recall f1
  [mean_best_jaccard_truth mean_best_jaccard_calls moc]

Examples:
  contactmap simulate blocks -o sim.cool --truth-boundaries truth.bed --truth-domains tads.bed
  contactmap score boundaries --truth truth.bed calls.bed
  contactmap score boundaries --truth truth.bed calls.bed --tolerance-bins 2 --bin-size 10000 \\
      --truth-domains tads.bed --domains called_tads.bed -o score.tsv")]
pub struct BoundariesArgs {
    /// True boundaries (BED: chrom start end; e.g. from `simulate blocks --truth-boundaries`).
    #[arg(long, value_name = "BED")]
    pub truth: PathBuf,
    /// Called boundaries (BED: chrom start end; plain or gzip).
    #[arg(value_name = "CALLS.bed")]
    pub calls: PathBuf,
    /// A call matches a truth boundary at most this many bins away.
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub tolerance_bins: u64,
    /// Bin size in bp (default: the median width of the call intervals).
    #[arg(long, value_name = "BP")]
    pub bin_size: Option<u64>,
    /// True domains (BED: chrom start end), for the domain scores; needs --domains.
    #[arg(long, value_name = "BED", requires = "domains")]
    pub truth_domains: Option<PathBuf>,
    /// Called domains (BED: chrom start end); needs --truth-domains.
    #[arg(long, value_name = "BED", requires = "truth_domains")]
    pub domains: Option<PathBuf>,
    /// Write the table here instead of standard output (.gz compresses).
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Run `contactmap score`.
pub fn run(args: &ScoreArgs) -> Result<()> {
    match &args.command {
        ScoreCommand::Boundaries(boundaries) => run_boundaries(boundaries),
    }
}

/// The position of a boundary record: its midpoint, or its start when zero-length.
fn position(record: &BedRecord) -> (String, u64) {
    (
        record.chrom.clone(),
        record.start + (record.end - record.start) / 2,
    )
}

/// The median width of `records` (the upper median for an even count).
fn median_width(records: &[BedRecord]) -> Option<u64> {
    let mut widths: Vec<u64> = records.iter().map(BedRecord::width).collect();
    widths.sort_unstable();
    widths.get(widths.len() / 2).copied().filter(|&w| w > 0)
}

fn intervals(path: &Path) -> Result<Vec<(String, u64, u64)>> {
    Ok(read_bed(path)?
        .into_iter()
        .map(|r| (r.chrom, r.start, r.end))
        .collect())
}

fn run_boundaries(args: &BoundariesArgs) -> Result<()> {
    if args.bin_size == Some(0) {
        return Err(Error::Invalid("--bin-size must be positive".into()));
    }
    let truth = read_bed(&args.truth)?;
    let calls = read_bed(&args.calls)?;
    let tolerance_bp = if args.tolerance_bins == 0 {
        0
    } else {
        let bin_size = match args.bin_size {
            Some(size) => size,
            None => median_width(&calls).ok_or_else(|| {
                Error::format(
                    &args.calls,
                    "cannot infer the bin size from the call intervals (no call, or zero-width \
                     calls): give --bin-size",
                )
            })?,
        };
        args.tolerance_bins.saturating_mul(bin_size)
    };
    let truth_points: Vec<(String, u64)> = truth.iter().map(position).collect();
    let call_points: Vec<(String, u64)> = calls.iter().map(position).collect();
    let m = score_boundaries(&truth_points, &call_points, tolerance_bp);

    let mut header =
        String::from("tolerance_bp\tn_truth\tn_calls\ttrue_positives\tprecision\trecall\tf1");
    let mut row = format!(
        "{tolerance_bp}\t{}\t{}\t{}\t{}\t{}\t{}",
        m.n_truth, m.n_calls, m.true_positives, m.precision, m.recall, m.f1
    );
    if let (Some(truth_path), Some(calls_path)) = (&args.truth_domains, &args.domains) {
        let overlap = domain_overlap(&intervals(truth_path)?, &intervals(calls_path)?);
        header.push_str("\tmean_best_jaccard_truth\tmean_best_jaccard_calls\tmoc");
        let moc = overlap
            .moc
            .map_or_else(|| "nan".to_string(), |v| v.to_string());
        row.push_str(&format!(
            "\t{}\t{}\t{moc}",
            overlap.mean_best_jaccard_truth, overlap.mean_best_jaccard_calls
        ));
    }
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(format!("{header}\n{row}\n").as_bytes())?;
    out.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_and_bin_size_inference() {
        let record = |s, e| BedRecord::new("c", s, e);
        assert_eq!(position(&record(100, 200)).1, 150);
        assert_eq!(position(&record(100, 100)).1, 100);
        assert_eq!(position(&record(100, 101)).1, 100);
        let calls = [record(0, 10), record(20, 40), record(50, 60)];
        assert_eq!(median_width(&calls), Some(10));
        assert_eq!(median_width(&[]), None);
        assert_eq!(median_width(&[record(5, 5)]), None);
    }
}
