//! Rectangles of a map as the Python tools fetch them: cooler's `Cooler.matrix().fetch` (a
//! dense array of the full symmetric matrix, balanced or not) and hictk's `fetch` (the pixels of
//! a query, optionally balanced). The binding (`python/`) and any caller reach every reader
//! through these.

use std::ops::Range;

use ndarray::Array2;
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::io::matrices::reader::MatrixReader;
use crate::matrix::PixelBlock;

/// The stored pixels of a query with their balanced values.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct QueryPixels {
    /// The pixels: bin ids genome-wide, raw counts.
    pub pixels: PixelBlock,
    /// `(weight[bin1] * weight[bin2]) * count` per pixel (cooler's order of operations), when weights were given (NaN where a bin
    /// is masked).
    pub balanced: Option<Vec<f64>>,
}

fn check_ranges(reader: &dyn MatrixReader, rows: &Range<usize>, cols: &Range<usize>) -> Result<()> {
    let n = reader.bins().n_bins();
    for (what, range) in [("rows", rows), ("columns", cols)] {
        if range.start > range.end || range.end > n {
            return Err(Error::Argument(format!(
                "{}: {what} {}..{} outside the map's {n} bins",
                reader.source(),
                range.start,
                range.end
            )));
        }
    }
    Ok(())
}

fn check_weights(reader: &dyn MatrixReader, weights: Option<&[f64]>) -> Result<()> {
    let n = reader.bins().n_bins();
    match weights {
        Some(w) if w.len() != n => Err(Error::Argument(format!(
            "{}: {} weights for {n} bins",
            reader.source(),
            w.len()
        ))),
        _ => Ok(()),
    }
}

