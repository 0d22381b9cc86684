//! The passes over the pixels every method shares: the bins' layout in groups, the pixel filter,
//! marginals and matrix-vector products over a stream of pixel blocks.

use super::params::{BalanceParams, Scope};
use crate::error::Result;
use crate::genome::BinTable;
use crate::matrix::{PixelSlice, PixelSource};

/// Bins, chromosomes and groups, as the passes need them.
pub(super) struct Layout {
    pub(super) n_bins: usize,
    /// Chromosome of every bin.
    pub(super) chrom_of: Vec<u32>,
    /// One past the last bin of every bin's chromosome.
    pub(super) chrom_end: Vec<u32>,
    /// First bin of each chromosome, plus `n_bins`.
    pub(super) chrom_offsets: Vec<usize>,
    pub(super) scope: Scope,
}

impl Layout {
    pub(super) fn new(bins: &BinTable, scope: Scope) -> Self {
        let n_bins = bins.n_bins();
        let mut chrom_of = vec![0u32; n_bins];
        let mut chrom_end = vec![0u32; n_bins];
        for c in 0..bins.n_chroms() {
            let range = bins.chrom_bins(c);
            for b in range.clone() {
                chrom_of[b] = c as u32;
                chrom_end[b] = range.end as u32;
            }
        }
        Layout {
            n_bins,
            chrom_of,
            chrom_end,
            chrom_offsets: bins.chrom_offsets().to_vec(),
            scope,
        }
    }

    /// The groups balanced independently: one per chromosome with cis scope, else the genome.
    pub(super) fn groups(&self) -> Vec<std::ops::Range<usize>> {
        match self.scope {
            Scope::Cis => self.chrom_offsets.windows(2).map(|w| w[0]..w[1]).collect(),
            _ => std::iter::once(0..self.n_bins).collect(),
        }
    }

    /// Number of groups.
    pub(super) fn n_groups(&self) -> usize {
        match self.scope {
            Scope::Cis => self.chrom_offsets.len() - 1,
            _ => 1,
        }
    }

    /// Group of a bin.
    #[inline]
    pub(super) fn group_of(&self, bin: usize) -> usize {
        match self.scope {
            Scope::Cis => self.chrom_of[bin] as usize,
            _ => 0,
        }
    }
}

/// Which pixels a pass keeps.
#[derive(Clone, Copy)]
pub(super) struct PixelFilter<'a> {
    pub(super) ignore_diags: usize,
    pub(super) keep: Keep,
    /// One past the last bin of each bin's chromosome.
    pub(super) chrom_end: &'a [u32],
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Keep {
    All,
    Cis,
    Trans,
}

impl PixelFilter<'_> {
    /// The accepted columns `lo..hi` of row `bin1` (pixels are upper-triangle: `bin2 >= bin1`,
    /// and a row's cis columns are those before the end of its chromosome).
    #[inline]
    pub(super) fn columns(&self, bin1: usize) -> (usize, usize) {
        let lo = bin1.saturating_add(self.ignore_diags);
        let chrom_end = self.chrom_end[bin1] as usize;
        match self.keep {
            Keep::All => (lo, usize::MAX),
            Keep::Cis => (lo, chrom_end),
            Keep::Trans => (lo.max(chrom_end), usize::MAX),
        }
    }

    /// The positions of the accepted columns among a row's sorted `columns` (row `bin1`).
    #[inline]
    pub(super) fn accepted(&self, bin1: usize, columns: &[u32]) -> std::ops::Range<usize> {
        let (lo, hi) = self.columns(bin1);
        let first = columns.partition_point(|&j| (j as usize) < lo);
        let last = columns.partition_point(|&j| (j as usize) < hi);
        first..last.max(first)
    }
}

/// Per-bin sums accumulated over one slice of pixels: a dense window starting at the slice's first
/// row (which holds every row sum and the near-diagonal column sums), and a list of the column
/// contributions that fall outside it. A slice's partial result therefore stays small whatever
/// the number of bins; the list turns into a dense genome-wide vector when that is smaller.
#[derive(Clone, Debug, Default)]
pub(super) struct BinSums {
    pub(super) start: usize,
    pub(super) dense: Vec<f64>,
    pub(super) far_bins: Vec<u32>,
    pub(super) far_values: Vec<f64>,
    pub(super) n_bins: usize,
}

