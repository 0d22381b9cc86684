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
/// text table (`-` for stdin).
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
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn open_matrix(uri: &str, options: &OpenOptions) -> Result<Box<dyn MatrixReader>> {
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
