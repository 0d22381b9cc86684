//! Line charts on a shared horizontal axis: panels stacked top to bottom (P(s) on log-log axes
//! above its local slope, as cooltools' and HiCExplorer's P(s) figures), each with its own
//! vertical scale, and a legend in the first panel that asks for one.
//!
//! Limits follow the data with matplotlib's default margins (5% of the range on each side, in
//! log space on log axes); a point with a non-finite coordinate (or a non-positive one on a log
//! axis) breaks its line. Only the bottom panel labels the shared axis.

use crate::error::{Error, Result};
use crate::expected::powerlaw::PowerLaw;
use crate::genome::{format_bp, format_distance};
use crate::plot::axes::{
    Axes, AxisScale, CURVE_COLOURS, LegendEntry, Side, Theme, legend, legend_size, log_ticks,
};
use crate::plot::svg::{Anchor, Baseline, Stroke, Svg, TextStyle, text_width};

/// One line.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text (`None`: not in the legend).
    pub label: Option<String>,
    /// `(x, y)` in data units, in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Colour, width and dashes.
    pub stroke: Stroke,
}

/// Linear or logarithmic.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// Linear.
    Linear,
    /// Logarithmic (positive values only).
    Log,
}

/// One panel of lines.
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    /// Vertical axis label.
    pub y_label: String,
    /// Vertical scale.
    pub y_scale: Scale,
    /// The lines, drawn in order.
    pub series: Vec<Series>,
    /// Height relative to the other panels.
    pub weight: f64,
    /// Draw the legend of the labelled series in this panel (top right).
    pub legend: bool,
    /// Smallest span of a linear vertical axis, around the data's middle (so that a nearly
    /// constant slope is not blown up to the panel's height).
    pub min_span: f64,
}

/// A figure of stacked panels sharing the horizontal axis.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveFigure {
    /// Title above the first panel (empty: none).
    pub title: String,
    /// Label of the shared horizontal axis.
    pub x_label: String,
    /// Horizontal scale.
    pub x_scale: Scale,
    /// Label horizontal log ticks as distances (`10 kb`, `1 Mb`) instead of `10^k`.
    pub x_in_bp: bool,
    /// The panels, top to bottom.
    pub panels: Vec<Panel>,
    /// Figure width in pixels.
    pub width_px: usize,
    /// Figure height in pixels (`None`: the panels' default proportions).
    pub height_px: Option<usize>,
    /// Dots per inch.
    pub dpi: f64,
}

/// Default height of a panel of weight 1, as a fraction of the axes' width.
const UNIT_HEIGHT: f64 = 0.25;

/// The data range of `values` on `scale` widened by matplotlib's 5% margins; a single value
/// gets a range around it.
pub fn data_limits(values: impl Iterator<Item = f64>, scale: Scale) -> Option<(f64, f64)> {
    let usable = |v: &f64| v.is_finite() && (scale == Scale::Linear || *v > 0.0);
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(usable) {
        low = low.min(v);
        high = high.max(v);
    }
    if low > high {
        return None;
    }
    Some(match scale {
        Scale::Linear => {
            let pad = if high > low {
                0.05 * (high - low)
            } else {
                0.5 * low.abs().max(1.0)
            };
            (low - pad, high + pad)
        }
        Scale::Log => {
            let (l, h) = (low.log10(), high.log10());
            let pad = if h > l { 0.05 * (h - l) } else { 0.5 };
            (10f64.powf(l - pad), 10f64.powf(h + pad))
        }
    })
}

fn axis_scale(scale: Scale, (min, max): (f64, f64)) -> AxisScale {
    match scale {
        Scale::Linear => AxisScale::Linear { min, max },
        Scale::Log => AxisScale::Log { min, max },
    }
}

/// Ticks of the shared axis: decades as distances when `in_bp` (with `1, 2, 5` times them
/// when the range is under two decades).
fn x_ticks(scale: &AxisScale, in_bp: bool) -> (Vec<(f64, String)>, Vec<f64>) {
    match (scale, in_bp) {
        (AxisScale::Log { min, max }, true) => {
            let (major, minor) = log_ticks(*min, *max);
            let major = major
                .into_iter()
                .map(|(value, _)| (value, format_bp(value)))
                .collect();
            (major, minor)
        }
        _ => scale.ticks(6),
    }
}

