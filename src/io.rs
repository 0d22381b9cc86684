//! Reading and writing contact-matrix files.
//!
//! Every reader implements [`MatrixReader`]: it exposes the bin table, the weight columns and a
//! streaming pixel query that hands sorted [`PixelBlock`]s to a callback, so that callers never need
//! a whole pixel table in memory. [`open_matrix`] picks the reader from the URI:
//!
//! | input | how it is recognised | reader |
//! |---|---|---|
//! | `.cool`, `file.mcool::/resolutions/N`, `file.cool::/GROUP` | HDF5 magic bytes | [`cool`] |
//! | HiCExplorer / HiCMatrix `.h5` (CSR `matrix/` + `intervals/`) | HDF5 magic bytes, root groups `matrix` and `intervals`, no cooler group | [`hicexplorer`] |
//! | Juicer `.hic` v8 / v9 (`file.hic::/resolutions/N` or `file.hic` for its only resolution) | `HIC\0` magic | [`hic`] |
//! | BG2 / COO pixel tables, pairs, dense matrices (gzip or plain, `-` for stdin) | `--format` or extension | [`text`] |
//!
//! Protein inputs have their own readers: [`structure`] (PDB / mmCIF) and [`predictions`]
//! (CASP RR, CCMpred / PSICOV matrices, `i j score` tables, trRosetta `.npz`, `.npy` distance
//! maps).
//!
//! Format modules only read and write: they never compute biology.

pub mod atomic;
pub mod bed;
pub mod cool;
pub mod fasta;
pub mod hdf5_guard;
pub mod hic;
pub mod hicexplorer;
pub mod info;
pub mod merged;
pub mod output;
pub mod predictions;
pub mod structure;
pub mod tables;
pub mod text;

use std::io::{BufRead, BufReader, Read};
use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::matrix::pixels::{PixelSlice, PixelSource, Pixels, BYTES_PER_PIXEL};
use crate::matrix::{ContactMatrix, CountType, PixelBlock, Weights};

