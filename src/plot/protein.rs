//! The protein contact-map figure, as ConKit's `conkit-plot cmap` with a reference structure
//! (Simkovic et al., Bioinformatics 2017), and the precision-vs-list-size curve beside it.
//!
//! **Map** (left panel): a square residue x residue map; both axes are residue numbers, the
//! row (`i`) growing downwards and the column (`j`) to the right, as a matrix and as
//! `plot map`; the cell of residue `r` spans `r - 0.5 .. r + 0.5`. The true contacts of the
//! structure are light grey squares in both triangles. The top-`k` predicted pairs of the first
//! prediction are circles of radius 0.48 cell in the upper triangle (`i < j`: row `i`, column
//! `j`), dark navy for a true positive and pink-red for a false positive (ConKit's
//! `ColorDefinitions`: MATCH `#0F0B2C`, MISMATCH `#DC4869`, STRUCTURAL `#D8D6D6`); a pair with a
//! residue not observed in the structure (listed only when the caller keeps them) is an open
//! grey circle. A second prediction is drawn the same way mirrored in the lower triangle (row
//! `j`, column `i`), as ConKit's `--otherfile`. Below the panels, a legend gives the counts:
//! true contacts, and for each prediction TP, FP (and unobserved) and the precision
//! `TP / listed pairs`.
//!
//! **Curve** (right panel): precision against the list size, `k / L` on the x axis from 0 to the
//! curve's largest size, one line per prediction through `(k / L, TP_k / k)` for every `k` from
//! 1, where `TP_k` is [`crate::score::contacts::ContactScore::curve`] (the numbers of
//! `score contacts --curve`); a dashed line marks the map's list size.
//!
//! What is drawn is computed by the caller ([`PredictionLayer`]); this module does the layout
//! ([`ContactLayout`]) and the drawing ([`draw_contacts`]). Sizes are in points, scaled by
//! `dpi / 72` ([`Theme`]); the panels' edges are snapped to whole pixels.

use crate::error::Result;
use crate::plot::axes::{self, Axes, AxisScale, LegendEntry, Side, Theme, linear_ticks};
use crate::plot::svg::{Anchor, Baseline, Rgb, Stroke, Svg, TextStyle, text_width};
use crate::score::contacts::{
    Prediction, ScoreParams, TrueContacts, list_length, ranked_predictions, score_contacts,
};

/// Colour of a true positive (ConKit's `ColorDefinitions.MATCH`).
pub const TRUE_POSITIVE: Rgb = Rgb(0x0f, 0x0b, 0x2c);
/// Colour of a false positive (ConKit's `ColorDefinitions.MISMATCH`).
pub const FALSE_POSITIVE: Rgb = Rgb(0xdc, 0x48, 0x69);
/// Colour of a true contact of the structure (ConKit's `ColorDefinitions.STRUCTURAL`).
pub const STRUCTURAL: Rgb = Rgb(0xd8, 0xd6, 0xd6);
/// Outline colour of a pair with an unobserved residue.
pub const UNOBSERVED: Rgb = Rgb(0x80, 0x80, 0x80);
/// Radius of a prediction marker, in cells (ConKit's 0.48).
pub const MARKER_RADIUS: f64 = 0.48;

/// What the structure says of a predicted pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    /// A true contact.
    TruePositive,
    /// Both residues observed, not in contact.
    FalsePositive,
    /// A residue is not observed in the structure.
    Unobserved,
}

impl Mark {
    /// The `class` of the SVG group holding these markers.
    pub fn class(self) -> &'static str {
        match self {
            Mark::TruePositive => "tp",
            Mark::FalsePositive => "fp",
            Mark::Unobserved => "unobserved",
        }
    }
}

/// One prediction as the figure shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct PredictionLayer {
    /// Its name in the legend (the file name).
    pub name: String,
    /// The list size as written (`L`, `L/5`, `30`).
    pub list_label: String,
    /// `k`, the requested list size.
    pub k: usize,
    /// The listed pairs `(i, j, mark)`, `i < j`, in rank order (at most `k`).
    pub pairs: Vec<(i32, i32, Mark)>,
    /// `L`, for the curve's `k / L`.
    pub length: usize,
    /// `curve[k - 1]`: true positives among the top `k` pairs.
    pub curve: Vec<usize>,
    /// The curve's requested largest `k` (the x axis reaches it even when fewer pairs exist).
    pub curve_max_k: usize,
}

