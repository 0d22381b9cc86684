//! Opening a matrix by its URI: the reader it needs ([`open_matrix`]) and the resolutions a
//! file holds ([`list_resolutions`]).

use std::io::Read;
use std::path::Path;

use crate::error::{Error, Result};

use super::kind::{FileKind, detect_kind};
use super::reader::{InMemory, MatrixReader};
use super::text::options::OpenOptions;
use super::uri::{parse_resolution_group, split_uri};
use super::{cool, hic, hicexplorer, text};

/// Open any supported matrix: `.cool`, `.mcool::/resolutions/N`, `.hic[::/resolutions/N]`, or a
/// text table (`-` for stdin). `options.resolution` chooses the level of an `.mcool` or `.hic`
/// named without one (the same reader as the URI's `::/resolutions/N`); given with a URI that
/// names another, or for a single-resolution map of another bin size, it is an error.
///
/// # Examples
///
/// The same mm9 map as a cooler and as a `.hic` written by hictk (`data/README.md`): one bin
/// table, the same pixels.
///
/// ```
/// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
///
/// let options = OpenOptions::default();
/// let cool = open_matrix("data/CN.mm9.10000kb.cool", &options)?;
/// let hic = open_matrix("data/CN.mm9.multires.hic::/resolutions/10000000", &options)?;
/// assert!(cool.info().format.starts_with("cool"));
/// assert_eq!(cool.bins().n_bins(), hic.bins().n_bins());
/// assert_eq!(cool.totals()?, (38_503, 499_864_755.0)); // cooler's nnz and sum
/// assert_eq!(hic.totals()?, cool.totals()?);
/// assert!(open_matrix("data/no-such-file.cool", &options).is_err());
///
/// // a level chosen apart from the path, as hictk's --resolution
/// let at = |resolution| OpenOptions { resolution: Some(resolution), ..OpenOptions::default() };
/// let level = open_matrix("data/CN.mm9.multires.hic", &at(10_000_000))?;
/// assert_eq!(level.totals()?, hic.totals()?);
/// let level = open_matrix("data/cooler_test_file.mcool", &at(1_000_000))?;
/// assert_eq!(level.source(), "data/cooler_test_file.mcool::/resolutions/1000000");
/// assert!(open_matrix("data/cooler_test_file.mcool", &at(5_000)).is_err()); // no such level
/// assert!(open_matrix("data/CN.mm9.10000kb.cool", &at(10_000_000)).is_ok()); // its own
/// assert!(open_matrix("data/CN.mm9.10000kb.cool", &at(5_000)).is_err());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn open_matrix(uri: &str, options: &OpenOptions) -> Result<Box<dyn MatrixReader>> {
    let Some(resolution) = options.resolution else {
        return open_uri(uri, options);
    };
    let uri = uri_at_resolution(uri, resolution)?;
    let reader = open_uri(&uri, options)?;
    // a single-resolution map (a cooler, HiCExplorer's .h5, a group of a legacy layout)
    match reader.bins().resolution() {
        Some(size) if size == resolution => Ok(reader),
        size => Err(Error::Argument(format!(
            "{uri} holds one resolution, {}, not the resolution {resolution} asked for",
            size.map_or("bins of varying sizes".to_string(), |s| format!("{s} bp"))
        ))),
    }
}

