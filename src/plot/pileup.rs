//! Pileups as plotpup.py (coolpuppy 1.1.0) draws them: one square heatmap per group, facets in
//! a grid, a log colour scale centred at 1 (coolwarm), the centre score written in the top left
//! corner of each, one colour bar for all.

use crate::error::{Error, Result};
use crate::plot::axes::{Theme, colour_bar};
use crate::plot::colormap::{ColorMap, ColorScale};
use crate::plot::svg::{Anchor, Baseline, Rgb, RgbImage, Svg, TextStyle};

/// One facet: a pileup grid and what is written on it.
#[derive(Clone, Debug, PartialEq)]
pub struct PileupPanel {
    /// Above the panel (the group).
    pub title: String,
    /// Side of the grid.
    pub n: usize,
    /// Row-major `n x n` values (NaN: grey).
    pub values: Vec<f64>,
    /// Written in the top left corner (the score, formatted), if any.
    pub corner: Option<String>,
}

/// What a pileup figure shows.
#[derive(Clone, Debug)]
pub struct PileupFigure {
    /// The facets, in reading order.
    pub panels: Vec<PileupPanel>,
    /// Facets per row.
    pub columns: usize,
    /// Colour map.
    pub cmap: ColorMap,
    /// Colour scale.
    pub scale: ColorScale,
    /// Label of the colour bar.
    pub bar_label: String,
    /// Title (empty: none).
    pub title: String,
    /// Figure width in pixels.
    pub width_px: usize,
    /// Dots per inch.
    pub dpi: f64,
}

/// The symmetric log limits plotpup uses by default: `1 / m` to `m`, `m` the largest of the
/// values and their inverses (finite, positive values only); 1 to 1 widened when flat.
pub fn centred_limits<'a>(values: impl IntoIterator<Item = &'a f64>) -> (f64, f64) {
    let m = values
        .into_iter()
        .filter(|v| v.is_finite() && **v > 0.0)
        .map(|v| v.ln().abs())
        .fold(0.0f64, f64::max);
    let m = if m > 0.0 { m.exp() } else { 1.1 };
    (1.0 / m, m)
}