impl PredictionLayer {
    /// The layer of `prediction` (named `name`) scored against `truth` with `params` (one list
    /// size, `list_label` as written, and the curve up to `params.curve`): its top `k` pairs in
    /// rank order, each marked a true positive, a false positive or unobserved; and the residues
    /// it spans (the sequence or matrix `1..=L` when the prediction has one, the observed
    /// residues, the drawn pairs).
    pub fn score(
        name: String,
        list_label: String,
        truth: &TrueContacts,
        prediction: &Prediction,
        params: &ScoreParams,
    ) -> Result<(PredictionLayer, (i32, i32))> {
        let list_size = params.list_sizes.first().copied().ok_or_else(|| {
            crate::error::Error::parameter("list_sizes", "[]", "expected one list size")
        })?;
        let curve_size = params.curve.unwrap_or(list_size);
        let score = score_contacts(truth, prediction, params)?;
        let k = list_length(list_size, score.length, params.rounding, score.n_true);
        let pairs: Vec<(i32, i32, Mark)> =
            ranked_predictions(truth, prediction, params.range, params.drop_unobserved)
                .into_iter()
                .take(k)
                .map(|pair| {
                    let mark = match (pair.distance_angstrom, pair.is_contact) {
                        (None, _) => Mark::Unobserved,
                        (Some(_), true) => Mark::TruePositive,
                        (Some(_), false) => Mark::FalsePositive,
                    };
                    (pair.i, pair.j, mark)
                })
                .collect();
        let (mut first, mut last) = (i32::MAX, i32::MIN);
        if prediction.sequence.is_some() || prediction.length.is_some() {
            first = 1;
            last = i32::try_from(score.length).unwrap_or(i32::MAX);
        }
        let numbers = truth.numbers();
        if let (Some(&low), Some(&high)) = (numbers.first(), numbers.last()) {
            first = first.min(low);
            last = last.max(high);
        }
        for &(i, j, _) in &pairs {
            first = first.min(i);
            last = last.max(j);
        }
        let layer = PredictionLayer {
            name,
            list_label,
            k,
            pairs,
            length: score.length,
            curve_max_k: list_length(curve_size, score.length, params.rounding, score.n_true),
            curve: score.curve,
        };
        Ok((layer, (first, last)))
    }

    /// Listed pairs with this mark.
    pub fn count(&self, mark: Mark) -> usize {
        self.pairs.iter().filter(|pair| pair.2 == mark).count()
    }

    /// `TP / listed pairs` (0 without pairs), the precision `score contacts` reports.
    pub fn precision(&self) -> f64 {
        if self.pairs.is_empty() {
            0.0
        } else {
            self.count(Mark::TruePositive) as f64 / self.pairs.len() as f64
        }
    }

    /// The curve's points `(k / L, TP_k / k)` for `k` = 1, 2, ...
    pub fn curve_points(&self) -> Vec<(f64, f64)> {
        let length = self.length.max(1) as f64;
        self.curve
            .iter()
            .enumerate()
            .map(|(index, &tp)| {
                let k = (index + 1) as f64;
                (k / length, tp as f64 / k)
            })
            .collect()
    }
}

/// Everything the figure shows.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactFigure {
    /// First and last residue number of the axes.
    pub residues: (i32, i32),
    /// True contacts `(i, j)`, `i < j`, drawn in both triangles.
    pub true_contacts: Vec<(i32, i32)>,
    /// Smallest separation of the true contacts and of the listed pairs.
    pub min_separation: u32,
    /// One or two predictions: the first in the upper triangle, the second in the lower.
    pub predictions: Vec<PredictionLayer>,
    /// Title above the map (empty: none).
    pub title: String,
}

impl ContactFigure {
    /// Right end of the curve's x axis: the largest `curve_max_k / L` (1 when there is none).
    pub fn curve_max_fraction(&self) -> f64 {
        let max = self
            .predictions
            .iter()
            .map(|p| p.curve_max_k as f64 / p.length.max(1) as f64)
            .fold(0.0, f64::max);
        if max > 0.0 { max } else { 1.0 }
    }

    /// Rows of the legend under the panels: the true contacts, then one per prediction.
    pub fn n_legend_rows(&self) -> usize {
        1 + self.predictions.len()
    }
}

/// Where everything goes, in pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactLayout {
    /// Figure width.
    pub width_px: usize,
    /// Figure height.
    pub height_px: usize,
    /// Dots per inch.
    pub dpi: f64,
    /// The map's axes (square; y grows downwards).
    pub map: Axes,
    /// The curve's axes (same top and height as the map).
    pub curve: Axes,
    /// Top of the first legend row.
    pub legend_top: f64,
    /// Height of a legend row.
    pub legend_row: f64,
}

