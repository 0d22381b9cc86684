//! Figures: contact-map heatmaps (square or 45-degree), P(s) curves, protein contact maps,
//! compartment saddles.
//!
//! Our code computes the pictures: which bins fall in which image cell and with what mean
//! ([`heatmap`]), the colour of each value ([`colormap`]: matplotlib's and cooltools' maps and
//! their lookup rule), the layout, ticks and legends ([`axes`]). A figure is written as SVG
//! ([`svg`]); PNG output rasterises that SVG with resvg and the DejaVu Sans font compiled into the
//! binary ([`render`]), so both formats show the same picture and no system font is needed.
//!
//! Coordinates: genomic positions in bp (0-based, half-open bins as everywhere in contactmap);
//! figure sizes in pixels at the figure's dpi, text and line sizes in points.

pub mod axes;
pub mod colormap;
pub mod curves;
pub mod diff;
pub mod heatmap;
pub mod map;
pub mod map_job;
pub mod pileup;
pub mod protein;
pub mod render;
pub mod saddle;
pub mod similarity;
pub mod svg;

pub use colormap::{ColorMap, ColorScale, ScaleKind};
pub use render::{ImageFormat, figure_bytes};
pub use svg::{Rgb, RgbImage, Svg};
