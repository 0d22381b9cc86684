//! A target structure and the predictions scored against it, the steps `score contacts`,
//! `score overlap`, `plot contacts` and `contacts` share: read the chain, place it on a
//! prediction's sequence (the register), measure its true contacts, load predictions, score
//! each one over ranges and list sizes, and write the scores as TSV.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::contacts::{
    ContactDefinition, ContactScore, Prediction, ScoreParams, TrueContacts, score_contacts,
};
use super::lists::{LengthChoice, NamedRange};
use super::register::{Register, RegisterMethod, RegisterMode, register};
use crate::error::{Error, Result};
use crate::io::frequencies::{FrequencyResidue, FrequencyRow};
use crate::io::structure::{Chain, amino_acid, chain_label};
use crate::io::tables::real_text;
use crate::score::contacts::{ListSize, Rounding, SeparationRange};
use crate::score::frequency::BLANK_CHAIN;

/// How the structure's residues are placed on a prediction's sequence.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RegisterChoice {
    /// The residue numbers when they agree with the sequence (also with an offset), else a
    /// sequence alignment.
    #[default]
    Auto,
    /// Always a sequence alignment.
    Align,
    /// The residue numbers as they are, unchecked.
    Numbering,
}

/// Without a sequence (no --fasta, none in the prediction's file) the prediction's residue numbers
/// are taken as the structure's. Refuse when they cannot be: structure residues numbered below 1,
/// or past the length the prediction's shape gives (a matrix, a distogram), or no residue of the
/// prediction in the structure. Return a warning when more than a tenth of the prediction's
/// residues are not in the structure (unobserved ends, or a prediction of another protein).
pub fn check_numbering(
    structure: &Path,
    chain: &Chain,
    prediction: &Prediction,
    path: &Path,
) -> Result<Option<String>> {
    let numbers = chain.residues.iter().map(|r| r.number);
    let (Some(first), Some(last)) = (numbers.clone().min(), numbers.max()) else {
        return Ok(None);
    };
    let largest = prediction
        .pairs
        .iter()
        .map(|&(i, j, _)| i.max(j))
        .max()
        .unwrap_or(0);
    let length = prediction.length.unwrap_or(largest as usize);
    let fix = "give the prediction's sequence with --fasta, and the chain is aligned to it";
    let what = format!(
        "chain {} of {} has {} residues numbered {first}-{last}",
        chain.id,
        structure.display(),
        chain.residues.len()
    );
    let refuse = |why: String| {
        Err(Error::format(
            path,
            format!(
                "{why}: without a sequence the prediction's numbers are the structure's; {fix}"
            ),
        ))
    };
    if first < 1 || (prediction.length.is_some() && last as usize > length) {
        return refuse(format!(
            "the prediction covers residues 1-{length} but {what}"
        ));
    }
    let observed: std::collections::HashSet<i32> =
        chain.residues.iter().map(|r| r.number).collect();
    if !prediction.pairs.is_empty()
        && !prediction
            .pairs
            .iter()
            .any(|(i, j, _)| observed.contains(i) || observed.contains(j))
    {
        return refuse(format!(
            "no residue of the prediction (1-{length}) is in the structure: {what}"
        ));
    }
    // Structures often miss a few terminal residues: more than a tenth of the prediction is
    // worth a word.
    let missing = (1..=length as i32)
        .filter(|n| !observed.contains(n))
        .count();
    if prediction.length.is_some() && missing * 10 > length {
        return Ok(Some(format!(
            "{}: the prediction covers {length} residues but {what}: {missing} of its residues \
             are not in the structure and are scored as unobserved. If the prediction is for \
             another sequence, {fix}",
            path.display()
        )));
    }
    Ok(None)
}

/// The chain with its residues numbered by their position in `sequence` (see
/// [`crate::score::register`]), and the register; the chain unchanged without a sequence or
/// with [`RegisterChoice::Numbering`].
pub fn place_chain(
    structure: &Path,
    chain: &Chain,
    sequence: Option<&str>,
    mode: RegisterChoice,
) -> Result<(Chain, Option<Register>)> {
    let mode = match (sequence, mode) {
        (None, _) | (_, RegisterChoice::Numbering) => return Ok((chain.clone(), None)),
        (Some(_), RegisterChoice::Auto) => RegisterMode::Auto,
        (Some(_), RegisterChoice::Align) => RegisterMode::Alignment,
    };
    let register = register(chain, sequence.unwrap_or_default(), mode)
        .map_err(|err| err.in_file(structure))?;
    Ok((register.renumber(chain), Some(register)))
}

