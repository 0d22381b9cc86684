//! HiCExplorer's native `.h5` matrices (HiCMatrix's `h5` format): reader.
//!
//! Layout (HiCMatrix `hicmatrix/lib/h5.py`, written through PyTables with blosc compression):
//!
//! | dataset | content |
//! |---|---|
//! | `matrix/{data,indices,indptr,shape}` | a scipy CSR matrix, `shape = (n, n)` |
//! | `intervals/{chr_list,start_list,end_list,extra_list}` | the `n` bins; `chr_list` fixed-length bytes |
//! | `nan_bins` (optional) | ids of the bins HiCExplorer masks (filtered out by `hicCorrectMatrix`) |
//! | `correction_factors` (optional) | `n` divisive factors, shape `(n,)` or `(n, 1)` |
//! | `distance_counts` (optional) | not read |
//!
//! What the reader makes of it, in contactmap's (and cooler's) conventions:
//!
//! - **Triangle.** HiCMatrix saves the upper triangle (`triu`) by default; some tools
//!   (`hicTransform`) save the full symmetric matrix. Pixels are read row by row and only the
//!   entries with `bin2 >= bin1` are kept: entries below the diagonal are taken as the mirror images
//!   of those above it. Column indices are sorted within each row (scipy does not guarantee sorted
//!   rows) and duplicates summed; stored zeros and `NaN`s are dropped, as HiCMatrix does when it
//!   writes a cooler.
//! - **Bins.** Intervals are 0-based half-open, each bin starting at the previous one's end, as
//!   cooler's; a chromosome's first bin may start after 0 (a matrix cut out of it, which
//!   HiCExplorer writes), read as [`BinTable`]'s cut spans. Bins may have any size; a table whose bins are
//!   all the same size but the last of each chromosome is a fixed-size table. Chromosomes come in
//!   the order of their first bin and must be contiguous. HiCExplorer stores no chromosome lengths:
//!   each chromosome's length is taken as its last bin's end (`info` says so).
//! - **Correction.** After `hicCorrectMatrix`, `matrix/data` holds *corrected* values and
//!   `correction_factors` the divisive factors `c`: `corrected = raw / (c[i] * c[j])`. As
//!   HiCExplorer's own `hicConvertFormat` to cooler does, counts are restored to
//!   `data * c[i] * c[j]` and the factors are exposed inverted, as the multiplicative column
//!   `weight` (`1 / c`), so that cooler's balanced value `count * weight[i] * weight[j]` is the
//!   stored corrected value. Bins whose factor is zero or not finite, and the `nan_bins`, get a
//!   `NaN` weight, cooler's mark of a masked bin (hicConvertFormat writes 0 there, which cooler
//!   and cooltools would take as a valid bin of balanced value 0); a pixel touching such a bin
//!   keeps its stored value (hicCorrectMatrix leaves no pixel on a masked bin).
//! - **Corrupt files.** Every dataset's length is checked against `matrix/shape` and against the
//!   bytes the file holds for it, and its filter pipeline is parsed (blosc: only blosclz, the
//!   codec HiCMatrix uses, is built in), before anything is read; libhdf5's metadata reads run under
//!   the [`hdf5_guard`] deadline, so a damaged file is one error naming the file and the dataset.
//! - **Masked bins.** `nan_bins` are also exposed as their own column `nan_bins` (1 for a kept bin,
//!   `NaN` for a masked one), so that balanced-value commands given `--weight-name nan_bins` skip
//!   them as cooler skips `NaN`-weighted bins.
//!
//! Memory: `indptr` (one integer per bin) is read at open; pixels are read in blocks of whole rows
//! holding about [`BLOCK_PIXELS`] stored entries, so a query never holds the whole matrix.

use std::ops::Range;

use hdf5::types::{TypeDescriptor, VarLenUnicode};

use crate::error::{Error, Result};
use crate::genome::{Bin, BinTable, Chrom};
use crate::io::matrices::reader::{MatrixInfo, MatrixReader};
use crate::io::plumbing::hdf5_guard;
use crate::matrix::{CountType, PixelBlock, Weights, invert_weight};

