//! Writing `.cool` and `.mcool` files (cooler format-version 3).

use std::path::{Path, PathBuf};

use hdf5::types::{FixedAscii, VarLenUnicode};

use super::chunk_writer::{ChunkValue, ChunkedColumn};
use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::io::matrices::reader::MatrixReader;
use crate::io::plumbing::atomic::with_temporary;
use crate::matrix::{CountType, PixelBlock, Weights, invert_weight};

/// Elements per HDF5 chunk of the pixel columns (128 KiB of `int64` before compression).
const PIXEL_CHUNK: usize = 16_384;

/// deflate level cooler uses.
const DEFLATE_LEVEL: u8 = 6;

/// Options for the cooler writer.
#[derive(Clone, Debug, Default)]
pub struct CoolWriteOptions {
    /// `genome-assembly` attribute (cooler writes "unknown" when not known).
    pub assembly: Option<String>,
    /// Copy these weight columns from the input (all of them when `None`); only at the input's
    /// own resolution (coarsened levels carry no weights, as with `cooler zoomify`).
    pub weight_columns: Option<Vec<String>>,
}

/// Write `reader`'s matrix to a single-resolution `.cool` at `path`.
///
/// The file is written to a temporary name beside `path` and renamed when complete.
///
/// # Examples
///
/// A matrix built in memory, written and read back.
///
/// ```
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::cool::{write_cool, CoolWriteOptions};
/// use contactmap::io::{load_matrix, open_matrix, InMemory, MatrixReader, OpenOptions};
/// use contactmap::matrix::{CountType, MatrixBuilder, Weights};
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 500), Chrom::new("chr2", 300)], 100)?;
/// let mut builder = MatrixBuilder::new(bins, CountType::Integer);
/// builder.push(0, 0, 5.0)?;
/// builder.push(1, 4, 2.0)?;
/// builder.push(2, 6, 1.0)?; // a trans pixel
/// builder.add_weights(Weights {
///     name: "weight".into(),
///     values: vec![1.0, 0.5, f64::NAN, 1.0, 2.0, 1.0, 1.0, 1.0],
///     provenance: None,
/// })?;
/// let matrix = InMemory::new("example".into(), builder.build());
/// let dir = std::env::temp_dir().join(format!("contactmap-write-cool-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("example.cool");
/// let options = CoolWriteOptions { assembly: Some("toy".into()), ..CoolWriteOptions::default() };
/// write_cool(&matrix, &path, &options)?;
/// let back = load_matrix(&*open_matrix(path.to_str().unwrap(), &OpenOptions::default())?)?;
/// assert_eq!(back.bins(), matrix.bins());
/// assert_eq!((back.get(0, 0), back.get(1, 4), back.get(2, 6)), (5.0, 2.0, 1.0));
/// assert_eq!((back.nnz(), back.sum()), (3, 8.0));
/// let weight = &back.weight("weight").expect("copied").values;
/// assert_eq!(weight[4], 2.0);
/// assert!(weight[2].is_nan());
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_cool(
    reader: &dyn MatrixReader,
    path: &Path,
    options: &CoolWriteOptions,
) -> Result<()> {
    check_chroms(reader)?;
    with_temporary(path, super::hdf5_file::create_excl, |tmp, file| {
        let root = file
            .as_group()
            .map_err(|e| Error::hdf5(tmp, "opening the root group", e))?;
        let mut writer = GroupWriter::create(tmp, &root, reader, reader.bins())?;
        let n = reader.bins().n_bins();
        reader.read_pixels(0..n, 0..n, &mut |block| writer.append(block))?;
        let weights = selected_weights(reader, options)?;
        writer.finish(&weights, options)?;
        file.close()
            .map_err(|e| Error::hdf5(tmp, "closing the file", e))
    })
}

