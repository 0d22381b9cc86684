//! `contactmap plot diff`: the MA or volcano plot of a `contactmap diff` table.

use std::path::PathBuf;

use clap::Args;

use super::figure::{FigureArgs, write_figure};
use crate::cli::output::refuse_overwrites;
use contactmap::error::{Error, Result};
use contactmap::io::tables::Table;
use contactmap::plot::curves::{Scale, draw_curves};
use contactmap::plot::diff::{DiffClass, DiffFigure, DiffPoint, diff_figure};

/// Arguments of `contactmap plot diff`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
The table is the output of `contactmap diff`, recognised by its columns:
  loops (PREFIX.loops.bedpe)        MA: log2FoldChange against baseMean (log scale)
  boundaries (PREFIX.boundaries.tsv) MA: log2FoldChange of the contacts across against
                                     baseMean (log scale; negative: deeper in B)
  compartments (PREFIX.compartments.tsv) MA: difference of E1 against the mean E1
--volcano draws -log10(pvalue) against the change instead. Each feature is a dot coloured by
its call: red higher in B (loop up; boundary gained or stronger; bin B->A), blue lower in B
(down; lost or weaker; A->B), orange shifted boundaries, grey unchanged; the legend counts
them. Features without a p-value (or a coordinate) are left out.

Examples:
  contactmap plot diff wt_vs_ko.loops.bedpe -o ma.png
  contactmap plot diff wt_vs_ko.loops.bedpe --volcano -o volcano.svg
  contactmap plot diff wt_vs_ko.boundaries.tsv --title 'WT vs KO' \\
      -o boundaries.png")]
pub struct DiffPlotArgs {
    /// A table of `contactmap diff loops`, `boundaries` or `compartments`.
    #[arg(value_name = "TABLE")]
    pub table: PathBuf,
    /// Volcano plot (-log10 p against the change) instead of the MA plot.
    #[arg(long)]
    pub volcano: bool,
    /// Output, size, dpi, title.
    #[command(flatten)]
    pub figure: FigureArgs,
}

/// Default figure width in inches.
const DEFAULT_WIDTH_IN: f64 = 6.0;

/// How a kind of table becomes points: its level (two columns averaged, or one), its change,
/// the column of the call and the calls' classes.
struct Layout {
    level: &'static [&'static str],
    level_label: &'static str,
    level_scale: Scale,
    change: &'static str,
    change_label: &'static str,
    call: &'static str,
    up: &'static [&'static str],
    down: &'static [&'static str],
    other: &'static [&'static str],
    names: [&'static str; 4],
}

const LAYOUTS: [Layout; 3] = [
    Layout {
        level: &["baseMean"],
        level_label: "mean of normalised counts",
        level_scale: Scale::Log,
        change: "log2FoldChange",
        change_label: "log2 fold change (B / A)",
        call: "direction",
        up: &["up"],
        down: &["down"],
        other: &[],
        names: ["up in B", "down in B", "other", "not changed"],
    },
    Layout {
        level: &["baseMean"],
        level_label: "mean of normalised contacts across",
        level_scale: Scale::Log,
        change: "log2FoldChange",
        change_label: "log2 fold change of contacts across (B / A)",
        call: "status",
        up: &["gained", "stronger"],
        down: &["lost", "weaker"],
        other: &["shifted"],
        names: [
            "gained / stronger",
            "lost / weaker",
            "shifted",
            "not changed",
        ],
    },
    Layout {
        level: &["E1_A", "E1_B"],
        level_label: "mean E1",
        level_scale: Scale::Linear,
        change: "difference",
        change_label: "E1 difference (B - A)",
        call: "switch",
        up: &["B->A"],
        down: &["A->B"],
        other: &[],
        names: ["B->A", "A->B", "other", "not switched"],
    },
];

/// Run `contactmap plot diff`.
pub fn run(args: &DiffPlotArgs) -> Result<()> {
    refuse_overwrites(&[args.table.as_path()], &[Some(&args.figure.out)])?;
    let figure = args.figure.check(DEFAULT_WIDTH_IN)?;
    let path = args.table.display().to_string();
    let table = Table::read(&path)?;
    let has = |name: &str| table.header().iter().any(|h| h == name);
    let layout = LAYOUTS
        .iter()
        .find(|l| l.level.iter().chain([&l.change, &l.call]).all(|c| has(c)) && has("pvalue"))
        .ok_or_else(|| {
            Error::Data(format!(
                "{path}: not a table of contactmap diff loops, boundaries or compartments (expected \
                 columns baseMean log2FoldChange with direction or status, or \
                 E1_A E1_B difference switch, with pvalue)"
            ))
        })?;
    let mut names: Vec<&str> = layout.level.to_vec();
    names.extend([layout.change, "pvalue"]);
    let numbers = table.numbers(&names)?;
    let call = table.column(layout.call)?;
    let n_level = layout.level.len();
    let points: Vec<DiffPoint> = numbers
        .iter()
        .enumerate()
        .filter(|(_, row)| !row[n_level + 1].is_nan())
        .map(|(r, row)| {
            let level = row[..n_level].iter().sum::<f64>() / n_level as f64;
            let (change, p) = (row[n_level], row[n_level + 1]);
            let word = table.text(r, call);
            let class = if layout.up.contains(&word) {
                DiffClass::Up
            } else if layout.down.contains(&word) {
                DiffClass::Down
            } else if layout.other.contains(&word) {
                DiffClass::Other
            } else {
                DiffClass::Unchanged
            };
            let (x, y) = if args.volcano {
                (change, -p.log10())
            } else {
                (level, change)
            };
            DiffPoint { x, y, class }
        })
        .collect();
    let options = DiffFigure {
        title: args.figure.title.clone().unwrap_or_default(),
        x_label: if args.volcano {
            layout.change_label
        } else {
            layout.level_label
        }
        .into(),
        x_scale: if args.volcano {
            Scale::Linear
        } else {
            layout.level_scale
        },
        y_label: if args.volcano {
            "-log10 p-value"
        } else {
            layout.change_label
        }
        .into(),
        zero_line: !args.volcano,
        names: layout.names.map(String::from),
        width_px: figure.width_px,
        height_px: figure.height_px,
        dpi: figure.dpi,
    };
    let svg = draw_curves(&diff_figure(&points, &options))?;
    write_figure(&svg, &figure, &args.figure)
}
