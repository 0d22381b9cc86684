//! The heatmap raster of a contact map: bins to image cells, with memory bounded by the image.
//!
//! A rectangle of `n_rows x n_cols` bins is drawn on a grid of at most `max_rows x max_cols`
//! cells: along an axis with more bins than pixels, cell `c` gathers the consecutive bins of
//! offset `k` with `floor(k * cells / n) = c`, and shows their **mean** over valid
//! bin pairs (stored pixels summed, unstored pixels counting as zero, pairs of masked bins and of
//! the `min_diagonal` first diagonals left out); with fewer bins than pixels each cell is one bin
//! and the image is stretched (pixelated) over the axes. A cell with no valid pair is NaN (drawn
//! in the NaN colour). The accumulators hold one sum and one count per cell, never the
//! `n_rows x n_cols` matrix, so a 5,000 x 5,000-bin region drawn at 800 pixels costs 800 x 800
//! cells.

use std::ops::Range;

use crate::error::Result;
use crate::io::MatrixReader;
use crate::matrix::PixelBlock;
use crate::normalize::Normalizer;
use crate::plot::colormap::{ColorMap, ColorScale, ScaleKind};
use crate::plot::svg::{Rgb, RgbImage};

/// How the bins of one axis fall into cells.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AxisCells {
    /// The bins (global bin ids).
    pub bins: Range<usize>,
    /// Number of cells: `min(bins, max_cells)`.
    pub n_cells: usize,
}

impl AxisCells {
    /// Cells for `bins` on an axis of at most `max_cells` cells.
    pub fn new(bins: Range<usize>, max_cells: usize) -> AxisCells {
        let n_cells = bins.len().min(max_cells.max(1));
        AxisCells { bins, n_cells }
    }

    /// The cell of global bin `bin` (which must be in `bins`).
    pub fn cell(&self, bin: usize) -> usize {
        ((bin - self.bins.start) as u128 * self.n_cells as u128 / self.bins.len() as u128) as usize
    }

    /// The bins of cell `cell`.
    pub fn cell_bins(&self, cell: usize) -> Range<usize> {
        let n = self.bins.len();
        let first = (cell * n).div_ceil(self.n_cells);
        let last = ((cell + 1) * n).div_ceil(self.n_cells);
        self.bins.start + first..self.bins.start + last
    }
}

/// Sums and valid-pair counts on the cell grid of a bin rectangle.
#[derive(Clone, Debug)]
pub struct CellGrid {
    /// Row axis (top to bottom).
    pub rows: AxisCells,
    /// Column axis (left to right).
    pub cols: AxisCells,
    sum: Vec<f64>,
    n_valid: Vec<f64>,
}

impl CellGrid {
    /// An empty grid. `valid(bin)` says whether a bin is drawn (not masked); pairs `(i, j)` with
    /// `|i - j| < min_diagonal` are left out when `same_chrom` (for o/e maps whose first
    /// diagonals have no expected).
    pub fn new(
        rows: AxisCells,
        cols: AxisCells,
        valid: &dyn Fn(usize) -> bool,
        min_diagonal: usize,
        same_chrom: bool,
    ) -> CellGrid {
        let count = |axis: &AxisCells| {
            let mut per_cell = vec![0.0; axis.n_cells];
            for bin in axis.bins.clone() {
                if valid(bin) {
                    per_cell[axis.cell(bin)] += 1.0;
                }
            }
            per_cell
        };
        let (row_valid, col_valid) = (count(&rows), count(&cols));
        let mut n_valid = Vec::with_capacity(rows.n_cells * cols.n_cells);
        for r in &row_valid {
            n_valid.extend(col_valid.iter().map(|c| r * c));
        }
        if same_chrom && min_diagonal > 0 {
            for i in rows.bins.clone().filter(|&i| valid(i)) {
                let low = i.saturating_sub(min_diagonal - 1).max(cols.bins.start);
                let high = (i + min_diagonal).min(cols.bins.end);
                for j in (low..high).filter(|&j| valid(j)) {
                    n_valid[rows.cell(i) * cols.n_cells + cols.cell(j)] -= 1.0;
                }
            }
        }
        CellGrid {
            sum: vec![0.0; rows.n_cells * cols.n_cells],
            n_valid,
            rows,
            cols,
        }
    }

