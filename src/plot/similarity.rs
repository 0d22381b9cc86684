//! A clustered similarity heatmap: an `n x n` matrix of sample-to-sample values (HiCRep SCCs)
//! with the samples in the order of a dendrogram drawn above it (seaborn `clustermap`'s
//! layout), sample names on the left and below, each cell's value written in it when the cells
//! are large enough, and a colour bar.

use crate::compare::cluster::Dendrogram;
use crate::error::{Error, Result};
use crate::plot::axes::{Theme, colour_bar};
use crate::plot::colormap::{ColorMap, ColorScale};
use crate::plot::svg::{Anchor, Baseline, Rgb, RgbImage, Stroke, Svg, TextStyle, text_width};

/// What a similarity figure shows.
#[derive(Clone, Debug)]
pub struct SimilarityFigure {
    /// Sample names, in the matrix's order.
    pub names: Vec<String>,
    /// Row-major `n x n` values (NaN: drawn in `nan`).
    pub values: Vec<f64>,
    /// The tree drawn above the matrix, which orders the samples; `None`: the given order.
    pub dendrogram: Option<Dendrogram>,
    /// Colour map.
    pub cmap: ColorMap,
    /// Colour scale.
    pub scale: ColorScale,
    /// Colour of NaN cells.
    pub nan: Rgb,
    /// Label of the colour bar.
    pub bar_label: String,
    /// Title (empty: none).
    pub title: String,
    /// Figure width in pixels.
    pub width_px: usize,
    /// Dots per inch.
    pub dpi: f64,
}

/// Draw the figure as SVG.
///
/// # Examples
///
/// ```
/// use contactmap::compare::cluster::Dendrogram;
/// use contactmap::plot::similarity::{draw_similarity, SimilarityFigure};
/// use contactmap::plot::{figure_bytes, ColorMap, ColorScale, ImageFormat, Rgb, ScaleKind};
///
/// let scc = vec![1.0, 0.7, 0.95, 0.7, 1.0, 0.72, 0.95, 0.72, 1.0];
/// let distances: Vec<f64> = scc.iter().map(|s| 1.0 - s).collect();
/// let figure = SimilarityFigure {
///     names: vec!["rep1".into(), "other".into(), "rep2".into()],
///     values: scc,
///     dendrogram: Some(Dendrogram::average_linkage(&distances, 3)?),
///     cmap: ColorMap::by_name("viridis")?,
///     scale: ColorScale::new(ScaleKind::Linear, 0.7, 1.0)?,
///     nan: Rgb(211, 211, 211),
///     bar_label: "SCC".into(),
///     title: String::new(),
///     width_px: 500,
///     dpi: 100.0,
/// };
/// let svg = draw_similarity(&figure)?;
/// let text = svg.finish();
/// assert!(text.contains(">rep1<") && text.contains(">0.950<"));
/// let png = figure_bytes(&svg, ImageFormat::Png, figure.dpi)?;
/// assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 500);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn draw_similarity(figure: &SimilarityFigure) -> Result<Svg> {
    let n = figure.names.len();
    if n == 0 || figure.values.len() != n * n {
        return Err(Error::Argument(format!(
            "a similarity matrix of {n} samples needs {} values, not {}",
            n * n,
            figure.values.len()
        )));
    }
    let order: Vec<usize> = match &figure.dendrogram {
        Some(tree) if tree.n == n => tree.leaf_order(),
        Some(tree) => {
            return Err(Error::Argument(format!(
                "a dendrogram of {} leaves for {n} samples",
                tree.n
            )));
        }
        None => (0..n).collect(),
    };
    let theme = Theme::new(figure.dpi);
    let font = theme.font();
    let name_width = figure
        .names
        .iter()
        .map(|name| text_width(name, font))
        .fold(0.0, f64::max);
    let left = (theme.px(8.0) + name_width + theme.px(6.0)).ceil();
    let bottom = (theme.px(6.0) + name_width + theme.px(8.0)).ceil();
    let bar_room = (theme.px(14.0) + theme.px(10.0) + font * 3.0 + theme.label_font() * 1.6).ceil();
    let side = (figure.width_px as f64 - left - bar_room - theme.px(8.0)).round();
    if side < theme.px(60.0) {
        return Err(Error::Argument(format!(
            "the figure is too narrow for {n} samples ({} pixels wide; names take {name_width:.0})",
            figure.width_px
        )));
    }
    let tree_height = if figure.dendrogram.is_some() && n > 1 {
        (side * 0.2).round()
    } else {
        0.0
    };
    let top = theme.top_margin(!figure.title.is_empty()) + tree_height;
    let height = (top + side + bottom).round() as usize;
    let mut svg = Svg::new(figure.width_px, height, figure.dpi);
    let cell = side / n as f64;

    let mut image = RgbImage::filled(n, n, figure.nan);
    for (r, &row) in order.iter().enumerate() {
        for (c, &col) in order.iter().enumerate() {
            if let Some(t) = figure.scale.position(figure.values[row * n + col]) {
                image.set(c, r, figure.cmap.colour(t));
            }
        }
    }
    svg.image(left, top, side, side, &image)?;
    svg.rect(left, top, side, side, None, Some(theme.frame_stroke()));

    // Values in the cells, when they fit.
    let value_font = (cell * 0.28).min(font);
    if value_font >= theme.px(5.0) {
        for (r, &row) in order.iter().enumerate() {
            for (c, &col) in order.iter().enumerate() {
                let value = figure.values[row * n + col];
                let colour = match figure.scale.position(value) {
                    Some(t) => figure.cmap.colour(t),
                    None => figure.nan,
                };
                let mut style = TextStyle::new(value_font, Anchor::Middle, Baseline::Middle);
                style.colour = readable_on(colour);
                let text = if value.is_nan() {
                    "nan".to_string()
                } else {
                    format!("{value:.3}")
                };
                svg.text(
                    left + (c as f64 + 0.5) * cell,
                    top + (r as f64 + 0.5) * cell,
                    &text,
                    &style,
                );
            }
        }
    }

    // Names: left of the rows, under the columns (rotated).
    for (k, &sample) in order.iter().enumerate() {
        let centre = (k as f64 + 0.5) * cell;
        svg.text(
            left - theme.px(6.0),
            top + centre,
            &figure.names[sample],
            &TextStyle::new(font, Anchor::End, Baseline::Middle),
        );
        svg.text(
            left + centre,
            top + side + theme.px(6.0),
            &figure.names[sample],
            &TextStyle::new(font, Anchor::End, Baseline::Middle).rotated(90.0),
        );
    }

    if let Some(tree) = figure.dendrogram.as_ref().filter(|_| n > 1) {
        draw_tree(&mut svg, &theme, tree, (left, top, cell, tree_height));
    }
    if !figure.title.is_empty() {
        svg.text(
            left + side / 2.0,
            theme.top_margin(true) - theme.px(6.0),
            &figure.title,
            &TextStyle::new(theme.label_font(), Anchor::Middle, Baseline::Bottom),
        );
    }
    colour_bar(
        &mut svg,
        &theme,
        (left + side + theme.px(14.0), top, theme.px(10.0), side),
        &figure.cmap,
        &figure.scale,
        &figure.bar_label,
    )?;
    Ok(svg)
}

