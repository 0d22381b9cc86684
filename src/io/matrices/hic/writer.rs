//! Juicer `.hic` writer (format version 9): every resolution from one stream of pixels, blocks
//! compressed on every core, then a footer with expected-value and normalisation vectors.
//!
//! # Layout written
//!
//! As the Aiden lab specification (`HiCFormatV9.md`) describes, with hictk's choices where it
//! leaves one open:
//!
//! - Header: `HIC`, version 9, footer position, genome id, the position and length of the
//!   normalisation-vector index, attributes (`software`), the chromosomes with Juicer's `All`
//!   pseudo-chromosome first (length: the genome in kb), the base-pair resolutions (ascending, as
//!   hictk lists them), no fragment resolution.
//! - Body: the compressed blocks of every chromosome pair `(i, j >= i)` and resolution, each pair's
//!   matrix metadata (sum, block size, block columns, the block index sorted by block number)
//!   after its blocks. Intra-chromosomal records keep `x <= y`, Juicer's stored triangle; their
//!   blocks are numbered along the diagonal (version 9's rotated grid), inter-chromosomal blocks on
//!   a square grid. Blocks hold at most `block_bin_count` bins a side (default 1000, Juicer's).
//! - `All`: the whole genome at one coarse bin size (in kb, Juicer's unit for it: the coarsest
//!   resolution, or a thousandth of the genome when that is coarser), resolution index one past
//!   the last, as hictk writes it.
//! - Footer: master index, expected-value vectors, normalised expected-value vectors, the
//!   normalisation-vector index and the vectors (float32). [`HicWriter::write_footer`] can be
//!   called again: it replaces the footer, so a file can first be closed without vectors, read
//!   back to compute them, and then finished.
//!
//! # Streaming and memory
//!
//! Pixels arrive sorted by `(bin1, bin2)` at the finest resolution and are coarsened on the fly
//! for every resolution (a bin's coarse bin is its index in the chromosome divided by the
//! resolution factor); each resolution takes every slice of the stream on its own core (rayon),
//! and finds a record's block with the specification's formula, the depth of a rotated block
//! looked up in a table bisected from that formula (no `log2` per record, the same numbers).
//! A block is complete once the stream has passed the last row it can hold
//! (column `k` of the grid holds rows below `(k + 1) * block_bin_count`), so blocks are written as
//! the rows go by and the memory held is that of the open blocks: at most one block-column band
//! of each inter-chromosomal matrix, and for intra-chromosomal ones the pixels whose block along
//! the diagonal is still ahead. Complete blocks are batched (about [`BATCH_RECORDS`] records),
//! sorted, encoded and zlib-compressed in parallel (rayon), then written in order; output does
//! not depend on the thread count.
//!
//! Values are stored as the specification allows: `short` when a block's values are all whole
//! numbers up to 32,767, else `float` (float32: sums above 2^24 are rounded, as in every `.hic`).

mod block;

use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::expected::JuicerExpected;
use crate::error::{Error, Result};
use crate::genome::{BinTable, Chrom};
use crate::io::matrices::reader::MatrixReader;
use crate::matrix::PixelBlock;

use block::{Record, block_coordinates, compress_block};

/// Pixels the resolutions take at a time (a slice of the reader's block).
const RUN_PIXELS: usize = 1 << 18;

/// Records gathered before a batch of complete blocks is compressed in parallel.
pub const BATCH_RECORDS: usize = 1 << 21;

/// Options of [`HicWriter`].
#[derive(Clone, Debug)]
pub struct HicWriteOptions {
    /// Genome identifier written in the header (`hg38`, ...).
    pub genome_id: String,
    /// Bins on a side of a block (Juicer: 1000).
    pub block_bin_count: u64,
    /// zlib compression level, 0-9 (Juicer: the default, 6).
    pub compression_level: u32,
    /// Write Juicer's `All` pseudo-chromosome and its whole-genome matrix (Juicebox shows it).
    pub whole_genome: bool,
}

