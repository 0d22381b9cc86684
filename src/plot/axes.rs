//! Axes: scales, tick positions and labels, frames, legends and colour bars.
//!
//! Sizes are given in points and converted with the figure's [`Theme`] (`dpi / 72` pixels per
//! point), so a figure at `--dpi 300` has the proportions of the same figure at 100 dpi.
//! Linear ticks fall on 1, 2, 2.5 and 5 times a power of ten (matplotlib's `MaxNLocator`
//! steps); log axes tick every decade, labelled `10^k`, with minor ticks at 2..9 times it.

use crate::error::Result;
use crate::plot::colormap::{ColorMap, ColorScale, ScaleKind};
use crate::plot::svg::{Anchor, Baseline, Rgb, RgbImage, Stroke, Svg, TextStyle, text_width};

/// Sizes of a figure's text and lines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Theme {
    /// Pixels per point (`dpi / 72`).
    pub px_per_pt: f64,
    /// Tick label size in points.
    pub font_pt: f64,
}

impl Theme {
    /// The theme of a figure drawn at `dpi`.
    pub fn new(dpi: f64) -> Theme {
        Theme {
            px_per_pt: dpi / 72.0,
            font_pt: 9.0,
        }
    }

    /// `points` in pixels.
    pub fn px(&self, points: f64) -> f64 {
        points * self.px_per_pt
    }

    /// Tick label text size in pixels.
    pub fn font(&self) -> f64 {
        self.px(self.font_pt)
    }

    /// Axis label / title size in pixels.
    pub fn label_font(&self) -> f64 {
        self.px(self.font_pt + 1.0)
    }

    /// Pixels above the axes: room for the title when there is one.
    pub fn top_margin(&self, has_title: bool) -> f64 {
        if has_title {
            (self.px(10.0) + self.label_font() * 1.6).ceil()
        } else {
            self.px(10.0).ceil()
        }
    }

    /// Frame and tick stroke.
    pub fn frame_stroke(&self) -> Stroke {
        Stroke::solid(Rgb::BLACK, self.px(0.8))
    }
}

/// How an axis maps values to its length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AxisScale {
    /// Linear from `min` to `max`.
    Linear {
        /// Value at the axis start.
        min: f64,
        /// Value at the axis end.
        max: f64,
    },
    /// Logarithmic from `min` to `max` (both positive).
    Log {
        /// Value at the axis start.
        min: f64,
        /// Value at the axis end.
        max: f64,
    },
}

impl AxisScale {
    /// Fraction of the axis length at `value` (not clamped; NaN for non-positive values on a
    /// log axis).
    pub fn fraction(&self, value: f64) -> f64 {
        match *self {
            AxisScale::Linear { min, max } => (value - min) / (max - min),
            AxisScale::Log { min, max } => {
                if value > 0.0 {
                    (value.ln() - min.ln()) / (max.ln() - min.ln())
                } else {
                    f64::NAN
                }
            }
        }
    }

    /// Major ticks `(value, label)` and minor tick values, for about `target` labels.
    pub fn ticks(&self, target: usize) -> (Vec<(f64, String)>, Vec<f64>) {
        match *self {
            AxisScale::Linear { min, max } => {
                let values = linear_ticks(min, max, target);
                let step = if values.len() > 1 {
                    values[1] - values[0]
                } else {
                    (max - min).abs()
                };
                let labels = values.iter().map(|&v| (v, format_tick(v, step))).collect();
                (labels, Vec::new())
            }
            AxisScale::Log { min, max } => log_ticks(min, max),
        }
    }
}

/// About `target` evenly spaced round values inside `[min, max]`; at least two when the range
/// is not empty (a finer step is taken when the round step leaves only one inside).
pub fn linear_ticks(min: f64, max: f64, target: usize) -> Vec<f64> {
    let (low, high) = if min <= max { (min, max) } else { (max, min) };
    let span = high - low;
    if !(span > 0.0 && span.is_finite()) {
        return vec![low];
    }
    let raw = span / target.max(1) as f64;
    let magnitude = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * magnitude)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * magnitude);
    let first = (low / step - 1e-9).ceil();
    let last = (high / step + 1e-9).floor();
    let mut ticks = Vec::new();
    let mut k = first;
    while k <= last {
        let value = k * step;
        // Remove the -0 and rounding noise of k * step.
        ticks.push(if value.abs() < step * 1e-9 {
            0.0
        } else {
            value
        });
        k += 1.0;
    }
    if ticks.len() < 2 && target < 64 {
        return linear_ticks(min, max, target.max(1) * 2);
    }
    ticks
}

