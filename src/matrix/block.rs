//! A block of pixels as readers stream them, and how its counts are stored.

use std::ops::Range;

/// How counts are stored: integers (raw read counts) or floating point (already normalised).
///
/// Counts are held as `f64` in memory either way (every 32-bit integer is exact in an `f64`); the
/// type decides how they are written back (cooler's `int32` or `float64` `count` column) and printed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CountType {
    /// Whole numbers (cooler `int32`).
    Integer,
    /// Real numbers (cooler `float64`).
    Float,
}

/// A block of pixels in columnar layout, sorted by `(bin1, bin2)` with `bin1 <= bin2`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PixelBlock {
    /// Row bin ids (genome-wide).
    pub bin1: Vec<u64>,
    /// Column bin ids (genome-wide).
    pub bin2: Vec<u64>,
    /// Counts.
    pub count: Vec<f64>,
}

impl PixelBlock {
    /// An empty block with room for `capacity` pixels.
    pub fn with_capacity(capacity: usize) -> Self {
        PixelBlock {
            bin1: Vec::with_capacity(capacity),
            bin2: Vec::with_capacity(capacity),
            count: Vec::with_capacity(capacity),
        }
    }

    /// Number of pixels.
    pub fn len(&self) -> usize {
        self.count.len()
    }

    /// True when the block holds no pixel.
    pub fn is_empty(&self) -> bool {
        self.count.is_empty()
    }

    /// Append one pixel.
    pub fn push(&mut self, bin1: u64, bin2: u64, count: f64) {
        self.bin1.push(bin1);
        self.bin2.push(bin2);
        self.count.push(count);
    }

    /// Remove every pixel, keeping the allocations.
    pub fn clear(&mut self) {
        self.bin1.clear();
        self.bin2.clear();
        self.count.clear();
    }

    /// Keep only the pixels `(bin1, bin2, count)` for which `keep` is true, in order.
    pub fn retain(&mut self, keep: impl Fn(u64, u64, f64) -> bool) {
        let mut kept = 0;
        for k in 0..self.len() {
            if keep(self.bin1[k], self.bin2[k], self.count[k]) {
                self.bin1[kept] = self.bin1[k];
                self.bin2[kept] = self.bin2[k];
                self.count[kept] = self.count[k];
                kept += 1;
            }
        }
        self.bin1.truncate(kept);
        self.bin2.truncate(kept);
        self.count.truncate(kept);
    }

    /// Keep only the pixels of the upper triangle (`bin2 >= bin1`).
    pub fn retain_upper(&mut self) {
        self.retain(|bin1, bin2, _| bin2 >= bin1);
    }

    /// Keep only the pixels whose `bin2` lies in `cols`.
    pub fn retain_cols(&mut self, cols: &Range<u64>) {
        self.retain(|_, bin2, _| cols.contains(&bin2));
    }
}