/// The URI of the level `resolution` of the matrix at `uri`: `path::/resolutions/N` for an
/// `.mcool` or `.hic` named without a level, `uri` itself otherwise (a single-resolution map,
/// whose bin size [`open_matrix`] then checks). An error (a parameter's) when `uri` names
/// another level, the file has no such level, or `uri` is a text table.
///
/// ```
/// use contactmap::io::uri_at_resolution;
///
/// let uri = uri_at_resolution("data/cooler_test_file.mcool", 100_000)?;
/// assert_eq!(uri, "data/cooler_test_file.mcool::/resolutions/100000");
/// assert_eq!(uri_at_resolution(&uri, 100_000)?, uri);
/// assert!(uri_at_resolution(&uri, 1_000_000).is_err());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn uri_at_resolution(uri: &str, resolution: u64) -> Result<String> {
    if resolution == 0 {
        return Err(Error::Argument("the resolution must be positive".into()));
    }
    let (path, group) = split_uri(uri);
    let kind = detect_kind(path)?;
    let named = group.and_then(|g| parse_resolution_group(uri, g).ok());
    Ok(match (kind, group, named) {
        (FileKind::Text, _, _) => {
            return Err(Error::Argument(format!(
                "{uri}: the resolution chooses a level of an .mcool or .hic file, and this is a \
                 text table (pairs are binned at the bin size instead)"
            )));
        }
        (_, Some(_), Some(named)) if named != resolution => {
            return Err(Error::Argument(format!(
                "{uri} names the resolution {named} and the resolution {resolution} is asked \
                 for: give one of the two"
            )));
        }
        (FileKind::Hdf5, None, _) => match cool::inspect(path)? {
            cool::HdfContent::Multires(levels) if !levels.contains(&resolution) => {
                return Err(Error::Argument(format!(
                    "{path} has no resolution {resolution}: it has {}",
                    hic::list_numbers(&levels)
                )));
            }
            cool::HdfContent::Multires(_) => format!("{path}::/resolutions/{resolution}"),
            cool::HdfContent::Cooler => uri.to_string(),
        },
        (FileKind::Hic, None, _) => format!("{path}::/resolutions/{resolution}"),
        _ => uri.to_string(),
    })
}

/// [`open_matrix`] of the URI as it is.
fn open_uri(uri: &str, options: &OpenOptions) -> Result<Box<dyn MatrixReader>> {
    let (path, group) = split_uri(uri);
    match detect_kind(path)? {
        FileKind::Hdf5 if group.is_none() && hicexplorer::is_hicexplorer(path)? => {
            Ok(Box::new(hicexplorer::HicExplorerReader::open(path)?))
        }
        FileKind::Hdf5 => Ok(Box::new(cool::CoolReader::open(uri)?)),
        FileKind::Hic => {
            let resolution = match group {
                None => None,
                Some(g) => Some(parse_resolution_group(uri, g)?),
            };
            Ok(Box::new(hic::HicReader::open(Path::new(path), resolution)?))
        }
        FileKind::Text => {
            if let Some(expected) = binary_extension(path) {
                return Err(not_binary(path, expected));
            }
            if group.is_some() {
                return Err(Error::format(
                    path,
                    "a '::' group path was given but this is not a .cool/.mcool/.hic file",
                ));
            }
            Ok(Box::new(InMemory::new(
                uri.to_string(),
                text::read_matrix(path, options)?,
            )))
        }
    }
}

/// The binary format a file name promises (`.cool`, `.mcool`, `.h5` / `.hdf5`: HDF5; `.hic`),
/// if any.
fn binary_extension(path: &str) -> Option<&'static str> {
    let extension = Path::new(path).extension()?.to_str()?.to_ascii_lowercase();
    match extension.as_str() {
        "cool" | "mcool" | "h5" | "hdf5" => Some("HDF5"),
        "hic" => Some(".hic"),
        _ => None,
    }
}

/// The error for a file named as a binary format whose first bytes are not that format's.
fn not_binary(path: &str, expected: &str) -> Error {
    let size = std::fs::metadata(path).map_or(0, |m| m.len());
    let what = if size == 0 {
        "it is empty".to_string()
    } else {
        let mut head = [0u8; 16];
        let n = std::fs::File::open(path)
            .and_then(|mut f| f.read(&mut head))
            .unwrap_or(0);
        let text: String = String::from_utf8_lossy(&head[..n])
            .chars()
            .map(|c| if c.is_control() { '.' } else { c })
            .collect();
        format!("its {size} bytes start with '{text}'")
    };
    let signature = if expected == "HDF5" {
        "the HDF5 signature \\x89HDF"
    } else {
        "HIC\\0"
    };
    Error::format(
        path,
        format!(
            "not a{} {expected} file: {what}, not {signature} (truncated while downloading, or \
             another format under this name?)",
            if expected == "HDF5" { "n" } else { "" }
        ),
    )
}