/// Stored entries read from the file at a time (whole rows; a longer row is read whole).
pub const BLOCK_PIXELS: usize = 1 << 20;

/// Name of the weight column made from `correction_factors`.
pub const CORRECTION_WEIGHT: &str = "weight";

/// Name of the weight column made from `nan_bins`.
pub const NAN_BINS_WEIGHT: &str = "nan_bins";

/// True when the HDF5 file at `path` has HiCExplorer's layout: root groups `matrix` and
/// `intervals`, and none of a cooler's (`pixels`, `bins`, `chroms`, `resolutions`).
pub fn is_hicexplorer(path: &str) -> Result<bool> {
    let file = open_file(path)?;
    Ok(hdf5_guard::guarded(
        path,
        "the root group's members",
        || {
            let has = |name: &str| file.link_exists(name);
            let group = |name: &str| has(name) && file.group(name).is_ok();
            let cooler = ["pixels", "bins", "chroms", "resolutions"]
                .iter()
                .any(|name| has(name));
            !cooler && group("matrix") && group("intervals")
        },
    ))
}

fn open_file(path: &str) -> Result<hdf5::File> {
    if let Err(e) = std::fs::metadata(path) {
        return Err(Error::io(path, e));
    }
    hdf5_guard::guarded(path, "the file's superblock and root group", || {
        crate::io::matrices::cool::file_builder().open(path)
    })
    .map_err(|e| {
        Error::format(
            path,
            format!("not a readable HDF5 file (truncated or corrupt?): {e}"),
        )
    })
}

/// An open HiCExplorer `.h5` matrix.
#[derive(Debug)]
pub struct HicExplorerReader {
    path: String,
    data: hdf5::Dataset,
    indices: hdf5::Dataset,
    indptr: Vec<u64>,
    bins: BinTable,
    count_type: CountType,
    correction_factors: Option<Vec<f64>>,
    nan_bins: Vec<usize>,
    has_nan_bins: bool,
    has_distance_counts: bool,
    attributes: Vec<(String, serde_json::Value)>,
}

