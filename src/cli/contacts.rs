//! `contactmap contacts`: the true residue contacts of a protein structure as CASP RR rows, or
//! the full residue distance matrix ([`contactmap::score::contacts::TrueContacts`]).

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::output::refuse_overwrites;
use crate::cli::output::Output;
use crate::cli::protein::{DefinitionArgs, RegisterArg};
use contactmap::error::Result;
use contactmap::io::predictions::read_fasta;
use contactmap::score::target::{
    distance_matrix_tsv, measure, place_chain, read_chain, true_contacts_rr,
};

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

Examples:
  contactmap contacts 1abc.pdb             # Cb, d < 8 A, separation >= 6
  contactmap contacts 1abc.cif --chain B --atom heavy --cutoff 5 --min-sep 1 \\
      -o B.rr
  contactmap contacts 1abc.pdb --matrix -o distances.tsv
  # sequence numbering
  contactmap contacts 1a8o.cif --fasta 1a8o.fasta -o true.rr")]
pub struct ContactsArgs {
    /// The structure (.pdb / .ent or .cif / .mmcif, optionally .gz).
    #[arg(value_name = "STRUCTURE")]
    pub structure: PathBuf,
    /// Chain (author chain id; default: the first protein chain).
    #[arg(long)]
    pub chain: Option<String>,
    /// Smallest sequence separation |i - j| of the listed contacts.
    #[arg(long, default_value_t = 6, value_name = "N", conflicts_with = "matrix")]
    pub min_sep: u32,
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
    pub definition: DefinitionArgs,
}

/// Run `contactmap contacts`.
pub fn run(args: &ContactsArgs) -> Result<()> {
    let inputs: Vec<&Path> = std::iter::once(args.structure.as_path())
        .chain(args.fasta.as_deref())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let original = read_chain(&args.structure, args.chain.as_deref())?;
    let sequence = args.fasta.as_deref().map(read_fasta).transpose()?;
    let (chain, register) = place_chain(
        &args.structure,
        &original,
        sequence.as_deref(),
        args.register.into(),
    )?;
    if let Some(register) = &register {
        eprintln!("{}", register.describe(&original));
    }
    let truth = measure(&args.structure, &chain, &args.definition.definition())?;
    let mut notes = crate::cli::warnings::Warnings::new();
    let text = if args.matrix {
        distance_matrix_tsv(&truth)
    } else {
        let cutoff = args.definition.cutoff;
        let (text, offset) = true_contacts_rr(&chain, &truth, sequence, args.min_sep, cutoff);
        if offset != 0 {
            notes.note(format!(
                "{}: chain {} is numbered from {}: the RR numbers its residues from 1 there (its \
                 sequence line is the chain's); give --fasta to number them by a target sequence",
                args.structure.display(),
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