/// Margins and gaps of the layout, in points: left of the map (tick labels and axis label),
/// between the map and the curve (the curve's tick labels and label), right, top (plus a title
/// line when there is one), under the panels (tick labels and axis labels).
const LEFT_PT: f64 = 52.0;
const GAP_PT: f64 = 62.0;
const RIGHT_PT: f64 = 14.0;
const TOP_PT: f64 = 12.0;
const TITLE_PT: f64 = 18.0;
const BOTTOM_PT: f64 = 42.0;
/// Top of the precision axis: a little above 1 so that a curve at precision 1 is not hidden
/// by the frame.
pub const PRECISION_AXIS_MAX: f64 = 1.05;
/// The curve panel's width relative to the map's side.
const CURVE_RATIO: f64 = 0.75;

impl ContactLayout {
    /// The layout of a figure `width_px` wide (and at most `max_height_px` high, if given: the
    /// map shrinks to fit, but never below 40 points).
    pub fn new(
        width_px: usize,
        max_height_px: Option<usize>,
        dpi: f64,
        figure: &ContactFigure,
    ) -> ContactLayout {
        let theme = Theme::new(dpi);
        let top = theme.px(TOP_PT
            + if figure.title.is_empty() {
                0.0
            } else {
                TITLE_PT
            });
        let (left, gap, right, bottom) = (
            theme.px(LEFT_PT),
            theme.px(GAP_PT),
            theme.px(RIGHT_PT),
            theme.px(BOTTOM_PT),
        );
        let legend_row = (theme.font() * 1.6).round();
        let legend_height = legend_row * figure.n_legend_rows() as f64 + theme.px(6.0);
        let room = (width_px as f64 - left - gap - right).max(theme.px(80.0));
        let mut side = (room / (1.0 + CURVE_RATIO)).floor();
        if let Some(max_height) = max_height_px {
            let fits = (max_height as f64 - top - bottom - legend_height).floor();
            if side > fits {
                side = fits.max(theme.px(40.0).floor());
            }
        }
        let curve_width = (room - side).floor().max(theme.px(40.0).floor());
        let (first, last) = figure.residues;
        let residue_scale = AxisScale::Linear {
            min: f64::from(first) - 0.5,
            max: f64::from(last) + 0.5,
        };
        let map = Axes {
            x: left.round(),
            y: top.round(),
            width: side,
            height: side,
            x_scale: residue_scale,
            y_scale: residue_scale,
            y_down: true,
        };
        let curve = Axes {
            x: (map.x + side + gap).round(),
            y: map.y,
            width: curve_width,
            height: side,
            x_scale: AxisScale::Linear {
                min: 0.0,
                max: figure.curve_max_fraction(),
            },
            y_scale: AxisScale::Linear {
                min: 0.0,
                max: PRECISION_AXIS_MAX,
            },
            y_down: false,
        };
        let legend_top = (map.y + side + bottom).round();
        let height_px = (legend_top + legend_height).ceil() as usize;
        ContactLayout {
            width_px,
            height_px: max_height_px.map_or(height_px, |h| h.max(height_px)),
            dpi,
            map,
            curve,
            legend_top,
            legend_row,
        }
    }

    /// The cell of the pair at row `row`, column `col`: `(x, y, width, height)` in pixels, its
    /// edges rounded to whole pixels so that neighbouring cells meet without an anti-aliased
    /// seam (a cell is then one pixel wider or narrower than the exact `side / residues`).
    pub fn cell(&self, row: i32, col: i32) -> (f64, f64, f64, f64) {
        let map = &self.map;
        let x0 = map.px(f64::from(col) - 0.5).round();
        let x1 = map.px(f64::from(col) + 0.5).round();
        let y0 = map.py(f64::from(row) - 0.5).round();
        let y1 = map.py(f64::from(row) + 0.5).round();
        (x0, y0, x1 - x0, y1 - y0)
    }

    /// The pixel centre of the cell at row `row`, column `col`.
    pub fn cell_centre(&self, row: i32, col: i32) -> (f64, f64) {
        (self.map.px(f64::from(col)), self.map.py(f64::from(row)))
    }

    /// The pixel point of `(k / L, precision)` on the curve panel.
    pub fn curve_point(&self, fraction: f64, precision: f64) -> (f64, f64) {
        (self.curve.px(fraction), self.curve.py(precision))
    }
}