/// `value` with as many decimals as `step` needs (`2.5`, `10`, `0.25`).
pub fn format_tick(value: f64, step: f64) -> String {
    let decimals = if step >= 1.0 && (step - step.round()).abs() < 1e-9 {
        0
    } else {
        let mut d = 0usize;
        let mut s = step;
        while d < 8 && (s - s.round()).abs() > 1e-6 * s.abs().max(1e-12) {
            s *= 10.0;
            d += 1;
        }
        d
    };
    format!("{value:.decimals$}")
}

/// Decade ticks inside `[min, max]` labelled `10^k`, minor ticks at 2..9 times each decade;
/// a range within one decade gets labelled ticks at 1, 2 and 5 times it.
pub fn log_ticks(min: f64, max: f64) -> (Vec<(f64, String)>, Vec<f64>) {
    let (low, high) = if min <= max { (min, max) } else { (max, min) };
    if !(low > 0.0 && high.is_finite()) {
        return (Vec::new(), Vec::new());
    }
    let inside = |v: f64| v >= low * (1.0 - 1e-9) && v <= high * (1.0 + 1e-9);
    let (first, last) = (low.log10().floor() as i32, high.log10().ceil() as i32);
    let mut major = Vec::new();
    let mut minor = Vec::new();
    for exponent in first..=last {
        let decade = 10f64.powi(exponent);
        if inside(decade) {
            major.push((decade, format!("10^{exponent}")));
        }
        for m in 2..10 {
            let value = f64::from(m) * decade;
            if inside(value) {
                minor.push(value);
            }
        }
    }
    if major.len() < 2 {
        // Less than a decade: label 1, 2, 5 times the decades as plain numbers.
        major.clear();
        minor.clear();
        for exponent in first..=last {
            for m in [1.0, 2.0, 5.0] {
                let value = m * 10f64.powi(exponent);
                if inside(value) {
                    major.push((value, format_tick(value, value)));
                }
            }
        }
    }
    if major.len() < 2 {
        // A narrower range still (0.7 to 1.8 holds only 1): round linear values, at least two.
        let values = linear_ticks(low, high, 5);
        let step = match values.as_slice() {
            [a, b, ..] => b - a,
            _ => high - low,
        };
        major = values
            .into_iter()
            .filter(|&v| v > 0.0)
            .map(|v| (v, format_tick(v, step)))
            .collect();
        minor.clear();
    }
    (major, minor)
}

/// A unit for genomic coordinates: `(divisor, name)`, chosen so that `span_bp` reads as a
/// small number (Mb from 2 Mb, kb from 2 kb).
pub fn genomic_unit(span_bp: f64) -> (f64, &'static str) {
    if span_bp >= 2e6 {
        (1e6, "Mb")
    } else if span_bp >= 2e3 {
        (1e3, "kb")
    } else {
        (1.0, "bp")
    }
}

/// Whether `text` at `size` pixels fits in `room` pixels.
pub fn text_width_fits(text: &str, size: f64, room: f64) -> bool {
    text_width(text, size) <= room
}

/// A rectangle of the figure with a scale on each side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axes {
    /// Left edge in pixels.
    pub x: f64,
    /// Top edge in pixels.
    pub y: f64,
    /// Width in pixels.
    pub width: f64,
    /// Height in pixels.
    pub height: f64,
    /// Horizontal scale (left to right).
    pub x_scale: AxisScale,
    /// Vertical scale (bottom to top, unless `y_down`).
    pub y_scale: AxisScale,
    /// The vertical axis grows downwards (matrix rows).
    pub y_down: bool,
}

