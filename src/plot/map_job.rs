//! `plot map` as one call ([`map_figure`]): the cells of a region (or a pair of regions) filled
//! from one map or two (balanced, raw or observed / expected; a second map below the diagonal or
//! as a log2 ratio), the colour scale from the drawn values, and the figure drawn with its
//! overlays and track panels. The caller opens the maps and reads the overlays' and tracks'
//! files; the checks of what can be drawn together are here.

use std::ops::Range;
use std::path::PathBuf;

use super::colormap::{ColorMap, ColorScale, ScaleKind};
use super::heatmap::{AxisCells, CellGrid, GridComparison, colour_limits};
use super::map::{GenomicSpan, MapFigure, MapLayout, MapStyle, MapView, Overlays, Track, draw_map};
use super::svg::{Rgb, Svg};
use crate::compare::check_comparable;
use crate::compare::coverage::total;
use crate::error::{Error, Result};
use crate::genome::{BinTable, Region};
use crate::io::bed::{BedRecord, BedpeRecord};
use crate::io::tables::{Table, TrackRow};
use crate::io::{LoadedPixels, MatrixReader, StreamedPixels};
use crate::normalize::{Method, Normalizer};

/// One map to draw.
pub struct MapSource<'a> {
    /// The map.
    pub reader: &'a dyn MatrixReader,
    /// Its weights; `None` draws raw counts.
    pub weights: Option<&'a [f64]>,
    /// Its name in the title and the colour bar's label (the file's stem).
    pub name: String,
}

/// How a second map is drawn against the first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Comparison {
    /// The first map on and above the diagonal, the second below it.
    Split,
    /// log2(first / second) per cell.
    Log2Ratio,
}

/// What to draw and how: the regions, the view, the values, the colours, the figure's size.
#[derive(Clone, Debug)]
pub struct MapRequest {
    /// Region of the rows (and of the columns without `region2`): `chrom` or `chrom:start-end`.
    pub region: String,
    /// Region of the columns.
    pub region2: Option<String>,
    /// The 45-degree view, up to `depth_bp` from the diagonal (default: a quarter of the region).
    pub triangle: bool,
    /// The largest distance the 45-degree view shows (bp).
    pub depth_bp: Option<u64>,
    /// Observed / expected: each map divided by its own expected.
    pub oe: bool,
    /// Diagonals left out of the expected of o/e.
    pub ignore_diags: usize,
    /// How the second map is drawn: `None` for one map, which [`map_figure`] then takes alone.
    pub comparison: Option<Comparison>,
    /// A linear colour scale (else log; always linear for a log2 ratio).
    pub linear: bool,
    /// Value of the lowest colour (default from `percentiles`).
    pub vmin: Option<f64>,
    /// Value of the highest colour.
    pub vmax: Option<f64>,
    /// Percentiles of the drawn values giving the colour limits `vmin` / `vmax` leave free:
    /// `0 <= low < high <= 100`.
    pub percentiles: [f64; 2],
    /// Colour map name (default `fall`, `RdBu_r` for o/e and ratios).
    pub colour_map: Option<String>,
    /// Colour of masked (NaN) cells.
    pub nan: Rgb,
    /// The weight column drawn with (named in the colour bar's label; `weight`: "balanced").
    pub weight_name: String,
    /// Title (default: none, or "A (upper) vs B (lower)" for two maps split).
    pub title: Option<String>,
    /// Figure width (px).
    pub width_px: usize,
    /// Figure height (px; default from the width).
    pub height_px: Option<usize>,
    /// Resolution (dots per inch) of the text and lines.
    pub dpi: f64,
}

impl MapRequest {
    /// An error unless the colour map is known and the percentiles are `0 <= low < high <=
    /// 100` (what can be checked before a map is read).
    pub fn check(&self) -> Result<()> {
        self.colour_map()?;
        let [low, high] = self.percentiles;
        if !((0.0..=100.0).contains(&low) && low < high && high <= 100.0) {
            return Err(Error::Argument(
                "--percentiles takes LOW,HIGH with 0 <= LOW < HIGH <= 100".into(),
            ));
        }
        Ok(())
    }

    /// Whether a log2 ratio of two maps is drawn.
    fn ratio(&self) -> bool {
        self.comparison == Some(Comparison::Log2Ratio)
    }

