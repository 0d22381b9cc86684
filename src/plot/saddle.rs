//! The saddle plot: mean observed/expected of each pair of track classes as a square heatmap
//! (cooltools' `saddleplot`: classes from low to high track values, log colour scale from 0.5 to
//! 2 by default), with a colour bar.

use crate::error::{Error, Result};
use crate::plot::axes::{Axes, AxisScale, Side, Theme, colour_bar};
use crate::plot::colormap::{ColorMap, ColorScale};
use crate::plot::svg::{Anchor, Baseline, Rgb, RgbImage, Svg, TextStyle};

/// What a saddle figure shows.
#[derive(Clone, Debug)]
pub struct SaddleFigure {
    /// Classes on a side.
    pub n: usize,
    /// Mean observed/expected, row-major `n x n` (NaN: no pair).
    pub values: Vec<f64>,
    /// Colour map.
    pub cmap: ColorMap,
    /// Colour scale.
    pub scale: ColorScale,
    /// Label of both axes.
    pub axis_label: String,
    /// Label of the colour bar.
    pub bar_label: String,
    /// Title (empty: none).
    pub title: String,
    /// Figure width in pixels.
    pub width_px: usize,
    /// Dots per inch.
    pub dpi: f64,
}

/// Draw the saddle as SVG.
///
/// # Examples
///
/// ```
/// use contactmap::plot::saddle::{draw_saddle, SaddleFigure};
/// use contactmap::plot::{figure_bytes, ColorMap, ColorScale, ImageFormat, ScaleKind};
///
/// let figure = SaddleFigure {
///     n: 3,
///     values: vec![2.0, 1.0, 0.5, 1.0, 1.0, 1.0, 0.5, 1.0, 2.0],
///     cmap: ColorMap::by_name("RdBu_r")?,
///     scale: ColorScale::new(ScaleKind::Log, 0.5, 2.0)?,
///     axis_label: "E1 class".into(),
///     bar_label: "observed / expected".into(),
///     title: String::new(),
///     width_px: 400,
///     dpi: 100.0,
/// };
/// let svg = draw_saddle(&figure)?;
/// let png = figure_bytes(&svg, ImageFormat::Png, figure.dpi)?;
/// assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 400);
/// // 4 values, not a square of 3 x 3: refused
/// assert!(draw_saddle(&SaddleFigure { values: vec![1.0; 4], ..figure }).is_err());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn draw_saddle(figure: &SaddleFigure) -> Result<Svg> {
    let n = figure.n;
    if n == 0 || figure.values.len() != n * n {
        return Err(Error::Argument(format!(
            "a saddle needs n x n values ({} for n = {n})",
            figure.values.len()
        )));
    }
    let theme = Theme::new(figure.dpi);
    let font = theme.font();
    let left = (theme.px(8.0) + theme.label_font() * 1.4 + theme.px(6.0) + font * 2.0).ceil();
    let top = theme.top_margin(!figure.title.is_empty());
    let bottom = (theme.px(5.5) + font * 1.1 + theme.label_font() * 1.4 + theme.px(8.0)).ceil();
    let bar_room = (theme.px(12.0) + theme.px(10.0) + font * 3.0 + theme.label_font() * 1.6).ceil();
    let side = figure.width_px as f64 - left - bar_room - theme.px(8.0);
    if side < theme.px(60.0) {
        return Err(Error::Argument(format!(
            "the figure is too narrow for a saddle ({} pixels)",
            figure.width_px
        )));
    }
    let side = side.round();
    let height = (top + side + bottom).round() as usize;
    let mut svg = Svg::new(figure.width_px, height, figure.dpi);
    let mut image = RgbImage::filled(n, n, Rgb(255, 255, 255));
    for r in 0..n {
        for c in 0..n {
            if let Some(t) = figure.scale.position(figure.values[r * n + c]) {
                image.set(c, r, figure.cmap.colour(t));
            }
        }
    }
    let axes = Axes {
        x: left,
        y: top,
        width: side,
        height: side,
        x_scale: AxisScale::Linear {
            min: 0.5,
            max: n as f64 + 0.5,
        },
        y_scale: AxisScale::Linear {
            min: 0.5,
            max: n as f64 + 0.5,
        },
        y_down: true,
    };
    svg.image(axes.x, axes.y, side, side, &image)?;
    axes.frame(&mut svg, &theme);
    let (major, minor) = axes.x_scale.ticks(6);
    let depth = axes.ticks(&mut svg, &theme, Side::Bottom, &major, &minor);
    axes.label(&mut svg, &theme, Side::Bottom, depth, &figure.axis_label);
    let (major, minor) = axes.y_scale.ticks(6);
    let depth = axes.ticks(&mut svg, &theme, Side::Left, &major, &minor);
    axes.label(&mut svg, &theme, Side::Left, depth, &figure.axis_label);
    if !figure.title.is_empty() {
        svg.text(
            axes.x + side / 2.0,
            axes.y - theme.px(6.0),
            &figure.title,
            &TextStyle::new(theme.label_font(), Anchor::Middle, Baseline::Bottom),
        );
    }
    colour_bar(
        &mut svg,
        &theme,
        (left + side + theme.px(12.0), top, theme.px(10.0), side),
        &figure.cmap,
        &figure.scale,
        &figure.bar_label,
    )?;
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::ScaleKind;

    #[test]
    fn draws_one_cell_per_class_pair() {
        let n = 4;
        let values: Vec<f64> = (0..n * n).map(|k| 0.5 + k as f64 / 10.0).collect();
        let figure = SaddleFigure {
            n,
            values,
            cmap: ColorMap::by_name("RdBu_r").unwrap(),
            scale: ColorScale::new(ScaleKind::Log, 0.5, 2.0).unwrap(),
            axis_label: "E1 class".into(),
            bar_label: "obs/exp".into(),
            title: "t".into(),
            width_px: 500,
            dpi: 100.0,
        };
        let svg = draw_saddle(&figure).unwrap().finish();
        assert!(svg.contains("<image") && svg.contains("E1 class") && svg.contains(">t<"));
        let short = SaddleFigure {
            values: vec![1.0; 3],
            ..figure
        };
        assert!(draw_saddle(&short).is_err());
    }
}
