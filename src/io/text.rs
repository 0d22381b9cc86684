//! Text pixel tables, pairs and dense matrices. Being written.

use crate::error::{Error, Result};
use crate::io::OpenOptions;
use crate::matrix::ContactMatrix;

/// A text layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextFormat {
    /// chrom1 start1 end1 chrom2 start2 end2 count
    Bg2,
    /// bin1 bin2 count (with a bin BED)
    Coo,
    /// pairs (binned on the fly)
    Pairs,
    /// dense matrix
    Dense,
}

/// Read a text matrix into memory.
pub fn read_matrix(path: &str, _options: &OpenOptions) -> Result<ContactMatrix> {
    Err(Error::format(path, "text reading is not available yet"))
}

/// Write a matrix as text.
pub fn write_text(
    reader: &dyn crate::io::MatrixReader,
    path: &str,
    _format: TextFormat,
) -> Result<()> {
    Err(Error::format(
        path,
        format!("{}: text writing is not available yet", reader.source()),
    ))
}
