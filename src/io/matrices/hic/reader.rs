//! [`HicReader`]: opening a `.hic` file at one resolution, planning which blocks a query needs,
//! and streaming their pixels band by band (see the module root for the method).

use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::ErrorKind;
use std::ops::Range;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use rayon::prelude::*;

use super::blocks::{
    BLOCK_ENTRY_BYTES, BlockEntry, BlockStats, MatrixIndex, PairPlan, Pixel, decode_block, inflate,
};
use super::bytes::{SeqReader, printable};
use super::header::{read_footer, read_header};
use super::norms::{HicExpected, NormVector};
use crate::error::{Error, Result};
use crate::genome::{BinTable, Chrom};
use crate::io::matrices::reader::{MatrixInfo, MatrixReader};
use crate::matrix::{CountType, PixelBlock, Weights};

/// Compressed bytes of blocks decoded per band of rows; bounds the memory of a pixel query.
pub const BAND_BUDGET_BYTES: u64 = 4 << 20;
/// Bins accepted at one resolution whatever the file's size (2^24: a 3.1 Gbp genome at 200 bp).
pub(super) const MIN_BIN_ALLOWANCE: u64 = 1 << 24;
/// Bins accepted per byte of file beyond [`MIN_BIN_ALLOWANCE`].
pub(super) const BINS_PER_FILE_BYTE: u64 = 16;
/// Pixels handed to the sink per call.
const SINK_BLOCK_PIXELS: usize = 1 << 16;
/// Bands with more pixels than this are sorted in parallel.
const PARALLEL_SORT_MIN_PIXELS: usize = 1 << 16;

/// Records past the end of a chromosome by block, `(chrom1, chrom2, block number)`: how many,
/// and the first one `(x, y)`.
type PastEnd = BTreeMap<(usize, usize, u64), (u64, (i64, i64))>;

/// An open `.hic` file at one base-pair resolution.
#[derive(Debug)]
pub struct HicReader {
    pub(super) path: PathBuf,
    pub(super) source: String,
    pub(super) file: File,
    pub(super) file_len: u64,
    pub(super) version: i32,
    pub(super) footer_position: u64,
    pub(super) genome_id: String,
    pub(super) attributes: Vec<(String, String)>,
    pub(super) resolutions: Vec<u64>,
    pub(super) resolution: u64,
    pub(super) bins: BinTable,
    /// File chromosome index of each bin-table chromosome (the file's index 0 is `All`).
    pub(super) file_chrom: Vec<usize>,
    /// Master index: file chromosome indices `(i, j)`, `i <= j` -> matrix record position.
    pub(super) master: HashMap<(usize, usize), u64>,
    /// For each bin-table chromosome `i`, the chromosomes `j >= i` with a matrix, ascending.
    pub(super) partners: Vec<Vec<usize>>,
    /// Normalisation vectors at this resolution (base pairs), `NONE` excluded.
    pub(super) norm_vectors: Vec<NormVector>,
    /// Names of the normalisations at this resolution, in file order.
    pub(super) norm_names: Vec<String>,
    /// Block indexes read so far, by bin-table chromosome pair.
    pub(super) matrix_cache: Mutex<HashMap<(usize, usize), Arc<MatrixIndex>>>,
    /// Compressed bytes per band ([`BAND_BUDGET_BYTES`]; smaller in tests, to get many bands).
    pub(super) band_budget_bytes: u64,
    /// Blocks decoded so far that hold records past the end of their chromosome, by
    /// `(chrom1, chrom2, block number)`: how many, and the first one `(x, y)`. Keyed by block so
    /// that a block decoded twice counts once.
    pub(super) past_end: Mutex<PastEnd>,
}

