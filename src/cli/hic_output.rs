//! `--normalizations` of the commands that write a `.hic` (convert, merge, zoomify), and the
//! warnings of [`contactmap::export::write_hic`].

use std::path::Path;

use contactmap::balance::Method;
use contactmap::error::{Error, Result};
use contactmap::export::{self, DEFAULT_HIC_NORMALIZATIONS};
use contactmap::io::hic::HicWriteOptions;
use contactmap::io::MatrixReader;

/// Parse `--normalizations`: names (case-insensitive: VC, VC_SQRT, KR, SCALE, ICE) or `none`;
/// none given is Juicer's set.
pub fn parse_normalizations(items: &[String]) -> Result<Vec<Method>> {
    if items.is_empty() {
        return Ok(DEFAULT_HIC_NORMALIZATIONS.to_vec());
    }
    let mut methods = Vec::new();
    for item in items {
        if item.trim().eq_ignore_ascii_case("none") {
            continue;
        }
        let method = Method::from_juicer_name(item).ok_or_else(|| {
            Error::Invalid(format!(
                "--normalizations: '{item}' is not one of VC, VC_SQRT, KR, SCALE, ICE, none"
            ))
        })?;
        if !methods.contains(&method) {
            methods.push(method);
        }
    }
    Ok(methods)
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
