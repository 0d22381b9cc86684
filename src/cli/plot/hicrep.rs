//! `contactmap plot hicrep`: the SCC table of `contactmap hicrep` as a clustered heatmap.

use std::path::PathBuf;

use clap::Args;

use super::figure::{FigureArgs, write_figure};
use crate::cli::output::refuse_overwrites;
use contactmap::compare::cluster::Dendrogram;
use contactmap::compare::hicrep::SccTable;
use contactmap::error::{Error, Result};
use contactmap::io::tables::Table;
use contactmap::plot::similarity::{SimilarityFigure, draw_similarity};
use contactmap::plot::{ColorMap, ColorScale, Rgb, ScaleKind};

/// Default figure width in inches.
const DEFAULT_WIDTH_IN: f64 = 6.0;

/// Arguments of `contactmap plot hicrep`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Draws the SCC table of `contactmap hicrep` (sample1 sample2 chrom length scc) as a clustered
heatmap, as seaborn's clustermap: the samples ordered by average-linkage clustering (UPGMA,
scipy's linkage(method='average') and dendrogram leaf order) of the distances 1 - SCC, the tree
above the matrix, each cell's SCC written in it when the cells are large enough. A pair whose
SCC is nan is drawn in --nan-color and clustered at distance 1. The genome-wide rows are drawn
unless --chrom names a chromosome. Colours: --cmap between --vmin (default: the lowest SCC
drawn) and --vmax (default 1).

Examples:
  contactmap hicrep s1.cool s2.cool s3.cool s4.cool --h 3 -o scc.tsv
  contactmap plot hicrep scc.tsv -o scc.png
  contactmap plot hicrep scc.tsv --chrom chr2 --no-cluster -o chr2.svg")]
pub struct HicrepPlotArgs {
    /// The table of `contactmap hicrep` (tab-separated, with its header).
    #[arg(value_name = "SCC.tsv")]
    pub table: PathBuf,
    /// Draw this chromosome's SCCs instead of the genome-wide ones.
    #[arg(long, default_value = "genome")]
    pub chrom: String,
    /// Keep the samples in the table's order (no clustering, no tree).
    #[arg(long)]
    pub no_cluster: bool,
    /// Colour map (viridis, magma, RdBu_r, Greys, ...; _r reverses).
    #[arg(long, default_value = "viridis")]
    pub cmap: String,
    /// Lowest colour (default: the lowest SCC drawn).
    #[arg(long, allow_negative_numbers = true)]
    pub vmin: Option<f64>,
    /// Highest colour.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub vmax: f64,
    /// Colour of pairs without an SCC: #rrggbb or a name.
    #[arg(long, value_name = "COLOUR", default_value = "lightgrey")]
    pub nan_color: String,
    /// Output and size.
    #[command(flatten)]
    pub figure: FigureArgs,
}

/// Run `contactmap plot hicrep`.
pub fn run(args: &HicrepPlotArgs) -> Result<()> {
    refuse_overwrites(&[args.table.as_path()], &[Some(&args.figure.out)])?;
    let figure = args.figure.check(DEFAULT_WIDTH_IN)?;
    let nan = Rgb::parse(&args.nan_color).ok_or_else(|| {
        Error::parameter(
            "nan-color",
            &args.nan_color,
            "a colour (#rrggbb, #rgb or a name such as lightgrey)",
        )
    })?;
    let table = Table::read(&args.table.to_string_lossy())?;
    let columns = [
        table.column("sample1")?,
        table.column("sample2")?,
        table.column("chrom")?,
        table.column("scc")?,
    ];
    let mut rows = Vec::new();
    for row in 0..table.len() {
        if table.text(row, columns[2]) != args.chrom {
            continue;
        }
        rows.push((
            table.text(row, columns[0]).to_string(),
            table.text(row, columns[1]).to_string(),
            table.number(row, columns[3])?,
        ));
    }
    if rows.is_empty() {
        // the chromosomes of the table, in order, to name them (and a `chr` prefix that differs)
        let mut chroms: Vec<&str> = Vec::new();
        for row in 0..table.len() {
            let chrom = table.text(row, columns[2]);
            if !chroms.contains(&chrom) {
                chroms.push(chrom);
            }
        }
        let other = match args.chrom.strip_prefix("chr") {
            Some(bare) => bare.to_string(),
            None => format!("chr{}", args.chrom),
        };
        let hint = if chroms.contains(&other.as_str()) {
            format!(": the table names it '{other}' (the names differ by the 'chr' prefix)")
        } else {
            String::new()
        };
        return Err(Error::format(
            table.path(),
            format!(
                "no row of chromosome '{}' (the table has {}){hint}",
                args.chrom,
                chroms.join(", ")
            ),
        ));
    }
    let scc = SccTable::from_pairs(&rows)
        .map_err(|why| Error::format(table.path(), format!("chrom {}: {why}", args.chrom)))?;
    let n = scc.names.len();
    let dendrogram = if args.no_cluster {
        None
    } else {
        Some(Dendrogram::average_linkage(&scc.distances(), n)?)
    };
    let lowest = scc
        .values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::INFINITY, f64::min);
    let vmin = match args.vmin {
        Some(v) => v,
        None if lowest < args.vmax => lowest,
        None => args.vmax - 0.1,
    };
    let scale = ColorScale::new(ScaleKind::Linear, vmin, args.vmax)?;
    let svg = draw_similarity(&SimilarityFigure {
        names: scc.names,
        values: scc.values,
        dendrogram,
        cmap: ColorMap::by_name(&args.cmap)?,
        scale,
        nan,
        bar_label: if args.chrom == "genome" {
            "SCC (genome-wide)".into()
        } else {
            format!("SCC ({})", args.chrom)
        },
        title: args.figure.title.clone().unwrap_or_default(),
        width_px: figure.width_px,
        dpi: figure.dpi,
    })?;
    write_figure(&svg, &figure, &args.figure)
}
