//! The options every figure shares (output, format, size, dpi, title), their checks, the
//! writing of the figure, and legend names.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use crate::cli::output::Output;
use contactmap::error::{Error, Result};
use contactmap::plot::{ImageFormat, Svg, figure_bytes};

/// The legend names of `inputs`: `labels` (`--labels`, one per input) or `default` of each.
pub fn legend_labels(
    labels: Option<&Vec<String>>,
    inputs: &[String],
    default: impl Fn(&str) -> String,
) -> Result<Vec<String>> {
    match labels {
        Some(labels) if labels.len() != inputs.len() => Err(Error::Argument(format!(
            "--labels gives {} name(s) for {} input(s)",
            labels.len(),
            inputs.len()
        ))),
        Some(labels) => Ok(labels.clone()),
        None => Ok(inputs.iter().map(|input| default(input)).collect()),
    }
}

/// Image formats, for `--format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FormatArg {
    /// PNG raster
    Png,
    /// SVG vector graphics (heatmaps embedded as PNG rasters)
    Svg,
}

/// Output and size options shared by every figure.
#[derive(Debug, Args)]
pub struct FigureArgs {
    /// Output image: FILE.png or FILE.svg, or `-` for standard output (PNG unless --to).
    #[arg(short, long, value_name = "FILE")]
    pub out: PathBuf,
    /// Image format (default: from the extension of --out).
    #[arg(long, value_enum, value_name = "FORMAT")]
    pub to: Option<FormatArg>,
    /// Figure width in inches (the figure's default when absent).
    #[arg(long, value_name = "INCHES")]
    pub width: Option<f64>,
    /// Figure height in inches (default: what the content needs at that width).
    #[arg(long, value_name = "INCHES")]
    pub height: Option<f64>,
    /// Resolution: pixels per inch of the PNG; text and lines scale with it.
    #[arg(long, default_value_t = 100.0)]
    pub dpi: f64,
    /// Title above the figure.
    #[arg(long)]
    pub title: Option<String>,
}

/// Checked output and size options.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// PNG or SVG.
    pub format: ImageFormat,
    /// Width in pixels.
    pub width_px: usize,
    /// Height in pixels, when asked.
    pub height_px: Option<usize>,
    /// Dots per inch.
    pub dpi: f64,
}

/// Largest figure side in pixels.
const MAX_SIDE_PX: f64 = 30_000.0;

impl FigureArgs {
    /// Check the options; `default_width_in` is the figure's default width.
    pub fn check(&self, default_width_in: f64) -> Result<Figure> {
        let format = match self.to {
            Some(FormatArg::Png) => ImageFormat::Png,
            Some(FormatArg::Svg) => ImageFormat::Svg,
            None if self.out.as_os_str() == "-" => ImageFormat::Png,
            None => ImageFormat::from_path(&self.out).ok_or_else(|| {
                Error::Argument(format!(
                    "--out {}: the extension must be .png or .svg (or give --to png|svg)",
                    self.out.display()
                ))
            })?,
        };
        if !(self.dpi >= 10.0 && self.dpi <= 2400.0) {
            return Err(Error::Argument(format!(
                "--dpi must be between 10 and 2400 (got {})",
                self.dpi
            )));
        }
        let pixels = |inches: f64, what: &str| -> Result<usize> {
            let px = inches * self.dpi;
            if !(inches > 0.0 && (50.0..=MAX_SIDE_PX).contains(&px)) {
                return Err(Error::Argument(format!(
                    "--{what} {inches} in at {} dpi gives {px:.0} pixels: it must give 50 to {MAX_SIDE_PX} pixels",
                    self.dpi
                )));
            }
            Ok(px.round() as usize)
        };
        Ok(Figure {
            format,
            width_px: pixels(self.width.unwrap_or(default_width_in), "width")?,
            height_px: self.height.map(|h| pixels(h, "height")).transpose()?,
            dpi: self.dpi,
        })
    }
}

/// Write the figure to `--out` (under a temporary name renamed when complete; stdout for `-`).
pub fn write_figure(svg: &Svg, figure: &Figure, args: &FigureArgs) -> Result<()> {
    let bytes = figure_bytes(svg, figure.format, figure.dpi)?;
    let mut out = Output::open(Some(&args.out))?;
    out.write_all(&bytes)?;
    out.finish()
}