/// The dense `rows x cols` rectangle of the full (symmetric) matrix, as cooler's
/// `Cooler.matrix(balance=...).fetch(region1, region2)` returns it: pixels stored in the upper
/// triangle appear at `(i, j)` and, where the rectangle covers it, at `(j, i)`; pixels not stored
/// are 0. With `weights`, every value (zeros included) is multiplied by `weight[i] * weight[j]`,
/// so the rows and columns of masked (NaN) bins are NaN throughout, as in cooler.
///
/// ```
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{query_dense, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
///
/// let bins = BinTable::fixed(vec![Chrom::new("a", 40)], 10)?;
/// let mut builder = MatrixBuilder::new(bins, CountType::Integer);
/// builder.push(0, 2, 5.0)?;
/// builder.push(1, 1, 3.0)?;
/// let reader = InMemory::new("toy".into(), builder.build());
/// let m = query_dense(&reader, 0..3, 0..3, None)?;
/// assert_eq!(m[[0, 2]], 5.0);
/// assert_eq!(m[[2, 0]], 5.0); // the lower triangle filled from the upper
/// let w = [2.0, f64::NAN, 0.5, 1.0];
/// let b = query_dense(&reader, 0..3, 2..4, Some(&w))?;
/// assert_eq!(b[[0, 0]], 5.0 * 2.0 * 0.5);
/// assert!(b[[1, 0]].is_nan()); // a masked bin's row
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn query_dense(
    reader: &dyn MatrixReader,
    rows: Range<usize>,
    cols: Range<usize>,
    weights: Option<&[f64]>,
) -> Result<Array2<f64>> {
    let mut values = vec![0.0f64; rows.len() * cols.len()];
    query_dense_into(reader, rows.clone(), cols.clone(), weights, &mut values)?;
    Array2::from_shape_vec((rows.len(), cols.len()), values)
        .map_err(|e| Error::Invalid(format!("dense query: {e}")))
}

/// [`query_dense`] into `out`, row-major `rows.len() x cols.len()`, which must hold zeros (a
/// freshly zeroed allocation: numpy's `zeros`, `calloc`): only the stored pixels and the masked
/// bins' rows and columns are written, so the pages of empty parts of the rectangle are never
/// touched.
pub fn query_dense_into(
    reader: &dyn MatrixReader,
    rows: Range<usize>,
    cols: Range<usize>,
    weights: Option<&[f64]>,
    out: &mut [f64],
) -> Result<()> {
    check_ranges(reader, &rows, &cols)?;
    check_weights(reader, weights)?;
    let width = cols.len();
    if out.len() != rows.len() * width {
        return Err(Error::Argument(format!(
            "dense query: {} values for {} x {width}",
            out.len(),
            rows.len()
        )));
    }
    if rows.is_empty() || cols.is_empty() {
        return Ok(());
    }
    let (r0, c0) = (rows.start, cols.start);
    // `(weight[i] * weight[j]) * count`, cooler's `count * outer(w, w)`
    let value = |i: usize, j: usize, count: f64| match weights {
        Some(w) => (w[i] * w[j]) * count,
        None => count,
    };
    let symmetric = rows == cols;
    // The pixels first (the upper triangle's with their row in `rows`, column in `cols`), then
    // the rectangle filled in bands of rows, each band by one thread: the pages of the output
    // are first touched (and zeroed by the kernel) on every core, and no two threads write one
    // row.
    let mut upper: Vec<PixelBlock> = Vec::new();
    reader.read_pixels_owned(rows.clone(), cols.clone(), &mut |block| {
        upper.push(block);
        Ok(())
    })?;
    // the lower triangle: stored (a, b), a < b, a in `cols` and b in `rows`, seen at (b, a)
    let mut lower: Vec<PixelBlock> = Vec::new();
    if !symmetric && cols.start + 1 < rows.end {
        reader.read_pixels_owned(cols.clone(), rows.clone(), &mut |block| {
            lower.push(block);
            Ok(())
        })?;
    }
    let masked_cols: Vec<usize> = match weights {
        Some(w) => cols.clone().filter(|&j| w[j].is_nan()).collect(),
        None => Vec::new(),
    };
    // where each block's rows start (pixels are sorted by bin1, then bin2 within a row)
    let runs = |blocks: &[PixelBlock]| -> Vec<Vec<usize>> {
        blocks
            .par_iter()
            .map(|block| {
                let mut starts: Vec<usize> = (0..block.len())
                    .filter(|&k| k == 0 || block.bin1[k] != block.bin1[k - 1])
                    .collect();
                starts.push(block.len());
                starts
            })
            .collect()
    };
    let (upper_runs, lower_runs) = (runs(&upper), runs(&lower));
    let band = rows.len().div_ceil(4 * rayon::current_num_threads()).max(1);
    out.par_chunks_mut(band * width)
        .enumerate()
        .for_each(|(b, chunk)| {
            let lo = r0 + b * band;
            let hi = lo + chunk.len() / width;
            let band_rows = lo as u64..hi as u64;
            // the pixels (i, j) of a row whose column j lies in the band, for each row of each
            // block whose row comes before the band's end
            let in_band_columns =
                |blocks: &[PixelBlock],
                 runs: &[Vec<usize>],
                 each: &mut dyn FnMut(&PixelBlock, usize)| {
                    for (block, starts) in blocks.iter().zip(runs) {
                        if block.bin1.first().is_none_or(|&i| i >= band_rows.end) {
                            continue;
                        }
                        for run in starts.windows(2) {
                            let (s, e) = (run[0], run[1]);
                            if block.bin1[s] >= band_rows.end {
                                break;
                            }
                            let cols = &block.bin2[s..e];
                            let first = s + cols.partition_point(|&j| j < band_rows.start);
                            let last = s + cols.partition_point(|&j| j < band_rows.end);
                            for k in first..last {
                                each(block, k);
                            }
                        }
                    }
                };
            for block in &upper {
                // blocks are sorted by bin1: the band's rows are one slice of a block
                let first = block.bin1.partition_point(|&i| i < band_rows.start);
                let last = block.bin1.partition_point(|&i| i < band_rows.end);
                for k in first..last {
                    let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                    chunk[(i - lo) * width + (j - c0)] = value(i, j, block.count[k]);
                }
            }
            if symmetric {
                // mirrored: (i, j), i < j, j in the band, seen at (j, i)
                in_band_columns(&upper, &upper_runs, &mut |block, k| {
                    let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                    if i != j {
                        chunk[(j - lo) * width + (i - c0)] = value(j, i, block.count[k]);
                    }
                });
            }
            in_band_columns(&lower, &lower_runs, &mut |block, k| {
                let (a, b) = (block.bin1[k] as usize, block.bin2[k] as usize);
                if a < b {
                    chunk[(b - lo) * width + (a - c0)] = value(b, a, block.count[k]);
                }
            });
            // a masked bin's row and column are NaN throughout (zeros included: 0 x NaN)
            if let Some(w) = weights {
                for (row, i) in chunk.chunks_mut(width).zip(lo..hi) {
                    if w[i].is_nan() {
                        row.fill(f64::NAN);
                    } else {
                        for &j in &masked_cols {
                            row[j - c0] = f64::NAN;
                        }
                    }
                }
            }
        });
    for block in upper.into_iter().chain(lower) {
        reader.recycle(block);
    }
    Ok(())
}

/// The stored pixels of the upper triangle whose row lies in `rows` and column in `cols`, sorted
/// by `(bin1, bin2)`, as hictk's `fetch(range1, range2).to_df()` gives them; with `weights`, their
/// balanced values too.
///
/// ```
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{query_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
///
/// let bins = BinTable::fixed(vec![Chrom::new("a", 40)], 10)?;
/// let mut builder = MatrixBuilder::new(bins, CountType::Integer);
/// builder.push(0, 2, 5.0)?;
/// builder.push(1, 3, 3.0)?;
/// let reader = InMemory::new("toy".into(), builder.build());
/// let q = query_pixels(&reader, 0..2, 2..4, Some(&[1.0, 2.0, 0.5, 1.0]))?;
/// assert_eq!((q.pixels.bin1, q.pixels.bin2), (vec![0, 1], vec![2, 3]));
/// assert_eq!(q.balanced, Some(vec![2.5, 6.0]));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn query_pixels(
    reader: &dyn MatrixReader,
    rows: Range<usize>,
    cols: Range<usize>,
    weights: Option<&[f64]>,
) -> Result<QueryPixels> {
    check_ranges(reader, &rows, &cols)?;
    check_weights(reader, weights)?;
    let mut pixels = PixelBlock::default();
    if !rows.is_empty() && !cols.is_empty() {
        reader.read_pixels(rows, cols, &mut |block| {
            pixels.bin1.extend_from_slice(&block.bin1);
            pixels.bin2.extend_from_slice(&block.bin2);
            pixels.count.extend_from_slice(&block.count);
            Ok(())
        })?;
    }
    let balanced = weights.map(|w| {
        pixels
            .bin1
            .par_iter()
            .zip(pixels.bin2.par_iter())
            .zip(pixels.count.par_iter())
            .map(|((&i, &j), &c)| (w[i as usize] * w[j as usize]) * c)
            .collect()
    });
    Ok(QueryPixels { pixels, balanced })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::{BinTable, Chrom};
    use crate::io::InMemory;
    use crate::matrix::{CountType, MatrixBuilder};

    /// A naive full matrix of a small random map, against which every rectangle is checked.
    #[test]
    #[allow(clippy::needless_range_loop)] // the naive matrix indexed as written
    fn every_rectangle_equals_the_naive_full_matrix() {
        let bins = BinTable::fixed(vec![Chrom::new("a", 130), Chrom::new("b", 70)], 10).unwrap();
        let n = bins.n_bins();
        let mut full = vec![vec![0.0; n]; n];
        let mut builder = MatrixBuilder::new(bins, CountType::Integer);
        let mut state = 7u64;
        for i in 0..n {
            for j in i..n {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                if (state >> 33).is_multiple_of(3) {
                    let c = ((state >> 40) % 50 + 1) as f64;
                    builder.push(i as u64, j as u64, c).unwrap();
                    full[i][j] = c;
                    full[j][i] = c;
                }
            }
        }
        let reader = InMemory::new("toy".into(), builder.build());
        let w: Vec<f64> = (0..n)
            .map(|i| {
                if i % 7 == 3 {
                    f64::NAN
                } else {
                    1.0 + i as f64 / 10.0
                }
            })
            .collect();
        let ranges = [0..n, 0..5, 3..9, 5..12, 12..20, 8..8, 19..20];
        for rows in &ranges {
            for cols in &ranges {
                for weights in [None, Some(w.as_slice())] {
                    let m = query_dense(&reader, rows.clone(), cols.clone(), weights).unwrap();
                    assert_eq!(m.dim(), (rows.len(), cols.len()));
                    for i in rows.clone() {
                        for j in cols.clone() {
                            let want = match weights {
                                Some(w) => (w[i] * w[j]) * full[i][j], // cooler's order
                                None => full[i][j],
                            };
                            let got = m[[i - rows.start, j - cols.start]];
                            assert!(
                                got == want || (got.is_nan() && want.is_nan()),
                                "{rows:?} x {cols:?} at ({i}, {j}): {got} vs {want}"
                            );
                        }
                    }
                    let q = query_pixels(&reader, rows.clone(), cols.clone(), weights).unwrap();
                    let mut want = Vec::new();
                    for i in rows.clone() {
                        for j in cols.clone() {
                            if i <= j && full[i][j] != 0.0 {
                                want.push((i as u64, j as u64, full[i][j]));
                            }
                        }
                    }
                    let got: Vec<(u64, u64, f64)> = (0..q.pixels.len())
                        .map(|k| (q.pixels.bin1[k], q.pixels.bin2[k], q.pixels.count[k]))
                        .collect();
                    assert_eq!(got, want, "{rows:?} x {cols:?}");
                    assert_eq!(q.balanced.is_some(), weights.is_some());
                }
            }
        }
        assert!(query_dense(&reader, 0..n + 1, 0..3, None).is_err());
        assert!(query_pixels(&reader, 0..3, 0..3, Some(&[1.0])).is_err());
    }

    /// A cooler's rectangles (rows from the index, filled in bands on every thread) equal the
    /// matrix of its pixels streamed whole (rows from the bin1_id column, checked).
    #[test]
    fn a_coolers_rectangles_equal_its_streamed_pixels() {
        let reader = crate::io::matrices::cool::CoolReader::open("data/yeast.10kb.cool").unwrap();
        let n = reader.bins().n_bins();
        let w = reader.weights("weight").unwrap().values;
        let mut full = vec![0.0f64; n * n];
        reader
            .read_pixels(0..n, 0..n, &mut |block| {
                for k in 0..block.len() {
                    let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                    full[i * n + j] = block.count[k];
                    full[j * n + i] = block.count[k];
                }
                Ok(())
            })
            .unwrap();
        for (rows, cols) in [
            (0..n, 0..n),
            (100..700, 100..700),
            (100..700, 400..1000),
            (400..1000, 100..700),
            (0..50, 900..1100),
            (1000..1100, 0..30),
        ] {
            for weights in [None, Some(w.as_slice())] {
                let m = query_dense(&reader, rows.clone(), cols.clone(), weights).unwrap();
                for i in rows.clone() {
                    for j in cols.clone() {
                        let raw = full[i * n + j];
                        let want = weights.map_or(raw, |w| (w[i] * w[j]) * raw);
                        let got = m[[i - rows.start, j - cols.start]];
                        assert!(
                            got == want || (got.is_nan() && want.is_nan()),
                            "{rows:?} x {cols:?} at ({i}, {j}): {got} vs {want}"
                        );
                    }
                }
            }
        }
    }
}