/// The true contacts of a chain read from `structure`.
pub fn measure(
    structure: &Path,
    chain: &Chain,
    definition: &ContactDefinition,
) -> Result<TrueContacts> {
    TrueContacts::from_chain(chain, *definition).map_err(|err| err.in_file(structure))
}

/// What the register step did, for the outputs.
#[derive(Clone, Debug)]
pub struct RegisterSummary {
    /// `numbering` or `alignment`.
    pub method: &'static str,
    /// The offset of a numbering register.
    pub offset: Option<i32>,
    /// Residues placed on the sequence.
    pub placed: usize,
    /// Placed residues identical to the sequence.
    pub identical: usize,
    /// Residues of the chain.
    pub residues: usize,
    /// The description printed for the user.
    pub text: String,
}

/// The chain placed on one sequence, and its true contacts.
pub struct Placed {
    /// The true contacts, in the sequence's numbering when there is a sequence.
    pub truth: TrueContacts,
    /// What the register step did, when there was one.
    pub register: Option<RegisterSummary>,
    /// A warning about the numbering ([`check_numbering`]), printed once the command succeeded.
    pub warning: Option<String>,
    /// For each residue of the chain as read, its number in the truth's numbering (`None`: not
    /// placed on the sequence).
    pub numbers: Vec<Option<i32>>,
}

/// Place `chain` (read from `structure`) on `sequence` as `mode` says ([`place_chain`]) and
/// measure its true contacts; without a sequence, a chain whose numbers are not unique asks
/// for one.
pub fn place(
    structure: &Path,
    chain: &Chain,
    sequence: Option<&str>,
    mode: RegisterChoice,
    definition: &ContactDefinition,
) -> Result<Placed> {
    let (placed, register) = place_chain(structure, chain, sequence, mode)?;
    let numbers = match &register {
        Some(register) => {
            let mut numbers = vec![None; chain.residues.len()];
            for &(position, index) in &register.pairs {
                numbers[index] = Some(position as i32);
            }
            numbers
        }
        None => chain.residues.iter().map(|r| Some(r.number)).collect(),
    };
    let truth = measure(structure, &placed, definition).map_err(|err| match err {
        Error::Invalid(message) if sequence.is_none() => Error::Data(format!(
            "{message} (give the target sequence with --fasta to place the residues on it)"
        )),
        other => other,
    })?;
    Ok(Placed {
        truth,
        register: register.map(|register| RegisterSummary {
            method: match register.method {
                RegisterMethod::Numbering { .. } => "numbering",
                RegisterMethod::Alignment => "alignment",
            },
            offset: match register.method {
                RegisterMethod::Numbering { offset } => Some(offset),
                RegisterMethod::Alignment => None,
            },
            placed: register.pairs.len(),
            identical: register.identical,
            residues: register.n_residues,
            text: register.describe(chain),
        }),
        warning: None,
        numbers,
    })
}

/// The truth of an MD ensemble: a contact frequency table (`contactmap contacts --trajectory`)
/// and the smallest fraction of frames of a true contact.
#[derive(Clone, Debug)]
pub struct EnsembleTruth {
    /// The table's file, named in messages.
    pub path: PathBuf,
    /// Its rows.
    pub rows: Vec<FrequencyRow>,
    /// A pair is a true contact when in contact in at least this fraction of the frames.
    pub threshold: f64,
}

impl EnsembleTruth {
    /// The rows of the frequency table at `path` (read by
    /// [`read_frequency_table`](crate::io::frequencies::read_frequency_table); `path` is named in
    /// messages); `threshold` in `(0, 1]`.
    pub fn new(path: &Path, rows: Vec<FrequencyRow>, threshold: f64) -> Result<Self> {
        if !(threshold > 0.0 && threshold <= 1.0) {
            return Err(Error::Argument(format!(
                "--truth-frequency must be a fraction of frames above 0 and at most 1, got \
                 {threshold}"
            )));
        }
        Ok(EnsembleTruth {
            path: path.to_path_buf(),
            rows,
            threshold,
        })
    }

