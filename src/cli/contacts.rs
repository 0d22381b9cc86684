//! `contactmap contacts`: the true residue contacts of a protein structure as CASP RR rows, or
//! the full residue distance matrix ([`contactmap::score::contacts::TrueContacts`]); with
//! `--trajectory`, the residue contact frequencies of an MD trajectory
//! ([`contactmap::score::frequency`]).

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::output::Output;
use crate::cli::output::refuse_overwrites;
use crate::cli::progress::spinner;
use crate::cli::protein::{DefinitionArgs, RegisterArg};

use contactmap::error::Result;
use contactmap::io::predictions::read_fasta;
use contactmap::io::structure::read_chain;
use contactmap::io::topology::read_topology;
use contactmap::score::frequency::{
    FrequencySpec, Scheme, contact_frequencies_of, frequency_table,
};
use contactmap::score::target::{distance_matrix_tsv, measure, place_chain, true_contacts_rr};

/// Arguments of `contactmap contacts`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Residues are those of the chosen chain of the first model, numbered by their author numbers
(PDB columns 23-26, mmCIF auth_seq_id); hetero groups and waters are ignored, modified amino
acids such as MSE are kept as their parent, PCA is dropped, and a residue without the atom the
definition needs (a non-Gly residue without Cb) is unobserved.

With --fasta, residues are numbered by their position in the target sequence instead: the
chain is placed on the sequence as `score contacts` does it (--register; what was done is
printed on standard error), so the list is in the numbering of the predictions.

