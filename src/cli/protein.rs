//! Protein options and steps shared by the subcommands that read a structure and contact
//! predictions (`contacts`, `score contacts`, `score overlap`, `plot contacts`): the contact
//! definition (`--atom`, `--cutoff`, `--le`), the register of the chain on the target sequence
//! (`--register`), prediction formats and loading with `--fasta`, and the parsing of separation
//! ranges, list sizes (`L/5`, `0.5L`, `30`, `NC`) and `--length`.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};

use contactmap::error::Result;
use contactmap::io::predictions::PredictionFormat;
use contactmap::io::structure::Chain;
use contactmap::io::structure::read_chain;
use contactmap::score::contacts::{
    ContactAtom, ContactDefinition, DistanceTest, Prediction, Rounding,
};
use contactmap::score::target::{Placed, RegisterChoice, place_prediction};

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

    /// A short description, e.g. `Cb (Ca for Gly), d < 8 A`.
    pub fn describe(&self) -> String {
        self.definition().describe()
    }
}

impl From<RegisterArg> for RegisterChoice {
    fn from(arg: RegisterArg) -> Self {
        match arg {
            RegisterArg::Auto => RegisterChoice::Auto,
            RegisterArg::Align => RegisterChoice::Align,
            RegisterArg::Numbering => RegisterChoice::Numbering,
        }
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
        place_prediction(
            &self.structure,
            chain,
            prediction,
            path,
            self.register.into(),
            &definition.definition(),
        )
    }
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
