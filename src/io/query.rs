//! Rectangles of a map as the Python tools fetch them: cooler's `Cooler.matrix().fetch` (a
//! dense array of the full symmetric matrix, balanced or not) and hictk's `fetch` (the pixels of
//! a query, optionally balanced). The binding (`python/`) and any caller reach every reader
//! through these.

use std::ops::Range;

use ndarray::Array2;
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::io::MatrixReader;
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
            return Err(Error::Invalid(format!(
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
        Some(w) if w.len() != n => Err(Error::Invalid(format!(
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
        return Err(Error::Invalid(format!(
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
    // the upper triangle's pixels with their row in `rows`, column in `cols`
    reader.read_pixels(rows.clone(), cols.clone(), &mut |block| {
        for k in 0..block.len() {
            let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
            let v = value(i, j, block.count[k]);
            out[(i - r0) * width + (j - c0)] = v;
            if symmetric && i != j {
                out[(j - r0) * width + (i - c0)] = v;
            }
        }
        Ok(())
    })?;
    // the lower triangle: stored (a, b), a < b, a in `cols` and b in `rows`, seen at (b, a)
    if !symmetric && cols.start + 1 < rows.end {
        reader.read_pixels(cols.clone(), rows.clone(), &mut |block| {
            for k in 0..block.len() {
                let (a, b) = (block.bin1[k] as usize, block.bin2[k] as usize);
                if a < b {
                    out[(b - r0) * width + (a - c0)] = value(b, a, block.count[k]);
                }
            }
            Ok(())
        })?;
    }
    // a masked bin's row and column are NaN throughout (zeros included: 0 x NaN)
    if let Some(w) = weights {
        let masked_cols: Vec<usize> = cols.clone().filter(|&j| w[j].is_nan()).collect();
        out.par_chunks_mut(width)
            .zip(rows.clone().into_par_iter())
            .for_each(|(row, i)| {
                if w[i].is_nan() {
                    row.fill(f64::NAN);
                } else {
                    for &j in &masked_cols {
                        row[j - c0] = f64::NAN;
                    }
                }
            });
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
}