Output (default): CASP RR. The first line is the sequence: the --fasta sequence, or residue 1
to the last residue number with `X` at numbers that are not observed (so the file reads back as
a prediction with the structure's numbering; it is omitted when a residue number is below 1).
Then one row per true contact `i j 0 CUTOFF 1`, i < j, |i - j| >= --min-sep, sorted.

With --matrix: the distance matrix of the observed residues in Angstrom (3 decimals), as a
tab-separated table whose first row and column are the residue numbers.

With --trajectory TRAJ... --topology TOP: the residue contact frequencies over the frames of an
MD trajectory (DCD, XTC, multi-model PDB / mmCIF; several files are read one after the other),
as MDTraj's compute_contacts measures them: the pairs of residues with a CA atom, in the same
chain, at least --min-sep (default 3) residues apart by index; the distance of --definition
(MDTraj's schemes ca, closest, closest-heavy, sidechain, sidechain-heavy, or CASP's cb); the
minimum image when a frame has a periodic box (unless --no-periodic). The topology (PDB or
mmCIF) lists the trajectory's atoms in its order, waters and ions included. Output: one row
per pair, `chain residue1 residue2 name1 name2 index1 index2 contact_frames frequency`
(residue: author number; index: MDTraj's 0-based residue index); `score contacts
--truth-frequency` reads it as the truth.

Examples:
  contactmap contacts 1abc.pdb             # Cb, d < 8 A, separation >= 6
  contactmap contacts 1abc.cif --chain B --atom heavy --cutoff 5 --min-sep 1 \\
      -o B.rr
  contactmap contacts 1abc.pdb --matrix -o distances.tsv
  # sequence numbering
  contactmap contacts 1a8o.cif --fasta 1a8o.fasta -o true.rr
  # MD contact frequencies (Cb < 8 A, CASP's definition: the default here;
  # MDTraj's default scheme is closest-heavy, as in the second example)
  contactmap contacts --trajectory run.xtc --topology conf.pdb -o freq.tsv
  contactmap contacts --trajectory run.dcd --topology top.pdb \\
      --definition closest-heavy --cutoff 4.5 --stride 10 -o freq.tsv")]
pub struct ContactsArgs {
    /// The structure (.pdb / .ent or .cif / .mmcif, optionally .gz).
    #[arg(value_name = "STRUCTURE", required_unless_present = "trajectory")]
    pub structure: Option<PathBuf>,
    /// MD trajectory files (DCD, XTC, multi-model PDB / mmCIF): contact frequencies over
    /// their frames, read in order.
    #[arg(long, num_args = 1.., value_name = "TRAJ", requires = "topology",
          conflicts_with_all = ["structure", "matrix", "fasta", "le", "chain"])]
    pub trajectory: Vec<PathBuf>,
    /// The trajectory's topology: a PDB or mmCIF file of its atoms, in order.
    #[arg(long, value_name = "TOP", requires = "trajectory")]
    pub topology: Option<PathBuf>,
    /// How the distance of two residues is measured over a trajectory (MDTraj's schemes, and
    /// CASP's cb, the default here, as `score contacts` scores; MDTraj's default is
    /// closest-heavy).
    #[arg(
        long,
        value_enum,
        default_value = "cb",
        requires = "trajectory",
        conflicts_with = "atom"
    )]
    pub definition: SchemeArg,
    /// Measure every K-th frame of the trajectory, from the first.
    #[arg(long, default_value_t = 1, value_name = "K", requires = "trajectory",
          value_parser = clap::value_parser!(u64).range(1..))]
    pub stride: u64,
    /// Ignore the trajectory's periodic box (plain distances, MDTraj's periodic=False).
    #[arg(long, requires = "trajectory")]
    pub no_periodic: bool,
    /// Chain (author chain id; default: the first protein chain).
    #[arg(long)]
    pub chain: Option<String>,
    /// Smallest sequence separation |i - j| of the listed contacts [default: 6; with
    /// --trajectory 3, by residue index, as MDTraj's "all"].
    #[arg(long, value_name = "N", conflicts_with = "matrix")]
    pub min_sep: Option<u32>,
    /// Write the full residue distance matrix instead of the contact list.
    #[arg(long)]
    pub matrix: bool,
    /// Target sequence (FASTA, first record): number residues by their position in it.
    #[arg(long, value_name = "FILE")]
    pub fasta: Option<PathBuf>,
    /// How the chain is placed on the --fasta sequence.
    #[arg(long, value_enum, default_value = "auto", requires = "fasta")]
    pub register: RegisterArg,
    /// Write here instead of standard output (.gz compresses).
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// The contact definition.
    #[command(flatten)]
    pub definition_cutoff: DefinitionArgs,
}

/// Contact schemes, for `--definition`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SchemeArg {
    /// Cb - Cb (Ca for glycine), CASP's
    Cb,
    /// Ca - Ca
    Ca,
    /// the closest pair of atoms
    Closest,
    /// the closest pair of non-hydrogen atoms (MDTraj's default scheme)
    ClosestHeavy,
    /// the closest pair of side-chain atoms
    Sidechain,
    /// the closest pair of side-chain heavy atoms
    SidechainHeavy,
}

impl From<SchemeArg> for Scheme {
    fn from(arg: SchemeArg) -> Scheme {
        match arg {
            SchemeArg::Cb => Scheme::Cb,
            SchemeArg::Ca => Scheme::Ca,
            SchemeArg::Closest => Scheme::Closest,
            SchemeArg::ClosestHeavy => Scheme::ClosestHeavy,
            SchemeArg::Sidechain => Scheme::Sidechain,
            SchemeArg::SidechainHeavy => Scheme::SidechainHeavy,
        }
    }
}

/// Run `contactmap contacts`.
pub fn run(args: &ContactsArgs) -> Result<()> {
    let Some(structure) = args.structure.as_deref() else {
        return run_trajectory(args);
    };
    let inputs: Vec<&Path> = std::iter::once(structure)
        .chain(args.fasta.as_deref())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let original = read_chain(structure, args.chain.as_deref())?;
    let sequence = args.fasta.as_deref().map(read_fasta).transpose()?;
    let (chain, register) = place_chain(
        structure,
        &original,
        sequence.as_deref(),
        args.register.into(),
    )?;
    if let Some(register) = &register {
        eprintln!("{}", register.describe(&original));
    }
    let truth = measure(structure, &chain, &args.definition_cutoff.definition())?;
    let mut notes = crate::cli::warnings::Warnings::new();
    let text = if args.matrix {
        distance_matrix_tsv(&truth)
    } else {
        let cutoff = args.definition_cutoff.cutoff;
        let min_sep = args.min_sep.unwrap_or(6);
        let (text, offset) = true_contacts_rr(&chain, &truth, sequence, min_sep, cutoff);
        if offset != 0 {
            notes.note(format!(
                "{}: chain {} is numbered from {}: the RR numbers its residues from 1 there (its \
                 sequence line is the chain's); give --fasta to number them by a target sequence",
                structure.display(),
                chain.id,
                offset + 1
            ));
        }
        text
    };
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(&text)?;
    out.finish()?;
    notes.print();
    Ok(())
}

/// `contacts --trajectory`: the residue contact frequencies of a trajectory.
fn run_trajectory(args: &ContactsArgs) -> Result<()> {
    let topology_path = args.topology.as_deref().expect("clap requires --topology");
    let inputs: Vec<&Path> = args
        .trajectory
        .iter()
        .map(PathBuf::as_path)
        .chain([topology_path])
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let topology = read_topology(topology_path)?;
    let names: Vec<String> = args
        .trajectory
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    let spec = FrequencySpec {
        scheme: args.definition.into(),
        cutoff_angstrom: args.definition_cutoff.cutoff,
        min_separation: args.min_sep.unwrap_or(3) as usize,
        periodic: !args.no_periodic,
        stride: args.stride as usize,
    };
    let bar = spinner("frames");
    let frequencies = contact_frequencies_of(&topology, &names, &spec, |done| {
        bar.set_position(done as u64)
    })?;
    bar.finish_and_clear();
    let text = frequency_table(&topology, &frequencies);
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(text.as_bytes())?;
    out.finish()?;
    eprintln!(
        "contacts: {} frames, {} residue pairs ({}, d < {} A), {} in contact in at least one frame",
        frequencies.frames,
        frequencies.pairs.pairs.len(),
        spec.scheme.name(),
        spec.cutoff_angstrom,
        frequencies.counts.iter().filter(|&&n| n > 0).count()
    );
    if topology.chains.iter().any(String::is_empty) {
        eprintln!(
            "contacts: {} has no chain ids: its chain is written {} (the PDB's convention for a \
             file's one chain)",
            topology_path.display(),
            contactmap::score::frequency::BLANK_CHAIN
        );
    }
    Ok(())
}
