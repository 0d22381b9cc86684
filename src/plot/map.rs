//! The contact-map figure: a square heatmap of a region (or of two regions, rows and columns)
//! or its 45-degree rotation up to a depth, with a colour bar, genomic axes, overlays (domains,
//! boundaries, loops) and line tracks aligned under the map.
//!
//! Layout in points (scaled by `dpi / 72`): the map fills the width left by the tick labels
//! and the colour bar; its height follows the spans (square for one region; `depth / 2` over
//! the span for the triangle, whose vertical axis is the distance `j - i` between the two
//! bins, but at least 0.15 of the width: a shallow triangle is stretched upwards to stay
//! readable, as HiCExplorer's fixed track heights do); each track is a 50-point panel below. The map's edges are snapped to whole pixels so
//! that raster cells land on pixels.

use std::ops::Range;
use std::path::Path;

use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::io::bed::{BedRecord, BedpeRecord};
use crate::io::tables::TrackRow;
use crate::plot::axes::{
    self, Axes, AxisScale, Side, Theme, colour_bar, genomic_unit, linear_ticks,
};
use crate::plot::colormap::{ColorMap, ColorScale};
use crate::plot::heatmap::CellGrid;
use crate::plot::svg::{Anchor, Baseline, Rgb, Stroke, Svg, TextStyle};

/// A genomic interval shown along an axis.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GenomicSpan {
    /// Chromosome name.
    pub chrom: String,
    /// Start in bp (the first bin's start).
    pub start_bp: u64,
    /// End in bp (the last bin's end).
    pub end_bp: u64,
}

impl GenomicSpan {
    /// The span of the bins `range` of `bins` (one chromosome): the first bin's start to the last
    /// bin's end.
    pub fn of_bins(bins: &BinTable, range: &Range<usize>) -> GenomicSpan {
        let (first, last) = (bins.bin(range.start), bins.bin(range.end - 1));
        GenomicSpan {
            chrom: bins.chroms()[first.chrom_id].name.clone(),
            start_bp: first.start,
            end_bp: last.end,
        }
    }

    /// True when `chrom:start-end` overlaps the span.
    pub fn overlaps(&self, chrom: &str, start: u64, end: u64) -> bool {
        chrom == self.chrom && start < self.end_bp && end > self.start_bp
    }

    fn length(&self) -> f64 {
        (self.end_bp - self.start_bp) as f64
    }

    fn scale(&self) -> AxisScale {
        AxisScale::Linear {
            min: self.start_bp as f64,
            max: self.end_bp as f64,
        }
    }

    /// Ticks in bp labelled in the span's unit, and the axis label (`chr2L (Mb)`).
    fn ticks(&self) -> (Vec<(f64, String)>, String) {
        let (unit, name) = genomic_unit(self.length());
        let values = linear_ticks(self.start_bp as f64 / unit, self.end_bp as f64 / unit, 5);
        let step = if values.len() > 1 {
            values[1] - values[0]
        } else {
            1.0
        };
        let ticks = values
            .iter()
            .map(|&v| (v * unit, axes::format_tick(v, step)))
            .collect();
        (ticks, format!("{} ({name})", self.chrom))
    }
}

/// Square map or 45-degree view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MapView {
    /// Rows down, columns across.
    Square,
    /// The upper triangle rotated so that the diagonal is horizontal, up to `depth_bp`.
    Triangle {
        /// Largest distance `j - i` shown, in bp.
        depth_bp: u64,
    },
}

/// A line track: values over intervals of the column chromosome.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    /// Name shown in the panel.
    pub label: String,
    /// `(start_bp, end_bp, value)`, sorted; NaN breaks the line.
    pub intervals: Vec<(u64, u64, f64)>,
}