/// Bins past a slice's last row covered by its dense window.
pub(super) const WINDOW_EXTRA_BINS: usize = 4096;

impl BinSums {
    /// Sums for the pixels of `slice` (empty when the slice is).
    pub(super) fn for_slice(slice: &PixelSlice<'_>, n_bins: usize) -> Self {
        if slice.is_empty() {
            return BinSums::default();
        }
        let start = slice.bin1[0] as usize;
        let end = (slice.bin1[slice.len() - 1] as usize + 1 + WINDOW_EXTRA_BINS).min(n_bins);
        BinSums {
            start,
            dense: vec![0.0; end - start],
            far_bins: Vec::new(),
            far_values: Vec::new(),
            n_bins,
        }
    }

    pub(super) fn is_unset(&self) -> bool {
        self.n_bins == 0
    }

    pub(super) fn is_full(&self) -> bool {
        self.start == 0 && self.dense.len() == self.n_bins
    }

    #[inline]
    pub(super) fn add(&mut self, bin: usize, value: f64) {
        let k = bin.wrapping_sub(self.start);
        if k < self.dense.len() {
            self.dense[k] += value;
        } else {
            self.far_bins.push(bin as u32);
            self.far_values.push(value);
            if self.far_bins.len() * 3 > self.n_bins * 2 {
                self.make_full();
            }
        }
    }

    /// Add `vi * vector[j] * count` (or `vi * vector[j]` for each nonzero count with `BINARIZE`)
    /// to every column `j` of one row `i` (its columns sorted, none before `i`), and return the
    /// row's sum without its diagonal pixel. The hot loop of balancing: the columns inside the
    /// dense window go through four independent partial sums, so that the row's sum does not
    /// wait on one addition per pixel.
    #[inline]
    pub(super) fn add_row<const BINARIZE: bool, C: Copy + Into<f64>>(
        &mut self,
        i: usize,
        vi: f64,
        bin2: &[u32],
        count: &[C],
        vector: &[f64],
    ) -> f64 {
        let value = |j: usize, c: C| {
            let c: f64 = c.into();
            let c = if BINARIZE {
                f64::from(u8::from(c != 0.0))
            } else {
                c
            };
            vi * vector[j] * c
        };
        let mut skip = 0;
        if bin2.first().is_some_and(|&j| j as usize == i) {
            self.add(i, value(i, count[0]));
            skip = 1;
        }
        let (bin2, count) = (&bin2[skip..], &count[skip..]);
        // columns inside the dense window (all of them but the far ones at the row's end)
        let window_end = self.start + self.dense.len();
        // (most rows lie inside it whole: the binary search, which reads ahead out of order,
        // only when the row's last column does not)
        let inside = if bin2.last().is_none_or(|&j| (j as usize) < window_end) {
            bin2.len()
        } else {
            bin2.partition_point(|&j| (j as usize) < window_end)
        };
        let dense = &mut self.dense[..];
        let start = self.start;
        let mut sums = [0.0f64; 4];
        let mut chunks = bin2[..inside]
            .chunks_exact(4)
            .zip(count[..inside].chunks_exact(4));
        for (js, cs) in &mut chunks {
            for lane in 0..4 {
                let j = js[lane] as usize;
                let v = value(j, cs[lane]);
                sums[lane] += v;
                dense[j - start] += v;
            }
        }
        let done = inside - inside % 4;
        for (&j, &c) in bin2[done..inside].iter().zip(&count[done..inside]) {
            let v = value(j as usize, c);
            sums[0] += v;
            dense[j as usize - start] += v;
        }
        for (&j, &c) in bin2[inside..].iter().zip(&count[inside..]) {
            let v = value(j as usize, c);
            sums[1] += v;
            self.add(j as usize, v);
        }
        (sums[0] + sums[1]) + (sums[2] + sums[3])
    }

