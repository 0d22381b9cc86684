//! Pixel passes for the numerical algorithms: a compact in-memory copy of the pixels, or a file
//! streamed from disk, behind one map-reduce interface.
//!
//! Balancing and expected make many passes over every pixel. [`Pixels`] holds them in 16 bytes
//! each (`u32` bin ids, `f64` count), sorted by `(bin1, bin2)`; a pass splits them into slices
//! folded in parallel by rayon and reduces the partial results. When the copy would not fit the
//! memory budget, a [`PixelSource`] that streams blocks from the file gives the same passes (see
//! `io::StreamedPixels`). Results do not depend on the number of threads: partial results are
//! combined in a fixed order of fixed-size slices.

use rayon::prelude::*;

use super::block::{CountType, PixelBlock};
use crate::error::{Error, Result};
use crate::genome::BinTable;

/// Pixels per slice of a parallel pass (fixed, so results do not depend on the thread count).
pub const SLICE_PIXELS: usize = 1 << 16;

/// A borrowed run of pixels sorted by `(bin1, bin2)`, upper triangle.
#[derive(Clone, Copy, Debug)]
pub struct PixelSlice<'a> {
    /// Row bin ids.
    pub bin1: &'a [u32],
    /// Column bin ids.
    pub bin2: &'a [u32],
    /// Counts.
    pub count: &'a [f64],
}

impl<'a> PixelSlice<'a> {
    /// Number of pixels.
    pub fn len(&self) -> usize {
        self.count.len()
    }

    /// True when the slice holds no pixel.
    pub fn is_empty(&self) -> bool {
        self.count.is_empty()
    }

    /// Iterate over `(bin1, bin2, count)`.
    pub fn iter(&self) -> impl Iterator<Item = (usize, usize, f64)> + 'a + use<'a> {
        let (b1, b2, c) = (self.bin1, self.bin2, self.count);
        (0..c.len()).map(move |k| (b1[k] as usize, b2[k] as usize, c[k]))
    }

    /// Each row's run of pixels, in order: `(row, positions)` (pixels are sorted by
    /// `(bin1, bin2)`, so a row's pixels are contiguous and sorted by column).
    pub fn rows(&self) -> impl Iterator<Item = (usize, std::ops::Range<usize>)> + 'a + use<'a> {
        let bin1 = self.bin1;
        let mut k = 0;
        std::iter::from_fn(move || {
            let &row = bin1.get(k)?;
            let end = bin1[k..]
                .iter()
                .position(|&b| b != row)
                .map_or(bin1.len(), |n| k + n);
            let run = k..end;
            k = end;
            Some((row as usize, run))
        })
    }

    fn split(self, at: usize) -> (PixelSlice<'a>, PixelSlice<'a>) {
        let (b1a, b1b) = self.bin1.split_at(at);
        let (b2a, b2b) = self.bin2.split_at(at);
        let (ca, cb) = self.count.split_at(at);
        (
            PixelSlice {
                bin1: b1a,
                bin2: b2a,
                count: ca,
            },
            PixelSlice {
                bin1: b1b,
                bin2: b2b,
                count: cb,
            },
        )
    }

    /// Fold fixed-size slices in parallel and reduce the partial results in slice order.
    pub fn fold<T, I, F, R>(self, init: &I, fold: &F, reduce: &R) -> T
    where
        T: Send,
        I: Fn() -> T + Sync,
        F: Fn(T, PixelSlice<'_>) -> T + Sync,
        R: Fn(T, T) -> T + Sync,
    {
        let mut parts = Vec::with_capacity(self.len() / SLICE_PIXELS + 1);
        let mut rest = self;
        while rest.len() > SLICE_PIXELS {
            let (head, tail) = rest.split(SLICE_PIXELS);
            parts.push(head);
            rest = tail;
        }
        parts.push(rest);
        let partial: Vec<T> = parts.into_par_iter().map(|p| fold(init(), p)).collect();
        partial.into_iter().fold(init(), reduce)
    }
}

/// Anything whose pixels the algorithms can pass over: bins, count type and a map-reduce pass.
pub trait PixelSource {
    /// The bin table.
    fn bins(&self) -> &BinTable;

    /// Whether counts are integers or reals.
    fn count_type(&self) -> CountType;

    /// One pass over every stored pixel: `fold` partial results over slices (in parallel, each
    /// starting from `init()`), combined with `reduce` in pixel order.
    fn pass<T, I, F, R>(&self, init: I, fold: F, reduce: R) -> Result<T>
    where
        T: Send,
        I: Fn() -> T + Sync,
        F: Fn(T, PixelSlice<'_>) -> T + Sync,
        R: Fn(T, T) -> T + Sync;

    /// Every pixel as one slice when the source holds them in memory (`None` when it streams
    /// them): algorithms that pass over the pixels many times may build their own layout from it.
    fn in_memory(&self) -> Option<PixelSlice<'_>> {
        None
    }
}

/// The pixels of a matrix held in memory: sorted `(bin1, bin2)` upper triangle, 16 bytes a pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Pixels {
    bins: BinTable,
    count_type: CountType,
    bin1: Vec<u32>,
    bin2: Vec<u32>,
    count: Vec<f64>,
}

/// Bytes one pixel takes in [`Pixels`].
pub const BYTES_PER_PIXEL: u64 = 16;