impl Track {
    /// The track of column `column` of the table at `path` (a header name, or a 1-based column
    /// number of a bedGraph; its `rows` read by [`read_track`](crate::io::tables::read_track),
    /// the path named in messages) on the bins `cols` of `bins`, whose span is `span`: the file
    /// must hold one row per bin there (same resolution), else an error naming the file and the
    /// counts.
    pub fn from_rows(
        path: &Path,
        column: &str,
        rows: &[TrackRow],
        bins: &BinTable,
        cols: &Range<usize>,
        span: &GenomicSpan,
    ) -> Result<Track> {
        let rows: Vec<&TrackRow> = rows
            .iter()
            .filter(|r| span.overlaps(&r.chrom, r.start, r.end))
            .collect();
        let matches = rows.len() == cols.len()
            && rows.iter().zip(cols.clone()).all(|(row, bin)| {
                let bin = bins.bin(bin);
                row.start == bin.start && row.end == bin.end
            });
        if !matches {
            let resolution = bins
                .resolution()
                .map_or(String::new(), |b| format!(" of {b} bp"));
            return Err(Error::format(
                path,
                format!(
                    "track column '{column}' has {} rows in {}:{}-{}, where the map has {} bins{resolution}: a track must hold one row per bin of the map (same resolution)",
                    rows.len(),
                    span.chrom,
                    span.start_bp,
                    span.end_bp,
                    cols.len()
                ),
            ));
        }
        Ok(Track {
            label: column.to_string(),
            intervals: rows.iter().map(|r| (r.start, r.end, r.value)).collect(),
        })
    }
}

/// Features drawn on the map.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overlays {
    /// Domains `(start_bp, end_bp)`: squares on the diagonal (triangles in the 45-degree view).
    pub domains: Vec<(u64, u64)>,
    /// Boundaries `(start_bp, end_bp)`: marks across the diagonal at their middle.
    pub boundaries: Vec<(u64, u64)>,
    /// Loops: `(start1, end1, start2, end2)` anchors in bp (row anchor, column anchor).
    pub loops: Vec<[u64; 4]>,
    /// Each loop's outline colour (empty: all in the domains' colour).
    pub loop_colours: Vec<Rgb>,
}

impl Overlays {
    /// The features of `domains`, `boundaries` (BED records) and `loops` (BEDPE, each with its
    /// colour in `loop_colours` when that is not empty) that fall on the drawn spans: an
    /// interval on either span; a loop with one anchor on the rows' span and the other on the
    /// columns' (given row anchor first).
    pub fn on_spans(
        domains: &[BedRecord],
        boundaries: &[BedRecord],
        loops: &[BedpeRecord],
        loop_colours: &[Rgb],
        rows: &GenomicSpan,
        cols: &GenomicSpan,
    ) -> Overlays {
        let on = |span: &GenomicSpan, r: &BedRecord| span.overlaps(&r.chrom, r.start, r.end);
        let intervals = |records: &[BedRecord]| {
            records
                .iter()
                .filter(|r| on(rows, r) || on(cols, r))
                .map(|r| (r.start, r.end))
                .collect()
        };
        let mut drawn = Vec::new();
        let mut colours = Vec::new();
        for (k, record) in loops.iter().enumerate() {
            let (a, b) = (&record.first, &record.second);
            let kept = if on(rows, a) && on(cols, b) {
                Some([a.start, a.end, b.start, b.end])
            } else if on(rows, b) && on(cols, a) {
                Some([b.start, b.end, a.start, a.end])
            } else {
                None
            };
            if let Some(anchors) = kept {
                drawn.push(anchors);
                colours.extend(loop_colours.get(k).copied());
            }
        }
        Overlays {
            domains: intervals(domains),
            boundaries: intervals(boundaries),
            loops: drawn,
            loop_colours: colours,
        }
    }
}

/// Colours and labels of the map.
#[derive(Clone, Debug, PartialEq)]
pub struct MapStyle {
    /// Colour map.
    pub colour_map: ColorMap,
    /// Colour scale.
    pub scale: ColorScale,
    /// Colour of NaN cells (masked bins, no valid pair).
    pub nan: Rgb,
    /// Label of the colour bar.
    pub colour_label: String,
    /// Title above the map (empty: none).
    pub title: String,
}

/// Colour of domain and loop outlines.
pub const DOMAIN_COLOUR: Rgb = Rgb(0, 114, 178);
/// Colour of boundary marks.
pub const BOUNDARY_COLOUR: Rgb = Rgb(0, 158, 115);
/// Colour of track lines.
pub const TRACK_COLOUR: Rgb = Rgb(31, 119, 180);

/// Least height of the colour bar (with its NaN swatch), in points.
const BAR_MIN_PT: f64 = 90.0;