pub use atomic::{is_special_file, same_file, Temporary, WriteLock};

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
    ///
    /// # Examples
    ///
    /// The dm6 `.mcool` carries cooler's ICE `weight` and Juicer's divisive `KR`, `VC`, ... as
    /// hic2cool stored them: every column reads multiplicative.
    ///
    /// ```
    /// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
    ///
    /// let uri = "data/cooler_test_file.mcool::/resolutions/100000";
    /// let reader = open_matrix(uri, &OpenOptions::default())?;
    /// let vc = reader.weights("VC")?;
    /// let stored = reader.stored_weights("VC")?; // divisive, as in the file
    /// assert_eq!(vc.values.len(), reader.bins().n_bins());
    /// for (w, v) in vc.values.iter().zip(&stored.values) {
    ///     assert!(w.is_nan() && !(*v > 0.0) || (w * v - 1.0).abs() < 1e-12);
    /// }
    /// assert!(reader.weights("no such column").is_err());
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    fn weights(&self, name: &str) -> Result<Weights>;

    /// The weight column `name` as the file stores it: divisive columns (Juicer's convention)
    /// not inverted, as `cooler dump -t bins` prints them. Only for showing; compute with
    /// [`MatrixReader::weights`].
    fn stored_weights(&self, name: &str) -> Result<Weights> {
        self.weights(name)
    }

    /// Format and attributes, for `info`.
    fn info(&self) -> MatrixInfo;

    /// Attribute `key` of weight column `name` (cooler stores the balancing parameters there:
    /// `ignore_diags`, `converged` ...); `None` where the format has none.
    fn weight_attribute(&self, _name: &str, _key: &str) -> Option<serde_json::Value> {
        None
    }

    /// Stream the stored pixels in the rectangle `rows x cols` to `sink`, sorted by
    /// `(bin1, bin2)`. The sink may stop the stream early by returning an error.
    ///
    /// # Examples
    ///
    /// The chr2L box of `data/reference/dm6_100kb.chr2L_box.balanced.join.tsv` (`cooler dump
    /// --join --balanced -r chr2L:1,000,000-3,000,000 -r2 chr2L:2,000,000-5,000,000`): its first
    /// pixel is `(chr2L:1.0-1.1 Mb, chr2L:2.0-2.1 Mb)`, count 541, balanced 0.00723358.
    ///
    /// ```
    /// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
    ///
    /// let uri = "data/cooler_test_file.mcool::/resolutions/100000";
    /// let reader = open_matrix(uri, &OpenOptions::default())?;
    /// let rows = reader.bins().parse_region_bins("chr2L:1,000,000-3,000,000")?;
    /// let cols = reader.bins().parse_region_bins("chr2L:2,000,000-5,000,000")?;
    /// let weights = reader.weights("weight")?.values;
    /// let mut pixels = Vec::new();
    /// reader.read_pixels(rows.clone(), cols.clone(), &mut |block| {
    ///     for k in 0..block.len() {
    ///         pixels.push((block.bin1[k] as usize, block.bin2[k] as usize, block.count[k]));
    ///     }
    ///     Ok(())
    /// })?;
    /// assert!(pixels.windows(2).all(|w| (w[0].0, w[0].1) < (w[1].0, w[1].1)));
    /// assert!(pixels.iter().all(|p| rows.contains(&p.0) && cols.contains(&p.1)));
    /// let (i, j, count) = pixels[0];
    /// assert_eq!((i, j, count), (rows.start, cols.start, 541.0));
    /// assert!((count * weights[i] * weights[j] - 0.00723358).abs() < 1e-8);
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()>;

    /// True when the file stores both triangles of its matrix (cooler `storage-mode: square`):
    /// [`MatrixReader::read_pixels`] then hands out the upper triangle only (what cooltools'
    /// expected and insulation use), [`MatrixReader::read_stored_pixels`] every stored pixel.
    fn stores_both_triangles(&self) -> bool {
        false
    }

    /// Stream every stored pixel of `rows x cols`, sorted by `(bin1, bin2)`: the lower triangle
    /// too where the file stores it ([`MatrixReader::stores_both_triangles`]); otherwise the same
    /// as [`MatrixReader::read_pixels`].
    fn read_stored_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.read_pixels(rows, cols, sink)
    }

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

    /// Warnings about the data read so far (records dropped while reading, for instance), one
    /// line each without the `warning:` prefix; empty for most formats. Commands print them once
    /// their work has succeeded, so that a warning never precedes an error.
    fn warnings(&self) -> Vec<String> {
        Vec::new()
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
            let (bin2s, counts) = self.matrix.row_window(bin1, &cols);
            for (&bin2, &count) in bin2s.iter().zip(counts) {
                block.push(bin1 as u64, bin2 as u64, count);
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

/// Inside `impl MatrixReader for W`, where `self.FIELD` is the wrapped reader: every method but
/// the pixel reads forwarded to it (totals, the stored pixels' sums, included). An adapter that
/// changes the pixels (progress, checks) writes only `read_pixels` and `read_stored_pixels`, and a
/// method added to the trait is forwarded by every adapter at once.
macro_rules! forward_reader_metadata {
    ($field:ident) => {
        fn source(&self) -> &str {
            self.$field.source()
        }

        fn bins(&self) -> &$crate::genome::BinTable {
            self.$field.bins()
        }

        fn count_type(&self) -> $crate::matrix::CountType {
            self.$field.count_type()
        }

        fn weight_names(&self) -> Vec<String> {
            self.$field.weight_names()
        }

        fn weights(&self, name: &str) -> $crate::error::Result<$crate::matrix::Weights> {
            self.$field.weights(name)
        }

        fn stored_weights(&self, name: &str) -> $crate::error::Result<$crate::matrix::Weights> {
            self.$field.stored_weights(name)
        }

        fn info(&self) -> $crate::io::MatrixInfo {
            self.$field.info()
        }

        fn weight_attribute(&self, name: &str, key: &str) -> Option<serde_json::Value> {
            self.$field.weight_attribute(name, key)
        }

        fn stores_both_triangles(&self) -> bool {
            self.$field.stores_both_triangles()
        }

        fn totals(&self) -> $crate::error::Result<(u64, f64)> {
            self.$field.totals()
        }

        fn warnings(&self) -> Vec<String> {
            self.$field.warnings()
        }
    };
}

/// A reader that shows every block of pixels it streams to a callback, then passes it on
/// unchanged: progress bars, running sums beside another job, checks (an error from the callback
/// ends the stream).
///
/// # Examples
///
/// ```
/// use std::sync::atomic::{AtomicUsize, Ordering};
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{InMemory, Inspect, MatrixReader};
/// use contactmap::matrix::{CountType, MatrixBuilder};
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 1_000)], 100)?;
/// let mut builder = MatrixBuilder::new(bins, CountType::Integer);
/// builder.push(0, 3, 2.0)?;
/// builder.push(1, 1, 5.0)?;
/// let matrix = InMemory::new("example".into(), builder.build());
/// let seen = AtomicUsize::new(0);
/// let inspected = Inspect::new(&matrix, |block| {
///     seen.fetch_add(block.len(), Ordering::Relaxed);
///     Ok(())
/// });
/// let n = inspected.bins().n_bins();
/// inspected.read_pixels(0..n, 0..n, &mut |_| Ok(()))?;
/// assert_eq!(seen.load(Ordering::Relaxed), 2);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub struct Inspect<'a, F> {
    inner: &'a dyn MatrixReader,
    on_block: F,
}