impl HicReader {
    /// Open `path` at `resolution` base pairs, or at the file's only base-pair resolution when
    /// `resolution` is `None`.
    ///
    /// # Examples
    ///
    /// ```
    /// use std::path::Path;
    /// use contactmap::io::hic::HicReader;
    /// use contactmap::io::MatrixReader;
    /// let reader = HicReader::open(Path::new("data/hic_test_file.hic"), Some(100_000))?;
    /// assert_eq!(reader.bins().resolution(), Some(100_000));
    /// assert!(reader.bins().n_bins() > 0);
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn open(path: &Path, resolution: Option<u64>) -> Result<HicReader> {
        let file = File::open(path).map_err(|e| Error::io(path, e))?;
        let file_len = file.metadata().map_err(|e| Error::io(path, e))?.len();
        let header = read_header(&mut SeqReader::new(&file, path, file_len, 0))?;

        let mut resolutions = header.resolutions.clone();
        resolutions.sort_unstable();
        resolutions.dedup();
        let listed = list_numbers(&resolutions);
        let resolution = match resolution {
            Some(r) if resolutions.contains(&r) => r,
            Some(r) => {
                return Err(Error::format(
                    path,
                    format!("no resolution {r} in this .hic file (available: {listed})"),
                ));
            }
            None if resolutions.len() == 1 => resolutions[0],
            None if resolutions.is_empty() => return Err(no_base_pair_resolution(path)),
            None => {
                return Err(Error::format(
                    path,
                    format!(
                        "the .hic file has {} resolutions ({listed}); choose one with \
                         '{}::/resolutions/<bin size>'",
                        resolutions.len(),
                        path.display()
                    ),
                ));
            }
        };

        // Juicer's "All" pseudo-chromosome (index 0) is not part of the genome.
        let skip_all = header
            .chroms
            .first()
            .is_some_and(|c| c.name.eq_ignore_ascii_case("all"));
        let file_chrom: Vec<usize> = (usize::from(skip_all)..header.chroms.len()).collect();
        let chroms: Vec<Chrom> = file_chrom
            .iter()
            .map(|&i| header.chroms[i].clone())
            .collect();
        let bins = BinTable::fixed(chroms, resolution).map_err(|e| {
            Error::format(
                path,
                format!("chromosome table: {}", printable(&e.to_string())),
            )
        })?;
        let max_bins = max_bins(file_len);
        if bins.n_bins() as u64 > max_bins {
            return Err(Error::format(
                path,
                format!(
                    "the chromosome lengths in the header make {} bins at resolution \
                     {resolution}, more than a file of {file_len} bytes can hold data for (at \
                     most {max_bins}): the header is corrupt",
                    bins.n_bins()
                ),
            ));
        }

        let footer = read_footer(&file, path, file_len, &header, resolution)?;
        let bin_chrom_of_file: HashMap<usize, usize> = file_chrom
            .iter()
            .enumerate()
            .map(|(k, &i)| (i, k))
            .collect();
        let mut partners = vec![Vec::new(); file_chrom.len()];
        for &(i, j) in footer.master.keys() {
            if let (Some(&a), Some(&b)) = (bin_chrom_of_file.get(&i), bin_chrom_of_file.get(&j)) {
                if a <= b {
                    partners[a].push(b);
                }
            }
        }
        for list in &mut partners {
            list.sort_unstable();
            list.dedup();
        }
        let mut norm_names: Vec<String> = Vec::new();
        for vector in &footer.norm_vectors {
            if !norm_names.contains(&vector.name) {
                norm_names.push(vector.name.clone());
            }
        }

        Ok(HicReader {
            path: path.to_path_buf(),
            source: path.display().to_string(),
            file,
            file_len,
            version: header.version,
            footer_position: header.footer_position,
            genome_id: header.genome_id,
            attributes: header.attributes,
            resolutions,
            resolution,
            bins,
            file_chrom,
            master: footer.master,
            partners,
            norm_vectors: footer.norm_vectors,
            norm_names,
            matrix_cache: Mutex::new(HashMap::new()),
            band_budget_bytes: BAND_BUDGET_BYTES,
            past_end: Mutex::new(BTreeMap::new()),
        })
    }

    /// The base-pair resolutions of the `.hic` file at `path`, ascending, from its header alone
    /// (to choose one before opening, e.g. for `contactmap info` on a multi-resolution file).
    pub fn list_resolutions(path: &Path) -> Result<Vec<u64>> {
        let file = File::open(path).map_err(|e| Error::io(path, e))?;
        let file_len = file.metadata().map_err(|e| Error::io(path, e))?.len();
        let header = read_header(&mut SeqReader::new(&file, path, file_len, 0))?;
        let mut resolutions = header.resolutions;
        resolutions.sort_unstable();
        resolutions.dedup();
        if resolutions.is_empty() {
            return Err(no_base_pair_resolution(path));
        }
        Ok(resolutions)
    }

    /// All base-pair resolutions of the file, ascending.
    pub fn resolutions(&self) -> &[u64] {
        &self.resolutions
    }

    /// The resolution (bin size in base pairs) this reader was opened at.
    pub fn resolution(&self) -> u64 {
        self.resolution
    }

    /// The `.hic` format version (8 or 9).
    pub fn version(&self) -> i32 {
        self.version
    }