/// Where everything goes, in pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct MapLayout {
    /// Figure width.
    pub width_px: usize,
    /// Figure height.
    pub height_px: usize,
    /// Dots per inch.
    pub dpi: f64,
    /// The map's axes (for the triangle: x along the genome, y the distance up).
    pub map: Axes,
    /// The track panels, top to bottom.
    pub tracks: Vec<Axes>,
}

impl MapLayout {
    /// The layout of a figure `width_px` wide (and at most `max_height_px` high, if given: a
    /// square map shrinks to fit it, a triangle grows or shrinks to fill it).
    pub fn new(
        width_px: usize,
        max_height_px: Option<usize>,
        dpi: f64,
        view: MapView,
        rows: &GenomicSpan,
        cols: &GenomicSpan,
        n_tracks: usize,
    ) -> MapLayout {
        let theme = Theme::new(dpi);
        let (left, right, top, bottom) = (
            theme.px(66.0),
            theme.px(84.0),
            theme.px(24.0),
            theme.px(46.0),
        );
        let (track_height, track_gap) = (theme.px(50.0), theme.px(6.0));
        let tracks_height = n_tracks as f64 * (track_height + track_gap);
        let mut map_width = (width_px as f64 - left - right).max(theme.px(40.0)).floor();
        let aspect = match view {
            MapView::Square => (rows.length() / cols.length()).clamp(0.25, 4.0),
            MapView::Triangle { depth_bp } => {
                (depth_bp as f64 / 2.0 / cols.length()).clamp(0.15, 1.0)
            }
        };
        let mut map_height = (map_width * aspect).floor();
        if let Some(max_height) = max_height_px {
            let room = (max_height as f64 - top - bottom - tracks_height).floor();
            if map_height > room && room > theme.px(20.0) {
                map_height = room;
                map_width = (map_height / aspect).floor().min(map_width);
            } else if matches!(view, MapView::Triangle { .. }) && room > map_height {
                // The triangle's height is a choice, not a geometry: --height stretches it.
                map_height = room;
            }
        }
        let map = Axes {
            x: left.round(),
            y: top.round(),
            width: map_width.max(1.0),
            height: map_height.max(1.0),
            x_scale: cols.scale(),
            y_scale: match view {
                MapView::Square => rows.scale(),
                MapView::Triangle { depth_bp } => AxisScale::Linear {
                    min: 0.0,
                    max: depth_bp as f64,
                },
            },
            y_down: view == MapView::Square,
        };
        let mut tracks = Vec::new();
        let mut y = map.y + map.height + track_gap;
        for _ in 0..n_tracks {
            tracks.push(Axes {
                x: map.x,
                y: y.round(),
                width: map.width,
                height: track_height.round(),
                x_scale: cols.scale(),
                y_scale: AxisScale::Linear { min: 0.0, max: 1.0 },
                y_down: false,
            });
            y += track_height + track_gap;
        }
        let content_bottom = tracks.last().map_or(map.y + map.height, |t| t.y + t.height);
        // The colour bar (beside the map, at least 90 points high) may reach lower than a flat
        // triangle and its tracks.
        let bar_bottom = map.y + map.height.max(theme.px(BAR_MIN_PT)) + theme.px(6.0);
        let height_px = (content_bottom + bottom).max(bar_bottom).ceil() as usize;
        MapLayout {
            width_px,
            height_px: max_height_px.map_or(height_px, |h| h.max(height_px)),
            dpi,
            map,
            tracks,
        }
    }

    /// Pixels along the map's width (cells of the raster across).
    pub fn map_width_px(&self) -> usize {
        self.map.width as usize
    }

    /// Pixels along the map's height.
    pub fn map_height_px(&self) -> usize {
        self.map.height as usize
    }
}

/// Everything the map figure shows.
#[derive(Clone, Debug)]
pub struct MapFigure<'a> {
    /// The layout (from [`MapLayout::new`]).
    pub layout: &'a MapLayout,
    /// Square or triangle.
    pub view: MapView,
    /// The cell grid, filled (rows x columns; the same region twice for the triangle).
    pub grid: &'a CellGrid,
    /// The rows' span.
    pub rows: &'a GenomicSpan,
    /// The columns' span.
    pub cols: &'a GenomicSpan,
    /// Colours and labels.
    pub style: &'a MapStyle,
    /// Domains, boundaries and loops.
    pub overlays: &'a Overlays,
    /// Tracks under the map.
    pub tracks: &'a [Track],
}