    /// Replace the contacts of `placed` (the chain `chain` of `structure`, placed) by the
    /// ensemble's: the table's rows of the chain, matched to its residues by author number
    /// and insertion code, names checked. Pairs with a residue the structure lacks are
    /// unmeasured (a warning when they are more than a tenth of the chain's rows).
    pub fn apply(&self, structure: &Path, chain: &Chain, placed: &mut Placed) -> Result<()> {
        // a blank chain is written `A` (frequency::BLANK_CHAIN); tables of earlier versions
        // left it empty
        let blank = chain.id.is_empty();
        let rows: Vec<&FrequencyRow> = self
            .rows
            .iter()
            .filter(|r| r.chain == chain.id || (blank && r.chain == BLANK_CHAIN))
            .collect();
        if rows.is_empty() {
            let mut chains: Vec<&str> = self.rows.iter().map(|r| chain_label(&r.chain)).collect();
            chains.dedup();
            return Err(Error::format(
                &self.path,
                format!(
                    "no residue pair of chain {} of {} (the table's chains: {}): choose the \
                     chain with --chain",
                    chain_label(&chain.id),
                    structure.display(),
                    chains.join(", ")
                ),
            ));
        }
        let index: HashMap<(i32, Option<char>), usize> = chain
            .residues
            .iter()
            .enumerate()
            .map(|(k, r)| ((r.number, r.insertion), k))
            .collect();
        let placed_number = |row: &FrequencyRow, residue: &FrequencyResidue| {
            let Some(&k) = index.get(&(residue.number, residue.insertion)) else {
                return Ok(None);
            };
            let name = amino_acid(&residue.name).map_or(residue.name.as_str(), |(n, _)| n);
            let ours = &chain.residues[k];
            if name != ours.name {
                return Err(Error::parse(
                    &self.path,
                    row.line,
                    format!(
                        "residue {}{} is {} here but {} in chain {} of {}: the table was \
                         computed on another topology",
                        residue.number,
                        residue.insertion.map(String::from).unwrap_or_default(),
                        residue.name,
                        ours.name,
                        chain_label(&chain.id),
                        structure.display()
                    ),
                ));
            }
            Ok(placed.numbers[k])
        };
        let mut missing = 0;
        let mut pairs = Vec::with_capacity(rows.len());
        for row in &rows {
            let first = placed_number(row, &row.residue1)?;
            let second = placed_number(row, &row.residue2)?;
            match (first, second) {
                (Some(i), Some(j)) => pairs.push((i, j, row.frequency)),
                _ => missing += 1,
            }
        }
        if pairs.is_empty() {
            return Err(Error::format(
                &self.path,
                format!(
                    "none of the table's pairs of chain {} has both residues in {}: the table \
                     was computed on another topology",
                    chain_label(&chain.id),
                    structure.display()
                ),
            ));
        }
        if missing * 10 > rows.len() {
            let warning = format!(
                "{}: {missing} of the table's {} pairs of chain {} have a residue that {} lacks \
                 (or that is not placed on the sequence); they are scored as unobserved",
                self.path.display(),
                rows.len(),
                chain_label(&chain.id),
                structure.display()
            );
            placed.warning = Some(match placed.warning.take() {
                Some(before) => format!("{before}\n{warning}"),
                None => warning,
            });
        }
        placed.truth = placed
            .truth
            .clone()
            .with_frequencies(pairs, self.threshold)?;
        Ok(())
    }

    /// What the truth is, for the outputs.
    pub fn describe(&self, definition: &ContactDefinition) -> String {
        format!(
            "in >= {} of the frames of {} (Xd distances: {})",
            real_text(self.threshold),
            self.path.display(),
            definition.describe()
        )
    }
}

