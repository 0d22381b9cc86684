//! `contactmap score`: calls scored against a truth. `score boundaries` compares TAD boundary
//! (and optionally domain) calls with a truth ([`contactmap::score::boundaries`]); `score contacts`
//! scores protein residue-contact predictions against a structure
//! ([`contactmap::score::contacts`]).

mod compartments;
mod lists;
mod loops;
mod overlap;

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};

use crate::cli::output::{Output, refuse_overwrites, write_text_file};
use crate::cli::protein::{DefinitionArgs, TargetArgs};
use contactmap::error::{Error, Result};
use contactmap::io::bed::read_bed;
use contactmap::io::frequencies::read_frequency_table;
use contactmap::io::predictions::load_prediction;
use contactmap::score::boundaries::{
    boundary_table, domain_overlap_records, median_width, score_boundary_records,
};
use contactmap::score::contacts::SeparationRange;
use contactmap::score::lists::{NamedRange, parse_length, parse_list_size};
use contactmap::score::target::{
    EnsembleTruth, Placed, ScorePlan, curves_tsv, score_prediction, scores_json, scores_text,
    scores_tsv,
};
use lists::ListArgs;

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
    /// Protein residue-contact predictions against a structure: precision, recall, F1, MCC, Xd
    /// per separation range and top-list size (CASP conventions by default).
    Contacts(Box<ContactsScoreArgs>),
    /// Compartment eigenvectors against known A/B types: sign accuracy and correlation, per
    /// chromosome.
    Compartments(compartments::CompartmentsScoreArgs),
    /// Two contact predictions against each other, without a structure: shared pairs and
    /// Jaccard index of their top lists.
    Overlap(overlap::OverlapArgs),
    /// Loop (dot) calls against true loops: precision, recall, F1 within a tolerance, per
    /// distance class; weak truth loops (held in few samples) left out with --min-fraction.
    Loops(loops::LoopsScoreArgs),
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
  contactmap simulate blocks -o sim.cool --truth-boundaries truth.bed \\
      --truth-domains tads.bed
  contactmap score boundaries --truth truth.bed calls.bed
  contactmap score boundaries --truth truth.bed calls.bed --tolerance-bins 2 \\
      --bin-size 10000 --truth-domains tads.bed --domains called_tads.bed \\
      -o score.tsv")]
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
        ScoreCommand::Contacts(contacts) => run_contacts(contacts),
        ScoreCommand::Compartments(args) => compartments::run(args),
        ScoreCommand::Overlap(args) => overlap::run(args),
        ScoreCommand::Loops(args) => loops::run(args),
    }
}

fn run_boundaries(args: &BoundariesArgs) -> Result<()> {
    if args.bin_size == Some(0) {
        return Err(Error::Argument("--bin-size must be positive".into()));
    }
    let inputs: Vec<&Path> = [args.truth.as_path(), args.calls.as_path()]
        .into_iter()
        .chain(args.truth_domains.as_deref())
        .chain(args.domains.as_deref())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let truth = read_bed(&args.truth)?;
    let calls = read_bed(&args.calls)?;
    let tolerance_bp = if args.tolerance_bins == 0 {
        0
    } else {
        let resolution = match args.bin_size {
            Some(size) => size,
            None => median_width(&calls).ok_or_else(|| {
                Error::format(
                    &args.calls,
                    "cannot infer the bin size from the call intervals (no call, or zero-width \
                     calls): give --bin-size",
                )
            })?,
        };
        args.tolerance_bins.saturating_mul(resolution)
    };
    let m = score_boundary_records(&truth, &calls, tolerance_bp);

    let overlap = match (&args.truth_domains, &args.domains) {
        (Some(truth), Some(calls)) => {
            Some(domain_overlap_records(&read_bed(truth)?, &read_bed(calls)?))
        }
        _ => None,
    };
    let table = boundary_table(tolerance_bp, &m, overlap.as_ref());
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(table.as_bytes())?;
    out.finish()
}