/// Draw the figure.
///
/// # Examples
///
/// A 100-bin map whose pixels decay as `1 / (1 + |i - j|)`, as PNG and SVG: the image has the
/// layout's size, and each raster cell holds one bin pair (the map is wider than 100 pixels).
///
/// ```
/// use contactmap::plot::heatmap::{AxisCells, CellGrid};
/// use contactmap::plot::map::{draw_map, GenomicSpan, MapFigure, MapLayout, MapStyle, MapView, Overlays};
/// use contactmap::plot::{figure_bytes, ColorMap, ColorScale, ImageFormat, Rgb, ScaleKind};
///
/// let span = GenomicSpan { chrom: "chr1".into(), start_bp: 0, end_bp: 100_000 };
/// let layout = MapLayout::new(500, None, 100.0, MapView::Square, &span, &span, 0);
/// let rows = AxisCells::new(0..100, layout.map_height_px());
/// let cols = AxisCells::new(0..100, layout.map_width_px());
/// let mut grid = CellGrid::new(rows, cols, &|_| true, 0, true);
/// for i in 0..100usize {
///     for j in 0..100usize {
///         grid.add(i, j, 1.0 / (1 + i.abs_diff(j)) as f64);
///     }
/// }
/// assert_eq!((grid.rows.n_cells, grid.cols.n_cells), (100, 100));
/// assert_eq!((grid.value(0, 0), grid.value(0, 99)), (1.0, 0.01));
/// let style = MapStyle {
///     colour_map: ColorMap::by_name("fall")?,
///     scale: ColorScale::new(ScaleKind::Log, 0.01, 1.0)?,
///     nan: Rgb(200, 200, 200),
///     colour_label: "contacts".into(),
///     title: "example".into(),
/// };
/// let figure = MapFigure {
///     layout: &layout,
///     view: MapView::Square,
///     grid: &grid,
///     rows: &span,
///     cols: &span,
///     style: &style,
///     overlays: &Overlays { domains: vec![(0, 50_000)], ..Overlays::default() },
///     tracks: &[],
/// };
/// let svg = draw_map(&figure)?;
/// let png = figure_bytes(&svg, ImageFormat::Png, 100.0)?;
/// let size = |at: usize| u32::from_be_bytes(png[at..at + 4].try_into().unwrap()) as usize;
/// assert_eq!((size(16), size(20)), (layout.width_px, layout.height_px));
/// let text = String::from_utf8(figure_bytes(&svg, ImageFormat::Svg, 100.0)?).unwrap();
/// assert!(text.contains("<svg") && text.contains("example") && text.trim_end().ends_with("</svg>"));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn draw_map(figure: &MapFigure<'_>) -> Result<Svg> {
    let layout = figure.layout;
    let theme = Theme::new(layout.dpi);
    let mut svg = Svg::new(layout.width_px, layout.height_px, layout.dpi);
    let map = layout.map;
    let style = figure.style;
    let image = match figure.view {
        MapView::Square => figure
            .grid
            .image(&style.colour_map, &style.scale, style.nan),
        MapView::Triangle { depth_bp } => {
            let bin_bp = figure.cols.length() / figure.grid.rows.bins.len() as f64;
            figure.grid.triangle_image(
                layout.map_width_px(),
                layout.map_height_px(),
                depth_bp as f64 / bin_bp,
                &style.colour_map,
                &style.scale,
                (style.nan, Rgb::WHITE),
            )
        }
    };
    svg.image(map.x, map.y, map.width, map.height, &image)?;
    map.clip(&mut svg);
    draw_overlays(&mut svg, &theme, &map, figure);
    svg.end_group();
    map.frame(&mut svg, &theme);

    // Axes: the column span along the bottom (of the map or of the last track).
    let (col_ticks, col_label) = figure.cols.ticks();
    let has_tracks = !figure.tracks.is_empty();
    if has_tracks {
        map.ticks(&mut svg, &theme, Side::Bottom, &unlabelled(&col_ticks), &[]);
    } else {
        let depth = map.ticks(&mut svg, &theme, Side::Bottom, &col_ticks, &[]);
        map.label(&mut svg, &theme, Side::Bottom, depth, &col_label);
    }
    match figure.view {
        MapView::Square => {
            let (row_ticks, row_label) = figure.rows.ticks();
            let depth = map.ticks(&mut svg, &theme, Side::Left, &row_ticks, &[]);
            map.label(&mut svg, &theme, Side::Left, depth, &row_label);
        }
        MapView::Triangle { depth_bp } => {
            let (unit, name) = genomic_unit(depth_bp as f64);
            let target = (map.height / theme.px(28.0)).floor().max(2.0) as usize;
            let values = linear_ticks(0.0, depth_bp as f64 / unit, target);
            let step = if values.len() > 1 {
                values[1] - values[0]
            } else {
                1.0
            };
            let ticks: Vec<(f64, String)> = values
                .iter()
                .map(|&v| (v * unit, axes::format_tick(v, step)))
                .collect();
            let depth = map.ticks(&mut svg, &theme, Side::Left, &ticks, &[]);
            // A flat triangle gets the short name of the distance (s, as in P(s)).
            let long = format!("distance ({name})");
            let label = if axes::text_width_fits(&long, theme.label_font(), map.height) {
                long
            } else {
                format!("s ({name})")
            };
            map.label(&mut svg, &theme, Side::Left, depth, &label);
        }
    }
    if !style.title.is_empty() {
        svg.text(
            map.x + map.width / 2.0,
            map.y - theme.px(6.0),
            &style.title,
            &TextStyle::new(theme.label_font(), Anchor::Middle, Baseline::Bottom),
        );
    }

    // Colour bar beside the map, and the NaN swatch under it.
    let bar_height = map.height.max(theme.px(BAR_MIN_PT)).min(theme.px(260.0));
    let bar = (
        map.x + map.width + theme.px(10.0),
        map.y,
        theme.px(10.0),
        (bar_height - theme.px(16.0)).round(),
    );
    colour_bar(
        &mut svg,
        &theme,
        bar,
        &style.colour_map,
        &style.scale,
        &style.colour_label,
    )?;
    let swatch_y = bar.1 + bar.3 + theme.px(5.0);
    svg.rect(
        bar.0,
        swatch_y,
        bar.2,
        theme.px(8.0),
        Some(style.nan),
        Some(theme.frame_stroke()),
    );
    svg.text(
        bar.0 + bar.2 + theme.px(5.5),
        swatch_y + theme.px(4.0),
        "NaN",
        &TextStyle::new(theme.font(), Anchor::Start, Baseline::Middle),
    );

    for (i, (track, panel)) in figure.tracks.iter().zip(&layout.tracks).enumerate() {
        let last = i + 1 == figure.tracks.len();
        draw_track(&mut svg, &theme, panel, track, last.then_some(&col_ticks));
        if last {
            let depth = theme.px(3.5) + theme.px(2.0) + theme.font() * 1.1;
            panel.label(&mut svg, &theme, Side::Bottom, depth, &col_label);
        }
    }
    Ok(svg)
}