impl<'a, F: Fn(&PixelBlock) -> Result<()>> Inspect<'a, F> {
    /// Show the blocks `inner` streams to `on_block`.
    pub fn new(inner: &'a dyn MatrixReader, on_block: F) -> Self {
        Inspect { inner, on_block }
    }
}

impl<F: Fn(&PixelBlock) -> Result<()>> MatrixReader for Inspect<'_, F> {
    forward_reader_metadata!(inner);

    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.inner.read_pixels(rows, cols, &mut |block| {
            (self.on_block)(block)?;
            sink(block)
        })
    }

    fn read_stored_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.inner.read_stored_pixels(rows, cols, &mut |block| {
            (self.on_block)(block)?;
            sink(block)
        })
    }
}

/// A reader whose counts are checked as they stream: the first pixel whose count is negative, NaN
/// or infinite ends the stream with an error naming the file, the pixel's bin ids and
/// coordinates, and its value.
///
/// The analyses (balance, expected, normalize, tads) read through it, so that they never compute
/// on such counts; `dump` and `info` read the file as it is, so that users can look at them. Text
/// tables refuse such counts when they are parsed; this adapter does the same for the binary
/// formats (.cool / .mcool / .hic), one pass over each block's counts as it goes by.
pub struct CheckedCounts {
    inner: Box<dyn MatrixReader>,
}

impl CheckedCounts {
    /// Check the counts of `inner`.
    pub fn new(inner: Box<dyn MatrixReader>) -> Self {
        CheckedCounts { inner }
    }

    /// Fail on the first count of `block` that is not finite and `>= 0`.
    fn check(&self, block: &PixelBlock) -> Result<()> {
        // A branch-free pass over the block; the position is looked for only on failure.
        let valid = block
            .count
            .iter()
            .fold(true, |ok, c| ok & (0.0..=f64::MAX).contains(c));
        if valid {
            return Ok(());
        }
        let k = block
            .count
            .iter()
            .position(|c| !(0.0..=f64::MAX).contains(c))
            .unwrap_or(0);
        Err(self.bad_count(block.bin1[k], block.bin2[k], block.count[k]))
    }

