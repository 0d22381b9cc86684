//! `contactmap plot contacts`: a protein contact map with the true contacts of a structure and
//! the top-ranked predicted pairs coloured true / false positive, and the precision curve
//! ([`contactmap::plot::protein`]).

use std::path::{Path, PathBuf};

use clap::Args;

use super::figure::{FigureArgs, write_figure};
use crate::cli::output::refuse_overwrites;
use crate::cli::protein::{DefinitionArgs, RoundingArg, TargetArgs};
use contactmap::error::{Error, Result};
use contactmap::io::predictions::load_prediction;
use contactmap::plot::protein::{ContactFigure, ContactLayout, PredictionLayer, draw_contacts};
use contactmap::score::contacts::{ScoreParams, SeparationRange};
use contactmap::score::lists::{parse_length, parse_list_size};

/// Arguments of `contactmap plot contacts`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
The figure of ConKit's `conkit-plot cmap` with a reference structure, and the precision curve:

Left: the residue x residue map (row i down, column j right). Light grey squares: the true
contacts of the structure with |i - j| >= --min-sep, in both triangles (Cb-Cb < 8 A by default;
--atom, --cutoff, --le). Circles: the top-k pairs of the prediction (k from --top, default L) in
the upper triangle, dark navy for a true positive, pink-red for a false positive (ConKit's
colours); a second prediction is drawn mirrored in the lower triangle. The pairs are those
`score contacts` ranks, with the same options: i < j, duplicates keep their highest score, pairs
closer than --min-sep dropped, and pairs with a residue not observed in the structure dropped
before ranking (--keep-unobserved lists them as open grey circles; they count as false). The
legend under the panels gives the counts and precision = TP / listed pairs, the numbers of
`score contacts --min-sep N --top SIZE`.

Right: precision against the list size k / L, for k = 1 to --curve-max (default 2L), one line
per prediction: the numbers of `score contacts --curve`. A dashed line marks the map's k.

Residue numbers are the positions in the target sequence (--fasta, or the sequence an RR file
carries): the chain is placed on it as `score contacts` does (--register; what was done is
printed on standard error). L is the sequence length, else the size of a matrix, else the
number of observed residues (--length overrides). Two predictions on different sequences are
each scored on their own placement; the grey contacts are those of the first.

Examples:
  contactmap plot contacts --structure toxd.pdb --fasta toxd.fasta toxd.mat \\
      -o toxd.png
  contactmap plot contacts --structure 1aap.pdb 1aapA.rr --top L/2 -o 1aap.svg
  contactmap plot contacts --structure 1guu.pdb --fasta 1guu.fasta 1guu.npz \\
      ccmpred.mat --top L --min-sep 24 --title '1guu, long range' \\
      -o compare.png")]
pub struct ContactsArgs {
    /// The structure, its chain, the target sequence, the prediction format and the register.
    #[command(flatten)]
    pub target: TargetArgs,
    /// The prediction (upper triangle), and optionally a second one (lower triangle).
    #[arg(value_name = "PRED", required = true, num_args = 1..=2)]
    pub predictions: Vec<PathBuf>,
    /// The list size drawn: L, L/5, 0.5L, a count N, or NC.
    #[arg(long, default_value = "L", value_name = "SIZE")]
    pub top: String,
    /// Smallest sequence separation |i - j| of the true contacts and of the listed pairs.
    #[arg(long, default_value_t = 6, value_name = "N")]
    pub min_sep: u32,
    /// L: sequence, observed or a number [default: sequence when there is one, else the
    /// matrix size, else observed].
    #[arg(long, value_name = "sequence|observed|N")]
    pub length: Option<String>,
    /// Rounding of L * fraction.
    #[arg(long, value_enum, default_value = "floor")]
    pub rounding: RoundingArg,
    /// List pairs with a residue not observed in the structure (open circles, never true).
    #[arg(long)]
    pub keep_unobserved: bool,
    /// Largest list size of the precision curve (2L, L, a count N ...).
    #[arg(long, default_value = "2L", value_name = "SIZE")]
    pub curve_max: String,
    /// The contact definition.
    #[command(flatten)]
    pub definition: DefinitionArgs,
    /// Output, size, dpi, title.
    #[command(flatten)]
    pub figure: FigureArgs,
}

/// Default figure width in inches (two panels).
const DEFAULT_WIDTH_IN: f64 = 9.0;

/// File name of a path, for the legend.
fn display_name(path: &std::path::Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |name| name.to_string_lossy().into_owned(),
    )
}

/// Run `contactmap plot contacts`.
pub fn run(args: &ContactsArgs) -> Result<()> {
    let inputs: Vec<&Path> = args
        .target
        .files()
        .chain(args.predictions.iter().map(PathBuf::as_path))
        .collect();
    refuse_overwrites(&inputs, &[Some(&args.figure.out)])?;
    let figure_options = args.figure.check(DEFAULT_WIDTH_IN)?;
    let (list_label, list_size) =
        parse_list_size(&args.top).map_err(|err| prefixed("--top", err))?;
    let (_, curve_size) =
        parse_list_size(&args.curve_max).map_err(|err| prefixed("--curve-max", err))?;
    let length = parse_length(args.length.as_deref())?;
    let (fasta, chain) = args.target.read()?;
    let range = SeparationRange::new(args.min_sep, None);

    let mut layers = Vec::with_capacity(args.predictions.len());
    let mut warnings = crate::cli::warnings::Warnings::new();
    let mut true_contacts = None;
    let (mut first, mut last) = (i32::MAX, i32::MIN);
    for path in &args.predictions {
        let prediction =
            load_prediction(path, args.target.format.map(Into::into), fasta.as_deref())?;
        let mut placed = args
            .target
            .place(&chain, &prediction, path, &args.definition)?;
        warnings.extend(placed.warning.take());
        if let Some(register) = &placed.register {
            eprintln!("{}: {}", path.display(), register.text);
        }
        let (target_length, _) = length.resolve(&prediction);
        let params = ScoreParams {
            range,
            length: target_length,
            rounding: args.rounding.into(),
            list_sizes: vec![list_size],
            drop_unobserved: !args.keep_unobserved,
            curve: Some(curve_size),
        };
        let (layer, (low, high)) = PredictionLayer::score(
            display_name(path),
            list_label.clone(),
            &placed.truth,
            &prediction,
            &params,
        )
        .map_err(|err| err.in_file(path))?;
        (first, last) = (first.min(low), last.max(high));
        if true_contacts.is_none() {
            true_contacts = Some(placed.truth.contacts(range));
        }
        layers.push(layer);
    }
    if first > last {
        return Err(Error::Data(format!(
            "{}: no observed residue to draw",
            args.target.structure.display()
        )));
    }
    let figure = ContactFigure {
        residues: (first, last),
        true_contacts: true_contacts.unwrap_or_default(),
        min_separation: args.min_sep,
        predictions: layers,
        title: args.figure.title.clone().unwrap_or_default(),
    };
    let layout = ContactLayout::new(
        figure_options.width_px,
        figure_options.height_px,
        figure_options.dpi,
        &figure,
    );
    let svg = draw_contacts(&figure, &layout)?;
    write_figure(&svg, &figure_options, &args.figure)?;
    warnings.print();
    Ok(())
}

/// An invalid-value error with the option's name in front.
fn prefixed(option: &str, err: Error) -> Error {
    match err {
        Error::Argument(message) => Error::Argument(format!("{option}: {message}")),
        other => other,
    }
}
