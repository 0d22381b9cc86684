//! `contactmap plot polymer-stats`: the tables of `contactmap polymer-stats` drawn as
//! `plot expected` draws P(s): several ensembles overlaid on log-log axes, with local slopes.

use std::path::{Path, PathBuf};

use clap::Args;

use super::figure::{FigureArgs, write_figure};
use crate::cli::output::refuse_overwrites;
use contactmap::error::{Error, Result};
use contactmap::io::tables::Table;
use contactmap::plot::curves::{PolymerFigure, PolymerSample, draw_curves, polymer_figure};

/// Arguments of `contactmap plot polymer-stats`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Each input is the PREFIX given to `contactmap polymer-stats -o PREFIX`: its tables
PREFIX.scaling.tsv (P(s)), PREFIX.r2.tsv (<R^2(s)>, <Rg^2(s)>) and, with --over-time,
PREFIX.rg2.tsv (each conformation's Rg^2) are read. One colour per input.

Against the separation s in beads (log axes): P(s) on top; <R^2(s)> (solid) and <Rg^2(s)>
(dashed) below; at the bottom (unless --no-slope) the local slopes d ln y / d ln s between
consecutive points of P(s) (solid) and of <R^2(s)> (dashed): an ideal chain has -1.5 and 1, a
fractal globule about -1 and 2/3. --over-time: each conformation's Rg^2 against its number in
the order read (a trajectory's relaxation).

Examples:
  contactmap polymer-stats traj/ -o traj
  contactmap plot polymer-stats traj -o traj.png
  contactmap plot polymer-stats wt ko --labels WT,KO --no-slope -o stats.svg
  contactmap plot polymer-stats traj --over-time -o rg2.png")]
pub struct PolymerStatsPlotArgs {
    /// Prefixes of `polymer-stats` outputs (PREFIX.scaling.tsv, PREFIX.r2.tsv, PREFIX.rg2.tsv).
    #[arg(value_name = "PREFIX", required = true)]
    pub inputs: Vec<String>,
    /// Legend names of the inputs, comma separated (default: the prefixes' file names).
    #[arg(long, value_delimiter = ',', value_name = "NAMES")]
    pub labels: Option<Vec<String>>,
    /// Draw each conformation's Rg^2 against its number instead of the curves against s.
    #[arg(long)]
    pub over_time: bool,
    /// Leave out the local-slope panel.
    #[arg(long, conflicts_with = "over_time")]
    pub no_slope: bool,
    /// Output, size, dpi, title.
    #[command(flatten)]
    pub figure: FigureArgs,
}

/// Default figure width in inches.
const DEFAULT_WIDTH_IN: f64 = 6.0;

/// The columns `names` of `table`, as numbers, row by row; a table without rows is an error.
fn columns(table: &Table, names: &[&str]) -> Result<Vec<Vec<f64>>> {
    let rows = table.numbers(names)?;
    if rows.is_empty() {
        return Err(Error::format(table.path(), "the table has no row"));
    }
    Ok(rows)
}

/// The tables of `polymer-stats -o prefix`, the Rg^2 one when `over_time`.
fn read_sample(prefix: &str, label: String, over_time: bool) -> Result<PolymerSample> {
    let table = |kind: &str| Table::read(&format!("{prefix}.{kind}.tsv"));
    let mut sample = PolymerSample {
        label,
        scaling: Vec::new(),
        r2: Vec::new(),
        rg2: Vec::new(),
    };
    if over_time {
        let rows = columns(&table("rg2")?, &["rg2"])?;
        sample.rg2 = rows.into_iter().map(|row| row[0]).collect();
    } else {
        let rows = columns(&table("scaling")?, &["s_mid", "contact_probability"])?;
        sample.scaling = rows.into_iter().map(|row| (row[0], row[1])).collect();
        let rows = columns(&table("r2")?, &["s", "r2", "rg2"])?;
        sample.r2 = rows
            .into_iter()
            .map(|row| (row[0], row[1], row[2]))
            .collect();
    }
    Ok(sample)
}

/// Run `contactmap plot polymer-stats`.
pub fn run(args: &PolymerStatsPlotArgs) -> Result<()> {
    let kinds: &[&str] = if args.over_time {
        &["rg2"]
    } else {
        &["scaling", "r2"]
    };
    let files: Vec<PathBuf> = args
        .inputs
        .iter()
        .flat_map(|prefix| {
            kinds
                .iter()
                .map(move |k| PathBuf::from(format!("{prefix}.{k}.tsv")))
        })
        .collect();
    let inputs: Vec<&Path> = files.iter().map(PathBuf::as_path).collect();
    refuse_overwrites(&inputs, &[Some(&args.figure.out)])?;
    let figure = args.figure.check(DEFAULT_WIDTH_IN)?;
    let labels = super::figure::legend_labels(args.labels.as_ref(), &args.inputs, |prefix| {
        Path::new(prefix)
            .file_name()
            .map_or_else(|| prefix.to_string(), |n| n.to_string_lossy().into_owned())
    })?;
    let samples = args
        .inputs
        .iter()
        .zip(labels)
        .map(|(prefix, label)| read_sample(prefix, label, args.over_time))
        .collect::<Result<Vec<_>>>()?;
    let options = PolymerFigure {
        over_time: args.over_time,
        slope_panel: !args.no_slope,
        title: args.figure.title.clone().unwrap_or_default(),
        width_px: figure.width_px,
        height_px: figure.height_px,
        dpi: figure.dpi,
    };
    let svg = draw_curves(&polymer_figure(&samples, &options))?;
    write_figure(&svg, &figure, &args.figure)
}
