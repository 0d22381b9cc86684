//! The figures of a comparison between conditions (`contactmap diff`): the MA plot (each
//! feature's change against its mean level) and the volcano plot (its change against
//! `-log10 p`), features coloured by their call: higher in B, lower in B, another change (a
//! shifted boundary), unchanged. Drawn as [`super::curves`] draws lines, one point per feature.

use super::curves::{CurveFigure, Panel, Scale, Series};
use super::svg::{Rgb, Stroke};

/// What the comparison called a feature.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiffClass {
    /// Significantly higher in B (a loop up, a boundary gained or stronger, a bin B->A).
    Up,
    /// Significantly lower in B.
    Down,
    /// Another significant change (a boundary shifted).
    Other,
    /// Not significant.
    Unchanged,
}

/// One feature: its coordinates and its call.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffPoint {
    /// Horizontal coordinate.
    pub x: f64,
    /// Vertical coordinate.
    pub y: f64,
    /// The call.
    pub class: DiffClass,
}

/// A figure's axes and size.
#[derive(Clone, Debug, PartialEq)]
pub struct DiffFigure {
    /// Title (empty: none).
    pub title: String,
    /// Horizontal axis label.
    pub x_label: String,
    /// Horizontal scale (log for a mean count).
    pub x_scale: Scale,
    /// Vertical axis label.
    pub y_label: String,
    /// A dashed line at y = 0 (the MA plot's "no change").
    pub zero_line: bool,
    /// Legend names of up, down, other and unchanged.
    pub names: [String; 4],
    /// Width in pixels.
    pub width_px: usize,
    /// Height in pixels (`None`: the default proportion).
    pub height_px: Option<usize>,
    /// Dots per inch.
    pub dpi: f64,
}

/// The classes' colours: red up, blue down, orange other, grey unchanged.
const COLOURS: [Rgb; 4] = [
    Rgb(214, 39, 40),
    Rgb(31, 119, 180),
    Rgb(255, 127, 14),
    Rgb(160, 160, 160),
];

/// The figure of `points`: unchanged features first (under the others), each class one colour
/// with its count in the legend; points with a non-finite coordinate are left out.
///
/// # Examples
///
/// ```
/// use contactmap::plot::curves::{Scale, draw_curves};
/// use contactmap::plot::diff::{DiffClass, DiffFigure, DiffPoint, diff_figure};
///
/// let points = [
///     DiffPoint { x: 10.0, y: 2.0, class: DiffClass::Up },
///     DiffPoint { x: 50.0, y: 0.1, class: DiffClass::Unchanged },
///     DiffPoint { x: 80.0, y: -1.5, class: DiffClass::Down },
/// ];
/// let options = DiffFigure {
///     title: String::new(),
///     x_label: "mean of normalised counts".into(),
///     x_scale: Scale::Log,
///     y_label: "log2 fold change".into(),
///     zero_line: true,
///     names: ["up".into(), "down".into(), "other".into(), "not changed".into()],
///     width_px: 500,
///     height_px: None,
///     dpi: 100.0,
/// };
/// let figure = diff_figure(&points, &options);
/// let svg = draw_curves(&figure)?.finish();
/// assert!(svg.contains("up (1)") && svg.contains("not changed (1)"));
/// assert!(!svg.contains("other ("), "an empty class has no legend entry");
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn diff_figure(points: &[DiffPoint], options: &DiffFigure) -> CurveFigure {
    let radius = 2.0 * options.dpi / 100.0;
    let usable = |p: &&DiffPoint| {
        p.x.is_finite() && p.y.is_finite() && (options.x_scale == Scale::Linear || p.x > 0.0)
    };
    let order = [
        (DiffClass::Unchanged, 3),
        (DiffClass::Other, 2),
        (DiffClass::Down, 1),
        (DiffClass::Up, 0),
    ];
    let mut series = Vec::new();
    let (mut x_min, mut x_max) = (f64::INFINITY, f64::NEG_INFINITY);
    for (class, k) in order {
        let mut drawn = Vec::new();
        for p in points.iter().filter(usable).filter(|p| p.class == class) {
            // a break between points: each is drawn as a dot, never joined
            if !drawn.is_empty() {
                drawn.push((f64::NAN, f64::NAN));
            }
            drawn.push((p.x, p.y));
            x_min = x_min.min(p.x);
            x_max = x_max.max(p.x);
        }
        let n = drawn.iter().filter(|p| p.0.is_finite()).count();
        if n > 0 {
            series.push(Series {
                label: Some(format!("{} ({n})", options.names[k])),
                points: drawn,
                stroke: Stroke::solid(COLOURS[k], radius),
            });
        }
    }
    if options.zero_line && x_min.is_finite() {
        series.insert(
            0,
            Series {
                label: None,
                points: vec![(x_min, 0.0), (x_max, 0.0)],
                stroke: Stroke::solid(Rgb(80, 80, 80), options.dpi / 100.0).dashed(4.0),
            },
        );
    }
    CurveFigure {
        title: options.title.clone(),
        x_label: options.x_label.clone(),
        x_scale: options.x_scale,
        x_in_bp: false,
        panels: vec![Panel {
            y_label: options.y_label.clone(),
            y_scale: Scale::Linear,
            series,
            weight: 2.4,
            legend: true,
            min_span: 0.0,
        }],
        width_px: options.width_px,
        height_px: options.height_px,
        dpi: options.dpi,
    }
}