impl HicExplorerReader {
    /// Open the HiCExplorer matrix at `path`, reading its bins and row index and checking that
    /// the datasets agree with one another.
    pub fn open(path: &str) -> Result<HicExplorerReader> {
        let file = open_file(path)?;
        let file_len = std::fs::metadata(path)
            .map_err(|e| Error::io(path, e))?
            .len();
        for group in ["matrix", "intervals"] {
            if hdf5_guard::guarded(path, group, || file.group(group)).is_err() {
                return Err(Error::format(
                    path,
                    format!("not a HiCExplorer .h5 matrix: it has no '{group}' group"),
                ));
            }
        }
        let dataset = |name: &str| {
            hdf5_guard::guarded(path, name, || file.dataset(name))
                .map_err(|e| Error::format(path, format!("missing dataset {name}: {e}")))
        };
        // Every length is checked against the others (and against the file's size) before
        // anything is read from it.
        let shape_dataset = dataset("matrix/shape")?;
        let n_shape = hdf5_guard::checked_len(path, &shape_dataset, "matrix/shape", file_len)?;
        if n_shape != 2 {
            return Err(Error::format(
                path,
                format!("matrix/shape has {n_shape} values; expected 2 ([n, n])"),
            ));
        }
        let shape = read_ints(path, &shape_dataset, "matrix/shape")?;
        if shape[0] != shape[1] || shape[0] < 0 {
            return Err(Error::format(
                path,
                format!("matrix/shape is {shape:?}; expected a square matrix [n, n]"),
            ));
        }
        let n_bins = shape[0] as usize;
        let expect_len = |name: &str, wanted: usize, what: &str| -> Result<hdf5::Dataset> {
            let found = dataset(name)?;
            let n_values = hdf5_guard::checked_len(path, &found, name, file_len)?;
            if n_values != wanted {
                return Err(Error::format(
                    path,
                    format!(
                        "{name} has {n_values} values but matrix/shape {shape:?} needs {wanted} ({what})"
                    ),
                ));
            }
            Ok(found)
        };
        for name in [
            "intervals/chr_list",
            "intervals/start_list",
            "intervals/end_list",
        ] {
            expect_len(name, n_bins, "one per bin")?;
        }
        let indptr_dataset = expect_len("matrix/indptr", n_bins + 1, "number of bins + 1")?;
        let bins = read_intervals(path, &file)?;
        if bins.n_bins() != n_bins {
            return Err(Error::format(
                path,
                format!(
                    "matrix/shape is {shape:?} but intervals/ lists {} bins: they must agree",
                    bins.n_bins()
                ),
            ));
        }
        let data = dataset("matrix/data")?;
        let nnz = hdf5_guard::checked_len(path, &data, "matrix/data", file_len)?;
        let indices = dataset("matrix/indices")?;
        let n_indices = hdf5_guard::checked_len(path, &indices, "matrix/indices", file_len)?;
        if n_indices != nnz {
            return Err(Error::format(
                path,
                format!("matrix/indices has {n_indices} entries but matrix/data has {nnz}"),
            ));
        }
        let indptr = read_ints(path, &indptr_dataset, "matrix/indptr")?;
        if let Some(k) = indptr.windows(2).position(|w| w[0] > w[1]) {
            return Err(Error::format(
                path,
                format!(
                    "matrix/indptr decreases at row {k} ({} then {}): not a CSR row index",
                    indptr[k],
                    indptr[k + 1]
                ),
            ));
        }
        if indptr.first() != Some(&0) || indptr.last() != Some(&(nnz as i64)) {
            return Err(Error::format(
                path,
                format!(
                    "matrix/indptr runs from {} to {}; expected 0 to {nnz} (the length of matrix/data)",
                    indptr.first().copied().unwrap_or(0),
                    indptr.last().copied().unwrap_or(0)
                ),
            ));
        }
        let integer_data = matches!(
            hdf5_guard::guarded(path, "the type of matrix/data", || {
                data.dtype().and_then(|t| t.to_descriptor())
            }),
            Ok(TypeDescriptor::Integer(_) | TypeDescriptor::Unsigned(_))
        );

        let exists = |name: &str| hdf5_guard::guarded(path, name, || file.link_exists(name));
        let correction_factors = if exists("correction_factors") {
            let values = expect_len("correction_factors", n_bins, "one per bin")?
                .read_raw::<f64>()
                .map_err(|e| Error::hdf5(path, "reading correction_factors", e))?;
            Some(values)
        } else {
            None
        };
        let has_nan_bins = exists("nan_bins");
        let mut nan_bins = Vec::new();
        if has_nan_bins {
            let nan_bins_dataset = dataset("nan_bins")?;
            let n_nan_bins =
                hdf5_guard::checked_len(path, &nan_bins_dataset, "nan_bins", file_len)?;
            if n_nan_bins > n_bins {
                return Err(Error::format(
                    path,
                    format!("nan_bins lists {n_nan_bins} bins, more than the {n_bins} bins"),
                ));
            }
            for value in read_ints(path, &nan_bins_dataset, "nan_bins")? {
                if value < 0 || value >= n_bins as i64 {
                    return Err(Error::format(
                        path,
                        format!("nan_bins lists bin {value}, outside the {n_bins} bins"),
                    ));
                }
                nan_bins.push(value as usize);
            }
            nan_bins.sort_unstable();
            nan_bins.dedup();
        }
        let count_type = if integer_data && correction_factors.is_none() {
            CountType::Integer
        } else {
            CountType::Float
        };
        Ok(HicExplorerReader {
            path: path.to_string(),
            data,
            indices,
            indptr: indptr.into_iter().map(|v| v as u64).collect(),
            bins,
            count_type,
            correction_factors,
            nan_bins,
            has_nan_bins,
            has_distance_counts: exists("distance_counts"),
            attributes: read_string_attributes(path, &file),
        })
    }

