//! The near-diagonal band of each view region, dense, for callers that look at every pixel within a
//! window of the diagonal (TopDom, Armatus, the directionality HMM).
//!
//! A [`CisBand`] holds, for the bins of one region, the values at distances `0..width` from the
//! diagonal: balanced (`count * w1 * w2`, cooler's convention) when weights are given, raw counts
//! otherwise. Pixels touching a masked bin (NaN weight) are stored as 0 and the bin is flagged in
//! [`CisBand::bad`]. Missing pixels are 0. Memory: 8 bytes times bins times width.

use crate::error::Result;
use crate::genome::{View, ViewRegion};
use crate::matrix::PixelSource;

/// The dense band `0 <= j - i < width` of one region's symmetric matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct CisBand {
    /// Genome-wide index of the region's first bin.
    pub first_bin: usize,
    /// Number of bins.
    pub n_bins: usize,
    /// Number of diagonals kept (distance 0 to `width - 1`).
    pub width: usize,
    /// Masked bins (NaN weight), by local index.
    pub bad: Vec<bool>,
    /// Row-major `n_bins x width`: `values[i * width + d]` is pixel `(i, i + d)`.
    values: Vec<f64>,
}

impl CisBand {
    /// An empty (all-zero, nothing masked) band.
    pub fn zeros(first_bin: usize, n_bins: usize, width: usize) -> CisBand {
        CisBand {
            first_bin,
            n_bins,
            width,
            bad: vec![false; n_bins],
            values: vec![0.0; n_bins * width],
        }
    }

    /// The value at local bins `(i, j)` in either order; 0 outside the band or the region.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        let d = j - i;
        if j >= self.n_bins || d >= self.width {
            0.0
        } else {
            self.values[i * self.width + d]
        }
    }

    /// Add `value` at local bins `(i, j)`, `i <= j`, inside the band.
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        let d = j - i;
        debug_assert!(j < self.n_bins && d < self.width);
        self.values[i * self.width + d] += value;
    }

    /// Set the pixels closer than `n_diagonals` to the diagonal (`j - i < n_diagonals`) to 0, as
    /// callers that ignore the first diagonals need.
    pub fn clear_near_diagonal(&mut self, n_diagonals: usize) {
        let n = n_diagonals.min(self.width);
        for row in self.values.chunks_mut(self.width) {
            row[..n].fill(0.0);
        }
    }

    /// The row of distances `0..width` starting at local bin `i` (shorter near the region end:
    /// entries past the end are 0).
    pub fn row(&self, i: usize) -> &[f64] {
        &self.values[i * self.width..(i + 1) * self.width]
    }
}

/// The bands of every region of `view`, in one pass over the pixels. Trans pixels, pixels
/// between different regions and pixels farther than `width - 1` bins from the diagonal are
/// skipped. With `weights`, values are balanced and bins with a NaN weight are masked.
///
/// # Examples
///
/// ```
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
/// use contactmap::tads::band::cis_bands;
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 400), Chrom::new("chr2", 300)], 100)?;
/// let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
/// builder.push(0, 1, 2.0)?;
/// builder.push(0, 3, 5.0)?; // farther than the band
/// builder.push(2, 4, 7.0)?; // trans
/// builder.push(4, 5, 4.0)?;
/// let matrix = InMemory::new("example".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// let weights = [1.0, 0.5, 1.0, 1.0, 2.0, 1.0, f64::NAN];
/// let bands = cis_bands(&pixels, Some(&weights), &View::chromosomes(&bins), 3)?;
/// assert_eq!(bands.len(), 2);
/// assert_eq!((bands[0].get(0, 1), bands[0].get(1, 0), bands[0].get(0, 3)), (1.0, 1.0, 0.0));
/// assert_eq!((bands[1].first_bin, bands[1].get(0, 1)), (4, 8.0)); // local bins of chr2
/// assert_eq!(bands[1].bad, [false, false, true]);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn cis_bands<S: PixelSource>(
    source: &S,
    weights: Option<&[f64]>,
    view: &View,
    width: usize,
) -> Result<Vec<CisBand>> {
    let n_bins = source.bins().n_bins();
    let bin_region = view.bin_regions(n_bins);
    let width = width.max(1);
    // Each slice collects (region, local i, local j, value); the pieces are concatenated in pixel
    // order, so the sums below are in the same order whatever the thread count.
    let kept: Vec<(u32, u32, u32, f64)> = source.pass(
        Vec::new,
        |mut acc: Vec<(u32, u32, u32, f64)>, slice| {
            for (b1, b2, count) in slice.iter() {
                if b2 - b1 >= width {
                    continue;
                }
                let (Some(r1), Some(r2)) = (bin_region[b1], bin_region[b2]) else {
                    continue;
                };
                if r1 != r2 {
                    continue;
                }
                let value = match weights {
                    Some(w) => count * w[b1] * w[b2],
                    None => count,
                };
                if !value.is_finite() {
                    continue;
                }
                let first = view.regions()[r2].bins.start;
                acc.push((r2 as u32, (b1 - first) as u32, (b2 - first) as u32, value));
            }
            acc
        },
        |mut a, mut b| {
            a.append(&mut b);
            a
        },
    )?;
    let mut bands: Vec<CisBand> = view
        .regions()
        .iter()
        .map(|region| empty_band(region, weights, width))
        .collect();
    for (r, i, j, value) in kept {
        let band = &mut bands[r as usize];
        // A bin shared by two regions (regions meeting inside a bin) starts the later region.
        if (i as usize) < band.n_bins && (j as usize) < band.n_bins {
            band.add(i as usize, j as usize, value);
        }
    }
    Ok(bands)
}