/// Residue ticks: round numbers inside `first..=last`, about one per 40 points.
pub fn residue_ticks(first: i32, last: i32, side_px: f64, theme: &Theme) -> Vec<(f64, String)> {
    let target = (side_px / theme.px(40.0)).floor().clamp(2.0, 10.0) as usize;
    linear_ticks(f64::from(first), f64::from(last), target)
        .into_iter()
        .filter(|value| value.fract() == 0.0)
        .map(|value| (value, format!("{value:.0}")))
        .collect()
}

/// Draw the figure.
///
/// # Examples
///
/// Three predicted pairs, two of them true contacts: two dark circles, one red.
///
/// ```
/// use contactmap::plot::protein::{draw_contacts, ContactFigure, ContactLayout, Mark, PredictionLayer};
///
/// let prediction = PredictionLayer {
///     name: "pred.rr".into(),
///     list_label: "L/10".into(),
///     k: 3,
///     pairs: vec![(1, 30, Mark::TruePositive), (5, 40, Mark::FalsePositive), (8, 33, Mark::TruePositive)],
///     length: 40,
///     curve: vec![1, 1, 2],
///     curve_max_k: 40,
/// };
/// assert_eq!((prediction.precision(), prediction.curve_points()[2]), (2.0 / 3.0, (3.0 / 40.0, 2.0 / 3.0)));
/// let figure = ContactFigure {
///     residues: (1, 40),
///     true_contacts: vec![(1, 30), (8, 33), (10, 35)],
///     min_separation: 24,
///     predictions: vec![prediction],
///     title: "example".into(),
/// };
/// let layout = ContactLayout::new(600, None, 100.0, &figure);
/// let text = draw_contacts(&figure, &layout)?.finish();
/// let circles_in = |class: &str| {
///     let start = text.find(&format!(r#"<g class="{class}">"#)).expect("the group");
///     let group = &text[start..];
///     group[..group.find("</g>").unwrap()].matches("<circle").count()
/// };
/// assert_eq!((circles_in("tp"), circles_in("fp")), (2, 1));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn draw_contacts(figure: &ContactFigure, layout: &ContactLayout) -> Result<Svg> {
    let theme = Theme::new(layout.dpi);
    let mut svg = Svg::new(layout.width_px, layout.height_px, layout.dpi);
    let map = layout.map;
    let cell_px = map.width / (f64::from(figure.residues.1 - figure.residues.0) + 1.0);

    map.clip(&mut svg);
    svg.begin_class("true-contacts");
    for &(i, j) in &figure.true_contacts {
        for (row, col) in [(i, j), (j, i)] {
            let (x, y, w, h) = layout.cell(row, col);
            svg.rect(x, y, w, h, Some(STRUCTURAL), None);
        }
    }
    svg.end_group();
    for (index, layer) in figure.predictions.iter().enumerate().take(2) {
        let upper = index == 0;
        svg.begin_class(if upper { "upper" } else { "lower" });
        for mark in [Mark::Unobserved, Mark::FalsePositive, Mark::TruePositive] {
            svg.begin_class(mark.class());
            for &(i, j, _) in layer.pairs.iter().filter(|pair| pair.2 == mark) {
                let (row, col) = if upper { (i, j) } else { (j, i) };
                let (x, y) = layout.cell_centre(row, col);
                let radius = MARKER_RADIUS * cell_px;
                match mark {
                    Mark::TruePositive => svg.circle(x, y, radius, TRUE_POSITIVE),
                    Mark::FalsePositive => svg.circle(x, y, radius, FALSE_POSITIVE),
                    Mark::Unobserved => svg.circle_outline(
                        x,
                        y,
                        radius * 0.85,
                        Stroke::solid(UNOBSERVED, (0.15 * cell_px).clamp(0.5, theme.px(1.0))),
                    ),
                }
            }
            svg.end_group();
        }
        svg.end_group();
    }
    svg.end_group();
    map.frame(&mut svg, &theme);
    let (first, last) = figure.residues;
    let ticks = residue_ticks(first, last, map.width, &theme);
    let depth = map.ticks(&mut svg, &theme, Side::Bottom, &ticks, &[]);
    map.label(&mut svg, &theme, Side::Bottom, depth, "residue j");
    let depth = map.ticks(&mut svg, &theme, Side::Left, &ticks, &[]);
    map.label(&mut svg, &theme, Side::Left, depth, "residue i");
    if !figure.title.is_empty() {
        svg.text(
            map.x + map.width / 2.0,
            map.y - theme.px(8.0),
            &figure.title,
            &TextStyle::new(theme.label_font(), Anchor::Middle, Baseline::Bottom),
        );
    }

    draw_curve(&mut svg, &theme, figure, layout);
    draw_legend(&mut svg, &theme, figure, layout);
    Ok(svg)
}