    /// Turn into a dense genome-wide vector.
    pub(super) fn make_full(&mut self) {
        if self.is_full() && self.far_bins.is_empty() {
            return;
        }
        let mut dense = vec![0.0; self.n_bins];
        dense[self.start..self.start + self.dense.len()].copy_from_slice(&self.dense);
        for (&b, &v) in self.far_bins.iter().zip(&self.far_values) {
            dense[b as usize] += v;
        }
        self.start = 0;
        self.dense = dense;
        self.far_bins = Vec::new();
        self.far_values = Vec::new();
    }

    /// Combine two partial results (the left one first, always in the same order).
    pub(super) fn merge(mut self, other: BinSums) -> BinSums {
        if other.is_unset() {
            return self;
        }
        if self.is_unset() {
            return other;
        }
        self.make_full();
        let window = &mut self.dense[other.start..other.start + other.dense.len()];
        for (a, b) in window.iter_mut().zip(&other.dense) {
            *a += b;
        }
        for (&b, &v) in other.far_bins.iter().zip(&other.far_values) {
            self.dense[b as usize] += v;
        }
        self
    }

    /// The genome-wide vector of sums.
    pub(super) fn into_vec(mut self, n_bins: usize) -> Vec<f64> {
        if self.is_unset() {
            return vec![0.0; n_bins];
        }
        self.make_full();
        self.dense
    }
}

/// cooler's `_marginalize` of `vector[i] * vector[j] * count` (or of 1 for each nonzero count with
/// `binarize`) over the accepted pixels: each value is added to both of its bins (once for
/// diagonal pixels). Rows whose `vector` entry is 0 contribute nothing and are skipped.
pub(super) fn marginals<S: PixelSource>(
    source: &S,
    n_bins: usize,
    filter: PixelFilter<'_>,
    vector: &[f64],
    binarize: bool,
) -> Result<Vec<f64>> {
    let sums = source.pass(
        BinSums::default,
        |mut acc: BinSums, slice: PixelSlice<'_>| {
            if acc.is_unset() {
                acc = BinSums::for_slice(&slice, n_bins);
            }
            for (i, run) in slice.rows() {
                let vi = vector[i];
                if vi != 0.0 {
                    let accepted = filter.accepted(i, &slice.bin2[run.clone()]);
                    let (first, last) = (run.start + accepted.start, run.start + accepted.end);
                    let (bin2, count) = (&slice.bin2[first..last], &slice.count[first..last]);
                    let row_sum = if binarize {
                        acc.add_row::<true, f64>(i, vi, bin2, count, vector)
                    } else {
                        acc.add_row::<false, f64>(i, vi, bin2, count, vector)
                    };
                    acc.add(i, row_sum);
                }
            }
            acc
        },
        BinSums::merge,
    )?;
    Ok(sums.into_vec(n_bins))
}

/// `(A u)` for the accepted pixels (the symmetric matrix, the diagonal once), and per group the
/// sums `sum(count * u_i * u_j)` and `sum(count [u_i > 0 and u_j > 0])` over the full symmetric
/// matrix (Juicer's sum factor).
pub(super) struct Product {
    pub(super) au: Vec<f64>,
    pub(super) norm_sums: Vec<f64>,
    pub(super) matrix_sums: Vec<f64>,
}