/// Write `reader`'s matrix to a multi-resolution `.mcool` at `path`, one cooler per resolution in
/// `resolutions` under `/resolutions/<bin size>`. Each resolution must be a multiple of the input's
/// bin size; the coarser levels are made by summing pixels (as `cooler zoomify`), in one pass over
/// the input.
///
/// # Examples
///
/// The mm9 map at 10, 20 and 50 Mb: the coarse levels hold the pixels that hictk's writer made
/// of the same map (`data/CN.mm9.multires.hic`, totals in `data/reference/totals.tsv`).
///
/// ```
/// use contactmap::io::cool::{write_mcool, CoolWriteOptions};
/// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
///
/// let options = OpenOptions::default();
/// let input = open_matrix("data/CN.mm9.10000kb.cool", &options)?;
/// let dir = std::env::temp_dir().join(format!("contactmap-write-mcool-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("mm9.mcool");
/// let resolutions = [10_000_000, 20_000_000, 50_000_000];
/// write_mcool(&*input, &path, &resolutions, &CoolWriteOptions::default())?;
/// for (resolution, n_bins, nnz) in [(20_000_000, 145, 10_585), (50_000_000, 65, 2_145)] {
///     let uri = format!("{}::/resolutions/{resolution}", path.display());
///     let level = open_matrix(&uri, &options)?;
///     assert_eq!(level.bins().n_bins(), n_bins);
///     assert_eq!(level.totals()?, (nnz, 499_864_755.0));
/// }
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_mcool(
    reader: &dyn MatrixReader,
    path: &Path,
    resolutions: &[u64],
    options: &CoolWriteOptions,
) -> Result<()> {
    let base_bins = reader.bins();
    let Some(base) = base_bins.resolution() else {
        return Err(Error::Unsupported(format!(
            "{}: .mcool needs fixed-size bins; this matrix has variable bins",
            reader.source()
        )));
    };
    let mut resolutions = resolutions.to_vec();
    resolutions.sort_unstable();
    resolutions.dedup();
    if resolutions.is_empty() {
        resolutions.push(base);
    }
    for &r in &resolutions {
        if r % base != 0 {
            return Err(Error::Argument(format!(
                "resolution {r} is not a multiple of the input's bin size {base}"
            )));
        }
    }
    check_chroms(reader)?;
    with_temporary(path, super::hdf5_file::create_excl, |tmp, file| {
        write_str_attr(tmp, &file, "format", "HDF5::MCOOL")?;
        write_int_attr(tmp, &file, "format-version", 2)?;
        write_str_attr(tmp, &file, "bin-type", "fixed")?;
        let group = file
            .create_group("resolutions")
            .map_err(|e| Error::hdf5(tmp, "creating /resolutions", e))?;
        let mut levels = Vec::with_capacity(resolutions.len());
        for &r in &resolutions {
            let level_group = group
                .create_group(&r.to_string())
                .map_err(|e| Error::hdf5(tmp, format!("creating /resolutions/{r}"), e))?;
            let bins = base_bins.coarsen(r / base)?;
            let coarsener = Coarsener::new(base_bins, &bins);
            let writer = GroupWriter::create(tmp, &level_group, reader, &bins)?;
            levels.push((r, coarsener, writer));
        }
        let n = base_bins.n_bins();
        reader.read_pixels(0..n, 0..n, &mut |block| {
            for (r, coarsener, writer) in levels.iter_mut() {
                if *r == base {
                    writer.append(block)?;
                } else {
                    coarsener.push(block, writer)?;
                }
            }
            Ok(())
        })?;
        let weights = selected_weights(reader, options)?;
        for (r, mut coarsener, mut writer) in levels {
            if r == base {
                writer.finish(&weights, options)?;
            } else {
                coarsener.flush(&mut writer)?;
                writer.finish(&[], options)?;
            }
        }
        file.close()
            .map_err(|e| Error::hdf5(tmp, "closing the file", e))
    })
}

fn selected_weights(reader: &dyn MatrixReader, options: &CoolWriteOptions) -> Result<Vec<Weights>> {
    let names = match &options.weight_columns {
        Some(names) => names.clone(),
        None => reader.weight_names(),
    };
    names.iter().map(|name| reader.weights(name)).collect()
}

/// Maps pixels of a fine fixed bin table to a coarser one, summing them row by row.
struct Coarsener {
    /// Coarse bin of every fine bin.
    coarse_of: Vec<u64>,
    /// Coarse row being accumulated and its `(bin2, count)` entries.
    row: Option<u64>,
    entries: Vec<(u64, f64)>,
}

impl Coarsener {
    fn new(fine: &BinTable, coarse: &BinTable) -> Self {
        let coarse_of = fine
            .iter()
            .map(|bin| coarse.bin_at(bin.chrom_id, bin.start) as u64)
            .collect();
        Coarsener {
            coarse_of,
            row: None,
            entries: Vec::new(),
        }
    }