/// The curve colours: the first prediction's curve in the true-positive navy, the second in
/// the false-positive red would read as TP / FP, so the curves take matplotlib's tab10.
fn curve_colour(index: usize) -> Rgb {
    axes::CURVE_COLOURS[index % axes::CURVE_COLOURS.len()]
}

fn draw_curve(svg: &mut Svg, theme: &Theme, figure: &ContactFigure, layout: &ContactLayout) {
    let curve = layout.curve;
    svg.begin_class("precision-curve");
    // Light grid at the precision ticks.
    let grid = Stroke::solid(Rgb(230, 230, 230), theme.px(0.6));
    let y_ticks: Vec<(f64, String)> = [0.0, 0.2, 0.4, 0.6, 0.8, 1.0]
        .iter()
        .map(|&v| (v, axes::format_tick(v, 0.2)))
        .collect();
    for (value, _) in &y_ticks {
        let y = curve.py(*value);
        svg.line(curve.x, y, curve.x + curve.width, y, grid);
    }
    curve.clip(svg);
    for (index, layer) in figure.predictions.iter().enumerate() {
        // The map's list size.
        let length = layer.length.max(1) as f64;
        let x = curve.px(layer.k as f64 / length);
        svg.line(
            x,
            curve.y,
            x,
            curve.y + curve.height,
            Stroke::solid(curve_colour(index), theme.px(0.8)).dashed(theme.px(3.0)),
        );
    }
    for (index, layer) in figure.predictions.iter().enumerate() {
        let points: Vec<(f64, f64)> = layer
            .curve_points()
            .into_iter()
            .map(|(fraction, precision)| layout.curve_point(fraction, precision))
            .collect();
        svg.begin_class(&format!("curve-{}", index + 1));
        svg.polyline(&points, Stroke::solid(curve_colour(index), theme.px(1.4)));
        svg.end_group();
    }
    svg.end_group();
    curve.frame(svg, theme);
    let max = figure.curve_max_fraction();
    let target = (curve.width / theme.px(45.0)).floor().clamp(2.0, 8.0) as usize;
    let values = linear_ticks(0.0, max, target);
    let step = if values.len() > 1 {
        values[1] - values[0]
    } else {
        max
    };
    let x_ticks: Vec<(f64, String)> = values
        .iter()
        .map(|&v| (v, axes::format_tick(v, step)))
        .collect();
    let depth = curve.ticks(svg, theme, Side::Bottom, &x_ticks, &[]);
    curve.label(svg, theme, Side::Bottom, depth, "list size k / L");
    let depth = curve.ticks(svg, theme, Side::Left, &y_ticks, &[]);
    curve.label(svg, theme, Side::Left, depth, "precision");
    let entries: Vec<LegendEntry> = figure
        .predictions
        .iter()
        .enumerate()
        .map(|(index, layer)| LegendEntry {
            stroke: Stroke::solid(curve_colour(index), theme.px(1.4)),
            filled: false,
            label: layer.name.clone(),
        })
        .collect();
    svg.end_group();
    let lines: Vec<Vec<(f64, f64)>> = figure
        .predictions
        .iter()
        .map(|layer| {
            layer
                .curve_points()
                .into_iter()
                .map(|(fraction, precision)| layout.curve_point(fraction, precision))
                .collect()
        })
        .collect();
    let (right, top) = legend_corner(theme, &curve, &entries, &lines);
    axes::legend(svg, theme, right, top, &entries);
}