/// The points of `series` split where they cannot be drawn, in pixels.
fn segments(axes: &Axes, points: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut current = Vec::new();
    for &(x, y) in points {
        let (px, py) = (axes.px(x), axes.py(y));
        if px.is_finite() && py.is_finite() {
            current.push((px, py));
        } else if !current.is_empty() {
            out.push(std::mem::take(&mut current));
        }
    }
    if !current.is_empty() {
        out.push(current);
    }
    out
}

/// Where the legend of `entries` goes in `axes` (its top right corner): the corner of the axes
/// whose legend box covers the fewest points of the `drawn` lines (sampled along each
/// segment), top right first on ties.
fn legend_corner(
    axes: &Axes,
    theme: &Theme,
    entries: &[LegendEntry],
    drawn: &[Vec<(f64, f64)>],
) -> (f64, f64) {
    let (width, height) = legend_size(theme, entries);
    let margin = theme.px(6.0);
    let (left, right) = (axes.x + margin + width, axes.x + axes.width - margin);
    let (top, bottom) = (axes.y + margin, axes.y + axes.height - margin - height);
    let covered = |(r, t): (f64, f64)| {
        let inside = |(x, y): (f64, f64)| x >= r - width && x <= r && y >= t && y <= t + height;
        let mut count = 0;
        for line in drawn {
            count += usize::from(line.first().is_some_and(|&p| inside(p)));
            for pair in line.windows(2) {
                let ((x0, y0), (x1, y1)) = (pair[0], pair[1]);
                count += (1..=8)
                    .filter(|&k| {
                        let f = f64::from(k) / 8.0;
                        inside((x0 + (x1 - x0) * f, y0 + (y1 - y0) * f))
                    })
                    .count();
            }
        }
        count
    };
    [(right, top), (left, top), (right, bottom), (left, bottom)]
        .into_iter()
        .min_by_key(|&corner| covered(corner))
        .unwrap_or((right, top))
}