/// The dendrogram above the matrix: `(left, top, cell, height)`, the leaves at the columns'
/// centres along the bottom edge `top`, the highest merge at `top - height`.
fn draw_tree(
    svg: &mut Svg,
    theme: &Theme,
    tree: &Dendrogram,
    (left, top, cell, height): (f64, f64, f64, f64),
) {
    let at = tree.positions();
    let highest = tree.merges.iter().map(|m| m.distance).fold(0.0, f64::max);
    let y = |distance: f64| {
        if highest > 0.0 {
            top - theme.px(3.0) - (height - theme.px(6.0)) * distance / highest
        } else {
            top - theme.px(3.0)
        }
    };
    let x = |slot: f64| left + (slot + 0.5) * cell;
    let stroke = Stroke::solid(Rgb::BLACK, theme.px(0.8));
    for (k, merge) in tree.merges.iter().enumerate() {
        let (_, h) = at[tree.n + k];
        let (a, b) = (at[merge.left], at[merge.right]);
        svg.polyline(
            &[
                (x(a.0), y(a.1)),
                (x(a.0), y(h)),
                (x(b.0), y(h)),
                (x(b.0), y(b.1)),
            ],
            stroke,
        );
    }
}

/// Black or white, whichever reads better on `background`.
fn readable_on(background: Rgb) -> Rgb {
    let Rgb(r, g, b) = background;
    let luminance = 0.299 * r as f64 + 0.587 * g as f64 + 0.114 * b as f64;
    if luminance > 140.0 {
        Rgb::BLACK
    } else {
        Rgb::WHITE
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::ScaleKind;

    fn figure(n: usize, width_px: usize) -> SimilarityFigure {
        let values: Vec<f64> = (0..n * n)
            .map(|k| {
                if k / n == k % n {
                    1.0
                } else {
                    0.8 + 0.01 * ((k / n + k % n) % 7) as f64
                }
            })
            .collect();
        let distances: Vec<f64> = values.iter().map(|v| 1.0 - v).collect();
        SimilarityFigure {
            names: (0..n).map(|k| format!("sample{k}")).collect(),
            dendrogram: Some(Dendrogram::average_linkage(&distances, n).unwrap()),
            values,
            cmap: ColorMap::by_name("viridis").unwrap(),
            scale: ColorScale::new(ScaleKind::Linear, 0.8, 1.0).unwrap(),
            nan: Rgb(211, 211, 211),
            bar_label: "SCC".into(),
            title: "t".into(),
            width_px,
            dpi: 100.0,
        }
    }

    #[test]
    fn rows_follow_the_dendrogram_and_values_appear_only_when_they_fit() {
        let small = figure(4, 600);
        let order = small.dendrogram.as_ref().unwrap().leaf_order();
        let text = draw_similarity(&small).unwrap().finish();
        // the row names are written top to bottom in the leaves' order
        let positions: Vec<usize> = order
            .iter()
            .map(|&k| text.find(&format!(">sample{k}<")).unwrap())
            .collect();
        assert!(positions.windows(2).all(|w| w[0] < w[1]), "{positions:?}");
        assert!(text.contains(">1.000<") && text.contains("<polyline"));
        // 40 samples in 600 pixels: no values in the cells
        let many = draw_similarity(&figure(40, 600)).unwrap().finish();
        assert!(!many.contains(">1.000<"));
        // a dendrogram of another size, too few values, a figure too narrow: refused
        let mut wrong = figure(4, 600);
        wrong.dendrogram = figure(3, 600).dendrogram;
        assert!(draw_similarity(&wrong).is_err());
        let mut short = figure(4, 600);
        short.values.pop();
        assert!(draw_similarity(&short).is_err());
        assert!(draw_similarity(&figure(4, 120)).is_err());
    }

    #[test]
    fn text_is_readable_on_dark_and_light_cells() {
        assert_eq!(readable_on(Rgb(0, 0, 0)), Rgb::WHITE);
        assert_eq!(readable_on(Rgb(253, 231, 37)), Rgb::BLACK);
    }
}