    fn bad_count(&self, bin1: u64, bin2: u64, count: f64) -> Error {
        let bins = self.inner.bins();
        let place = |bin: u64| match usize::try_from(bin) {
            Ok(id) if id < bins.n_bins() => {
                let bin = bins.bin(id);
                format!(
                    "{}:{}-{}",
                    bins.chroms()[bin.chrom_id].name,
                    bin.start,
                    bin.end
                )
            }
            _ => "outside the bin table".to_string(),
        };
        let problem = if count.is_nan() {
            "NaN"
        } else if count.is_infinite() {
            "infinite"
        } else {
            "negative"
        };
        Error::format(
            self.inner.source(),
            format!(
                "pixel bin1_id={bin1} bin2_id={bin2} ({} x {}) has a {problem} count ({count}): \
                 counts must be finite and >= 0 to be analysed (dump shows the pixels as stored)",
                place(bin1),
                place(bin2)
            ),
        )
    }
}

impl MatrixReader for CheckedCounts {
    forward_reader_metadata!(inner);

    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        Inspect::new(self.inner.as_ref(), |block| self.check(block)).read_pixels(rows, cols, sink)
    }

    fn read_stored_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        Inspect::new(self.inner.as_ref(), |block| self.check(block))
            .read_stored_pixels(rows, cols, sink)
    }
}

/// Read every pixel of `reader` into a [`ContactMatrix`] (with all its weight columns).
///
/// # Examples
///
/// ```
/// use contactmap::io::{load_matrix, open_matrix, MatrixReader, OpenOptions};
///
/// let reader = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
/// let matrix = load_matrix(&*reader)?;
/// assert_eq!((matrix.nnz(), matrix.sum()), (38_503, 499_864_755.0));
/// let stored = reader.weights("weight")?.values;
/// let copied = &matrix.weight("weight").expect("the weight column").values;
/// assert!(stored.iter().zip(copied).all(|(a, b)| a.to_bits() == b.to_bits()));
/// // the dense view of chr1 is symmetric
/// let chr1 = matrix.bins().parse_region_bins("chr1")?;
/// let dense = matrix.dense(chr1.clone(), chr1);
/// assert_eq!(dense, dense.t());
/// # Ok::<(), contactmap::Error>(())
/// ```
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

/// The pixels of a matrix for the numerical algorithms: copied into memory when they fit the
/// budget, otherwise streamed from the file on every pass.
pub enum LoadedPixels<'a> {
    /// A compact in-memory copy.
    Memory(Pixels),
    /// Passes stream the file.
    Streamed(StreamedPixels<'a>),
}

/// Load `reader`'s pixels into memory if `nnz * 16 bytes <= max_memory_bytes`, else stream them.
///
/// # Examples
///
/// Both give the same answers: here the coverage of every bin, in one pass.
///
/// ```
/// use contactmap::io::{load_pixels, open_matrix, LoadedPixels, MatrixReader, OpenOptions};
/// use contactmap::matrix::PixelSource;
///
/// let reader = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
/// let n = reader.bins().n_bins();
/// let coverage = |pixels: &LoadedPixels| {
///     pixels.pass(
///         || vec![0.0; n],
///         |mut sums, slice| {
///             for (i, j, count) in slice.iter() {
///                 sums[i] += count;
///                 sums[j] += count;
///             }
///             sums
///         },
///         |a, b| a.iter().zip(&b).map(|(x, y)| x + y).collect(),
///     )
/// };
/// let memory = load_pixels(&*reader, u64::MAX)?;
/// let streamed = load_pixels(&*reader, 0)?;
/// assert!(matches!(memory, LoadedPixels::Memory(_)));
/// assert!(matches!(streamed, LoadedPixels::Streamed(_)));
/// assert_eq!(coverage(&memory)?, coverage(&streamed)?);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn load_pixels(reader: &dyn MatrixReader, max_memory_bytes: u64) -> Result<LoadedPixels<'_>> {
    let (nnz, _) = reader.totals()?;
    if nnz.saturating_mul(BYTES_PER_PIXEL) > max_memory_bytes {
        return Ok(LoadedPixels::Streamed(StreamedPixels { reader }));
    }
    let mut pixels =
        Pixels::with_capacity(reader.bins().clone(), reader.count_type(), nnz as usize)?;
    let n = reader.bins().n_bins();
    reader.read_pixels(0..n, 0..n, &mut |block| {
        pixels
            .extend(block)
            .map_err(|e| Error::format(reader.source(), e.to_string()))
    })?;
    Ok(LoadedPixels::Memory(pixels))
}