    /// The colour map: the one named, else `RdBu_r` for o/e and ratios, `fall` otherwise.
    fn colour_map(&self) -> Result<ColorMap> {
        let default = if self.oe || self.ratio() {
            "RdBu_r"
        } else {
            "fall"
        };
        ColorMap::by_name(self.colour_map.as_deref().unwrap_or(default))
    }
}

/// The features drawn over the map and the panels under it, as read from their files.
#[derive(Clone, Debug, Default)]
pub struct MapDecorations {
    /// Domains (BED): squares on the diagonal, triangles in the 45-degree view.
    pub domains: Vec<BedRecord>,
    /// Boundaries (BED): marks across the diagonal.
    pub boundaries: Vec<BedRecord>,
    /// Loops (BEDPE): squares around each.
    pub loops: Vec<BedpeRecord>,
    /// Each loop's colour (empty: all in the outline colour).
    pub loop_colours: Vec<Rgb>,
    /// Track panels: the table's path (named in messages), its column and its rows.
    pub tracks: Vec<(PathBuf, String, Vec<TrackRow>)>,
}

/// The expected table o/e reads (`table`, column `column`) instead of computing the expected.
pub struct ExpectedTable<'a> {
    /// The cooltools expected-cis table.
    pub table: &'a Table,
    /// Its column (`balanced.avg`, `count.avg`).
    pub column: &'a str,
}

