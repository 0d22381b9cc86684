//! The figure model: an SVG document written element by element.
//!
//! Every figure is built as SVG; PNG output rasterises that SVG ([`crate::plot::render`]), so
//! the two formats always show the same picture. User units are output pixels at the figure's
//! dpi (`width="W in"` with a `viewBox` in pixels), so a raster placed at integer coordinates
//! with its pixel size lands pixel for pixel in the PNG. Heatmaps are embedded as PNG rasters
//! (`<image href="data:image/png;base64,...">`, as matplotlib's SVG backend does), drawn with
//! `image-rendering: pixelated` so viewers do not smooth them.

use std::fmt::Write as _;

use base64::Engine as _;

use crate::error::{Error, Result};

/// An RGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    /// Black.
    pub const BLACK: Rgb = Rgb(0, 0, 0);
    /// White.
    pub const WHITE: Rgb = Rgb(255, 255, 255);

    /// Parse `#rrggbb`, `#rgb` or one of a few names (black, white, grey/gray, lightgrey, red,
    /// blue, green, orange, none is not a colour).
    pub fn parse(text: &str) -> Option<Rgb> {
        let t = text.trim().to_ascii_lowercase();
        let named = match t.as_str() {
            "black" => Some(Rgb(0, 0, 0)),
            "white" => Some(Rgb(255, 255, 255)),
            "grey" | "gray" => Some(Rgb(128, 128, 128)),
            "lightgrey" | "lightgray" => Some(Rgb(211, 211, 211)),
            "darkgrey" | "darkgray" => Some(Rgb(169, 169, 169)),
            "red" => Some(Rgb(255, 0, 0)),
            "blue" => Some(Rgb(0, 0, 255)),
            "green" => Some(Rgb(0, 128, 0)),
            "orange" => Some(Rgb(255, 165, 0)),
            "cyan" => Some(Rgb(0, 255, 255)),
            "magenta" => Some(Rgb(255, 0, 255)),
            _ => None,
        };
        if named.is_some() {
            return named;
        }
        let hex = t.strip_prefix('#')?;
        let digit = |i: usize, n: usize| u8::from_str_radix(hex.get(i..i + n)?, 16).ok();
        match hex.len() {
            6 => Some(Rgb(digit(0, 2)?, digit(2, 2)?, digit(4, 2)?)),
            3 => Some(Rgb(digit(0, 1)? * 17, digit(1, 1)? * 17, digit(2, 1)? * 17)),
            _ => None,
        }
    }

    /// `#rrggbb`.
    pub fn hex(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }
}

/// An RGB raster, row-major from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// `3 * width * height` bytes.
    pub data: Vec<u8>,
}

impl RgbImage {
    /// A raster filled with `colour`.
    pub fn filled(width: usize, height: usize, colour: Rgb) -> RgbImage {
        let mut data = Vec::with_capacity(3 * width * height);
        for _ in 0..width * height {
            data.extend_from_slice(&[colour.0, colour.1, colour.2]);
        }
        RgbImage {
            width,
            height,
            data,
        }
    }

    /// Set pixel `(x, y)`.
    pub fn set(&mut self, x: usize, y: usize, colour: Rgb) {
        let at = 3 * (y * self.width + x);
        self.data[at..at + 3].copy_from_slice(&[colour.0, colour.1, colour.2]);
    }

    /// Pixel `(x, y)`.
    pub fn get(&self, x: usize, y: usize) -> Rgb {
        let at = 3 * (y * self.width + x);
        Rgb(self.data[at], self.data[at + 1], self.data[at + 2])
    }

    /// Encode as PNG (fast compression: these rasters are re-decoded at once).
    pub fn encode_png(&self) -> Result<Vec<u8>> {
        encode_png_rgb(self.width, self.height, &self.data)
    }
}

/// Encode an RGB buffer as PNG.
pub fn encode_png_rgb(width: usize, height: usize, data: &[u8]) -> Result<Vec<u8>> {
    let invalid = |e: png::EncodingError| Error::Argument(format!("PNG encoding: {e}"));
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, width as u32, height as u32);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Fast);
        let mut writer = encoder.write_header().map_err(invalid)?;
        writer.write_image_data(data).map_err(invalid)?;
        writer.finish().map_err(invalid)?;
    }
    Ok(bytes)
}

/// Stroke of lines and outlines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stroke {
    /// Colour.
    pub colour: Rgb,
    /// Width in pixels.
    pub width: f64,
    /// Dash length in pixels (`None`: solid).
    pub dash: Option<f64>,
    /// Opacity, 0..1.
    pub opacity: f64,
}

