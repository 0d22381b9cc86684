//! Whole-file outputs that carry computed results, standing above both the formats
//! ([`crate::io`]) and the algorithms: a Juicer `.hic` with its normalisation vectors and expected
//! values ([`hic`]), results stored into a cooler ([`cooler`]: balancing weights, coverage), and
//! the one way every command and the Python package write a matrix in any format
//! ([`write_matrix`]), a `.hic` being one of them.

pub mod cooler;
pub mod hic;
pub mod matrix;

pub use hic::{DEFAULT_HIC_NORMALIZATIONS, Unconverged, parse_normalizations, write_hic};
pub use matrix::{MatrixFormat, MatrixOutput, write_matrix};