/// The pixels balancing reads: [`load_pixels`], except for files that store both triangles
/// (cooler `storage-mode: square`), whose stored pixels are all loaded and folded onto the upper
/// triangle as cooler's balance counts them ([`Pixels::from_folded`]). Those are held in memory
/// whatever `max_memory_bytes`, which they must fit.
///
/// # Examples
///
/// `square.cool` stores both triangles; its folded upper triangle sums to the stored pixels.
///
/// ```
/// use contactmap::io::{load_pixels_for_balancing, open_matrix, LoadedPixels, MatrixReader, OpenOptions};
/// use contactmap::matrix::PixelSource;
///
/// let reader = open_matrix("data/layouts/square.cool", &OpenOptions::default())?;
/// assert!(reader.stores_both_triangles());
/// let n = reader.bins().n_bins();
/// let (mut n_stored, mut stored) = (0, 0.0);
/// reader.read_stored_pixels(0..n, 0..n, &mut |block| {
///     n_stored += block.len();
///     stored += block.count.iter().sum::<f64>();
///     Ok(())
/// })?;
/// let pixels = load_pixels_for_balancing(&*reader, u64::MAX)?;
/// let LoadedPixels::Memory(memory) = &pixels else { panic!("held in memory") };
/// assert_eq!(memory.len(), n_stored); // every stored pixel, each triangle's kept apart
/// let folded = pixels.pass(
///     || 0.0,
///     |sum, slice| sum + slice.iter().map(|(_, _, count)| count).sum::<f64>(),
///     |a, b| a + b,
/// )?;
/// assert_eq!(folded, stored);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn load_pixels_for_balancing(
    reader: &dyn MatrixReader,
    max_memory_bytes: u64,
) -> Result<LoadedPixels<'_>> {
    if !reader.stores_both_triangles() {
        return load_pixels(reader, max_memory_bytes);
    }
    let n = reader.bins().n_bins();
    let mut pixels: Vec<(u32, u32, f64)> = Vec::new();
    reader.read_stored_pixels(0..n, 0..n, &mut |block| {
        if (pixels.len() + block.len()) as u64 * BYTES_PER_PIXEL > max_memory_bytes {
            return Err(Error::format(
                reader.source(),
                format!(
                    "balancing a matrix stored in both triangles (storage-mode square) holds its \
                     pixels in memory: more than the {max_memory_bytes} bytes allowed; raise \
                     --max-memory"
                ),
            ));
        }
        pixels.extend(
            (0..block.len()).map(|k| (block.bin1[k] as u32, block.bin2[k] as u32, block.count[k])),
        );
        Ok(())
    })?;
    let pixels = Pixels::from_folded(reader.bins().clone(), reader.count_type(), pixels)
        .map_err(|e| Error::format(reader.source(), e.to_string()))?;
    Ok(LoadedPixels::Memory(pixels))
}

impl PixelSource for LoadedPixels<'_> {
    fn bins(&self) -> &BinTable {
        match self {
            LoadedPixels::Memory(p) => p.bins(),
            LoadedPixels::Streamed(s) => s.bins(),
        }
    }

    fn count_type(&self) -> CountType {
        match self {
            LoadedPixels::Memory(p) => p.count_type(),
            LoadedPixels::Streamed(s) => s.count_type(),
        }
    }

    fn pass<T, I, F, R>(&self, init: I, fold: F, reduce: R) -> Result<T>
    where
        T: Send,
        I: Fn() -> T + Sync,
        F: Fn(T, PixelSlice<'_>) -> T + Sync,
        R: Fn(T, T) -> T + Sync,
    {
        match self {
            LoadedPixels::Memory(p) => p.pass(init, fold, reduce),
            LoadedPixels::Streamed(s) => s.pass(init, fold, reduce),
        }
    }
}