    /// The normalisation vector `name` over every bin, as stored (Juicer's divisive values;
    /// NaN for chromosomes without one).
    fn stored_norm_vector(&self, name: &str) -> Result<Vec<f64>> {
        if !self.norm_names.iter().any(|n| n == name) {
            let available = if self.norm_names.is_empty() {
                "none".to_string()
            } else {
                printable(&self.norm_names.join(", "))
            };
            return Err(Error::format(
                &self.path,
                format!(
                    "no normalisation '{}' at resolution {} (available: {available})",
                    printable(name),
                    self.resolution
                ),
            ));
        }
        let mut values = Vec::with_capacity(self.bins.n_bins());
        for (chrom_id, chrom) in self.bins.chroms().iter().enumerate() {
            let n_bins = self.bins.chrom_bins(chrom_id).len();
            let file_chrom = self.file_chrom[chrom_id];
            match self
                .norm_vectors
                .iter()
                .find(|v| v.name == name && v.file_chrom == file_chrom)
            {
                Some(vector) => values.extend(self.read_norm_vector(vector, chrom, n_bins)?),
                None => values.extend(std::iter::repeat_n(f64::NAN, n_bins)),
            }
        }
        Ok(values)
    }

    /// `chr2L-chr2R`, for messages.
    fn pair_label(&self, chrom1: usize, chrom2: usize) -> String {
        let chroms = self.bins.chroms();
        format!(
            "{}-{}",
            printable(&chroms[chrom1].name),
            printable(&chroms[chrom2].name)
        )
    }

    /// The block index of the matrix of bin-table chromosomes `chrom1 <= chrom2`, read on first
    /// use; `None` when the file has no matrix for the pair.
    pub(super) fn matrix_index(
        &self,
        chrom1: usize,
        chrom2: usize,
    ) -> Result<Option<Arc<MatrixIndex>>> {
        let key = (self.file_chrom[chrom1], self.file_chrom[chrom2]);
        let Some(&position) = self.master.get(&key) else {
            return Ok(None);
        };
        {
            let cache = self.matrix_cache.lock().unwrap_or_else(|e| e.into_inner());
            if let Some(index) = cache.get(&(chrom1, chrom2)) {
                return Ok(Some(Arc::clone(index)));
            }
        }
        let index = Arc::new(self.read_matrix_index(position, key, chrom1, chrom2)?);
        let mut cache = self.matrix_cache.lock().unwrap_or_else(|e| e.into_inner());
        cache.insert((chrom1, chrom2), Arc::clone(&index));
        Ok(Some(index))
    }

    /// Parse the matrix record at `position` and keep the block index of the open resolution.
    fn read_matrix_index(
        &self,
        position: u64,
        file_pair: (usize, usize),
        chrom1: usize,
        chrom2: usize,
    ) -> Result<MatrixIndex> {
        let label = self.pair_label(chrom1, chrom2);
        let what = format!("the matrix record of {label}");
        let mut reader = SeqReader::new(&self.file, &self.path, self.file_len, position);
        let found1 = reader.i32(&what)?;
        let found2 = reader.i32(&what)?;
        if i64::from(found1) != file_pair.0 as i64 || i64::from(found2) != file_pair.1 as i64 {
            return Err(Error::format(
                &self.path,
                format!(
                    "the matrix record at offset {position} is for chromosomes {found1}_{found2}, \
                     but the master index lists it for {label} ({}_{})",
                    file_pair.0, file_pair.1
                ),
            ));
        }
        let n_levels = reader.i32(&what)?;
        // unit (>= 1 byte), then 10 four-byte fields per resolution level
        let n_levels = reader.count(i64::from(n_levels), 41, &what)?;
        for _ in 0..n_levels {
            let unit = reader.string(&what)?;
            reader.i32(&what)?; // index into the header's resolution list
            reader.f32(&what)?; // sum of counts
            reader.i32(&what)?; // occupied cell count (unused)
            reader.f32(&what)?; // 5th percentile (unused)
            reader.f32(&what)?; // 95th percentile (unused)
            let resolution = reader.i32(&what)?;
            let block_bin_count = reader.i32(&what)?;
            let block_column_count = reader.i32(&what)?;
            let n_blocks = reader.i32(&what)?;
            let n_blocks = reader.count(i64::from(n_blocks), BLOCK_ENTRY_BYTES, &what)?;
            if unit != "BP" || i64::from(resolution) != self.resolution as i64 {
                reader.skip(n_blocks as u64 * BLOCK_ENTRY_BYTES, &what)?;
                continue;
            }
            if n_blocks > 0 && (block_bin_count <= 0 || block_column_count <= 0) {
                return Err(Error::format(
                    &self.path,
                    format!(
                        "{what}: block bin count {block_bin_count} and block column count \
                         {block_column_count} must be positive"
                    ),
                ));
            }
            let what = format!("the block index of {label}");
            let mut blocks = Vec::with_capacity(n_blocks);
            for _ in 0..n_blocks {
                let number = reader.i32(&what)?;
                let block_position = reader.i64(&what)?;
                let size = reader.i32(&what)?;
                if number < 0 || block_position < 0 || size < 0 {
                    return Err(Error::format(
                        &self.path,
                        format!(
                            "{what}: block {number} has position {block_position} and size {size}"
                        ),
                    ));
                }
                let (block_position, size) = (block_position as u64, size as u64);
                if block_position.saturating_add(size) > self.file_len {
                    return Err(Error::format(
                        &self.path,
                        format!(
                            "block {number} of {label} at offset {block_position} ({size} bytes) \
                             extends past the end of the file ({} bytes): the file is truncated",
                            self.file_len
                        ),
                    ));
                }
                if size > 0 {
                    blocks.push(BlockEntry {
                        number: number as u64,
                        position: block_position,
                        size,
                    });
                }
            }
            blocks.sort_unstable_by_key(|b| b.number);
            return Ok(MatrixIndex {
                block_bin_count: block_bin_count.max(1) as u64,
                block_column_count: block_column_count.max(1) as u64,
                blocks,
            });
        }
        // The pair has no record at this resolution: nothing is stored for it.
        Ok(MatrixIndex::default())
    }