    /// Add fine pixels (sorted by fine bin1, hence by coarse bin1).
    fn push(&mut self, block: &PixelBlock, writer: &mut GroupWriter) -> Result<()> {
        for k in 0..block.len() {
            let coarse = |bin: u64| {
                usize::try_from(bin)
                    .ok()
                    .and_then(|b| self.coarse_of.get(b))
            };
            let (Some(&i), Some(&j)) = (coarse(block.bin1[k]), coarse(block.bin2[k])) else {
                return Err(Error::format(
                    &writer.source,
                    format!(
                        "pixel ({}, {}) is out of range ({} bins)",
                        block.bin1[k],
                        block.bin2[k],
                        self.coarse_of.len()
                    ),
                ));
            };
            if self.row != Some(i) {
                self.flush(writer)?;
                self.row = Some(i);
            }
            self.entries.push((j, block.count[k]));
        }
        Ok(())
    }

    /// Emit the accumulated row, summed and sorted.
    fn flush(&mut self, writer: &mut GroupWriter) -> Result<()> {
        let Some(row) = self.row.take() else {
            return Ok(());
        };
        self.entries.sort_unstable_by_key(|&(j, _)| j);
        let mut block = PixelBlock::with_capacity(self.entries.len());
        for &(j, c) in &self.entries {
            if block.bin2.last() == Some(&j) {
                *block.count.last_mut().expect("a pixel") += c;
            } else {
                block.push(row, j, c);
            }
        }
        self.entries.clear();
        writer.append(&block)
    }
}

/// The count column: cooler's `int32` for integer counts, else `float64`.
enum CountColumn {
    Integer(ChunkedColumn<i32>),
    Float(ChunkedColumn<f64>),
}

/// Writes one cooler group, streaming pixel blocks into resizable chunked datasets.
struct GroupWriter {
    path: PathBuf,
    /// The input's name, for errors in its pixels.
    source: String,
    group: hdf5::Group,
    bins: BinTable,
    count_type: CountType,
    bin1: ChunkedColumn<i64>,
    bin2: ChunkedColumn<i64>,
    count: CountColumn,
    n_pixels: usize,
    row_counts: Vec<u64>,
    sum: f64,
    last: Option<(u64, u64)>,
}

impl GroupWriter {
    /// A writer into `group` of the pixels of `reader` over `bins` (the reader's own bins or a
    /// coarser table of them).
    fn create(
        path: &Path,
        group: &hdf5::Group,
        reader: &dyn MatrixReader,
        bins: &BinTable,
    ) -> Result<Self> {
        let count_type = reader.count_type();
        let err = |what: &str| {
            let what = what.to_string();
            move |e| Error::hdf5(path, what, e)
        };
        let pixels = group
            .create_group("pixels")
            .map_err(err("creating pixels"))?;
        let column = |name: &str, int: bool| {
            let builder = pixels.new_dataset_builder();
            let builder = if int {
                builder.empty::<i64>()
            } else {
                builder.empty::<f64>()
            };
            builder
                .shape(0..)
                .chunk(PIXEL_CHUNK)
                .shuffle()
                .deflate(DEFLATE_LEVEL)
                .create(name)
                .map_err(err(&format!("creating pixels/{name}")))
        };
        fn chunked<T: ChunkValue>(
            path: &Path,
            name: &str,
            dataset: hdf5::Dataset,
        ) -> ChunkedColumn<T> {
            ChunkedColumn::new(
                path,
                &format!("pixels/{name}"),
                dataset,
                PIXEL_CHUNK,
                DEFLATE_LEVEL,
            )
        }
        let bin1 = chunked(path, "bin1_id", column("bin1_id", true)?);
        let bin2 = chunked(path, "bin2_id", column("bin2_id", true)?);
        let count = match count_type {
            CountType::Integer => CountColumn::Integer(chunked(
                path,
                "count",
                pixels
                    .new_dataset_builder()
                    .empty::<i32>()
                    .shape(0..)
                    .chunk(PIXEL_CHUNK)
                    .shuffle()
                    .deflate(DEFLATE_LEVEL)
                    .create("count")
                    .map_err(err("creating pixels/count"))?,
            )),
            CountType::Float => CountColumn::Float(chunked(path, "count", column("count", false)?)),
        };
        Ok(GroupWriter {
            path: path.to_path_buf(),
            source: reader.source().to_string(),
            group: group.clone(),
            bins: bins.clone(),
            count_type,
            bin1,
            bin2,
            count,
            n_pixels: 0,
            row_counts: vec![0; bins.n_bins()],
            sum: 0.0,
            last: None,
        })
    }

