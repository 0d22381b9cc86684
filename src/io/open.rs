//! Opening a matrix by its URI: the file and group of a URI, the kind of a file from its first
//! bytes, the reader it needs ([`open_matrix`]), and text inputs (plain, gzip or standard input).

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

use super::{InMemory, MatrixReader, cool, hic, hicexplorer, text};

/// Split `cool.mcool::/resolutions/1000` into the file path and the group path (if any).
pub fn split_uri(uri: &str) -> (&str, Option<&str>) {
    match uri.split_once("::") {
        Some((path, group)) => (path, Some(group)),
        None => (uri, None),
    }
}

/// The on-disk kind of a matrix file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// HDF5: .cool / .mcool.
    Hdf5,
    /// Juicer .hic.
    Hic,
    /// Anything else: a text table, maybe gzip-compressed.
    Text,
}

/// Recognise a file by its first bytes (`-`, stdin, is always text).
pub fn detect_kind(path: &str) -> Result<FileKind> {
    if path == "-" {
        return Ok(FileKind::Text);
    }
    let mut file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut magic = [0u8; 8];
    let mut n = 0;
    while n < magic.len() {
        match file.read(&mut magic[n..]).map_err(|e| Error::io(path, e))? {
            0 => break,
            k => n += k,
        }
    }
    Ok(if n >= 8 && &magic == b"\x89HDF\r\n\x1a\n" {
        FileKind::Hdf5
    } else if n >= 4 && &magic[..4] == b"HIC\0" {
        FileKind::Hic
    } else {
        FileKind::Text
    })
}

/// Options for opening inputs that do not carry their own bin table (text tables, pairs).
#[derive(Clone, Debug, Default)]
pub struct OpenOptions {
    /// Text format; guessed from the extension and the first data line when `None`.
    pub text_format: Option<text::TextFormat>,
    /// Bin size for pairs and for BG2 / COO tables given with `chrom_sizes`.
    pub bin_size_bp: Option<u64>,
    /// Chromosome sizes file (`name<TAB>length`).
    pub chrom_sizes: Option<PathBuf>,
    /// Bin table BED (`chrom start end`), for COO and dense tables.
    pub bins_bed: Option<PathBuf>,
    /// 1-based columns of chrom1, pos1, chrom2, pos2 in a pairs file (default: from the
    /// `#columns:` header, else the 4DN layout 2, 3, 4, 5).
    pub pairs_columns: Option<[usize; 4]>,
    /// Pairs positions are 0-based (cooler `cload pairs --zero-based`); default 1-based, as the
    /// 4DN pairs specification and cooler's default.
    pub pairs_zero_based: bool,
}

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

/// Parse `/resolutions/N` (or a bare `N`) in a URI.
pub fn parse_resolution_group(uri: &str, group: &str) -> Result<u64> {
    let trimmed = group.trim_start_matches('/');
    let number = trimmed.strip_prefix("resolutions/").unwrap_or(trimmed);
    number.parse::<u64>().map_err(|_| {
        Error::format(
            uri,
            format!("'{group}' is not a resolution path (expected /resolutions/<bin size>)"),
        )
    })
}

/// Open a text file for reading line by line: `-` is standard input; gzip is detected from the
/// content (the magic bytes), whatever the extension.
pub fn open_text(path: &Path) -> Result<Box<dyn BufRead>> {
    let input: Box<dyn Read> = if path == Path::new("-") {
        Box::new(std::io::stdin())
    } else {
        Box::new(std::fs::File::open(path).map_err(|e| Error::io(path, e))?)
    };
    let mut reader = BufReader::new(input);
    let gzip = reader
        .fill_buf()
        .map_err(|e| Error::io(path, e))?
        .starts_with(&[0x1f, 0x8b]);
    Ok(if gzip {
        Box::new(BufReader::new(flate2::read::MultiGzDecoder::new(reader)))
    } else {
        Box::new(reader)
    })
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