    /// The decoding plan of the matrix `(chrom1, chrom2)`, keeping pixels in `rows x cols`.
    fn plan(
        &self,
        chrom1: usize,
        chrom2: usize,
        rows: Range<u64>,
        cols: Range<u64>,
    ) -> Result<Option<PairPlan>> {
        let Some(index) = self.matrix_index(chrom1, chrom2)? else {
            return Ok(None);
        };
        let bins1 = self.bins.chrom_bins(chrom1);
        let bins2 = self.bins.chrom_bins(chrom2);
        Ok(Some(PairPlan {
            label: self.pair_label(chrom1, chrom2),
            chroms: (chrom1, chrom2),
            index,
            intra: chrom1 == chrom2,
            rotated: chrom1 == chrom2 && self.version >= 9,
            offset1: bins1.start as u64,
            n1: bins1.len() as u64,
            offset2: bins2.start as u64,
            n2: bins2.len() as u64,
            keep_rows: rows,
            keep_cols: cols,
        }))
    }

    /// Read, inflate and decode one block, appending its pixels in the plan's rectangle to `out`;
    /// records past the end of a chromosome are dropped and noted for [`MatrixReader::warnings`].
    fn decode_into(
        &self,
        plan: &PairPlan,
        entry: &BlockEntry,
        out: &mut Vec<Pixel>,
    ) -> Result<BlockStats> {
        let block_error = |message: String| {
            Error::format(
                &self.path,
                format!("block {} of {}: {message}", entry.number, plan.label),
            )
        };
        let mut compressed = vec![0u8; entry.size as usize];
        self.file
            .read_exact_at(&mut compressed, entry.position)
            .map_err(|e| {
                if e.kind() == ErrorKind::UnexpectedEof {
                    block_error(format!(
                        "truncated while reading {} bytes at offset {}",
                        entry.size, entry.position
                    ))
                } else {
                    Error::io(&self.path, e)
                }
            })?;
        let data = inflate(&compressed).map_err(block_error)?;
        let stats = decode_block(&data, self.version, plan, out).map_err(block_error)?;
        if let Some(first) = stats.first_past_end {
            let mut past_end = self.past_end.lock().unwrap_or_else(|e| e.into_inner());
            past_end.insert(
                (plan.chroms.0, plan.chroms.1, entry.number),
                (stats.past_end, first),
            );
        }
        Ok(stats)
    }

    /// Decode `jobs` in parallel; the result keeps the order of `jobs`.
    fn decode_many(
        &self,
        plans: &[PairPlan],
        jobs: &[(usize, BlockEntry)],
    ) -> Result<Vec<Vec<Pixel>>> {
        jobs.par_iter()
            .map(|(plan, entry)| {
                let mut out = Vec::new();
                self.decode_into(&plans[*plan], entry, &mut out)?;
                Ok(out)
            })
            .collect()
    }

