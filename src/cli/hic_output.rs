//! `--normalizations` of the commands that write a `.hic` (convert, merge, zoomify), and the
//! warnings of [`contactmap::export::write_hic`].

use std::path::Path;

use contactmap::balance::Method;
use contactmap::error::{Error, Result};
use contactmap::export;
use contactmap::io::MatrixReader;
use contactmap::io::hic::HicWriteOptions;

/// Parse `--normalizations` ([`export::parse_normalizations`]).
pub fn parse_normalizations(items: &[String]) -> Result<Vec<Method>> {
    export::parse_normalizations(items)
        .map_err(|e| Error::Argument(format!("--normalizations: {e}")))
}

/// [`export::write_hic`], then a warning on standard error for each chromosome whose balancing
/// did not converge.
pub fn write_hic(
    reader: &dyn MatrixReader,
    path: &Path,
    resolutions: &[u64],
    methods: &[Method],
    options: &HicWriteOptions,
) -> Result<()> {
    for unconverged in export::write_hic(reader, path, resolutions, methods, options)? {
        eprintln!("contactmap: WARNING: {unconverged}");
    }
    Ok(())
}