/// Where the curve legend goes: `(right, top)` of the corner of the panel (top right, bottom
/// left, bottom right, top left, in this order of preference) whose legend box covers the
/// least of the polylines `lines` (each segment sampled every 2 pixels, so that a steep
/// segment crossing the box counts). The box's size is the one [`axes::legend`] draws.
pub fn legend_corner(
    theme: &Theme,
    curve: &Axes,
    entries: &[LegendEntry],
    lines: &[Vec<(f64, f64)>],
) -> (f64, f64) {
    let mut points = Vec::new();
    for line in lines {
        points.extend(line.first().copied());
        for pair in line.windows(2) {
            let ((x0, y0), (x1, y1)) = (pair[0], pair[1]);
            let n = ((x1 - x0).hypot(y1 - y0) / 2.0).ceil().clamp(1.0, 1000.0) as u32;
            for step in 1..=n {
                let t = f64::from(step) / f64::from(n);
                points.push((x0 + t * (x1 - x0), y0 + t * (y1 - y0)));
            }
        }
    }
    let font = theme.font();
    let (pad, row, line) = (theme.px(4.0), font * 1.45, theme.px(18.0));
    let widest = entries
        .iter()
        .map(|e| text_width(&e.label, font))
        .fold(0.0, f64::max);
    let (width, height) = (
        pad * 3.0 + line + widest,
        pad * 2.0 + row * entries.len() as f64,
    );
    let inset = theme.px(4.0);
    let (left_edge, right_edge) = (curve.x + inset + width, curve.x + curve.width - inset);
    let (top_edge, bottom_edge) = (curve.y + inset, curve.y + curve.height - inset - height);
    let corners = [
        (right_edge, top_edge),
        (left_edge, bottom_edge),
        (right_edge, bottom_edge),
        (left_edge, top_edge),
    ];
    let covered = |&(right, top): &(f64, f64)| {
        points
            .iter()
            .filter(|&&(x, y)| x >= right - width && x <= right && y >= top && y <= top + height)
            .count()
    };
    let mut best = corners[0];
    let mut fewest = covered(&best);
    for corner in &corners[1..] {
        let n = covered(corner);
        if n < fewest {
            best = *corner;
            fewest = n;
        }
    }
    best
}

/// One legend item: an optional swatch and its text.
type LegendItem = (Option<Swatch>, String);

/// One legend row: swatches and texts left to right from `x`, centred on `y`; item `n` takes at
/// least `columns[n]` pixels of text width, so that rows with the same items line up.
fn legend_row(
    svg: &mut Svg,
    theme: &Theme,
    (x, y): (f64, f64),
    items: &[LegendItem],
    columns: &[f64],
) {
    let font = theme.font();
    let style = TextStyle::new(font, Anchor::Start, Baseline::Middle);
    let size = font * 0.9;
    let mut cursor = x;
    for (index, (swatch, text)) in items.iter().enumerate() {
        if let Some(swatch) = swatch {
            let (cx, r) = (cursor + size / 2.0, size / 2.0);
            match swatch {
                Swatch::Square(colour) => {
                    svg.rect(cursor, y - r, size, size, Some(*colour), None);
                }
                Swatch::Disc(colour) => svg.circle(cx, y, r, *colour),
                Swatch::Ring(colour) => {
                    svg.circle_outline(cx, y, r * 0.85, Stroke::solid(*colour, theme.px(1.0)))
                }
            }
            cursor += size + theme.px(3.0);
        }
        svg.text(cursor, y, text, &style);
        let width = text_width(text, font).max(columns.get(index).copied().unwrap_or(0.0));
        cursor += width + theme.px(10.0);
    }
}

/// A legend sample.
#[derive(Clone, Copy, Debug)]
enum Swatch {
    Square(Rgb),
    Disc(Rgb),
    Ring(Rgb),
}

/// The legend items of a prediction: where it is, its list, TP, FP, (unobserved when any
/// prediction has some), precision.
fn prediction_items(index: usize, layer: &PredictionLayer, unobserved: bool) -> Vec<LegendItem> {
    let side = if index == 0 { "upper" } else { "lower" };
    let mut items = vec![
        (
            None,
            format!(
                "{side}: {}, top {} (k = {}):",
                layer.name, layer.list_label, layer.k
            ),
        ),
        (
            Some(Swatch::Disc(TRUE_POSITIVE)),
            format!("TP {}", layer.count(Mark::TruePositive)),
        ),
        (
            Some(Swatch::Disc(FALSE_POSITIVE)),
            format!("FP {}", layer.count(Mark::FalsePositive)),
        ),
    ];
    if unobserved {
        items.push((
            Some(Swatch::Ring(UNOBSERVED)),
            format!("unobserved {}", layer.count(Mark::Unobserved)),
        ));
    }
    items.push((None, format!("precision {:.3}", layer.precision())));
    items
}