    /// Append sorted pixels.
    fn append(&mut self, block: &PixelBlock) -> Result<()> {
        if block.is_empty() {
            return Ok(());
        }
        let n_bins = self.bins.n_bins() as u64;
        for k in 0..block.len() {
            let key = (block.bin1[k], block.bin2[k]);
            if key.0 > key.1 || key.1 >= n_bins {
                return Err(Error::format(
                    &self.source,
                    format!(
                        "pixel ({}, {}) is below the diagonal or out of range ({n_bins} bins)",
                        key.0, key.1
                    ),
                ));
            }
            if self.last.is_some_and(|last| last >= key) {
                return Err(Error::format(
                    &self.source,
                    format!(
                        "pixels are not sorted by (bin1, bin2) or are duplicated at pixel {}: a \
                         .cool needs them sorted and unique",
                        pixel_name(&self.bins, key.0, key.1)
                    ),
                ));
            }
            self.last = Some(key);
            self.row_counts[key.0 as usize] += 1;
        }
        let hi = self.n_pixels + block.len();
        self.bin1.extend(block.bin1.iter().map(|&b| b as i64))?;
        self.bin2.extend(block.bin2.iter().map(|&b| b as i64))?;
        match &mut self.count {
            CountColumn::Integer(column) => {
                let mut counts = Vec::with_capacity(block.len());
                for (k, &c) in block.count.iter().enumerate() {
                    // (a cast and back: fract() is a libm call on baseline x86-64; NaN fails)
                    let fits = (i32::MIN as f64..=i32::MAX as f64).contains(&c);
                    if !fits || (c as i32) as f64 != c {
                        return Err(Error::format(
                            &self.source,
                            format!(
                                "pixel {}: count {c} does not fit cooler's int32 count column \
                                 (whole numbers from {} to {})",
                                pixel_name(&self.bins, block.bin1[k], block.bin2[k]),
                                i32::MIN,
                                i32::MAX
                            ),
                        ));
                    }
                    counts.push(c as i32);
                }
                column.extend(counts)?;
            }
            CountColumn::Float(column) => column.extend(block.count.iter().copied())?,
        }
        self.sum += block.count.iter().sum::<f64>();
        self.n_pixels = hi;
        Ok(())
    }