/// [`place`] the chain on the sequence of `prediction` (read from `path`, named in errors);
/// without a sequence, [`check_numbering`] first, its warning in [`Placed::warning`].
///
/// ```
/// use contactmap::score::contacts::ContactDefinition;
/// use contactmap::io::{predictions::load_prediction, structure::read_chain};
/// use contactmap::score::target::{place_prediction, RegisterChoice};
/// use std::path::Path;
/// let (structure, rr) = (Path::new("data/protein/1aapA/1aapA.pdb.gz"), Path::new("data/protein/1aapA/1aapA.rr.gz"));
/// let chain = read_chain(structure, None)?;
/// let prediction = load_prediction(rr, None, None)?;
/// let placed = place_prediction(structure, &chain, &prediction, rr, RegisterChoice::Auto, &ContactDefinition::default())?;
/// assert!(placed.truth.n_observed() > 50 && placed.warning.is_none());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn place_prediction(
    structure: &Path,
    chain: &Chain,
    prediction: &Prediction,
    path: &Path,
    mode: RegisterChoice,
    definition: &ContactDefinition,
) -> Result<Placed> {
    let warning = match prediction.sequence {
        None => check_numbering(structure, chain, prediction, path)?,
        Some(_) => None,
    };
    let mut placed = place(
        structure,
        chain,
        prediction.sequence.as_deref(),
        mode,
        definition,
    )
    .map_err(|err| err.in_file(path))?;
    placed.warning = warning;
    Ok(placed)
}

/// The scores of one prediction.
#[derive(Clone, Debug)]
pub struct PredictionScores {
    /// The prediction's file.
    pub path: String,
    /// Where L comes from (`sequence`, `matrix size`, `observed`, `given`).
    pub length_source: &'static str,
    /// Observed residues of the chain as placed on the sequence.
    pub n_observed: usize,
    /// What the register step did, when there was one.
    pub register: Option<RegisterSummary>,
    /// Per separation range: the range, the labels of the list sizes, and the scores.
    pub scores: Vec<(NamedRange, Vec<String>, ContactScore)>,
}

/// What to compute for each prediction.
#[derive(Clone, Debug)]
pub struct ScorePlan {
    /// Separation ranges.
    pub ranges: Vec<NamedRange>,
    /// List sizes with their labels.
    pub sizes: Vec<(String, ListSize)>,
    /// What L is.
    pub length: LengthChoice,
    /// Rounding of `L * fraction`.
    pub rounding: Rounding,
    /// Keep pairs with a residue the structure does not have (they take a slot and are never
    /// true).
    pub keep_unobserved: bool,
    /// The largest list of the precision curve, when one is wanted.
    pub curve_size: Option<ListSize>,
}

/// Score `prediction` (read from `path`, named in errors) against the chain `placed` on its
/// sequence, over every range and list size of `plan`.
pub fn score_prediction(
    path: &Path,
    prediction: &Prediction,
    placed: &Placed,
    plan: &ScorePlan,
) -> Result<PredictionScores> {
    let ScorePlan {
        ranges,
        sizes,
        length,
        curve_size,
        rounding,
        keep_unobserved,
    } = plan;
    let (target_length, length_source) = length.resolve(prediction);
    let labels: Vec<String> = sizes.iter().map(|(label, _)| label.clone()).collect();
    let mut scores = Vec::with_capacity(ranges.len());
    for named in ranges {
        let params = ScoreParams {
            range: named.range,
            length: target_length,
            rounding: *rounding,
            list_sizes: sizes.iter().map(|(_, size)| *size).collect(),
            drop_unobserved: !keep_unobserved,
            curve: *curve_size,
        };
        let score =
            score_contacts(&placed.truth, prediction, &params).map_err(|err| err.in_file(path))?;
        scores.push((named.clone(), labels.clone(), score));
    }
    Ok(PredictionScores {
        path: path.display().to_string(),
        length_source,
        n_observed: placed.truth.n_observed(),
        register: placed.register.clone(),
        scores,
    })
}

