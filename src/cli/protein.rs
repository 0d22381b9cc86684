//! Protein options and steps shared by the subcommands that read a structure and contact
//! predictions (`contacts`, `score contacts`, `score overlap`, `plot contacts`): the contact
//! definition (`--atom`, `--cutoff`, `--le`), the register of the chain on the target sequence
//! (`--register`), prediction formats and loading with `--fasta`, and the parsing of separation
//! ranges, list sizes (`L/5`, `0.5L`, `30`, `NC`) and `--length`.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};

use contactmap::error::{Error, Result};
use contactmap::io::predictions::{read_prediction, PredictionFormat};
use contactmap::io::structure::{read_structure, Chain};
use contactmap::score::contacts::{
    ContactAtom, ContactDefinition, DistanceTest, ListSize, Prediction, Rounding, SeparationRange,
    TargetLength, TrueContacts,
};
use contactmap::score::register::{register, Register, RegisterMethod, RegisterMode};

/// The atoms measured, for `--atom`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AtomArg {
    /// Cb-Cb, Ca for glycine (CASP)
    Cb,
    /// Ca-Ca
    Ca,
    /// closest pair of heavy (non-hydrogen) atoms
    Heavy,
}

impl From<AtomArg> for ContactAtom {
    fn from(arg: AtomArg) -> Self {
        match arg {
            AtomArg::Cb => ContactAtom::Cb,
            AtomArg::Ca => ContactAtom::Ca,
            AtomArg::Heavy => ContactAtom::Heavy,
        }
    }
}

/// When two residues of the structure are in contact.
#[derive(Debug, Args, Clone)]
#[command(next_help_heading = "Contact definition")]
pub struct DefinitionArgs {
    /// Atoms whose distance defines a contact.
    #[arg(long, value_enum, default_value = "cb")]
    pub atom: AtomArg,
    /// Distance cutoff in Angstrom.
    #[arg(long, default_value_t = 8.0, value_name = "ANGSTROM")]
    pub cutoff: f64,
    /// A contact is `d <= cutoff` (ConKit) instead of `d < cutoff` (CASP, ConEVA, DISTEVAL).
    #[arg(long)]
    pub le: bool,
}

impl DefinitionArgs {
    /// The library's contact definition.
    pub fn definition(&self) -> ContactDefinition {
        ContactDefinition {
            atom: self.atom.into(),
            cutoff_angstrom: self.cutoff,
            test: if self.le {
                DistanceTest::LessOrEqual
            } else {
                DistanceTest::Less
            },
        }
    }

    /// A short description, e.g. `cb d < 8 A`.
    pub fn describe(&self) -> String {
        let atom = match self.atom {
            AtomArg::Cb => "Cb (Ca for Gly)",
            AtomArg::Ca => "Ca",
            AtomArg::Heavy => "closest heavy atoms",
        };
        let test = if self.le { "<=" } else { "<" };
        format!("{atom}, d {test} {} A", self.cutoff)
    }
}

/// How `--register` places the structure's residues on the sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RegisterArg {
    /// the residue numbers when they agree with the sequence (also with an offset), else a
    /// sequence alignment
    Auto,
    /// always a sequence alignment
    Align,
    /// the residue numbers as they are, unchecked
    Numbering,
}

/// The structure and how predictions are read and placed on it: the options `score contacts`
/// and `plot contacts` share.
#[derive(Debug, Args)]
pub struct TargetArgs {
    /// The structure with the true contacts (.pdb / .ent or .cif / .mmcif, optionally .gz).
    #[arg(long, value_name = "PDB|CIF")]
    pub structure: PathBuf,
    /// Chain of the structure (author chain id; default: the first protein chain).
    #[arg(long)]
    pub chain: Option<String>,
    /// Target sequence (FASTA, first record): gives L and checks the residue numbers.
    #[arg(long, value_name = "FILE")]
    pub fasta: Option<PathBuf>,
    /// Prediction format (default: detected from the content of each file).
    #[arg(long, value_enum)]
    pub format: Option<PredictionFormatArg>,
    /// How the structure's residues are placed on the prediction's sequence.
    #[arg(long, value_enum, default_value = "auto")]
    pub register: RegisterArg,
}

