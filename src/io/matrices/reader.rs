//! The interface every matrix reader implements ([`MatrixReader`]), its metadata, and the
//! reader of a matrix held in memory ([`InMemory`]).

use std::ops::Range;

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

impl MatrixInfo {
    /// The genome assembly the file names (cooler's `genome-assembly`, the .hic `genome_id`),
    /// when it is a name (not empty, `unknown` or a path such as a .hic's chrom.sizes file).
    ///
    /// ```
    /// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
    /// let reader = open_matrix("data/cooler_test_file.mcool::/resolutions/100000", &OpenOptions::default())?;
    /// assert_eq!(reader.info().assembly().as_deref(), Some("dm6"));
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn assembly(&self) -> Option<String> {
        self.attributes
            .iter()
            .find(|(k, _)| k == "genome-assembly" || k == "genome_id")
            .and_then(|(_, v)| v.as_str())
            .filter(|id| !id.is_empty() && *id != "unknown" && !id.contains('/'))
            .map(str::to_string)
    }
}

/// A source of pixels: an open file or an in-memory matrix.
///
/// Pixel queries return the stored upper triangle (`bin1 <= bin2`) restricted to `bin1 in rows`
/// and `bin2 in cols`, sorted by `(bin1, bin2)`, in blocks of bounded size.
///
/// Readers are `Send + Sync`: one reader may be queried from several threads at once (`hicrep`
/// reads its two maps side by side; libhdf5's calls still take its one lock, the raw chunks are
/// read with positioned reads).
pub trait MatrixReader: Send + Sync {
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

    /// The number of diagonals the balancing that made weight column `name` left out, as
    /// cooler stores it (the column's `ignore_diags` attribute; `false`, which cooler's API
    /// may store, is 0): the default of cooltools' insulation, directionality, eigs_cis and
    /// coverage. `None` where the column has no such attribute (another format, another
    /// balancer).
    fn stored_ignore_diags(&self, name: &str) -> Option<usize> {
        match self.weight_attribute(name, "ignore_diags")? {
            serde_json::Value::Bool(false) => Some(0),
            value => value.as_u64().map(|n| n as usize),
        }
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

    /// Stream the pixels of whole rows `rows` (every column, as [`MatrixReader::read_pixels`]
    /// gives them), each block handed over to keep: readers that decode every block afresh
    /// (cooler) give their blocks without a copy; by default each block is copied.
    fn read_rows_owned(
        &self,
        rows: Range<usize>,
        sink: &mut dyn FnMut(PixelBlock) -> Result<()>,
    ) -> Result<()> {
        let n = self.bins().n_bins();
        self.read_pixels(rows, 0..n, &mut |block| sink(block.clone()))
    }

    /// Stream the pixels of `rows x cols` as [`MatrixReader::read_pixels`] does, each block
    /// handed over to keep (cooler's without a copy; by default each block is copied).
    fn read_pixels_owned(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.read_pixels(rows, cols, &mut |block| sink(block.clone()))
    }

    /// Hand back a block from [`MatrixReader::read_rows_owned`] that is no longer needed: a reader
    /// that decodes into fresh buffers (cooler) reads its next blocks into it instead of
    /// allocating and zeroing new ones. By default the block is dropped.
    fn recycle(&self, block: PixelBlock) {
        drop(block);
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

/// Hand the rows of an in-memory source to `sink`: each row its bin, its columns and counts (in
/// order), gathered in blocks of at least [`MEMORY_BLOCK_PIXELS`] pixels (a row never split).
pub(crate) fn sink_rows<'a>(
    rows: impl Iterator<Item = (usize, &'a [u32], &'a [f64])>,
    sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
) -> Result<()> {
    let mut block = PixelBlock::with_capacity(MEMORY_BLOCK_PIXELS);
    for (bin1, bin2s, counts) in rows {
        for (&bin2, &count) in bin2s.iter().zip(counts) {
            block.push(bin1 as u64, u64::from(bin2), count);
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
        let rows = rows.map(|bin1| {
            let (bin2s, counts) = self.matrix.row_window(bin1, &cols);
            (bin1, bin2s, counts)
        });
        sink_rows(rows, sink)
    }

    fn totals(&self) -> Result<(u64, f64)> {
        Ok((self.matrix.nnz() as u64, self.matrix.sum()))
    }
}

/// Read `items` in turn with `read` and hand each, with what was read, to `process`, the next
/// item read on another thread meanwhile: reading and processing overlap, and at most two items'
/// data are in memory. Stops at the first error (the processing's first, then the reading's).
///
/// ```
/// use contactmap::io::read_ahead;
///
/// let mut seen = Vec::new();
/// read_ahead(1..=3, |&k| Ok(k * 10), |k, data| {
///     seen.push((k, data));
///     Ok(())
/// })?;
/// assert_eq!(seen, [(1, 10), (2, 20), (3, 30)]);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn read_ahead<I: Send, T: Send>(
    items: impl IntoIterator<Item = I>,
    read: impl Fn(&I) -> Result<T> + Sync,
    process: impl FnMut(I, T) -> Result<()>,
) -> Result<()> {
    read_ahead_by(items, 1, read, process)
}

/// [`read_ahead`] with up to `depth` items read ahead at once (each on its own thread), for
/// readings that leave cores idle part of the time (a serial check after a parallel decoding):
/// at most `depth + 1` items' data are in memory. `depth` 0 reads and processes in turn.
pub fn read_ahead_by<I: Send, T: Send>(
    items: impl IntoIterator<Item = I>,
    depth: usize,
    read: impl Fn(&I) -> Result<T> + Sync,
    mut process: impl FnMut(I, T) -> Result<()>,
) -> Result<()> {
    let read = &read;
    let mut items = items.into_iter();
    let Some(first) = items.next() else {
        return Ok(());
    };
    let data = read(&first)?;
    std::thread::scope(|scope| {
        let mut current = (first, data);
        let mut pending = std::collections::VecDeque::with_capacity(depth);
        loop {
            while pending.len() < depth {
                let Some(item) = items.next() else { break };
                pending.push_back(scope.spawn(move || {
                    let data = read(&item);
                    (item, data)
                }));
            }
            let (item, data) = current;
            process(item, data)?;
            crate::interrupt::check()?;
            let next = match pending.pop_front() {
                Some(reading) => reading
                    .join()
                    .map_err(|_| Error::Invalid("a reading thread panicked".into()))?,
                None => match items.next() {
                    Some(item) => {
                        let data = read(&item);
                        (item, data)
                    }
                    None => return Ok(()),
                },
            };
            current = (next.0, next.1?);
        }
    })
}