    /// Add the value of bin pair `(row, col)` (both inside the grid); NaN values are skipped.
    pub fn add(&mut self, row: usize, col: usize, value: f64) {
        if value.is_nan() {
            return;
        }
        let at = self.rows.cell(row) * self.cols.n_cells + self.cols.cell(col);
        self.sum[at] += value;
    }

    /// The mean of cell `(r, c)` over its valid pairs (NaN when it has none).
    pub fn value(&self, r: usize, c: usize) -> f64 {
        let at = r * self.cols.n_cells + c;
        if self.n_valid[at] > 0.5 {
            self.sum[at] / self.n_valid[at]
        } else {
            f64::NAN
        }
    }

    /// Every cell value, row by row.
    pub fn values(&self) -> Vec<f64> {
        (0..self.rows.n_cells)
            .flat_map(|r| (0..self.cols.n_cells).map(move |c| (r, c)))
            .map(|(r, c)| self.value(r, c))
            .collect()
    }

    /// The grid as an image, one pixel per cell.
    pub fn image(&self, map: &ColorMap, scale: &ColorScale, nan: Rgb) -> RgbImage {
        let mut image = RgbImage::filled(self.cols.n_cells, self.rows.n_cells, nan);
        for r in 0..self.rows.n_cells {
            for c in 0..self.cols.n_cells {
                if let Some(t) = scale.position(self.value(r, c)) {
                    image.set(c, r, map.colour(t));
                }
            }
        }
        image
    }

    /// The 45-degree view of a square grid (rows and columns the same bins): an image of
    /// `width x height` pixels whose bottom edge is the diagonal and whose top edge is
    /// `depth_bins` diagonals away. Pixel `(x, y)` shows the pair `(p - d / 2, p + d / 2)` at
    /// position `p = (x + 1/2) n / width` and distance `d = (height - y - 1/2) depth / height`
    /// bins; pixels outside the matrix take `background`.
    pub fn triangle_image(
        &self,
        width: usize,
        height: usize,
        depth_bins: f64,
        map: &ColorMap,
        scale: &ColorScale,
        colours: (Rgb, Rgb),
    ) -> RgbImage {
        let (nan, background) = colours;
        let n = self.rows.bins.len() as f64;
        let mut image = RgbImage::filled(width, height, background);
        for y in 0..height {
            let d = (height as f64 - y as f64 - 0.5) * depth_bins / height as f64;
            for x in 0..width {
                let p = (x as f64 + 0.5) * n / width as f64;
                let (i, j) = (p - d / 2.0, p + d / 2.0);
                if i < 0.0 || j >= n {
                    continue;
                }
                let (bi, bj) = (
                    self.rows.bins.start + i as usize,
                    self.rows.bins.start + j as usize,
                );
                let value = self.value(self.rows.cell(bi), self.cols.cell(bj));
                image.set(
                    x,
                    y,
                    match scale.position(value) {
                        Some(t) => map.colour(t),
                        None => nan,
                    },
                );
            }
        }
        image
    }
}