impl TargetArgs {
    /// The files these options name (structure, FASTA), inputs of the command.
    pub fn files(&self) -> impl Iterator<Item = &Path> {
        std::iter::once(self.structure.as_path()).chain(self.fasta.as_deref())
    }

    /// The target sequence (`--fasta`, when given) and the chain of the structure.
    pub fn read(&self) -> Result<(Option<String>, Chain)> {
        let fasta = self
            .fasta
            .as_deref()
            .map(contactmap::io::predictions::read_fasta)
            .transpose()?;
        let chain = read_chain(&self.structure, self.chain.as_deref())?;
        Ok((fasta, chain))
    }

    /// `chain` placed on the sequence of `prediction` (read from `path`, named in errors) and
    /// its true contacts under `definition`.
    pub fn place(
        &self,
        chain: &Chain,
        prediction: &Prediction,
        path: &Path,
        definition: &DefinitionArgs,
    ) -> Result<Placed> {
        let warning = match prediction.sequence {
            None => check_numbering(&self.structure, chain, prediction, path)?,
            Some(_) => None,
        };
        let mut placed = place(
            &self.structure,
            chain,
            prediction.sequence.as_deref(),
            self.register,
            definition,
        )
        .map_err(|err| err.in_file(path))?;
        placed.warning = warning;
        Ok(placed)
    }
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

/// Read `structure` and select the chain.
pub fn read_chain(structure: &Path, chain: Option<&str>) -> Result<Chain> {
    let parsed = read_structure(structure)?;
    Ok(parsed
        .chain(chain)
        .map_err(|err| err.in_file(structure))?
        .clone())
}

/// The chain with its residues numbered by their position in `sequence` (see
/// [`contactmap::score::register`]), and the register; the chain unchanged without a sequence or
/// with `--register numbering`.
pub fn place_chain(
    structure: &Path,
    chain: &Chain,
    sequence: Option<&str>,
    mode: RegisterArg,
) -> Result<(Chain, Option<Register>)> {
    let mode = match (sequence, mode) {
        (None, _) | (_, RegisterArg::Numbering) => return Ok((chain.clone(), None)),
        (Some(_), RegisterArg::Auto) => RegisterMode::Auto,
        (Some(_), RegisterArg::Align) => RegisterMode::Alignment,
    };
    let register = register(chain, sequence.unwrap_or_default(), mode)
        .map_err(|err| err.in_file(structure))?;
    Ok((register.renumber(chain), Some(register)))
}

/// The true contacts of a chain read from `structure`.
pub fn measure(
    structure: &Path,
    chain: &Chain,
    definition: &DefinitionArgs,
) -> Result<TrueContacts> {
    TrueContacts::from_chain(chain, definition.definition()).map_err(|err| err.in_file(structure))
}

/// Prediction formats, for `--format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PredictionFormatArg {
    /// CASP RR (optional header and sequence lines; `i j score`, `i j d1 d2 score` or mode 2
    /// `i j p b1..b10` rows)
    Rr,
    /// square matrix (CCMpred, PSICOV, ccmpred-py; `#` lines skipped)
    Matrix,
    /// `i j score` rows (whitespace or commas; plmDCA, PSICOV-style lists)
    Table,
    /// trRosetta .npz distogram (score P(d < 8 A))
    Npz,
    /// .npy predicted distance map (score: minus the distance)
    Npy,
    /// EVfold / EVcouplings `i A j B x score` rows
    Evfold,
    /// GREMLIN table with its `i j i_id j_id r_sco s_sco prob` header (score r_sco)
    Gremlin,
}

impl From<PredictionFormatArg> for PredictionFormat {
    fn from(arg: PredictionFormatArg) -> Self {
        match arg {
            PredictionFormatArg::Rr => PredictionFormat::Rr,
            PredictionFormatArg::Matrix => PredictionFormat::Matrix,
            PredictionFormatArg::Table => PredictionFormat::Table,
            PredictionFormatArg::Npz => PredictionFormat::Npz,
            PredictionFormatArg::Npy => PredictionFormat::Npy,
            PredictionFormatArg::Evfold => PredictionFormat::Evfold,
            PredictionFormatArg::Gremlin => PredictionFormat::Gremlin,
        }
    }
}