/// Draw the figure.
///
/// # Examples
///
/// P(s) above its slope, as `contactmap plot expected` draws them:
///
/// ```
/// use contactmap::plot::curves::{draw_curves, CurveFigure, Panel, Scale, Series};
/// use contactmap::plot::svg::Stroke;
/// use contactmap::plot::Rgb;
///
/// let line = |points: Vec<(f64, f64)>| Series {
///     label: Some("sample".into()),
///     points,
///     stroke: Stroke::solid(Rgb(31, 119, 180), 1.5),
/// };
/// let distances: Vec<f64> = (1..=50).map(|k| 1e4 * 1.2f64.powi(k)).collect();
/// let panel = |y_label: &str, y_scale, points, weight| Panel {
///     y_label: y_label.into(),
///     y_scale,
///     series: vec![line(points)],
///     weight,
///     legend: weight > 1.0,
///     min_span: 0.5,
/// };
/// let figure = CurveFigure {
///     title: "P(s)".into(),
///     x_label: "distance".into(),
///     x_scale: Scale::Log,
///     x_in_bp: true,
///     panels: vec![
///         panel("P(s)", Scale::Log, distances.iter().map(|&s| (s, 1.0 / s)).collect(), 2.0),
///         panel("slope", Scale::Linear, distances.iter().map(|&s| (s, -1.0)).collect(), 1.0),
///     ],
///     width_px: 600,
///     height_px: None,
///     dpi: 100.0,
/// };
/// let svg = draw_curves(&figure)?;
/// assert_eq!(svg.width_px(), 600);
/// let text = svg.finish();
/// assert!(text.contains("P(s)") && text.contains("sample") && text.contains("1 Mb"));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn draw_curves(figure: &CurveFigure) -> Result<Svg> {
    if figure.panels.is_empty() {
        return Err(Error::Argument("a figure needs at least one panel".into()));
    }
    let theme = Theme::new(figure.dpi);
    let all_points = || {
        figure
            .panels
            .iter()
            .flat_map(|p| p.series.iter().flat_map(|s| s.points.iter()))
    };
    let x_limits = data_limits(all_points().map(|p| p.0), figure.x_scale)
        .ok_or_else(|| Error::Data("nothing to draw: no point has a usable distance".into()))?;
    let x_scale = axis_scale(figure.x_scale, x_limits);
    let mut y_scales = Vec::with_capacity(figure.panels.len());
    for panel in &figure.panels {
        let points = panel.series.iter().flat_map(|s| s.points.iter());
        let mut limits = data_limits(points.map(|p| p.1), panel.y_scale).ok_or_else(|| {
            Error::Data(format!("nothing to draw in the panel '{}'", panel.y_label))
        })?;
        if panel.y_scale == Scale::Linear && limits.1 - limits.0 < panel.min_span {
            let middle = (limits.0 + limits.1) / 2.0;
            limits = (middle - panel.min_span / 2.0, middle + panel.min_span / 2.0);
        }
        y_scales.push(axis_scale(panel.y_scale, limits));
    }
    let y_ticks: Vec<_> = y_scales.iter().map(|s| s.ticks(5)).collect();

    // Margins in pixels: tick labels and axis labels measured, the rest in points.
    let font = theme.font();
    let widest_y = y_ticks
        .iter()
        .flat_map(|(major, _)| major.iter().map(|(_, label)| text_width(label, font)))
        .fold(0.0, f64::max);
    let left = (theme.px(8.0) + theme.label_font() * 1.4 + theme.px(6.0) + widest_y).ceil();
    let (x_major, x_minor) = x_ticks(&x_scale, figure.x_in_bp);
    let last_x_label = x_major
        .last()
        .map_or(0.0, |(_, label)| text_width(label, font));
    let right = (theme.px(12.0))
        .max(last_x_label / 2.0 + theme.px(4.0))
        .ceil();
    let top = theme.top_margin(!figure.title.is_empty());
    let bottom = (theme.px(5.5) + font * 1.1 + theme.label_font() * 1.4 + theme.px(8.0)).ceil();
    let gap = theme.px(8.0).ceil();
    let width = figure.width_px as f64;
    let axes_width = width - left - right;
    if axes_width < theme.px(60.0) {
        return Err(Error::Argument(format!(
            "the figure is too narrow for its axes ({} pixels)",
            figure.width_px
        )));
    }
    let total_weight: f64 = figure.panels.iter().map(|p| p.weight.max(0.1)).sum();
    let gaps = gap * (figure.panels.len() - 1) as f64;
    let panels_height = match figure.height_px {
        Some(h) => h as f64 - top - bottom - gaps,
        None => (UNIT_HEIGHT * axes_width * total_weight).round(),
    };
    if panels_height < theme.px(30.0) * figure.panels.len() as f64 {
        return Err(Error::Argument(format!(
            "the figure is too short for {} panel(s)",
            figure.panels.len()
        )));
    }
    let height_px = figure
        .height_px
        .unwrap_or((top + panels_height + gaps + bottom).round() as usize);
    let mut svg = Svg::new(figure.width_px, height_px, figure.dpi);

    let mut y = top;
    let last = figure.panels.len() - 1;
    for (index, panel) in figure.panels.iter().enumerate() {
        let height = (panels_height * panel.weight.max(0.1) / total_weight).round();
        let axes = Axes {
            x: left,
            y,
            width: axes_width.round(),
            height,
            x_scale,
            y_scale: y_scales[index],
            y_down: false,
        };
        axes.clip(&mut svg);
        let mut drawn = Vec::new();
        for series in &panel.series {
            for line in segments(&axes, &series.points) {
                drawn.push(line.clone());
                if line.len() == 1 {
                    svg.circle(
                        line[0].0,
                        line[0].1,
                        series.stroke.width,
                        series.stroke.colour,
                    );
                } else {
                    svg.polyline(&line, series.stroke);
                }
            }
        }
        svg.end_group();
        axes.frame(&mut svg, &theme);
        let (major, minor) = &y_ticks[index];
        let depth = axes.ticks(&mut svg, &theme, Side::Left, major, minor);
        axes.label(&mut svg, &theme, Side::Left, depth, &panel.y_label);
        if index == last {
            let depth = axes.ticks(&mut svg, &theme, Side::Bottom, &x_major, &x_minor);
            axes.label(&mut svg, &theme, Side::Bottom, depth, &figure.x_label);
        } else {
            let marks: Vec<(f64, String)> =
                x_major.iter().map(|(v, _)| (*v, String::new())).collect();
            axes.ticks(&mut svg, &theme, Side::Bottom, &marks, &x_minor);
        }
        if index == 0 && !figure.title.is_empty() {
            svg.text(
                axes.x + axes.width / 2.0,
                axes.y - theme.px(6.0),
                &figure.title,
                &TextStyle::new(theme.label_font(), Anchor::Middle, Baseline::Bottom),
            );
        }
        if panel.legend {
            let entries: Vec<LegendEntry> = panel
                .series
                .iter()
                .filter_map(|s| {
                    s.label.as_ref().map(|label| LegendEntry {
                        stroke: s.stroke,
                        filled: false,
                        label: label.clone(),
                    })
                })
                .collect();
            let (right, top) = legend_corner(&axes, &theme, &entries, &drawn);
            legend(&mut svg, &theme, right, top, &entries);
        }
        y += height + gap;
    }
    Ok(svg)
}