impl Default for HicWriteOptions {
    fn default() -> Self {
        HicWriteOptions {
            genome_id: "unknown".into(),
            block_bin_count: 1000,
            compression_level: 6,
            whole_genome: true,
        }
    }
}

impl HicWriteOptions {
    /// The defaults with the genome identifier `genome` (`unknown` when none).
    pub fn for_genome(genome: Option<String>) -> Self {
        HicWriteOptions {
            genome_id: genome.unwrap_or_else(|| "unknown".into()),
            ..HicWriteOptions::default()
        }
    }
}

/// One normalisation vector to store: divisive values (Juicer's convention), one per bin of
/// `chrom` at `resolution`.
#[derive(Clone, Debug)]
pub struct HicNormVector {
    /// Normalisation name (`VC`, `VC_SQRT`, `KR`, `SCALE`, ...).
    pub name: String,
    /// Chromosome index in the bin table.
    pub chrom: usize,
    /// Resolution.
    pub resolution: u64,
    /// Divisive values (`NaN` for bins without one).
    pub values: Vec<f64>,
}

/// A `.hic` file being written; see the module documentation.
pub struct HicWriter {
    path: PathBuf,
    out: BufWriter<File>,
    position: u64,
    chroms: Vec<Chrom>,
    base_bins: BinTable,
    resolutions: Vec<u64>,
    options: HicWriteOptions,
    /// File chromosome index of bin-table chromosome 0 (1 with `All`, else 0).
    chrom_shift: usize,
    /// `(key, position, bytes)` of every matrix written.
    master: Vec<(String, u64, u64)>,
    footer_slot: u64,
    nvi_slot: u64,
    footer_position: Option<u64>,
}

impl HicWriter {
    /// Create `path` and write the header for the chromosomes of `base_bins` (fixed-size bins)
    /// and `resolutions` (multiples of its bin size).
    pub fn create(
        path: &Path,
        base_bins: &BinTable,
        resolutions: &[u64],
        options: &HicWriteOptions,
    ) -> Result<HicWriter> {
        let base = base_bins.resolution().ok_or_else(|| {
            Error::Unsupported(".hic needs fixed-size bins; this matrix has variable bins".into())
        })?;
        let mut resolutions = resolutions.to_vec();
        resolutions.sort_unstable();
        resolutions.dedup();
        if resolutions.is_empty() {
            resolutions.push(base);
        }
        if let Some(r) = resolutions.iter().find(|&&r| r == 0 || r % base != 0) {
            return Err(Error::Argument(format!(
                "resolution {r} is not a multiple of the input's bin size {base}"
            )));
        }
        if let Some(r) = resolutions.iter().find(|&&r| r > i32::MAX as u64) {
            return Err(Error::Argument(format!(
                "resolution {r} does not fit the .hic format's 32-bit bin sizes"
            )));
        }
        if !(1..=i32::MAX as u64 / 2).contains(&options.block_bin_count) {
            return Err(Error::Argument(format!(
                "block size {} is out of range",
                options.block_bin_count
            )));
        }
        // Exclusively: `path` is a temporary name (crate::io::plumbing::atomic), never followed as a link.
        let file = File::options()
            .write(true)
            .create_new(true)
            .open(path)
            .map_err(|e| Error::io(path, e))?;
        let mut writer = HicWriter {
            path: path.to_path_buf(),
            out: BufWriter::with_capacity(1 << 20, file),
            position: 0,
            chroms: base_bins.chroms().to_vec(),
            base_bins: base_bins.clone(),
            resolutions,
            options: options.clone(),
            chrom_shift: usize::from(options.whole_genome),
            master: Vec::new(),
            footer_slot: 0,
            nvi_slot: 0,
            footer_position: None,
        };
        writer.write_header()?;
        Ok(writer)
    }

    /// The resolutions written, ascending.
    pub fn resolutions(&self) -> &[u64] {
        &self.resolutions
    }