fn empty_band(region: &ViewRegion, weights: Option<&[f64]>, width: usize) -> CisBand {
    let mut band = CisBand::zeros(region.bins.start, region.n_bins(), width);
    if let Some(w) = weights {
        for (local, bin) in region.bins.clone().enumerate() {
            band.bad[local] = !w[bin].is_finite();
        }
    }
    band
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PixelBlock;
    use crate::genome::{BinTable, Chrom};
    use crate::matrix::{CountType, Pixels};

    fn pixels(bins: BinTable, triplets: &[(u64, u64, f64)]) -> Pixels {
        let mut block = PixelBlock::with_capacity(triplets.len());
        for &(a, b, c) in triplets {
            block.push(a, b, c);
        }
        let mut p = Pixels::with_capacity(bins, CountType::Integer, triplets.len()).unwrap();
        p.extend(&block).unwrap();
        p
    }

    #[test]
    fn bands_keep_cis_near_diagonal_pixels_balanced() {
        let bins = BinTable::fixed(vec![Chrom::new("a", 400), Chrom::new("b", 300)], 100).unwrap();
        let view = View::chromosomes(&bins);
        let p = pixels(
            bins,
            &[
                (0, 0, 1.0),
                (0, 1, 2.0),
                (0, 3, 5.0), // too far for width 3
                (1, 2, 3.0),
                (2, 4, 7.0), // trans
                (4, 5, 4.0),
                (5, 6, 6.0), // bin 6 masked
            ],
        );
        let w = [1.0, 2.0, 1.0, 1.0, 0.5, 1.0, f64::NAN];
        let bands = cis_bands(&p, Some(&w), &view, 3).unwrap();
        assert_eq!(bands.len(), 2);
        assert_eq!(bands[0].get(0, 0), 1.0);
        assert_eq!(bands[0].get(1, 0), 4.0);
        assert_eq!(bands[0].get(1, 2), 6.0);
        assert_eq!(bands[0].get(0, 3), 0.0);
        assert_eq!(bands[1].first_bin, 4);
        assert_eq!(bands[1].get(0, 1), 2.0);
        assert_eq!(bands[1].get(1, 2), 0.0);
        assert_eq!(bands[1].bad, vec![false, false, true]);
        let mut cleared = bands[0].clone();
        cleared.clear_near_diagonal(1);
        assert_eq!((cleared.get(0, 0), cleared.get(0, 1)), (0.0, 4.0));
        let raw = cis_bands(&p, None, &view, 3).unwrap();
        assert_eq!(raw[1].get(1, 2), 6.0);
        assert!(raw[1].bad.iter().all(|b| !b));
    }
}
