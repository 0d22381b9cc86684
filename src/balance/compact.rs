//! The pixels ICE iterates over, copied once into compressed rows: only the pixels its filter
//! accepts, no row ids (each row's pixels are a range), and counts in 4 bytes when every count
//! is exactly a 32-bit float (integer counts below 2^24: every merged or sampled map of reads).
//! A pass then reads 8 bytes a pixel instead of 16, and does no filtering: ICE's 200 passes
//! are bound by memory bandwidth. The sums are those of [`marginals`](super::passes::marginals)
//! (the same products, the same order within a row; partial sums combined in a fixed order).

use rayon::prelude::*;

use super::passes::{BinSums, PixelFilter, WINDOW_EXTRA_BINS};
use crate::matrix::PixelSlice;

/// Pixels per parallel task of a pass (whole rows; fixed, so sums do not depend on threads).
const TASK_PIXELS: usize = 1 << 18;

/// Counts in 4 bytes when they all fit exactly, else in 8.
enum Counts {
    Single(Vec<f32>),
    Double(Vec<f64>),
}

/// The accepted pixels in compressed rows.
pub(super) struct CompactRows {
    n_bins: usize,
    /// Row `i`'s pixels are `row_ptr[i]..row_ptr[i + 1]`.
    row_ptr: Vec<usize>,
    cols: Vec<u32>,
    counts: Counts,
    /// Row ranges of the parallel tasks, and the end of each task's dense window of sums (its
    /// first row to its last column, at most `WINDOW_EXTRA_BINS` past its last row).
    tasks: Vec<(std::ops::Range<usize>, usize)>,
}

impl CompactRows {
    /// The pixels of `all` (sorted by `(bin1, bin2)`, upper triangle) that `filter` accepts.
    pub(super) fn new(all: PixelSlice<'_>, n_bins: usize, filter: PixelFilter<'_>) -> Self {
        let mut row_ptr = vec![0usize; n_bins + 1];
        let mut cols = Vec::with_capacity(all.len());
        let mut wide = Vec::with_capacity(all.len());
        for (i, run) in all.rows() {
            let accepted = filter.accepted(i, &all.bin2[run.clone()]);
            let (first, last) = (run.start + accepted.start, run.start + accepted.end);
            cols.extend_from_slice(&all.bin2[first..last]);
            wide.extend_from_slice(&all.count[first..last]);
            row_ptr[i + 1] = last - first;
        }
        for i in 0..n_bins {
            row_ptr[i + 1] += row_ptr[i];
        }
        let exact = wide.iter().all(|&c| f64::from(c as f32) == c);
        let counts = if exact {
            Counts::Single(wide.iter().map(|&c| c as f32).collect())
        } else {
            Counts::Double(wide)
        };
        let mut tasks = Vec::new();
        let (mut start, mut last_column) = (0, 0);
        for i in 0..n_bins {
            if row_ptr[i + 1] > row_ptr[i] {
                last_column = last_column.max(cols[row_ptr[i + 1] - 1] as usize);
            }
            if row_ptr[i + 1] - row_ptr[start] >= TASK_PIXELS || i + 1 == n_bins {
                let window_end = (last_column + 1).min(i + 1 + WINDOW_EXTRA_BINS).max(i + 1);
                tasks.push((start..i + 1, window_end));
                (start, last_column) = (i + 1, 0);
            }
        }
        CompactRows {
            n_bins,
            row_ptr,
            cols,
            counts,
            tasks,
        }
    }

    /// cooler's marginals of `vector[i] * vector[j] * count` over the accepted pixels, as
    /// [`marginals`](super::passes::marginals) computes them.
    pub(super) fn marginals(&self, vector: &[f64]) -> Vec<f64> {
        match &self.counts {
            Counts::Single(counts) => self.sums(counts, vector),
            Counts::Double(counts) => self.sums(counts, vector),
        }
    }

    fn sums<C: Copy + Into<f64> + Sync>(&self, counts: &[C], vector: &[f64]) -> Vec<f64> {
        let partial: Vec<BinSums> = self
            .tasks
            .par_iter()
            .map(|(rows, window_end)| {
                let mut acc = BinSums {
                    start: rows.start,
                    dense: vec![0.0; window_end - rows.start],
                    far_bins: Vec::new(),
                    far_values: Vec::new(),
                    n_bins: self.n_bins,
                };
                for i in rows.clone() {
                    let vi = vector[i];
                    let (a, b) = (self.row_ptr[i], self.row_ptr[i + 1]);
                    if vi == 0.0 || a == b {
                        continue;
                    }
                    let row_sum =
                        acc.add_row::<false, C>(i, vi, &self.cols[a..b], &counts[a..b], vector);
                    acc.add(i, row_sum);
                }
                acc
            })
            .collect();
        partial
            .into_iter()
            .fold(BinSums::default(), BinSums::merge)
            .into_vec(self.n_bins)
    }
}