    fn put(&mut self, bytes: &[u8]) -> Result<()> {
        self.out
            .write_all(bytes)
            .map_err(|e| Error::io(&self.path, e))?;
        self.position += bytes.len() as u64;
        Ok(())
    }
    fn put_i32(&mut self, v: i64) -> Result<()> {
        let v = i32::try_from(v).map_err(|_| {
            Error::Unsupported(format!(
                "{v} does not fit a 32-bit field of the .hic format"
            ))
        })?;
        self.put(&v.to_le_bytes())
    }
    fn put_i64(&mut self, v: i64) -> Result<()> {
        self.put(&v.to_le_bytes())
    }
    fn put_f32(&mut self, v: f64) -> Result<()> {
        self.put(&(v as f32).to_le_bytes())
    }
    /// A vector as version 9 stores it: its length (`long`), then float32 values.
    fn put_f32_vector(&mut self, values: &[f64]) -> Result<()> {
        self.put_i64(values.len() as i64)?;
        let bytes: Vec<u8> = values
            .iter()
            .flat_map(|&x| (x as f32).to_le_bytes())
            .collect();
        self.put(&bytes)
    }
    fn put_str(&mut self, s: &str) -> Result<()> {
        if s.as_bytes().contains(&0) {
            return Err(Error::Unsupported(format!(
                "'{}' holds a NUL byte, which the .hic format cannot store",
                s.escape_debug()
            )));
        }
        self.put(s.as_bytes())?;
        self.put(&[0])
    }

    fn write_header(&mut self) -> Result<()> {
        self.put(b"HIC\0")?;
        self.put_i32(9)?;
        self.footer_slot = self.position;
        self.put_i64(0)?;
        let genome = self.options.genome_id.clone();
        self.put_str(&genome)?;
        self.nvi_slot = self.position;
        self.put_i64(0)?;
        self.put_i64(0)?;
        self.put_i32(1)?;
        self.put_str("software")?;
        self.put_str(&format!("contactmap {}", env!("CARGO_PKG_VERSION")))?;
        let chroms = self.chroms.clone();
        self.put_i32((chroms.len() + self.chrom_shift) as i64)?;
        if self.options.whole_genome {
            self.put_str("All")?;
            self.put_i64(self.genome_kb().iter().sum::<u64>() as i64)?;
        }
        for chrom in &chroms {
            self.put_str(&chrom.name)?;
            self.put_i64(chrom.length_bp as i64)?;
        }
        let resolutions = self.resolutions.clone();
        self.put_i32(resolutions.len() as i64)?;
        for r in resolutions {
            self.put_i32(r as i64)?;
        }
        self.put_i32(0) // no fragment resolutions
    }

    /// Each chromosome's length in kb (Juicer's unit for the `All` matrix).
    fn genome_kb(&self) -> Vec<u64> {
        self.chroms.iter().map(|c| c.length_bp / 1000).collect()
    }

