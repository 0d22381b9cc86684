//! Blocks: where they lie (the block index of a chromosome pair), which part of the matrix each
//! can hold, and their decoding (zlib inflate, then the list-of-rows or dense representation).

use std::ops::Range;
use std::sync::Arc;

use flate2::{Decompress, FlushDecompress, Status};

/// Size of one block-index entry: block number (int32), position (int64), size (int32).
pub(super) const BLOCK_ENTRY_BYTES: u64 = 16;
/// The `short` count that marks an empty cell of a dense block.
pub(super) const DENSE_SHORT_EMPTY: i16 = i16::MIN;

/// The block index of one chromosome-pair matrix at the open resolution.
#[derive(Debug)]
pub(super) struct MatrixIndex {
    pub(super) block_bin_count: u64,
    pub(super) block_column_count: u64,
    pub(super) blocks: Vec<BlockEntry>,
}

impl Default for MatrixIndex {
    /// A matrix without blocks (the pair has no record at the resolution). The grid is one bin a
    /// block, never zero: its sizes are divisors of the band planner.
    fn default() -> Self {
        MatrixIndex {
            block_bin_count: 1,
            block_column_count: 1,
            blocks: Vec::new(),
        }
    }
}

/// Where one block lies in the file.
#[derive(Clone, Copy, Debug)]
pub(super) struct BlockEntry {
    pub(super) number: u64,
    pub(super) position: u64,
    pub(super) size: u64,
}

/// A pixel while a band is assembled: `bin1 << 32 | bin2`, the count as stored (a `short` or a
/// `float`, both exact in `f32`), and whether it was stored in the lower triangle of an
/// intra-chromosomal matrix (record `(x, y)` with `x > y`, mirrored to `bin1 <= bin2`).
#[derive(Clone, Copy, Debug)]
pub(super) struct Pixel {
    pub(super) key: u64,
    pub(super) count: f32,
    pub(super) mirrored: bool,
}

impl Pixel {
    pub(super) fn bin1(self) -> u64 {
        self.key >> 32
    }

    pub(super) fn bin2(self) -> u64 {
        self.key & 0xFFFF_FFFF
    }
}

/// How the blocks of one matrix are decoded and filtered.
pub(super) struct PairPlan {
    pub(super) label: String,
    /// The bin-table chromosomes of the matrix, `(chrom1, chrom2)`.
    pub(super) chroms: (usize, usize),
    pub(super) index: Arc<MatrixIndex>,
    pub(super) intra: bool,
    /// Version 9 intra-chromosomal blocks: rotated along the diagonal.
    pub(super) rotated: bool,
    pub(super) offset1: u64,
    pub(super) n1: u64,
    pub(super) offset2: u64,
    pub(super) n2: u64,
    /// Genome-wide `bin1` range kept.
    pub(super) keep_rows: Range<u64>,
    /// Genome-wide `bin2` range kept.
    pub(super) keep_cols: Range<u64>,
}

impl PairPlan {
    /// A range of local rows (chromosome 1, or the smaller bin for intra-chromosomal matrices) and
    /// one of local columns that hold every pixel block `number` can contain. Exact for grid
    /// blocks; for rotated blocks, a box around the block with a margin for rounding.
    pub(super) fn block_box(&self, number: u64) -> (Range<u64>, Range<u64>) {
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
/// Inflate one zlib stream, checking that it ends properly.
pub(super) fn inflate(compressed: &[u8]) -> std::result::Result<Vec<u8>, String> {
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

/// What [`decode_block`] found besides the pixels it kept.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct BlockStats {
    /// Records past the last bin of their chromosome (dropped, as hictk and hic2cool drop them).
    pub(super) past_end: u64,
    /// The first such record, `(x, y)` in the matrix's own bins.
    pub(super) first_past_end: Option<(i64, i64)>,
    /// Intra-chromosomal records in the lower triangle (`x > y`), mirrored.
    pub(super) lower: u64,
    /// Intra-chromosomal records in the upper triangle off the diagonal (`x < y`).
    pub(super) upper: u64,
}

/// Decode an inflated block of a version 8 / 9 file into `out` (only pixels in the plan's
/// rectangle, with `bin1 <= bin2`). Records past the end of their chromosome are dropped and
/// counted in the returned [`BlockStats`]; records at negative bins are an error.
pub(super) fn decode_block(
    data: &[u8],
    version: i32,
    plan: &PairPlan,
    out: &mut Vec<Pixel>,
) -> std::result::Result<BlockStats, String> {
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

    let mut stats = BlockStats::default();
    let mut emit = |x: i64, y: i64, count: f32| -> std::result::Result<(), String> {
        if x < 0 || y < 0 {
            return Err(format!("record at negative bins ({x}, {y})"));
        }
        if x as u64 >= plan.n1 || y as u64 >= plan.n2 {
            stats.past_end += 1;
            stats.first_past_end.get_or_insert((x, y));
            return Ok(());
        }
        let (mut bin1, mut bin2) = (plan.offset1 + x as u64, plan.offset2 + y as u64);
        let mirrored = bin1 > bin2;
        if mirrored {
            std::mem::swap(&mut bin1, &mut bin2);
        }
        if plan.intra {
            stats.lower += u64::from(mirrored);
            stats.upper += u64::from(bin1 < bin2 && !mirrored);
        }
        if plan.keep_rows.contains(&bin1) && plan.keep_cols.contains(&bin2) {
            out.push(Pixel {
                key: (bin1 << 32) | bin2,
                count,
                mirrored,
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
            ));
        }
    }
    Ok(stats)
}