/// Draw the pileups as SVG.
///
/// # Examples
///
/// ```
/// use contactmap::plot::pileup::{draw_pileups, PileupFigure, PileupPanel};
/// use contactmap::plot::{figure_bytes, ColorMap, ColorScale, ImageFormat, ScaleKind};
///
/// let panel = |title: &str, centre: f64| PileupPanel {
///     title: title.into(),
///     n: 3,
///     values: vec![1.0, 1.2, 1.0, 0.9, centre, 1.1, 1.0, 0.8, 1.0],
///     corner: Some(format!("{centre:.2}")),
/// };
/// let figure = PileupFigure {
///     panels: vec![panel("near", 3.0), panel("far", 1.5)],
///     columns: 2,
///     cmap: ColorMap::by_name("coolwarm")?,
///     scale: ColorScale::new(ScaleKind::Log, 1.0 / 3.0, 3.0)?,
///     bar_label: "observed / expected".into(),
///     title: String::new(),
///     width_px: 600,
///     dpi: 100.0,
/// };
/// let svg = draw_pileups(&figure)?;
/// let png = figure_bytes(&svg, ImageFormat::Png, figure.dpi)?;
/// assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 600);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn draw_pileups(figure: &PileupFigure) -> Result<Svg> {
    let count = figure.panels.len();
    if count == 0 {
        return Err(Error::Argument("no pileup to draw".into()));
    }
    for panel in &figure.panels {
        if panel.n == 0 || panel.values.len() != panel.n * panel.n {
            return Err(Error::Argument(format!(
                "pileup '{}': {} values for a {2} x {2} grid",
                panel.title,
                panel.values.len(),
                panel.n
            )));
        }
    }
    let columns = figure.columns.clamp(1, count);
    let rows = count.div_ceil(columns);
    let theme = Theme::new(figure.dpi);
    let font = theme.font();
    let margin = theme.px(8.0);
    let gap = theme.px(8.0);
    let panel_title = (font * 1.4).ceil();
    let top = theme.top_margin(!figure.title.is_empty());
    let bar_room = (theme.px(12.0) + theme.px(10.0) + font * 3.0 + theme.label_font() * 1.6).ceil();
    let room = figure.width_px as f64 - 2.0 * margin - bar_room - (columns - 1) as f64 * gap;
    let side = (room / columns as f64).floor();
    if side < theme.px(40.0) {
        return Err(Error::Argument(format!(
            "the figure is too narrow for {columns} pileups side by side ({} pixels)",
            figure.width_px
        )));
    }
    let height = top + rows as f64 * (panel_title + side) + (rows - 1) as f64 * gap + margin;
    let mut svg = Svg::new(figure.width_px, height.ceil() as usize, figure.dpi);
    let nan = Rgb(211, 211, 211);
    let corner_style = TextStyle::new(font, Anchor::Start, Baseline::Top);
    let title_style = TextStyle::new(font, Anchor::Middle, Baseline::Bottom);
    for (k, panel) in figure.panels.iter().enumerate() {
        let (r, c) = (k / columns, k % columns);
        let x = margin + c as f64 * (side + gap);
        let y = top + r as f64 * (panel_title + side + gap) + panel_title;
        let n = panel.n;
        let mut image = RgbImage::filled(n, n, nan);
        for i in 0..n {
            for j in 0..n {
                if let Some(t) = figure.scale.position(panel.values[i * n + j]) {
                    image.set(j, i, figure.cmap.colour(t));
                }
            }
        }
        svg.image(x, y, side, side, &image)?;
        svg.rect(x, y, side, side, None, Some(theme.frame_stroke()));
        if !panel.title.is_empty() {
            svg.text(
                x + side / 2.0,
                y - theme.px(2.0),
                &panel.title,
                &title_style,
            );
        }
        if let Some(corner) = &panel.corner {
            svg.text(x + theme.px(3.0), y + theme.px(3.0), corner, &corner_style);
        }
    }
    if !figure.title.is_empty() {
        let grid_width = columns as f64 * side + (columns - 1) as f64 * gap;
        svg.text(
            margin + grid_width / 2.0,
            top - theme.px(6.0),
            &figure.title,
            &TextStyle::new(theme.label_font(), Anchor::Middle, Baseline::Bottom),
        );
    }
    let bar_x = margin + columns as f64 * side + (columns - 1) as f64 * gap + theme.px(12.0);
    let bar_top = top + panel_title;
    let bar_height = (side * rows as f64 + (rows - 1) as f64 * (gap + panel_title)).min(side * 1.5);
    colour_bar(
        &mut svg,
        &theme,
        (bar_x, bar_top, theme.px(10.0), bar_height),
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
    fn limits_are_centred_at_one_in_log() {
        let (lo, hi) = centred_limits(&[0.5, 1.0, 1.5, f64::NAN, 0.0, -1.0]);
        assert!((lo - 0.5).abs() < 1e-12 && (hi - 2.0).abs() < 1e-12);
        let (lo, hi) = centred_limits(&[1.0, 1.0]);
        assert!(lo < 1.0 && hi > 1.0);
    }

    #[test]
    fn one_panel_per_group_and_bad_grids_refused() {
        let panel = |n: usize| PileupPanel {
            title: "g".into(),
            n,
            values: vec![1.0; 9],
            corner: None,
        };
        let figure = PileupFigure {
            panels: vec![panel(3), panel(3), panel(3)],
            columns: 2,
            cmap: ColorMap::by_name("coolwarm").unwrap(),
            scale: ColorScale::new(ScaleKind::Log, 0.5, 2.0).unwrap(),
            bar_label: "x".into(),
            title: "t".into(),
            width_px: 500,
            dpi: 100.0,
        };
        let svg = draw_pileups(&figure).unwrap().finish();
        assert_eq!(
            svg.matches("<image").count(),
            3 + 1,
            "three panels and the bar"
        );
        let bad = PileupFigure {
            panels: vec![panel(4)],
            ..figure.clone()
        };
        assert!(draw_pileups(&bad).is_err());
        let narrow = PileupFigure {
            width_px: 100,
            ..figure
        };
        assert!(draw_pileups(&narrow).is_err());
    }
}