/// The scores as TSV, one row per prediction x range x list size, with a header:
/// `prediction range min_sep max_sep list k n_scored tp precision recall f1 mcc xd length
/// n_true n_available` (`max_sep` is `inf` for an open range).
pub fn scores_tsv(reports: &[PredictionScores]) -> String {
    let mut text = String::from(
        "prediction\trange\tmin_sep\tmax_sep\tlist\tk\tn_scored\ttp\tprecision\trecall\tf1\tmcc\
         \txd\tlength\tn_true\tn_available\n",
    );
    for report in reports {
        for (named, labels, score) in &report.scores {
            for (label, list) in labels.iter().zip(&score.lists) {
                text.push_str(&format!(
                    "{}\t{}\t{}\t{}\t{label}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\n",
                    report.path,
                    named.name,
                    named.range.min,
                    named.range.max_text(),
                    list.k,
                    list.n_scored,
                    list.true_positives,
                    real_text(list.precision),
                    real_text(list.recall),
                    real_text(list.f1),
                    real_text(list.mcc),
                    real_text(list.xd),
                    score.length,
                    score.n_true,
                    score.n_available,
                ));
            }
        }
    }
    text
}

/// The precision curves as TSV: one row per prediction x range x list size k.
pub fn curves_tsv(reports: &[PredictionScores]) -> String {
    let mut text = String::from("prediction\trange\tk\tk_over_l\ttp\tprecision\trecall\n");
    for report in reports {
        for (named, _, score) in &report.scores {
            for (index, &tp) in score.curve.iter().enumerate() {
                let k = index + 1;
                text.push_str(&format!(
                    "{}\t{}\t{k}\t{}\t{tp}\t{}\t{}\n",
                    report.path,
                    named.name,
                    real_text(k as f64 / score.length.max(1) as f64),
                    real_text(tp as f64 / k as f64),
                    real_text(if score.n_true == 0 {
                        0.0
                    } else {
                        tp as f64 / score.n_true as f64
                    }),
                ));
            }
        }
    }
    text
}

/// The scores as the aligned text table `score contacts` prints by default: per prediction, a
/// header (the `structure` and `chain` it was scored against, the observed residues, the contact
/// `definition`, L and where it comes from, the rounding, what was done with unobserved pairs,
/// the register) and one row per range x list size.
///
/// ```
/// use contactmap::score::contacts::{ContactDefinition, Rounding};
/// use contactmap::score::lists::{parse_length, parse_list_size, parse_range};
/// use contactmap::io::{predictions::load_prediction, structure::read_chain};
/// use contactmap::score::target::*;
/// use std::path::Path;
/// let (structure, rr) = (Path::new("data/protein/1aapA/1aapA.pdb.gz"), Path::new("data/protein/1aapA/1aapA.rr.gz"));
/// let chain = read_chain(structure, None)?;
/// let prediction = load_prediction(rr, None, None)?;
/// let definition = ContactDefinition::default();
/// let placed = place_prediction(structure, &chain, &prediction, rr, RegisterChoice::Auto, &definition)?;
/// let plan = ScorePlan {
///     ranges: vec![parse_range("long")?],
///     sizes: vec![parse_list_size("L/5")?],
///     length: parse_length(None)?,
///     rounding: Rounding::Floor,
///     keep_unobserved: false,
///     curve_size: None,
/// };
/// let report = score_prediction(rr, &prediction, &placed, &plan)?;
/// let text = scores_text("1aapA.pdb.gz", &chain.id, &definition.describe(), &plan, &[report]);
/// assert!(text.contains("precision") && text.contains("long"));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn scores_text(
    structure: &str,
    chain: &str,
    definition: &str,
    plan: &ScorePlan,
    reports: &[PredictionScores],
) -> String {
    let mut text = String::new();
    for (index, report) in reports.iter().enumerate() {
        if index > 0 {
            text.push('\n');
        }
        let length = report
            .scores
            .first()
            .map_or(0, |(_, _, score)| score.length);
        text.push_str(&format!(
            "{}\n  structure {} chain {}: {} observed residues; contacts {}\n  L = {length} ({}), \
             rounding {}, unobserved pairs {}\n",
            report.path,
            structure,
            chain_label(chain),
            report.n_observed,
            definition,
            report.length_source,
            plan.rounding.name(),
            if plan.keep_unobserved {
                "kept"
            } else {
                "dropped"
            },
        ));
        match &report.register {
            Some(register) => {
                for line in register.text.lines() {
                    text.push_str("  ");
                    text.push_str(line.trim_start());
                    text.push('\n');
                }
            }
            None => {
                text.push_str("  register: none (the prediction's numbers are the structure's)\n")
            }
        }
        let mut rows = vec![
            [
                "range",
                "sep",
                "true",
                "avail",
                "list",
                "k",
                "TP",
                "precision",
                "recall",
                "F1",
                "MCC",
                "Xd",
            ]
            .map(String::from)
            .to_vec(),
        ];
        for (named, labels, score) in &report.scores {
            let separation = match named.range.max {
                Some(max) => format!("{}-{max}", named.range.min),
                None => format!(">={}", named.range.min),
            };
            for (label, list) in labels.iter().zip(&score.lists) {
                rows.push(vec![
                    named.name.clone(),
                    separation.clone(),
                    score.n_true.to_string(),
                    score.n_available.to_string(),
                    label.clone(),
                    list.k.to_string(),
                    list.true_positives.to_string(),
                    format!("{:.4}", list.precision),
                    format!("{:.4}", list.recall),
                    format!("{:.4}", list.f1),
                    format!("{:.4}", list.mcc),
                    format!("{:.2}", list.xd),
                ]);
            }
        }
        for line in crate::io::tables::aligned(&rows).lines() {
            text.push_str("  ");
            text.push_str(line);
            text.push('\n');
        }
    }
    text
}