/// Rounding of `L * f`, for `--rounding`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RoundingArg {
    /// floor(L f) (CASP, ConKit)
    Floor,
    /// floor(L f + 0.5) (ConEVA)
    HalfUp,
    /// half to even, Python's round (DISTEVAL)
    Banker,
}

impl From<RoundingArg> for Rounding {
    fn from(arg: RoundingArg) -> Self {
        match arg {
            RoundingArg::Floor => Rounding::Floor,
            RoundingArg::HalfUp => Rounding::HalfUp,
            RoundingArg::Banker => Rounding::Banker,
        }
    }
}

/// A list size with its label as written (`L/5`, `NC`, ...).
pub type LabelledSize = (String, ListSize);

/// A named separation range.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedRange {
    /// The range as written, lower case (`long`, `12-23`, `6+`).
    pub name: String,
    /// The range.
    pub range: SeparationRange,
}

/// Parse a separation range: short, medium, long, all, MIN-MAX or MIN+.
pub fn parse_range(token: &str) -> Result<NamedRange> {
    let token = token.trim();
    let bad = || {
        Error::Invalid(format!(
            "bad separation range '{token}' (expected short, medium, long, all, MIN-MAX or MIN+)"
        ))
    };
    let number = |text: &str| text.trim().parse::<u32>().map_err(|_| bad());
    let range = match token.to_ascii_lowercase().as_str() {
        "short" => SeparationRange::SHORT,
        "medium" => SeparationRange::MEDIUM,
        "long" => SeparationRange::LONG,
        "all" => SeparationRange::ALL,
        other => {
            if let Some(min) = other.strip_suffix('+') {
                SeparationRange::new(number(min)?, None)
            } else if let Some((min, max)) = other.split_once('-') {
                let (min, max) = (number(min)?, number(max)?);
                if max < min {
                    return Err(bad());
                }
                SeparationRange::new(min, Some(max))
            } else {
                return Err(bad());
            }
        }
    };
    Ok(NamedRange {
        name: token.to_ascii_lowercase(),
        range,
    })
}

/// Parse a list size: L/10, L, 0.3L, a count N or NC; returns it with its label as written.
pub fn parse_list_size(token: &str) -> Result<(String, ListSize)> {
    let token = token.trim();
    let bad = || {
        Error::Invalid(format!(
            "bad list size '{token}' (expected L/10, L, 0.3L, a count N, or NC)"
        ))
    };
    let upper = token.to_ascii_uppercase();
    let size = if upper == "NC" {
        ListSize::TrueContacts
    } else if upper == "L" {
        ListSize::Fraction(1.0)
    } else if let Some(divisor) = upper.strip_prefix("L/") {
        let divisor: f64 = divisor.parse().map_err(|_| bad())?;
        if !(divisor.is_finite() && divisor > 0.0) {
            return Err(bad());
        }
        ListSize::Fraction(1.0 / divisor)
    } else if let Some(fraction) = upper.strip_suffix('L') {
        let fraction: f64 = fraction.trim_end_matches('*').parse().map_err(|_| bad())?;
        if !(fraction.is_finite() && fraction >= 0.0) {
            return Err(bad());
        }
        ListSize::Fraction(fraction)
    } else {
        ListSize::Count(token.parse().map_err(|_| bad())?)
    };
    Ok((token.to_string(), size))
}

/// What L is, as asked on the command line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LengthChoice {
    /// The sequence when the prediction has one, else the size of its matrix, else the
    /// observed residues.
    Auto,
    /// As given.
    Fixed(TargetLength),
}

