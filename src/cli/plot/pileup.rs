//! `contactmap plot pileup`: the picture of the pileups written by `contactmap pileup`.

use std::path::{Path, PathBuf};

use clap::Args;

use super::figure::{FigureArgs, write_figure};
use crate::cli::output::refuse_overwrites;
use contactmap::error::{Error, Result};
use contactmap::io::tables::Table;
use contactmap::plot::pileup::{PileupFigure, PileupPanel, centred_limits, draw_pileups};
use contactmap::plot::{ColorMap, ColorScale, ScaleKind};

/// Default figure width in inches.
const DEFAULT_WIDTH_IN: f64 = 6.0;

/// Arguments of `contactmap plot pileup`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Draws the pileups of `contactmap pileup ... -o PREFIX` as coolpuppy's plotpup.py does: one
square heatmap per group (PREFIX.groups.tsv when the pileup was grouped by distance or strand,
else PREFIX.pileup.tsv), facets in rows of --columns, coolwarm on a log colour scale centred at 1
(from 1/--vmax to --vmax; by default the largest deviation from 1 of any pixel, both ways), masked
pixels grey, and the score of each group (--score, a column of PREFIX.scores.tsv: by default the
first score, the central enrichment of a pileup of pairs, the insulation strength or domain score
of a local one) written in its top left corner, with 2 decimals.

Examples:
  contactmap pileup map.cool loops.bedpe --by-distance -o loops
  contactmap plot pileup loops -o loops.png
  contactmap plot pileup tads --vmax 2 --score domain_score -o tads.svg")]
pub struct PileupPlotArgs {
    /// The prefix given to `contactmap pileup -o`.
    pub prefix: String,
    /// Colour map (coolwarm as plotpup; RdBu_r, bwr, ...; _r reverses).
    #[arg(long, default_value = "coolwarm")]
    pub cmap: String,
    /// Highest colour (the lowest is its inverse) [default: from the data].
    #[arg(long)]
    pub vmax: Option<f64>,
    /// Facets per row [default: up to 4].
    #[arg(long)]
    pub columns: Option<usize>,
    /// The score written in each corner (a column of PREFIX.scores.tsv), or `none`.
    #[arg(long)]
    pub score: Option<String>,
    /// Output and size.
    #[command(flatten)]
    pub figure: FigureArgs,
}

/// The grids of `PREFIX.groups.tsv` or `PREFIX.pileup.tsv`: `(label, n, values)`.
fn grids(prefix: &str) -> Result<Vec<(String, usize, Vec<f64>)>> {
    let grouped = format!("{prefix}.groups.tsv");
    if Path::new(&grouped).exists() {
        let table = Table::read(&grouped)?;
        let mut out: Vec<(String, usize, Vec<f64>)> = Vec::new();
        for row in 0..table.len() {
            let label = table.text(row, 0).to_string();
            let values = (2..table.header().len())
                .map(|c| table.number(row, c))
                .collect::<Result<Vec<f64>>>()?;
            match out.last_mut() {
                Some(last) if last.0 == label => last.2.extend(values),
                _ => out.push((label, values.len(), values)),
            }
        }
        return Ok(out);
    }
    let path = format!("{prefix}.pileup.tsv");
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    let mut values = Vec::new();
    let mut n = 0;
    for (k, line) in text.lines().enumerate() {
        let row = line
            .split('\t')
            .map(|v| match v {
                "nan" => Ok(f64::NAN),
                v => v.parse::<f64>(),
            })
            .collect::<std::result::Result<Vec<f64>, _>>()
            .map_err(|_| Error::parse(&path, k as u64 + 1, "expected numbers (or nan)"))?;
        n = row.len();
        values.extend(row);
    }
    Ok(vec![("all".into(), n, values)])
}

/// Per group label, the score `name` (`None`: the first score column) of PREFIX.scores.tsv.
fn scores(prefix: &str, name: Option<&str>) -> Result<Vec<(String, f64)>> {
    let table = Table::read(&format!("{prefix}.scores.tsv"))?;
    let column = match name {
        Some(name) => table.column(name)?,
        None => match table
            .header()
            .iter()
            .position(|h| !["group", "n", "control_n"].contains(&h.as_str()))
        {
            Some(c) => c,
            None => return Ok(Vec::new()),
        },
    };
    (0..table.len())
        .map(|row| Ok((table.text(row, 0).to_string(), table.number(row, column)?)))
        .collect()
}

/// Run `contactmap plot pileup`.
pub fn run(args: &PileupPlotArgs) -> Result<()> {
    let prefix = args.prefix.as_str();
    let inputs = [
        PathBuf::from(format!("{prefix}.pileup.tsv")),
        PathBuf::from(format!("{prefix}.groups.tsv")),
        PathBuf::from(format!("{prefix}.scores.tsv")),
    ];
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    refuse_overwrites(&inputs, &[Some(&args.figure.out)])?;
    let figure = args.figure.check(DEFAULT_WIDTH_IN)?;
    let grids = grids(prefix)?;
    for (label, n, values) in &grids {
        if *n == 0 || values.len() != n * n {
            return Err(Error::format(
                format!("{prefix}.pileup.tsv"),
                format!("group {label}: {} values, not a square grid", values.len()),
            ));
        }
    }
    let scores = match args.score.as_deref() {
        Some("none") => Vec::new(),
        name => scores(prefix, name)?,
    };
    let (vmin, vmax) = match args.vmax {
        Some(vmax) if vmax > 1.0 && vmax.is_finite() => (1.0 / vmax, vmax),
        Some(vmax) => {
            return Err(Error::parameter(
                "vmax",
                vmax,
                "a number above 1 (the scale is 1/vmax to vmax)",
            ));
        }
        None => centred_limits(grids.iter().flat_map(|g| &g.2)),
    };
    let panels = grids
        .into_iter()
        .map(|(label, n, values)| PileupPanel {
            corner: scores
                .iter()
                .find(|(l, _)| *l == label)
                .map(|(_, v)| format!("{v:.2}")),
            title: label,
            n,
            values,
        })
        .collect::<Vec<_>>();
    let columns = args.columns.unwrap_or(panels.len().min(4));
    if columns == 0 {
        return Err(Error::parameter("columns", 0, "1 or more"));
    }
    let svg = draw_pileups(&PileupFigure {
        panels,
        columns,
        cmap: ColorMap::by_name(&args.cmap)?,
        scale: ColorScale::new(ScaleKind::Log, vmin, vmax)?,
        bar_label: "enrichment".into(),
        title: args.figure.title.clone().unwrap_or_default(),
        width_px: figure.width_px,
        dpi: figure.dpi,
    })?;
    write_figure(&svg, &figure, &args.figure)
}