/// The RR sequence line of a chain without a target sequence, and the offset to subtract from
/// the structure's numbers to get the RR's positions in it.
///
/// The structure's numbers are the positions when they can be: the line runs from residue 1 to
/// the last, `X` where a number is not observed (toxd, numbered from 2: one `X`, its unobserved
/// first residue). When the chain is numbered from below 1, or from so far on that the line would
/// hold more `X` before the chain than residues (1A8O, numbered 151-220: the C-terminal domain
/// of a longer protein), the numbers are not positions in a sequence we know: the line is the
/// chain's own, numbered from 1 at its first residue.
fn sequence_line(chain: &Chain) -> Option<(String, i32)> {
    let first = chain.residues.iter().map(|r| r.number).min()?;
    let last = chain.residues.iter().map(|r| r.number).max()?;
    let offset = if first < 1 || (first - 1) as usize > chain.residues.len() {
        first - 1
    } else {
        0
    };
    let mut sequence = vec!['X'; (last - offset) as usize];
    for residue in chain.residues.iter().filter(|r| r.insertion.is_none()) {
        sequence[(residue.number - offset - 1) as usize] = residue.one_letter;
    }
    Some((sequence.into_iter().collect(), offset))
}

/// The true contacts of `chain` as CASP RR rows, what `contactmap contacts` writes: a sequence
/// line (`sequence`, when the chain was placed on one, else the chain's own), then
/// `i j 0 cutoff 1` for every contact at least `min_sep` apart. Returns the text and the offset
/// subtracted from the structure's numbers (0 unless the chain's numbers are not positions in a
/// sequence: numbered from below 1, or from so far on that the line would hold more `X` than
/// residues).
///
/// ```
/// use contactmap::score::contacts::ContactDefinition;
/// use contactmap::io::structure::read_chain;
/// use contactmap::score::target::{measure, true_contacts_rr};
/// use std::path::Path;
/// let path = Path::new("data/protein/1aapA/1aapA.pdb.gz");
/// let chain = read_chain(path, None)?;
/// let truth = measure(path, &chain, &ContactDefinition::default())?;
/// let (text, offset) = true_contacts_rr(&chain, &truth, None, 6, 8.0);
/// assert_eq!(offset, 0);
/// let mut lines = text.split(|&b| b == b'\n');
/// assert!(lines.next().unwrap().starts_with(b"VREVCSEQ"));
/// assert!(lines.next().unwrap().ends_with(b" 0 8 1"));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn true_contacts_rr(
    chain: &Chain,
    truth: &TrueContacts,
    sequence: Option<String>,
    min_sep: u32,
    cutoff: f64,
) -> (Vec<u8>, i32) {
    use std::io::Write as _;
    let mut text = Vec::new();
    let (line, offset) = match sequence {
        Some(sequence) => (Some(sequence), 0),
        None => match sequence_line(chain) {
            Some((line, offset)) => (Some(line), offset),
            None => (None, 0),
        },
    };
    if let Some(line) = line {
        text.extend_from_slice(line.as_bytes());
        text.push(b'\n');
    }
    let mut cutoff_text = Vec::new();
    crate::io::tables::write_real(&mut cutoff_text, cutoff);
    for (i, j) in truth.contacts(SeparationRange::new(min_sep, None)) {
        let (i, j) = (i - offset, j - offset);
        let _ = write!(text, "{i} {j} 0 ");
        text.extend_from_slice(&cutoff_text);
        text.extend_from_slice(b" 1\n");
    }
    (text, offset)
}

