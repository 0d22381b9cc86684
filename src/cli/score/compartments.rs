//! `contactmap score compartments`: compartment eigenvectors against known A/B types
//! ([`contactmap::score::compartments`]).

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::input::file_column;
use crate::cli::output::{Output, column_file, refuse_overwrites};
use contactmap::error::Result;
use contactmap::io::bed::read_bed;
use contactmap::io::tables::read_track;
use contactmap::score::compartments::score_track_table;

/// Arguments of `contactmap score compartments`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
The truth is a BED file whose 4th column is each interval's compartment: A (or a positive
number) or B (or a negative number), e.g. from `simulate polymer --types A200B200
--truth-compartments truth.bed`. Each bin of the eigenvector table (FILE[:COLUMN], default
column E1: the output of `contactmap compartments` or of cooltools eigs-cis) takes the truth of
the interval with the same chromosome, start and end; bins without a truth or with a NaN value
are left out.

Per chromosome and over all bins: n_bins, sign_accuracy (the fraction of bins with E > 0 in A
and E < 0 in B), sign_accuracy_up_to_sign (the better of the vector and its negation: for a
vector oriented without a phasing track) and pearson (the correlation of E with +1 / -1).

Output: a tab-separated table with a header line, one row per chromosome, then `all`.

Examples:
  contactmap simulate polymer -o ab.cool --chains 2000 --density 0.3 \\
      --types A200B200 --attraction 0.4 --monomers-per-bin 10 \\
      --truth-compartments truth.bed
  contactmap balance ab.cool --store
  contactmap compartments ab.cool --phasing-track truth.bed:5 -o ab
  contactmap score compartments --truth truth.bed ab.cis.vecs.tsv")]
pub struct CompartmentsScoreArgs {
    /// True compartments (BED: chrom start end A|B).
    #[arg(long, value_name = "BED")]
    pub truth: PathBuf,
    /// Eigenvector table and column: FILE[:COLUMN] (default column E1).
    #[arg(value_name = "EIGS.tsv[:E1]")]
    pub eigs: String,
    /// Write here instead of standard output (.gz compresses).
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Run `contactmap score compartments`.
pub fn run(args: &CompartmentsScoreArgs) -> Result<()> {
    refuse_overwrites(
        &[args.truth.as_path(), column_file(&args.eigs)],
        &[args.out.as_deref()],
    )?;
    let (path, column) = file_column(&args.eigs, "EIGS", Some("E1"))?;
    let truth = read_bed(&args.truth)?;
    let rows = read_track(Path::new(path), column)?;
    let text = score_track_table(&args.truth, &truth, Path::new(path), &rows)?;
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(text.as_bytes())?;
    out.finish()
}
