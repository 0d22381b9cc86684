//! `contactmap plot map`: a contact-map heatmap of a region or a pair of regions.

use std::ops::Range;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};

use super::figure::{FigureArgs, write_figure};
use crate::cli::args::InputArgs;
use crate::cli::input::expected_column;
use crate::cli::input::{open_for_analysis, read_weights};
use crate::cli::output::{column_file, refuse_overwrites, uri_file};
use contactmap::compare::check_comparable;
use contactmap::compare::coverage::total;
use contactmap::error::{Error, Result};
use contactmap::genome::{BinTable, Region};
use contactmap::io::bed::{BedRecord, read_bed, read_bedpe};
use contactmap::io::tables::read_track;
use contactmap::io::{LoadedPixels, MatrixReader, StreamedPixels};
use contactmap::normalize::{Method, Normalizer};
use contactmap::plot::heatmap::{AxisCells, CellGrid, GridComparison, colour_limits};
use contactmap::plot::map::{
    GenomicSpan, MapFigure, MapLayout, MapStyle, MapView, Overlays, Track, draw_map,
};
use contactmap::plot::{ColorMap, ColorScale, Rgb, ScaleKind};

/// Arguments of `contactmap plot map`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Values: balanced counts (count * w1 * w2 with the `weight` column, or --balanced COLUMN) unless
--raw; --oe divides by the expected of each diagonal (cooltools expected-cis balanced.avg or
count.avg, computed on the fly over whole chromosomes, or read from --expected), leaving out
the --ignore-diags first diagonals.

Drawing: the map takes the figure's width; when the region has more bins than the map has
pixels, each pixel shows the mean of the bins it covers (unstored pixels count as zeros; pairs
of masked bins are left out), so the image never needs the full matrix in memory. Colours: a log
scale (--linear for a linear one) between --vmin and --vmax, by default the --percentiles of the
drawn values (0,100: their minimum and maximum; positive values only on a log scale; o/e limits
are made symmetric around 1). Colour maps: fall (cooltools' default for Hi-C), blues,
acidblues, afmhot, RdBu, bwr, viridis, magma, inferno, plasma, Greys, gray, Reds, YlOrRd, each
reversed with _r; the default is fall, RdBu_r with --oe. Masked bins (NaN) are drawn in
--nan-color with a swatch under the colour bar; values at or below zero on a log scale take the
lowest colour.

--triangle rotates the upper triangle by 45 degrees: the diagonal along the bottom, the distance
between the two bins up to --depth (default: a quarter of the region). Overlays: --domains BED
(outlined squares, or triangles), --boundaries BED (marks across the diagonal at each
boundary's middle), --loops BEDPE (squares around each loop, both triangles when the anchors
are on one chromosome). --track FILE:COLUMN draws a line panel under the map (several stack):
FILE is a per-bin table starting `chrom start end` (a cooltools or `contactmap tads` insulation
table, a directionality table, an eigenvector table, a bedGraph), COLUMN a header name or a
1-based column number, and its rows over the region must be the map's bins.

--compare B draws a second map on the same bins: the first map on and above the diagonal, B
below it (one region, square view), or with --ratio log2(first / B) per cell (a diverging
colour map, RdBu_r by default, symmetric about 0). --compare-mode total multiplies B by the
ratio of the maps' totals (the sums of their contacts over the whole map, raw or balanced as
drawn); --compare-mode expected divides each map by its own expected (computed on the fly).

Examples:
  contactmap plot map data/yeast.10kb.cool -r chrIV:200k-800k -o map.png
  contactmap plot map in.mcool::/resolutions/10000 -r chr2L:5M-10M \\
      --triangle --depth 1M --domains domains.bed \\
      --track insulation.tsv:log2_insulation_score_100000 -o tads.svg
  contactmap plot map in.cool -r chr1 --oe -o oe.png
  contactmap plot map in.cool -r chr1 --region2 chr2 --raw --cmap viridis \\
      -o trans.png
  contactmap plot map wt.cool -r chr2:10M-15M --compare ko.cool -o split.png
  contactmap plot map wt.cool -r chr2:10M-15M --compare ko.cool --ratio \\
      --compare-mode expected -o log2ratio.png")]