/// The distance matrix of the observed residues as TSV (`contacts --matrix`): a header
/// `residue` then the residue numbers, one row per residue, distances in Å to 3 decimals.
///
/// ```
/// use contactmap::score::contacts::ContactDefinition;
/// use contactmap::io::structure::read_chain;
/// use contactmap::score::target::{distance_matrix_tsv, measure};
/// use std::path::Path;
/// let path = Path::new("data/protein/toxd/toxd.pdb.gz");
/// let chain = read_chain(path, None)?;
/// let truth = measure(path, &chain, &ContactDefinition::default())?;
/// let text = String::from_utf8(distance_matrix_tsv(&truth)).unwrap();
/// let n = truth.numbers().len();
/// assert_eq!(text.lines().count(), n + 1);
/// assert!(text.lines().nth(1).unwrap().split('\t').nth(1) == Some("0.000"));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn distance_matrix_tsv(truth: &TrueContacts) -> Vec<u8> {
    use std::io::Write as _;
    let mut text = Vec::new();
    let numbers = truth.numbers();
    text.extend_from_slice(b"residue");
    for number in numbers {
        let _ = write!(text, "\t{number}");
    }
    text.push(b'\n');
    for &i in numbers {
        let _ = write!(text, "{i}");
        for &j in numbers {
            let distance = truth.distance(i, j).unwrap_or(0.0);
            let _ = write!(text, "\t{distance:.3}");
        }
        text.push(b'\n');
    }
    text
}

fn json_number(value: f64) -> serde_json::Value {
    serde_json::Number::from_f64(value).map_or(serde_json::Value::Null, serde_json::Value::Number)
}

/// The scores as a JSON array, one object per prediction (what `score contacts --json` prints),
/// with the `structure` and the contact `definition` (its description) they were scored against.
pub fn scores_json(structure: &str, definition: &str, reports: &[PredictionScores]) -> String {
    use serde_json::json;
    let predictions: Vec<serde_json::Value> = reports
        .iter()
        .map(|report| {
            let ranges: Vec<serde_json::Value> = report
                .scores
                .iter()
                .map(|(named, labels, score)| {
                    let lists: Vec<serde_json::Value> = labels
                        .iter()
                        .zip(&score.lists)
                        .map(|(label, list)| {
                            json!({
                                "list": label,
                                "k": list.k,
                                "n_scored": list.n_scored,
                                "tp": list.true_positives,
                                "precision": json_number(list.precision),
                                "recall": json_number(list.recall),
                                "f1": json_number(list.f1),
                                "mcc": json_number(list.mcc),
                                "xd": json_number(list.xd),
                            })
                        })
                        .collect();
                    json!({
                        "range": named.name,
                        "min_sep": named.range.min,
                        "max_sep": named.range.max,
                        "n_true": score.n_true,
                        "n_pairs": score.n_pairs,
                        "n_available": score.n_available,
                        "lists": lists,
                    })
                })
                .collect();
            let length = report.scores.first().map(|(_, _, score)| score.length);
            json!({
                "prediction": report.path,
                "structure": structure,
                "contact_definition": definition,
                "n_observed": report.n_observed,
                "register": report.register.as_ref().map(|register| json!({
                    "method": register.method,
                    "offset": register.offset,
                    "placed": register.placed,
                    "identical": register.identical,
                    "residues": register.residues,
                })),
                "length": length,
                "length_source": report.length_source,
                "ranges": ranges,
            })
        })
        .collect();
    let mut text = serde_json::to_string_pretty(&predictions).unwrap_or_default();
    text.push('\n');
    text
}