/// One sample of a P(s) figure.
pub struct PsSample {
    /// Its name in the legend.
    pub label: String,
    /// Its log-binned P(s), slopes and fit.
    pub power_law: PowerLaw,
}

/// What a P(s) figure shows.
#[derive(Clone, Debug, PartialEq)]
pub struct PsFigure {
    /// A curve per region instead of the combined curve.
    pub per_region: bool,
    /// The fitted power law of each sample (dashed, over its fit range).
    pub fit: bool,
    /// The panel of local slopes under the curves.
    pub slope_panel: bool,
    /// The title (empty: none).
    pub title: String,
    /// Width in pixels.
    pub width_px: usize,
    /// Height in pixels (`None`: what the panels need).
    pub height_px: Option<usize>,
    /// Dots per inch.
    pub dpi: f64,
}

/// The P(s) figure of `samples`: P(s) (and fits) on log-log axes above, the local slopes below,
/// one colour per curve.
pub fn ps_figure(samples: &[PsSample], options: &PsFigure) -> CurveFigure {
    let theme = Theme::new(options.dpi);
    let line =
        |index: usize| Stroke::solid(CURVE_COLOURS[index % CURVE_COLOURS.len()], theme.px(1.5));
    let dashed = |index: usize| line(index).dashed(theme.px(4.0));
    let mut ps = Vec::new();
    let mut slopes = Vec::new();
    let mut colour = 0;
    for sample in samples {
        let binned = &sample.power_law.binned;
        let bin_bp = binned.resolution as f64;
        if options.per_region {
            for (region, name) in binned.region_names.iter().enumerate() {
                let points: Vec<(f64, f64)> = binned
                    .by_region
                    .iter()
                    .filter(|b| b.region as usize == region)
                    .map(|b| (b.dist_avg * bin_bp, b.average))
                    .collect();
                if points.is_empty() {
                    continue;
                }
                let label = if samples.len() == 1 {
                    name.clone()
                } else {
                    format!("{} {name}", sample.label)
                };
                ps.push(Series {
                    label: Some(label),
                    points,
                    stroke: line(colour),
                });
                slopes.push(Series {
                    label: None,
                    points: binned
                        .region_slopes
                        .iter()
                        .filter(|s| s.region == Some(region as u32))
                        .map(|s| (s.dist_avg * bin_bp, s.slope))
                        .collect(),
                    stroke: line(colour),
                });
                colour += 1;
            }
            continue;
        }
        ps.push(Series {
            label: Some(sample.label.clone()),
            points: binned
                .combined
                .iter()
                .map(|b| (b.dist_avg * bin_bp, b.average))
                .collect(),
            stroke: line(colour),
        });
        slopes.push(Series {
            label: None,
            points: binned
                .slopes
                .iter()
                .map(|s| (s.dist_avg * bin_bp, s.slope))
                .collect(),
            stroke: line(colour),
        });
        if let (true, Ok(report)) = (options.fit, &sample.power_law.fit) {
            let fit = &report.fit;
            let at = |s: f64| 10f64.powf(fit.intercept_log10) * s.powf(fit.alpha);
            ps.push(Series {
                label: Some(format!(
                    "fit {}-{}: s^{:.2}",
                    format_distance(fit.first_bp),
                    format_distance(fit.last_bp),
                    fit.alpha
                )),
                points: vec![
                    (fit.first_bp, at(fit.first_bp)),
                    (fit.last_bp, at(fit.last_bp)),
                ],
                stroke: dashed(colour),
            });
            slopes.push(Series {
                label: None,
                points: vec![(fit.first_bp, fit.alpha), (fit.last_bp, fit.alpha)],
                stroke: dashed(colour),
            });
        }
        colour += 1;
    }
    let balanced: Vec<bool> = samples
        .iter()
        .map(|s| s.power_law.table.is_balanced())
        .collect();
    let y_label = if balanced.iter().all(|&b| b) {
        "P(s), balanced"
    } else if balanced.iter().all(|&b| !b) {
        "P(s), raw counts"
    } else {
        "P(s)"
    };
    let mut panels = vec![Panel {
        y_label: y_label.to_string(),
        y_scale: Scale::Log,
        series: ps,
        weight: 2.2,
        legend: true,
        min_span: 0.0,
    }];
    if options.slope_panel {
        panels.push(Panel {
            y_label: "slope".to_string(),
            y_scale: Scale::Linear,
            series: slopes,
            weight: 1.0,
            legend: false,
            min_span: 0.5,
        });
    }
    CurveFigure {
        title: options.title.clone(),
        x_label: "separation s".to_string(),
        x_scale: Scale::Log,
        x_in_bp: true,
        panels,
        width_px: options.width_px,
        height_px: options.height_px,
        dpi: options.dpi,
    }
}

