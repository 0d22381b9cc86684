//! One way to write a matrix ([`write_matrix`]): the format ([`MatrixFormat`], from a file's
//! extension or named) and what the formats take beyond the map ([`MatrixOutput`]), over the formats' writers
//! (`io::cool::write_cool` / `write_mcool`, `io::text::write_text`) and the `.hic` writer that
//! balances ([`super::hic::write_hic`]). `convert`, `merge`, `zoomify`, `normalize` and the Python
//! package's writers all write through it.

use std::path::Path;

use super::hic::{DEFAULT_HIC_NORMALIZATIONS, Unconverged, write_hic};
use crate::balance::Method;
use crate::error::{Error, Result};
use crate::io::MatrixReader;
use crate::io::cool::{CoolWriteOptions, write_cool, write_mcool};
use crate::io::hic::HicWriteOptions;
use crate::io::text::{TextFormat, write_text};

/// The formats a matrix is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatrixFormat {
    /// A single-resolution cooler (format-version 3).
    Cool,
    /// A multi-resolution cooler (one group per resolution under `/resolutions`).
    Mcool,
    /// A Juicer `.hic` (version 9), every resolution, with normalisation and expected vectors.
    Hic,
    /// `chrom1 start1 end1 chrom2 start2 end2 count` (`cooler dump --join`).
    Bg2,
    /// `bin1_id bin2_id count` (`cooler dump`).
    Coo,
    /// A square dense matrix (small matrices only).
    Dense,
}

impl MatrixFormat {
    /// The format named by the extension of `path` (a `.gz` suffix aside): `.mcool`, `.hic`,
    /// `.cool`, `.bg2` / `.bedpe`, `.coo` / `.pixels`, `.dense` / `.mat` / `.matrix`.
    ///
    /// ```
    /// use contactmap::export::MatrixFormat;
    /// use std::path::Path;
    /// assert_eq!(MatrixFormat::from_extension(Path::new("a.mcool"))?, MatrixFormat::Mcool);
    /// assert_eq!(MatrixFormat::from_extension(Path::new("a.bg2.gz"))?, MatrixFormat::Bg2);
    /// assert!(MatrixFormat::from_extension(Path::new("a.txt")).is_err());
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn from_extension(path: &Path) -> Result<MatrixFormat> {
        let name = path.to_string_lossy().to_ascii_lowercase();
        let name = name.strip_suffix(".gz").unwrap_or(&name);
        let format = if name.ends_with(".mcool") {
            MatrixFormat::Mcool
        } else if name.ends_with(".hic") {
            MatrixFormat::Hic
        } else if name.ends_with(".cool") {
            MatrixFormat::Cool
        } else if name.ends_with(".bg2") || name.ends_with(".bedpe") {
            MatrixFormat::Bg2
        } else if name.ends_with(".coo") || name.ends_with(".pixels") {
            MatrixFormat::Coo
        } else if name.ends_with(".dense") || name.ends_with(".mat") || name.ends_with(".matrix") {
            MatrixFormat::Dense
        } else {
            return Err(Error::Argument(format!(
                "cannot tell the output format from '{}': use an extension (.cool, .mcool, .hic, \
                 .bg2, .coo, .dense) or --to",
                path.display()
            )));
        };
        Ok(format)
    }

    /// Whether the format is a binary file that needs a path (not standard output).
    pub fn needs_a_file(self) -> bool {
        matches!(
            self,
            MatrixFormat::Cool | MatrixFormat::Mcool | MatrixFormat::Hic
        )
    }

    /// Whether the format holds several resolutions (`.mcool`, `.hic`).
    pub fn has_resolutions(self) -> bool {
        matches!(self, MatrixFormat::Mcool | MatrixFormat::Hic)
    }
}

/// What the formats take beyond the map: each field is read by the formats it names, the
/// others ignore it.
#[derive(Clone, Debug)]
pub struct MatrixOutput {
    /// The resolutions of an `.mcool` or `.hic` (bp; the map's own first; see
    /// [`crate::io::cool::resolutions`]).
    pub resolutions: Vec<u64>,
    /// The genome assembly: a cooler's `genome-assembly`, a `.hic`'s genome (`unknown` when
    /// none).
    pub assembly: Option<String>,
    /// The weight columns a cooler copies (every one when `None`; only at the map's own
    /// resolution).
    pub weight_columns: Option<Vec<String>>,
    /// The normalisations a `.hic` stores (default: Juicer's set).
    pub normalizations: Vec<Method>,
    /// A `.hic`'s zlib compression level, 0-9 (default: 6, Juicer's).
    pub compression_level: u32,
}

impl Default for MatrixOutput {
    fn default() -> Self {
        MatrixOutput {
            resolutions: Vec::new(),
            assembly: None,
            weight_columns: None,
            normalizations: DEFAULT_HIC_NORMALIZATIONS.to_vec(),
            compression_level: HicWriteOptions::default().compression_level,
        }
    }
}

/// Write the map of `reader` to `path` in `format`, with what `output` gives it (text formats
/// write to standard output for `-`); returns the `.hic`'s balancings that did not converge
/// (stored anyway, as Juicer does), none for the other formats.
///
/// ```
/// use contactmap::export::{MatrixFormat, MatrixOutput, write_matrix};
/// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
/// let dir = std::env::temp_dir().join(format!("cm-write-matrix-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let reader = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
/// for name in ["copy.cool", "copy.bg2"] {
///     let path = dir.join(name);
///     let format = MatrixFormat::from_extension(&path)?;
///     assert!(write_matrix(reader.as_ref(), &path, format, &MatrixOutput::default())?.is_empty());
/// }
/// let copy = open_matrix(dir.join("copy.cool").to_str().unwrap(), &OpenOptions::default())?;
/// assert_eq!(copy.totals()?, reader.totals()?);
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_matrix(
    reader: &dyn MatrixReader,
    path: &Path,
    format: MatrixFormat,
    output: &MatrixOutput,
) -> Result<Vec<Unconverged>> {
    let cool = || CoolWriteOptions {
        assembly: output.assembly.clone(),
        weight_columns: output.weight_columns.clone(),
    };
    let text = |format: TextFormat| write_text(reader, &path.to_string_lossy(), format);
    match format {
        MatrixFormat::Cool => write_cool(reader, path, &cool())?,
        MatrixFormat::Mcool => write_mcool(reader, path, &output.resolutions, &cool())?,
        MatrixFormat::Hic => {
            let options = HicWriteOptions {
                compression_level: output.compression_level,
                ..HicWriteOptions::for_genome(output.assembly.clone())
            };
            return write_hic(
                reader,
                path,
                &output.resolutions,
                &output.normalizations,
                &options,
            );
        }
        MatrixFormat::Bg2 => text(TextFormat::Bg2)?,
        MatrixFormat::Coo => text(TextFormat::Coo)?,
        MatrixFormat::Dense => text(TextFormat::Dense)?,
    }
    Ok(Vec::new())
}