/// The same ticks with empty labels.
fn unlabelled(ticks: &[(f64, String)]) -> Vec<(f64, String)> {
    ticks.iter().map(|(v, _)| (*v, String::new())).collect()
}

/// Sizes of the overlay marks, scaled to the bins on screen so that they never hide the map: a
/// region of a few hundred bins gets the full sizes; a whole chromosome at 10 kb (bins of a
/// tenth of a pixel, boundaries a few pixels apart) thin outlines and short marks that stop
/// short of the diagonal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarkSizes {
    /// Width of domain and loop outlines, px.
    pub outline: f64,
    /// Width of boundary marks, px.
    pub mark: f64,
    /// Half-length of a boundary mark across the diagonal (triangle: its height), px.
    pub half: f64,
    /// The part of a mark left out on each side of the diagonal (square view), px.
    pub gap: f64,
}

impl MarkSizes {
    /// The sizes for bins of `bin_px` pixels and boundaries `spacing_px` apart (median; `None`
    /// with fewer than two), at `theme`'s resolution.
    pub fn new(theme: &Theme, bin_px: f64, spacing_px: Option<f64>) -> MarkSizes {
        // Outlines thin down to a third of their width as bins shrink below 4 points.
        let fine = (bin_px / theme.px(4.0)).clamp(0.35, 1.0);
        let outline = theme.px(1.2) * fine;
        if bin_px >= theme.px(4.0) {
            // Bins large on screen: a full mark across the diagonal cell.
            return MarkSizes {
                outline,
                mark: theme.px(1.5),
                half: theme.px(5.0),
                gap: 0.0,
            };
        }
        // Small bins: the marks stop short of the diagonal (its few pixels stay in view), keep
        // a visible length beside it, and are no wider than a third of the space between them.
        let mark = spacing_px
            .map_or(theme.px(1.5), |s| 0.3 * s)
            .clamp(theme.px(0.5), theme.px(1.5));
        let gap = theme.px(2.0) + bin_px;
        MarkSizes {
            outline,
            mark,
            half: gap + theme.px(4.0),
            gap,
        }
    }
}