impl LengthChoice {
    /// What L is for `prediction`, and where it comes from (`sequence`, `matrix size`,
    /// `observed`, `given`).
    pub fn resolve(self, prediction: &Prediction) -> (TargetLength, &'static str) {
        match self {
            LengthChoice::Auto if prediction.sequence.is_some() => {
                (TargetLength::Sequence, "sequence")
            }
            LengthChoice::Auto => match prediction.length {
                Some(n) => (TargetLength::Residues(n), "matrix size"),
                None => (TargetLength::Observed, "observed"),
            },
            LengthChoice::Fixed(TargetLength::Sequence) => (TargetLength::Sequence, "sequence"),
            LengthChoice::Fixed(TargetLength::Observed) => (TargetLength::Observed, "observed"),
            LengthChoice::Fixed(fixed) => (fixed, "given"),
        }
    }
}

/// Parse `--length`: sequence, observed or a positive number (`None`: [`LengthChoice::Auto`]).
pub fn parse_length(text: Option<&str>) -> Result<LengthChoice> {
    Ok(match text.map(str::trim) {
        None => LengthChoice::Auto,
        Some(text) => match text.to_ascii_lowercase().as_str() {
            "sequence" | "seq" => LengthChoice::Fixed(TargetLength::Sequence),
            "observed" => LengthChoice::Fixed(TargetLength::Observed),
            other => match other.parse::<usize>() {
                Ok(n) if n > 0 => LengthChoice::Fixed(TargetLength::Residues(n)),
                _ => {
                    return Err(Error::Invalid(format!(
                        "bad --length '{text}' (expected sequence, observed or a positive number)"
                    )))
                }
            },
        },
    })
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
}

/// Place `chain` (read from `structure`) on `sequence` as `mode` says ([`place_chain`]) and
/// measure its true contacts; without a sequence, a chain whose numbers are not unique asks
/// for one.
pub fn place(
    structure: &Path,
    chain: &Chain,
    sequence: Option<&str>,
    mode: RegisterArg,
    definition: &DefinitionArgs,
) -> Result<Placed> {
    let (placed, register) = place_chain(structure, chain, sequence, mode)?;
    let truth = measure(structure, &placed, definition).map_err(|err| match err {
        Error::Invalid(message) if sequence.is_none() => Error::Invalid(format!(
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
    })
}

/// Read the prediction at `path` (`format`, or detected from the content); with `fasta`, attach
/// that sequence and check the residue numbers against it. The sequence is made upper case.
pub fn load_prediction(
    path: &Path,
    format: Option<PredictionFormatArg>,
    fasta: Option<&str>,
) -> Result<Prediction> {
    let mut prediction = read_prediction(path, format.map(Into::into))?;
    if let Some(sequence) = fasta {
        prediction = prediction
            .with_sequence(sequence)
            .map_err(|err| err.in_file(path))?;
    }
    if let Some(sequence) = &mut prediction.sequence {
        sequence.make_ascii_uppercase();
    }
    Ok(prediction)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_list_size_and_length_parsing() {
        assert_eq!(parse_range("long").unwrap().range, SeparationRange::LONG);
        assert_eq!(
            parse_range("12-23").unwrap().range,
            SeparationRange::new(12, Some(23))
        );
        assert_eq!(
            parse_range("5+").unwrap().range,
            SeparationRange::new(5, None)
        );
        for bad in ["", "9-3", "x", "5", "-3"] {
            assert!(parse_range(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_list_size("L/5").unwrap().1, ListSize::Fraction(0.2));
        assert_eq!(parse_list_size("L").unwrap().1, ListSize::Fraction(1.0));
        assert_eq!(parse_list_size("1.5L").unwrap().1, ListSize::Fraction(1.5));
        assert_eq!(parse_list_size("30").unwrap().1, ListSize::Count(30));
        assert_eq!(parse_list_size("nc").unwrap().1, ListSize::TrueContacts);
        for bad in ["L/0", "xL", "-1", "L/"] {
            assert!(parse_list_size(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_length(None).unwrap(), LengthChoice::Auto);
        assert_eq!(
            parse_length(Some("observed")).unwrap(),
            LengthChoice::Fixed(TargetLength::Observed)
        );
        assert_eq!(
            parse_length(Some("70")).unwrap(),
            LengthChoice::Fixed(TargetLength::Residues(70))
        );
        assert!(parse_length(Some("0")).is_err());
    }
}