impl CellGrid {
    /// Stream the pixels of the grid's rectangle from `reader` into it, both triangles (a stored
    /// pixel `(i, j)` fills `(i, j)` and `(j, i)` where the rectangle holds them), each value
    /// transformed by `normalizer` (observed / expected), else multiplied by the two bins'
    /// `weights` (balanced), else raw.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::io::open_matrix;
    /// use contactmap::plot::heatmap::{AxisCells, CellGrid};
    ///
    /// let reader = open_matrix("data/CN.mm9.10000kb.cool", &Default::default())?;
    /// let rows = 0..20; // the first 20 bins, drawn as 20 x 20 cells
    /// let mut grid = CellGrid::new(
    ///     AxisCells::new(rows.clone(), 20),
    ///     AxisCells::new(rows.clone(), 20),
    ///     &|_| true,
    ///     0,
    ///     true,
    /// );
    /// grid.fill(reader.as_ref(), None, None)?;
    /// // Raw counts: the cells are the symmetric dense matrix.
    /// let mut dense = 0.0;
    /// reader.read_pixels(rows.clone(), rows.clone(), &mut |block| {
    ///     for k in 0..block.len() {
    ///         dense += if block.bin1[k] == block.bin2[k] { 1.0 } else { 2.0 } * block.count[k];
    ///     }
    ///     Ok(())
    /// })?;
    /// assert_eq!(grid.values().iter().sum::<f64>(), dense);
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn fill(
        &mut self,
        reader: &dyn MatrixReader,
        weights: Option<&[f64]>,
        normalizer: Option<&Normalizer>,
    ) -> Result<()> {
        let rows = self.rows.bins.clone();
        let cols = self.cols.bins.clone();
        let value = |block: &PixelBlock| -> Result<PixelBlock> {
            match (normalizer, weights) {
                (Some(n), _) => n.apply(block),
                (None, Some(w)) => {
                    let mut out = block.clone();
                    for k in 0..out.len() {
                        out.count[k] *= w[out.bin1[k] as usize] * w[out.bin2[k] as usize];
                    }
                    Ok(out)
                }
                (None, None) => Ok(block.clone()),
            }
        };
        let symmetric = rows == cols;
        reader.read_pixels(rows.clone(), cols.clone(), &mut |block| {
            let block = value(block)?;
            for k in 0..block.len() {
                let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                self.add(i, j, block.count[k]);
                if symmetric && i != j {
                    self.add(j, i, block.count[k]);
                }
            }
            Ok(())
        })?;
        if !symmetric {
            // The lower triangle of the rectangle: stored as (col, row) with col < row.
            reader.read_pixels(cols.clone(), rows.clone(), &mut |block| {
                let block = value(block)?;
                for k in 0..block.len() {
                    let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                    if i != j {
                        self.add(j, i, block.count[k]);
                    }
                }
                Ok(())
            })?;
        }
        Ok(())
    }
}

/// How [`CellGrid::compared`] combines the grids of two maps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GridComparison {
    /// The first map on and above the diagonal, the second below it, multiplied by
    /// `scale_second` (to the first map's depth).
    Split {
        /// Factor of the second map's cells.
        scale_second: f64,
    },
    /// `log2(first / (second * scale_second))` per cell: NaN where either cell is NaN or not
    /// positive.
    Log2Ratio {
        /// Factor of the second map's cells.
        scale_second: f64,
    },
}

impl CellGrid {
    /// The grid of two maps drawn on the same cells (same bins, same grid size): their cell
    /// means split along the diagonal (rows and columns the same region) or their log2 ratio.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::plot::heatmap::{AxisCells, CellGrid, GridComparison};
    ///
    /// let grid = |value: f64| {
    ///     let mut g = CellGrid::new(AxisCells::new(0..3, 3), AxisCells::new(0..3, 3), &|_| true, 0, true);
    ///     for i in 0..3 {
    ///         for j in 0..3 {
    ///             g.add(i, j, value);
    ///         }
    ///     }
    ///     g
    /// };
    /// let (a, b) = (grid(4.0), grid(1.0));
    /// let split = CellGrid::compared(&a, &b, GridComparison::Split { scale_second: 2.0 })?;
    /// assert_eq!((split.value(0, 2), split.value(1, 1), split.value(2, 0)), (4.0, 4.0, 2.0));
    /// let ratio = CellGrid::compared(&a, &b, GridComparison::Log2Ratio { scale_second: 2.0 })?;
    /// assert_eq!(ratio.value(2, 0), 1.0); // log2(4 / (1 * 2))
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn compared(first: &CellGrid, second: &CellGrid, how: GridComparison) -> Result<CellGrid> {
        if first.rows != second.rows || first.cols != second.cols {
            return Err(crate::error::Error::Data(
                "the two maps are drawn on different cells: they must cover the same bins".into(),
            ));
        }
        if matches!(how, GridComparison::Split { .. }) && first.rows != first.cols {
            return Err(crate::error::Error::Argument(
                "a split map shows one region (rows and columns the same bins)".into(),
            ));
        }
        let (n_rows, n_cols) = (first.rows.n_cells, first.cols.n_cells);
        let mut sum = vec![f64::NAN; n_rows * n_cols];
        for r in 0..n_rows {
            for c in 0..n_cols {
                let (a, b) = (first.value(r, c), second.value(r, c));
                sum[r * n_cols + c] = match how {
                    GridComparison::Split { scale_second } if c < r => b * scale_second,
                    GridComparison::Split { .. } => a,
                    GridComparison::Log2Ratio { scale_second } => {
                        let ratio = a / (b * scale_second);
                        if a > 0.0 && b > 0.0 && ratio.is_finite() {
                            ratio.log2()
                        } else {
                            f64::NAN
                        }
                    }
                };
            }
        }
        let n_valid = sum
            .iter()
            .map(|v| if v.is_nan() { 0.0 } else { 1.0 })
            .collect();
        let sum = sum
            .into_iter()
            .map(|v| if v.is_nan() { 0.0 } else { v })
            .collect();
        Ok(CellGrid {
            rows: first.rows.clone(),
            cols: first.cols.clone(),
            sum,
            n_valid,
        })
    }
}