/// The median distance between consecutive boundary middles, in pixels along the columns.
fn boundary_spacing(map: &Axes, boundaries: &[(u64, u64)]) -> Option<f64> {
    let mut xs: Vec<f64> = boundaries
        .iter()
        .map(|&(start, end)| map.px(((start + end) / 2) as f64))
        .collect();
    xs.sort_by(f64::total_cmp);
    let mut gaps: Vec<f64> = xs
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|&g| g > 0.0)
        .collect();
    if gaps.is_empty() {
        return None;
    }
    gaps.sort_by(f64::total_cmp);
    Some(gaps[gaps.len() / 2])
}

fn draw_overlays(svg: &mut Svg, theme: &Theme, map: &Axes, figure: &MapFigure<'_>) {
    let overlays = figure.overlays;
    let bin_px = map.width / figure.grid.cols.bins.len().max(1) as f64;
    let sizes = MarkSizes::new(theme, bin_px, boundary_spacing(map, &overlays.boundaries));
    let domain = Stroke::solid(DOMAIN_COLOUR, sizes.outline);
    let boundary = Stroke::solid(BOUNDARY_COLOUR, sizes.mark);
    // Loops are points on the map, a few bins wide: however small their bins on screen, each is
    // marked by an outline of full width and a visible size (issue 51: 10 kb loops in a 7 Mb
    // view were hairlines).
    let loop_stroke = |k: usize| {
        let colour = overlays
            .loop_colours
            .get(k)
            .copied()
            .unwrap_or(DOMAIN_COLOUR);
        Stroke::solid(colour, sizes.outline.max(theme.px(1.5)))
    };
    let same_chrom = figure.rows == figure.cols
        || (figure.rows.chrom == figure.cols.chrom && figure.view == MapView::Square);
    let px = |bp: u64| map.px(bp as f64);
    match figure.view {
        MapView::Square => {
            let py = |bp: u64| map.py(bp as f64);
            if same_chrom {
                for &(start, end) in &overlays.domains {
                    svg.rect(
                        px(start),
                        py(start),
                        px(end) - px(start),
                        py(end) - py(start),
                        None,
                        Some(domain),
                    );
                }
                // Two strokes across the diagonal, leaving the diagonal itself in view.
                let (half, gap) = (sizes.half, sizes.gap);
                for &(start, end) in &overlays.boundaries {
                    let middle = (start + end) / 2;
                    let (x, y) = (px(middle), py(middle));
                    if gap > 0.0 {
                        svg.line(x - half, y + half, x - gap, y + gap, boundary);
                        svg.line(x + gap, y - gap, x + half, y - half, boundary);
                    } else {
                        svg.line(x - half, y + half, x + half, y - half, boundary);
                    }
                }
            }
            let least = theme.px(if bin_px >= theme.px(4.0) { 6.0 } else { 9.0 });
            for (k, &[s1, e1, s2, e2]) in overlays.loops.iter().enumerate() {
                let looped = loop_stroke(k);
                let mut square = |rows: (u64, u64), cols: (u64, u64)| {
                    let (x0, x1) = (px(cols.0), px(cols.1));
                    let (y0, y1) = (map.py(rows.0 as f64), map.py(rows.1 as f64));
                    let (w, h) = ((x1 - x0).max(least), (y1 - y0).max(least));
                    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
                    svg.rect(cx - w / 2.0, cy - h / 2.0, w, h, None, Some(looped));
                };
                square((s1, e1), (s2, e2));
                if same_chrom {
                    square((s2, e2), (s1, e1));
                }
            }
        }
        MapView::Triangle { .. } => {
            let base = map.y + map.height;
            let up = |distance: f64| map.py(distance);
            for &(start, end) in &overlays.domains {
                let apex = ((start + end) / 2, (end - start) as f64);
                svg.polyline(
                    &[
                        (px(start), base),
                        (map.px(apex.0 as f64), up(apex.1)),
                        (px(end), base),
                    ],
                    domain,
                );
            }
            // Ticks up from the diagonal (from above it when bins are small, so that the
            // diagonal stays in view).
            let height = (sizes.half - sizes.gap).clamp(theme.px(4.0), theme.px(8.0));
            for &(start, end) in &overlays.boundaries {
                let x = px((start + end) / 2);
                svg.line(x, base - sizes.gap, x, base - sizes.gap - height, boundary);
            }
            for (k, &[s1, e1, s2, e2]) in overlays.loops.iter().enumerate() {
                let looped = loop_stroke(k);
                let (m1, m2) = ((s1 + e1) as f64 / 2.0, (s2 + e2) as f64 / 2.0);
                let (x, y) = (map.px((m1 + m2) / 2.0), up((m2 - m1).abs()));
                let r = theme.px(if bin_px >= theme.px(4.0) { 4.0 } else { 5.0 });
                svg.polygon(
                    &[(x, y - r), (x + r, y), (x, y + r), (x - r, y)],
                    None,
                    Some(looped),
                );
            }
        }
    }
}