/// The polymer statistics of one ensemble (`contactmap polymer-stats`'s tables).
#[derive(Clone, Debug, PartialEq)]
pub struct PolymerSample {
    /// Its name in the legend.
    pub label: String,
    /// P(s): `(s_mid, contact probability)`.
    pub scaling: Vec<(f64, f64)>,
    /// `(s, <R^2(s)>, <Rg^2(s)>)`.
    pub r2: Vec<(f64, f64, f64)>,
    /// Each conformation's `Rg^2`, in the order read.
    pub rg2: Vec<f64>,
}

/// What a polymer-statistics figure shows.
#[derive(Clone, Debug, PartialEq)]
pub struct PolymerFigure {
    /// `Rg^2` of each conformation against its number (time, for a trajectory) instead of the
    /// curves against the separation.
    pub over_time: bool,
    /// The panel of local slopes (P(s) solid, `<R^2(s)>` dashed).
    pub slope_panel: bool,
    /// The title (empty: none).
    pub title: String,
    /// Width in pixels.
    pub width_px: usize,
    /// Height in pixels (`None`: what the panels need).
    pub height_px: Option<usize>,
    /// Dots per inch.
    pub dpi: f64,
}

/// The figure of `samples`' polymer statistics, one colour per sample. Against the separation
/// `s` (beads, log axes): P(s) above, `<R^2(s)>` (solid) and `<Rg^2(s)>` (dashed) below it, and
/// the local slopes ([`crate::conformations::stats::log_slopes`]) of P(s) (solid) and
/// `<R^2(s)>` (dashed) at the bottom; or, `over_time`, each conformation's `Rg^2` against its
/// number (linear axes).
pub fn polymer_figure(samples: &[PolymerSample], options: &PolymerFigure) -> CurveFigure {
    use crate::conformations::stats::log_slopes;
    let theme = Theme::new(options.dpi);
    let line =
        |index: usize| Stroke::solid(CURVE_COLOURS[index % CURVE_COLOURS.len()], theme.px(1.5));
    let dashed = |index: usize| line(index).dashed(theme.px(4.0));
    let base = |x_label: &str, x_scale, panels| CurveFigure {
        title: options.title.clone(),
        x_label: x_label.to_string(),
        x_scale,
        x_in_bp: false,
        panels,
        width_px: options.width_px,
        height_px: options.height_px,
        dpi: options.dpi,
    };
    let panel = |y_label: &str, y_scale, series, weight, legend| Panel {
        y_label: y_label.to_string(),
        y_scale,
        series,
        weight,
        legend,
        min_span: if y_scale == Scale::Linear { 0.5 } else { 0.0 },
    };
    if options.over_time {
        let series = samples
            .iter()
            .enumerate()
            .map(|(k, sample)| Series {
                label: Some(sample.label.clone()),
                points: (1..)
                    .zip(&sample.rg2)
                    .map(|(n, &g)| (f64::from(n), g))
                    .collect(),
                stroke: line(k),
            })
            .collect();
        return base(
            "conformation (in the order read)",
            Scale::Linear,
            vec![panel("Rg\u{b2}", Scale::Linear, series, 2.0, true)],
        );
    }
    let (mut ps, mut sizes, mut slopes) = (Vec::new(), Vec::new(), Vec::new());
    for (k, sample) in samples.iter().enumerate() {
        let r2: Vec<(f64, f64)> = sample.r2.iter().map(|&(s, r2, _)| (s, r2)).collect();
        ps.push(Series {
            label: Some(sample.label.clone()),
            points: sample.scaling.clone(),
            stroke: line(k),
        });
        sizes.push(Series {
            label: Some(format!("{} R\u{b2}(s)", sample.label)),
            points: r2.clone(),
            stroke: line(k),
        });
        sizes.push(Series {
            label: Some(format!("{} Rg\u{b2}(s)", sample.label)),
            points: sample.r2.iter().map(|&(s, _, g)| (s, g)).collect(),
            stroke: dashed(k),
        });
        slopes.push(Series {
            label: None,
            points: log_slopes(&sample.scaling),
            stroke: line(k),
        });
        slopes.push(Series {
            label: None,
            points: log_slopes(&r2),
            stroke: dashed(k),
        });
    }
    let mut panels = vec![
        panel("contact probability P(s)", Scale::Log, ps, 2.0, true),
        panel("<R\u{b2}(s)>, <Rg\u{b2}(s)>", Scale::Log, sizes, 1.6, true),
    ];
    if options.slope_panel {
        panels.push(panel("slope", Scale::Linear, slopes, 1.0, false));
    }
    base("separation s (beads)", Scale::Log, panels)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::svg::Rgb;

    #[test]
    fn limits_have_matplotlib_margins() {
        let (low, high) = data_limits([1.0, 3.0, f64::NAN].into_iter(), Scale::Linear).unwrap();
        assert!((low - 0.9).abs() < 1e-12 && (high - 3.1).abs() < 1e-12);
        let (low, high) = data_limits([10.0, 1e5, 0.0, -1.0].into_iter(), Scale::Log).unwrap();
        assert!((low.log10() - 0.8).abs() < 1e-12 && (high.log10() - 5.2).abs() < 1e-12);
        assert!(data_limits([0.0, -2.0].into_iter(), Scale::Log).is_none());
        let (low, high) = data_limits([2.0].into_iter(), Scale::Linear).unwrap();
        assert!(low < 2.0 && high > 2.0);
    }

    #[test]
    fn distance_ticks_read_as_bp() {
        let (major, minor) = x_ticks(&AxisScale::Log { min: 5e3, max: 2e7 }, true);
        let labels: Vec<&str> = major.iter().map(|(_, l)| l.as_str()).collect();
        assert_eq!(labels, ["10 kb", "100 kb", "1 Mb", "10 Mb"]);
        assert!(minor.contains(&2e4) && minor.contains(&2e7));
    }

    #[test]
    fn lines_break_at_unusable_points() {
        let axes = Axes {
            x: 0.0,
            y: 0.0,
            width: 100.0,
            height: 100.0,
            x_scale: AxisScale::Log {
                min: 1.0,
                max: 100.0,
            },
            y_scale: AxisScale::Linear { min: 0.0, max: 1.0 },
            y_down: false,
        };
        let points = [
            (1.0, 0.0),
            (10.0, 0.5),
            (0.0, 0.5),
            (100.0, 1.0),
            (10.0, f64::NAN),
        ];
        let lines = segments(&axes, &points);
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[0], vec![(0.0, 100.0), (50.0, 50.0)]);
        assert_eq!(lines[1], vec![(100.0, 0.0)]);
    }

    #[test]
    fn polymer_statistics_are_drawn_with_their_power_laws_slopes() {
        let s: Vec<f64> = (0..20).map(|k| 4.0 * 1.3f64.powi(k)).collect();
        let sample = PolymerSample {
            label: "ideal".into(),
            scaling: s.iter().map(|&s| (s, 0.5 * s.powf(-1.5))).collect(),
            r2: s.iter().map(|&s| (s, 2.0 * s, s / 3.0)).collect(),
            rg2: vec![3.0, 2.0, 4.0],
        };
        let mut options = PolymerFigure {
            over_time: false,
            slope_panel: true,
            title: String::new(),
            width_px: 600,
            height_px: None,
            dpi: 100.0,
        };
        let figure = polymer_figure(std::slice::from_ref(&sample), &options);
        assert_eq!(figure.panels.len(), 3);
        assert_eq!(figure.panels[0].series[0].points, sample.scaling);
        assert_eq!(figure.panels[1].series.len(), 2, "R^2 and Rg^2");
        assert_eq!(figure.panels[1].series[1].points[3], (s[3], s[3] / 3.0));
        let slopes = &figure.panels[2].series;
        for (series, exponent) in slopes.iter().zip([-1.5, 1.0]) {
            assert_eq!(series.points.len(), 19);
            for &(x, k) in &series.points {
                assert!((k - exponent).abs() < 1e-12 && x > 4.0);
            }
        }
        assert!(draw_curves(&figure).is_ok());
        options.slope_panel = false;
        assert_eq!(
            polymer_figure(std::slice::from_ref(&sample), &options)
                .panels
                .len(),
            2
        );
        options.over_time = true;
        let figure = polymer_figure(&[sample], &options);
        assert_eq!(figure.panels.len(), 1);
        assert_eq!(
            figure.panels[0].series[0].points,
            [(1.0, 3.0), (2.0, 2.0), (3.0, 4.0)]
        );
    }

    #[test]
    fn the_legend_takes_the_emptiest_corner() {
        let figure = |points: Vec<(f64, f64)>| CurveFigure {
            title: String::new(),
            x_label: "x".into(),
            x_scale: Scale::Linear,
            x_in_bp: false,
            panels: vec![Panel {
                y_label: "y".into(),
                y_scale: Scale::Linear,
                series: vec![Series {
                    label: Some("a line".into()),
                    points,
                    stroke: Stroke::solid(Rgb::BLACK, 1.0),
                }],
                weight: 1.0,
                legend: true,
                min_span: 0.0,
            }],
            width_px: 600,
            height_px: Some(400),
            dpi: 100.0,
        };
        let legend_x = |points: Vec<(f64, f64)>| {
            let text = draw_curves(&figure(points)).unwrap().finish();
            let at = text.find(">a line</text>").unwrap();
            let start = text[..at].rfind("<text x=\"").unwrap() + 9;
            let end = start + text[start..].find('"').unwrap();
            text[start..end].parse::<f64>().unwrap()
        };
        // falling: the top right is free; rising: the top left
        let falling = legend_x((0..50).map(|k| (f64::from(k), -f64::from(k))).collect());
        let rising = legend_x((0..50).map(|k| (f64::from(k), f64::from(k))).collect());
        assert!(falling > 300.0 && rising < 300.0, "{falling} {rising}");
    }

    #[test]
    fn panels_stack_with_the_asked_height() {
        let series = |points: Vec<(f64, f64)>| Series {
            label: Some("a".into()),
            points,
            stroke: Stroke::solid(Rgb::BLACK, 1.0),
        };
        let figure = CurveFigure {
            title: "t".into(),
            x_label: "s".into(),
            x_scale: Scale::Log,
            x_in_bp: true,
            panels: vec![
                Panel {
                    y_label: "P(s)".into(),
                    y_scale: Scale::Log,
                    series: vec![series(vec![(1e4, 1.0), (1e6, 0.01)])],
                    weight: 2.0,
                    legend: true,
                    min_span: 0.0,
                },
                Panel {
                    y_label: "slope".into(),
                    y_scale: Scale::Linear,
                    series: vec![series(vec![(1e4, -1.0), (1e6, -1.0)])],
                    weight: 1.0,
                    legend: false,
                    min_span: 1.0,
                },
            ],
            width_px: 600,
            height_px: Some(450),
            dpi: 100.0,
        };
        let svg = draw_curves(&figure).unwrap();
        assert_eq!((svg.width_px(), svg.height_px()), (600, 450));
        let text = svg.finish();
        assert_eq!(text.matches("<polyline").count(), 2, "{text}");
        assert!(text.contains(">P(s)</text>") && text.contains(">10 kb</text>"));
        let default = draw_curves(&CurveFigure {
            height_px: None,
            ..figure.clone()
        })
        .unwrap();
        assert!(default.height_px() > 300 && default.height_px() < 600);
        let empty = CurveFigure {
            panels: vec![Panel {
                series: vec![series(vec![(0.0, 1.0)])],
                ..figure.panels[0].clone()
            }],
            ..figure
        };
        assert!(draw_curves(&empty).is_err());
    }
}