pub struct MapArgs {
    /// Matrix URI: file.cool, file.mcool::/resolutions/N, file.hic[::/resolutions/N], text table.
    pub uri: String,
    /// Region of the rows (and of the columns without --region2): chrom or chrom:start-end.
    #[arg(short, long)]
    pub region: String,
    /// Region of the columns (another part of the genome, another chromosome).
    #[arg(long, value_name = "REGION")]
    pub region2: Option<String>,
    /// Raw counts (no balancing).
    #[arg(long, conflicts_with = "balanced")]
    pub raw: bool,
    /// Balance with this weight column (default `weight`, cooler's ICE weights).
    #[arg(long, value_name = "COLUMN", num_args = 0..=1, default_missing_value = "weight")]
    pub balanced: Option<String>,
    /// Observed / expected instead of contacts.
    #[arg(long)]
    pub oe: bool,
    /// Read the expected from this cooltools expected-cis table (with --oe).
    #[arg(long, value_name = "TSV", requires = "oe")]
    pub expected: Option<String>,
    /// Column of --expected (default balanced.avg, or count.avg with --raw).
    #[arg(long, value_name = "NAME", requires = "expected")]
    pub expected_column: Option<String>,
    /// Diagonals left out of the expected of o/e (2, as cooltools expected-cis, which does not
    /// read the number stored with the weights).
    #[arg(long, default_value_t = 2, value_name = "N")]
    pub ignore_diags: usize,
    /// Linear colour scale (default: log).
    #[arg(long)]
    pub linear: bool,
    /// Value of the lowest colour.
    #[arg(long, allow_negative_numbers = true)]
    pub vmin: Option<f64>,
    /// Value of the highest colour.
    #[arg(long, allow_negative_numbers = true)]
    pub vmax: Option<f64>,
    /// Percentiles of the drawn values giving the colour limits when --vmin / --vmax are absent.
    #[arg(
        long,
        value_name = "LOW,HIGH",
        value_delimiter = ',',
        default_value = "0,100"
    )]
    pub percentiles: Vec<f64>,
    /// Colour map (see below; `_r` reverses).
    #[arg(long, value_name = "NAME")]
    pub cmap: Option<String>,
    /// Colour of NaN (masked) bins: #rrggbb or a name.
    #[arg(long, value_name = "COLOUR", default_value = "lightgrey")]
    pub nan_color: String,
    /// The 45-degree view, for TAD figures.
    #[arg(long)]
    pub triangle: bool,
    /// Largest distance shown by --triangle (e.g. 2Mb; default: a quarter of the region).
    #[arg(long, value_name = "BP", requires = "triangle")]
    pub depth: Option<String>,
    /// Domains to outline (BED).
    #[arg(long, value_name = "BED")]
    pub domains: Option<PathBuf>,
    /// Boundaries to mark (BED).
    #[arg(long, value_name = "BED")]
    pub boundaries: Option<PathBuf>,
    /// Loops to outline (BEDPE).
    #[arg(long, value_name = "BEDPE")]
    pub loops: Option<PathBuf>,
    /// A track panel under the map: FILE:COLUMN (repeat for several).
    #[arg(long, value_name = "FILE:COLUMN")]
    pub track: Vec<String>,
    /// A second map on the same bins: drawn below the diagonal (the first map above), or the
    /// log2 ratio of the two with --ratio.
    #[arg(long, value_name = "URI", conflicts_with = "oe")]
    pub compare: Option<String>,
    /// With --compare: draw log2(first / second) on a diverging scale centred at 0.
    #[arg(long, requires = "compare")]
    pub ratio: bool,
    /// With --compare: bring the maps to one scale by their totals (`total`, the default) or
    /// divide each by its own expected (`expected`).
    #[arg(long, value_enum, value_name = "MODE", requires = "compare")]
    pub compare_mode: Option<CompareMode>,
    /// Output, size, dpi, title.
    #[command(flatten)]
    pub figure: FigureArgs,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// How `--compare` puts two maps on one scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CompareMode {
    /// The second map times the first map's total over its own (total contacts, raw or
    /// balanced).
    Total,
    /// Each map divided by its own expected (observed / expected).
    Expected,
}

/// Default figure width in inches.
const DEFAULT_WIDTH_IN: f64 = 6.0;

