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
use crate::io::MatrixReader;

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
    let ke0 = expected_sums(settings.kernels, region.expected, settings.band.min(n));
    let mut total = init();
    let mut b0 = region.bins.start;
    while b0 < region.bins.end {
        let b1 = (b0 + BLOCK_ROWS).min(region.bins.end);
        let rows = Rows::read(reader, region, b0..b1, w, settings.band)?;
        let chunks: Vec<Range<usize>> = (b0..b1)
            .step_by(CHUNK_ROWS)
            .map(|c0| c0..(c0 + CHUNK_ROWS).min(b1))
            .collect();
        let part = chunks
            .into_par_iter()
            .try_fold(&init, |mut state, chunk| {
                score_chunk(
                    &rows,
                    region,
                    settings,
                    &layout,
                    &ke0,
                    chunk,
                    &mut |pixel| visit(&mut state, pixel),
                )?;
                Ok::<T, Error>(state)
            })
            .try_reduce(&init, |a, b| Ok(reduce(a, b)))?;
        total = reduce(total, part);
        b0 = b1;
    }
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
}

/// The expected at diagonal `t`; NaN off the table (below the diagonal, past the region).
fn expected_at(expected: &[f64], t: i64) -> f64 {
    if t >= 0 && (t as usize) < expected.len() {
        expected[t as usize]
    } else {
        f64::NAN
    }
}