/// Arguments of `contactmap score contacts`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
What is computed (the CASP assessors' method; defaults are CASP's):
  1. True contacts: residues of the chain (first model; author numbering; hetero groups and
     waters ignored; MSE kept as MET) whose Cb atoms (Ca for Gly) are closer than 8 A
     (--atom, --cutoff, --le).
  2. Predicted pairs are made i < j, self pairs and NaN scores dropped, a pair given twice keeps
     its highest score; pairs outside the separation range are dropped, and so are pairs with a
     residue not observed in the structure (unless --keep-unobserved: such a pair then takes a
     slot and is never a true positive). A higher score is a more confident contact.
  3. The rest is sorted by score, descending, stably (ties keep the file's order).
  4. Each list size gives k: L/10 = round(L / 10) with --rounding (default floor), N a count,
     NC the number of true contacts of the range (DISTEVAL's Top-NC). L is the sequence length
     (--fasta, else the sequence the file carries), else the size of a matrix / distogram,
     else the number of observed residues; or --length.
  5. TP = true contacts among the top min(k, available) pairs; precision = TP / min(k,
     available), recall = TP / true contacts of the range, F1, MCC over all observed pairs of
     the range; a ratio with a zero denominator is 0. Xd (CASP, in percent) compares the
     distances of the listed pairs with those of all pairs in 15 bins of 4 A:
     Xd = sum_i (P_i,listed - P_i,all) / i; near 0 for a random list, large for true contacts.
  --curve FILE adds the precision-vs-list-size curve: TP, precision and recall at every k from
  1 to --curve-max (default 2L), one TSV row each.

Register: the prediction numbers residues by their position in its sequence (--fasta, or the
RR file's sequence lines); the structure by its author numbers. With a sequence, the chain is
placed on it (--register auto): the residue numbers are kept when they agree with the sequence
(at least 90% identical residues at those positions), else shifted by the offset an alignment
suggests if that agrees, else each residue takes the position a semi-global alignment gives it
(residues aligned to a gap are left out; insertion codes are handled this way). What was done
is printed on standard error and in the table. --register align always aligns; --register
numbering takes i as the residue with author number i, unchecked. Without a sequence the
numbers are used as they are.

Separation ranges (--ranges, comma separated): short (6-11), medium (12-23), long (>= 24),
all (>= 6), MIN-MAX, or MIN+ (>= MIN); --min-sep N is --ranges N+.
List sizes (--top, comma separated): L/10, L/5, L/2, L, a fraction such as 0.3L or 1.5L, a
count N, or NC.

Output: per prediction, an aligned table (range x list size); --tsv: one row per prediction x
range x list size, with a header:
  prediction range min_sep max_sep list k n_scored tp precision recall f1 mcc xd length
  n_true n_available
(max_sep is `inf` for an open range); --json: an array with one object per prediction.

Examples (formats are detected from the content; --format overrides):
  # CASP RR
  contactmap score contacts --structure 1aap.pdb 1aapA.rr
  # CCMpred matrix
  contactmap score contacts --structure toxd.pdb toxd.mat --fasta toxd.fasta
  # i j score list
  contactmap score contacts --structure 1abc.cif --chain B plmdca.txt \\
      --fasta 1abc.fasta --format table
  # trRosetta
  contactmap score contacts --structure 1guu.pdb 1guu.npz --fasta 1guu.fasta
  contactmap score contacts --structure 1guu.pdb 1guu.predicted.npy \\
      --fasta 1guu.fasta
  contactmap score contacts --structure t.pdb --fasta t.fasta preds/*.rr \\
      --tsv -o scores.tsv
  # against an MD ensemble: pairs in contact in at least 30% of the frames
  contactmap contacts --trajectory run.xtc --topology t.pdb -o freq.tsv
  contactmap score contacts --structure t.pdb --fasta t.fasta t.rr \\
      --frequencies freq.tsv --truth-frequency 0.3

Other tools' conventions:
  ConKit:    --le (d <= 8); its documented toxd example is
             --le --min-sep 5 --top 0.5L,L,1.5L
  ConEVA:    --length observed --rounding half-up --ranges long
  DISTEVAL:  --rounding banker --ranges 12+,24+ --top L/5,NC")]
pub struct ContactsScoreArgs {
    /// The structure, its chain, the target sequence, the prediction format and the register.
    #[command(flatten)]
    pub target: TargetArgs,
    /// Prediction files, scored one by one against the same structure.
    #[arg(value_name = "PRED", required = true)]
    pub predictions: Vec<PathBuf>,
    /// Separation ranges and list sizes.
    #[command(flatten)]
    pub lists: ListArgs,
    /// One range of separations >= N (same as --ranges N+).
    #[arg(long, value_name = "N", conflicts_with = "ranges")]
    pub min_sep: Option<u32>,
    /// L: sequence (the FASTA / RR sequence length), observed (residues observed in the
    /// structure) or a number [default: sequence when there is one, else observed].
    #[arg(long, value_name = "sequence|observed|N")]
    pub length: Option<String>,
    /// Keep pairs with a residue not observed in the structure (they count as false).
    #[arg(long)]
    pub keep_unobserved: bool,
    /// Tab-separated output, one row per prediction x range x list size.
    #[arg(long, conflicts_with = "json")]
    pub tsv: bool,
    /// JSON output.
    #[arg(long)]
    pub json: bool,
    /// Write here instead of standard output (.gz compresses).
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Also write the precision-vs-list-size curve here (TSV: prediction, range, k, k/L, TP,
    /// precision, recall for every k from 1 to --curve-max).
    #[arg(long, value_name = "FILE")]
    pub curve: Option<PathBuf>,
    /// Largest list size of the curve (L/10, 2L, a count N, NC ...).
    #[arg(long, default_value = "2L", value_name = "SIZE", requires = "curve")]
    pub curve_max: String,
    /// The contact definition.
    #[command(flatten)]
    pub definition: DefinitionArgs,
    /// Score against an MD ensemble: the contact frequency table `contactmap contacts
    /// --trajectory` wrote (its topology is --structure, or a structure with the same residue
    /// numbers); a true contact is a pair in contact in at least --truth-frequency of the
    /// frames. The structure still places the residues on the sequence and gives Xd its
    /// distances; pairs the table lacks are unobserved.
    #[arg(long, value_name = "TSV", help_heading = "Truth from an MD ensemble")]
    pub frequencies: Option<PathBuf>,
    /// The smallest fraction of frames of a true contact (with --frequencies) [default: 0.5].
    #[arg(
        long,
        value_name = "F",
        requires = "frequencies",
        help_heading = "Truth from an MD ensemble"
    )]
    pub truth_frequency: Option<f64>,
}

fn run_contacts(args: &ContactsScoreArgs) -> Result<()> {
    let inputs: Vec<&Path> = args
        .target
        .files()
        .chain(args.predictions.iter().map(PathBuf::as_path))
        .chain(args.frequencies.as_deref())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref(), args.curve.as_deref()])?;
    let (mut ranges, sizes) = args.lists.parse()?;
    if let Some(min) = args.min_sep {
        ranges = vec![NamedRange {
            name: format!("{min}+"),
            range: SeparationRange::new(min, None),
        }];
    }
    let length = parse_length(args.length.as_deref())?;
    let curve_size = match &args.curve {
        Some(_) => Some(parse_list_size(&args.curve_max)?.1),
        None => None,
    };
    let plan = ScorePlan {
        ranges,
        sizes,
        length,
        rounding: args.lists.rounding.into(),
        keep_unobserved: args.keep_unobserved,
        curve_size,
    };
    let (fasta, chain) = args.target.read()?;
    let ensemble = args
        .frequencies
        .as_deref()
        .map(|path| {
            EnsembleTruth::new(
                path,
                read_frequency_table(path)?,
                args.truth_frequency.unwrap_or(0.5),
            )
        })
        .transpose()?;
    let definition = match &ensemble {
        Some(ensemble) => ensemble.describe(&args.definition.definition()),
        None => args.definition.describe(),
    };
    // One placement per distinct sequence (usually one for all predictions).
    let mut placements: Vec<(Option<String>, Placed)> = Vec::new();
    let mut reports = Vec::with_capacity(args.predictions.len());
    // --tsv streams: each prediction's rows are written as soon as it is scored
    let mut out = Output::open(args.out.as_deref())?;
    let mut warnings = crate::cli::warnings::Warnings::new();
    for path in &args.predictions {
        let prediction =
            load_prediction(path, args.target.format.map(Into::into), fasta.as_deref())?;
        let index = match placements
            .iter()
            .position(|(sequence, _)| *sequence == prediction.sequence)
        {
            Some(index) => index,
            None => {
                let mut placed = args
                    .target
                    .place(&chain, &prediction, path, &args.definition)?;
                if let Some(ensemble) = &ensemble {
                    ensemble.apply(&args.target.structure, &chain, &mut placed)?;
                }
                warnings.extend(placed.warning.take());
                // The table shows the register; other outputs get it on standard error.
                let table_on_stdout = !(args.tsv || args.json || args.out.is_some());
                if let Some(register) = placed.register.as_ref().filter(|_| !table_on_stdout) {
                    eprintln!("{}: {}", path.display(), register.text);
                }
                placements.push((prediction.sequence.clone(), placed));
                placements.len() - 1
            }
        };
        let report = score_prediction(path, &prediction, &placements[index].1, &plan)?;
        if args.tsv && !args.json {
            let rows = scores_tsv(std::slice::from_ref(&report));
            let rows = if reports.is_empty() {
                rows.as_str()
            } else {
                rows.split_once('\n').map_or("", |(_, rest)| rest)
            };
            out.write_all(rows.as_bytes())?;
            out.flush()?;
        }
        reports.push(report);
    }
    if args.json {
        let text = scores_json(
            &args.target.structure.display().to_string(),
            &definition,
            &reports,
        );
        out.write_all(text.as_bytes())?;
    } else if !args.tsv {
        let text = scores_text(
            &args.target.structure.display().to_string(),
            &chain.id,
            &definition,
            &plan,
            &reports,
        );
        out.write_all(text.as_bytes())?;
    }
    if let Some(path) = &args.curve {
        write_text_file(path, curves_tsv(&reports))?;
    }
    out.finish()?;
    warnings.print();
    Ok(())
}