/// Run `contactmap plot map`.
pub fn run(args: &MapArgs) -> Result<()> {
    let inputs: Vec<&Path> = std::iter::once(uri_file(&args.uri))
        .chain(args.compare.as_deref().map(uri_file))
        .chain(args.expected.as_deref().map(Path::new))
        .chain(args.domains.as_deref())
        .chain(args.boundaries.as_deref())
        .chain(args.loops.as_deref())
        .chain(args.track.iter().map(|track| column_file(track)))
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[Some(&args.figure.out)])?;
    let figure = args.figure.check(DEFAULT_WIDTH_IN)?;
    // With --compare-mode expected, each map is drawn as observed / expected.
    let oe =
        args.oe || (args.compare.is_some() && args.compare_mode == Some(CompareMode::Expected));
    let colour_map = ColorMap::by_name(args.cmap.as_deref().unwrap_or(if oe || args.ratio {
        "RdBu_r"
    } else {
        "fall"
    }))?;
    let nan = Rgb::parse(&args.nan_color).ok_or_else(|| {
        Error::Argument(format!(
            "--nan-color '{}' is not a colour (#rrggbb, #rgb or a name such as lightgrey)",
            args.nan_color
        ))
    })?;
    if args.percentiles.len() != 2
        || !(0.0..=100.0).contains(&args.percentiles[0])
        || !(args.percentiles[0] < args.percentiles[1] && args.percentiles[1] <= 100.0)
    {
        return Err(Error::Argument(
            "--percentiles takes LOW,HIGH with 0 <= LOW < HIGH <= 100".into(),
        ));
    }
    let reader = open_for_analysis(&args.uri, &args.input)?;
    let bins = reader.bins().clone();
    let rows = region_bins(&bins, &args.region, reader.source())?;
    let cols = match &args.region2 {
        Some(text) => region_bins(&bins, text, reader.source())?,
        None => rows.clone(),
    };
    let row_span = GenomicSpan::of_bins(&bins, &rows);
    let col_span = GenomicSpan::of_bins(&bins, &cols);
    let same_chrom = row_span.chrom == col_span.chrom;
    let view = if args.triangle {
        if rows != cols {
            return Err(Error::Argument(
                "--triangle draws one region: leave out --region2".into(),
            ));
        }
        let length = col_span.end_bp - col_span.start_bp;
        let depth = match &args.depth {
            Some(text) => contactmap::genome::parse_bp(text)
                .map_err(|m| Error::Argument(format!("--depth '{text}': {m}")))?,
            None => length.div_ceil(4),
        };
        if depth == 0 {
            return Err(Error::Argument("--depth must be positive".into()));
        }
        MapView::Triangle {
            depth_bp: depth.min(length),
        }
    } else {
        MapView::Square
    };
    if args.compare.is_some() && !args.ratio && (rows != cols || args.triangle) {
        return Err(Error::Argument(
            "--compare splits one square map along its diagonal: leave out --region2 and \
             --triangle, or draw the log2 ratio (--ratio)"
                .into(),
        ));
    }
    if oe && !same_chrom {
        return Err(Error::Argument(
            "observed / expected (--oe, --compare-mode expected) needs both regions on one \
             chromosome (the expected is per diagonal)"
                .into(),
        ));
    }
    let weight_name = args.balanced.as_deref().unwrap_or("weight");
    // the weights drawn with (none for --raw)
    let weights_of = |reader: &dyn MatrixReader| {
        (!args.raw)
            .then(|| read_weights(reader, weight_name, "--balanced", true))
            .transpose()
    };
    let weights = weights_of(reader.as_ref())?;
    let second = args
        .compare
        .as_deref()
        .map(|uri| -> Result<_> {
            let other = open_for_analysis(uri, &args.input)?;
            check_comparable(reader.as_ref(), other.as_ref())?;
            let weights = weights_of(other.as_ref())?;
            Ok((other, weights))
        })
        .transpose()?;

    let overlays = read_overlays(args, &row_span, &col_span)?;
    let tracks = args
        .track
        .iter()
        .map(|spec| {
            let (path, column) = crate::cli::input::file_column(spec, "--track", None)?;
            let rows = read_track(Path::new(path), column)?;
            Track::from_rows(Path::new(path), column, rows, &bins, &cols, &col_span)
        })
        .collect::<Result<Vec<_>>>()?;

    let layout = MapLayout::new(
        figure.width_px,
        figure.height_px,
        figure.dpi,
        view,
        &row_span,
        &col_span,
        tracks.len(),
    );
    let (max_rows, max_cols) = match view {
        MapView::Square => (layout.map_height_px(), layout.map_width_px()),
        MapView::Triangle { .. } => (layout.map_width_px(), layout.map_width_px()),
    };
    let fill = |reader: &dyn MatrixReader, weights: Option<&[f64]>| -> Result<CellGrid> {
        let normalizer = match oe {
            true => Some(oe_normalizer(args, reader, weights.map(<[f64]>::to_vec))?),
            false => None,
        };
        let valid = |bin: usize| weights.is_none_or(|w| w[bin].is_finite());
        let mut grid = CellGrid::new(
            AxisCells::new(rows.clone(), max_rows),
            AxisCells::new(cols.clone(), max_cols),
            &valid,
            if oe { args.ignore_diags } else { 0 },
            same_chrom,
        );
        grid.fill(reader, weights, normalizer.as_ref())?;
        Ok(grid)
    };
    let grid = fill(reader.as_ref(), weights.as_deref())?;
    let grid = match &second {
        None => grid,
        Some((other, other_weights)) => {
            let other_grid = fill(other.as_ref(), other_weights.as_deref())?;
            let scale_second = if oe {
                1.0
            } else {
                total(reader.as_ref(), weights.as_deref())?
                    / total(other.as_ref(), other_weights.as_deref())?
            };
            let how = match args.ratio {
                true => GridComparison::Log2Ratio { scale_second },
                false => GridComparison::Split { scale_second },
            };
            CellGrid::compared(&grid, &other_grid, how)?
        }
    };

    let scale = colour_scale(args, oe, &grid.values(), &args.region)?;
    let name = |uri: &str| {
        let path = uri_file(uri);
        path.file_stem().map_or_else(
            || path.display().to_string(),
            |stem| stem.to_string_lossy().into_owned(),
        )
    };
    let second_name = args.compare.as_deref().map(name);
    let colour_label = if let (true, Some(second)) = (args.ratio, &second_name) {
        format!("log2({} / {second})", name(&args.uri))
    } else if oe {
        "observed / expected".to_string()
    } else if args.raw {
        "contacts".to_string()
    } else if weight_name == "weight" {
        "balanced contacts".to_string()
    } else {
        format!("contacts balanced by {weight_name}")
    };
    let style = MapStyle {
        colour_map,
        scale,
        nan,
        colour_label,
        title: match (&args.figure.title, &second_name) {
            (Some(title), _) => title.clone(),
            (None, Some(second)) if !args.ratio => {
                format!("{} (upper) vs {second} (lower)", name(&args.uri))
            }
            (None, _) => String::new(),
        },
    };
    let svg = draw_map(&MapFigure {
        layout: &layout,
        view,
        grid: &grid,
        rows: &row_span,
        cols: &col_span,
        style: &style,
        overlays: &overlays,
        tracks: &tracks,
    })?;
    write_figure(&svg, &figure, &args.figure)?;
    crate::cli::warnings::print_reader_warnings(reader.warnings());
    Ok(())
}

