//! The pixels of a matrix for the algorithms: loaded into memory when they fit a budget, else
//! streamed from the file on every pass; and that budget (`8G`, half of the RAM by default).

use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::matrix::pixels::{BYTES_PER_PIXEL, PixelSlice, PixelSource, Pixels};
use crate::matrix::{ContactMatrix, CountType, PixelBlock};

use super::reader::{MatrixReader, sink_rows};

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

impl LoadedPixels<'_> {
    /// `reader`'s pixels served from this copy when it holds them in memory (the same pixels,
    /// without reading and decoding the file again; everything else asked of `reader`); `None`
    /// when its pixels are streamed or were folded from both triangles (read `reader` then).
    /// `reader` must be the one these pixels were loaded from.
    pub fn reader<'s>(&'s self, reader: &'s dyn MatrixReader) -> Option<impl MatrixReader + 's> {
        match self {
            LoadedPixels::Memory(pixels) if !reader.stores_both_triangles() => {
                Some(MemoryReader { reader, pixels })
            }
            _ => None,
        }
    }
}

/// A reader whose pixels come from memory ([`LoadedPixels::reader`]).
struct MemoryReader<'s> {
    reader: &'s dyn MatrixReader,
    pixels: &'s Pixels,
}

impl MatrixReader for MemoryReader<'_> {
    forward_reader_metadata!(reader);

    fn read_pixels(
        &self,
        rows: std::ops::Range<usize>,
        cols: std::ops::Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        let all = self.pixels.as_slice();
        let first = all.bin1.partition_point(|&b| (b as usize) < rows.start);
        let last = all.bin1.partition_point(|&b| (b as usize) < rows.end);
        let wanted = PixelSlice {
            bin1: &all.bin1[first..last],
            bin2: &all.bin2[first..last],
            count: &all.count[first..last],
        };
        let rows = wanted.rows().map(|(row, run)| {
            let columns = &wanted.bin2[run.clone()];
            let from = run.start + columns.partition_point(|&j| (j as usize) < cols.start);
            let to = run.start + columns.partition_point(|&j| (j as usize) < cols.end);
            (row, &wanted.bin2[from..to], &wanted.count[from..to])
        });
        sink_rows(rows, sink)
    }

    fn read_stored_pixels(
        &self,
        rows: std::ops::Range<usize>,
        cols: std::ops::Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.read_pixels(rows, cols, sink)
    }
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

    fn in_memory(&self) -> Option<PixelSlice<'_>> {
        match self {
            LoadedPixels::Memory(p) => p.in_memory(),
            LoadedPixels::Streamed(_) => None,
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
            return Err(Error::Argument(format!(
                "'{text}' is not a memory size (expected e.g. 8G, 512M)"
            )));
        }
    };
    let value: f64 = number.parse().map_err(|_| {
        Error::Argument(format!(
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