fn draw_legend(svg: &mut Svg, theme: &Theme, figure: &ContactFigure, layout: &ContactLayout) {
    let x = layout.map.x;
    let row = layout.legend_row;
    let mut y = layout.legend_top + row / 2.0;
    svg.begin_class("legend");
    let true_contacts = format!(
        "true contacts (|i - j| >= {}): {}",
        figure.min_separation,
        figure.true_contacts.len()
    );
    legend_row(
        svg,
        theme,
        (x, y),
        &[(Some(Swatch::Square(STRUCTURAL)), true_contacts)],
        &[],
    );
    let layers = &figure.predictions[..figure.predictions.len().min(2)];
    let unobserved = layers.iter().any(|l| l.count(Mark::Unobserved) > 0);
    let rows: Vec<Vec<LegendItem>> = layers
        .iter()
        .enumerate()
        .map(|(index, layer)| prediction_items(index, layer, unobserved))
        .collect();
    let n_columns = rows.iter().map(Vec::len).max().unwrap_or(0);
    let columns: Vec<f64> = (0..n_columns)
        .map(|c| {
            rows.iter()
                .filter_map(|items| items.get(c))
                .map(|item| text_width(&item.1, theme.font()))
                .fold(0.0, f64::max)
        })
        .collect();
    for items in &rows {
        y += row;
        legend_row(svg, theme, (x, y), items, &columns);
    }
    svg.end_group();
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layer(pairs: Vec<(i32, i32, Mark)>, curve: Vec<usize>) -> PredictionLayer {
        PredictionLayer {
            name: "p.rr".into(),
            list_label: "L".into(),
            k: pairs.len(),
            pairs,
            length: 10,
            curve,
            curve_max_k: 20,
        }
    }

    fn figure(residues: (i32, i32), predictions: Vec<PredictionLayer>) -> ContactFigure {
        ContactFigure {
            residues,
            true_contacts: vec![(1, 7), (2, 9)],
            min_separation: 6,
            predictions,
            title: String::new(),
        }
    }

    #[test]
    fn cells_tile_the_square_map() {
        let fig = figure((1, 10), vec![layer(Vec::new(), Vec::new())]);
        let layout = ContactLayout::new(1000, None, 100.0, &fig);
        let map = layout.map;
        assert_eq!(map.width, map.height);
        assert_eq!(map.x, map.x.round());
        assert_eq!(map.y, map.y.round());
        // Residue 1 starts at the left / top edge, residue 10 ends at the right / bottom.
        let (x, y, w, h) = layout.cell(1, 1);
        assert!((x - map.x).abs() < 1e-9 && (y - map.y).abs() < 1e-9);
        assert!((w - map.width / 10.0).abs() <= 0.5 && (h - w).abs() < 1e-9);
        let (x, y, w, h) = layout.cell(10, 10);
        assert!((x + w - map.x - map.width).abs() < 1e-9);
        assert!((y + h - map.y - map.height).abs() < 1e-9);
        // Whole-pixel edges, each cell starting where the one before ends.
        for col in 1..10 {
            let (x0, _, w0, _) = layout.cell(1, col);
            let (x1, _, _, _) = layout.cell(1, col + 1);
            assert_eq!(x0, x0.round());
            assert_eq!(x0 + w0, x1);
        }
        // Row i down, column j right: (2, 9) is in the upper-right triangle.
        let (cx, cy) = layout.cell_centre(2, 9);
        assert!(cx > map.x + map.width / 2.0 && cy < map.y + map.height / 2.0);
        assert!((cx - (map.x + 8.5 * map.width / 10.0)).abs() < 1e-9);
    }

    #[test]
    fn panels_fit_the_width_and_the_height_holds_the_legend() {
        let fig = figure(
            (1, 62),
            vec![layer(Vec::new(), Vec::new()), layer(Vec::new(), Vec::new())],
        );
        let layout = ContactLayout::new(1000, None, 100.0, &fig);
        let theme = Theme::new(100.0);
        let (map, curve) = (layout.map, layout.curve);
        assert!(curve.x >= map.x + map.width + theme.px(GAP_PT) - 1.0);
        assert!(curve.x + curve.width <= 1000.0);
        assert_eq!((curve.y, curve.height), (map.y, map.height));
        assert!((curve.width / map.width - CURVE_RATIO).abs() < 0.02);
        assert!(layout.legend_top >= map.y + map.height + theme.px(30.0));
        assert!(layout.height_px as f64 >= layout.legend_top + 3.0 * layout.legend_row);
        // A height limit shrinks the map; a bigger one is kept.
        let short = ContactLayout::new(1000, Some(400), 100.0, &fig);
        assert_eq!(short.height_px, 400);
        assert!(short.map.width < map.width);
        let tall = ContactLayout::new(1000, Some(2000), 100.0, &fig);
        assert_eq!(tall.height_px, 2000);
        assert_eq!(tall.map, map);
    }

    #[test]
    fn curve_points_are_precision_over_list_size() {
        let mut one = layer(
            vec![
                (1, 7, Mark::TruePositive),
                (1, 9, Mark::FalsePositive),
                (2, 9, Mark::TruePositive),
                (3, 10, Mark::Unobserved),
            ],
            vec![1, 1, 2, 2],
        );
        assert_eq!(one.count(Mark::TruePositive), 2);
        assert_eq!(one.count(Mark::Unobserved), 1);
        assert_eq!(one.precision(), 0.5);
        assert_eq!(
            one.curve_points(),
            vec![(0.1, 1.0), (0.2, 0.5), (0.3, 2.0 / 3.0), (0.4, 0.5)]
        );
        let fig = figure((1, 10), vec![one.clone()]);
        assert_eq!(fig.curve_max_fraction(), 2.0);
        let layout = ContactLayout::new(800, None, 100.0, &fig);
        let (x, y) = layout.curve_point(1.0, 0.5);
        let curve = layout.curve;
        assert!((x - (curve.x + curve.width / 2.0)).abs() < 1e-9);
        let half = curve.y + curve.height * (1.0 - 0.5 / PRECISION_AXIS_MAX);
        assert!((y - half).abs() < 1e-9);
        one.pairs.clear();
        assert_eq!(one.precision(), 0.0);
    }

    #[test]
    fn markers_go_to_their_triangle_in_classed_groups() {
        let upper = layer(
            vec![(1, 7, Mark::TruePositive), (1, 9, Mark::FalsePositive)],
            vec![1, 1],
        );
        let lower = layer(vec![(3, 10, Mark::FalsePositive)], vec![0]);
        let fig = figure((1, 10), vec![upper, lower]);
        let layout = ContactLayout::new(800, None, 100.0, &fig);
        let doc = draw_contacts(&fig, &layout).unwrap().finish();
        let tree = roxmltree::Document::parse(&doc).unwrap();
        let group = |class: &str| {
            tree.descendants()
                .find(|n| n.attribute("class") == Some(class))
                .unwrap()
        };
        let circles = |node: roxmltree::Node, class: &str| -> Vec<(f64, f64)> {
            node.descendants()
                .filter(|n| n.attribute("class") == Some(class))
                .flat_map(|g| g.children().filter(|c| c.has_tag_name("circle")))
                .map(|c| {
                    (
                        c.attribute("cx").unwrap().parse().unwrap(),
                        c.attribute("cy").unwrap().parse().unwrap(),
                    )
                })
                .collect()
        };
        let near = |got: (f64, f64), want: (f64, f64)| {
            (got.0 - want.0).abs() < 0.01 && (got.1 - want.1).abs() < 0.01
        };
        let tp = circles(group("upper"), "tp");
        assert_eq!(tp.len(), 1);
        assert!(near(tp[0], layout.cell_centre(1, 7)));
        let fp = circles(group("lower"), "fp");
        assert_eq!(fp.len(), 1);
        assert!(near(fp[0], layout.cell_centre(10, 3)));
        let grey = group("true-contacts")
            .children()
            .filter(|n| n.has_tag_name("rect"))
            .count();
        assert_eq!(grey, 4);
    }

    #[test]
    fn the_curve_legend_takes_an_empty_corner() {
        let theme = Theme::new(100.0);
        let curve = Axes {
            x: 100.0,
            y: 50.0,
            width: 300.0,
            height: 300.0,
            x_scale: AxisScale::Linear { min: 0.0, max: 2.0 },
            y_scale: AxisScale::Linear { min: 0.0, max: 1.0 },
            y_down: false,
        };
        let entries = [LegendEntry {
            stroke: Stroke::solid(Rgb::BLACK, 1.0),
            filled: false,
            label: "p.mat".into(),
        }];
        let inset = theme.px(4.0);
        // No points: top right.
        assert_eq!(
            legend_corner(&theme, &curve, &entries, &[]),
            (400.0 - inset, 50.0 + inset)
        );
        // A curve along the top: bottom left.
        let top = vec![(100.0, 60.0), (400.0, 60.0)];
        let (right, top_y) = legend_corner(&theme, &curve, &entries, &[top]);
        assert!(right < 250.0 && top_y > 250.0, "{right} {top_y}");
        // A steep segment through the top right box, no vertex inside it: bottom left too.
        let steep = vec![(360.0, 50.0), (370.0, 350.0)];
        let (right, top_y) = legend_corner(&theme, &curve, &entries, &[steep]);
        assert!(right < 250.0 && top_y > 250.0, "{right} {top_y}");
    }

    #[test]
    fn residue_ticks_are_whole_numbers_inside_the_range() {
        let theme = Theme::new(100.0);
        let ticks = residue_ticks(1, 62, 400.0, &theme);
        assert!(ticks.iter().all(|(v, _)| *v >= 1.0 && *v <= 62.0));
        assert_eq!(ticks.first().map(|t| t.1.as_str()), Some("10"));
        assert!(ticks.len() >= 3);
    }
}
