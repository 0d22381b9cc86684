//! From the SVG model to the bytes of a PNG or SVG file.
//!
//! PNG output rasterises the figure's SVG with resvg (tiny-skia, anti-aliased) using DejaVu Sans
//! compiled into the binary: no system font is looked up, so a static binary draws the same
//! picture on a bare machine. The PNG records the dpi (pHYs chunk).

use std::sync::{Arc, OnceLock};

use resvg::{tiny_skia, usvg};

use crate::error::{Error, Result};
use crate::plot::svg::Svg;

/// Image file formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// Portable Network Graphics (raster).
    Png,
    /// Scalable Vector Graphics (vector; heatmaps embedded as PNG rasters).
    Svg,
}

impl ImageFormat {
    /// The format named by a file's extension (`.png`, `.svg`), if any.
    pub fn from_path(path: &std::path::Path) -> Option<ImageFormat> {
        let extension = path.extension()?.to_str()?.to_ascii_lowercase();
        match extension.as_str() {
            "png" => Some(ImageFormat::Png),
            "svg" => Some(ImageFormat::Svg),
            _ => None,
        }
    }
}

/// The font database: DejaVu Sans regular and bold, nothing from the system.
fn fonts() -> Arc<usvg::fontdb::Database> {
    static FONTS: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut database = usvg::fontdb::Database::new();
            database.load_font_data(dejavu::sans::regular().to_vec());
            database.load_font_data(dejavu::sans::bold().to_vec());
            database.set_sans_serif_family("DejaVu Sans");
            Arc::new(database)
        })
        .clone()
}

/// Rasterise `svg` to RGB pixels (`3 * width * height` bytes, white background).
pub fn rasterize(svg: &Svg) -> Result<Vec<u8>> {
    let text = svg.finish();
    let options = usvg::Options {
        font_family: "DejaVu Sans".into(),
        fontdb: fonts(),
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_str(&text, &options)
        .map_err(|e| Error::Invalid(format!("internal error: the figure's SVG is invalid: {e}")))?;
    let (width, height) = (svg.width_px() as u32, svg.height_px() as u32);
    let mut pixmap = tiny_skia::Pixmap::new(width, height).ok_or_else(|| {
        Error::Argument(format!(
            "a {width} x {height} pixel image is too large or empty"
        ))
    })?;
    pixmap.fill(tiny_skia::Color::WHITE);
    let size = tree.size();
    let transform = tiny_skia::Transform::from_scale(
        width as f32 / size.width(),
        height as f32 / size.height(),
    );
    resvg::render(&tree, transform, &mut pixmap.as_mut());
    // Opaque white background: premultiplied RGBA equals straight RGBA.
    let mut rgb = Vec::with_capacity(3 * (width * height) as usize);
    for pixel in pixmap.data().chunks_exact(4) {
        rgb.extend_from_slice(&pixel[..3]);
    }
    Ok(rgb)
}

/// The PNG file of `svg`, with its dpi recorded.
pub fn png_bytes(svg: &Svg, dpi: f64) -> Result<Vec<u8>> {
    let rgb = rasterize(svg)?;
    let invalid = |e: png::EncodingError| Error::Argument(format!("PNG encoding: {e}"));
    let mut bytes = Vec::new();
    {
        let mut encoder =
            png::Encoder::new(&mut bytes, svg.width_px() as u32, svg.height_px() as u32);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        // Figures are written once and kept (papers, READMEs): the smaller file is worth the
        // few milliseconds (a 600 x 600 heatmap: about 40% smaller than the default).
        encoder.set_compression(png::Compression::Best);
        encoder.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
        let per_metre = (dpi / 0.0254).round() as u32;
        encoder.set_pixel_dims(Some(png::PixelDimensions {
            xppu: per_metre,
            yppu: per_metre,
            unit: png::Unit::Meter,
        }));
        let mut writer = encoder.write_header().map_err(invalid)?;
        writer.write_image_data(&rgb).map_err(invalid)?;
        writer.finish().map_err(invalid)?;
    }
    Ok(bytes)
}

/// The bytes of the figure in `format`.
///
/// # Examples
///
/// ```
/// use contactmap::plot::{figure_bytes, ImageFormat, Rgb, Svg};
///
/// let mut svg = Svg::new(120, 80, 100.0);
/// svg.rect(10.0, 10.0, 50.0, 30.0, Some(Rgb(200, 30, 30)), None);
/// let png = figure_bytes(&svg, ImageFormat::Png, 100.0)?;
/// assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
/// assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 120);
/// assert_eq!(u32::from_be_bytes(png[20..24].try_into().unwrap()), 80);
/// let text = figure_bytes(&svg, ImageFormat::Svg, 100.0)?;
/// assert_eq!(text, svg.finish().into_bytes());
/// assert_eq!(ImageFormat::from_path("a/figure.PNG".as_ref()), Some(ImageFormat::Png));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn figure_bytes(svg: &Svg, format: ImageFormat, dpi: f64) -> Result<Vec<u8>> {
    match format {
        ImageFormat::Png => png_bytes(svg, dpi),
        ImageFormat::Svg => Ok(svg.finish().into_bytes()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::svg::{Anchor, Baseline, Rgb, RgbImage, TextStyle};

    fn decode(png: &[u8]) -> (usize, usize, Vec<u8>) {
        let decoder = png::Decoder::new(png);
        let mut reader = decoder.read_info().unwrap();
        let mut buffer = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buffer).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        buffer.truncate(info.buffer_size());
        (info.width as usize, info.height as usize, buffer)
    }

    #[test]
    fn rectangles_and_rasters_land_on_their_pixels() {
        let mut svg = Svg::new(40, 30, 100.0);
        svg.rect(10.0, 5.0, 10.0, 10.0, Some(Rgb(255, 0, 0)), None);
        let mut image = RgbImage::filled(4, 2, Rgb(0, 0, 255));
        image.set(3, 1, Rgb(0, 255, 0));
        // Each raster pixel drawn as a 2 x 3 block.
        svg.image(20.0, 20.0, 8.0, 6.0, &image).unwrap();
        let (width, height, rgb) = decode(&png_bytes(&svg, 100.0).unwrap());
        assert_eq!((width, height), (40, 30));
        let at = |x: usize, y: usize| {
            let i = 3 * (y * width + x);
            (rgb[i], rgb[i + 1], rgb[i + 2])
        };
        assert_eq!(at(0, 0), (255, 255, 255));
        assert_eq!(at(10, 5), (255, 0, 0));
        assert_eq!(at(19, 14), (255, 0, 0));
        assert_eq!(at(20, 14), (255, 255, 255));
        assert_eq!(at(20, 20), (0, 0, 255));
        assert_eq!(at(25, 22), (0, 0, 255));
        // The green raster pixel: columns 26-27, rows 23-25.
        assert_eq!(at(26, 23), (0, 255, 0));
        assert_eq!(at(27, 25), (0, 255, 0));
        assert_eq!(at(25, 25), (0, 0, 255));
        assert_eq!(at(28, 25), (255, 255, 255));
    }

    #[test]
    fn text_is_drawn_with_the_embedded_font() {
        let mut svg = Svg::new(120, 40, 100.0);
        svg.text(
            5.0,
            20.0,
            "Hi-C 10^5",
            &TextStyle::new(20.0, Anchor::Start, Baseline::Middle),
        );
        let rgb = rasterize(&svg).unwrap();
        let dark = rgb.chunks_exact(3).filter(|p| p[0] < 128).count();
        // Glyphs cover some pixels, not most.
        assert!(dark > 100 && dark < 2000, "{dark} dark pixels");
    }
}