    /// Stream the pixels of row chromosome `chrom1`, rows `rows` (genome-wide, inside the
    /// chromosome), columns `cols`, band by band.
    fn stream_chromosome(
        &self,
        chrom1: usize,
        rows: Range<u64>,
        cols: &Range<u64>,
        block: &mut PixelBlock,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        let chrom_start = self.bins.chrom_bins(chrom1).start as u64;
        // Plan every matrix (chrom1, chrom2 >= chrom1) that meets the query, and its blocks.
        let mut plans: Vec<PairPlan> = Vec::new();
        let mut planned: Vec<(usize, BlockEntry, u64)> = Vec::new();
        for &chrom2 in &self.partners[chrom1] {
            let bins2 = self.bins.chrom_bins(chrom2);
            let low = if chrom2 == chrom1 { rows.start } else { 0 };
            let keep_cols =
                cols.start.max(bins2.start as u64).max(low)..cols.end.min(bins2.end as u64);
            if keep_cols.is_empty() {
                continue;
            }
            let Some(plan) = self.plan(chrom1, chrom2, rows.clone(), keep_cols.clone())? else {
                continue;
            };
            let plan_id = plans.len();
            for entry in &plan.index.blocks {
                let (row_box, col_box) = plan.block_box(entry.number);
                let row_box = (row_box.start + plan.offset1)..(row_box.end + plan.offset1);
                let col_box = (col_box.start + plan.offset2)..(col_box.end + plan.offset2);
                if overlaps(&row_box, &rows) && overlaps(&col_box, &keep_cols) {
                    planned.push((plan_id, *entry, row_box.start.max(rows.start)));
                }
            }
            plans.push(plan);
        }
        if planned.is_empty() {
            return Ok(());
        }

        // Bands of rows aligned on the chromosome's start (and on the intra-chromosomal block
        // grid), about `band_budget_bytes` of compressed blocks each.
        let n_rows = rows.end - rows.start;
        let total_bytes: u64 = planned.iter().map(|p| p.1.size).sum();
        // Aligned on the intra-chromosomal block grid (never wider than the chromosome, and at
        // least one row, whatever the header says).
        let align = plans
            .iter()
            .find(|p| p.intra && !p.index.blocks.is_empty())
            .map_or(1, |p| p.index.block_bin_count.clamp(1, p.n1.max(1)));
        let wanted = ((n_rows as u128 * u128::from(self.band_budget_bytes))
            .div_ceil(u128::from(total_bytes.max(1))))
        .clamp(1, u128::from(n_rows)) as u64;
        let chrom_rows = self.bins.chrom_bins(chrom1).len() as u64;
        let band_rows = wanted
            .div_ceil(align)
            .saturating_mul(align)
            .clamp(1, chrom_rows.max(1));
        let first_band = (rows.start - chrom_start) / band_rows;
        let last_band = (rows.end - 1 - chrom_start) / band_rows;
        let n_bands = (last_band - first_band + 1) as usize;
        let band_of = |bin1: u64| ((bin1 - chrom_start) / band_rows - first_band) as usize;

        let mut starting: Vec<Vec<(usize, BlockEntry)>> = vec![Vec::new(); n_bands];
        for (plan_id, entry, first_row) in planned {
            starting[band_of(first_row)].push((plan_id, entry));
        }
        let mut waiting: Vec<Vec<Pixel>> = vec![Vec::new(); n_bands];
        for band in 0..n_bands {
            let mut jobs = std::mem::take(&mut starting[band]);
            jobs.sort_unstable_by_key(|job| job.1.position);
            let decoded = self.decode_many(&plans, &jobs)?;
            let mut current = std::mem::take(&mut waiting[band]);
            for (pixels, (plan_id, entry)) in decoded.into_iter().zip(&jobs) {
                for pixel in pixels {
                    let target = band_of(pixel.bin1());
                    if target == band {
                        current.push(pixel);
                    } else if target > band {
                        waiting[target].push(pixel);
                    } else {
                        return Err(Error::format(
                            &self.path,
                            format!(
                                "block {} of {} holds pixel ({}, {}), outside the block's place \
                                 in the block grid",
                                entry.number,
                                plans[*plan_id].label,
                                pixel.bin1(),
                                pixel.bin2()
                            ),
                        ));
                    }
                }
            }
            let band_start = chrom_start + (first_band + band as u64) * band_rows;
            let sorted = once_each(sort_band(current, band_start, band_rows as usize));
            for chunk in sorted.chunks(SINK_BLOCK_PIXELS) {
                block.clear();
                for pixel in chunk {
                    block.push(pixel.bin1(), pixel.bin2(), f64::from(pixel.count));
                }
                sink(block)?;
            }
        }
        Ok(())
    }

