//! `contactmap score overlap`: two contact predictions compared with each other, without a
//! structure ([`contactmap::score::overlap`]).

use std::path::{Path, PathBuf};

use clap::Args;

use super::lists::ListArgs;
use crate::cli::output::{Output, refuse_overwrites};
use crate::cli::protein::PredictionFormatArg;
use contactmap::error::{Error, Result};
use contactmap::io::predictions::{read_fasta, read_prediction};
use contactmap::score::contacts::ListSize;
use contactmap::score::overlap::{compare_predictions, overlap_text, overlap_tsv};

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
        return Err(Error::Argument(
            "list size NC needs a structure (use `score contacts`)".into(),
        ));
    }
    if args.length == Some(0) {
        return Err(Error::Argument("--length must be positive".into()));
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
    let (first, second) = (args.first.display(), args.second.display());
    let text = if args.tsv {
        overlap_tsv(&first.to_string(), &second.to_string(), &results)
    } else {
        overlap_text(&first.to_string(), &second.to_string(), length, &results)
    };
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(text.as_bytes())?;
    out.finish()
}
