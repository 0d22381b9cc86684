//! Juicer `.hic` reader (format versions 8 and 9).
//!
//! A `.hic` file (Durand et al. 2016, "Juicer provides a one-click system for analyzing
//! loop-resolution Hi-C experiments", *Cell Systems* 3:95) stores, for every pair of chromosomes and
//! every resolution, the contact matrix cut into zlib-compressed blocks, with an index of the blocks,
//! expected values and normalisation vectors. This module follows the Aiden lab specification,
//! <https://github.com/aidenlab/hic-format> (`HiCFormatV8.md`, `HiCFormatV9.md`); hictk and straw
//! were read to check our understanding of it. Only base-pair resolutions are read; fragment
//! resolutions are skipped.
//!
//! # Method
//!
//! [`HicReader::open`] reads the header (version, genome, attributes, chromosomes, resolutions),
//! the master index of chromosome-pair matrices in the footer, skips the expected-value sections
//! and reads the index of normalisation vectors (version 8: at the end of the footer; version 9: at
//! the position the header gives). The block index of a chromosome pair is read on first use and
//! cached. Every length read from the file is checked against the file size before anything is
//! allocated, so a truncated or corrupt file gives an [`Error::Format`] naming what was being
//! read, never a panic.
//!
//! A pixel query is answered one row chromosome at a time, in bands of rows sized so that a band
//! holds about [`BAND_BUDGET_BYTES`] of compressed blocks. For each band, the blocks (of every
//! chromosome pair `(i, j >= i)`) whose first possible row falls in the band are read with
//! positioned reads and inflated and decoded in parallel (rayon); their pixels are filtered to the
//! query, the band's own pixels are sorted by `(bin1, bin2)` and handed to the sink, and pixels of
//! later rows wait in the bucket of their band. Each block is thus read once, and memory stays
//! proportional to a band, not to the file. Results do not depend on the number of threads.
//!
//! # Coordinates
//!
//! Bins are fixed-size and 0-based, as [`BinTable::fixed`] makes them. Juicer's `All`
//! pseudo-chromosome (index 0) is left out of the bin table, as hictk does; the other chromosomes
//! keep their order. Blocks of the matrix of chromosomes `(i, j)`, `i <= j` in file order, hold
//! records `(x, y)` with `x` a bin of `i` and `y` a bin of `j`, so genome-wide `bin1 =
//! offset[i] + x` and `bin2 = offset[j] + y`. Intra-chromosomal matrices store one triangle; either
//! orientation is accepted and pixels are always returned with `bin1 <= bin2`. Version 8 blocks and
//! version 9 inter-chromosomal blocks form a square grid (`block = (y / blockBinCount) *
//! blockColumnCount + x / blockBinCount`); version 9 intra-chromosomal blocks are rotated, numbered
//! by position along the diagonal and a depth that doubles away from it.
//!
//! # Weights and counts
//!
//! `.hic` normalisation vectors (KR, VC, VC_SQRT, SCALE, ...) are divisive: `balanced = count /
//! (v[i] * v[j])`. They are inverted on read into cooler's multiplicative convention with
//! [`Weights::from_divisive`] (zero, negative and non-finite values become `NaN`); chromosomes
//! without a vector get `NaN`. Version 8 stores vectors as `float64`, version 9 as `float32`.
//! Counts are reported as [`CountType::Integer`]: raw Juicer counts are whole numbers, and hictk
//! converts the raw matrix to cooler's `int32` counts too.

use std::collections::HashMap;
use std::fs::File;
use std::io::ErrorKind;
use std::ops::Range;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use flate2::{Decompress, FlushDecompress, Status};
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::genome::{BinTable, Chrom};
use crate::io::{MatrixInfo, MatrixReader};
use crate::matrix::{CountType, PixelBlock, Weights};

/// The first four bytes of every `.hic` file.
const MAGIC: &[u8; 4] = b"HIC\0";
/// Compressed bytes of blocks decoded per band of rows; bounds the memory of a pixel query.
pub const BAND_BUDGET_BYTES: u64 = 4 << 20;
/// Pixels handed to the sink per call.
const SINK_BLOCK_PIXELS: usize = 1 << 16;
/// Bytes fetched per positioned read while parsing the header, footer and indexes.
const READ_CHUNK_BYTES: usize = 64 << 10;
/// Longest string (chromosome name, attribute value) accepted.
const MAX_STRING_BYTES: usize = 16 << 20;
/// Bands with more pixels than this are sorted in parallel.
const PARALLEL_SORT_MIN_PIXELS: usize = 1 << 16;
/// Size of one block-index entry: block number (int32), position (int64), size (int32).
const BLOCK_ENTRY_BYTES: u64 = 16;
/// The `short` count that marks an empty cell of a dense block.
const DENSE_SHORT_EMPTY: i16 = i16::MIN;

/// An open `.hic` file at one base-pair resolution.
#[derive(Debug)]
pub struct HicReader {
    path: PathBuf,
    source: String,
    file: File,
    file_len: u64,
    version: i32,
    genome_id: String,
    attributes: Vec<(String, String)>,
    resolutions: Vec<u64>,
    resolution: u64,
    bins: BinTable,
    /// File chromosome index of each bin-table chromosome (the file's index 0 is `All`).
    file_chrom: Vec<usize>,
    /// Master index: file chromosome indices `(i, j)`, `i <= j` -> matrix record position.
    master: HashMap<(usize, usize), u64>,
    /// For each bin-table chromosome `i`, the chromosomes `j >= i` with a matrix, ascending.
    partners: Vec<Vec<usize>>,
    /// Normalisation vectors at this resolution (base pairs), `NONE` excluded.
    norm_vectors: Vec<NormVector>,
    /// Names of the normalisations at this resolution, in file order.
    norm_names: Vec<String>,
    /// Block indexes read so far, by bin-table chromosome pair.
    matrix_cache: Mutex<HashMap<(usize, usize), Arc<MatrixIndex>>>,
    /// Compressed bytes per band ([`BAND_BUDGET_BYTES`]; smaller in tests, to get many bands).
    band_budget_bytes: u64,
}

/// One entry of the normalisation-vector index.
#[derive(Clone, Debug)]
struct NormVector {
    name: String,
    file_chrom: usize,
    position: u64,
}

/// The block index of one chromosome-pair matrix at the open resolution.
#[derive(Debug, Default)]
struct MatrixIndex {
    block_bin_count: u64,
    block_column_count: u64,
    blocks: Vec<BlockEntry>,
}

/// Where one block lies in the file.
#[derive(Clone, Copy, Debug)]
struct BlockEntry {
    number: u64,
    position: u64,
    size: u64,
}

/// A pixel while a band is assembled: `bin1 << 32 | bin2`, and the count as stored (a `short` or
/// a `float`, both exact in `f32`).
#[derive(Clone, Copy, Debug)]
struct Pixel {
    key: u64,
    count: f32,
}

impl Pixel {
    fn bin1(self) -> u64 {
        self.key >> 32
    }

    fn bin2(self) -> u64 {
        self.key & 0xFFFF_FFFF
    }
}

/// The parsed header.
struct Header {
    version: i32,
    footer_position: u64,
    genome_id: String,
    norm_vector_index: Option<(i64, i64)>,
    attributes: Vec<(String, String)>,
    chroms: Vec<Chrom>,
    resolutions: Vec<u64>,
}

/// The parts of the footer the reader keeps.
struct Footer {
    master: HashMap<(usize, usize), u64>,
    norm_vectors: Vec<NormVector>,
}