pub(super) fn product<S: PixelSource>(
    source: &S,
    layout: &Layout,
    filter: PixelFilter<'_>,
    u: &[f64],
) -> Result<Product> {
    let n_bins = layout.n_bins;
    let n_groups = layout.n_groups();
    type Acc = (BinSums, Vec<f64>, Vec<f64>);
    let init = || -> Acc { (BinSums::default(), Vec::new(), Vec::new()) };
    let (sums, norm_sums, matrix_sums) = source.pass(
        init,
        |mut acc: Acc, slice: PixelSlice<'_>| {
            if acc.0.is_unset() {
                acc.0 = BinSums::for_slice(&slice, n_bins);
                acc.1 = vec![0.0; n_groups];
                acc.2 = vec![0.0; n_groups];
            }
            let mut row = usize::MAX;
            let (mut lo, mut hi) = (0, 0);
            let (mut ui, mut row_sum, mut group) = (0.0, 0.0, 0);
            for ((&b1, &b2), &c) in slice.bin1.iter().zip(slice.bin2).zip(slice.count) {
                let (i, j) = (b1 as usize, b2 as usize);
                if i != row {
                    if row != usize::MAX {
                        acc.0.add(row, row_sum);
                    }
                    row = i;
                    row_sum = 0.0;
                    ui = u[i];
                    group = layout.group_of(i);
                    (lo, hi) = filter.columns(i);
                }
                if j < lo || j >= hi {
                    continue;
                }
                let uj = u[j];
                row_sum += c * uj;
                let factor = if i != j {
                    acc.0.add(j, c * ui);
                    2.0
                } else {
                    1.0
                };
                if ui > 0.0 && uj > 0.0 {
                    acc.1[group] += factor * c * ui * uj;
                    acc.2[group] += factor * c;
                }
            }
            if row != usize::MAX {
                acc.0.add(row, row_sum);
            }
            acc
        },
        |a: Acc, b: Acc| {
            let add = |mut x: Vec<f64>, y: Vec<f64>| {
                if x.is_empty() {
                    return y;
                }
                x.iter_mut().zip(&y).for_each(|(p, q)| *p += q);
                x
            };
            (a.0.merge(b.0), add(a.1, b.1), add(a.2, b.2))
        },
    )?;
    Ok(Product {
        au: sums.into_vec(n_bins),
        norm_sums: if norm_sums.is_empty() {
            vec![0.0; n_groups]
        } else {
            norm_sums
        },
        matrix_sums: if matrix_sums.is_empty() {
            vec![0.0; n_groups]
        } else {
            matrix_sums
        },
    })
}

/// A balancing problem that needs one matrix-vector product at a time (KR, SCALE): one per
/// group, all groups sharing each pass over the pixels.
pub(super) trait ProductGroup {
    /// Whether the group has its result.
    fn is_done(&self) -> bool;
    /// Put the vector the group needs multiplied into `u` (its bins; zero elsewhere).
    fn request(&self, u: &mut [f64]);
    /// Take the product (the group is number `group` of the layout).
    fn feed(&mut self, product: &Product, group: usize);
}

/// Step every group until all are done, one pass over the pixels per product.
pub(super) fn solve_groups<S: PixelSource, G: ProductGroup>(
    source: &S,
    layout: &Layout,
    filter: PixelFilter<'_>,
    groups: &mut [G],
) -> Result<()> {
    while groups.iter().any(|g| !g.is_done()) {
        let mut u = vec![0.0; layout.n_bins];
        for g in groups.iter() {
            g.request(&mut u);
        }
        let product = product(source, layout, filter, &u)?;
        for (index, g) in groups.iter_mut().enumerate() {
            if !g.is_done() {
                g.feed(&product, index);
            }
        }
    }
    Ok(())
}

/// The pixels every method balances (ICE, VC, KR, SCALE): the scope's, minus the ignored
/// diagonals.
pub(super) fn scope_filter<'a>(params: &BalanceParams, layout: &'a Layout) -> PixelFilter<'a> {
    PixelFilter {
        ignore_diags: params.ignore_diags.min(usize::MAX as u64) as usize,
        keep: match params.scope {
            Scope::GenomeWide => Keep::All,
            Scope::Cis => Keep::Cis,
            Scope::Trans => Keep::Trans,
        },
        chrom_end: &layout.chrom_end,
    }
}

/// Row sums of the matrix restricted to the unmasked bins.
pub(super) fn row_sums<S: PixelSource>(
    source: &S,
    layout: &Layout,
    filter: PixelFilter<'_>,
    masked: &[bool],
) -> Result<Vec<f64>> {
    let ones: Vec<f64> = masked.iter().map(|&m| if m { 0.0 } else { 1.0 }).collect();
    let mut sums = product(source, layout, filter, &ones)?.au;
    for (s, &m) in sums.iter_mut().zip(masked) {
        if m {
            *s = 0.0;
        }
    }
    Ok(sums)
}

/// Juicer's sum factor `sqrt(norm_sum / matrix_sum)`, or `NaN` when there is nothing to sum.
pub(super) fn sum_factor(norm_sum: f64, matrix_sum: f64) -> f64 {
    if matrix_sum > 0.0 && norm_sum > 0.0 {
        (norm_sum / matrix_sum).sqrt()
    } else {
        f64::NAN
    }
}
