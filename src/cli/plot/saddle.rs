//! `contactmap plot saddle`: the picture of a saddle computed by `contactmap saddle`.

use std::path::PathBuf;

use clap::Args;

use super::figure::{FigureArgs, write_figure};
use crate::cli::output::refuse_overwrites;
use contactmap::error::{Error, Result};
use contactmap::io::tables::Table;
use contactmap::plot::saddle::{SaddleFigure, draw_saddle};
use contactmap::plot::{ColorMap, ColorScale, ScaleKind};

/// Default figure width in inches.
const DEFAULT_WIDTH_IN: f64 = 5.5;

/// Arguments of `contactmap plot saddle`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Draws PREFIX.saddle.tsv (written by `contactmap saddle`: i j sum count) as cooltools'
saddleplot does: each cell is the mean observed/expected (sum / count) of a pair of track
classes, classes from the lowest track values (top left: B-B for an E1 track) to the highest
(bottom right: A-A), on a log colour scale from --vmin to --vmax (default 0.5 to 2, centred on
1). The two outlier classes (below the first edge, above the last) are left out, as cooltools
does, unless --with-outliers. The axes name the track (E1 ...) read from PREFIX.digitized.tsv
beside the table, or --track-name.

Examples:
  contactmap saddle in.cool --track eigs.cis.vecs.tsv:E1 -o s
  contactmap plot saddle s.saddle.tsv -o saddle.png --title 'sample 1, 100 kb'")]
pub struct SaddlePlotArgs {
    /// The saddle table (PREFIX.saddle.tsv of `contactmap saddle`).
    #[arg(value_name = "SADDLE.tsv")]
    pub saddle: PathBuf,
    /// Colour map (RdBu_r, bwr, viridis, ...; _r reverses).
    #[arg(long, default_value = "RdBu_r")]
    pub cmap: String,
    /// Lowest colour (observed/expected).
    #[arg(long, default_value_t = 0.5)]
    pub vmin: f64,
    /// Highest colour (observed/expected).
    #[arg(long, default_value_t = 2.0)]
    pub vmax: f64,
    /// Keep the two outlier classes.
    #[arg(long)]
    pub with_outliers: bool,
    /// The track's name on the axes [default: the column of PREFIX.digitized.tsv beside the
    /// table, e.g. E1; else `track`].
    #[arg(long, value_name = "NAME")]
    pub track_name: Option<String>,
    /// Output and size.
    #[command(flatten)]
    pub figure: FigureArgs,
}

/// The track's name: --track-name, else the column `NAME.d` of the `digitized.tsv` that
/// `contactmap saddle` wrote beside the table (same prefix), else `track`.
fn track_name(args: &SaddlePlotArgs) -> String {
    if let Some(name) = &args.track_name {
        return name.clone();
    }
    let text = args.saddle.to_string_lossy();
    text.strip_suffix(".saddle.tsv")
        .and_then(|prefix| std::fs::read_to_string(format!("{prefix}.digitized.tsv")).ok())
        .and_then(|table| {
            let header = table.lines().next()?.to_string();
            let column = header.split('\t').nth(3)?;
            column.strip_suffix(".d").map(String::from)
        })
        .filter(|name| !name.is_empty())
        .unwrap_or_else(|| "track".into())
}

/// Run `contactmap plot saddle`.
pub fn run(args: &SaddlePlotArgs) -> Result<()> {
    refuse_overwrites(&[args.saddle.as_path()], &[Some(&args.figure.out)])?;
    let figure = args.figure.check(DEFAULT_WIDTH_IN)?;
    let table = Table::read(&args.saddle.to_string_lossy())?;
    let (ci, cj, cs, cc) = (
        table.column("i")?,
        table.column("j")?,
        table.column("sum")?,
        table.column("count")?,
    );
    let mut cells = Vec::with_capacity(table.len());
    for row in 0..table.len() {
        let index = |c: usize| -> Result<usize> {
            let v = table.number(row, c)?;
            if v >= 0.0 && v.fract() == 0.0 {
                Ok(v as usize)
            } else {
                Err(Error::format(
                    table.path(),
                    format!("row {}: class {v} is not a class index", row + 2),
                ))
            }
        };
        cells.push((
            index(ci)?,
            index(cj)?,
            table.number(row, cs)?,
            table.number(row, cc)?,
        ));
    }
    let full = cells
        .iter()
        .map(|c| c.0.max(c.1))
        .max()
        .map_or(0, |m| m + 1);
    if full == 0 || cells.len() != full * full {
        return Err(Error::format(
            table.path(),
            format!(
                "expected the {0} x {0} class pairs of a saddle, found {1} rows",
                full,
                cells.len()
            ),
        ));
    }
    let (skip, n) = if args.with_outliers || full < 3 {
        (0, full)
    } else {
        (1, full - 2)
    };
    let mut values = vec![f64::NAN; n * n];
    for &(i, j, sum, count) in &cells {
        if i < skip || j < skip || i - skip >= n || j - skip >= n {
            continue;
        }
        values[(i - skip) * n + (j - skip)] = if count > 0.0 { sum / count } else { f64::NAN };
    }
    let svg = draw_saddle(&SaddleFigure {
        n,
        values,
        cmap: ColorMap::by_name(&args.cmap)?,
        scale: ColorScale::new(ScaleKind::Log, args.vmin, args.vmax)?,
        axis_label: format!("{} class (low to high)", track_name(args)),
        bar_label: "mean observed / expected".into(),
        title: args.figure.title.clone().unwrap_or_default(),
        width_px: figure.width_px,
        dpi: figure.dpi,
    })?;
    write_figure(&svg, &figure, &args.figure)
}