/// Which side of the axes a tick set is drawn on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Below the axes.
    Bottom,
    /// Above the axes.
    Top,
    /// Left of the axes.
    Left,
    /// Right of the axes.
    Right,
}

impl Axes {
    /// Pixel column of `value` on the horizontal scale.
    pub fn px(&self, value: f64) -> f64 {
        self.x + self.x_scale.fraction(value) * self.width
    }

    /// Pixel row of `value` on the vertical scale.
    pub fn py(&self, value: f64) -> f64 {
        let f = self.y_scale.fraction(value);
        if self.y_down {
            self.y + f * self.height
        } else {
            self.y + (1.0 - f) * self.height
        }
    }

    /// The frame.
    pub fn frame(&self, svg: &mut Svg, theme: &Theme) {
        svg.rect(
            self.x,
            self.y,
            self.width,
            self.height,
            None,
            Some(theme.frame_stroke()),
        );
    }

    /// Start clipping to the axes (close with [`Svg::end_group`]).
    pub fn clip(&self, svg: &mut Svg) {
        svg.begin_clip(self.x, self.y, self.width, self.height);
    }

    /// Ticks and labels on `side`; returns the depth in pixels they take beyond the frame.
    pub fn ticks(
        &self,
        svg: &mut Svg,
        theme: &Theme,
        side: Side,
        major: &[(f64, String)],
        minor: &[f64],
    ) -> f64 {
        let stroke = theme.frame_stroke();
        let (long, short, gap) = (theme.px(3.5), theme.px(2.0), theme.px(2.0));
        let font = theme.font();
        let mut depth: f64 = long + gap;
        let mark = |svg: &mut Svg, value: f64, length: f64| -> Option<f64> {
            match side {
                Side::Bottom | Side::Top => {
                    let x = self.px(value);
                    if !(x >= self.x - 0.5 && x <= self.x + self.width + 0.5) {
                        return None;
                    }
                    let y0 = if side == Side::Bottom {
                        self.y + self.height
                    } else {
                        self.y
                    };
                    let y1 = if side == Side::Bottom {
                        y0 + length
                    } else {
                        y0 - length
                    };
                    svg.line(x, y0, x, y1, stroke);
                    Some(x)
                }
                Side::Left | Side::Right => {
                    let y = self.py(value);
                    if !(y >= self.y - 0.5 && y <= self.y + self.height + 0.5) {
                        return None;
                    }
                    let x0 = if side == Side::Left {
                        self.x
                    } else {
                        self.x + self.width
                    };
                    let x1 = if side == Side::Left {
                        x0 - length
                    } else {
                        x0 + length
                    };
                    svg.line(x0, y, x1, y, stroke);
                    Some(y)
                }
            }
        };
        for &value in minor {
            mark(svg, value, short);
        }
        let mut widest: f64 = 0.0;
        for (value, label) in major {
            let Some(at) = mark(svg, *value, long) else {
                continue;
            };
            match side {
                Side::Bottom => svg.text(
                    at,
                    self.y + self.height + long + gap,
                    label,
                    &TextStyle::new(font, Anchor::Middle, Baseline::Top),
                ),
                Side::Top => svg.text(
                    at,
                    self.y - long - gap,
                    label,
                    &TextStyle::new(font, Anchor::Middle, Baseline::Bottom),
                ),
                Side::Left => svg.text(
                    self.x - long - gap,
                    at,
                    label,
                    &TextStyle::new(font, Anchor::End, Baseline::Middle),
                ),
                Side::Right => svg.text(
                    self.x + self.width + long + gap,
                    at,
                    label,
                    &TextStyle::new(font, Anchor::Start, Baseline::Middle),
                ),
            }
            widest = widest.max(text_width(label, font));
        }
        depth += match side {
            Side::Bottom | Side::Top => font * 1.1,
            Side::Left | Side::Right => widest,
        };
        depth
    }