impl Pixels {
    /// An empty store for pixels over `bins`, with room for `capacity` pixels.
    pub fn with_capacity(bins: BinTable, count_type: CountType, capacity: usize) -> Result<Self> {
        if bins.n_bins() > u32::MAX as usize {
            return Err(Error::Unsupported(format!(
                "{} bins do not fit 32-bit bin ids",
                bins.n_bins()
            )));
        }
        Ok(Pixels {
            bins,
            count_type,
            bin1: Vec::with_capacity(capacity),
            bin2: Vec::with_capacity(capacity),
            count: Vec::with_capacity(capacity),
        })
    }

    /// Append a sorted block (as readers stream them); checks order and range.
    pub fn extend(&mut self, block: &PixelBlock) -> Result<()> {
        let n_bins = self.bins.n_bins() as u64;
        let mut last = match (self.bin1.last(), self.bin2.last()) {
            (Some(&i), Some(&j)) => Some((i as u64, j as u64)),
            _ => None,
        };
        for k in 0..block.len() {
            let key = (block.bin1[k], block.bin2[k]);
            if key.0 > key.1 || key.1 >= n_bins || last.is_some_and(|l| l >= key) {
                return Err(Error::Data(format!(
                    "pixel ({}, {}) is out of order, below the diagonal or out of range",
                    key.0, key.1
                )));
            }
            last = Some(key);
            self.bin1.push(key.0 as u32);
            self.bin2.push(key.1 as u32);
            self.count.push(block.count[k]);
        }
        Ok(())
    }

    /// The pixels of a matrix stored in both triangles (cooler `storage-mode: square`), folded
    /// onto the upper triangle as cooler's balance sees them: a pixel `(i, j)` with `i > j` becomes
    /// `(j, i)` and is kept beside the stored `(j, i)`, not summed with it, so that each stored
    /// pixel counts once in a row's sum and once in its number of nonzero pixels (cooler's
    /// `bincount(bin1) + bincount(bin2)` over the stored pixels). The result is sorted by
    /// `(bin1, bin2)` with such keys repeated; only the balancers read it.
    pub fn from_folded(
        bins: BinTable,
        count_type: CountType,
        mut pixels: Vec<(u32, u32, f64)>,
    ) -> Result<Self> {
        let n_bins = bins.n_bins();
        if let Some(&(i, j, _)) = pixels
            .iter()
            .find(|&&(i, j, _)| i as usize >= n_bins || j as usize >= n_bins)
        {
            return Err(Error::Data(format!(
                "pixel ({i}, {j}) is out of range ({n_bins} bins)"
            )));
        }
        for pixel in &mut pixels {
            if pixel.0 > pixel.1 {
                (pixel.0, pixel.1) = (pixel.1, pixel.0);
            }
        }
        pixels.par_sort_by_key(|&(i, j, _)| (i, j));
        let mut out = Pixels::with_capacity(bins, count_type, pixels.len())?;
        for (i, j, count) in pixels {
            out.bin1.push(i);
            out.bin2.push(j);
            out.count.push(count);
        }
        Ok(out)
    }

    /// All pixels as one slice.
    pub fn as_slice(&self) -> PixelSlice<'_> {
        PixelSlice {
            bin1: &self.bin1,
            bin2: &self.bin2,
            count: &self.count,
        }
    }

    /// Number of pixels.
    pub fn len(&self) -> usize {
        self.count.len()
    }

    /// True when there is no pixel.
    pub fn is_empty(&self) -> bool {
        self.count.is_empty()
    }
}

impl PixelSource for Pixels {
    fn bins(&self) -> &BinTable {
        &self.bins
    }

    fn count_type(&self) -> CountType {
        self.count_type
    }

    fn pass<T, I, F, R>(&self, init: I, fold: F, reduce: R) -> Result<T>
    where
        T: Send,
        I: Fn() -> T + Sync,
        F: Fn(T, PixelSlice<'_>) -> T + Sync,
        R: Fn(T, T) -> T + Sync,
    {
        Ok(self.as_slice().fold(&init, &fold, &reduce))
    }

    fn in_memory(&self) -> Option<PixelSlice<'_>> {
        Some(self.as_slice())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::Chrom;

    #[test]
    fn passes_reduce_in_order_whatever_the_slicing() {
        let bins = BinTable::fixed(vec![Chrom::new("a", 1000)], 1).unwrap();
        let mut pixels = Pixels::with_capacity(bins, CountType::Float, 0).unwrap();
        let mut block = PixelBlock::default();
        for i in 0..1000u64 {
            for j in i..(i + 300).min(1000) {
                block.push(i, j, 1.0 / (1.0 + (j - i) as f64));
            }
        }
        pixels.extend(&block).unwrap();
        assert!(pixels.len() > 3 * SLICE_PIXELS);
        let naive: f64 = block.count.iter().sum();
        let sum = pixels
            .pass(
                || 0.0,
                |acc, s| acc + s.count.iter().sum::<f64>(),
                |a, b| a + b,
            )
            .unwrap();
        assert!((sum - naive).abs() < 1e-9 * naive);
        // The same pass twice gives bit-identical results.
        let again = pixels
            .pass(
                || 0.0,
                |acc, s| acc + s.count.iter().sum::<f64>(),
                |a, b| a + b,
            )
            .unwrap();
        assert_eq!(sum.to_bits(), again.to_bits());
        let mut bad = PixelBlock::default();
        bad.push(5, 4, 1.0);
        assert!(pixels.extend(&bad).is_err());
    }
}