    /// The bins HiCExplorer masks (`nan_bins`), sorted; empty when the file has none.
    pub fn nan_bins(&self) -> &[usize] {
        &self.nan_bins
    }

    /// The divisive correction factors as stored, when the file has them.
    pub fn correction_factors(&self) -> Option<&[f64]> {
        self.correction_factors.as_deref()
    }

    /// The multiplicative weight of each bin: `1 / correction_factor`, `NaN` for masked bins.
    fn correction_weights(&self, factors: &[f64]) -> Vec<f64> {
        let mut values: Vec<f64> = factors.iter().map(|&c| invert_weight(c)).collect();
        for &bin in &self.nan_bins {
            values[bin] = f64::NAN;
        }
        values
    }

    /// Read the stored entries of rows `rows` (whole rows) as (column, value) per row.
    fn read_rows(&self, rows: Range<usize>) -> Result<(Vec<i64>, Vec<f64>)> {
        let lo = self.indptr[rows.start] as usize;
        let hi = self.indptr[rows.end] as usize;
        let columns = self
            .indices
            .read_slice_1d::<i64, _>(lo..hi)
            .map_err(|e| Error::hdf5(&self.path, format!("reading matrix/indices[{lo}..{hi}]"), e))?
            .to_vec();
        let values = self
            .data
            .read_slice_1d::<f64, _>(lo..hi)
            .map_err(|e| Error::hdf5(&self.path, format!("reading matrix/data[{lo}..{hi}]"), e))?
            .to_vec();
        Ok((columns, values))
    }

    /// Turn the stored entries of one row into sorted upper-triangle pixels within `cols`.
    fn row_pixels(
        &self,
        row: usize,
        columns: &[i64],
        values: &[f64],
        cols: &Range<usize>,
        scratch: &mut Vec<(u64, f64)>,
        block: &mut PixelBlock,
    ) -> Result<()> {
        let n_bins = self.bins.n_bins();
        scratch.clear();
        for (&column, &value) in columns.iter().zip(values) {
            if column < 0 || column >= n_bins as i64 {
                return Err(Error::format(
                    &self.path,
                    format!(
                        "matrix/indices: row {row} has column {column}, outside the {n_bins} bins"
                    ),
                ));
            }
            let column = column as usize;
            if column >= row && cols.contains(&column) && value != 0.0 && !value.is_nan() {
                scratch.push((column as u64, value));
            }
        }
        if !scratch.windows(2).all(|w| w[0].0 < w[1].0) {
            scratch.sort_by_key(|&(column, _)| column);
        }
        let factor = |bin: usize| {
            self.correction_factors
                .as_ref()
                .map(|c| c[bin])
                .filter(|c| c.is_finite() && *c > 0.0)
        };
        let row_factor = factor(row);
        let mut previous: Option<u64> = None;
        for &(column, value) in scratch.iter() {
            let count = match (self.correction_factors.is_some(), row_factor) {
                (false, _) => value,
                (true, Some(ci)) => match factor(column as usize) {
                    Some(cj) => value * ci * cj,
                    None => value,
                },
                (true, None) => value,
            };
            if previous == Some(column) {
                if let Some(last) = block.count.last_mut() {
                    *last += count;
                }
            } else {
                block.push(row as u64, column, count);
                previous = Some(column);
            }
        }
        Ok(())
    }
}

impl MatrixReader for HicExplorerReader {
    fn source(&self) -> &str {
        &self.path
    }

    fn bins(&self) -> &BinTable {
        &self.bins
    }

    fn count_type(&self) -> CountType {
        self.count_type
    }

    fn weight_names(&self) -> Vec<String> {
        let mut names = Vec::new();
        if self.has_nan_bins {
            names.push(NAN_BINS_WEIGHT.to_string());
        }
        if self.correction_factors.is_some() {
            names.push(CORRECTION_WEIGHT.to_string());
        }
        names
    }