    /// Every present matrix `(chrom1 <= chrom2)` with its whole extent as the kept rectangle.
    fn all_plans(&self) -> Result<Vec<PairPlan>> {
        let mut plans = Vec::new();
        for (chrom1, partners) in self.partners.iter().enumerate() {
            let bins1 = self.bins.chrom_bins(chrom1);
            for &chrom2 in partners {
                let bins2 = self.bins.chrom_bins(chrom2);
                let rows = bins1.start as u64..bins1.end as u64;
                let cols = bins2.start as u64..bins2.end as u64;
                if let Some(plan) = self.plan(chrom1, chrom2, rows, cols)? {
                    plans.push(plan);
                }
            }
        }
        Ok(plans)
    }
}

impl MatrixReader for HicReader {
    fn source(&self) -> &str {
        &self.source
    }

    fn bins(&self) -> &BinTable {
        &self.bins
    }

    fn count_type(&self) -> CountType {
        CountType::Integer
    }

    fn weight_names(&self) -> Vec<String> {
        self.norm_names.clone()
    }

    fn weights(&self, name: &str) -> Result<Weights> {
        let values = self.stored_norm_vector(name)?;
        Ok(Weights::from_divisive(
            name,
            &values,
            format!(".hic {name} vector (divisive), inverted to multiplicative on read"),
        ))
    }

    fn stored_weights(&self, name: &str) -> Result<Weights> {
        Ok(Weights {
            name: name.to_string(),
            values: self.stored_norm_vector(name)?,
            provenance: None,
        })
    }