    /// Write chroms, bins (with `weights`), indexes and attributes.
    fn finish(mut self, weights: &[Weights], options: &CoolWriteOptions) -> Result<()> {
        self.bin1.finish()?;
        self.bin2.finish()?;
        match &mut self.count {
            CountColumn::Integer(column) => column.finish()?,
            CountColumn::Float(column) => column.finish()?,
        };
        let path = self.path.as_path();
        let group = &self.group;
        let err = |what: &str| {
            let what = what.to_string();
            move |e| Error::hdf5(path, what, e)
        };
        let bins = &self.bins;
        // chroms
        let chroms = group
            .create_group("chroms")
            .map_err(err("creating chroms"))?;
        let names: Vec<&str> = bins.chroms().iter().map(|c| c.name.as_str()).collect();
        write_fixed_strings(path, &chroms, "name", &names)?;
        // check_chroms refused any length past i32::MAX before the file was created
        let lengths: Vec<i32> = bins.chroms().iter().map(|c| c.length_bp as i32).collect();
        write_column(path, &chroms, "length", &lengths)?;
        // bins
        let bins_group = group.create_group("bins").map_err(err("creating bins"))?;
        let (mut chrom_ids, mut starts, mut ends) = (Vec::new(), Vec::new(), Vec::new());
        for bin in bins.iter() {
            chrom_ids.push(bin.chrom_id as i32);
            starts.push(bin.start as i32);
            ends.push(bin.end as i32);
        }
        let chrom_dataset = write_column(path, &bins_group, "chrom", &chrom_ids)?;
        write_str_attr(path, &chrom_dataset, "enum_path", "/chroms/name")?;
        write_column(path, &bins_group, "start", &starts)?;
        write_column(path, &bins_group, "end", &ends)?;
        for w in weights {
            if w.values.len() != bins.n_bins() {
                return Err(Error::format(
                    &self.source,
                    format!(
                        "weight column '{}' has {} values for {} bins",
                        w.name,
                        w.values.len(),
                        bins.n_bins()
                    ),
                ));
            }
            // cooler divides by KR / VC / VC_SQRT whatever their attributes say: store those divisive.
            let divisive = super::weights::DIVISIVE_BY_NAME.contains(&w.name.as_str());
            let dataset = if divisive {
                let inverted: Vec<f64> = w.values.iter().map(|&v| invert_weight(v)).collect();
                write_column(path, &bins_group, &w.name, &inverted)?
            } else {
                write_column(path, &bins_group, &w.name, &w.values)?
            };
            dataset
                .new_attr::<bool>()
                .create("divisive_weights")
                .and_then(|a| a.write_scalar(&divisive))
                .map_err(|e| {
                    Error::hdf5(path, format!("writing bins/{}.divisive_weights", w.name), e)
                })?;
        }
        // indexes
        let indexes = group
            .create_group("indexes")
            .map_err(err("creating indexes"))?;
        let chrom_offsets: Vec<i64> = bins.chrom_offsets().iter().map(|&o| o as i64).collect();
        write_column(path, &indexes, "chrom_offset", &chrom_offsets)?;
        let mut bin1_offsets = Vec::with_capacity(bins.n_bins() + 1);
        let mut total = 0i64;
        bin1_offsets.push(0);
        for &n in &self.row_counts {
            total += n as i64;
            bin1_offsets.push(total);
        }
        write_column(path, &indexes, "bin1_offset", &bin1_offsets)?;
        // attributes, as cooler 0.11 writes them
        write_str_attr(path, group, "format", "HDF5::Cooler")?;
        write_int_attr(path, group, "format-version", 3)?;
        write_str_attr(
            path,
            group,
            "format-url",
            "https://github.com/open2c/cooler",
        )?;
        write_str_attr(
            path,
            group,
            "generated-by",
            concat!("contactmap-", env!("CARGO_PKG_VERSION")),
        )?;
        write_str_attr(path, group, "creation-date", &iso_timestamp_now())?;
        write_str_attr(
            path,
            group,
            "genome-assembly",
            options.assembly.as_deref().unwrap_or("unknown"),
        )?;
        write_str_attr(path, group, "metadata", "{}")?;
        match bins.resolution() {
            Some(size) => {
                write_str_attr(path, group, "bin-type", "fixed")?;
                write_int_attr(path, group, "bin-size", size as i64)?;
            }
            None => {
                write_str_attr(path, group, "bin-type", "variable")?;
                write_str_attr(path, group, "bin-size", "null")?;
            }
        }
        write_str_attr(path, group, "storage-mode", "symmetric-upper")?;
        write_int_attr(path, group, "nbins", bins.n_bins() as i64)?;
        write_int_attr(path, group, "nchroms", bins.n_chroms() as i64)?;
        write_int_attr(path, group, "nnz", self.n_pixels as i64)?;
        match self.count_type {
            CountType::Integer => write_int_attr(path, group, "sum", self.sum as i64)?,
            CountType::Float => {
                let attr = group
                    .new_attr::<f64>()
                    .create("sum")
                    .map_err(err("creating attribute sum"))?;
                attr.write_scalar(&self.sum)
                    .map_err(err("writing attribute sum"))?;
            }
        }
        Ok(())
    }
}

fn write_column<T: hdf5::H5Type>(
    path: &Path,
    group: &hdf5::Group,
    name: &str,
    values: &[T],
) -> Result<hdf5::Dataset> {
    let builder = group.new_dataset_builder().with_data(values);
    let builder = if values.is_empty() {
        builder
    } else {
        builder
            .chunk(values.len().min(1 << 16))
            .shuffle()
            .deflate(DEFLATE_LEVEL)
    };
    builder
        .create(name)
        .map_err(|e| Error::hdf5(path, format!("writing {name}"), e))
}

