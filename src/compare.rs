//! Comparing samples: replicate reproducibility (HiCRep's stratum-adjusted correlation,
//! [`hicrep`]), downsampling contacts to a common depth ([`sample`]), coverage per bin
//! ([`coverage`]), a viewpoint's row of the map ([`virtual4c`]), and the clustering of samples by
//! their SCCs ([`cluster`]).
//!
//! Each function reads maps through [`MatrixReader`](crate::io::MatrixReader) and returns plain
//! tables; random draws take an explicit seed and never depend on the number of threads.

pub mod cluster;
mod comparable;
pub mod coverage;
pub mod hicrep;
pub mod sample;
pub mod virtual4c;

pub use comparable::check_comparable;