/// `KE` of a footprint without missing cells, per kernel and diagonal `d < band`.
fn expected_sums(kernels: &[Kernel], expected: &[f64], band: usize) -> Vec<Vec<f64>> {
    kernels
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
        .collect()
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

/// Score the pixel rows `chunk`.
fn score_chunk(
    rows: &Rows,
    region: &RegionScan<'_>,
    settings: &ScanSettings<'_>,
    layout: &Layout,
    ke0: &[Vec<f64>],
    chunk: Range<usize>,
    visit: &mut dyn FnMut(Scored<'_>) -> Result<()>,
) -> Result<()> {
    let kernels = settings.kernels;
    let w = layout.w as i64;
    let (s, e) = (region.bins.start as i64, region.bins.end as i64);
    let band = settings.band as i64;
    let weights = region.weights;
    let expected = region.expected;
    let exp_at = |t: i64| expected_at(expected, t);
    let (c0, c1) = (chunk.start as i64, chunk.end as i64);
    // columns any footprint of the chunk's pixels touches
    let col_lo = c0 + 1 - w;
    let col_hi = (c1 - 1) + (band - 1) + w + 1;
    let width = (col_hi - col_lo) as usize;
    let row_lo = c0 - w;
    let n_rows = (c1 + w - row_lo) as usize;
    // observed (0 where missing) and missing flags of every cell, row by row
    let mut obs = vec![0.0f64; n_rows * width];
    let mut missing = vec![1u32; n_rows * width];
    for r in 0..n_rows {
        let a = row_lo + r as i64;
        if a < s || a >= e {
            continue;
        }
        let wa = weights[a as usize];
        let o_row = &mut obs[r * width..(r + 1) * width];
        let m_row = &mut missing[r * width..(r + 1) * width];
        // present unless masked: cells of the region on or above the diagonal
        let b_start = a.max(col_lo).max(s);
        let b_end = col_hi.min(e);
        for b in b_start..b_end {
            let o = 0.0 * (wa * weights[b as usize]);
            if !(o.is_nan() || exp_at(b - a).is_nan()) {
                m_row[(b - col_lo) as usize] = 0;
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
    let n_strips = layout.strips.len();
    let mut v_obs = vec![0.0f64; n_strips * width];
    let mut v_miss = vec![0u32; n_strips * width];
    // prefix sums of the missing counts per strip (exact, integers): NN in two reads a rectangle
    let mut p_miss = vec![0u32; n_strips * (width + 1)];
    let n_kernels = kernels.len();
    let mut la = vec![0.0f64; n_kernels];
    let mut nn = vec![0u32; n_kernels];
    // each rectangle as offsets from a pixel's column into the strip arrays: (observed, prefix
    // counts, width)
    let rects: Vec<Vec<(isize, isize, usize)>> = layout
        .rects
        .iter()
        .map(|rects| {
            rects
                .iter()
                .map(|&(strip, dx0, dx1)| {
                    (
                        (strip * width) as isize + dx0 as isize,
                        (strip * (width + 1)) as isize + dx0 as isize,
                        (dx1 - dx0 + 1) as usize,
                    )
                })
                .collect()
        })
        .collect();
    for i in c0..c1 {
        let j_end = (i + band).min(e);
        if j_end <= i + 1 {
            continue;
        }
        // the columns row i's footprints touch
        let lo = (i + 1 - w - col_lo) as usize;
        let hi = ((j_end - 1 + w + 1 - col_lo) as usize).min(width);
        // vertical strips for pixel row i
        for (k, &(dy0, dy1)) in layout.strips.iter().enumerate() {
            let vo = &mut v_obs[k * width + lo..k * width + hi];
            let vm = &mut v_miss[k * width + lo..k * width + hi];
            vo.fill(0.0);
            vm.fill(0);
            for dy in dy0..=dy1 {
                let r = (i + dy as i64 - row_lo) as usize;
                let o_row = &obs[r * width + lo..r * width + hi];
                let m_row = &missing[r * width + lo..r * width + hi];
                for ((v, &o), (m, &x)) in vo.iter_mut().zip(o_row).zip(vm.iter_mut().zip(m_row)) {
                    *v += o;
                    *m += x;
                }
            }
            let pm = &mut p_miss[k * (width + 1)..(k + 1) * (width + 1)];
            pm[lo] = 0;
            let vm = &v_miss[k * width..(k + 1) * width];
            for c in lo..hi {
                pm[c + 1] = pm[c] + vm[c];
            }
        }
        let wi = weights[i as usize];
        let (cols, counts) = rows.row(i as usize);
        let mut next = 0usize;
        for j in (i + 1)..j_end {
            // the raw count at (i, j)
            while next < cols.len() && (cols[next] as i64) < j {
                next += 1;
            }
            let count = if next < cols.len() && cols[next] as i64 == j {
                counts[next]
            } else {
                0.0
            };
            if count < settings.min_count as f64 {
                continue;
            }
            let base = (j - col_lo) as isize;
            let mut rejected = false;
            for (kk, rects) in rects.iter().enumerate() {
                let mut n = 0u32;
                for &(_, p0, len) in rects {
                    let start = (base + p0) as usize;
                    n += p_miss[start + len] - p_miss[start];
                }
                nn[kk] = n;
                if n as usize >= settings.max_nans_tolerated {
                    rejected = true;
                    break;
                }
            }
            if rejected {
                continue;
            }
            let d = j - i;
            let wj = weights[j as usize];
            let e_bal = exp_at(d);
            let pixel_missing = (0.0 * (wi * wj)).is_nan() || e_bal.is_nan();
            let e_raw = if pixel_missing {
                0.0
            } else {
                e_bal / (wi * wj)
            };
            for (kk, rects) in rects.iter().enumerate() {
                let mut ko = 0.0;
                for &(o0, _, len) in rects {
                    let start = (base + o0) as usize;
                    ko += v_obs[start..start + len].iter().sum::<f64>();
                }
                let ke = if nn[kk] == 0 {
                    ke0[kk][d as usize]
                } else {
                    let mut sum = 0.0;
                    for &(dy, dx) in &kernels[kk].cells {
                        let (a, b) = (i + dy as i64, j + dx as i64);
                        let r = (a - row_lo) as usize;
                        if missing[r * width + (b - col_lo) as usize] == 0 {
                            sum += exp_at(b - a);
                        }
                    }
                    sum
                };
                let factor = ko / ke;
                if !factor.is_finite() {
                    rejected = true;
                    break;
                }
                la[kk] = e_raw * factor;
            }
            if rejected {
                continue;
            }
            if count.fract() != 0.0 || count < 0.0 {
                return Err(Error::Invalid(format!(
                    "dots needs integer counts (raw contacts): pixel ({i}, {j}) has {count}"
                )));
            }
            visit(Scored {
                bin1: i as usize,
                bin2: j as usize,
                count: count as u64,
                la_exp: &la,
            })?;
        }
    }
    Ok(())
}