    /// Stream every pixel of `reader` (on the base bins given to [`HicWriter::create`]) into
    /// blocks at every resolution, with the `All` matrix if asked.
    pub fn write_matrices(&mut self, reader: &dyn MatrixReader) -> Result<()> {
        if reader.bins() != &self.base_bins {
            return Err(Error::Data(format!(
                "{}: its bins are not those the .hic was created for",
                reader.source()
            )));
        }
        let base = self.base_bins.resolution().expect("checked in create");
        let offsets: Vec<u64> = self
            .base_bins
            .chrom_offsets()
            .iter()
            .map(|&o| o as u64)
            .collect();
        let chrom_of: Vec<u32> = (0..self.base_bins.n_bins())
            .map(|b| self.base_bins.chrom_of(b) as u32)
            .collect();
        let mut levels: Vec<Level> = self
            .resolutions
            .iter()
            .enumerate()
            .map(|(index, &r)| Level::new(index, r, r / base, &self.chroms, &self.options))
            .collect();
        let mut whole = self
            .options
            .whole_genome
            .then(|| WholeGenome::new(&self.chroms, *self.resolutions.last().unwrap()));
        let mut current: Option<usize> = None;
        let n = self.base_bins.n_bins();
        let source = reader.source().to_string();
        // (c2, x, y, count) of a run of pixels on one row chromosome, in base bins
        let mut run: Vec<(usize, u64, u64, f64)> = Vec::new();
        reader.read_pixels(0..n, 0..n, &mut |pixels: &PixelBlock| {
            let mut start = 0;
            while start < pixels.len() {
                let out_of_range = |k: usize| {
                    Error::format(
                        &source,
                        format!(
                            "pixel ({}, {}) is out of range ({n} bins)",
                            pixels.bin1[k], pixels.bin2[k]
                        ),
                    )
                };
                let chrom = |bin: u64| chrom_of.get(bin as usize).map(|&c| c as usize);
                let c1 = chrom(pixels.bin1[start]).ok_or_else(|| out_of_range(start))?;
                if current != Some(c1) {
                    if let Some(previous) = current {
                        self.finish_chrom(previous, &mut levels)?;
                    }
                    for level in levels.iter_mut() {
                        level.start_chrom(c1);
                    }
                    current = Some(c1);
                }
                run.clear();
                let mut end = start;
                while end < pixels.len()
                    && end - start < RUN_PIXELS
                    && chrom(pixels.bin1[end]) == Some(c1)
                {
                    let (b1, b2) = (pixels.bin1[end], pixels.bin2[end]);
                    let c2 = chrom(b2).ok_or_else(|| out_of_range(end))?;
                    run.push((c2, b1 - offsets[c1], b2 - offsets[c2], pixels.count[end]));
                    end += 1;
                }
                // every resolution (and the All matrix) takes the run on its own core
                rayon::join(
                    || {
                        levels.par_iter_mut().for_each(|level| {
                            for &(c2, x, y, count) in &run {
                                level.add(c2, x / level.factor, y / level.factor, count);
                            }
                        })
                    },
                    || {
                        if let Some(whole) = whole.as_mut() {
                            for &(c2, x, y, count) in &run {
                                whole.add(c1, x * base, c2, y * base, count);
                            }
                        }
                    },
                );
                start = end;
                if levels.iter().map(|l| l.n_closed_records).sum::<usize>() >= BATCH_RECORDS {
                    self.write_batch(&mut levels)?;
                }
            }
            Ok(())
        })?;
        if let Some(previous) = current {
            self.finish_chrom(previous, &mut levels)?;
        }
        if let Some(whole) = whole {
            self.write_whole_genome(whole)?;
        }
        Ok(())
    }

    /// Close every block of the row chromosome `c1` and write its matrices' metadata.
    fn finish_chrom(&mut self, c1: usize, levels: &mut [Level]) -> Result<()> {
        for level in levels.iter_mut() {
            level.close_all();
        }
        self.write_batch(levels)?;
        // every chromosome pair (c1, c2) with a block at any resolution
        let mut partners: Vec<usize> = levels
            .iter()
            .flat_map(|l| l.index.keys().copied())
            .collect();
        partners.sort_unstable();
        partners.dedup();
        for c2 in partners {
            let start = self.position;
            self.put_i32((c1 + self.chrom_shift) as i64)?;
            self.put_i32((c2 + self.chrom_shift) as i64)?;
            let present: Vec<usize> = (0..levels.len())
                .filter(|&l| levels[l].index.contains_key(&c2))
                .collect();
            self.put_i32(present.len() as i64)?;
            for l in present {
                let level = &mut levels[l];
                let mut entries = level.index.remove(&c2).unwrap_or_default();
                let sum = level.sums[c2];
                let (size, columns) = level.grids[c2];
                let (res_index, resolution) = (level.res_index, level.resolution);
                entries.sort_unstable_by_key(|e| e.0);
                self.write_level_metadata(res_index, resolution, sum, size, columns, &entries)?;
            }
            self.master.push((
                format!("{}_{}", c1 + self.chrom_shift, c2 + self.chrom_shift),
                start,
                self.position - start,
            ));
        }
        for level in levels.iter_mut() {
            level.index.clear();
        }
        Ok(())
    }

