//! Comparing samples: replicate reproducibility (HiCRep's stratum-adjusted correlation,
//! [`hicrep`]), downsampling contacts to a common depth ([`sample`]), coverage per bin
//! ([`coverage`]), a viewpoint's row of the map ([`virtual4c`]), and the clustering of samples by
//! their SCCs ([`cluster`]).
//!
//! Each function reads maps through [`MatrixReader`] and returns plain
//! tables; random draws take an explicit seed and never depend on the number of threads.

pub mod cluster;
pub mod coverage;
pub mod hicrep;
pub mod sample;
pub mod virtual4c;

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