fn draw_track(
    svg: &mut Svg,
    theme: &Theme,
    panel: &Axes,
    track: &Track,
    x_ticks: Option<&Vec<(f64, String)>>,
) {
    let finite = track
        .intervals
        .iter()
        .map(|t| t.2)
        .filter(|v| v.is_finite());
    let (low, high) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    let (low, high) = if low.is_finite() {
        let pad = ((high - low) * 0.08).max(1e-9 * high.abs().max(1.0));
        (low - pad, high + pad)
    } else {
        (0.0, 1.0)
    };
    let panel = Axes {
        y_scale: AxisScale::Linear {
            min: low,
            max: high,
        },
        ..*panel
    };
    panel.clip(svg);
    if low < 0.0 && high > 0.0 {
        svg.line(
            panel.x,
            panel.py(0.0),
            panel.x + panel.width,
            panel.py(0.0),
            Stroke::solid(Rgb(150, 150, 150), theme.px(0.6)).dashed(theme.px(2.0)),
        );
    }
    let points: Vec<(f64, f64)> = track
        .intervals
        .iter()
        .map(|&(start, end, value)| {
            let middle = (start + end) as f64 / 2.0;
            (panel.px(middle), panel.py(value))
        })
        .collect();
    svg.polyline(&points, Stroke::solid(TRACK_COLOUR, theme.px(1.0)));
    svg.end_group();
    panel.frame(svg, theme);
    let (y_ticks, _) = panel.y_scale.ticks(3);
    panel.ticks(svg, theme, Side::Left, &y_ticks, &[]);
    match x_ticks {
        Some(ticks) => panel.ticks(svg, theme, Side::Bottom, ticks, &[]),
        None => panel.ticks(svg, theme, Side::Bottom, &[], &[]),
    };
    svg.text(
        panel.x + theme.px(4.0),
        panel.y + theme.px(3.0),
        &track.label,
        &TextStyle::new(theme.font(), Anchor::Start, Baseline::Top),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span(end_bp: u64) -> GenomicSpan {
        GenomicSpan {
            chrom: "c".into(),
            start_bp: 0,
            end_bp,
        }
    }

    #[test]
    fn a_given_height_stretches_a_triangle_and_bounds_a_square() {
        let view = MapView::Triangle {
            depth_bp: 3_000_000,
        };
        let (rows, cols) = (span(23_000_000), span(23_000_000));
        let natural = MapLayout::new(750, None, 100.0, view, &rows, &cols, 1);
        let tall = MapLayout::new(750, Some(400), 100.0, view, &rows, &cols, 1);
        assert_eq!(tall.height_px, 400);
        assert!(tall.map.height > natural.map.height + 100.0);
        assert_eq!(tall.map.width, natural.map.width);
        let track = &tall.tracks[0];
        // Everything fits: the track's bottom and the axis labels under it.
        assert!(track.y + track.height < 400.0 - 40.0);
        let square = MapLayout::new(750, Some(400), 100.0, MapView::Square, &rows, &cols, 0);
        assert_eq!(square.map.width, square.map.height);
        assert!(square.map.y + square.map.height <= 400.0);
    }
}
