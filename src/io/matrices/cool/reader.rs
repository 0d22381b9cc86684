//! Reading a cooler: the bin table, weight columns (divisive ones inverted), attributes and
//! streamed pixel queries.

use std::fs::File;
use std::ops::Range;
use std::path::Path;
use std::sync::Mutex;

use hdf5::types::{TypeDescriptor, VarLenAscii, VarLenUnicode};

use super::chunks::{self, Column};
use super::hdf5_file::{file_builder, file_len};
use super::weights::DIVISIVE_BY_NAME;
use crate::error::{Error, Result};
use crate::genome::{Bin, BinTable, Chrom};
use crate::io::matrices::reader::{MatrixInfo, MatrixReader, read_ahead};
use crate::io::plumbing::hdf5_guard;
use crate::matrix::{CountType, PixelBlock, Weights};

/// Maximum number of pixels in one streamed block.
pub const BLOCK_PIXELS: usize = 1 << 20;

/// The most blocks a reader keeps to read into again: one being read ahead, one being handed
/// over, one spare.
const SPARE_BLOCKS: usize = 3;

/// Juicer's SCALE vector: divisive when hic2cool wrote it, although cooler reads it as multiplicative.
const HIC2COOL_SCALE: &str = "SCALE";

/// Where a block's rows come from: the `bin1_id` column (read and checked against the index:
/// the streamed analyses), or `indexes/bin1_offset` alone (the rectangle queries, as cooler's
/// range queries take them: one column less to inflate).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RowSource {
    Column,
    Index,
}

/// An open cooler (one resolution).
#[derive(Debug)]
pub struct CoolReader {
    pub(super) uri: String,
    pub(super) path: String,
    pub(super) group: hdf5::Group,
    pub(super) raw: File,
    pub(super) bins: BinTable,
    pub(super) bin1_offsets: Vec<u64>,
    pub(super) attributes: Vec<(String, serde_json::Value)>,
    pub(super) format_version: i64,
    pub(super) weight_columns: Vec<String>,
    pub(super) bin1: Column,
    pub(super) bin2: Column,
    pub(super) count: Column,
    /// `storage-mode: square`: both triangles are stored.
    pub(super) square: bool,
    /// Blocks handed back ([`MatrixReader::recycle`]), read into again (at most
    /// [`SPARE_BLOCKS`]).
    pub(super) spare: Mutex<Vec<PixelBlock>>,
    /// Remarks on the layout for `info` (an index one entry short, ...).
    pub(super) layout_notes: Vec<String>,
}

/// What a URI without a group points to in an HDF5 file.
#[derive(Debug)]
pub enum HdfContent {
    /// A single cooler at the root.
    Cooler,
    /// A multi-resolution file with these resolutions (ascending).
    Multires(Vec<u64>),
}

/// Inspect the root of an HDF5 file: a cooler, or an .mcool with its resolutions.
pub fn inspect(path: &str) -> Result<HdfContent> {
    let file = open_file(path)?;
    if file.link_exists("resolutions") {
        let group = file
            .group("resolutions")
            .map_err(|e| Error::hdf5(path, "opening /resolutions", e))?;
        Ok(HdfContent::Multires(list_resolutions(path, &group)?))
    } else {
        Ok(HdfContent::Cooler)
    }
}

fn list_resolutions(path: &str, group: &hdf5::Group) -> Result<Vec<u64>> {
    let names = group
        .member_names()
        .map_err(|e| Error::hdf5(path, "listing /resolutions", e))?;
    let mut resolutions: Vec<u64> = names.iter().filter_map(|n| n.parse().ok()).collect();
    resolutions.sort_unstable();
    Ok(resolutions)
}

fn open_file(path: &str) -> Result<hdf5::File> {
    if let Err(e) = std::fs::metadata(path) {
        return Err(Error::io(path, e));
    }
    crate::io::plumbing::hdf5_guard::guarded(path, "the file's superblock and root group", || {
        file_builder().open(path)
    })
    .map_err(|e| {
        Error::format(
            path,
            format!("not a readable HDF5 file (truncated or corrupt?): {e}"),
        )
    })
}