    fn weights(&self, name: &str) -> Result<Weights> {
        match (name, &self.correction_factors) {
            (CORRECTION_WEIGHT, Some(factors)) => Ok(Weights {
                name: name.to_string(),
                values: self.correction_weights(factors),
                provenance: Some(
                    "HiCExplorer correction_factors (divisive), inverted to multiplicative on read"
                        .to_string(),
                ),
            }),
            (NAN_BINS_WEIGHT, _) if self.has_nan_bins => {
                let mut values = vec![1.0; self.bins.n_bins()];
                for &bin in &self.nan_bins {
                    values[bin] = f64::NAN;
                }
                Ok(Weights {
                    name: name.to_string(),
                    values,
                    provenance: Some(
                        "HiCExplorer nan_bins: NaN for a masked bin, 1 elsewhere".to_string(),
                    ),
                })
            }
            _ => {
                let names = self.weight_names();
                Err(Error::format(
                    &self.path,
                    format!(
                        "no weight column '{name}' (available: {})",
                        if names.is_empty() {
                            "none".to_string()
                        } else {
                            names.join(", ")
                        }
                    ),
                ))
            }
        }
    }

    fn info(&self) -> MatrixInfo {
        let mut notes = vec![
            "HiCExplorer stores no chromosome lengths: each chromosome's length is its last bin's end"
                .to_string(),
            "the CSR matrix is read through its upper triangle (bin1 <= bin2); entries below the diagonal (full matrices, as hicTransform saves) are taken as mirror images"
                .to_string(),
        ];
        if self.correction_factors.is_some() {
            notes.push(
                "matrix/data holds corrected values: counts are restored as data * c[i] * c[j] from the divisive correction_factors c, which are exposed inverted (1 / c, cooler's multiplicative convention) as the weight column 'weight', as hicConvertFormat does"
                    .to_string(),
            );
        }
        if self.has_nan_bins {
            notes.push(format!(
                "{} nan_bins (bins HiCExplorer masks) are NaN in the weight column 'nan_bins' (1 elsewhere){}",
                self.nan_bins.len(),
                if self.correction_factors.is_some() {
                    " and in 'weight'"
                } else {
                    ""
                }
            ));
        }
        if self.has_distance_counts {
            notes.push("distance_counts is present and not read".to_string());
        }
        MatrixInfo {
            format: "HiCExplorer h5 (HiCMatrix CSR)".to_string(),
            attributes: self.attributes.clone(),
            resolutions: self.bins.resolution().into_iter().collect(),
            notes,
        }
    }

    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        let n_bins = self.bins.n_bins();
        let rows = rows.start.min(n_bins)..rows.end.min(n_bins);
        let cols = cols.start.min(n_bins)..cols.end.min(n_bins);
        if rows.is_empty() || cols.is_empty() {
            return Ok(());
        }
        let mut block = PixelBlock::with_capacity(BLOCK_PIXELS.min(1 << 16));
        let mut scratch = Vec::new();
        let mut first = rows.start;
        while first < rows.end {
            // Whole rows holding at most BLOCK_PIXELS stored entries (at least one row).
            let limit = self.indptr[first] + BLOCK_PIXELS as u64;
            let mut last = first + 1;
            while last < rows.end && self.indptr[last + 1] <= limit {
                last += 1;
            }
            let (columns, values) = self.read_rows(first..last)?;
            let base = self.indptr[first] as usize;
            for row in first..last {
                let lo = self.indptr[row] as usize - base;
                let hi = self.indptr[row + 1] as usize - base;
                self.row_pixels(
                    row,
                    &columns[lo..hi],
                    &values[lo..hi],
                    &cols,
                    &mut scratch,
                    &mut block,
                )?;
            }
            if block.len() >= BLOCK_PIXELS / 2 {
                sink(&block)?;
                block.clear();
            }
            first = last;
        }
        if !block.is_empty() {
            sink(&block)?;
        }
        Ok(())
    }
}

/// Read an integer dataset of any integer width.
fn read_ints(path: &str, dataset: &hdf5::Dataset, name: &str) -> Result<Vec<i64>> {
    dataset
        .read_raw::<i64>()
        .map_err(|e| Error::hdf5(path, format!("reading {name}"), e))
}

