//! Scoring every pixel of the band: the locally adjusted expected of each kernel, computed from
//! the sparse band a block of rows at a time (no dense tiles), on every core.
//!
//! For pixel `(i, j)` of a region, `i < j`, `j - i < band`, and each kernel, as cooltools'
//! `get_adjusted_expected_tile_some_nans` and `score_tile` define it:
//!
//! - a footprint cell `(a, b)` is *missing* (NaN) when it lies outside the region, below the
//!   diagonal (`b < a`), on a masked bin (NaN weight) or on a diagonal whose expected is NaN (the
//!   ignored diagonals); otherwise its balanced observed is `raw * (w_a * w_b)` and its expected
//!   `E[b - a]`;
//! - `KO` and `KE` are the sums of observed and expected over the footprint's present cells,
//!   `NN` the number of its missing cells;
//! - the pixel is scored when every kernel has `NN < max_nans_tolerated` and a finite `KO / KE`;
//!   its locally adjusted expected is `E[j - i] / (w_i * w_j) * KO / KE` (0 when the pixel itself
//!   is missing), in raw counts, and its count is the raw count.
//!
//! The sums are direct sums of non-negative values (vertical strips, then horizontal runs), so
//! they carry no cancellation: they equal scipy's convolutions to a few units in the last place.
//! `KE` of a footprint with no missing cell depends on `j - i` only and is computed once per
//! diagonal.

use std::ops::Range;

use rayon::prelude::*;

use super::kernels::Kernel;
use crate::error::{Error, Result};
use crate::io::{MatrixReader, read_ahead};

/// Rows of pixels read from the file at a time (their memory: rows times the band).
const BLOCK_ROWS: usize = 2048;
/// Rows of pixels one task scores.
const CHUNK_ROWS: usize = 64;

/// One region to scan.
#[derive(Clone, Debug)]
pub struct RegionScan<'a> {
    /// Genome-wide bins of the region.
    pub bins: Range<usize>,
    /// Balancing weights, genome-wide (multiplicative).
    pub weights: &'a [f64],
    /// The region's expected (balanced) by diagonal, from 0; missing diagonals are NaN.
    pub expected: &'a [f64],
}

/// A scored pixel, handed to the visitor.
#[derive(Clone, Copy, Debug)]
pub struct Scored<'a> {
    /// Genome-wide row bin.
    pub bin1: usize,
    /// Genome-wide column bin.
    pub bin2: usize,
    /// Raw count.
    pub count: u64,
    /// Locally adjusted expected per kernel.
    pub la_exp: &'a [f64],
}

/// What the scan needs besides the region.
#[derive(Clone, Copy, Debug)]
pub struct ScanSettings<'a> {
    /// The kernels (same `w`).
    pub kernels: &'a [Kernel],
    /// Pixels with `j - i < band` are scored.
    pub band: usize,
    /// A kernel with this many missing cells or more rejects the pixel.
    pub max_nans_tolerated: usize,
    /// Pixels with a smaller count are skipped unscored (0: score all). The extraction pass sets
    /// the smallest threshold a pixel must reach, which leaves most pixels unscored.
    pub min_count: u64,
    /// Only these rows (genome-wide bins, `true` to score) when given; blocks without one are
    /// not read.
    pub rows: Option<&'a [bool]>,
}

