//! The matrix files several commands write (`convert`, `merge`, `zoomify`, `normalize`): the
//! output format named by a file's extension (the resolutions of an .mcool or .hic are
//! [`contactmap::io::cool::resolutions`]).

use std::path::Path;

use clap::ValueEnum;

use contactmap::error::{Error, Result};

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

/// The output format named by the extension of `path` (a `.gz` suffix aside).
pub fn format_from_extension(path: &Path) -> Result<OutputFormat> {
    let name = path.to_string_lossy().to_ascii_lowercase();
    let name = name.strip_suffix(".gz").unwrap_or(&name);
    let format = if name.ends_with(".mcool") {
        OutputFormat::Mcool
    } else if name.ends_with(".hic") {
        OutputFormat::Hic
    } else if name.ends_with(".cool") {
        OutputFormat::Cool
    } else if name.ends_with(".bg2") || name.ends_with(".bedpe") {
        OutputFormat::Bg2
    } else if name.ends_with(".coo") || name.ends_with(".pixels") {
        OutputFormat::Coo
    } else if name.ends_with(".dense") || name.ends_with(".matrix") || name.ends_with(".mat") {
        OutputFormat::Dense
    } else {
        return Err(Error::Argument(format!(
            "cannot tell the output format from '{}': use an extension (.cool, .mcool, .hic, .bg2, .coo, .dense) or --to",
            path.display()
        )));
    };
    Ok(format)
}