    /// An axis label on `side`, `offset` pixels beyond the frame (past the tick labels).
    pub fn label(&self, svg: &mut Svg, theme: &Theme, side: Side, offset: f64, text: &str) {
        let font = theme.label_font();
        let gap = theme.px(3.0);
        match side {
            Side::Bottom => svg.text(
                self.x + self.width / 2.0,
                self.y + self.height + offset + gap,
                text,
                &TextStyle::new(font, Anchor::Middle, Baseline::Top),
            ),
            Side::Top => svg.text(
                self.x + self.width / 2.0,
                self.y - offset - gap,
                text,
                &TextStyle::new(font, Anchor::Middle, Baseline::Bottom),
            ),
            Side::Left => svg.text(
                self.x - offset - gap,
                self.y + self.height / 2.0,
                text,
                &TextStyle::new(font, Anchor::Middle, Baseline::Bottom).rotated(90.0),
            ),
            Side::Right => svg.text(
                self.x + self.width + offset + gap,
                self.y + self.height / 2.0,
                text,
                &TextStyle::new(font, Anchor::Middle, Baseline::Top).rotated(90.0),
            ),
        }
    }
}

/// One legend entry: a line (solid or dashed) or a filled marker, and its text.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendEntry {
    /// The sample of the entry.
    pub stroke: Stroke,
    /// Draw a filled square instead of a line.
    pub filled: bool,
    /// The text.
    pub label: String,
}

/// The width and height in pixels of the [`legend`] of `entries`.
pub fn legend_size(theme: &Theme, entries: &[LegendEntry]) -> (f64, f64) {
    let font = theme.font();
    let (line, pad, row) = (theme.px(18.0), theme.px(4.0), font * 1.45);
    let widest = entries
        .iter()
        .map(|e| text_width(&e.label, font))
        .fold(0.0, f64::max);
    (
        pad * 3.0 + line + widest,
        pad * 2.0 + row * entries.len() as f64,
    )
}

/// A legend box with its top-right corner at `(right, top)`.
pub fn legend(svg: &mut Svg, theme: &Theme, right: f64, top: f64, entries: &[LegendEntry]) {
    if entries.is_empty() {
        return;
    }
    let font = theme.font();
    let line = theme.px(18.0);
    let (pad, row) = (theme.px(4.0), font * 1.45);
    let (width, height) = legend_size(theme, entries);
    let left = right - width;
    svg.rect(
        left,
        top,
        width,
        height,
        Some(Rgb::WHITE),
        Some(Stroke::solid(Rgb(204, 204, 204), theme.px(0.8))),
    );
    for (i, entry) in entries.iter().enumerate() {
        let y = top + pad + row * (i as f64 + 0.5);
        if entry.filled {
            let side = font * 0.8;
            svg.rect(
                left + pad + (line - side) / 2.0,
                y - side / 2.0,
                side,
                side,
                Some(entry.stroke.colour),
                None,
            );
        } else {
            svg.line(left + pad, y, left + pad + line, y, entry.stroke);
        }
        svg.text(
            left + pad * 2.0 + line,
            y,
            &entry.label,
            &TextStyle::new(font, Anchor::Start, Baseline::Middle),
        );
    }
}

/// A vertical colour bar in `(x, y, width, height)` with ticks and `label` on its right; returns
/// the width it takes right of `x + width`.
#[allow(clippy::too_many_arguments)]
pub fn colour_bar(
    svg: &mut Svg,
    theme: &Theme,
    (x, y, width, height): (f64, f64, f64, f64),
    map: &ColorMap,
    scale: &ColorScale,
    label: &str,
) -> Result<f64> {
    let rows = height.round().max(1.0) as usize;
    let mut image = RgbImage::filled(1, rows, Rgb::WHITE);
    for row in 0..rows {
        // Row 0 at the top holds vmax; sample each row at its centre.
        let t = 1.0 - (row as f64 + 0.5) / rows as f64;
        image.set(0, row, map.colour(t));
    }
    svg.image(x, y, width, height, &image)?;
    let axes = Axes {
        x,
        y,
        width,
        height,
        x_scale: AxisScale::Linear { min: 0.0, max: 1.0 },
        y_scale: match scale.kind {
            ScaleKind::Linear => AxisScale::Linear {
                min: scale.vmin,
                max: scale.vmax,
            },
            ScaleKind::Log => AxisScale::Log {
                min: scale.vmin,
                max: scale.vmax,
            },
        },
        y_down: false,
    };
    axes.frame(svg, theme);
    let (major, minor) = axes.y_scale.ticks(5);
    let depth = axes.ticks(svg, theme, Side::Right, &major, &minor);
    if !label.is_empty() {
        axes.label(svg, theme, Side::Right, depth, label);
    }
    Ok(depth + theme.label_font() * 1.6)
}

