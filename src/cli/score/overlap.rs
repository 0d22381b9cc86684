//! `contactmap score overlap`: two contact predictions compared with each other, without a
//! structure ([`contactmap::score::overlap`]).

use std::path::{Path, PathBuf};

use clap::Args;

use super::{aligned, ListArgs};
use crate::cli::output::{refuse_overwrites, Output};
use crate::cli::protein::PredictionFormatArg;
use contactmap::error::{Error, Result};
use contactmap::io::predictions::{read_fasta, read_prediction};
use contactmap::io::tables::real_text as real;
use contactmap::score::contacts::ListSize;
use contactmap::score::overlap::compare_predictions;

/// Arguments of `contactmap score overlap`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Both predictions are prepared as for scoring: pairs made i < j, self pairs and NaN scores
dropped, a pair given twice keeps its highest score, pairs outside the separation range dropped,
the rest sorted by score (descending, ties in file order). For each range and list size the top
k pairs of each are compared as sets: shared = |A and B|, Jaccard = shared / |A or B| (0 when
both are empty). A list with fewer than k pairs in the range is compared as it is.

L is --length, else the length of the target sequence (--fasta, or the sequence the files
carry; two different sequences are an error), else the size of the matrices / distograms. List sizes and ranges are written as for
`score contacts`.

Output: an aligned table; --tsv: one row per range x list size with the header
  first second range min_sep max_sep list k n_first n_second shared jaccard

Examples:
  contactmap score overlap ccmpred.mat trrosetta.npz --fasta t.fasta
  contactmap score overlap a.rr b.rr --ranges long --top L/5,L,100 --tsv")]
pub struct OverlapArgs {
    /// The first prediction.
    #[arg(value_name = "PRED_A")]
    pub first: PathBuf,
    /// The second prediction.
    #[arg(value_name = "PRED_B")]
    pub second: PathBuf,
    /// Target sequence (FASTA, first record): gives L and checks the residue numbers.
    #[arg(long, value_name = "FILE")]
    pub fasta: Option<PathBuf>,
    /// L, the target length (default: the sequence's length).
    #[arg(long, value_name = "N")]
    pub length: Option<usize>,
    /// Prediction format of both files (default: detected from the content of each).
    #[arg(long, value_enum)]
    pub format: Option<PredictionFormatArg>,
    /// Separation ranges and list sizes.
    #[command(flatten)]
    pub lists: ListArgs,
    /// Tab-separated output with a header.
    #[arg(long)]
    pub tsv: bool,
    /// Write here instead of standard output (.gz compresses).
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Run `contactmap score overlap`.
pub fn run(args: &OverlapArgs) -> Result<()> {
    let inputs: Vec<&Path> = [args.first.as_path(), args.second.as_path()]
        .into_iter()
        .chain(args.fasta.as_deref())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let (ranges, sizes) = args.lists.parse()?;
    if sizes
        .iter()
        .any(|(_, size)| *size == ListSize::TrueContacts)
    {
        return Err(Error::Invalid(
            "list size NC needs a structure (use `score contacts`)".into(),
        ));
    }
    if args.length == Some(0) {
        return Err(Error::Invalid("--length must be positive".into()));
    }
    let fasta = args.fasta.as_deref().map(read_fasta).transpose()?;
    let mut predictions = Vec::with_capacity(2);
    for path in [&args.first, &args.second] {
        let mut prediction = read_prediction(path, args.format.map(Into::into))?;
        if let Some(sequence) = &fasta {
            prediction = prediction
                .with_sequence(sequence)
                .map_err(|err| err.in_file(path))?;
        }
        predictions.push(prediction);
    }
    let (length, results) = compare_predictions(
        [
            (&args.first.display().to_string(), &predictions[0]),
            (&args.second.display().to_string(), &predictions[1]),
        ],
        args.length,
        &ranges,
        &sizes,
        args.lists.rounding.into(),
    )?;
    let text = if args.tsv {
        let mut text = String::from(
            "first\tsecond\trange\tmin_sep\tmax_sep\tlist\tk\tn_first\tn_second\tshared\tjaccard\n",
        );
        for (named, label, result) in &results {
            text.push_str(&format!(
                "{}\t{}\t{}\t{}\t{}\t{label}\t{}\t{}\t{}\t{}\t{}\n",
                args.first.display(),
                args.second.display(),
                named.name,
                named.range.min,
                named.range.max_text(),
                result.k,
                result.n_first,
                result.n_second,
                result.shared,
                real(result.jaccard),
            ));
        }
        text
    } else {
        let mut rows = vec![["range", "list", "k", "A", "B", "shared", "Jaccard"]
            .map(String::from)
            .to_vec()];
        for (named, label, result) in &results {
            rows.push(vec![
                named.name.clone(),
                label.to_string(),
                result.k.to_string(),
                result.n_first.to_string(),
                result.n_second.to_string(),
                result.shared.to_string(),
                format!("{:.4}", result.jaccard),
            ]);
        }
        let mut text = format!(
            "A = {}\nB = {}\n  L = {length}\n",
            args.first.display(),
            args.second.display()
        );
        for line in aligned(&rows).lines() {
            text.push_str("  ");
            text.push_str(line);
            text.push('\n');
        }
        text
    };
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(text.as_bytes())?;
    out.finish()
}