impl Stroke {
    /// A solid stroke.
    pub fn solid(colour: Rgb, width: f64) -> Stroke {
        Stroke {
            colour,
            width,
            dash: None,
            opacity: 1.0,
        }
    }

    /// The same stroke dashed.
    pub fn dashed(self, dash: f64) -> Stroke {
        Stroke {
            dash: Some(dash),
            ..self
        }
    }

    fn attributes(&self, out: &mut String) {
        let _ = write!(
            out,
            r#" stroke="{}" stroke-width="{}""#,
            self.colour.hex(),
            num(self.width)
        );
        if let Some(dash) = self.dash {
            let _ = write!(out, r#" stroke-dasharray="{} {}""#, num(dash), num(dash));
        }
        if self.opacity < 1.0 {
            let _ = write!(out, r#" stroke-opacity="{}""#, num(self.opacity));
        }
    }
}

/// Horizontal anchor of a text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    /// The text starts at the point.
    Start,
    /// The text is centred on the point.
    Middle,
    /// The text ends at the point.
    End,
}

/// Vertical alignment of a text relative to its point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Baseline {
    /// The point is on the text's top (the text hangs below it).
    Top,
    /// The point is at the text's middle.
    Middle,
    /// The point is on the baseline.
    Bottom,
}

/// Style of a text.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextStyle {
    /// Font size in pixels.
    pub size: f64,
    /// Horizontal anchor.
    pub anchor: Anchor,
    /// Vertical alignment.
    pub baseline: Baseline,
    /// Rotation in degrees (counter-clockwise positive, as axis labels), about the point.
    pub rotate: f64,
    /// Colour.
    pub colour: Rgb,
    /// Bold.
    pub bold: bool,
}

impl TextStyle {
    /// A black, unrotated text of `size` pixels.
    pub fn new(size: f64, anchor: Anchor, baseline: Baseline) -> TextStyle {
        TextStyle {
            size,
            anchor,
            baseline,
            rotate: 0.0,
            colour: Rgb::BLACK,
            bold: false,
        }
    }

    /// The same style rotated by `degrees`.
    pub fn rotated(self, degrees: f64) -> TextStyle {
        TextStyle {
            rotate: degrees,
            ..self
        }
    }

    /// The same style in bold.
    pub fn bold(self) -> TextStyle {
        TextStyle { bold: true, ..self }
    }
}

/// Font family written in the SVG: the font PNG rendering uses, then common fallbacks.
pub const FONT_FAMILY: &str = "DejaVu Sans, Bitstream Vera Sans, Arial, Helvetica, sans-serif";

/// Approximate advance width of a text of `size` pixels in DejaVu Sans (0.62 em per character on
/// average for digits and lower case), for layout margins.
pub fn text_width(text: &str, size: f64) -> f64 {
    text.chars()
        .map(|c| match c {
            'i' | 'l' | '.' | ',' | ':' | '\'' | '|' | ' ' => 0.32,
            'm' | 'w' | 'M' | 'W' => 0.9,
            c if c.is_ascii_uppercase() => 0.7,
            _ => 0.62,
        })
        .sum::<f64>()
        * size
}

/// An SVG document under construction.
#[derive(Clone, Debug)]
pub struct Svg {
    width_px: usize,
    height_px: usize,
    dpi: f64,
    body: String,
    next_id: usize,
}

/// A number for an attribute: at most 2 decimals, no trailing zeros.
fn num(value: f64) -> String {
    let rounded = (value * 100.0).round() / 100.0;
    if rounded == rounded.trunc() {
        format!("{}", rounded as i64)
    } else {
        let mut text = format!("{rounded:.2}");
        while text.ends_with('0') {
            text.pop();
        }
        text
    }
}

/// Escape text content and attribute values.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

impl Svg {
    /// An empty white figure of `width_px x height_px` pixels meant for `dpi` dots per inch.
    pub fn new(width_px: usize, height_px: usize, dpi: f64) -> Svg {
        let mut svg = Svg {
            width_px,
            height_px,
            dpi,
            body: String::with_capacity(1 << 16),
            next_id: 0,
        };
        svg.rect(
            0.0,
            0.0,
            width_px as f64,
            height_px as f64,
            Some(Rgb::WHITE),
            None,
        );
        svg
    }

    /// Width in pixels.
    pub fn width_px(&self) -> usize {
        self.width_px
    }