    fn write_level_metadata(
        &mut self,
        res_index: usize,
        resolution: u64,
        sum: f64,
        size: u64,
        columns: u64,
        entries: &[(u64, u64, u64)],
    ) -> Result<()> {
        self.put_str("BP")?;
        self.put_i32(res_index as i64)?;
        self.put_f32(sum)?;
        self.put_i32(0)?; // occupiedCellCount (not used)
        self.put_f32(0.0)?; // percent5 (not used)
        self.put_f32(0.0)?; // percent95 (not used)
        self.put_i32(resolution as i64)?;
        self.put_i32(size as i64)?;
        self.put_i32(columns as i64)?;
        self.put_i32(entries.len() as i64)?;
        for &(number, position, bytes) in entries {
            self.put_i32(number as i64)?;
            self.put_i64(position as i64)?;
            self.put_i32(bytes as i64)?;
        }
        Ok(())
    }

    /// Compress the closed blocks in parallel and write them, level by level in the order they
    /// were closed.
    fn write_batch(&mut self, levels: &mut [Level]) -> Result<()> {
        let level_of_compression = self.options.compression_level;
        let mut blocks: Vec<ClosedBlock> = Vec::new();
        for level in levels.iter_mut() {
            blocks.append(&mut level.closed);
            level.n_closed_records = 0;
        }
        let compressed: Vec<Vec<u8>> = blocks
            .par_iter_mut()
            .map(|b| compress_block(&mut b.records, level_of_compression))
            .collect();
        for (closed, bytes) in blocks.iter().zip(compressed) {
            let position = self.position;
            self.put(&bytes)?;
            levels[closed.level]
                .index
                .entry(closed.c2)
                .or_default()
                .push((closed.number, position, bytes.len() as u64));
        }
        Ok(())
    }

    fn write_whole_genome(&mut self, whole: WholeGenome) -> Result<()> {
        let n = whole.n_bins as u64;
        let size = n + 1;
        let mut records: Vec<Record> = Vec::new();
        let mut sum = 0.0;
        for y in 0..whole.n_bins {
            for x in 0..=y {
                let value = whole.cells[y * whole.n_bins + x];
                if value != 0.0 {
                    records.push(Record {
                        x: x as u32,
                        y: y as u32,
                        value,
                    });
                    sum += value;
                }
            }
        }
        let mut entries = Vec::new();
        if !records.is_empty() {
            let bytes = compress_block(&mut records, self.options.compression_level);
            entries.push((0, self.position, bytes.len() as u64));
            self.put(&bytes)?;
        }
        let start = self.position;
        self.put_i32(0)?;
        self.put_i32(0)?;
        self.put_i32(1)?;
        let res_index = self.resolutions.len();
        self.write_level_metadata(res_index, whole.bin_kb, sum, size, 1, &entries)?;
        self.master
            .insert(0, ("0_0".into(), start, self.position - start));
        Ok(())
    }