/// The bins of region `text`, which must hold at least one.
fn region_bins(bins: &BinTable, text: &str, source: &str) -> Result<Range<usize>> {
    let range = bins.region_bins(&Region::parse(text)?)?;
    if range.is_empty() {
        return Err(Error::region(
            text,
            format!("no bins of {source} in this region (empty region)"),
        ));
    }
    Ok(range)
}

/// The o/e transform: the expected of every chromosome, computed or read.
fn oe_normalizer(
    args: &MapArgs,
    reader: &dyn MatrixReader,
    weights: Option<Vec<f64>>,
) -> Result<Normalizer> {
    let bins = reader.bins();
    let curves = match &args.expected {
        Some(path) => contactmap::expected::table::curves(
            &contactmap::io::tables::Table::read(path)?,
            bins,
            expected_column(args.expected_column.as_deref(), args.raw),
        )?,
        None => {
            let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader));
            contactmap::expected::cis_curves(&pixels, weights.as_deref(), args.ignore_diags)?
        }
    };
    Normalizer::new(Method::Oe, bins.n_bins(), weights, curves)
}

/// The colour scale from the options and the drawn values.
fn colour_scale(args: &MapArgs, oe: bool, values: &[f64], region: &str) -> Result<ColorScale> {
    let kind = if args.linear || args.ratio {
        ScaleKind::Linear
    } else {
        ScaleKind::Log
    };
    let (vmin, vmax) = match (args.vmin, args.vmax) {
        (Some(a), Some(b)) => (a, b),
        (low, high) => {
            let free = low.is_none() && high.is_none();
            let centre = match (args.ratio, oe) {
                (true, _) if free => Some(0.0),
                (false, true) if free => Some(1.0),
                _ => None,
            };
            let (a, b) = colour_limits(
                values,
                kind,
                args.percentiles[0],
                args.percentiles[1],
                centre,
            )
            .ok_or_else(|| {
                Error::region(
                    region,
                    format!(
                        "no {}values to draw (the region holds no contacts); give --vmin and --vmax to draw it anyway",
                        if kind == ScaleKind::Log { "positive " } else { "" }
                    ),
                )
            })?;
            (low.unwrap_or(a), high.unwrap_or(b))
        }
    };
    ColorScale::new(kind, vmin, vmax)
}

/// Domains, boundaries and loops on the drawn regions.
fn read_overlays(args: &MapArgs, rows: &GenomicSpan, cols: &GenomicSpan) -> Result<Overlays> {
    let bed = |path: &Option<PathBuf>| -> Result<Vec<BedRecord>> {
        path.as_deref().map_or(Ok(Vec::new()), read_bed)
    };
    let loops = match &args.loops {
        Some(path) => read_bedpe(path)?,
        None => Vec::new(),
    };
    Ok(Overlays::on_spans(
        &bed(&args.domains)?,
        &bed(&args.boundaries)?,
        &loops,
        rows,
        cols,
    ))
}