    fn info(&self) -> MatrixInfo {
        let mut attributes: Vec<(String, serde_json::Value)> = vec![
            ("genome_id".into(), self.genome_id.clone().into()),
            ("format-version".into(), self.version.into()),
            ("bin-size".into(), self.resolution.into()),
            ("n_resolutions".into(), self.resolutions.len().into()),
            (
                "normalisations".into(),
                serde_json::Value::from(self.norm_names.clone()),
            ),
        ];
        for (key, value) in &self.attributes {
            attributes.push((key.clone(), value.clone().into()));
        }
        MatrixInfo {
            format: format!("hic (version {})", self.version),
            attributes,
            resolutions: self.resolutions.clone(),
            notes: vec![
                "normalisation vectors are divisive in .hic; weights are shown inverted \
                 (multiplicative, cooler convention)"
                    .into(),
            ],
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
        let cols = cols.start.min(n_bins) as u64..cols.end.min(n_bins) as u64;
        if rows.is_empty() || cols.is_empty() {
            return Ok(());
        }
        let mut block = PixelBlock::with_capacity(SINK_BLOCK_PIXELS);
        let first = self.bins.chrom_of(rows.start);
        let last = self.bins.chrom_of(rows.end - 1);
        for chrom1 in first..=last {
            let bins1 = self.bins.chrom_bins(chrom1);
            let lo = rows.start.max(bins1.start) as u64;
            let hi = rows.end.min(bins1.end) as u64;
            if lo < hi && lo < cols.end {
                self.stream_chromosome(chrom1, lo..hi, &cols, &mut block, sink)?;
            }
        }
        Ok(())
    }

    fn totals(&self) -> Result<(u64, f64)> {
        let plans = self.all_plans()?;
        let jobs: Vec<(usize, BlockEntry)> = plans
            .iter()
            .enumerate()
            .flat_map(|(id, plan)| plan.index.blocks.iter().map(move |entry| (id, *entry)))
            .collect();
        // Per-block sums in block order, then added in that order: independent of the threads.
        let per_block: Vec<(u64, f64, BlockStats)> = jobs
            .par_iter()
            .map(|(plan, entry)| {
                let mut out = Vec::new();
                let stats = self.decode_into(&plans[*plan], entry, &mut out)?;
                let sum = out.iter().map(|p| f64::from(p.count)).sum::<f64>();
                Ok((out.len() as u64, sum, stats))
            })
            .collect::<Result<_>>()?;
        // A matrix with records in both triangles may hold a pixel twice: count it once, as
        // the stream does.
        let mut triangles = vec![(0u64, 0u64); plans.len()];
        for ((plan, _), (_, _, stats)) in jobs.iter().zip(&per_block) {
            triangles[*plan].0 += stats.lower;
            triangles[*plan].1 += stats.upper;
        }
        if triangles
            .iter()
            .any(|&(lower, upper)| lower > 0 && upper > 0)
        {
            let n = self.bins.n_bins();
            let (mut nnz, mut sum) = (0u64, 0.0f64);
            self.read_pixels(0..n, 0..n, &mut |block| {
                nnz += block.len() as u64;
                sum += block.count.iter().sum::<f64>();
                Ok(())
            })?;
            return Ok((nnz, sum));
        }
        Ok(per_block
            .iter()
            .fold((0, 0.0), |(n, s), &(dn, ds, _)| (n + dn, s + ds)))
    }

    fn warnings(&self) -> Vec<String> {
        let past_end = self.past_end.lock().unwrap_or_else(|e| e.into_inner());
        let Some((&(chrom1, chrom2, number), &(_, (x, y)))) = past_end.iter().next() else {
            return Vec::new();
        };
        let total: u64 = past_end.values().map(|v| v.0).sum();
        vec![format!(
            "{}: dropped {total} record{} past the end of a chromosome in the blocks read \
             (the first at bins ({x}, {y}) of block {number} of {}), as hictk and hic2cool \
             drop them",
            self.source,
            if total == 1 { "" } else { "s" },
            self.pair_label(chrom1, chrom2)
        )]
    }
}

/// Sort the pixels of the band of `n_rows` rows from `first_row` by `(bin1, bin2)`, a pixel
/// stored in the upper triangle before its mirrored twin: a counting sort by row, then each row
/// sorted by column (in parallel for large bands).
fn sort_band(pixels: Vec<Pixel>, first_row: u64, n_rows: usize) -> Vec<Pixel> {
    let mut row_starts = vec![0usize; n_rows + 1];
    for pixel in &pixels {
        row_starts[(pixel.bin1() - first_row) as usize + 1] += 1;
    }
    for row in 0..n_rows {
        row_starts[row + 1] += row_starts[row];
    }
    let mut next = row_starts.clone();
    let mut sorted = vec![
        Pixel {
            key: 0,
            count: 0.0,
            mirrored: false
        };
        pixels.len()
    ];
    for pixel in pixels {
        let slot = &mut next[(pixel.bin1() - first_row) as usize];
        sorted[*slot] = pixel;
        *slot += 1;
    }
    let mut rows: Vec<&mut [Pixel]> = Vec::with_capacity(n_rows);
    let mut rest = sorted.as_mut_slice();
    for row in 0..n_rows {
        let (head, tail) = rest.split_at_mut(row_starts[row + 1] - row_starts[row]);
        rows.push(head);
        rest = tail;
    }
    if row_starts[n_rows] >= PARALLEL_SORT_MIN_PIXELS {
        rows.par_iter_mut()
            .for_each(|r| r.sort_unstable_by_key(|p| (p.key, p.mirrored)));
    } else {
        rows.iter_mut()
            .for_each(|r| r.sort_unstable_by_key(|p| (p.key, p.mirrored)));
    }
    sorted
}

/// Drop the mirrored lower-triangle record of a pixel that the file also stores in the upper
/// triangle (some writers store both triangles of intra-chromosomal matrices): each pixel is
/// read once, from its upper record, which is what hictk returns for `bin1 <= bin2`. `sorted`
/// comes from [`sort_band`], so a pixel's upper record precedes its mirrored one.
fn once_each(mut sorted: Vec<Pixel>) -> Vec<Pixel> {
    let mut previous: Option<u64> = None;
    sorted.retain(|pixel| {
        let keep = !(pixel.mirrored && previous == Some(pixel.key));
        previous = Some(pixel.key);
        keep
    });
    sorted
}

fn overlaps(a: &Range<u64>, b: &Range<u64>) -> bool {
    a.start < b.end && b.start < a.end && !a.is_empty() && !b.is_empty()
}

/// The error for a file with fragment resolutions only.
fn no_base_pair_resolution(path: &Path) -> Error {
    Error::format(
        path,
        "the .hic file has no base-pair resolution (only fragment resolutions, which this \
         reader does not read)",
    )
}

/// The most bins a `.hic` file of `file_len` bytes may declare at one resolution: every bin of a
/// real file costs it bytes (normalisation vectors hold one value per bin, blocks hold the
/// contacts), so a header that claims far more bins than the file has bytes is corrupt.
/// [`MIN_BIN_ALLOWANCE`] bins are always accepted, so that sparse files of large genomes at fine
/// resolutions open; [`BINS_PER_FILE_BYTE`] bins per byte of file beyond that, and never more
/// than 2^32 (bins are 32-bit in pixel keys).
pub(super) fn max_bins(file_len: u64) -> u64 {
    MIN_BIN_ALLOWANCE
        .max(file_len.saturating_mul(BINS_PER_FILE_BYTE))
        .min(1 << 32)
}

/// `1000, 5000, 10000`.
pub(crate) fn list_numbers(values: &[u64]) -> String {
    values
        .iter()
        .map(u64::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

impl HicReader {
    /// Read the first `n_bins` values of the divisive vector `vector` of chromosome `chrom`.
    pub(super) fn read_norm_vector(
        &self,
        vector: &NormVector,
        chrom: &Chrom,
        n_bins: usize,
    ) -> Result<Vec<f64>> {
        let what = format!(
            "the {} normalisation vector of {}",
            printable(&vector.name),
            printable(&chrom.name)
        );
        let mut reader = SeqReader::new(&self.file, &self.path, self.file_len, vector.position);
        let n_values = if self.version >= 9 {
            reader.i64(&what)?
        } else {
            i64::from(reader.i32(&what)?)
        };
        let value_bytes: u64 = if self.version >= 9 { 4 } else { 8 };
        let n_values = reader.count(n_values, value_bytes, &what)?;
        // Some writers append a few trailing values; more values than bins is accepted.
        if n_values < n_bins {
            return Err(Error::format(
                &self.path,
                format!("{what} has {n_values} values for the {n_bins} bins of the chromosome"),
            ));
        }
        let bytes = reader.bytes(n_bins * value_bytes as usize, &what)?;
        Ok(if self.version >= 9 {
            bytes
                .chunks_exact(4)
                .map(|b| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])))
                .collect()
        } else {
            bytes
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
                .collect()
        })
    }
}

