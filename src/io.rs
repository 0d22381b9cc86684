//! Reading and writing contact-matrix files.
//!
//! Every reader implements [`MatrixReader`]: it exposes the bin table, the weight columns and a
//! streaming pixel query that hands sorted [`PixelBlock`]s to a callback, so that callers never need
//! a whole pixel table in memory. [`open_matrix`] picks the reader from the URI:
//!
//! | input | how it is recognised | reader |
//! |---|---|---|
//! | `.cool`, `file.mcool::/resolutions/N`, `file.cool::/GROUP` | HDF5 magic bytes | [`cool`] |
//! | Juicer `.hic` v8 / v9 (`file.hic::/resolutions/N` or `file.hic` for its only resolution) | `HIC\0` magic | [`hic`] |
//! | BG2 / COO pixel tables, pairs, dense matrices (gzip or plain, `-` for stdin) | `--format` or extension | [`text`] |
//!
//! Format modules only read and write: they never compute biology.

pub mod cool;
pub mod hic;
pub mod text;

use std::io::Read;
use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::matrix::{ContactMatrix, CountType, PixelBlock, Weights};

/// Descriptive metadata of an open matrix, for `contactmap info`.
#[derive(Clone, Debug, Default)]
pub struct MatrixInfo {
    /// Format name and version, e.g. `cool (format-version 3)` or `hic (version 9)`.
    pub format: String,
    /// File-level attributes as stored (cooler root attributes, .hic header fields).
    pub attributes: Vec<(String, serde_json::Value)>,
    /// Resolutions available in the file (all of them, for .mcool and .hic).
    pub resolutions: Vec<u64>,
    /// Remarks a user should know, such as weight conventions converted on read.
    pub notes: Vec<String>,
}

/// A source of pixels: an open file or an in-memory matrix.
///
/// Pixel queries return the stored upper triangle (`bin1 <= bin2`) restricted to `bin1 in rows`
/// and `bin2 in cols`, sorted by `(bin1, bin2)`, in blocks of bounded size.
pub trait MatrixReader {
    /// The URI or path the matrix was read from (used in messages).
    fn source(&self) -> &str;

    /// The bin table.
    fn bins(&self) -> &BinTable;

    /// Whether counts are integers or reals.
    fn count_type(&self) -> CountType;

    /// Names of the available weight columns.
    fn weight_names(&self) -> Vec<String>;

    /// The weight column `name`, in cooler's multiplicative convention.
    fn weights(&self, name: &str) -> Result<Weights>;

    /// Format and attributes, for `info`.
    fn info(&self) -> MatrixInfo;

    /// Stream the stored pixels in the rectangle `rows x cols` to `sink`, sorted by
    /// `(bin1, bin2)`. The sink may stop the stream early by returning an error.
    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()>;

    /// Number of stored pixels and sum of their counts (streams every pixel unless the format
    /// stores both).
    fn totals(&self) -> Result<(u64, f64)> {
        let n = self.bins().n_bins();
        let (mut nnz, mut sum) = (0u64, 0.0f64);
        self.read_pixels(0..n, 0..n, &mut |block| {
            nnz += block.len() as u64;
            sum += block.count.iter().sum::<f64>();
            Ok(())
        })?;
        Ok((nnz, sum))
    }
}

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
pub fn open_matrix(uri: &str, options: &OpenOptions) -> Result<Box<dyn MatrixReader>> {
    let (path, group) = split_uri(uri);
    match detect_kind(path)? {
        FileKind::Hdf5 => Ok(Box::new(cool::CoolReader::open(uri)?)),
        FileKind::Hic => {
            let resolution = match group {
                None => None,
                Some(g) => Some(parse_resolution_group(uri, g)?),
            };
            Ok(Box::new(hic::HicReader::open(Path::new(path), resolution)?))
        }
        FileKind::Text => {
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

/// A [`ContactMatrix`] held in memory, behind the [`MatrixReader`] interface.
#[derive(Debug)]
pub struct InMemory {
    source: String,
    matrix: ContactMatrix,
}

impl InMemory {
    /// Wrap `matrix`, read from `source`.
    pub fn new(source: String, matrix: ContactMatrix) -> Self {
        InMemory { source, matrix }
    }

    /// The matrix.
    pub fn matrix(&self) -> &ContactMatrix {
        &self.matrix
    }
}

/// Pixels handed to a sink per block by in-memory sources.
const MEMORY_BLOCK_PIXELS: usize = 1 << 16;

impl MatrixReader for InMemory {
    fn source(&self) -> &str {
        &self.source
    }

    fn bins(&self) -> &BinTable {
        self.matrix.bins()
    }

    fn count_type(&self) -> CountType {
        self.matrix.count_type()
    }

    fn weight_names(&self) -> Vec<String> {
        self.matrix
            .weights()
            .iter()
            .map(|w| w.name.clone())
            .collect()
    }

    fn weights(&self, name: &str) -> Result<Weights> {
        self.matrix
            .weight(name)
            .cloned()
            .ok_or_else(|| Error::format(&self.source, format!("no weight column '{name}'")))
    }

    fn info(&self) -> MatrixInfo {
        MatrixInfo {
            format: "text table (read into memory)".into(),
            ..MatrixInfo::default()
        }
    }

    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        let mut block = PixelBlock::with_capacity(MEMORY_BLOCK_PIXELS);
        for bin1 in rows {
            let (bin2s, counts) = self.matrix.row(bin1);
            let lo = bin2s.partition_point(|&c| (c as usize) < cols.start);
            let hi = bin2s.partition_point(|&c| (c as usize) < cols.end);
            for k in lo..hi {
                block.push(bin1 as u64, bin2s[k] as u64, counts[k]);
            }
            if block.len() >= MEMORY_BLOCK_PIXELS {
                sink(&block)?;
                block.clear();
            }
        }
        if !block.is_empty() {
            sink(&block)?;
        }
        Ok(())
    }

    fn totals(&self) -> Result<(u64, f64)> {
        Ok((self.matrix.nnz() as u64, self.matrix.sum()))
    }
}

/// Read every pixel of `reader` into a [`ContactMatrix`] (with all its weight columns).
pub fn load_matrix(reader: &dyn MatrixReader) -> Result<ContactMatrix> {
    let mut builder = crate::matrix::MatrixBuilder::new(reader.bins().clone(), reader.count_type());
    let n = reader.bins().n_bins();
    reader.read_pixels(0..n, 0..n, &mut |block| {
        for k in 0..block.len() {
            builder.push(block.bin1[k], block.bin2[k], block.count[k])?;
        }
        Ok(())
    })?;
    for name in reader.weight_names() {
        builder.add_weights(reader.weights(&name)?)?;
    }
    Ok(builder.build())
}