    /// Write (or rewrite) the footer: master index, `expected` (raw) vectors, `normalized`
    /// expected vectors (with their normalisation name) and the normalisation `vectors`; the
    /// header is patched to point at them. The file is complete and readable afterwards.
    pub fn write_footer(
        &mut self,
        expected: &[JuicerExpected],
        normalized: &[(String, JuicerExpected)],
        vectors: &[HicNormVector],
    ) -> Result<()> {
        let footer = match self.footer_position {
            Some(at) => {
                self.out.flush().map_err(|e| Error::io(&self.path, e))?;
                let file = self.out.get_mut();
                file.set_len(at).map_err(|e| Error::io(&self.path, e))?;
                file.seek(SeekFrom::Start(at))
                    .map_err(|e| Error::io(&self.path, e))?;
                self.position = at;
                at
            }
            None => self.position,
        };
        self.footer_position = Some(footer);
        self.put_i64(0)?; // nBytesV5, patched below
        let master = self.master.clone();
        self.put_i32(master.len() as i64)?;
        for (key, position, bytes) in &master {
            self.put_str(key)?;
            self.put_i64(*position as i64)?;
            self.put_i32(*bytes as i64)?;
        }
        self.put_i32(expected.len() as i64)?;
        for e in expected {
            self.put_str("BP")?;
            self.write_expected(e)?;
        }
        let n_bytes_v5 = self.position - footer - 8;
        self.put_i32(normalized.len() as i64)?;
        for (name, e) in normalized {
            self.put_str(name)?;
            self.put_str("BP")?;
            self.write_expected(e)?;
        }
        let index_position = self.position;
        self.put_i32(vectors.len() as i64)?;
        let mut slots = Vec::with_capacity(vectors.len());
        for v in vectors {
            self.put_str(&v.name)?;
            self.put_i32((v.chrom + self.chrom_shift) as i64)?;
            self.put_str("BP")?;
            self.put_i32(v.resolution as i64)?;
            slots.push(self.position);
            self.put_i64(0)?;
            self.put_i64(8 + 4 * v.values.len() as i64)?;
        }
        let index_length = self.position - index_position;
        let mut positions = Vec::with_capacity(vectors.len());
        for v in vectors {
            positions.push(self.position);
            self.put_f32_vector(&v.values)?;
        }
        self.out.flush().map_err(|e| Error::io(&self.path, e))?;
        let mut patches = vec![
            (self.footer_slot, footer as i64),
            (footer, n_bytes_v5 as i64),
            (self.nvi_slot, index_position as i64),
            (self.nvi_slot + 8, index_length as i64),
        ];
        patches.extend(slots.into_iter().zip(positions.iter().map(|&p| p as i64)));
        let file = self.out.get_mut();
        for (at, value) in patches {
            file.seek(SeekFrom::Start(at))
                .map_err(|e| Error::io(&self.path, e))?;
            file.write_all(&value.to_le_bytes())
                .map_err(|e| Error::io(&self.path, e))?;
        }
        file.seek(SeekFrom::Start(self.position))
            .map_err(|e| Error::io(&self.path, e))?;
        file.sync_data().map_err(|e| Error::io(&self.path, e))
    }

    fn write_expected(&mut self, e: &JuicerExpected) -> Result<()> {
        self.put_i32(e.resolution as i64)?;
        self.put_f32_vector(&e.values)?;
        self.put_i32(e.chrom_scale_factors.len() as i64)?;
        for &(chrom, factor) in &e.chrom_scale_factors {
            self.put_i32((chrom + self.chrom_shift) as i64)?;
            self.put_f32(factor)?;
        }
        Ok(())
    }
}

/// A block closed and waiting for compression.
struct ClosedBlock {
    level: usize,
    c2: usize,
    number: u64,
    records: Vec<Record>,
}

/// One resolution's open blocks for the current row chromosome.
struct Level {
    res_index: usize,
    resolution: u64,
    factor: u64,
    block_bin_count: u64,
    /// Bins of each chromosome at this resolution.
    chrom_bins: Vec<u64>,
    /// Open blocks: slot of `(c2, number)` in `slots`.
    open: HashMap<(usize, u64), usize>,
    slots: Vec<OpenBlock>,
    free: Vec<usize>,
    /// The last block used, as `(c2, number, slot)`.
    last: Option<(usize, u64, usize)>,
    /// Current row chromosome and band of rows (`x / block_bin_count`).
    c1: usize,
    band: u64,
    /// Block index and sum of each matrix `(c1, c2)` of the current row chromosome.
    index: BTreeMap<usize, Vec<(u64, u64, u64)>>,
    /// Sum of each matrix `(c1, c2)` being streamed, by `c2`.
    sums: Vec<f64>,
    /// Block size and columns of each matrix `(c1, c2)`, by `c2`.
    grids: Vec<(u64, u64)>,
    /// Depth boundaries of the intra-chromosomal matrix ([`depth_bounds`]).
    intra_depths: Vec<u64>,
    /// Blocks closed and waiting to be compressed, and their records.
    closed: Vec<ClosedBlock>,
    n_closed_records: usize,
}

