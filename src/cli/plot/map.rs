//! `contactmap plot map`: a contact-map heatmap of a region or a pair of regions.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};

use super::figure::{FigureArgs, write_figure};
use crate::cli::args::InputArgs;
use crate::cli::input::expected_column;
use crate::cli::input::{open_for_analysis, read_weights};
use crate::cli::output::{column_file, refuse_overwrites, uri_file};
use contactmap::error::{Error, Result};
use contactmap::io::MatrixReader;
use contactmap::io::bed::{BedRecord, read_bed, read_bedpe};
use contactmap::io::tables::{Table, read_track};
use contactmap::plot::Rgb;
use contactmap::plot::map_job::{
    Comparison, ExpectedTable, MapDecorations, MapRequest, MapSource, map_figure,
};

/// The colours of the loops of a `contactmap diff loops` table (a header with `chrom1` first
/// and a `direction` column): red up in B, blue down, grey unchanged; empty for another BEDPE.
fn diff_loop_colours(path: &Path) -> Result<Vec<Rgb>> {
    let text = path.display().to_string();
    if !Table::starts_with_column(&text, "chrom1")? {
        return Ok(Vec::new());
    }
    let table = Table::read(&text)?;
    let Ok(direction) = table.column("direction") else {
        return Ok(Vec::new());
    };
    Ok((0..table.len())
        .map(|row| match table.text(row, direction) {
            "up" => Rgb(214, 39, 40),
            "down" => Rgb(31, 119, 180),
            _ => Rgb(150, 150, 150),
        })
        .collect())
}

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
are on one chromosome; the table of `contactmap diff loops` colours them by direction: red up
in B, blue down, grey unchanged). --track FILE:COLUMN draws a line panel under the map (several stack):
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
  contactmap plot map wt.cool -r chr2:10M-15M --compare ko.cool \\
      --loops wt_vs_ko.loops.bedpe -o diff_loops.png
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

/// A map opened, with the weights it is drawn with (none for --raw).
type Opened = (Box<dyn MatrixReader>, Option<Vec<f64>>);

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
    let nan = Rgb::parse(&args.nan_color).ok_or_else(|| {
        Error::Argument(format!(
            "--nan-color '{}' is not a colour (#rrggbb, #rgb or a name such as lightgrey)",
            args.nan_color
        ))
    })?;
    let percentiles = match args.percentiles[..] {
        [low, high] => [low, high],
        _ => {
            return Err(Error::Argument(
                "--percentiles takes LOW,HIGH with 0 <= LOW < HIGH <= 100".into(),
            ));
        }
    };
    let depth_bp = match &args.depth {
        Some(text) => Some(
            contactmap::genome::parse_bp(text)
                .map_err(|m| Error::Argument(format!("--depth '{text}': {m}")))?,
        ),
        None => None,
    };
    let weight_name = args.balanced.as_deref().unwrap_or("weight");
    let request = MapRequest {
        region: args.region.clone(),
        region2: args.region2.clone(),
        triangle: args.triangle,
        depth_bp,
        // with --compare-mode expected, each map is drawn as observed / expected
        oe: args.oe || (args.compare.is_some() && args.compare_mode == Some(CompareMode::Expected)),
        ignore_diags: args.ignore_diags,
        comparison: args.compare.as_ref().map(|_| match args.ratio {
            true => Comparison::Log2Ratio,
            false => Comparison::Split,
        }),
        linear: args.linear,
        vmin: args.vmin,
        vmax: args.vmax,
        percentiles,
        colour_map: args.cmap.clone(),
        nan,
        weight_name: weight_name.to_string(),
        title: args.figure.title.clone(),
        width_px: figure.width_px,
        height_px: figure.height_px,
        dpi: figure.dpi,
    };
    request.check()?;
    // the maps, with the weights drawn with (none for --raw)
    let open = |uri: &str| -> Result<Opened> {
        let reader = open_for_analysis(uri, &args.input)?;
        let weights = (!args.raw)
            .then(|| read_weights(reader.as_ref(), weight_name, "--balanced", true))
            .transpose()?;
        Ok((reader, weights))
    };
    let name = |uri: &str| {
        let path = uri_file(uri);
        path.file_stem().map_or_else(
            || path.display().to_string(),
            |stem| stem.to_string_lossy().into_owned(),
        )
    };
    let (reader, weights) = open(&args.uri)?;
    let second = match args.compare.as_deref() {
        Some(uri) => Some((open(uri)?, name(uri))),
        None => None,
    };
    let expected = args.expected.as_deref().map(Table::read).transpose()?;
    let expected = expected.as_ref().map(|table| ExpectedTable {
        table,
        column: expected_column(args.expected_column.as_deref(), args.raw),
    });
    let bed = |path: &Option<PathBuf>| -> Result<Vec<BedRecord>> {
        path.as_deref().map_or(Ok(Vec::new()), read_bed)
    };
    let decorations = MapDecorations {
        domains: bed(&args.domains)?,
        boundaries: bed(&args.boundaries)?,
        loops: match &args.loops {
            Some(path) => read_bedpe(path)?,
            None => Vec::new(),
        },
        loop_colours: match &args.loops {
            Some(path) => diff_loop_colours(path)?,
            None => Vec::new(),
        },
        tracks: args
            .track
            .iter()
            .map(|spec| {
                let (path, column) = crate::cli::input::file_column(spec, "--track", None)?;
                let rows = read_track(Path::new(path), column)?;
                Ok((PathBuf::from(path), column.to_string(), rows))
            })
            .collect::<Result<Vec<_>>>()?,
    };
    let first = MapSource {
        reader: reader.as_ref(),
        weights: weights.as_deref(),
        name: name(&args.uri),
    };
    let second = second.as_ref().map(|((reader, weights), name)| MapSource {
        reader: reader.as_ref(),
        weights: weights.as_deref(),
        name: name.clone(),
    });
    let svg = map_figure(
        &request,
        &first,
        second.as_ref(),
        expected.as_ref(),
        &decorations,
    )?;
    write_figure(&svg, &figure, &args.figure)?;
    crate::cli::warnings::print_reader_warnings(reader.warnings());
    Ok(())
}