fn resolutions_text(resolutions: &[u64]) -> String {
    resolutions
        .iter()
        .map(|r| r.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

impl CoolReader {
    /// Open the cooler at `uri` (`file.cool`, `file.mcool::/resolutions/N`, `file.cool::/group`).
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::io::cool::CoolReader;
    /// use contactmap::io::MatrixReader;
    /// let reader = CoolReader::open("data/cooler_test_file.mcool::/resolutions/100000")?;
    /// assert_eq!(reader.bins().resolution(), Some(100_000));
    /// assert!(reader.weight_names().iter().any(|name| name == "weight"));
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn open(uri: &str) -> Result<CoolReader> {
        let (path, group_path) = crate::io::matrices::uri::split_uri(uri);
        let file = open_file(path)?;
        let group = match group_path {
            None | Some("") | Some("/") => {
                if file.link_exists("resolutions") {
                    let resolutions = file
                        .group("resolutions")
                        .map_err(|e| Error::hdf5(path, "opening /resolutions", e))
                        .and_then(|g| list_resolutions(path, &g))?;
                    return Err(Error::format(
                        path,
                        format!(
                            "this is a multi-resolution .mcool file: choose a resolution with {path}::/resolutions/N (available: {})",
                            resolutions_text(&resolutions)
                        ),
                    ));
                }
                file.as_group()
                    .map_err(|e| Error::hdf5(path, "opening the root group", e))?
            }
            Some(g) => {
                let mut trimmed = g.trim_start_matches('/').to_string();
                // `file.mcool::10000` is short for `file.mcool::/resolutions/10000` (as with
                // .hic files), unless the file has a group of that name (a legacy level).
                let shorthand = format!("resolutions/{trimmed}");
                if !trimmed.is_empty()
                    && trimmed.bytes().all(|b| b.is_ascii_digit())
                    && !file.link_exists(&trimmed)
                    && file.link_exists("resolutions")
                    && file.link_exists(&shorthand)
                {
                    trimmed = shorthand;
                }
                let trimmed = trimmed.as_str();
                if !file.link_exists(trimmed) || file.group(trimmed).is_err() {
                    let mut message = format!("no group '{g}' in this file");
                    if let Ok(res) = file.group("resolutions") {
                        let resolutions = list_resolutions(path, &res)?;
                        message = format!(
                            "no resolution group '{g}' in this file (available: {})",
                            resolutions_text(&resolutions)
                        );
                    }
                    return Err(Error::format(path, message));
                }
                file.group(trimmed)
                    .map_err(|e| Error::hdf5(path, format!("opening group {g}"), e))?
            }
        };
        if group_path.is_none() && !group.link_exists("chroms") {
            let legacy = legacy_levels(path, &group);
            if !legacy.is_empty() {
                return Err(Error::format(
                    path,
                    format!(
                        "this is a legacy multi-resolution cooler (cooler 0.6-0.7, numbered groups): choose a level with {path}::/N (available: {})",
                        legacy.join(", ")
                    ),
                ));
            }
        }
        for needed in ["chroms", "bins", "pixels", "indexes"] {
            if !group.link_exists(needed) {
                return Err(Error::format(
                    path,
                    format!(
                        "group '{}' is not a cooler: it has no '{needed}' group",
                        group_path.unwrap_or("/")
                    ),
                ));
            }
        }
        let attributes = read_attributes(path, &group);
        let format_version = attributes
            .iter()
            .find(|(k, _)| k == "format-version")
            .and_then(|(_, v)| match v {
                serde_json::Value::Number(n) => n.as_i64(),
                serde_json::Value::String(s) => s.trim().parse().ok(),
                _ => None,
            })
            .unwrap_or(1);
        if !(1..=3).contains(&format_version) {
            return Err(Error::format(
                path,
                format!(
                    "cooler format-version {format_version} is not supported (expected 1, 2 or 3)"
                ),
            ));
        }
        let chroms = read_chroms(path, &group)?;
        let resolution_hint = attributes
            .iter()
            .find(|(k, _)| k == "bin-size")
            .and_then(|(_, v)| v.as_u64());
        let (bins, weight_columns) = read_bins(path, &group, chroms, resolution_hint)?;
        let mut bin1_offsets = read_int_column(path, &group, "indexes/bin1_offset")?;
        let mut layout_notes = Vec::new();
        let bin1 = Column::open(&group, "pixels/bin1_id", path)?;
        if bin1_offsets.len() == bins.n_bins() && bin1_offsets.last() <= Some(&(bin1.len() as i64))
        {
            // hic2cool 0.3-0.4 wrote the index without its closing entry; cooler reads such
            // files, and the missing entry can only be the number of pixels.
            bin1_offsets.push(bin1.len() as i64);
            layout_notes.push(format!(
                "indexes/bin1_offset has {} entries, one short (hic2cool 0.3-0.4): the closing entry is taken as nnz",
                bins.n_bins()
            ));
        }
        if bin1_offsets.len() != bins.n_bins() + 1 {
            return Err(Error::format(
                path,
                format!(
                    "indexes/bin1_offset has {} entries; expected {} (number of bins + 1)",
                    bin1_offsets.len(),
                    bins.n_bins() + 1
                ),
            ));
        }
        let bin2 = Column::open(&group, "pixels/bin2_id", path)?;
        let count = Column::open(&group, "pixels/count", path)?;
        let nnz = count.len();
        if bin1.len() != nnz || bin2.len() != nnz {
            return Err(Error::format(
                path,
                format!(
                    "pixel columns differ in length (bin1_id {}, bin2_id {}, count {})",
                    bin1.len(),
                    bin2.len(),
                    nnz
                ),
            ));
        }
        let monotone = bin1_offsets.windows(2).all(|w| w[0] <= w[1]);
        if !monotone
            || bin1_offsets.first() != Some(&0)
            || bin1_offsets.last() != Some(&(nnz as i64))
        {
            return Err(Error::format(
                path,
                format!("indexes/bin1_offset is not a valid index of the {nnz} pixels"),
            ));
        }
        let square = attributes
            .iter()
            .any(|(k, v)| k == "storage-mode" && v.as_str() == Some("square"));
        if square {
            layout_notes.push(
                "storage-mode square: both triangles are stored; contactmap reads the upper triangle (as cooltools' expected and insulation do); the lower triangle is not read yet".to_string(),
            );
        }
        Ok(CoolReader {
            square,
            layout_notes,
            spare: Mutex::new(Vec::new()),
            uri: uri.to_string(),
            path: path.to_string(),
            raw: chunks::open_raw(Path::new(path))?,
            group,
            bins,
            bin1_offsets: bin1_offsets.into_iter().map(|o| o as u64).collect(),
            attributes,
            format_version,
            weight_columns,
            bin1,
            bin2,
            count,
        })
    }

    /// The cooler format version (1 to 3; 1 when the attribute is missing).
    pub fn format_version(&self) -> i64 {
        self.format_version
    }

    /// The root attributes of the cooler group.
    pub fn attributes(&self) -> &[(String, serde_json::Value)] {
        &self.attributes
    }

    /// True when every pixel column is read by the parallel chunk reader.
    pub fn reads_in_parallel(&self) -> bool {
        self.bin1.is_direct() && self.bin2.is_direct() && self.count.is_direct()
    }

    fn attribute_str(&self, name: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| k == name)
            .and_then(|(_, v)| v.as_str())
    }

    /// The values of weight column `name` as stored, and whether the column is divisive.
    fn stored_weight_values(&self, name: &str) -> Result<(Vec<f64>, bool)> {
        if !self.weight_columns.iter().any(|c| c == name) {
            return Err(Error::format(
                &self.uri,
                format!(
                    "no weight column '{name}' in the bin table (available: {})",
                    if self.weight_columns.is_empty() {
                        "none".to_string()
                    } else {
                        self.weight_columns.join(", ")
                    }
                ),
            ));
        }
        let dataset_path = format!("bins/{name}");
        let dataset = self
            .group
            .dataset(&dataset_path)
            .map_err(|e| Error::hdf5(&self.path, format!("opening {dataset_path}"), e))?;
        hdf5_guard::checked_len(&self.path, &dataset, &dataset_path, file_len(&self.path))?;
        let values = dataset
            .read_raw::<f64>()
            .map_err(|e| Error::hdf5(&self.path, format!("reading {dataset_path}"), e))?;
        if values.len() != self.bins.n_bins() {
            return Err(Error::format(
                &self.path,
                format!(
                    "{dataset_path} has {} values for {} bins",
                    values.len(),
                    self.bins.n_bins()
                ),
            ));
        }
        let divisive = self.is_divisive(name, &dataset);
        Ok((values, divisive))
    }

    /// True when weight column `name` holds divisive values that must be inverted: the column's
    /// `divisive_weights` attribute when present; else cooler's rule (KR, VC and VC_SQRT are
    /// divisive by name); else SCALE written by hic2cool (Juicer's SCALE vector is divisive).
    fn is_divisive(&self, name: &str, dataset: &hdf5::Dataset) -> bool {
        let stored =
            hdf5_guard::guarded(&self.path, &format!("bins/{name}/divisive_weights"), || {
                let attr = dataset.attr("divisive_weights").ok()?;
                attr.read_scalar::<bool>()
                    .ok()
                    .or_else(|| attr.read_scalar::<i64>().ok().map(|v| v != 0))
            });
        if let Some(value) = stored {
            return value;
        }
        let by_hic2cool = self
            .attribute_str("generated-by")
            .is_some_and(|g| g.starts_with("hic2cool"));
        DIVISIVE_BY_NAME.contains(&name) || (by_hic2cool && name == HIC2COOL_SCALE)
    }

    /// The end of the block of pixels that starts at `start` (a row boundary): about
    /// [`BLOCK_PIXELS`] pixels, ending on a row boundary so that each row is checked (and sorted,
    /// for legacy files) whole; a row longer than a block is read whole.
    fn block_end(&self, start: usize, hi: usize) -> usize {
        let target = (start + BLOCK_PIXELS).min(hi);
        if target == hi {
            return hi;
        }
        let offsets = &self.bin1_offsets;
        let next = offsets.partition_point(|&o| o as usize <= target);
        let boundary = offsets[next - 1] as usize;
        if boundary > start {
            boundary
        } else {
            offsets.get(next).map_or(hi, |&o| (o as usize).min(hi))
        }
    }

    /// Each pixel's row of `lo..hi` from `indexes/bin1_offset`, into `out`.
    fn rows_from_index(&self, lo: usize, hi: usize, out: &mut Vec<u64>) {
        out.clear();
        out.reserve(hi - lo);
        let offsets = &self.bin1_offsets;
        let mut row = offsets.partition_point(|&o| o as usize <= lo) - 1;
        let mut at = lo;
        while at < hi {
            let end = (offsets[row + 1] as usize).min(hi);
            out.resize(out.len() + (end - at), row as u64);
            at = end;
            row += 1;
        }
    }

    /// Read pixels `lo..hi` of the pixel table (`lo` and `hi` on row boundaries) and check them
    /// against the index: every pixel in its `bin1_offset` row, bin ids in range, no pixel below
    /// the diagonal (unless the file stores both triangles), no pixel stored twice. Rows whose
    /// `bin2_id` are not sorted (legacy cooler 0.6-0.7 multires levels, which cooler reads) are
    /// sorted here.
    fn read_block(&self, lo: usize, hi: usize, rows: RowSource) -> Result<PixelBlock> {
        // a block handed back (`recycle`) is read into, its columns not zeroed again
        let spare = self.spare.lock().ok().and_then(|mut spare| spare.pop());
        let PixelBlock {
            mut bin1,
            mut bin2,
            mut count,
        } = spare.unwrap_or_default();
        let ((read1, read2), read_count) = rayon::join(
            || {
                rayon::join(
                    || match rows {
                        RowSource::Column => self.bin1.read_into(&self.raw, lo, hi, &mut bin1),
                        RowSource::Index => {
                            self.rows_from_index(lo, hi, &mut bin1);
                            Ok(())
                        }
                    },
                    || self.bin2.read_into(&self.raw, lo, hi, &mut bin2),
                )
            },
            || self.count.read_into(&self.raw, lo, hi, &mut count),
        );
        read1?;
        read2?;
        read_count?;
        let n_bins = self.bins.n_bins() as u64;
        let offsets = &self.bin1_offsets;
        let mut row = offsets.partition_point(|&o| o as usize <= lo) - 1;
        let mut k = 0;
        while k < bin1.len() {
            while offsets[row + 1] as usize <= lo + k {
                row += 1;
            }
            let row_end = (offsets[row + 1] as usize).min(hi) - lo;
            // Checks as folds without early exit (they vectorise); the position of a fault is
            // looked for only when there is one.
            let row_bin1 = &bin1[k..row_end];
            let wrong_row = row_bin1
                .iter()
                .fold(false, |wrong, &b| wrong | (b != row as u64))
                .then(|| row_bin1.iter().position(|&b| b != row as u64))
                .flatten();
            if let Some(at) = wrong_row {
                let at = k + at;
                return Err(Error::format(
                    &self.path,
                    format!(
                        "pixel {}: bin1_id {} where indexes/bin1_offset puts row {row}: the pixels are not sorted by bin1_id or the index is wrong (`contactmap validate` reports, `--repair` rebuilds)",
                        lo + at,
                        bin1[at] as i64
                    ),
                ));
            }
            let low = if self.square { 0 } else { row as u64 };
            let row_bin2 = &bin2[k..row_end];
            // strictly increasing columns are in range when the first and the last are
            let sorted = row_bin2
                .iter()
                .zip(&row_bin2[1.min(row_bin2.len())..])
                .fold(true, |sorted, (a, b)| sorted & (a < b));
            let ends_in_range = row_bin2.first().is_none_or(|&j| j >= low)
                && row_bin2.last().is_none_or(|&j| j < n_bins);
            let bad = if sorted && ends_in_range {
                None
            } else {
                row_bin2.iter().position(|&j| j < low || j >= n_bins)
            };
            if let Some(at) = bad {
                let at = k + at;
                return Err(Error::format(
                    &self.path,
                    format!(
                        "pixel {}: (bin1_id {}, bin2_id {}) is out of range for {} bins or below the diagonal",
                        lo + at,
                        bin1[at] as i64,
                        bin2[at] as i64,
                        n_bins
                    ),
                ));
            }
            if !sorted {
                let row_bin2 = &mut bin2[k..row_end];
                let mut order: Vec<usize> = (0..row_bin2.len()).collect();
                order.sort_by_key(|&m| row_bin2[m]);
                let sorted_bin2: Vec<u64> = order.iter().map(|&m| row_bin2[m]).collect();
                if let Some(dup) = sorted_bin2.windows(2).position(|w| w[0] == w[1]) {
                    let (a, b) = (
                        order[dup].min(order[dup + 1]),
                        order[dup].max(order[dup + 1]),
                    );
                    return Err(Error::format(
                        &self.path,
                        format!(
                            "pixels {} and {} are both (bin1_id {row}, bin2_id {}): a pixel stored twice (`contactmap validate --repair` sums duplicates)",
                            lo + k + a,
                            lo + k + b,
                            sorted_bin2[dup]
                        ),
                    ));
                }
                let row_count = &count[k..row_end];
                let sorted_count: Vec<f64> = order.iter().map(|&m| row_count[m]).collect();
                row_bin2.copy_from_slice(&sorted_bin2);
                count[k..row_end].copy_from_slice(&sorted_count);
            }
            k = row_end;
        }
        Ok(PixelBlock { bin1, bin2, count })
    }

    /// Stream the stored pixels of `rows x cols` (both triangles for square storage, where
    /// `upper_only` keeps `bin2 >= bin1`).
    fn stream(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        upper_only: bool,
        row_source: RowSource,
        sink: &mut dyn FnMut(PixelBlock) -> Result<()>,
    ) -> Result<()> {
        let n_bins = self.bins.n_bins();
        let rows = rows.start.min(n_bins)..rows.end.min(n_bins);
        if rows.is_empty() || cols.is_empty() {
            return Ok(());
        }
        let lo = self.bin1_offsets[rows.start] as usize;
        let hi = self.bin1_offsets[rows.end] as usize;
        let whole_rows = cols.start == 0 && cols.end >= n_bins;
        let cols64 = cols.start as u64..cols.end as u64;
        // Blocks of whole rows, the next one read while the sink consumes the current one.
        let blocks = std::iter::successors(
            (lo < hi).then(|| (lo, self.block_end(lo, hi))),
            |&(_, end)| (end < hi).then(|| (end, self.block_end(end, hi))),
        );
        read_ahead(
            blocks,
            |&(start, end)| self.read_block(start, end, row_source),
            |_, mut block| {
                if !whole_rows {
                    block.retain_cols(&cols64);
                }
                if upper_only && self.square {
                    block.retain_upper();
                }
                if block.is_empty() {
                    Ok(())
                } else {
                    sink(block)
                }
            },
        )
    }
}

impl MatrixReader for CoolReader {
    fn source(&self) -> &str {
        &self.uri
    }

    fn bins(&self) -> &BinTable {
        &self.bins
    }

    fn count_type(&self) -> CountType {
        if self.count.is_float() {
            CountType::Float
        } else {
            CountType::Integer
        }
    }

    fn weight_names(&self) -> Vec<String> {
        self.weight_columns.clone()
    }

    fn weights(&self, name: &str) -> Result<Weights> {
        let (values, divisive) = self.stored_weight_values(name)?;
        if divisive {
            Ok(Weights::from_divisive(
                name,
                &values,
                format!(
                    "bins/{name} is divisive (Juicer convention); inverted to multiplicative on read"
                ),
            ))
        } else {
            Ok(Weights {
                name: name.to_string(),
                values,
                provenance: None,
            })
        }
    }

    fn weight_attribute(&self, name: &str, key: &str) -> Option<serde_json::Value> {
        if !self.weight_columns.iter().any(|c| c == name) {
            return None;
        }
        hdf5_guard::guarded(&self.path, &format!("bins/{name}/{key}"), || {
            let dataset = self.group.dataset(&format!("bins/{name}")).ok()?;
            let attr = dataset.attr(key).ok()?;
            Some(attribute_value(&attr))
        })
    }

    fn stored_weights(&self, name: &str) -> Result<Weights> {
        let (values, _) = self.stored_weight_values(name)?;
        Ok(Weights {
            name: name.to_string(),
            values,
            provenance: None,
        })
    }

    fn info(&self) -> MatrixInfo {
        let mut notes = Vec::new();
        for name in &self.weight_columns {
            if let Ok(dataset) = self.group.dataset(&format!("bins/{name}")) {
                if self.is_divisive(name, &dataset) {
                    notes.push(format!(
                        "weight column '{name}' is divisive in the file (Juicer / hic2cool); contactmap inverts it to cooler's multiplicative convention"
                    ));
                }
            }
        }
        notes.extend(self.layout_notes.iter().cloned());
        if !self.attributes.iter().any(|(k, _)| k == "format") {
            notes.push("old cooler without a 'format' attribute".to_string());
        }
        MatrixInfo {
            format: format!("cool (format-version {})", self.format_version),
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
        self.stream(rows, cols, true, RowSource::Column, &mut |block| {
            sink(&block)?;
            self.recycle(block);
            Ok(())
        })
    }

    fn recycle(&self, block: PixelBlock) {
        if let Ok(mut spare) = self.spare.lock() {
            if spare.len() < SPARE_BLOCKS {
                spare.push(block);
            }
        }
    }

    fn read_rows_owned(
        &self,
        rows: Range<usize>,
        sink: &mut dyn FnMut(PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.stream(rows, 0..self.bins.n_bins(), true, RowSource::Column, sink)
    }

    fn read_pixels_owned(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(PixelBlock) -> Result<()>,
    ) -> Result<()> {
        // a query of a rectangle: rows from the index, as cooler's range queries take them
        self.stream(rows, cols, true, RowSource::Index, sink)
    }

    fn stores_both_triangles(&self) -> bool {
        self.square
    }

    fn read_stored_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.stream(rows, cols, false, RowSource::Column, &mut |block| {
            sink(&block)?;
            self.recycle(block);
            Ok(())
        })
    }

    fn totals(&self) -> Result<(u64, f64)> {
        if self.square {
            let n = self.bins.n_bins();
            let (mut nnz, mut sum) = (0u64, 0.0f64);
            self.read_pixels(0..n, 0..n, &mut |block| {
                nnz += block.len() as u64;
                sum += block.count.iter().sum::<f64>();
                Ok(())
            })?;
            return Ok((nnz, sum));
        }
        let nnz = self.count.len();
        let mut sum = 0.0;
        let mut lo = 0;
        while lo < nnz {
            let hi = (lo + 4 * BLOCK_PIXELS).min(nnz);
            sum += self
                .count
                .read::<f64>(&self.raw, lo, hi)?
                .iter()
                .sum::<f64>();
            lo = hi;
        }
        Ok((nnz as u64, sum))
    }
}

/// The numbered groups (`/0`, `/1`, ...) of a legacy cooler 0.6-0.7 multi-resolution file that
/// hold a cooler, each as `N (BIN-SIZE bp)`, in numeric order.
fn legacy_levels(path: &str, root: &hdf5::Group) -> Vec<String> {
    let Ok(names) = hdf5_guard::guarded(path, "the root group's members", || root.member_names())
    else {
        return Vec::new();
    };
    let mut levels: Vec<(u64, String)> = names
        .iter()
        .filter_map(|name| {
            let level: u64 = name.parse().ok()?;
            let group = root.group(name).ok()?;
            group.link_exists("pixels").then_some(())?;
            let size = read_attributes(path, &group)
                .into_iter()
                .find(|(k, _)| k == "bin-size")
                .and_then(|(_, v)| v.as_u64());
            Some((
                level,
                match size {
                    Some(size) => format!("{level} ({size} bp)"),
                    None => level.to_string(),
                },
            ))
        })
        .collect();
    levels.sort();
    levels.into_iter().map(|(_, text)| text).collect()
}

fn read_int_column(path: &str, group: &hdf5::Group, name: &str) -> Result<Vec<i64>> {
    let dataset = group
        .dataset(name)
        .map_err(|e| Error::format(path, format!("missing dataset {name}: {e}")))?;
    hdf5_guard::checked_len(path, &dataset, name, file_len(path))?;
    dataset
        .read_raw::<i64>()
        .map_err(|e| Error::hdf5(path, format!("reading {name}"), e))
}

fn read_chroms(path: &str, group: &hdf5::Group) -> Result<Vec<Chrom>> {
    let names_dataset = group
        .dataset("chroms/name")
        .map_err(|e| Error::format(path, format!("missing dataset chroms/name: {e}")))?;
    let names = hdf5_guard::read_strings(path, &names_dataset, "chroms/name")?;
    let lengths = read_int_column(path, group, "chroms/length")?;
    if names.len() != lengths.len() {
        return Err(Error::format(
            path,
            format!(
                "chroms/name has {} entries but chroms/length has {}",
                names.len(),
                lengths.len()
            ),
        ));
    }
    names
        .into_iter()
        .zip(lengths)
        .map(|(name, length)| {
            if length < 0 {
                Err(Error::format(
                    path,
                    format!("chroms/length: chromosome {name} has negative length {length}"),
                ))
            } else {
                Ok(Chrom::new(name, length as u64))
            }
        })
        .collect()
}

/// Columns of `bins/` that are not weights.
const BIN_COORDINATE_COLUMNS: [&str; 3] = ["chrom", "start", "end"];

fn read_bins(
    path: &str,
    group: &hdf5::Group,
    chroms: Vec<Chrom>,
    resolution_hint: Option<u64>,
) -> Result<(BinTable, Vec<String>)> {
    let chrom_ids = read_int_column(path, group, "bins/chrom")?;
    let starts = read_int_column(path, group, "bins/start")?;
    let ends = read_int_column(path, group, "bins/end")?;
    if chrom_ids.len() != starts.len() || starts.len() != ends.len() {
        return Err(Error::format(
            path,
            format!(
                "bins/chrom, bins/start and bins/end differ in length ({}, {}, {})",
                chrom_ids.len(),
                starts.len(),
                ends.len()
            ),
        ));
    }
    let mut bins = Vec::with_capacity(starts.len());
    for k in 0..starts.len() {
        let (c, s, e) = (chrom_ids[k], starts[k], ends[k]);
        if c < 0 || c as usize >= chroms.len() || s < 0 || e < s {
            return Err(Error::format(
                path,
                format!(
                    "bins row {k}: chrom {c}, start {s}, end {e} is not a valid bin ({} chromosomes)",
                    chroms.len()
                ),
            ));
        }
        bins.push(Bin {
            chrom_id: c as usize,
            start: s as u64,
            end: e as u64,
        });
    }
    let table = BinTable::from_bins(chroms, &bins, resolution_hint)
        .map_err(|e| Error::format(path, format!("bins table: {e}")))?;
    let mut weights = Vec::new();
    let bins_group = group
        .group("bins")
        .map_err(|e| Error::hdf5(path, "opening bins", e))?;
    let members = bins_group
        .member_names()
        .map_err(|e| Error::hdf5(path, "listing bins", e))?;
    for name in members {
        if BIN_COORDINATE_COLUMNS.contains(&name.as_str()) {
            continue;
        }
        let is_float = bins_group
            .dataset(&name)
            .and_then(|d| d.dtype())
            .map(|t| matches!(t.to_descriptor(), Ok(TypeDescriptor::Float(_))))
            .unwrap_or(false);
        if is_float {
            weights.push(name);
        }
    }
    // h5py (and so cooler) lists columns by name; libhdf5 may iterate in another order.
    weights.sort();
    Ok((table, weights))
}

/// Read every attribute of `location` as JSON (numbers, strings, booleans, arrays); attributes of
/// other types are shown as a type description.
fn read_attributes(path: &str, location: &hdf5::Group) -> Vec<(String, serde_json::Value)> {
    let Ok(names) = hdf5_guard::guarded(path, "the attribute names", || location.attr_names())
    else {
        return Vec::new();
    };
    names
        .into_iter()
        .filter_map(|name| {
            hdf5_guard::guarded(path, &format!("attribute '{name}'"), || {
                let attr = location.attr(&name).ok()?;
                Some((name.clone(), attribute_value(&attr)))
            })
        })
        .collect()
}

fn attribute_value(attr: &hdf5::Attribute) -> serde_json::Value {
    use serde_json::Value;
    let Ok(descriptor) = attr.dtype().and_then(|t| t.to_descriptor()) else {
        return Value::Null;
    };
    // Attributes are small metadata: one holding more values than this is corrupt.
    const MAX_ATTRIBUTE_VALUES: usize = 1 << 16;
    let n_values = attr
        .shape()
        .iter()
        .try_fold(1usize, |n, &d| n.checked_mul(d));
    let Some(n_values) = n_values.filter(|&n| n <= MAX_ATTRIBUTE_VALUES) else {
        return Value::Null;
    };
    let scalar = n_values <= 1;
    let float = |v: f64| serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number);
    match descriptor {
        TypeDescriptor::Integer(_) | TypeDescriptor::Unsigned(_) if scalar => attr
            .read_raw::<i64>()
            .ok()
            .and_then(|v| v.first().copied())
            .map_or(Value::Null, Value::from),
        TypeDescriptor::Integer(_) | TypeDescriptor::Unsigned(_) => {
            attr.read_raw::<i64>().map_or(Value::Null, Value::from)
        }
        TypeDescriptor::Float(_) if scalar => attr
            .read_raw::<f64>()
            .ok()
            .and_then(|v| v.first().copied())
            .map_or(Value::Null, float),
        TypeDescriptor::Float(_) => attr.read_raw::<f64>().map_or(Value::Null, |v| {
            Value::Array(v.into_iter().map(float).collect())
        }),
        TypeDescriptor::Boolean => attr
            .read_raw::<bool>()
            .ok()
            .and_then(|v| v.first().copied())
            .map_or(Value::Null, Value::Bool),
        TypeDescriptor::VarLenUnicode => attr
            .read_raw::<VarLenUnicode>()
            .ok()
            .and_then(|v| {
                v.first()
                    .map(|s| Value::from(hdf5_guard::lossy(s.as_bytes())))
            })
            .unwrap_or(Value::Null),
        TypeDescriptor::VarLenAscii => attr
            .read_raw::<VarLenAscii>()
            .ok()
            .and_then(|v| {
                v.first()
                    .map(|s| Value::from(hdf5_guard::lossy(s.as_bytes())))
            })
            .unwrap_or(Value::Null),
        TypeDescriptor::FixedAscii(_) | TypeDescriptor::FixedUnicode(_) => attr
            .read_raw::<hdf5::types::FixedAscii<4096>>()
            .ok()
            .and_then(|v| {
                v.first()
                    .map(|s| Value::from(hdf5_guard::lossy(s.as_bytes()).trim_end_matches('\0')))
            })
            .unwrap_or(Value::Null),
        other => Value::from(format!("<{other:?}>")),
    }
}