#[derive(Default)]
struct OpenBlock {
    in_use: bool,
    c2: usize,
    number: u64,
    /// Rows from this one on cannot fall in the block: `(column + 1) * block size`.
    complete_from: u64,
    records: Vec<Record>,
}

impl Level {
    fn new(
        res_index: usize,
        resolution: u64,
        factor: u64,
        chroms: &[Chrom],
        options: &HicWriteOptions,
    ) -> Level {
        Level {
            res_index,
            resolution,
            factor,
            block_bin_count: options.block_bin_count,
            chrom_bins: chroms
                .iter()
                .map(|c| c.length_bp.div_ceil(resolution))
                .collect(),
            open: HashMap::new(),
            slots: Vec::new(),
            free: Vec::new(),
            last: None,
            c1: 0,
            band: 0,
            index: BTreeMap::new(),
            sums: vec![0.0; chroms.len()],
            grids: Vec::new(),
            intra_depths: Vec::new(),
            closed: Vec::new(),
            n_closed_records: 0,
        }
    }

    /// Block size and number of block columns of matrix `(c1, c2)`: Juicer's grid, its blocks
    /// no larger than the matrix needs.
    fn grid(&self, c1: usize, c2: usize) -> (u64, u64) {
        let (n1, n2) = (self.chrom_bins[c1], self.chrom_bins[c2]);
        let size = self.block_bin_count.min(n1.max(n2) + 1).max(1);
        let columns = if c1 == c2 {
            n1 / size + 1
        } else {
            n1.max(n2) / size + 1
        };
        (size, columns)
    }

    /// Start the blocks of row chromosome `c1`.
    fn start_chrom(&mut self, c1: usize) {
        self.c1 = c1;
        self.band = 0;
        self.last = None;
        self.grids = (0..self.chrom_bins.len())
            .map(|c2| self.grid(c1, c2))
            .collect();
        let (size, _) = self.grids[c1];
        self.intra_depths = depth_bounds(size, self.chrom_bins[c1]);
        self.sums.iter_mut().for_each(|s| *s = 0.0);
    }

    /// Add one pixel `(x, y)` of matrix `(c1, c2)` in this level's bins (`c1` the current row
    /// chromosome, `x` non-decreasing).
    #[inline]
    fn add(&mut self, c2: usize, x: u64, y: u64, value: f64) {
        let band = x / self.block_bin_count;
        if band != self.band {
            self.close_until(x);
            self.band = band;
        }
        let (size, columns) = self.grids[c2];
        let (column, number) = if c2 == self.c1 {
            // the specification's numbering, its depth looked up instead of a log2 per record
            let along = (x + y) / 2 / size;
            let depth = self.intra_depths.partition_point(|&d| d <= y - x) as u64;
            (along, depth * columns + along)
        } else {
            block_coordinates(false, x, y, size, columns)
        };
        let slot = match self.last {
            Some((lc2, ln, slot)) if lc2 == c2 && ln == number => slot,
            _ => {
                let slot = match self.open.get(&(c2, number)) {
                    Some(&slot) => slot,
                    None => {
                        let slot = self.free.pop().unwrap_or_else(|| {
                            self.slots.push(OpenBlock::default());
                            self.slots.len() - 1
                        });
                        let block = &mut self.slots[slot];
                        block.c2 = c2;
                        block.number = number;
                        block.complete_from = (column + 1) * size;
                        block.in_use = true;
                        self.open.insert((c2, number), slot);
                        slot
                    }
                };
                self.last = Some((c2, number, slot));
                slot
            }
        };
        self.slots[slot].records.push(Record {
            x: x as u32,
            y: y as u32,
            value,
        });
        self.sums[c2] += value;
    }