/// A matrix file whose pixels are streamed from disk on every pass (bounded memory).
pub struct StreamedPixels<'a> {
    reader: &'a dyn MatrixReader,
}

impl<'a> StreamedPixels<'a> {
    /// Stream `reader` on every pass.
    pub fn new(reader: &'a dyn MatrixReader) -> Self {
        StreamedPixels { reader }
    }
}

impl PixelSource for StreamedPixels<'_> {
    fn bins(&self) -> &BinTable {
        self.reader.bins()
    }

    fn count_type(&self) -> CountType {
        self.reader.count_type()
    }

    fn pass<T, I, F, R>(&self, init: I, fold: F, reduce: R) -> Result<T>
    where
        T: Send,
        I: Fn() -> T + Sync,
        F: Fn(T, PixelSlice<'_>) -> T + Sync,
        R: Fn(T, T) -> T + Sync,
    {
        let n = self.reader.bins().n_bins();
        let mut total = Some(init());
        let (mut bin1, mut bin2) = (Vec::new(), Vec::new());
        self.reader.read_pixels(0..n, 0..n, &mut |block| {
            bin1.clear();
            bin2.clear();
            bin1.extend(block.bin1.iter().map(|&b| b as u32));
            bin2.extend(block.bin2.iter().map(|&b| b as u32));
            let slice = PixelSlice {
                bin1: &bin1,
                bin2: &bin2,
                count: &block.count,
            };
            let part = slice.fold(&init, &fold, &reduce);
            total = total.take().map(|t| reduce(t, part));
            Ok(())
        })?;
        Ok(total.unwrap_or_else(&init))
    }
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

/// Parse a memory size such as `8G`, `512M`, `2GiB`, `1000000` (bytes).
pub fn parse_memory_size(text: &str) -> Result<u64> {
    let lower = text.trim().to_ascii_lowercase();
    let digits_end = lower
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(lower.len());
    let (number, unit) = lower.split_at(digits_end);
    let multiplier: u64 = match unit.trim() {
        "" | "b" => 1,
        "k" | "kb" | "kib" => 1 << 10,
        "m" | "mb" | "mib" => 1 << 20,
        "g" | "gb" | "gib" => 1 << 30,
        "t" | "tb" | "tib" => 1 << 40,
        _ => {
            return Err(Error::Invalid(format!(
                "'{text}' is not a memory size (expected e.g. 8G, 512M)"
            )))
        }
    };
    let value: f64 = number.parse().map_err(|_| {
        Error::Invalid(format!(
            "'{text}' is not a memory size (expected e.g. 8G, 512M)"
        ))
    })?;
    Ok((value * multiplier as f64) as u64)
}

/// The default memory budget for in-memory pixel copies: half of the machine's memory
/// (`/proc/meminfo`), or 4 GiB where that cannot be read.
pub fn default_memory_budget() -> u64 {
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("MemTotal:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<u64>().ok())
        })
        .map(|kb| kb * 1024 / 2)
        .unwrap_or(4 << 30)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::Chrom;
    use crate::matrix::MatrixBuilder;

    #[test]
    fn streamed_and_in_memory_passes_agree() {
        let bins = BinTable::fixed(vec![Chrom::new("a", 3000), Chrom::new("b", 2000)], 10).unwrap();
        let mut builder = MatrixBuilder::new(bins, CountType::Integer);
        for i in 0..500u64 {
            for j in (i..500).step_by(3) {
                builder.push(i, j, ((i * 7 + j) % 11) as f64).unwrap();
            }
        }
        let reader = InMemory::new("test".into(), builder.build());
        let pass = |p: &LoadedPixels| {
            p.pass(
                || vec![0.0; 500],
                |mut acc, s| {
                    for (i, j, c) in s.iter() {
                        acc[i] += c;
                        if i != j {
                            acc[j] += c;
                        }
                    }
                    acc
                },
                |mut a, b| {
                    a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
                    a
                },
            )
        };
        let memory = load_pixels(&reader, u64::MAX).unwrap();
        let streamed = load_pixels(&reader, 0).unwrap();
        assert!(matches!(memory, LoadedPixels::Memory(_)));
        assert!(matches!(streamed, LoadedPixels::Streamed(_)));
        let a = pass(&memory).unwrap();
        let b = pass(&streamed).unwrap();
        assert_eq!(a, b);
        assert_eq!(
            a.iter().sum::<f64>(),
            2.0 * reader.matrix().sum() - (0..500).map(|i| reader.matrix().get(i, i)).sum::<f64>()
        );
    }

    /// A reader that hands out one fixed block.
    struct OneBlock {
        bins: BinTable,
        block: PixelBlock,
    }

    impl MatrixReader for OneBlock {
        fn source(&self) -> &str {
            "one.cool"
        }
        fn bins(&self) -> &BinTable {
            &self.bins
        }
        fn count_type(&self) -> CountType {
            CountType::Float
        }
        fn weight_names(&self) -> Vec<String> {
            Vec::new()
        }
        fn weights(&self, name: &str) -> Result<Weights> {
            Err(Error::Invalid(name.into()))
        }
        fn info(&self) -> MatrixInfo {
            MatrixInfo::default()
        }
        fn read_pixels(
            &self,
            _rows: Range<usize>,
            _cols: Range<usize>,
            sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
        ) -> Result<()> {
            sink(&self.block)
        }
        fn warnings(&self) -> Vec<String> {
            vec![format!("{} pixels", self.block.len())]
        }
    }

    #[test]
    fn checked_counts_name_the_first_bad_pixel() {
        let bins = BinTable::fixed(vec![Chrom::new("a", 30), Chrom::new("b", 25)], 10).unwrap();
        for (bad, what) in [
            (-2.0, "negative count (-2)"),
            (f64::NAN, "NaN count (NaN)"),
            (f64::INFINITY, "infinite count (inf)"),
            (f64::NEG_INFINITY, "infinite count (-inf)"),
        ] {
            let mut block = PixelBlock::with_capacity(4);
            block.push(0, 0, 1.0);
            block.push(1, 4, bad);
            block.push(3, 4, -1.0);
            let reader = CheckedCounts::new(Box::new(OneBlock {
                bins: bins.clone(),
                block,
            }));
            let mut seen = 0;
            let error = reader
                .read_pixels(0..5, 0..5, &mut |b| {
                    seen += b.len();
                    Ok(())
                })
                .unwrap_err()
                .to_string();
            assert_eq!(seen, 0, "a bad block never reaches the sink");
            assert_eq!(reader.warnings(), vec!["3 pixels".to_string()]);
            assert!(
                error.starts_with(&format!(
                    "one.cool: pixel bin1_id=1 bin2_id=4 (a:10-20 x b:10-20) has a {what}"
                )),
                "{error}"
            );
        }
        let mut block = PixelBlock::with_capacity(2);
        block.push(0, 0, 0.0);
        block.push(0, 1, f64::MAX);
        let reader = CheckedCounts::new(Box::new(OneBlock { bins, block }));
        let mut seen = 0;
        reader
            .read_pixels(0..5, 0..5, &mut |b| {
                seen += b.len();
                Ok(())
            })
            .unwrap();
        assert_eq!(seen, 2);
    }

    #[test]
    fn memory_sizes_parse() {
        assert_eq!(parse_memory_size("8G").unwrap(), 8 << 30);
        assert_eq!(parse_memory_size("512m").unwrap(), 512 << 20);
        assert_eq!(parse_memory_size("1.5GiB").unwrap(), 3 << 29);
        assert!(parse_memory_size("lots").is_err());
    }
}