/// A palette for curves (matplotlib's tab10).
pub const CURVE_COLOURS: [Rgb; 10] = [
    Rgb(31, 119, 180),
    Rgb(255, 127, 14),
    Rgb(44, 160, 44),
    Rgb(214, 39, 40),
    Rgb(148, 103, 189),
    Rgb(140, 86, 75),
    Rgb(227, 119, 194),
    Rgb(127, 127, 127),
    Rgb(188, 189, 34),
    Rgb(23, 190, 207),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_ticks_are_round() {
        assert_eq!(
            linear_ticks(0.0, 10.0, 5),
            vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]
        );
        let fractional = linear_ticks(0.13, 0.9, 4);
        assert_eq!(fractional.len(), 4);
        for (got, want) in fractional.iter().zip([0.2, 0.4, 0.6, 0.8]) {
            assert!((got - want).abs() < 1e-12, "{fractional:?}");
        }
        assert_eq!(format_tick(fractional[2], 0.2), "0.6");
        assert_eq!(linear_ticks(1.05e6, 2.95e6, 4), vec![1.5e6, 2e6, 2.5e6]);
        // A step of 2 would leave only 0 inside (-1.6, 1.6): a finer one gives labels.
        let ticks = linear_ticks(-1.6, 1.6, 3);
        assert_eq!(ticks, vec![-1.0, 0.0, 1.0]);
        let step = ticks[1] - ticks[0];
        let labels: Vec<String> = ticks.iter().map(|&t| format_tick(t, step)).collect();
        assert_eq!(labels, ["-1", "0", "1"]);
        assert_eq!(format_tick(2.5, 0.5), "2.5");
        assert_eq!(format_tick(20.0, 10.0), "20");
        assert_eq!(format_tick(0.25, 0.25), "0.25");
    }

    #[test]
    fn log_ticks_label_decades() {
        let (major, minor) = log_ticks(3.0, 2000.0);
        let values: Vec<f64> = major.iter().map(|m| m.0).collect();
        assert_eq!(values, vec![10.0, 100.0, 1000.0]);
        assert_eq!(major[0].1, "10^1");
        assert!(minor.contains(&3.0) && minor.contains(&2000.0) && !minor.contains(&10.0));
        let (narrow, _) = log_ticks(1.5, 9.0);
        let values: Vec<f64> = narrow.iter().map(|m| m.0).collect();
        assert_eq!(values, vec![2.0, 5.0]);
        // issue 51: a pileup's colour bar from 0.7 to 1.8 had one tick, "1"
        let (narrow, _) = log_ticks(0.7, 1.8);
        let labels: Vec<&str> = narrow.iter().map(|m| m.1.as_str()).collect();
        assert!(labels.len() >= 3, "{labels:?}");
        assert!(narrow.iter().any(|m| m.0 == 1.0), "{labels:?}");
    }

    #[test]
    fn axes_map_values_to_pixels() {
        let axes = Axes {
            x: 10.0,
            y: 20.0,
            width: 100.0,
            height: 50.0,
            x_scale: AxisScale::Linear {
                min: 0.0,
                max: 10.0,
            },
            y_scale: AxisScale::Log {
                min: 1.0,
                max: 100.0,
            },
            y_down: false,
        };
        assert_eq!(axes.px(5.0), 60.0);
        assert_eq!(axes.py(10.0), 45.0);
        assert_eq!(axes.py(100.0), 20.0);
        assert!(axes.py(0.0).is_nan());
        assert_eq!(genomic_unit(5e6), (1e6, "Mb"));
        assert_eq!(genomic_unit(5e4), (1e3, "kb"));
    }
}
