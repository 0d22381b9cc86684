//! `contactmap score compartments`: compartment eigenvectors against known A/B types
//! ([`contactmap::score::compartments`]).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::input::file_column;
use crate::cli::output::{column_file, refuse_overwrites, Output};
use contactmap::error::{Error, Result};
use contactmap::io::bed::read_bed;
use contactmap::io::tables::read_track;
use contactmap::io::tables::real_text as real;
use contactmap::score::compartments::score_compartments;

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
    let mut truth: HashMap<(String, u64, u64), f64> = HashMap::new();
    for record in read_bed(&args.truth)? {
        let name = record.name.as_deref().unwrap_or("");
        let sign = match name.to_ascii_uppercase().as_str() {
            "A" => 1.0,
            "B" => -1.0,
            other => match other.parse::<f64>() {
                Ok(v) if v != 0.0 && v.is_finite() => v.signum(),
                _ => {
                    return Err(Error::format(
                        &args.truth,
                        format!(
                        "{}:{}-{}: the 4th column must be A, B or a signed number, found '{name}'",
                        record.chrom, record.start, record.end
                    ),
                    ))
                }
            },
        };
        truth.insert((record.chrom.clone(), record.start, record.end), sign);
    }
    let (path, column) = file_column(&args.eigs, "EIGS", Some("E1"))?;
    let rows = read_track(Path::new(path), column)?;
    let mut chroms: Vec<String> = Vec::new();
    let mut by_chrom: HashMap<String, (Vec<f64>, Vec<f64>)> = HashMap::new();
    let mut matched = 0usize;
    for row in &rows {
        let t = truth
            .get(&(row.chrom.clone(), row.start, row.end))
            .copied()
            .unwrap_or(f64::NAN);
        matched += t.is_finite() as usize;
        let entry = by_chrom.entry(row.chrom.clone()).or_insert_with(|| {
            chroms.push(row.chrom.clone());
            (Vec::new(), Vec::new())
        });
        entry.0.push(row.value);
        entry.1.push(t);
    }
    if matched == 0 {
        return Err(Error::format(
            path,
            format!(
                "no bin of the table is an interval of {} (the truth must be on the same bins)",
                args.truth.display()
            ),
        ));
    }
    let mut text =
        String::from("chrom\tn_bins\tsign_accuracy\tsign_accuracy_up_to_sign\tpearson\n");
    let (mut all_v, mut all_t) = (Vec::new(), Vec::new());
    let mut line = |name: &str, values: &[f64], t: &[f64]| {
        let s = score_compartments(values, t);
        text.push_str(&format!(
            "{name}\t{}\t{}\t{}\t{}\n",
            s.n_bins,
            real(s.sign_accuracy),
            real(s.sign_accuracy_up_to_sign),
            real(s.pearson)
        ));
    };
    for chrom in &chroms {
        let (v, t) = &by_chrom[chrom];
        line(chrom, v, t);
        all_v.extend_from_slice(v);
        all_t.extend_from_slice(t);
    }
    line("all", &all_v, &all_t);
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(text.as_bytes())?;
    out.finish()
}
