//! `contactmap contacts`: the true residue contacts of a protein structure as CASP RR rows, or
//! the full residue distance matrix ([`contactmap::score::contacts::TrueContacts`]).

use std::io::Write as _;
use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::output::refuse_overwrites;
use crate::cli::output::Output;
use crate::cli::protein::{DefinitionArgs, RegisterArg};
use contactmap::error::Result;
use contactmap::io::predictions::read_fasta;
use contactmap::io::structure::Chain;
use contactmap::io::tables::write_real;
use contactmap::score::contacts::SeparationRange;
use contactmap::score::target::{measure, place_chain, read_chain};

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
    let mut text = Vec::new();
    let mut notes = crate::cli::warnings::Warnings::new();
    if args.matrix {
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
    } else {
        let (line, offset) = match sequence {
            Some(sequence) => (Some(sequence), 0),
            None => match sequence_line(&chain) {
                Some((line, offset)) => (Some(line), offset),
                None => (None, 0),
            },
        };
        if let Some(line) = line {
            text.extend_from_slice(line.as_bytes());
            text.push(b'\n');
        }
        if offset != 0 {
            notes.note(format!(
                "{}: chain {} is numbered from {}: the RR numbers its residues from 1 there (its \
                 sequence line is the chain's); give --fasta to number them by a target sequence",
                args.structure.display(),
                chain.id,
                offset + 1
            ));
        }
        let mut cutoff = Vec::new();
        write_real(&mut cutoff, args.definition.cutoff);
        for (i, j) in truth.contacts(SeparationRange::new(args.min_sep, None)) {
            let (i, j) = (i - offset, j - offset);
            let _ = write!(text, "{i} {j} 0 ");
            text.extend_from_slice(&cutoff);
            text.extend_from_slice(b" 1\n");
        }
    }
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(&text)?;
    out.finish()?;
    notes.print();
    Ok(())
}
