//! `contactmap`: genome (Hi-C) and protein contact maps.
//!
//! The library is organised as the data flows:
//!
//! - [`io`] reads and writes files (`.cool` / `.mcool`, Juicer `.hic`, text tables and pairs) into
//!   the core types and back; readers stream sorted pixel blocks so that large maps never need to be
//!   held in memory;
//! - the core types: [`genome::BinTable`] (chromosomes cut into bins), [`matrix::ContactMatrix`]
//!   (upper-triangle sparse matrix with weight columns) and [`matrix::PixelBlock`];
//! - algorithms take core types and return core types or plain tables; they never open files:
//!   [`balance`] (ICE, VC, KR), [`expected`] (P(s), power laws), [`normalize`] (observed /
//!   expected), [`tads`] (insulation, directionality, TopDom, Armatus), [`score`] (calls against
//!   a truth), [`compartments`] (eigenvectors as cooltools, saddles);
//! - [`export`] writes files that carry computed results (a `.hic` with Juicer's normalisation
//!   vectors and expected values): it stands above both the formats and the algorithms;
//! - [`plot`] draws figures (heatmaps, P(s) curves, protein contact maps) as PNG or SVG;
//! - [`sim`] makes synthetic maps with a known truth (block-structured maps with TADs, polymer
//!   ensembles).
//!
//! The `contactmap` command line is a thin layer over these modules, in the binary (`src/cli/`):
//! each command parses its options into the library's parameters, calls the library and prints.
//! Modules import one another one way (`tests/architecture.rs` checks it).
//!
//! Coordinates are 0-based and half-open; weights are multiplicative (cooler's convention).
//!
//! ```
//! use contactmap::genome::{BinTable, Chrom};
//! use contactmap::matrix::{CountType, MatrixBuilder};
//!
//! let bins = BinTable::fixed(vec![Chrom::new("chr1", 1_000), Chrom::new("chr2", 500)], 100)?;
//! let mut builder = MatrixBuilder::new(bins, CountType::Integer);
//! builder.push(0, 3, 2.0)?;
//! builder.push(3, 0, 1.0)?; // lower-triangle pixels are mirrored and summed
//! let matrix = builder.build();
//! assert_eq!(matrix.get(0, 3), 3.0);
//! let rows = matrix.bins().parse_region_bins("chr1:0-400")?;
//! assert_eq!(matrix.dense(rows.clone(), rows).sum(), 6.0);
//! # Ok::<(), contactmap::Error>(())
//! ```

pub mod balance;
pub mod compartments;
pub mod error;
pub mod expected;
pub mod export;
pub mod genome;
pub mod io;
pub mod matrix;
pub mod normalize;
pub mod numeric;
pub mod plot;
pub mod score;
pub mod sim;
pub mod tads;
pub mod validate;

pub use error::{Error, Result};
pub use genome::{Bin, BinTable, Chrom, Region};
pub use matrix::{ContactMatrix, CountType, MatrixBuilder, PixelBlock, Weights};
