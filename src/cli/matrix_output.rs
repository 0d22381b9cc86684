//! The matrix files several commands write (`convert`, `merge`, `zoomify`, `normalize`):
//! `--to`'s names for [`MatrixFormat`], `--normalizations`, and [`export::write_matrix`] with its
//! warnings printed.

use std::path::Path;

use clap::ValueEnum;

use contactmap::balance::Method;
use contactmap::error::{Error, Result};
use contactmap::export::{self, MatrixFormat, MatrixOutput};
use contactmap::io::MatrixReader;

/// Output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OutputFormat {
    /// single-resolution cooler (format-version 3)
    Cool,
    /// multi-resolution cooler (one group per resolution under /resolutions)
    Mcool,
    /// Juicer .hic (version 9), every resolution, with normalisation and expected vectors
    Hic,
    /// chrom1 start1 end1 chrom2 start2 end2 count (cooler dump --join)
    Bg2,
    /// bin1_id bin2_id count (cooler dump)
    Coo,
    /// square dense matrix (small matrices only)
    Dense,
}

impl From<OutputFormat> for MatrixFormat {
    fn from(format: OutputFormat) -> MatrixFormat {
        match format {
            OutputFormat::Cool => MatrixFormat::Cool,
            OutputFormat::Mcool => MatrixFormat::Mcool,
            OutputFormat::Hic => MatrixFormat::Hic,
            OutputFormat::Bg2 => MatrixFormat::Bg2,
            OutputFormat::Coo => MatrixFormat::Coo,
            OutputFormat::Dense => MatrixFormat::Dense,
        }
    }
}

/// Parse `--normalizations` ([`export::parse_normalizations`]).
pub fn parse_normalizations(items: &[String]) -> Result<Vec<Method>> {
    export::parse_normalizations(items)
        .map_err(|e| Error::Argument(format!("--normalizations: {e}")))
}

/// [`export::write_matrix`], then a warning on standard error for each chromosome whose
/// balancing did not converge (a `.hic`'s).
pub fn write_matrix(
    reader: &dyn MatrixReader,
    path: &Path,
    format: MatrixFormat,
    output: &MatrixOutput,
) -> Result<()> {
    for unconverged in export::write_matrix(reader, path, format, output)? {
        eprintln!("contactmap: WARNING: {unconverged}");
    }
    Ok(())
}