/// The figure of `request`: `first` alone, or with `second` (on the same bins) drawn as
/// `request.comparison` says (a second map is given with a comparison, and only then); o/e from `expected` when given (one map), else computed over
/// whole chromosomes. Errors say what cannot be drawn together (`--region2` with the 45-degree
/// view or a split comparison, o/e across chromosomes, maps on other bins) and name the region
/// when it holds nothing to draw.
pub fn map_figure(
    request: &MapRequest,
    first: &MapSource<'_>,
    second: Option<&MapSource<'_>>,
    expected: Option<&ExpectedTable<'_>>,
    decorations: &MapDecorations,
) -> Result<Svg> {
    request.check()?;
    if second.is_some() != request.comparison.is_some() {
        return Err(Error::Argument(
            "a second map is drawn with a comparison (split or log2 ratio), and a comparison \
             needs a second map"
                .into(),
        ));
    }
    let ratio = request.ratio();
    let colour_map = request.colour_map()?;
    let reader = first.reader;
    let bins = reader.bins().clone();
    let rows = region_bins(&bins, &request.region, reader.source())?;
    let cols = match &request.region2 {
        Some(text) => region_bins(&bins, text, reader.source())?,
        None => rows.clone(),
    };
    let row_span = GenomicSpan::of_bins(&bins, &rows);
    let col_span = GenomicSpan::of_bins(&bins, &cols);
    let same_chrom = row_span.chrom == col_span.chrom;
    let view = if request.triangle {
        if rows != cols {
            return Err(Error::Argument(
                "--triangle draws one region: leave out --region2".into(),
            ));
        }
        let length = col_span.end_bp - col_span.start_bp;
        let depth = request.depth_bp.unwrap_or(length.div_ceil(4));
        if depth == 0 {
            return Err(Error::Argument("--depth must be positive".into()));
        }
        MapView::Triangle {
            depth_bp: depth.min(length),
        }
    } else {
        MapView::Square
    };
    if second.is_some() && !ratio && (rows != cols || request.triangle) {
        return Err(Error::Argument(
            "--compare splits one square map along its diagonal: leave out --region2 and \
             --triangle, or draw the log2 ratio (--ratio)"
                .into(),
        ));
    }
    if request.oe && !same_chrom {
        return Err(Error::Argument(
            "observed / expected (--oe, --compare-mode expected) needs both regions on one \
             chromosome (the expected is per diagonal)"
                .into(),
        ));
    }
    if let Some(second) = second {
        check_comparable(reader, second.reader)?;
    }

    let overlays = Overlays::on_spans(
        &decorations.domains,
        &decorations.boundaries,
        &decorations.loops,
        &decorations.loop_colours,
        &row_span,
        &col_span,
    );
    let tracks = decorations
        .tracks
        .iter()
        .map(|(path, column, rows)| Track::from_rows(path, column, rows, &bins, &cols, &col_span))
        .collect::<Result<Vec<_>>>()?;

    let layout = MapLayout::new(
        request.width_px,
        request.height_px,
        request.dpi,
        view,
        &row_span,
        &col_span,
        tracks.len(),
    );
    let (max_rows, max_cols) = match view {
        MapView::Square => (layout.map_height_px(), layout.map_width_px()),
        MapView::Triangle { .. } => (layout.map_width_px(), layout.map_width_px()),
    };
    let fill = |source: &MapSource<'_>, expected: Option<&ExpectedTable<'_>>| -> Result<CellGrid> {
        let weights = source.weights;
        let normalizer = match request.oe {
            true => Some(oe_normalizer(
                source.reader,
                weights,
                expected,
                request.ignore_diags,
            )?),
            false => None,
        };
        let valid = |bin: usize| weights.is_none_or(|w| w[bin].is_finite());
        let mut grid = CellGrid::new(
            AxisCells::new(rows.clone(), max_rows),
            AxisCells::new(cols.clone(), max_cols),
            &valid,
            if request.oe { request.ignore_diags } else { 0 },
            same_chrom,
        );
        grid.fill(source.reader, weights, normalizer.as_ref())?;
        Ok(grid)
    };
    let grid = fill(first, expected)?;
    let grid = match second {
        None => grid,
        Some(second) => {
            let other_grid = fill(second, None)?;
            let scale_second = if request.oe {
                1.0
            } else {
                total(reader, first.weights)? / total(second.reader, second.weights)?
            };
            let how = match ratio {
                true => GridComparison::Log2Ratio { scale_second },
                false => GridComparison::Split { scale_second },
            };
            CellGrid::compared(&grid, &other_grid, how)?
        }
    };

    let scale = colour_scale(request, &grid.values())?;
    let colour_label = match second {
        Some(second) if ratio => format!("log2({} / {})", first.name, second.name),
        _ if request.oe => "observed / expected".to_string(),
        _ if first.weights.is_none() => "contacts".to_string(),
        _ if request.weight_name == "weight" => "balanced contacts".to_string(),
        _ => format!("contacts balanced by {}", request.weight_name),
    };
    let style = MapStyle {
        colour_map,
        scale,
        nan: request.nan,
        colour_label,
        title: match (&request.title, second) {
            (Some(title), _) => title.clone(),
            (None, Some(second)) if !ratio => {
                format!("{} (upper) vs {} (lower)", first.name, second.name)
            }
            (None, _) => String::new(),
        },
    };
    draw_map(&MapFigure {
        layout: &layout,
        view,
        grid: &grid,
        rows: &row_span,
        cols: &col_span,
        style: &style,
        overlays: &overlays,
        tracks: &tracks,
    })
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

/// The o/e transform of a map: the expected of every chromosome, read or computed.
fn oe_normalizer(
    reader: &dyn MatrixReader,
    weights: Option<&[f64]>,
    expected: Option<&ExpectedTable<'_>>,
    ignore_diags: usize,
) -> Result<Normalizer> {
    let bins = reader.bins();
    let curves = match expected {
        Some(table) => crate::expected::table::curves(table.table, bins, table.column)?,
        None => {
            let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader));
            crate::expected::cis_curves(&pixels, weights, ignore_diags)?
        }
    };
    Normalizer::new(
        Method::Oe,
        bins.n_bins(),
        weights.map(<[f64]>::to_vec),
        curves,
    )
}

/// The colour scale from the request and the drawn values.
fn colour_scale(request: &MapRequest, values: &[f64]) -> Result<ColorScale> {
    let ratio = request.ratio();
    let kind = if request.linear || ratio {
        ScaleKind::Linear
    } else {
        ScaleKind::Log
    };
    let (vmin, vmax) = match (request.vmin, request.vmax) {
        (Some(a), Some(b)) => (a, b),
        (low, high) => {
            let free = low.is_none() && high.is_none();
            let centre = match (ratio, request.oe) {
                (true, _) if free => Some(0.0),
                (false, true) if free => Some(1.0),
                _ => None,
            };
            let [p_low, p_high] = request.percentiles;
            let (a, b) = colour_limits(values, kind, p_low, p_high, centre).ok_or_else(|| {
                Error::region(
                    &request.region,
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