impl HicReader {
    /// Open `path` at `resolution` base pairs, or at the file's only base-pair resolution when
    /// `resolution` is `None`.
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
                ))
            }
            None if resolutions.len() == 1 => resolutions[0],
            None if resolutions.is_empty() => {
                return Err(Error::format(
                    path,
                    "the .hic file has no base-pair resolution",
                ))
            }
            None => {
                return Err(Error::format(
                    path,
                    format!(
                        "the .hic file has {} resolutions ({listed}); choose one with \
                         '{}::/resolutions/<bin size>'",
                        resolutions.len(),
                        path.display()
                    ),
                ))
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
        let bins = BinTable::fixed(chroms, resolution)
            .map_err(|e| Error::format(path, format!("chromosome table: {e}")))?;
        if bins.n_bins() as u64 > u64::from(u32::MAX) {
            return Err(Error::format(
                path,
                format!(
                    "{} bins at resolution {resolution}: more than this reader supports (2^32)",
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

    /// `chr2L-chr2R`, for messages.
    fn pair_label(&self, chrom1: usize, chrom2: usize) -> String {
        let chroms = self.bins.chroms();
        format!("{}-{}", chroms[chrom1].name, chroms[chrom2].name)
    }

    /// The block index of the matrix of bin-table chromosomes `chrom1 <= chrom2`, read on first
    /// use; `None` when the file has no matrix for the pair.
    fn matrix_index(&self, chrom1: usize, chrom2: usize) -> Result<Option<Arc<MatrixIndex>>> {
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
            let bin_size = reader.i32(&what)?;
            let block_bin_count = reader.i32(&what)?;
            let block_column_count = reader.i32(&what)?;
            let n_blocks = reader.i32(&what)?;
            let n_blocks = reader.count(i64::from(n_blocks), BLOCK_ENTRY_BYTES, &what)?;
            if unit != "BP" || i64::from(bin_size) != self.resolution as i64 {
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

    /// Read, inflate and decode one block, appending its pixels in the plan's rectangle to `out`.
    fn decode_into(&self, plan: &PairPlan, entry: &BlockEntry, out: &mut Vec<Pixel>) -> Result<()> {
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
        decode_block(&data, self.version, plan, out).map_err(block_error)
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
        let align = plans
            .iter()
            .find(|p| p.intra)
            .map_or(1, |p| p.index.block_bin_count);
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
            let sorted = sort_band(current, band_start, band_rows as usize);
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

    /// Read the first `n_bins` values of the divisive vector `vector` of chromosome `chrom`.
    fn read_norm_vector(
        &self,
        vector: &NormVector,
        chrom: &Chrom,
        n_bins: usize,
    ) -> Result<Vec<f64>> {
        let what = format!("the {} normalisation vector of {}", vector.name, chrom.name);
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
        if !self.norm_names.iter().any(|n| n == name) {
            let available = if self.norm_names.is_empty() {
                "none".to_string()
            } else {
                self.norm_names.join(", ")
            };
            return Err(Error::format(
                &self.path,
                format!(
                    "no normalisation '{name}' at resolution {} (available: {available})",
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
        Ok(Weights::from_divisive(
            name,
            &values,
            format!(".hic {name} vector (divisive), inverted to multiplicative on read"),
        ))
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
        let per_block: Vec<(u64, f64)> = jobs
            .par_iter()
            .map(|(plan, entry)| {
                let mut out = Vec::new();
                self.decode_into(&plans[*plan], entry, &mut out)?;
                let sum = out.iter().map(|p| f64::from(p.count)).sum::<f64>();
                Ok((out.len() as u64, sum))
            })
            .collect::<Result<_>>()?;
        Ok(per_block
            .iter()
            .fold((0, 0.0), |(n, s), &(dn, ds)| (n + dn, s + ds)))
    }
}

/// How the blocks of one matrix are decoded and filtered.
struct PairPlan {
    label: String,
    index: Arc<MatrixIndex>,
    intra: bool,
    /// Version 9 intra-chromosomal blocks: rotated along the diagonal.
    rotated: bool,
    offset1: u64,
    n1: u64,
    offset2: u64,
    n2: u64,
    /// Genome-wide `bin1` range kept.
    keep_rows: Range<u64>,
    /// Genome-wide `bin2` range kept.
    keep_cols: Range<u64>,
}

impl PairPlan {
    /// A range of local rows (chromosome 1, or the smaller bin for intra-chromosomal matrices) and
    /// one of local columns that hold every pixel block `number` can contain. Exact for grid
    /// blocks; for rotated blocks, a box around the block with a margin for rounding.
    fn block_box(&self, number: u64) -> (Range<u64>, Range<u64>) {
        let size = self.index.block_bin_count;
        let columns = self.index.block_column_count;
        let (rows, cols) = if self.rotated {
            // position along the diagonal: (x + y) / 2 / size; depth: log2(1 + |x - y| / sqrt(2) / size)
            let along = number % columns;
            let depth = (number / columns).min(1000) as i32;
            let sum_lo = (2 * along).saturating_mul(size);
            let sum_hi = (2 * along + 2).saturating_mul(size); // exclusive
            let scale = std::f64::consts::SQRT_2 * size as f64;
            let distance_lo = ((scale * (2f64.powi(depth) - 1.0)).floor() as u64).saturating_sub(2);
            let distance_hi =
                ((scale * (2f64.powi(depth + 1) - 1.0)).ceil() as u64).saturating_add(2);
            // smaller bin = (sum - distance) / 2, larger bin = (sum + distance) / 2
            let row_lo = sum_lo.saturating_sub(distance_hi) / 2;
            let row_hi = sum_hi.saturating_sub(distance_lo) / 2 + 1;
            let col_lo = sum_lo.saturating_add(distance_lo) / 2;
            let col_hi = sum_hi.saturating_add(distance_hi) / 2 + 1;
            (row_lo..row_hi, col_lo..col_hi)
        } else {
            let x = (number % columns).saturating_mul(size)
                ..(number % columns + 1).saturating_mul(size);
            let y = (number / columns).saturating_mul(size)
                ..(number / columns + 1).saturating_mul(size);
            if self.intra {
                // either triangle may be stored: rows are the smaller bin, columns the larger
                (
                    x.start.min(y.start)..x.end.min(y.end),
                    x.start.max(y.start)..x.end.max(y.end),
                )
            } else {
                (x, y)
            }
        };
        (
            rows.start.min(self.n1)..rows.end.min(self.n1),
            cols.start.min(self.n2)..cols.end.min(self.n2),
        )
    }
}

/// Sort the pixels of the band of `n_rows` rows from `first_row` by `(bin1, bin2)`: a counting
/// sort by row, then each row sorted by column (in parallel for large bands).
fn sort_band(pixels: Vec<Pixel>, first_row: u64, n_rows: usize) -> Vec<Pixel> {
    let mut row_starts = vec![0usize; n_rows + 1];
    for pixel in &pixels {
        row_starts[(pixel.bin1() - first_row) as usize + 1] += 1;
    }
    for row in 0..n_rows {
        row_starts[row + 1] += row_starts[row];
    }
    let mut next = row_starts.clone();
    let mut sorted = vec![Pixel { key: 0, count: 0.0 }; pixels.len()];
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
            .for_each(|r| r.sort_unstable_by_key(|p| p.key));
    } else {
        rows.iter_mut()
            .for_each(|r| r.sort_unstable_by_key(|p| p.key));
    }
    sorted
}

fn overlaps(a: &Range<u64>, b: &Range<u64>) -> bool {
    a.start < b.end && b.start < a.end && !a.is_empty() && !b.is_empty()
}

/// `1000, 5000, 10000`.
fn list_numbers(values: &[u64]) -> String {
    values
        .iter()
        .map(u64::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Inflate one zlib stream, checking that it ends properly.
fn inflate(compressed: &[u8]) -> std::result::Result<Vec<u8>, String> {
    // Deflate expands at most about 1032:1; anything beyond is corrupt.
    let limit = compressed
        .len()
        .saturating_mul(1100)
        .saturating_add(1 << 16);
    let mut stream = Decompress::new(true);
    let mut out: Vec<u8> = Vec::with_capacity(compressed.len().saturating_mul(4).clamp(256, limit));
    loop {
        if out.len() == out.capacity() {
            if out.len() >= limit {
                return Err("zlib data corrupt (it inflates past the deflate limit)".into());
            }
            out.reserve(out.capacity().min(limit - out.len()).max(256));
        }
        let consumed = stream.total_in() as usize;
        let produced = out.len();
        let status = stream
            .decompress_vec(&compressed[consumed..], &mut out, FlushDecompress::Finish)
            .map_err(|e| format!("zlib data corrupt ({e})"))?;
        match status {
            Status::StreamEnd => return Ok(out),
            Status::Ok | Status::BufError => {
                let stalled = stream.total_in() as usize == consumed && out.len() == produced;
                if stalled && out.len() < out.capacity() {
                    return Err("zlib data truncated (the stream stops before its end)".into());
                }
            }
        }
    }
}

/// A bounds-checked little-endian cursor over an inflated block.
struct BlockCursor<'a> {
    data: &'a [u8],
    pos: usize,
}

impl BlockCursor<'_> {
    fn take<const N: usize>(&mut self) -> std::result::Result<[u8; N], String> {
        match self.data.get(self.pos..self.pos + N) {
            Some(bytes) => {
                let mut out = [0u8; N];
                out.copy_from_slice(bytes);
                self.pos += N;
                Ok(out)
            }
            None => Err(format!(
                "block data truncated at byte {} of {}",
                self.pos,
                self.data.len()
            )),
        }
    }

    fn u8(&mut self) -> std::result::Result<u8, String> {
        Ok(self.take::<1>()?[0])
    }

    fn i16(&mut self) -> std::result::Result<i16, String> {
        Ok(i16::from_le_bytes(self.take()?))
    }

    fn i32(&mut self) -> std::result::Result<i32, String> {
        Ok(i32::from_le_bytes(self.take()?))
    }

    fn f32(&mut self) -> std::result::Result<f32, String> {
        Ok(f32::from_le_bytes(self.take()?))
    }

    /// A bin position or count stored as `int` (wide) or `short`.
    fn position(&mut self, wide: bool) -> std::result::Result<i64, String> {
        Ok(if wide {
            i64::from(self.i32()?)
        } else {
            i64::from(self.i16()?)
        })
    }

    /// A count stored as `float` or `short`.
    fn count(&mut self, float: bool) -> std::result::Result<f32, String> {
        Ok(if float {
            self.f32()?
        } else {
            f32::from(self.i16()?)
        })
    }

    fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }
}

/// Decode an inflated block of a version 8 / 9 file into `out` (only pixels in the plan's
/// rectangle, with `bin1 <= bin2`).
fn decode_block(
    data: &[u8],
    version: i32,
    plan: &PairPlan,
    out: &mut Vec<Pixel>,
) -> std::result::Result<(), String> {
    let mut cursor = BlockCursor { data, pos: 0 };
    let n_records = cursor.i32()?;
    if n_records < 0 {
        return Err(format!("negative record count {n_records}"));
    }
    let x_offset = i64::from(cursor.i32()?);
    let y_offset = i64::from(cursor.i32()?);
    let float_counts = cursor.u8()? != 0;
    let (wide_x, wide_y) = if version >= 9 {
        (cursor.u8()? != 0, cursor.u8()? != 0)
    } else {
        (false, false)
    };
    let representation = cursor.u8()?;
    out.reserve((n_records as usize).min(cursor.remaining() / 2));

    let mut emit = |x: i64, y: i64, count: f32| -> std::result::Result<(), String> {
        if x < 0 || y < 0 || x as u64 >= plan.n1 || y as u64 >= plan.n2 {
            return Err(format!(
                "record at bins ({x}, {y}) lies outside the {} x {} matrix",
                plan.n1, plan.n2
            ));
        }
        let (mut bin1, mut bin2) = (plan.offset1 + x as u64, plan.offset2 + y as u64);
        if bin1 > bin2 {
            std::mem::swap(&mut bin1, &mut bin2);
        }
        if plan.keep_rows.contains(&bin1) && plan.keep_cols.contains(&bin2) {
            out.push(Pixel {
                key: (bin1 << 32) | bin2,
                count,
            });
        }
        Ok(())
    };

    match representation {
        1 => {
            // list of rows: rowCount, then per row: rowNumber, recordCount, (binX, value)...
            let n_rows = cursor.position(wide_y)?;
            if n_rows < 0 {
                return Err(format!("negative row count {n_rows}"));
            }
            for _ in 0..n_rows {
                let y = y_offset + cursor.position(wide_y)?;
                let n_cells = cursor.position(wide_x)?;
                if n_cells < 0 {
                    return Err(format!("negative record count {n_cells} in row {y}"));
                }
                for _ in 0..n_cells {
                    let x = x_offset + cursor.position(wide_x)?;
                    let count = cursor.count(float_counts)?;
                    emit(x, y, count)?;
                }
            }
        }
        2 => {
            // dense: nPoints, width, then nPoints values in row-major order
            let n_points = i64::from(cursor.i32()?);
            let width = i64::from(cursor.i16()?);
            let value_bytes = if float_counts { 4 } else { 2 };
            if n_points < 0 || (n_points > 0 && width <= 0) {
                return Err(format!(
                    "dense block with {n_points} values and width {width}"
                ));
            }
            if n_points as u64 * value_bytes > cursor.remaining() as u64 {
                return Err(format!(
                    "dense block declares {n_points} values but holds {} bytes",
                    cursor.remaining()
                ));
            }
            for i in 0..n_points {
                let count = if float_counts {
                    let value = cursor.f32()?;
                    if value.is_nan() {
                        continue;
                    }
                    value
                } else {
                    let value = cursor.i16()?;
                    if value == DENSE_SHORT_EMPTY {
                        continue;
                    }
                    f32::from(value)
                };
                emit(x_offset + i % width, y_offset + i / width, count)?;
            }
        }
        other => {
            return Err(format!(
                "unknown matrix representation {other} (expected 1, list of rows, or 2, dense)"
            ))
        }
    }
    Ok(())
}

/// A sequential little-endian reader over a file, by positioned reads, bounds-checked against the
/// file size so that a corrupt length never reads or allocates past the end of the file.
struct SeqReader<'a> {
    file: &'a File,
    path: &'a Path,
    file_len: u64,
    pos: u64,
    buf: Vec<u8>,
    buf_start: u64,
}

impl<'a> SeqReader<'a> {
    fn new(file: &'a File, path: &'a Path, file_len: u64, pos: u64) -> Self {
        SeqReader {
            file,
            path,
            file_len,
            pos,
            buf: Vec::new(),
            buf_start: 0,
        }
    }

    fn remaining(&self) -> u64 {
        self.file_len.saturating_sub(self.pos)
    }

    fn truncated(&self, what: &str) -> Error {
        Error::format(
            self.path,
            format!(
                "truncated while reading {what} at offset {} (the file has {} bytes)",
                self.pos, self.file_len
            ),
        )
    }

    /// Make the buffer hold `n` bytes from the current position.
    fn fill(&mut self, n: usize, what: &str) -> Result<()> {
        let buf_end = self.buf_start + self.buf.len() as u64;
        if self.pos >= self.buf_start && self.pos + n as u64 <= buf_end {
            return Ok(());
        }
        if n as u64 > self.remaining() {
            return Err(self.truncated(what));
        }
        let len = (n.max(READ_CHUNK_BYTES) as u64).min(self.remaining()) as usize;
        self.buf.clear();
        self.buf.resize(len, 0);
        if let Err(e) = self.file.read_exact_at(&mut self.buf, self.pos) {
            self.buf.clear();
            return Err(if e.kind() == ErrorKind::UnexpectedEof {
                self.truncated(what)
            } else {
                Error::io(self.path, e)
            });
        }
        self.buf_start = self.pos;
        Ok(())
    }

    fn bytes(&mut self, n: usize, what: &str) -> Result<&[u8]> {
        self.fill(n, what)?;
        let start = (self.pos - self.buf_start) as usize;
        self.pos += n as u64;
        Ok(&self.buf[start..start + n])
    }

    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        let mut out = [0u8; N];
        out.copy_from_slice(self.bytes(N, what)?);
        Ok(out)
    }

    fn i32(&mut self, what: &str) -> Result<i32> {
        Ok(i32::from_le_bytes(self.array(what)?))
    }

    fn i64(&mut self, what: &str) -> Result<i64> {
        Ok(i64::from_le_bytes(self.array(what)?))
    }

    fn f32(&mut self, what: &str) -> Result<f32> {
        Ok(f32::from_le_bytes(self.array(what)?))
    }

    fn skip(&mut self, n: u64, what: &str) -> Result<()> {
        if n > self.remaining() {
            return Err(self.truncated(what));
        }
        self.pos += n;
        Ok(())
    }

    /// A NUL-terminated string.
    fn string(&mut self, what: &str) -> Result<String> {
        let mut text = Vec::new();
        loop {
            if self.remaining() == 0 {
                return Err(self.truncated(what));
            }
            self.fill(1, what)?;
            let start = (self.pos - self.buf_start) as usize;
            let available = &self.buf[start..];
            match available.iter().position(|&b| b == 0) {
                Some(end) => {
                    text.extend_from_slice(&available[..end]);
                    self.pos += end as u64 + 1;
                    return Ok(String::from_utf8_lossy(&text).into_owned());
                }
                None => {
                    text.extend_from_slice(available);
                    self.pos += available.len() as u64;
                }
            }
            if text.len() > MAX_STRING_BYTES {
                return Err(Error::format(
                    self.path,
                    format!(
                        "{what} at offset {}: string longer than {MAX_STRING_BYTES} bytes \
                         (the file is corrupt)",
                        self.pos
                    ),
                ));
            }
        }
    }

    /// Check a count read from the file: not negative, and `n` items of at least
    /// `min_item_bytes` each fit in the rest of the file.
    fn count(&self, n: i64, min_item_bytes: u64, what: &str) -> Result<usize> {
        let fits = u64::try_from(n)
            .ok()
            .filter(|&n| n.saturating_mul(min_item_bytes) <= self.remaining());
        match fits {
            Some(n) => Ok(n as usize),
            None => Err(Error::format(
                self.path,
                format!(
                    "{what}: count {n} at offset {} does not fit in the {} bytes left in the \
                     file (the file is truncated or corrupt)",
                    self.pos.saturating_sub(4),
                    self.remaining()
                ),
            )),
        }
    }
}

/// Parse the header at the start of the file.
fn read_header(reader: &mut SeqReader) -> Result<Header> {
    let path = reader.path;
    let magic: [u8; 4] = reader.array("the magic bytes")?;
    if &magic != MAGIC {
        return Err(Error::format(
            path,
            "not a .hic file: it does not start with the magic bytes HIC\\0",
        ));
    }
    let version = reader.i32("the version")?;
    if version != 8 && version != 9 {
        return Err(Error::format(
            path,
            format!(
                ".hic version {version} is not supported: this reader reads versions 8 and 9 \
                 (newer Juicer Tools or hictk can convert older files)"
            ),
        ));
    }
    let footer_position = reader.i64("the footer position")?;
    if footer_position <= 0 || footer_position as u64 >= reader.file_len {
        return Err(Error::format(
            path,
            format!(
                "the footer position {footer_position} in the header is outside the file ({} \
                 bytes): the file is truncated or corrupt",
                reader.file_len
            ),
        ));
    }
    let genome_id = reader.string("the genome id")?;
    let norm_vector_index = if version >= 9 {
        let position = reader.i64("the normalisation vector index position")?;
        let length = reader.i64("the normalisation vector index length")?;
        Some((position, length))
    } else {
        None
    };
    let n_attributes = reader.i32("the number of header attributes")?;
    let n_attributes = reader.count(i64::from(n_attributes), 2, "the header attributes")?;
    let mut attributes = Vec::with_capacity(n_attributes);
    for _ in 0..n_attributes {
        let key = reader.string("a header attribute key")?;
        let value = reader.string(&format!("the value of header attribute '{key}'"))?;
        attributes.push((key, value));
    }
    let n_chroms = reader.i32("the number of chromosomes")?;
    let length_bytes = if version >= 9 { 8 } else { 4 };
    let n_chroms = reader.count(i64::from(n_chroms), 1 + length_bytes, "the chromosome list")?;
    let mut chroms = Vec::with_capacity(n_chroms);
    for _ in 0..n_chroms {
        let name = reader.string("a chromosome name")?;
        let what = format!("the length of chromosome '{name}'");
        let length = if version >= 9 {
            reader.i64(&what)?
        } else {
            i64::from(reader.i32(&what)?)
        };
        if length < 0 {
            return Err(Error::format(
                path,
                format!("chromosome '{name}' has a negative length {length}"),
            ));
        }
        chroms.push(Chrom::new(name, length as u64));
    }
    let n_resolutions = reader.i32("the number of base-pair resolutions")?;
    let n_resolutions = reader.count(i64::from(n_resolutions), 4, "the resolution list")?;
    let mut resolutions = Vec::with_capacity(n_resolutions);
    for _ in 0..n_resolutions {
        let resolution = reader.i32("a base-pair resolution")?;
        if resolution <= 0 {
            return Err(Error::format(
                path,
                format!("resolution {resolution} in the header is not positive"),
            ));
        }
        resolutions.push(resolution as u64);
    }
    // Fragment resolutions (and the fragment sites after them) are not read.
    let n_fragment = reader.i32("the number of fragment resolutions")?;
    reader.count(i64::from(n_fragment), 4, "the fragment resolution list")?;
    Ok(Header {
        version,
        footer_position: footer_position as u64,
        genome_id,
        norm_vector_index,
        attributes,
        chroms,
        resolutions,
    })
}

/// Parse the footer: master index, expected values (skipped) and the normalisation-vector index
/// (entries at `resolution`, in base pairs).
fn read_footer(
    file: &File,
    path: &Path,
    file_len: u64,
    header: &Header,
    resolution: u64,
) -> Result<Footer> {
    let version = header.version;
    let mut reader = SeqReader::new(file, path, file_len, header.footer_position);
    let what = "the footer";
    if version >= 9 {
        reader.i64(what)?; // nBytes of the "version 5" footer
    } else {
        reader.i32(what)?;
    }
    let n_entries = reader.i32("the master index")?;
    // key (>= 4 bytes: "0_0\0"), position (8), size (4)
    let n_entries = reader.count(i64::from(n_entries), 16, "the master index")?;
    let mut master = HashMap::with_capacity(n_entries);
    for _ in 0..n_entries {
        let key = reader.string("a master index key")?;
        let position = reader.i64("the master index")?;
        let size = reader.i32("the master index")?;
        let Some((i, j)) = key
            .split_once('_')
            .and_then(|(a, b)| Some((a.parse::<usize>().ok()?, b.parse::<usize>().ok()?)))
        else {
            continue; // not a chromosome pair: nothing we can look up
        };
        if i >= header.chroms.len() || j >= header.chroms.len() || i > j {
            continue;
        }
        let end = u64::try_from(position)
            .ok()
            .zip(u64::try_from(size).ok())
            .map(|(p, s)| p.saturating_add(s));
        match end {
            Some(end) if end <= file_len => {
                master.insert((i, j), position as u64);
            }
            _ => {
                return Err(Error::format(
                    path,
                    format!(
                        "the matrix record of {}-{} (offset {position}, {size} bytes) lies \
                         outside the file ({file_len} bytes): the file is truncated or corrupt",
                        header.chroms[i].name, header.chroms[j].name
                    ),
                ))
            }
        }
    }

    // Version 9 gives the position of the normalisation vector index; version 8 (and version 9
    // files without it) have it after the expected-value sections.
    let index_position = match header.norm_vector_index {
        Some((position, length)) if position > 0 && length > 0 => {
            if (position as u64).saturating_add(length as u64) > file_len {
                return Err(Error::format(
                    path,
                    format!(
                        "the normalisation vector index (offset {position}, {length} bytes) lies \
                         outside the file ({file_len} bytes): the file is truncated"
                    ),
                ));
            }
            Some(position as u64)
        }
        _ => {
            skip_expected_values(&mut reader, version, false)?;
            if reader.remaining() > 0 {
                skip_expected_values(&mut reader, version, true)?;
            }
            (reader.remaining() > 0).then_some(reader.pos)
        }
    };
    let mut norm_vectors = Vec::new();
    if let Some(position) = index_position {
        reader.pos = position;
        norm_vectors = read_norm_index(&mut reader, header, resolution)?;
    }
    Ok(Footer {
        master,
        norm_vectors,
    })
}

/// Skip the expected-value vectors (`normalized`: the normalised expected-value vectors, which
/// carry a normalisation name first).
fn skip_expected_values(reader: &mut SeqReader, version: i32, normalized: bool) -> Result<()> {
    let what = if normalized {
        "the normalised expected values"
    } else {
        "the expected values"
    };
    let value_bytes: u64 = if version >= 9 { 4 } else { 8 };
    let n_vectors = reader.i32(what)?;
    let n_vectors = reader.count(i64::from(n_vectors), 10, what)?;
    for _ in 0..n_vectors {
        if normalized {
            reader.string(what)?; // normalisation
        }
        reader.string(what)?; // unit
        reader.i32(what)?; // bin size
        let n_values = if version >= 9 {
            reader.i64(what)?
        } else {
            i64::from(reader.i32(what)?)
        };
        let n_values = reader.count(n_values, value_bytes, what)?;
        reader.skip(n_values as u64 * value_bytes, what)?;
        let n_factors = reader.i32(what)?;
        let n_factors = reader.count(i64::from(n_factors), 4 + value_bytes, what)?;
        reader.skip(n_factors as u64 * (4 + value_bytes), what)?;
    }
    Ok(())
}

/// Read the normalisation vector index, keeping the base-pair vectors at `resolution`.
fn read_norm_index(
    reader: &mut SeqReader,
    header: &Header,
    resolution: u64,
) -> Result<Vec<NormVector>> {
    let what = "the normalisation vector index";
    let size_bytes: u64 = if header.version >= 9 { 8 } else { 4 };
    let n_entries = reader.i32(what)?;
    let n_entries = reader.count(i64::from(n_entries), 18 + size_bytes, what)?;
    let mut vectors = Vec::new();
    for _ in 0..n_entries {
        let name = reader.string(what)?;
        let chrom = reader.i32(what)?;
        let unit = reader.string(what)?;
        let bin_size = reader.i32(what)?;
        let position = reader.i64(what)?;
        let n_bytes = if header.version >= 9 {
            reader.i64(what)?
        } else {
            i64::from(reader.i32(what)?)
        };
        if unit != "BP" || i64::from(bin_size) != resolution as i64 || name == "NONE" {
            continue;
        }
        let chrom_name = usize::try_from(chrom)
            .ok()
            .and_then(|c| header.chroms.get(c))
            .map(|c| c.name.clone());
        let Some(chrom_name) = chrom_name else {
            return Err(Error::format(
                reader.path,
                format!(
                    "{what}: the {name} vector names chromosome index {chrom}, not in the header"
                ),
            ));
        };
        let end = u64::try_from(position)
            .ok()
            .zip(u64::try_from(n_bytes).ok())
            .map(|(p, n)| p.saturating_add(n));
        if end.is_none_or(|end| end > reader.file_len) {
            return Err(Error::format(
                reader.path,
                format!(
                    "the {name} normalisation vector of {chrom_name} (offset {position}, {n_bytes} \
                     bytes) lies outside the file ({} bytes): the file is truncated or corrupt",
                    reader.file_len
                ),
            ));
        }
        vectors.push(NormVector {
            name,
            file_chrom: chrom as usize,
            position: position as u64,
        });
    }
    Ok(vectors)
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;
    use std::io::Write;

    use flate2::write::ZlibEncoder;
    use flate2::Compression;

    use super::*;

    const TEST_FILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/hic_test_file.hic");

    type Triplets = Vec<(u64, u64, f64)>;

    /// Every pixel of `rows x cols`, checking the stream's order and triangle on the way.
    fn dump(reader: &HicReader, rows: Range<usize>, cols: Range<usize>) -> Triplets {
        let mut out: Triplets = Vec::new();
        reader
            .read_pixels(rows, cols, &mut |block| {
                assert!(!block.is_empty());
                for k in 0..block.len() {
                    out.push((block.bin1[k], block.bin2[k], block.count[k]));
                }
                Ok(())
            })
            .unwrap();
        for pair in out.windows(2) {
            assert!(
                (pair[0].0, pair[0].1) < (pair[1].0, pair[1].1),
                "not sorted: {pair:?}"
            );
        }
        assert!(out.iter().all(|p| p.0 <= p.1));
        out
    }

    fn filter(all: &Triplets, rows: &Range<usize>, cols: &Range<usize>) -> Triplets {
        all.iter()
            .copied()
            .filter(|p| rows.contains(&(p.0 as usize)) && cols.contains(&(p.1 as usize)))
            .collect()
    }

    fn test_file() -> HicReader {
        HicReader::open(Path::new(TEST_FILE), None).unwrap()
    }

    #[test]
    fn reads_the_bin_table_and_metadata() {
        let reader = test_file();
        let bins = reader.bins();
        // hictkpy.File(path, 100000): nbins 1380, nchroms 8, chromosomes() in this order
        assert_eq!(bins.n_bins(), 1380);
        let names: Vec<&str> = bins.chroms().iter().map(|c| c.name.as_str()).collect();
        assert_eq!(
            names,
            ["chr2L", "chr2R", "chr3L", "chr3R", "chr4", "chrX", "chrY", "chrM"]
        );
        assert_eq!(bins.chroms()[0].length_bp, 23_513_712);
        assert_eq!(
            bins.chrom_offsets(),
            &[0, 236, 489, 771, 1092, 1106, 1342, 1379, 1380]
        );
        assert_eq!(bins.bin_size_bp(), Some(100_000));
        assert_eq!(reader.resolutions(), &[100_000]);
        assert_eq!(reader.version(), 9);
        assert_eq!(reader.count_type(), CountType::Integer);
        assert_eq!(reader.weight_names(), ["ICE"]);
        let info = reader.info();
        assert_eq!(info.format, "hic (version 9)");
        assert_eq!(info.resolutions, [100_000]);
        assert!(info.notes[0].contains("divisive"));
        assert!(info
            .attributes
            .iter()
            .any(|(k, v)| k == "software" && v.as_str() == Some("Juicer Tools Version 3.30.00")));
    }

    #[test]
    fn whole_genome_totals_match_hictkpy() {
        // hictkpy.File(path, 100000).fetch(): nnz() 890384, sum() 119208613
        let reader = test_file();
        let all = dump(&reader, 0..1380, 0..1380);
        assert_eq!(all.len(), 890_384);
        assert_eq!(all.iter().map(|p| p.2).sum::<f64>(), 119_208_613.0);
        assert_eq!(reader.totals().unwrap(), (890_384, 119_208_613.0));
    }

    #[test]
    fn chromosome_query_matches_hictkpy() {
        // hictkpy: f.fetch("chr2L"): nnz() 27733, sum() 19968156
        let reader = test_file();
        let chr2l = reader.bins().parse_region_bins("chr2L").unwrap();
        let pixels = dump(&reader, chr2l.clone(), chr2l);
        assert_eq!(pixels.len(), 27_733);
        assert_eq!(pixels.iter().map(|p| p.2).sum::<f64>(), 19_968_156.0);
    }

    #[test]
    fn pixel_values_match_hictkpy() {
        let reader = test_file();
        let all = dump(&reader, 0..1380, 0..1380);
        let get = |i: u64, j: u64| {
            all.iter()
                .find(|p| p.0 == i && p.1 == j)
                .map_or(0.0, |p| p.2)
        };
        // f.fetch("chr2L:0-300000").to_numpy() = [[101360 29915 4996] [29915 145946 29754] ...]
        assert_eq!(get(0, 0), 101_360.0);
        assert_eq!(get(0, 1), 29_915.0);
        assert_eq!(get(0, 2), 4_996.0);
        assert_eq!(get(1, 1), 145_946.0);
        assert_eq!(get(2, 2), 115_171.0);
        // f.fetch("chr2L:0-200000", "chr3R:1000000-1200000").to_numpy() = [[11 4] [11 10]];
        // chr3R starts at bin 771
        assert_eq!(get(0, 781), 11.0);
        assert_eq!(get(0, 782), 4.0);
        assert_eq!(get(1, 781), 11.0);
        assert_eq!(get(1, 782), 10.0);
    }

    #[test]
    fn region_queries_equal_filtering_the_full_dump() {
        let reader = test_file();
        let all = dump(&reader, 0..1380, 0..1380);
        let bins = reader.bins();
        let region = |r: &str| bins.parse_region_bins(r).unwrap();
        let queries = [
            (region("chr2L:1M-5M"), region("chr2L:1M-5M")),
            (region("chr2L:3M-4M"), region("chr3R:10M-20M")),
            (region("chr3R:10M-20M"), region("chr2L:3M-4M")),
            (region("chrX"), region("chrX:5M-6M")),
            (10..800, 300..1200),
            (1000..1380, 0..1380),
            (500..501, 0..1380),
            (1379..1380, 1379..1380),
            (700..700, 0..1380),
        ];
        for (rows, cols) in queries {
            let expected = filter(&all, &rows, &cols);
            assert_eq!(
                dump(&reader, rows.clone(), cols.clone()),
                expected,
                "{rows:?} x {cols:?}"
            );
        }
    }

    #[test]
    fn ice_weights_match_hictkpy_and_the_mcool() {
        let reader = test_file();
        let weights = reader.weights("ICE").unwrap();
        assert_eq!(weights.values.len(), 1380);
        assert!(weights.provenance.as_deref().unwrap().contains("divisive"));
        // hictkpy f.weights("ICE")[[0, 1, 2, 500, 1000, 1370]] (divisive):
        let divisive = [
            382.85430908,
            446.75976562,
            349.08926392,
            209.37458801,
            161.76849365,
            0.93698156,
        ];
        // cooler_test_file.mcool::/resolutions/100000 bins/weight at the same bins (multiplicative):
        let mcool = [
            0.00261196, 0.00223834, 0.0028646, 0.00477613, 0.00618167, 1.06725689,
        ];
        for (k, &bin) in [0usize, 1, 2, 500, 1000, 1370].iter().enumerate() {
            let w = weights.values[bin];
            assert!((w * divisive[k] - 1.0).abs() < 1e-7, "bin {bin}: {w}");
            assert!((w / mcool[k] - 1.0).abs() < 1e-5, "bin {bin}: {w}");
        }
        // chrM (bin 1379) has no ICE vector; hictkpy gives NaN for 61 bins
        assert!(weights.values[1379].is_nan());
        assert_eq!(weights.values.iter().filter(|w| w.is_nan()).count(), 61);
        assert!(reader
            .weights("KR")
            .unwrap_err()
            .to_string()
            .contains("available: ICE"));
    }

    #[test]
    fn resolution_choice_is_checked() {
        let error = HicReader::open(Path::new(TEST_FILE), Some(5_000)).unwrap_err();
        let message = error.to_string();
        assert!(message.contains("hic_test_file.hic"), "{message}");
        assert!(
            message.contains("5000") && message.contains("100000"),
            "{message}"
        );
        let reader = HicReader::open(Path::new(TEST_FILE), Some(100_000)).unwrap();
        assert_eq!(reader.resolution(), 100_000);
        assert_eq!(
            HicReader::list_resolutions(Path::new(TEST_FILE)).unwrap(),
            [100_000]
        );
    }

    /// Open, stream every pixel and read every weight vector.
    fn read_everything(path: &Path) -> Result<()> {
        let reader = HicReader::open(path, None)?;
        let n = reader.bins().n_bins();
        reader.read_pixels(0..n, 0..n, &mut |_| Ok(()))?;
        reader.totals()?;
        if n < 10_000_000 {
            for name in reader.weight_names() {
                reader.weights(&name)?;
            }
        }
        Ok(())
    }

    #[test]
    fn truncated_files_are_errors() {
        let bytes = std::fs::read(TEST_FILE).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let len = bytes.len();
        for n in [
            0,
            3,
            10,
            100,
            283,
            1000,
            343_990,
            len / 2,
            len - 5_000,
            len - 100,
            len - 1,
        ] {
            let path = dir.path().join(format!("truncated_{n}.hic"));
            std::fs::write(&path, &bytes[..n]).unwrap();
            let error = read_everything(&path).expect_err(&format!("{n} bytes"));
            let message = error.to_string();
            assert!(message.contains(&format!("truncated_{n}.hic")), "{message}");
        }
    }

    #[test]
    fn corrupt_bytes_never_panic() {
        let bytes = std::fs::read(TEST_FILE).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("corrupt.hic");
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for _ in 0..40 {
            let mut copy = bytes.clone();
            for _ in 0..4 {
                let at = (next() % copy.len() as u64) as usize;
                copy[at] = next() as u8;
            }
            std::fs::write(&path, &copy).unwrap();
            let _ = read_everything(&path);
        }
    }

    // ---- synthetic version 8 and 9 files, written by a test writer that follows the spec ----

    /// Little-endian writer.
    #[derive(Default)]
    struct Out(Vec<u8>);

    impl Out {
        fn len(&self) -> u64 {
            self.0.len() as u64
        }
        fn u8(&mut self, v: u8) {
            self.0.push(v);
        }
        fn i16(&mut self, v: i16) {
            self.0.extend(v.to_le_bytes());
        }
        fn i32(&mut self, v: i64) {
            self.0.extend(i32::try_from(v).unwrap().to_le_bytes());
        }
        fn i64(&mut self, v: i64) {
            self.0.extend(v.to_le_bytes());
        }
        fn f32(&mut self, v: f32) {
            self.0.extend(v.to_le_bytes());
        }
        fn f64(&mut self, v: f64) {
            self.0.extend(v.to_le_bytes());
        }
        /// `int` in version 8, `long` in version 9.
        fn int_or_long(&mut self, version: i32, v: i64) {
            if version >= 9 {
                self.i64(v)
            } else {
                self.i32(v)
            }
        }
        /// `double` in version 8, `float` in version 9.
        fn value(&mut self, version: i32, v: f64) {
            if version >= 9 {
                self.f32(v as f32)
            } else {
                self.f64(v)
            }
        }
        /// A bin position or count as `int` (wide) or `short`.
        fn position(&mut self, wide: bool, v: u64) {
            if wide {
                self.i32(v as i64)
            } else {
                self.i16(i16::try_from(v).unwrap())
            }
        }
        fn string(&mut self, s: &str) {
            self.0.extend(s.as_bytes());
            self.0.push(0);
        }
        fn patch_i64(&mut self, at: u64, v: i64) {
            self.0[at as usize..at as usize + 8].copy_from_slice(&v.to_le_bytes());
        }
        fn patch_i32(&mut self, at: u64, v: i64) {
            let v = i32::try_from(v).unwrap();
            self.0[at as usize..at as usize + 4].copy_from_slice(&v.to_le_bytes());
        }
    }

    /// A divisive vector: normalisation name, chromosome, values.
    type NormSpec = (&'static str, usize, Vec<f64>);
    /// One resolution: bin size, upper-triangle pixels (genome-wide bins), vectors.
    type Level = (u64, BTreeMap<(u64, u64), f32>, Vec<NormSpec>);

    /// A small genome with pixels at two resolutions and a few normalisation vectors.
    struct Synthetic {
        version: i32,
        chroms: Vec<Chrom>,
        block_bin_count: u64,
        levels: Vec<Level>,
        /// Store intra-chromosomal records with x >= y (the other triangle).
        intra_lower: bool,
    }

    fn synthetic(version: i32) -> Synthetic {
        let chroms = vec![
            Chrom::new("c1", 365),
            Chrom::new("c2", 230),
            Chrom::new("c3", 41),
        ];
        let fine = BinTable::fixed(chroms.clone(), 10).unwrap();
        let coarse = BinTable::fixed(chroms.clone(), 20).unwrap();
        let mut state = 0x9E37_79B9_7F4A_7C15u64 ^ version as u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let n = fine.n_bins() as u64;
        let mut pixels = BTreeMap::new();
        for i in 0..n {
            for j in i..n {
                let (ci, cj) = (fine.chrom_of(i as usize), fine.chrom_of(j as usize));
                let p = if ci == cj {
                    0.7 / (1.0 + (j - i) as f64 / 6.0)
                } else {
                    0.1
                };
                if (next() % 1000) as f64 >= p * 1000.0 {
                    continue;
                }
                let count = match next() % 50 {
                    0 => 40_000.0,        // too large for a short: a float block
                    1 if ci != cj => 2.5, // not a whole number: a float block
                    k => (k % 17 + 1) as f32,
                };
                pixels.insert((i, j), count);
            }
        }
        let mut coarse_pixels: BTreeMap<(u64, u64), f32> = BTreeMap::new();
        for (&(i, j), &v) in &pixels {
            let to_coarse = |b: u64| {
                let chrom = fine.chrom_of(b as usize);
                let local = b as usize - fine.chrom_bins(chrom).start;
                (coarse.chrom_bins(chrom).start + local / 2) as u64
            };
            *coarse_pixels
                .entry((to_coarse(i), to_coarse(j)))
                .or_default() += v;
        }
        let vector = |n: usize, seed: u64| -> Vec<f64> {
            (0..n)
                .map(|k| match (k as u64 + seed) % 11 {
                    0 => 0.0, // masked: NaN after inversion
                    r => 0.5 + r as f64 / 8.0,
                })
                .collect()
        };
        let fine_norms = vec![
            ("KR", 0, vector(37, 1)),
            ("KR", 1, vector(23, 2)),
            ("VC", 0, vector(37, 3)),
            ("VC", 1, vector(23, 4)),
            ("VC", 2, vector(5, 5)),
        ];
        let coarse_norms = vec![("SCALE", 0, vector(19, 6))];
        Synthetic {
            version,
            chroms,
            block_bin_count: 4,
            levels: vec![(10, pixels, fine_norms), (20, coarse_pixels, coarse_norms)],
            intra_lower: version == 8,
        }
    }

    /// The block a record `(x, y)` belongs to, as the spec numbers blocks.
    fn block_number(rotated: bool, x: u64, y: u64, size: u64, columns: u64) -> u64 {
        if rotated {
            let along = (x + y) / 2 / size;
            let distance = (x as f64 - y as f64).abs();
            let depth = (1.0 + distance / std::f64::consts::SQRT_2 / size as f64).log2() as u64;
            depth * columns + along
        } else {
            (y / size) * columns + x / size
        }
    }

    /// One compressed block; the representation and field widths vary with the block number so
    /// that every combination is written.
    fn encode_block(version: i32, number: u64, records: &[(u64, u64, f32)]) -> Vec<u8> {
        let x0 = records.iter().map(|r| r.0).min().unwrap();
        let y0 = records.iter().map(|r| r.1).min().unwrap();
        let short = number % 3 != 0
            && records
                .iter()
                .all(|r| r.2.fract() == 0.0 && r.2.abs() <= 32_767.0);
        let dense = number % 4 == 1;
        let (wide_x, wide_y) = if version >= 9 {
            (number % 2 == 1, number / 2 % 2 == 1)
        } else {
            (false, false)
        };
        let mut raw = Out::default();
        raw.i32(records.len() as i64);
        raw.i32(x0 as i64);
        raw.i32(y0 as i64);
        raw.u8(u8::from(!short));
        if version >= 9 {
            raw.u8(u8::from(wide_x));
            raw.u8(u8::from(wide_y));
        }
        raw.u8(if dense { 2 } else { 1 });
        if dense {
            let width = records.iter().map(|r| r.0).max().unwrap() - x0 + 1;
            let height = records.iter().map(|r| r.1).max().unwrap() - y0 + 1;
            let mut grid = vec![None; (width * height) as usize];
            for &(x, y, v) in records {
                grid[((y - y0) * width + (x - x0)) as usize] = Some(v);
            }
            raw.i32((width * height) as i64);
            raw.i16(width as i16);
            for cell in grid {
                match (cell, short) {
                    (Some(v), true) => raw.i16(v as i16),
                    (None, true) => raw.i16(i16::MIN),
                    (Some(v), false) => raw.f32(v),
                    (None, false) => raw.f32(f32::NAN),
                }
            }
        } else {
            let mut rows: BTreeMap<u64, Vec<(u64, f32)>> = BTreeMap::new();
            for &(x, y, v) in records {
                rows.entry(y).or_default().push((x, v));
            }
            raw.position(wide_y, rows.len() as u64);
            for (y, cells) in rows {
                raw.position(wide_y, y - y0);
                raw.position(wide_x, cells.len() as u64);
                for (x, v) in cells {
                    raw.position(wide_x, x - x0);
                    if short {
                        raw.i16(v as i16);
                    } else {
                        raw.f32(v);
                    }
                }
            }
        }
        let mut encoder = ZlibEncoder::new(Vec::new(), Compression::default());
        encoder.write_all(&raw.0).unwrap();
        encoder.finish().unwrap()
    }

    fn write_hic(s: &Synthetic) -> Vec<u8> {
        let version = s.version;
        let mut out = Out::default();
        out.0.extend(b"HIC\0");
        out.i32(version.into());
        let footer_slot = out.len();
        out.i64(0);
        out.string("synthetic");
        let index_slot = out.len();
        if version >= 9 {
            out.i64(0);
            out.i64(0);
        }
        out.i32(2);
        out.string("software");
        out.string("contactmap test writer");
        out.string("hicFileScalingFactor");
        out.string("1.0");
        out.i32(s.chroms.len() as i64 + 1);
        out.string("All");
        out.int_or_long(version, 1);
        for chrom in &s.chroms {
            out.string(&chrom.name);
            out.int_or_long(version, chrom.length_bp as i64);
        }
        out.i32(s.levels.len() as i64);
        for level in &s.levels {
            out.i32(level.0 as i64);
        }
        out.i32(0); // fragment resolutions

        // The "All" matrix: one level at another bin size, no blocks.
        let mut master: Vec<(String, u64, u64)> = Vec::new();
        let start = out.len();
        for v in [0, 0, 1] {
            out.i32(v);
        }
        out.string("BP");
        out.i32(0);
        out.f32(0.0);
        out.i32(0);
        out.f32(0.0);
        out.f32(0.0);
        for v in [1, 1, 1, 0] {
            out.i32(v);
        }
        master.push(("0_0".into(), start, out.len() - start));

        let size = s.block_bin_count;
        for c1 in 0..s.chroms.len() {
            for c2 in c1..s.chroms.len() {
                let mut metadata = Vec::new();
                for (level, (resolution, pixels, _)) in s.levels.iter().enumerate() {
                    let table = BinTable::fixed(s.chroms.clone(), *resolution).unwrap();
                    let (o1, o2) = (
                        table.chrom_bins(c1).start as u64,
                        table.chrom_bins(c2).start as u64,
                    );
                    let (n1, n2) = (
                        table.chrom_bins(c1).len() as u64,
                        table.chrom_bins(c2).len() as u64,
                    );
                    let intra = c1 == c2;
                    let rotated = intra && version >= 9;
                    let columns = if rotated {
                        n1 / size + 1
                    } else {
                        n1.max(n2) / size + 1
                    };
                    let mut blocks: BTreeMap<u64, Vec<(u64, u64, f32)>> = BTreeMap::new();
                    let mut sum = 0.0;
                    for (&(i, j), &v) in pixels {
                        let (ci, cj) = (table.chrom_of(i as usize), table.chrom_of(j as usize));
                        if (ci, cj) != (c1, c2) {
                            continue;
                        }
                        let (mut x, mut y) = (i - o1, j - o2);
                        if intra && s.intra_lower {
                            std::mem::swap(&mut x, &mut y);
                        }
                        let number = block_number(rotated, x, y, size, columns);
                        blocks.entry(number).or_default().push((x, y, v));
                        sum += v;
                    }
                    let mut entries = Vec::new();
                    for (number, records) in &blocks {
                        let bytes = encode_block(version, *number, records);
                        entries.push((*number, out.len(), bytes.len() as u64));
                        out.0.extend(bytes);
                    }
                    metadata.push((level, *resolution, columns, sum, entries));
                }
                if metadata.iter().all(|m| m.4.is_empty()) {
                    continue;
                }
                let start = out.len();
                out.i32(c1 as i64 + 1);
                out.i32(c2 as i64 + 1);
                out.i32(metadata.len() as i64);
                for (level, resolution, columns, sum, entries) in metadata {
                    out.string("BP");
                    out.i32(level as i64);
                    out.f32(sum);
                    out.i32(0);
                    out.f32(0.0);
                    out.f32(0.0);
                    out.i32(resolution as i64);
                    out.i32(size as i64);
                    out.i32(columns as i64);
                    out.i32(entries.len() as i64);
                    for (number, position, bytes) in entries {
                        out.i32(number as i64);
                        out.i64(position as i64);
                        out.i32(bytes as i64);
                    }
                }
                master.push((format!("{}_{}", c1 + 1, c2 + 1), start, out.len() - start));
            }
        }

        // Footer: master index, expected values, normalised expected values, vector index.
        let footer = out.len();
        out.patch_i64(footer_slot, footer as i64);
        out.int_or_long(version, 0); // nBytes, patched below
        out.i32(master.len() as i64);
        for (key, position, bytes) in &master {
            out.string(key);
            out.i64(*position as i64);
            out.i32(*bytes as i64);
        }
        out.i32(s.levels.len() as i64);
        for (resolution, _, _) in &s.levels {
            out.string("BP");
            out.i32(*resolution as i64);
            out.int_or_long(version, 3);
            for v in [10.0, 5.0, 2.5] {
                out.value(version, v);
            }
            out.i32(1);
            out.i32(1);
            out.value(version, 1.5);
        }
        let n_bytes = out.len() - footer - if version >= 9 { 8 } else { 4 };
        if version >= 9 {
            out.patch_i64(footer, n_bytes as i64);
        } else {
            out.patch_i32(footer, n_bytes as i64);
        }
        out.i32(s.levels.len() as i64);
        for (resolution, _, _) in &s.levels {
            out.string("VC");
            out.string("BP");
            out.i32(*resolution as i64);
            out.int_or_long(version, 2);
            out.value(version, 1.0);
            out.value(version, 0.5);
            out.i32(0);
        }
        let index_position = out.len();
        let vectors: Vec<(u64, &str, usize, &Vec<f64>)> = s
            .levels
            .iter()
            .flat_map(|(r, _, norms)| norms.iter().map(move |(n, c, v)| (*r, *n, *c, v)))
            .collect();
        out.i32(vectors.len() as i64 + 1);
        let mut slots = Vec::new();
        for &(resolution, name, chrom, values) in &vectors {
            out.string(name);
            out.i32(chrom as i64 + 1);
            out.string("BP");
            out.i32(resolution as i64);
            slots.push(out.len());
            out.i64(0);
            let (count_bytes, value_bytes) = if version >= 9 { (8, 4) } else { (4, 8) };
            out.int_or_long(
                version,
                count_bytes + (values.len() as i64 + 1) * value_bytes,
            );
        }
        // a fragment-unit vector, which the reader skips (it points nowhere)
        out.string("KR");
        out.i32(1);
        out.string("FRAG");
        out.i32(1);
        out.i64(0);
        out.int_or_long(version, 0);
        if version >= 9 {
            out.patch_i64(index_slot, index_position as i64);
            out.patch_i64(index_slot + 8, (out.len() - index_position) as i64);
        }
        for (slot, &(_, _, _, values)) in slots.into_iter().zip(&vectors) {
            out.patch_i64(slot, out.len() as i64);
            // one trailing value more than there are bins, as some writers leave
            out.int_or_long(version, values.len() as i64 + 1);
            for &v in values.iter().chain([0.0].iter()) {
                out.value(version, v);
            }
        }
        out.0
    }

    fn write_temp(dir: &tempfile::TempDir, name: &str, bytes: &[u8]) -> PathBuf {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }

    fn as_triplets(pixels: &BTreeMap<(u64, u64), f32>) -> Triplets {
        pixels
            .iter()
            .map(|(&(i, j), &v)| (i, j, f64::from(v)))
            .collect()
    }

    #[test]
    fn synthetic_files_round_trip_at_every_resolution() {
        let dir = tempfile::tempdir().unwrap();
        for version in [8, 9] {
            let s = synthetic(version);
            let path = write_temp(&dir, &format!("v{version}.hic"), &write_hic(&s));
            let error = HicReader::open(&path, None).unwrap_err().to_string();
            assert!(error.contains("2 resolutions (10, 20)"), "{error}");
            assert_eq!(HicReader::list_resolutions(&path).unwrap(), [10, 20]);
            for (resolution, pixels, norms) in &s.levels {
                let reader = HicReader::open(&path, Some(*resolution)).unwrap();
                assert_eq!(reader.version(), version);
                assert_eq!(reader.resolutions(), &[10, 20]);
                let n = reader.bins().n_bins();
                assert_eq!(
                    n,
                    if *resolution == 10 {
                        37 + 23 + 5
                    } else {
                        19 + 12 + 3
                    }
                );
                let expected = as_triplets(pixels);
                assert!(expected.len() > 150, "{}", expected.len());
                assert_eq!(
                    dump(&reader, 0..n, 0..n),
                    expected,
                    "v{version} at {resolution}"
                );
                // Bands of one block row: rotated blocks deep off the diagonal span many bands.
                let mut banded = HicReader::open(&path, Some(*resolution)).unwrap();
                banded.band_budget_bytes = 1;
                assert_eq!(dump(&banded, 0..n, 0..n), expected);
                let mut n_calls = 0;
                banded
                    .read_pixels(0..n, 0..n, &mut |_| {
                        n_calls += 1;
                        Ok(())
                    })
                    .unwrap();
                assert!(n_calls >= n / 4, "{n_calls} bands");
                let sum: f64 = expected.iter().map(|p| p.2).sum();
                assert_eq!(reader.totals().unwrap(), (expected.len() as u64, sum));

                let mut names: Vec<&str> = norms.iter().map(|v| v.0).collect();
                names.dedup();
                assert_eq!(reader.weight_names(), names);
                for name in names {
                    let weights = reader.weights(name).unwrap();
                    let mut expected = Vec::new();
                    for chrom in 0..3 {
                        let n_bins = reader.bins().chrom_bins(chrom).len();
                        match norms.iter().find(|v| v.0 == name && v.1 == chrom) {
                            Some(v) => expected.extend(v.2.iter().map(|&d| {
                                if d > 0.0 {
                                    1.0 / f64::from(d as f32)
                                } else {
                                    f64::NAN
                                }
                            })),
                            None => expected.extend(std::iter::repeat_n(f64::NAN, n_bins)),
                        }
                    }
                    assert_eq!(weights.values.len(), expected.len());
                    for (w, e) in weights.values.iter().zip(&expected) {
                        let both_nan = w.is_nan() && e.is_nan();
                        assert!(both_nan || (w / e - 1.0).abs() < 1e-12, "{w} {e}");
                    }
                }
            }
        }
    }

    #[test]
    fn synthetic_files_hold_every_block_layout() {
        // The writer's choices that the round-trip tests rely on: several blocks per matrix,
        // rotated blocks at several depths (version 9), dense and list-of-rows blocks.
        let dir = tempfile::tempdir().unwrap();
        for version in [8, 9] {
            let path = write_temp(&dir, "layout.hic", &write_hic(&synthetic(version)));
            let reader = HicReader::open(&path, Some(10)).unwrap();
            let intra = reader.matrix_index(0, 0).unwrap().unwrap();
            let inter = reader.matrix_index(0, 1).unwrap().unwrap();
            assert_eq!(intra.block_bin_count, 4);
            assert_eq!(intra.block_column_count, 10);
            for index in [&intra, &inter] {
                assert!(index.blocks.len() > 8);
                assert!(index.blocks.iter().any(|b| b.number % 4 == 1)); // dense
                assert!(index.blocks.iter().any(|b| b.number % 4 == 2)); // list of rows
            }
            let depths: std::collections::BTreeSet<u64> =
                intra.blocks.iter().map(|b| b.number / 10).collect();
            if version == 9 {
                assert_eq!(depths.into_iter().collect::<Vec<_>>(), [0, 1, 2]);
            } else {
                assert!(depths.len() >= 9); // grid rows
            }
            assert!(reader.matrix_index(0, 2).unwrap().is_some());
        }
    }

    #[test]
    fn synthetic_region_queries_match_a_naive_filter() {
        use proptest::test_runner::{Config, TestRunner};
        let dir = tempfile::tempdir().unwrap();
        for (version, budget) in [
            (8, BAND_BUDGET_BYTES),
            (8, 1),
            (9, BAND_BUDGET_BYTES),
            (9, 1),
        ] {
            let s = synthetic(version);
            let path = write_temp(&dir, &format!("v{version}.hic"), &write_hic(&s));
            let mut reader = HicReader::open(&path, Some(10)).unwrap();
            reader.band_budget_bytes = budget; // 1: bands of one block row (4 bins)
            let all = as_triplets(&s.levels[0].1);
            let n = reader.bins().n_bins();
            let mut runner = TestRunner::new(Config::with_cases(150));
            runner
                .run(&(0..=n, 0..=n, 0..=n, 0..=n), |(a, b, c, d)| {
                    let rows = a.min(b)..a.max(b);
                    let cols = c.min(d)..c.max(d);
                    let got = dump(&reader, rows.clone(), cols.clone());
                    proptest::prop_assert_eq!(got, filter(&all, &rows, &cols));
                    Ok(())
                })
                .unwrap();
        }
    }

    #[test]
    fn other_versions_are_rejected() {
        let dir = tempfile::tempdir().unwrap();
        let mut bytes = write_hic(&synthetic(8));
        bytes[4..8].copy_from_slice(&7i32.to_le_bytes());
        let path = write_temp(&dir, "v7.hic", &bytes);
        let message = HicReader::open(&path, None).unwrap_err().to_string();
        assert!(
            message.contains("version 7") && message.contains("v7.hic"),
            "{message}"
        );
        let path = write_temp(&dir, "text.hic", b"chr1\t0\t100\n");
        assert!(HicReader::open(&path, None).is_err());
    }

    #[test]
    fn corrupt_blocks_name_the_block() {
        let dir = tempfile::tempdir().unwrap();
        let s = synthetic(9);
        let clean = write_hic(&s);
        let path = write_temp(&dir, "clean.hic", &clean);
        let reader = HicReader::open(&path, Some(10)).unwrap();
        let index = reader.matrix_index(0, 0).unwrap().unwrap();
        let entry = index.blocks[0];
        let mut bytes = clean.clone();
        for b in &mut bytes[entry.position as usize + 2..(entry.position + entry.size) as usize] {
            *b = !*b;
        }
        let path = write_temp(&dir, "corrupt.hic", &bytes);
        let reader = HicReader::open(&path, Some(10)).unwrap();
        let n = reader.bins().n_bins();
        let message = reader
            .read_pixels(0..n, 0..n, &mut |_| Ok(()))
            .unwrap_err()
            .to_string();
        assert!(
            message.contains(&format!("block {} of c1-c1", entry.number)),
            "{message}"
        );
        assert!(reader.totals().is_err());
    }
}