    /// Close the blocks that rows from `x` on cannot reach.
    fn close_until(&mut self, x: u64) {
        for slot in 0..self.slots.len() {
            let block = &mut self.slots[slot];
            if block.in_use && block.complete_from <= x {
                self.close(slot);
            }
        }
    }

    /// Close every open block.
    fn close_all(&mut self) {
        for slot in 0..self.slots.len() {
            if self.slots[slot].in_use {
                self.close(slot);
            }
        }
    }

    fn close(&mut self, slot: usize) {
        let block = &mut self.slots[slot];
        block.in_use = false;
        self.open.remove(&(block.c2, block.number));
        if self.last.is_some_and(|(_, _, s)| s == slot) {
            self.last = None;
        }
        self.n_closed_records += block.records.len();
        self.closed.push(ClosedBlock {
            level: self.res_index,
            c2: block.c2,
            number: block.number,
            records: std::mem::take(&mut block.records),
        });
        self.free.push(slot);
    }
}

/// The distances (in bins, `y - x`) at which the depth of an intra-chromosomal block grows, for
/// blocks of `size` bins and distances up to `max_distance`: `depth(d)` is the number of bounds
/// `<= d`. Found by bisection on the specification's formula ([`block::depth`]), so the lookup
/// gives exactly what the formula gives, as readers compute it to find blocks.
fn depth_bounds(size: u64, max_distance: u64) -> Vec<u64> {
    let mut bounds = Vec::new();
    let mut k = 1;
    while block::depth(max_distance, size) >= k {
        let (mut low, mut high) = (0u64, max_distance);
        while low < high {
            let mid = low + (high - low) / 2;
            if block::depth(mid, size) >= k {
                high = mid;
            } else {
                low = mid + 1;
            }
        }
        bounds.push(low);
        k += 1;
    }
    bounds
}

/// Juicer's `All` matrix: the genome in kb, cut into `bin_kb` bins, counts summed densely.
struct WholeGenome {
    offsets_kb: Vec<u64>,
    bin_kb: u64,
    n_bins: usize,
    cells: Vec<f64>,
}

impl WholeGenome {
    fn new(chroms: &[Chrom], coarsest_bp: u64) -> WholeGenome {
        let mut offsets_kb = Vec::with_capacity(chroms.len());
        let mut genome_kb = 0;
        for chrom in chroms {
            offsets_kb.push(genome_kb);
            genome_kb += chrom.length_bp / 1000;
        }
        let bin_kb = (coarsest_bp / 1000).max(genome_kb.div_ceil(1000)).max(1);
        let n_bins = (genome_kb / bin_kb + 1) as usize;
        WholeGenome {
            offsets_kb,
            bin_kb,
            n_bins,
            cells: vec![0.0; n_bins * n_bins],
        }
    }

    #[inline]
    fn add(&mut self, c1: usize, start1_bp: u64, c2: usize, start2_bp: u64, count: f64) {
        let x = ((self.offsets_kb[c1] + start1_bp / 1000) / self.bin_kb) as usize;
        let y = ((self.offsets_kb[c2] + start2_bp / 1000) / self.bin_kb) as usize;
        let (x, y) = (x.min(y).min(self.n_bins - 1), x.max(y).min(self.n_bins - 1));
        self.cells[y * self.n_bins + x] += count;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depth_lookup_equals_the_formula() {
        for size in [1u64, 2, 3, 7, 10, 1000, 1001] {
            let max_distance = 300_000;
            let bounds = depth_bounds(size, max_distance);
            for d in (0..2000).chain((2000..max_distance).step_by(997)) {
                assert_eq!(
                    bounds.partition_point(|&b| b <= d) as u64,
                    block::depth(d, size),
                    "size {size} distance {d}"
                );
            }
            // just below and at every bound
            for &b in &bounds {
                assert_eq!(
                    bounds.partition_point(|&x| x <= b) as u64,
                    block::depth(b, size)
                );
                assert_eq!(
                    bounds.partition_point(|&x| x < b) as u64,
                    block::depth(b - 1, size)
                );
            }
        }
    }
}
