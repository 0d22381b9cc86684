//! Whether two maps can be compared bin by bin.

use crate::error::{Error, Result};
use crate::io::MatrixReader;

/// Fail unless two maps can be compared bin by bin: the error says which of chromosomes,
/// lengths or bins differ.
pub fn check_comparable(a: &dyn MatrixReader, b: &dyn MatrixReader) -> Result<()> {
    match a.bins().difference(b.bins()) {
        None => Ok(()),
        Some(why) => Err(Error::format(
            b.source(),
            format!(
                "its bins differ from those of {} ({why}): maps are compared bin by bin, so \
                 they must have the same chromosomes and bins (same resolution)",
                a.source()
            ),
        )),
    }
}