/// The colour limits of a map drawn on a `kind` scale: the `low` and `high` percentiles of the
/// drawn values ([`percentile_limits`]), made symmetric about `centre` when given (in log space
/// on a log scale: 1 for observed / expected; 0 for a linear log2 ratio), and widened around a
/// single value (half and twice it on a log scale, +-0.5 on a linear one). `None` when no value
/// can be drawn.
///
/// # Examples
///
/// ```
/// use contactmap::plot::heatmap::colour_limits;
/// use contactmap::plot::ScaleKind;
///
/// let oe = [0.5, 1.0, 1.5, f64::NAN];
/// let (low, high) = colour_limits(&oe, ScaleKind::Log, 0.0, 100.0, Some(1.0)).unwrap();
/// assert!((low - 0.5).abs() < 1e-12 && (high - 2.0).abs() < 1e-12);
/// let log2_ratio = [-0.5, 0.25, 1.0];
/// assert_eq!(colour_limits(&log2_ratio, ScaleKind::Linear, 0.0, 100.0, Some(0.0)), Some((-1.0, 1.0)));
/// assert_eq!(colour_limits(&[3.0], ScaleKind::Linear, 0.0, 100.0, None), Some((2.5, 3.5)));
/// assert_eq!(colour_limits(&[0.0], ScaleKind::Log, 0.0, 100.0, None), None);
/// ```
pub fn colour_limits(
    values: &[f64],
    kind: ScaleKind,
    low: f64,
    high: f64,
    centre: Option<f64>,
) -> Option<(f64, f64)> {
    let (mut a, mut b) = percentile_limits(values, kind == ScaleKind::Log, low, high)?;
    if let Some(centre) = centre {
        if kind == ScaleKind::Log {
            let m = (a / centre)
                .ln()
                .abs()
                .max((b / centre).ln().abs())
                .max(1e-3);
            (a, b) = (centre * (-m).exp(), centre * m.exp());
        } else {
            let m = (a - centre).abs().max((b - centre).abs()).max(1e-3);
            (a, b) = (centre - m, centre + m);
        }
    }
    if a == b {
        // One value everywhere: widen the range around it.
        (a, b) = match kind {
            ScaleKind::Log => (a / 2.0, b * 2.0),
            ScaleKind::Linear => (a - 0.5, b + 0.5),
        };
    }
    Some((a, b))
}