impl HicReader {
    /// The expected-value vectors the footer stores at the open resolution (base pairs): the raw
    /// one (`NONE`) and the normalised ones, in file order.
    pub fn expected_values(&self) -> Result<Vec<HicExpected>> {
        let mut reader =
            SeqReader::new(&self.file, &self.path, self.file_len, self.footer_position);
        let what = "the footer";
        if self.version >= 9 {
            reader.i64(what)?;
        } else {
            reader.i32(what)?;
        }
        let n_entries = reader.i32("the master index")?;
        let n_entries = reader.count(i64::from(n_entries), 16, "the master index")?;
        for _ in 0..n_entries {
            reader.string("a master index key")?;
            reader.skip(12, "the master index")?;
        }
        let mut out = self.read_expected_section(&mut reader, false)?;
        if reader.remaining() > 0 {
            out.extend(self.read_expected_section(&mut reader, true)?);
        }
        Ok(out)
    }

    fn read_expected_section(
        &self,
        reader: &mut SeqReader,
        normalized: bool,
    ) -> Result<Vec<HicExpected>> {
        let what = if normalized {
            "the normalised expected values"
        } else {
            "the expected values"
        };
        let version = self.version;
        let value_bytes: u64 = if version >= 9 { 4 } else { 8 };
        let value = |reader: &mut SeqReader| -> Result<f64> {
            if version >= 9 {
                Ok(f64::from(reader.f32(what)?))
            } else {
                Ok(f64::from_le_bytes(reader.array::<8>(what)?))
            }
        };
        let n_vectors = reader.i32(what)?;
        let n_vectors = reader.count(i64::from(n_vectors), 10, what)?;
        let mut out = Vec::new();
        for _ in 0..n_vectors {
            let normalization = if normalized {
                reader.string(what)?
            } else {
                "NONE".to_string()
            };
            let unit = reader.string(what)?;
            let resolution = reader.i32(what)?;
            let n_values = if version >= 9 {
                reader.i64(what)?
            } else {
                i64::from(reader.i32(what)?)
            };
            let n_values = reader.count(n_values, value_bytes, what)?;
            let keep = unit == "BP" && i64::from(resolution) == self.resolution as i64;
            let mut values = Vec::new();
            if keep {
                values.reserve(n_values);
                for _ in 0..n_values {
                    values.push(value(reader)?);
                }
            } else {
                reader.skip(n_values as u64 * value_bytes, what)?;
            }
            let n_factors = reader.i32(what)?;
            let n_factors = reader.count(i64::from(n_factors), 4 + value_bytes, what)?;
            let mut factors = Vec::new();
            for _ in 0..n_factors {
                let chrom = reader.i32(what)?;
                let factor = value(reader)?;
                let name = usize::try_from(chrom)
                    .ok()
                    .and_then(|f| self.file_chrom.iter().position(|&c| c == f))
                    .map(|k| self.bins.chroms()[k].name.clone());
                if let (true, Some(name)) = (keep, name) {
                    factors.push((name, factor));
                }
            }
            if keep {
                out.push(HicExpected {
                    normalization,
                    resolution: resolution as u64,
                    values,
                    chrom_scale_factors: factors,
                });
            }
        }
        Ok(out)
    }
}