/// Score every eligible pixel of `region`, folding them into per-task states (`init`, `visit`)
/// combined with `reduce`. The pixels of one task come in row-major order; tasks are combined
/// in an order that depends on scheduling, so `reduce` should not depend on it.
pub fn scan_region<T, I, V, R>(
    reader: &dyn MatrixReader,
    region: &RegionScan<'_>,
    settings: &ScanSettings<'_>,
    init: I,
    visit: V,
    reduce: R,
) -> Result<T>
where
    T: Send,
    I: Fn() -> T + Sync + Send,
    V: Fn(&mut T, Scored<'_>) -> Result<()> + Sync + Send,
    R: Fn(T, T) -> T + Sync + Send,
{
    let layout = Layout::new(settings.kernels);
    let w = layout.w;
    let n = region.bins.len();
    let diagonals = Diagonals::new(settings.kernels, region.expected, settings.band.min(n));
    // the blocks to read (those with a wanted row)
    let blocks: Vec<Range<usize>> = region
        .bins
        .clone()
        .step_by(BLOCK_ROWS)
        .map(|b0| b0..(b0 + BLOCK_ROWS).min(region.bins.end))
        .filter(|block| {
            settings
                .rows
                .is_none_or(|wanted| wanted[block.clone()].contains(&true))
        })
        .collect();
    let score_block = |rows: &Rows, block: &Range<usize>| -> Result<T> {
        let chunks: Vec<Range<usize>> = block
            .clone()
            .step_by(CHUNK_ROWS)
            .map(|c0| c0..(c0 + CHUNK_ROWS).min(block.end))
            .collect();
        chunks
            .into_par_iter()
            .try_fold(&init, |mut state, chunk| {
                score_chunk(
                    rows,
                    region,
                    settings,
                    &layout,
                    &diagonals,
                    chunk,
                    &mut |pixel| visit(&mut state, pixel),
                )?;
                Ok::<T, Error>(state)
            })
            .try_reduce(&init, |a, b| Ok(reduce(a, b)))
    };
    // each block is scored while the next one is read
    let mut total = init();
    read_ahead(
        blocks.iter(),
        |block| Rows::read(reader, region, (*block).clone(), w, settings.band),
        |block, rows| {
            let part = score_block(&rows, block)?;
            total = reduce(std::mem::replace(&mut total, init()), part);
            Ok(())
        },
    )?;
    Ok(total)
}

/// The vertical strips the kernels' rectangles use, and each rectangle's strip.
struct Layout {
    /// The kernels' outer half-width.
    w: usize,
    /// Distinct `(dy0, dy1)`.
    strips: Vec<(i32, i32)>,
    /// Per kernel: `(strip, dx0, dx1)`.
    rects: Vec<Vec<(usize, i32, i32)>>,
}

impl Layout {
    fn new(kernels: &[Kernel]) -> Layout {
        let mut strips: Vec<(i32, i32)> = Vec::new();
        let rects = kernels
            .iter()
            .map(|kernel| {
                kernel
                    .rects
                    .iter()
                    .map(|&(dy0, dy1, dx0, dx1)| {
                        let strip = match strips.iter().position(|&s| s == (dy0, dy1)) {
                            Some(k) => k,
                            None => {
                                strips.push((dy0, dy1));
                                strips.len() - 1
                            }
                        };
                        (strip, dx0, dx1)
                    })
                    .collect()
            })
            .collect();
        Layout {
            w: kernels.iter().map(|k| k.w).max().unwrap_or(0),
            strips,
            rects,
        }
    }

    /// Each kernel's rectangles as offsets into the strip arrays of a grid `width` wide.
    fn offsets(&self, width: usize) -> Vec<Vec<Rect>> {
        self.rects
            .iter()
            .map(|rects| {
                rects
                    .iter()
                    .map(|&(strip, dx0, dx1)| Rect {
                        sum: (strip * width) as isize + dx0 as isize,
                        prefix: (strip * (width + 1)) as isize + dx0 as isize,
                        len: (dx1 - dx0 + 1) as usize,
                    })
                    .collect()
            })
            .collect()
    }
}

/// A kernel rectangle seen from a pixel at grid column `c`: strip cells `c + sum ..` (`len` of
/// them) and prefix entries `c + prefix` and `c + prefix + len`.
#[derive(Clone, Copy, Debug)]
struct Rect {
    sum: isize,
    prefix: isize,
    len: usize,
}

/// The sum over `rects` of strip values for the pixel at column `c`: rectangle by rectangle, cell
/// by cell from the left. [`rect_sums`] adds in the same order, so the two agree to the bit.
fn rect_sum(strips: &[f64], rects: &[Rect], c: isize) -> f64 {
    let mut sum = 0.0;
    for rect in rects {
        let start = (c + rect.sum) as usize;
        for &x in &strips[start..start + rect.len] {
            sum += x;
        }
    }
    sum
}

/// Pixels per register block of [`rect_sums`].
const LANES: usize = 8;

/// [`rect_sum`] for the pixels at columns `c0..c0 + out.len()`, into `out`: blocks of
/// [`LANES`] pixels summed in registers (vectorised across pixels), the same additions per pixel.
fn rect_sums(strips: &[f64], rects: &[Rect], c0: isize, out: &mut [f64]) {
    let n = out.len();
    let mut blocks = out.chunks_exact_mut(LANES);
    for (b, block) in (&mut blocks).enumerate() {
        let mut acc = [0.0f64; LANES];
        for rect in rects {
            let start = (c0 + rect.sum) as usize + b * LANES;
            for cells in strips[start..start + rect.len + LANES - 1].windows(LANES) {
                let cells: &[f64; LANES] = cells.try_into().expect("a window of LANES");
                for (a, &x) in acc.iter_mut().zip(cells) {
                    *a += x;
                }
            }
        }
        block.copy_from_slice(&acc);
    }
    let done = n - blocks.into_remainder().len();
    for (t, o) in out[done..].iter_mut().enumerate() {
        *o = rect_sum(strips, rects, c0 + (done + t) as isize);
    }
}

/// The missing cells under `rects` for the pixel at column `c` (exact, from prefix counts).
fn rect_count(prefix: &[u32], rects: &[Rect], c: isize) -> u32 {
    rects
        .iter()
        .map(|rect| {
            let start = (c + rect.prefix) as usize;
            prefix[start + rect.len] - prefix[start]
        })
        .sum()
}

/// [`rect_count`] for the pixels at columns `c0..c0 + out.len()`, into `out`.
fn rect_counts(prefix: &[u32], rects: &[Rect], c0: isize, out: &mut [u32]) {
    out.fill(0);
    let n = out.len();
    for rect in rects {
        let start = (c0 + rect.prefix) as usize;
        let left = &prefix[start..start + n];
        let right = &prefix[start + rect.len..start + rect.len + n];
        for ((o, &l), &r) in out.iter_mut().zip(left).zip(right) {
            *o += r - l;
        }
    }
}

/// The expected at diagonal `t`; NaN off the table (below the diagonal, past the region).
fn expected_at(expected: &[f64], t: i64) -> f64 {
    if t >= 0 && (t as usize) < expected.len() {
        expected[t as usize]
    } else {
        f64::NAN
    }
}

/// A region's tables by diagonal `d < band`, computed once per region.
struct Diagonals {
    /// The balanced expected (NaN where the table has none).
    expected: Vec<f64>,
    /// Per kernel, `KE` of a footprint without missing cells.
    ke0: Vec<Vec<f64>>,
}

impl Diagonals {
    fn new(kernels: &[Kernel], expected: &[f64], band: usize) -> Diagonals {
        let ke0 = kernels
            .iter()
            .map(|kernel| {
                (0..band)
                    .map(|d| {
                        let mut sum = 0.0;
                        for &(dy, dx) in &kernel.cells {
                            sum += expected_at(expected, d as i64 + dx as i64 - dy as i64);
                        }
                        sum
                    })
                    .collect()
            })
            .collect();
        Diagonals {
            expected: (0..band.max(1) as i64)
                .map(|d| expected_at(expected, d))
                .collect(),
            ke0,
        }
    }
}

/// The raw counts of the rows a block needs (its rows and `w` more on each side), row by row:
/// `(column, count)` sorted by column, columns from the row's own bin.
struct Rows {
    first: usize,
    ptr: Vec<usize>,
    cols: Vec<u32>,
    counts: Vec<f64>,
}

impl Rows {
    fn read(
        reader: &dyn MatrixReader,
        region: &RegionScan<'_>,
        block: Range<usize>,
        w: usize,
        band: usize,
    ) -> Result<Rows> {
        let first = block.start.saturating_sub(w).max(region.bins.start);
        let last = (block.end + w).min(region.bins.end);
        let col_end = (block.end + band + 3 * w).min(region.bins.end);
        let reach = band + 2 * w;
        let mut ptr = vec![0usize; last - first + 1];
        let mut cols = Vec::new();
        let mut counts = Vec::new();
        let mut row = first;
        reader.read_pixels(first..last, first..col_end, &mut |pixels| {
            for k in 0..pixels.count.len() {
                let (a, b) = (pixels.bin1[k] as usize, pixels.bin2[k] as usize);
                if b < a || b - a > reach {
                    continue;
                }
                while row < a {
                    row += 1;
                    ptr[row - first] = cols.len();
                }
                cols.push(b as u32);
                counts.push(pixels.count[k]);
            }
            Ok(())
        })?;
        while row < last {
            row += 1;
            ptr[row - first] = cols.len();
        }
        Ok(Rows {
            first,
            ptr,
            cols,
            counts,
        })
    }

    /// The stored pixels of row `a` (which must be among the rows read).
    fn row(&self, a: usize) -> (&[u32], &[f64]) {
        let k = a - self.first;
        let range = self.ptr[k]..self.ptr[k + 1];
        (&self.cols[range.clone()], &self.counts[range])
    }
}

/// The cells around a chunk of pixel rows, dense: balanced observed (0 where missing), missing
/// flags and expected (0 where missing), row by row from `row_lo`, columns from `col_lo`.
struct Grid {
    row_lo: i64,
    col_lo: i64,
    width: usize,
    obs: Vec<f64>,
    missing: Vec<u32>,
    expected: Vec<f64>,
}

impl Grid {
    fn new(rows: &Rows, region: &RegionScan<'_>, band: i64, w: i64, chunk: &Range<usize>) -> Grid {
        let (s, e) = (region.bins.start as i64, region.bins.end as i64);
        let weights = region.weights;
        let (c0, c1) = (chunk.start as i64, chunk.end as i64);
        // columns and rows any footprint of the chunk's pixels touches
        let col_lo = c0 + 1 - w;
        let col_hi = (c1 - 1) + (band - 1) + w + 1;
        let width = (col_hi - col_lo) as usize;
        let row_lo = c0 - w;
        let n_rows = (c1 + w - row_lo) as usize;
        let mut obs = vec![0.0f64; n_rows * width];
        let mut missing = vec![1u32; n_rows * width];
        let mut expected = vec![0.0f64; n_rows * width];
        for r in 0..n_rows {
            let a = row_lo + r as i64;
            if a < s || a >= e {
                continue;
            }
            let wa = weights[a as usize];
            let cells = r * width..(r + 1) * width;
            let o_row = &mut obs[cells.clone()];
            let m_row = &mut missing[cells.clone()];
            let e_row = &mut expected[cells];
            // present unless masked: cells of the region on or above the diagonal
            let b_start = a.max(col_lo).max(s);
            let b_end = col_hi.min(e);
            for b in b_start..b_end {
                let o = 0.0 * (wa * weights[b as usize]);
                let x = expected_at(region.expected, b - a);
                if !(o.is_nan() || x.is_nan()) {
                    let k = (b - col_lo) as usize;
                    m_row[k] = 0;
                    e_row[k] = x;
                }
            }
            let (cols, counts) = rows.row(a as usize);
            for (&b, &count) in cols.iter().zip(counts) {
                let b = b as i64;
                if b < b_start || b >= b_end {
                    continue;
                }
                let k = (b - col_lo) as usize;
                if m_row[k] == 0 {
                    o_row[k] = count * (wa * weights[b as usize]);
                }
            }
        }
        Grid {
            row_lo,
            col_lo,
            width,
            obs,
            missing,
            expected,
        }
    }
}

/// The vertical strip sums of one pixel row: observed, prefix counts of missing cells and
/// (on demand) expected, per strip.
struct Strips {
    width: usize,
    obs: Vec<f64>,
    missing: Vec<u32>,
    prefix: Vec<u32>,
    expected: Vec<f64>,
    /// The pixel row `expected` holds, once asked for.
    expected_row: Option<i64>,
}

impl Strips {
    fn new(n_strips: usize, width: usize) -> Strips {
        Strips {
            width,
            obs: vec![0.0; n_strips * width],
            missing: vec![0; n_strips * width],
            prefix: vec![0; n_strips * (width + 1)],
            expected: vec![0.0; n_strips * width],
            expected_row: None,
        }
    }

    /// Sum `values` (a grid array) over each strip of pixel row `i`, columns `cols`, into `out`
    /// (row by row from the strip's top).
    fn sum<T: Copy + std::ops::AddAssign>(
        layout: &Layout,
        grid: &Grid,
        values: &[T],
        i: i64,
        cols: &Range<usize>,
        out: &mut [T],
    ) {
        let width = grid.width;
        let row = |dy: i32| {
            let r = (i + dy as i64 - grid.row_lo) as usize;
            &values[r * width + cols.start..r * width + cols.end]
        };
        for (k, &(dy0, dy1)) in layout.strips.iter().enumerate() {
            let v = &mut out[k * width + cols.start..k * width + cols.end];
            v.copy_from_slice(row(dy0));
            for dy in dy0 + 1..=dy1 {
                for (s, &x) in v.iter_mut().zip(row(dy)) {
                    *s += x;
                }
            }
        }
    }

    /// Observed sums and missing prefix counts of pixel row `i`.
    fn observed(&mut self, layout: &Layout, grid: &Grid, i: i64, cols: &Range<usize>) {
        Self::sum(layout, grid, &grid.obs, i, cols, &mut self.obs);
        Self::sum(layout, grid, &grid.missing, i, cols, &mut self.missing);
        let width = self.width;
        for k in 0..layout.strips.len() {
            let p = &mut self.prefix[k * (width + 1) + cols.start..(k + 1) * (width + 1)];
            let m = &self.missing[k * width + cols.start..k * width + cols.end];
            let mut acc = 0u32;
            p[0] = 0;
            for (p, &m) in p[1..].iter_mut().zip(m) {
                acc += m;
                *p = acc;
            }
        }
    }

    /// Expected sums of pixel row `i` (computed the first time a row asks for them).
    fn expected(&mut self, layout: &Layout, grid: &Grid, i: i64, cols: &Range<usize>) -> &[f64] {
        if self.expected_row != Some(i) {
            Self::sum(layout, grid, &grid.expected, i, cols, &mut self.expected);
            self.expected_row = Some(i);
        }
        &self.expected
    }
}

/// The raw expected of a pixel (0 when the pixel itself is missing) from its balanced expected
/// and its two weights.
fn raw_expected(e_bal: f64, wi: f64, wj: f64) -> f64 {
    let wij = wi * wj;
    if (0.0 * wij).is_nan() || e_bal.is_nan() {
        0.0
    } else {
        e_bal / wij
    }
}

/// Per-row work arrays of the scoring pass, per kernel `row_len` long.
struct RowArrays {
    row_len: usize,
    counts: Vec<f64>,
    e_raw: Vec<f64>,
    nn: Vec<u32>,
    /// `KO`, then `KO / KE` in place.
    factor: Vec<f64>,
    ke: Vec<f64>,
    la: Vec<f64>,
}

impl RowArrays {
    fn new(n_kernels: usize, row_len: usize) -> RowArrays {
        RowArrays {
            row_len,
            counts: vec![0.0; row_len],
            e_raw: vec![0.0; row_len],
            nn: vec![0; n_kernels * row_len],
            factor: vec![0.0; n_kernels * row_len],
            ke: vec![0.0; n_kernels * row_len],
            la: vec![0.0; n_kernels * row_len],
        }
    }

    /// Kernel `k`'s part of an array, for the row's `n` pixels.
    fn part(&self, k: usize, n: usize) -> Range<usize> {
        k * self.row_len..k * self.row_len + n
    }
}

/// Score the pixel rows `chunk`.
///
/// The scoring pass (`min_count` 0) computes every pixel of a row at once, vectorised across the
/// row; the extraction pass computes its few candidates one by one with the same operations in
/// the same order ([`rect_sum`] / [`rect_sums`], [`raw_expected`], `e_raw * (KO / KE)`), so a
/// pixel gets the same values to the bit in both passes.
fn score_chunk(
    rows: &Rows,
    region: &RegionScan<'_>,
    settings: &ScanSettings<'_>,
    layout: &Layout,
    diagonals: &Diagonals,
    chunk: Range<usize>,
    visit: &mut impl FnMut(Scored<'_>) -> Result<()>,
) -> Result<()> {
    let w = layout.w as i64;
    let e = region.bins.end as i64;
    let band = settings.band as i64;
    let weights = region.weights;
    let grid = Grid::new(rows, region, band, w, &chunk);
    let col_lo = grid.col_lo;
    let rects = layout.offsets(grid.width);
    let mut strips = Strips::new(layout.strips.len(), grid.width);
    let n_k = rects.len();
    let max_nans = settings.max_nans_tolerated;
    let (exp_band, ke0) = (&diagonals.expected, &diagonals.ke0);
    let dense = settings.min_count == 0;
    let mut arrays = RowArrays::new(n_k, if dense { exp_band.len() } else { 0 });
    let mut la = vec![0.0f64; n_k];
    let mut nn = vec![0u32; n_k];
    let min_count = settings.min_count as f64;
    let check_count = |i: i64, j: i64, count: f64| {
        if count.fract() != 0.0 || count < 0.0 {
            return Err(Error::Unsupported(format!(
                "dots needs integer counts (raw contacts): pixel ({i}, {j}) has {count}"
            )));
        }
        Ok(count as u64)
    };
    for i in chunk.start as i64..chunk.end as i64 {
        let j_end = (i + band).min(e);
        if j_end <= i + 1 || settings.rows.is_some_and(|wanted| !wanted[i as usize]) {
            continue;
        }
        let n_j = (j_end - i - 1) as usize;
        let (cols, counts) = rows.row(i as usize);
        // the row's stored pixels in (i, j_end)
        let from = cols.partition_point(|&b| (b as i64) <= i);
        let to = cols.partition_point(|&b| (b as i64) < j_end);
        let (cols, counts) = (&cols[from..to], &counts[from..to]);
        if !dense && !counts.iter().any(|&c| c >= min_count) {
            continue;
        }
        // the columns row i's footprints touch
        let c_first = i + 1 - col_lo;
        let span =
            c_first as usize - layout.w..((j_end - 1 + w + 1 - col_lo) as usize).min(grid.width);
        strips.observed(layout, &grid, i, &span);
        let wi = weights[i as usize];
        if dense {
            let a = &mut arrays;
            let row_counts = &mut a.counts[..n_j];
            row_counts.fill(0.0);
            for (&b, &count) in cols.iter().zip(counts) {
                check_count(i, b as i64, count)?;
                row_counts[(b as i64 - i - 1) as usize] = count;
            }
            let row_weights = &weights[(i + 1) as usize..j_end as usize];
            for ((x, &e_bal), &wj) in a.e_raw[..n_j]
                .iter_mut()
                .zip(&exp_band[1..=n_j])
                .zip(row_weights)
            {
                *x = raw_expected(e_bal, wi, wj);
            }
            for (kk, rects) in rects.iter().enumerate() {
                let part = a.part(kk, n_j);
                rect_counts(
                    &strips.prefix,
                    rects,
                    c_first as isize,
                    &mut a.nn[part.clone()],
                );
                rect_sums(
                    &strips.obs,
                    rects,
                    c_first as isize,
                    &mut a.factor[part.clone()],
                );
                let ke = &mut a.ke[part.clone()];
                ke.copy_from_slice(&ke0[kk][1..=n_j]);
                // footprints with missing cells sum the expected of their present cells
                for (t, &n) in a.nn[part.clone()].iter().enumerate() {
                    if n > 0 && (n as usize) < max_nans {
                        let expected = strips.expected(layout, &grid, i, &span);
                        ke[t] = rect_sum(expected, rects, c_first as isize + t as isize);
                    }
                }
                for (((f, &k), l), &x) in a.factor[part.clone()]
                    .iter_mut()
                    .zip(&*ke)
                    .zip(&mut a.la[part])
                    .zip(&a.e_raw[..n_j])
                {
                    *f /= k;
                    *l = x * *f;
                }
            }
            'pixel: for t in 0..n_j {
                for (kk, l) in la.iter_mut().enumerate() {
                    let k = kk * a.row_len + t;
                    if a.nn[k] as usize >= max_nans || !a.factor[k].is_finite() {
                        continue 'pixel;
                    }
                    *l = a.la[k];
                }
                visit(Scored {
                    bin1: i as usize,
                    bin2: (i + 1) as usize + t,
                    count: a.counts[t] as u64,
                    la_exp: &la,
                })?;
            }
        } else {
            'candidate: for (&b, &count) in cols.iter().zip(counts) {
                if count < min_count {
                    continue;
                }
                let c = (b as i64 - col_lo) as isize;
                for (kk, rects) in rects.iter().enumerate() {
                    nn[kk] = rect_count(&strips.prefix, rects, c);
                    if nn[kk] as usize >= max_nans {
                        continue 'candidate;
                    }
                }
                let d = b as usize - i as usize;
                let e_raw = raw_expected(exp_band[d], wi, weights[b as usize]);
                for (kk, rects) in rects.iter().enumerate() {
                    let ko = rect_sum(&strips.obs, rects, c);
                    let ke = if nn[kk] == 0 {
                        ke0[kk][d]
                    } else {
                        rect_sum(strips.expected(layout, &grid, i, &span), rects, c)
                    };
                    let factor = ko / ke;
                    if !factor.is_finite() {
                        continue 'candidate;
                    }
                    la[kk] = e_raw * factor;
                }
                visit(Scored {
                    bin1: i as usize,
                    bin2: b as usize,
                    count: check_count(i, b as i64, count)?,
                    la_exp: &la,
                })?;
            }
        }
    }
    Ok(())
}