/// Colour limits from the finite (and, for a log scale, positive) cell values: the `low` and
/// `high` percentiles (0 and 100: min and max). `None` when there is no such value.
pub fn percentile_limits(
    values: &[f64],
    positive: bool,
    low: f64,
    high: f64,
) -> Option<(f64, f64)> {
    let mut kept: Vec<f64> = values
        .iter()
        .copied()
        .filter(|v| v.is_finite() && (!positive || *v > 0.0))
        .collect();
    if kept.is_empty() {
        return None;
    }
    kept.sort_by(f64::total_cmp);
    // numpy's default (linear) percentile.
    let at = |q: f64| {
        let position = q / 100.0 * (kept.len() - 1) as f64;
        let (below, above) = (position.floor() as usize, position.ceil() as usize);
        kept[below] + (position - below as f64) * (kept[above] - kept[below])
    };
    Some((at(low), at(high)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The dense mean of each cell, computed naively from a full matrix.
    fn naive(
        matrix: &[Vec<f64>],
        rows: &AxisCells,
        cols: &AxisCells,
        valid: &dyn Fn(usize) -> bool,
        min_diagonal: usize,
    ) -> Vec<f64> {
        let mut out = Vec::new();
        for r in 0..rows.n_cells {
            for c in 0..cols.n_cells {
                let (mut sum, mut n) = (0.0, 0.0);
                for i in rows.cell_bins(r) {
                    for j in cols.cell_bins(c) {
                        if valid(i) && valid(j) && i.abs_diff(j) >= min_diagonal {
                            sum += matrix[i][j];
                            n += 1.0;
                        }
                    }
                }
                out.push(if n > 0.0 { sum / n } else { f64::NAN });
            }
        }
        out
    }

    #[test]
    fn cells_partition_the_bins() {
        for (n, cells) in [(10, 3), (7, 7), (5, 9), (5000, 800)] {
            let axis = AxisCells::new(100..100 + n, cells);
            let mut covered = 0;
            for cell in 0..axis.n_cells {
                let bins = axis.cell_bins(cell);
                assert!(!bins.is_empty());
                for bin in bins.clone() {
                    assert_eq!(axis.cell(bin), cell);
                }
                covered += bins.len();
            }
            assert_eq!(covered, n);
        }
    }

    #[test]
    fn cell_means_equal_the_dense_means() {
        let n = 23;
        let matrix: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        if (i * 7 + j * 3) % 5 == 0 {
                            0.0
                        } else {
                            (1 + i + j) as f64
                        }
                    })
                    .collect()
            })
            .collect();
        let valid = |bin: usize| bin != 4 && bin != 17;
        for (cells, min_diagonal) in [(5, 0), (5, 2), (23, 1), (40, 3), (7, 2)] {
            let rows = AxisCells::new(0..n, cells);
            let cols = AxisCells::new(3..n, cells);
            let mut grid = CellGrid::new(rows.clone(), cols.clone(), &valid, min_diagonal, true);
            for (i, row) in matrix.iter().enumerate() {
                for (j, &value) in row.iter().enumerate().skip(3) {
                    let masked = !valid(i) || !valid(j) || i.abs_diff(j) < min_diagonal;
                    if value != 0.0 && !masked {
                        grid.add(i, j, value);
                    }
                }
            }
            let expected = naive(&matrix, &rows, &cols, &valid, min_diagonal);
            let got = grid.values();
            for (a, b) in got.iter().zip(&expected) {
                assert!(
                    (a.is_nan() && b.is_nan()) || (a - b).abs() < 1e-12,
                    "cells {cells}, min diagonal {min_diagonal}: {a} vs {b}"
                );
            }
        }
    }

    #[test]
    fn triangle_pixels_show_their_pairs() {
        let n = 8;
        let axis = AxisCells::new(0..n, n);
        let mut grid = CellGrid::new(axis.clone(), axis, &|_| true, 0, true);
        for i in 0..n {
            for j in i..n {
                let value = (10 * i + j + 1) as f64;
                grid.add(i, j, value);
                if i != j {
                    grid.add(j, i, value);
                }
            }
        }
        let map = ColorMap::by_name("Greys").unwrap();
        let scale = ColorScale::new(ScaleKind::Linear, 0.0, 100.0).unwrap();
        let colours = (Rgb(255, 0, 0), Rgb(0, 0, 255));
        // 2 pixels per bin along the genome, 1 pixel per diagonal up to 4 diagonals.
        let image = grid.triangle_image(16, 4, 4.0, &map, &scale, colours);
        // Bottom row (d = 0.5): pixel x = 5 is p = 2.75, bins (2.5, 3.0): pair (2, 3).
        assert_eq!(image.get(5, 3), map.colour(scale.position(24.0).unwrap()));
        // Top row (d = 3.5): x = 7 is p = 3.75, bins (2.0, 5.5): pair (2, 5).
        assert_eq!(image.get(7, 0), map.colour(scale.position(26.0).unwrap()));
        // Outside the matrix (left corner of the top row).
        assert_eq!(image.get(0, 0), Rgb(0, 0, 255));
    }

    #[test]
    fn percentiles_follow_numpy() {
        let values = [f64::NAN, 4.0, 1.0, 0.0, 3.0, 2.0];
        assert_eq!(
            percentile_limits(&values, false, 0.0, 100.0),
            Some((0.0, 4.0))
        );
        assert_eq!(
            percentile_limits(&values, true, 0.0, 100.0),
            Some((1.0, 4.0))
        );
        assert_eq!(
            percentile_limits(&values, true, 50.0, 75.0),
            Some((2.5, 3.25))
        );
        assert_eq!(percentile_limits(&[f64::NAN], true, 0.0, 100.0), None);
    }
}