/// Read `intervals/` into a bin table: chromosomes in order of first appearance, each as long as
/// its last bin's end.
fn read_intervals(path: &str, file: &hdf5::File) -> Result<BinTable> {
    let dataset = |name: &str| {
        hdf5_guard::guarded(path, name, || file.dataset(name))
            .map_err(|e| Error::format(path, format!("missing dataset {name}: {e}")))
    };
    let names =
        hdf5_guard::read_strings(path, &dataset("intervals/chr_list")?, "intervals/chr_list")?;
    let starts = read_ints(
        path,
        &dataset("intervals/start_list")?,
        "intervals/start_list",
    )?;
    let ends = read_ints(path, &dataset("intervals/end_list")?, "intervals/end_list")?;
    if names.len() != starts.len() || starts.len() != ends.len() {
        return Err(Error::format(
            path,
            format!(
                "intervals/chr_list, start_list and end_list differ in length ({}, {}, {})",
                names.len(),
                starts.len(),
                ends.len()
            ),
        ));
    }
    let mut chroms: Vec<Chrom> = Vec::new();
    let mut bins = Vec::with_capacity(names.len());
    for (k, name) in names.into_iter().enumerate() {
        let (start, end) = (starts[k], ends[k]);
        if start < 0 || end <= start {
            return Err(Error::format(
                path,
                format!("intervals row {k}: {name}:{start}-{end} is not a valid bin"),
            ));
        }
        let chrom_id = match chroms.last() {
            Some(last) if last.name == name => chroms.len() - 1,
            _ => {
                if chroms.iter().any(|c| c.name == name) {
                    return Err(Error::format(
                        path,
                        format!(
                            "intervals row {k}: chromosome {name} appears again after other chromosomes; its bins must be contiguous"
                        ),
                    ));
                }
                chroms.push(Chrom::new(name, 0));
                chroms.len() - 1
            }
        };
        let chrom = &mut chroms[chrom_id];
        chrom.length_bp = chrom.length_bp.max(end as u64);
        bins.push(Bin {
            chrom_id,
            start: start as u64,
            end: end as u64,
        });
    }
    BinTable::from_bins(chroms, &bins, None)
        .map_err(|e| Error::format(path, format!("intervals: {e}")))
}

/// The root attributes that PyTables writes as strings (TITLE, VERSION, ...), for `info`.
fn read_string_attributes(path: &str, file: &hdf5::File) -> Vec<(String, serde_json::Value)> {
    let Ok(names) = hdf5_guard::guarded(path, "the attribute names", || file.attr_names()) else {
        return Vec::new();
    };
    let mut attributes = Vec::new();
    for name in names {
        let read = || {
            let Ok(attr) = file.attr(&name) else {
                return None;
            };
            read_string_attribute(&attr)
        };
        if let Some(value) = hdf5_guard::guarded(path, &format!("attribute '{name}'"), read) {
            attributes.push((name, serde_json::Value::from(value)));
        }
    }
    attributes
}

/// The value of a string attribute; `None` for other types or unreadable values.
fn read_string_attribute(attr: &hdf5::Attribute) -> Option<String> {
    match attr.dtype().and_then(|t| t.to_descriptor()) {
        Ok(TypeDescriptor::FixedAscii(_)) => attr
            .read_scalar::<hdf5::types::FixedAscii<4096>>()
            .ok()
            .map(|s| {
                hdf5_guard::lossy(s.as_bytes())
                    .trim_end_matches('\0')
                    .to_string()
            }),
        Ok(TypeDescriptor::FixedUnicode(_)) => attr
            .read_scalar::<hdf5::types::FixedUnicode<4096>>()
            .ok()
            .map(|s| {
                hdf5_guard::lossy(s.as_bytes())
                    .trim_end_matches('\0')
                    .to_string()
            }),
        Ok(TypeDescriptor::VarLenUnicode) => attr
            .read_scalar::<VarLenUnicode>()
            .ok()
            .map(|s| hdf5_guard::lossy(s.as_bytes())),
        _ => None,
    }
}

#[cfg(test)]
mod tests;
