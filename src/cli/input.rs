//! Opening the input matrix of the analyses (balance, expected, normalize, tads).
//!
//! The analyses read through [`CheckedCounts`], so that a file with a negative, NaN or infinite
//! count is refused (exit 2, naming the file and the first such pixel) instead of being computed
//! on; `dump`, `info` and `convert` open files as they are.

use crate::cli::InputArgs;
use crate::error::Result;
use crate::io::{self, CheckedCounts, MatrixReader};

/// Open the matrix at `uri` (with the text-input options `input`) for an analysis: its counts are
/// checked as they stream.
pub fn open_for_analysis(uri: &str, input: &InputArgs) -> Result<Box<dyn MatrixReader>> {
    let reader = io::open_matrix(uri, &input.to_options()?)?;
    Ok(Box::new(CheckedCounts::new(reader)))
}