    /// Height in pixels.
    pub fn height_px(&self) -> usize {
        self.height_px
    }

    /// A rectangle, filled and / or outlined.
    pub fn rect(
        &mut self,
        x: f64,
        y: f64,
        w: f64,
        h: f64,
        fill: Option<Rgb>,
        stroke: Option<Stroke>,
    ) {
        let _ = write!(
            self.body,
            r#"<rect x="{}" y="{}" width="{}" height="{}""#,
            num(x),
            num(y),
            num(w.max(0.0)),
            num(h.max(0.0))
        );
        self.paint(fill, stroke);
        self.body.push_str("/>\n");
    }

    fn paint(&mut self, fill: Option<Rgb>, stroke: Option<Stroke>) {
        match fill {
            Some(colour) => {
                let _ = write!(self.body, r#" fill="{}""#, colour.hex());
            }
            None => self.body.push_str(r#" fill="none""#),
        }
        if let Some(stroke) = stroke {
            stroke.attributes(&mut self.body);
        }
    }

    /// A straight line.
    pub fn line(&mut self, x1: f64, y1: f64, x2: f64, y2: f64, stroke: Stroke) {
        let _ = write!(
            self.body,
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}""#,
            num(x1),
            num(y1),
            num(x2),
            num(y2)
        );
        stroke.attributes(&mut self.body);
        self.body.push_str(r#" stroke-linecap="butt"/>"#);
        self.body.push('\n');
    }

    /// A polyline through `points`; a non-finite point breaks it into separate pieces.
    pub fn polyline(&mut self, points: &[(f64, f64)], stroke: Stroke) {
        for piece in points.split(|(x, y)| !(x.is_finite() && y.is_finite())) {
            if piece.len() < 2 {
                continue;
            }
            self.body.push_str(r#"<polyline points=""#);
            for (i, (x, y)) in piece.iter().enumerate() {
                if i > 0 {
                    self.body.push(' ');
                }
                let _ = write!(self.body, "{},{}", num(*x), num(*y));
            }
            self.body.push('"');
            self.paint(None, Some(stroke));
            self.body.push_str(r#" stroke-linejoin="round"/>"#);
            self.body.push('\n');
        }
    }

    /// A closed polygon.
    pub fn polygon(&mut self, points: &[(f64, f64)], fill: Option<Rgb>, stroke: Option<Stroke>) {
        self.body.push_str(r#"<polygon points=""#);
        for (i, (x, y)) in points.iter().enumerate() {
            if i > 0 {
                self.body.push(' ');
            }
            let _ = write!(self.body, "{},{}", num(*x), num(*y));
        }
        self.body.push('"');
        self.paint(fill, stroke);
        self.body.push_str("/>\n");
    }

    /// A filled circle (a marker).
    pub fn circle(&mut self, x: f64, y: f64, radius: f64, fill: Rgb) {
        let _ = writeln!(
            self.body,
            r#"<circle cx="{}" cy="{}" r="{}" fill="{}"/>"#,
            num(x),
            num(y),
            num(radius),
            fill.hex()
        );
    }

    /// A circle outline (an open marker).
    pub fn circle_outline(&mut self, x: f64, y: f64, radius: f64, stroke: Stroke) {
        let _ = write!(
            self.body,
            r#"<circle cx="{}" cy="{}" r="{}""#,
            num(x),
            num(y),
            num(radius)
        );
        self.paint(None, Some(stroke));
        self.body.push_str("/>\n");
    }

    /// A text at `(x, y)`. A `^` followed by a number (`10^5`) is written as a superscript.
    pub fn text(&mut self, x: f64, y: f64, text: &str, style: &TextStyle) {
        let anchor = match style.anchor {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        };
        // Vertical alignment by offsetting the baseline (dominant-baseline is not rendered
        // the same everywhere): DejaVu's cap height is about 0.73 em.
        let shift = match style.baseline {
            Baseline::Top => 0.76 * style.size,
            Baseline::Middle => 0.36 * style.size,
            Baseline::Bottom => 0.0,
        };
        let _ = write!(
            self.body,
            r#"<text x="{}" y="{}" font-family="{FONT_FAMILY}" font-size="{}" text-anchor="{anchor}" fill="{}""#,
            num(x),
            num(y + shift),
            num(style.size),
            style.colour.hex()
        );
        if style.bold {
            self.body.push_str(r#" font-weight="bold""#);
        }
        if style.rotate != 0.0 {
            // Rotate about the anchor point (before the baseline shift).
            let _ = write!(
                self.body,
                r#" transform="rotate({} {} {})""#,
                num(-style.rotate),
                num(x),
                num(y)
            );
        }
        self.body.push('>');
        match text.split_once('^') {
            Some((base, exponent)) if !exponent.is_empty() => {
                let small = 0.7 * style.size;
                let _ = write!(
                    self.body,
                    r#"{}<tspan dy="{}" font-size="{}">{}</tspan>"#,
                    escape(base),
                    num(-0.45 * style.size),
                    num(small),
                    escape(exponent)
                );
            }
            _ => self.body.push_str(&escape(text)),
        }
        self.body.push_str("</text>\n");
    }

    /// Embed `image` as a PNG raster stretched over `(x, y, w, h)`, not smoothed.
    pub fn image(&mut self, x: f64, y: f64, w: f64, h: f64, image: &RgbImage) -> Result<()> {
        let png = image.encode_png()?;
        let encoded = base64::engine::general_purpose::STANDARD.encode(png);
        let _ = writeln!(
            self.body,
            r#"<image x="{}" y="{}" width="{}" height="{}" preserveAspectRatio="none" style="image-rendering:pixelated" image-rendering="optimizeSpeed" href="data:image/png;base64,{encoded}"/>"#,
            num(x),
            num(y),
            num(w),
            num(h)
        );
        Ok(())
    }

    /// Start a group clipped to the rectangle `(x, y, w, h)`; close it with [`Svg::end_group`].
    pub fn begin_clip(&mut self, x: f64, y: f64, w: f64, h: f64) {
        self.next_id += 1;
        let id = format!("clip{}", self.next_id);
        let _ = writeln!(
            self.body,
            r#"<clipPath id="{id}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath><g clip-path="url(#{id})">"#,
            num(x),
            num(y),
            num(w),
            num(h)
        );
    }

    /// Start a group with a transform (`rotate(...)`, `translate(...)` ...); close it with
    /// [`Svg::end_group`].
    pub fn begin_transform(&mut self, transform: &str) {
        let _ = writeln!(self.body, r#"<g transform="{}">"#, escape(transform));
    }

    /// Start a group with a `class` attribute, naming what it holds for readers of the SVG
    /// (tests, style sheets); close it with [`Svg::end_group`].
    pub fn begin_class(&mut self, class: &str) {
        let _ = writeln!(self.body, r#"<g class="{}">"#, escape(class));
    }

    /// Close a group.
    pub fn end_group(&mut self) {
        self.body.push_str("</g>\n");
    }

    /// The document text.
    pub fn finish(&self) -> String {
        let inches = |px: usize| px as f64 / self.dpi;
        let mut out = String::with_capacity(self.body.len() + 512);
        let _ = writeln!(
            out,
            r#"<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{}in" height="{}in" viewBox="0 0 {} {}">
<!-- made by contactmap {} -->"#,
            num(inches(self.width_px)),
            num(inches(self.height_px)),
            self.width_px,
            self.height_px,
            env!("CARGO_PKG_VERSION")
        );
        out.push_str(&self.body);
        out.push_str("</svg>\n");
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_parse() {
        assert_eq!(Rgb::parse("#ff8000"), Some(Rgb(255, 128, 0)));
        assert_eq!(Rgb::parse("#f80"), Some(Rgb(255, 136, 0)));
        assert_eq!(Rgb::parse("lightgrey"), Some(Rgb(211, 211, 211)));
        assert_eq!(Rgb::parse("#ggg"), None);
        assert_eq!(Rgb::parse("mauve"), None);
        assert_eq!(Rgb(1, 2, 255).hex(), "#0102ff");
    }

    #[test]
    fn numbers_are_short() {
        assert_eq!(num(3.0), "3");
        assert_eq!(num(1.23456), "1.23");
        assert_eq!(num(-0.5), "-0.5");
    }

    #[test]
    fn text_is_escaped_and_superscripts_split() {
        let mut svg = Svg::new(10, 10, 100.0);
        svg.text(
            1.0,
            2.0,
            "a<b & c",
            &TextStyle::new(10.0, Anchor::Start, Baseline::Bottom),
        );
        svg.text(
            1.0,
            2.0,
            "10^5",
            &TextStyle::new(10.0, Anchor::Start, Baseline::Bottom),
        );
        let doc = svg.finish();
        assert!(doc.contains("a&lt;b &amp; c"));
        assert!(doc.contains(r#"10<tspan dy="-4.5" font-size="7">5</tspan>"#));
    }
}