/// The chromosomes of `reader` fit cooler's `chroms` columns (names ASCII and at most 255 bytes
/// long, lengths within int32): checked before anything is written, naming the input and the
/// chromosome.
fn check_chroms(reader: &dyn MatrixReader) -> Result<()> {
    for (id, chrom) in reader.bins().chroms().iter().enumerate() {
        if chrom.name.len() > 255 || !chrom.name.is_ascii() {
            return Err(Error::format(
                reader.source(),
                format!(
                    "chromosome {} '{}' cannot be written to a .cool: cooler's chromosome names \
                     must be ASCII and at most 255 bytes long",
                    id + 1,
                    chrom.name.escape_default()
                ),
            ));
        }
        if i32::try_from(chrom.length_bp).is_err() {
            return Err(Error::format(
                reader.source(),
                format!(
                    "chromosome {} ({} bp) is too long for cooler's int32 lengths (at most {} bp)",
                    chrom.name.escape_default(),
                    chrom.length_bp,
                    i32::MAX
                ),
            ));
        }
    }
    Ok(())
}

/// A pixel as `(bin1, bin2) chrom:start-end x chrom:start-end` (bin ids alone when out of range).
fn pixel_name(bins: &BinTable, bin1: u64, bin2: u64) -> String {
    let n_bins = bins.n_bins() as u64;
    if bin1 >= n_bins || bin2 >= n_bins {
        return format!("({bin1}, {bin2})");
    }
    let region = |id: u64| {
        let bin = bins.bin(id as usize);
        format!(
            "{}:{}-{}",
            bins.chroms()[bin.chrom_id].name,
            bin.start,
            bin.end
        )
    };
    format!("({bin1}, {bin2}) {} x {}", region(bin1), region(bin2))
}

fn write_fixed_strings(
    path: &Path,
    group: &hdf5::Group,
    name: &str,
    values: &[&str],
) -> Result<()> {
    let longest = values.iter().map(|s| s.len()).max().unwrap_or(1);
    if longest > 255 || !values.iter().all(|s| s.is_ascii()) {
        return Err(Error::format(
            path,
            format!(
                "{name}: strings must be ASCII and at most 255 bytes long (found '{}')",
                values
                    .iter()
                    .find(|s| s.len() > 255 || !s.is_ascii())
                    .unwrap_or(&"")
                    .escape_default()
            ),
        ));
    }
    macro_rules! write_as {
        ($n:literal) => {{
            let fixed = values
                .iter()
                .map(|s| FixedAscii::<$n>::from_ascii(s.as_bytes()))
                .collect::<std::result::Result<Vec<_>, _>>()
                .map_err(|e| Error::format(path, format!("{name}: {e}")))?;
            write_column(path, group, name, &fixed).map(|_| ())
        }};
    }
    match longest {
        0..=32 => write_as!(32),
        33..=64 => write_as!(64),
        65..=128 => write_as!(128),
        _ => write_as!(255),
    }
}

fn write_str_attr(path: &Path, location: &hdf5::Location, name: &str, value: &str) -> Result<()> {
    let value: VarLenUnicode = value.parse().map_err(|e| {
        Error::format(
            path,
            format!("attribute {name} '{}': {e}", value.escape_default()),
        )
    })?;
    location
        .new_attr::<VarLenUnicode>()
        .create(name)
        .and_then(|a| a.write_scalar(&value))
        .map_err(|e| Error::hdf5(path, format!("writing attribute {name}"), e))
}

fn write_int_attr(path: &Path, location: &hdf5::Location, name: &str, value: i64) -> Result<()> {
    location
        .new_attr::<i64>()
        .create(name)
        .and_then(|a| a.write_scalar(&value))
        .map_err(|e| Error::hdf5(path, format!("writing attribute {name}"), e))
}

/// The current UTC time as `YYYY-MM-DDTHH:MM:SS.ffffff` (the form cooler writes).
fn iso_timestamp_now() -> String {
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default();
    let seconds = now.as_secs() as i64;
    let (days, rem) = (seconds.div_euclid(86_400), seconds.rem_euclid(86_400));
    let (year, month, day) = civil_from_days(days);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}.{:06}",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60,
        now.subsec_micros()
    )
}