/// The resolutions (bin sizes in bp, ascending) of a multi-resolution file: an `.mcool`'s
/// levels, a `.hic`'s resolutions; empty for a single cooler, a HiCExplorer file or a text
/// table.
///
/// ```
/// use contactmap::io::list_resolutions;
///
/// assert_eq!(list_resolutions("data/cooler_test_file.mcool")?, [100000, 1000000]);
/// assert!(list_resolutions("data/yeast.10kb.cool")?.is_empty());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn list_resolutions(path: &str) -> Result<Vec<u64>> {
    match detect_kind(path)? {
        FileKind::Hdf5 => match cool::inspect(path)? {
            cool::HdfContent::Multires(resolutions) => Ok(resolutions),
            cool::HdfContent::Cooler => Ok(Vec::new()),
        },
        FileKind::Hic => hic::HicReader::list_resolutions(Path::new(path)),
        FileKind::Text => Ok(Vec::new()),
    }
}

/// A multi-resolution map's levels: each bin size with its reader.
pub type Levels = Vec<(u64, Box<dyn MatrixReader>)>;

/// Every resolution of the map at `path`, coarse or fine as the file lists them: an `.mcool`'s
/// or a `.hic`'s levels, or a single-resolution map's one (its bins must be of one size). Each
/// level with its bin size and its reader; with the file's kind. What a multi-resolution viewer
/// (`serve`, Python's `tiles`) opens.
///
/// ```
/// use contactmap::io::{FileKind, open_levels};
///
/// let (kind, levels) = open_levels("data/cooler_test_file.mcool")?;
/// assert_eq!(kind, FileKind::Hdf5);
/// let resolutions: Vec<u64> = levels.iter().map(|(r, _)| *r).collect();
/// assert_eq!(resolutions, [100000, 1000000]);
/// assert_eq!(open_levels("data/yeast.10kb.cool")?.1[0].0, 10000);
/// assert!(open_levels("data/cooler_variable_bins_test_file.cool").is_err());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn open_levels(path: &str) -> Result<(FileKind, Levels)> {
    let kind = detect_kind(path)?;
    let resolutions = list_resolutions(path)?;
    if resolutions.is_empty() {
        let reader = open_matrix(path, &OpenOptions::default())?;
        let Some(resolution) = reader.bins().resolution() else {
            return Err(Error::Argument(format!(
                "{path}: its bins are not of one size (a multi-resolution view needs fixed bins)"
            )));
        };
        return Ok((kind, vec![(resolution, reader)]));
    }
    let levels = resolutions
        .into_iter()
        .map(|resolution| {
            let options = OpenOptions {
                resolution: Some(resolution),
                ..OpenOptions::default()
            };
            Ok((resolution, open_matrix(path, &options)?))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((kind, levels))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(resolution: u64) -> OpenOptions {
        OpenOptions {
            resolution: Some(resolution),
            ..OpenOptions::default()
        }
    }

    fn message(uri: &str, resolution: u64) -> String {
        match open_matrix(uri, &at(resolution)) {
            Ok(_) => panic!("{uri} opened at {resolution}"),
            Err(e) => {
                assert!(matches!(e, Error::Argument(_)), "{e:?}");
                e.to_string()
            }
        }
    }

    #[test]
    fn the_resolution_option_opens_the_level_the_uri_would() {
        let uri = "data/cooler_test_file.mcool::/resolutions/100000";
        let by_uri = open_matrix(uri, &OpenOptions::default()).unwrap();
        let by_option = open_matrix("data/cooler_test_file.mcool", &at(100_000)).unwrap();
        assert_eq!(by_option.source(), by_uri.source());
        assert_eq!(by_option.totals().unwrap(), by_uri.totals().unwrap());
        // the same resolution both ways is no conflict
        assert!(open_matrix(uri, &at(100_000)).is_ok());
    }

    #[test]
    fn a_resolution_that_the_file_cannot_give_is_a_parameter_error() {
        let m = message(
            "data/cooler_test_file.mcool::/resolutions/100000",
            1_000_000,
        );
        assert!(m.contains("names the resolution 100000"), "{m}");
        let m = message("data/cooler_test_file.mcool", 5_000);
        assert!(
            m.contains("has no resolution 5000: it has 100000, 1000000"),
            "{m}"
        );
        let m = message("data/CN.mm9.10000kb.cool", 5_000);
        assert!(m.contains("holds one resolution, 10000000 bp"), "{m}");
        let m = message("data/hg19.GM12878-MboI.matrix.2000kb.bg2.gz", 2_000_000);
        assert!(m.contains("text table"), "{m}");
        assert!(message("data/CN.mm9.10000kb.cool", 0).contains("positive"));
    }
}