/// Gregorian date of a day count since 1970-01-01 (Howard Hinnant's algorithm).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::Chrom;
    use crate::io::MatrixInfo;

    /// A reader that hands out its pixels as listed, in one block (sorted or not).
    struct Listed {
        bins: BinTable,
        pixels: Vec<(u64, u64, f64)>,
    }

    impl MatrixReader for Listed {
        fn source(&self) -> &str {
            "listed.bg2"
        }
        fn bins(&self) -> &BinTable {
            &self.bins
        }
        fn count_type(&self) -> CountType {
            CountType::Integer
        }
        fn weight_names(&self) -> Vec<String> {
            Vec::new()
        }
        fn weights(&self, name: &str) -> Result<Weights> {
            Err(Error::Argument(format!("no weight column '{name}'")))
        }
        fn info(&self) -> MatrixInfo {
            MatrixInfo::default()
        }
        fn read_pixels(
            &self,
            _rows: std::ops::Range<usize>,
            _cols: std::ops::Range<usize>,
            sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
        ) -> Result<()> {
            let mut block = PixelBlock::with_capacity(self.pixels.len());
            for &(bin1, bin2, count) in &self.pixels {
                block.push(bin1, bin2, count);
            }
            sink(&block)
        }
    }

    /// The message of writing `pixels` to a .cool and an .mcool, checking that neither the
    /// output nor a temporary is left behind and that both give the same message.
    fn write_error(pixels: Vec<(u64, u64, f64)>) -> String {
        let bins = BinTable::fixed(vec![Chrom::new("chr1", 30), Chrom::new("chr2", 20)], 10)
            .expect("bins");
        let reader = Listed { bins, pixels };
        let dir = tempfile::TempDir::new().expect("temporary directory");
        let cool = write_cool(
            &reader,
            &dir.path().join("out.cool"),
            &CoolWriteOptions::default(),
        )
        .unwrap_err()
        .to_string();
        let mcool = write_mcool(
            &reader,
            &dir.path().join("out.mcool"),
            &[10],
            &CoolWriteOptions::default(),
        )
        .unwrap_err()
        .to_string();
        assert_eq!(cool, mcool);
        assert_eq!(std::fs::read_dir(dir.path()).expect("listing").count(), 0);
        cool
    }

    #[test]
    fn pixel_errors_name_the_input_and_the_pixel() {
        let sorted = vec![(0, 0, 1.0), (0, 3, 2.0), (1, 4, 3.0)];
        let bins = BinTable::fixed(vec![Chrom::new("chr1", 30), Chrom::new("chr2", 20)], 10)
            .expect("bins");
        let dir = tempfile::TempDir::new().expect("temporary directory");
        let path = dir.path().join("ok.cool");
        let reader = Listed {
            bins,
            pixels: sorted,
        };
        write_cool(&reader, &path, &CoolWriteOptions::default()).expect("sorted pixels");
        assert_eq!(
            write_error(vec![(0, 3, 2.0), (0, 0, 1.0), (1, 4, 3.0)]),
            "listed.bg2: pixels are not sorted by (bin1, bin2) or are duplicated at pixel (0, 0) \
             chr1:0-10 x chr1:0-10: a .cool needs them sorted and unique"
        );
        assert_eq!(
            write_error(vec![(0, 0, 1.0), (1, 4, 3.0), (1, 4, 3.0)]),
            "listed.bg2: pixels are not sorted by (bin1, bin2) or are duplicated at pixel (1, 4) \
             chr1:10-20 x chr2:10-20: a .cool needs them sorted and unique"
        );
        assert_eq!(
            write_error(vec![(0, 0, 1.0), (3, 2, 1.0)]),
            "listed.bg2: pixel (3, 2) is below the diagonal or out of range (5 bins)"
        );
        assert_eq!(
            write_error(vec![(0, 0, 1.0), (0, 5, 1.0)]),
            "listed.bg2: pixel (0, 5) is below the diagonal or out of range (5 bins)"
        );
        // Out of range while coarsening (an .mcool with a coarser level).
        let bins = BinTable::fixed(vec![Chrom::new("chr1", 30), Chrom::new("chr2", 20)], 10)
            .expect("bins");
        let reader = Listed {
            bins,
            pixels: vec![(0, 0, 1.0), (0, 7, 1.0)],
        };
        let error = write_mcool(
            &reader,
            &dir.path().join("out.mcool"),
            &[20],
            &CoolWriteOptions::default(),
        )
        .unwrap_err();
        assert_eq!(
            error.to_string(),
            "listed.bg2: pixel (0, 7) is out of range (5 bins)"
        );
        assert!(!dir.path().join("out.mcool").exists());
        assert_eq!(
            write_error(vec![(0, 0, 1.5)]),
            "listed.bg2: pixel (0, 0) chr1:0-10 x chr1:0-10: count 1.5 does not fit cooler's \
             int32 count column (whole numbers from -2147483648 to 2147483647)"
        );
    }

    #[test]
    fn civil_dates_match_known_days() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(20_778), (2026, 11, 21));
    }
}
