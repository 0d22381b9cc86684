//! HiCRep's stratum-adjusted correlation coefficient (SCC) of two maps on the same bins, as
//! hicrep 0.2.6 `hicrepSCC` computes it (Yang et al. 2017, Genome Research 27:1939; the Python
//! implementation of Lin et al.), and the choice of its smoothing as HiCRep's training does
//! (hicreppy 0.1.0 `h_train`).
//!
//! Per chromosome of `n` bins, with `n_diags = min(max_distance / bin size + 1, n)`:
//!
//! 1. the raw counts of the upper triangle, diagonals `1..n_diags` only (the main diagonal and
//!    farther pixels dropped), divided by the map's total (its `sum` attribute, as hicrep: no
//!    correlation depends on it, but the rounding of diagonals whose values are all equal does,
//!    and so does hicrep's SCC through them). With `downsample`, the map with more contacts on the
//!    chromosome (within those diagonals) is first resampled with replacement to the other's
//!    number (hicrep's `resample`; our random stream, seeded, not numpy's), and not divided;
//! 2. a 2D mean filter of half-width `h` (`meanFilterSparse`): each pixel of the upper triangle
//!    becomes the sum of the counts in the `(2h + 1)^2` window around it (zeros outside the
//!    matrix), divided by `nDim(i) * nDim(j)`, `nDim(i) = h + 1 + min(i, n - 1 - i, h)`;
//! 3. per diagonal `d` in `1..n_diags`, over the `N_d` pixels where either smoothed map is not
//!    zero: Pearson's `rho_d = (S12 - S1 S2 / N) / sqrt((S11 - S1^2 / N)(S22 - S2^2 / N))` and
//!    the weight `w_d = N_d (1 + 1 / N_d) / 12` (the variance of ranks, NaN below 2 pixels); NaN
//!    and infinite values become 0, and `SCC = sum(rho_d w_d) / sum(w_d)` (NaN when every weight
//!    is 0).
//!
//! The genome-wide SCC is the mean of the chromosomes' SCCs weighted by their lengths, NaN ones
//! left out (hicreppy's `genome_scc`; hicrep reports chromosomes only). Where hicrep stops on an
//! assertion (a chromosome without contacts in one map), the chromosome's SCC is NaN with a note.
//!
//! The smoothing streams row by row: a row's window sums along the row, then running sums down
//! each column of the `2h + 1` rows around it (exact for integer counts, so a smoothed pixel is
//! zero exactly where its window holds no contact). Rows are cut into pieces of [`PIECE_ROWS`]
//! computed in parallel, each summed into its own per-diagonal sums, added in order: the result
//! does not depend on the number of threads. Each piece is smoothed only as far from the
//! diagonal as the pixels of its rows (and the `h` rows around) reach plus `2h`: beyond, every
//! smoothed value is 0. Chromosomes are read [`SEGMENT_ROWS`] rows at a time (with `h` rows
//! around; small enough that the two maps' rows stay in cache until smoothed), the next segment,
//! of this chromosome or the next, read while the current one is smoothed, the two maps side by
//! side; `downsample` and the training read a chromosome whole (its draws span it).

use std::ops::Range;

use rayon::prelude::*;

use super::comparable::check_comparable;
use crate::compare::sample::{draw_with_replacement, draw_without_replacement};
use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::io::{MatrixReader, read_ahead};
use crate::numeric::reduceat_sum;
use crate::random::stream_rng;

/// Rows computed by one task.
pub const PIECE_ROWS: usize = 256;

/// Independent running sums along a row of window sums (whole counts).
const LANES: usize = 8;

/// Rows of a chromosome read at a time (512: at 10 kb and 5 Mb, about 3 MB of pixels per map;
/// segments of 4,096 rows took a fifth more time and three times the memory on big.cool).
pub const SEGMENT_ROWS: usize = 2 * PIECE_ROWS;

/// The largest distance compared by default, in bp (the HiCRep paper's, hicrep's help).
pub const DEFAULT_MAX_DISTANCE_BP: u64 = 5_000_000;

/// Largest h tried by the training by default (hicreppy `htrain --h_max`).
pub const DEFAULT_H_MAX: usize = 10;

/// Stream tags of the seed.
const TAG_DOWNSAMPLE: u64 = 0x4c_d0_5a;
const TAG_TRAINING: u64 = 0x4c_7a_1e;

/// How two maps are compared.
#[derive(Clone, Debug, PartialEq)]
pub struct SccParams {
    /// Half-width of the mean filter in bins (hicrep's `h`; 0 smooths nothing).
    pub h: usize,
    /// The largest distance compared, in bp (hicrep's `dBPMax`); `None`: whole chromosomes
    /// (hicrep's `-1`).
    pub max_distance_bp: Option<u64>,
    /// Resample the deeper map of each chromosome to the other's depth (hicrep's
    /// `bDownSample`).
    pub downsample: bool,
    /// Seed of the resampling.
    pub seed: u64,
}

impl Default for SccParams {
    fn default() -> Self {
        SccParams {
            h: 5,
            max_distance_bp: Some(DEFAULT_MAX_DISTANCE_BP),
            downsample: false,
            seed: 10,
        }
    }
}

/// The SCC of one chromosome.
#[derive(Clone, Debug, PartialEq)]
pub struct ChromScc {
    /// Chromosome name.
    pub chrom: String,
    /// Its length in bp (the genome-wide weight).
    pub length_bp: u64,
    /// The SCC (NaN when it cannot be computed: see `note`).
    pub scc: f64,
    /// Why the SCC is NaN, when it is.
    pub note: Option<String>,
}

impl ChromScc {
    /// Chromosome `c` of `bins`, its SCC not computed yet (NaN).
    fn unscored(bins: &BinTable, c: usize) -> ChromScc {
        let chrom = &bins.chroms()[c];
        ChromScc {
            chrom: chrom.name.clone(),
            length_bp: chrom.length_bp,
            scc: f64::NAN,
            note: None,
        }
    }
}

/// The SCC of two maps, per chromosome and genome-wide.
#[derive(Clone, Debug, PartialEq)]
pub struct Scc {
    /// Per chromosome, in the order asked for.
    pub chroms: Vec<ChromScc>,
    /// Length-weighted mean of the chromosomes' SCCs (NaN ones left out).
    pub genome_wide: f64,
}

/// The bin size that turns a distance into diagonals: the fixed bin size, or the median bin
/// length of variable bins (as hicrep).
fn resolution(bins: &BinTable) -> u64 {
    bins.resolution().unwrap_or_else(|| {
        let mut lengths: Vec<u64> = bins.iter().map(|b| b.end - b.start).collect();
        lengths.sort_unstable();
        // numpy's median of integers: the mean of the two middle values, truncated by int().
        let m = lengths.len();
        if m == 0 {
            1
        } else if m % 2 == 1 {
            lengths[m / 2]
        } else {
            (lengths[m / 2 - 1] + lengths[m / 2]) / 2
        }
    })
}

/// hicrep's `dMax`: the number of diagonals kept (`max_distance / bin size + 1`, all bins when
/// there is no limit); an error when it keeps no diagonal beyond the main one.
pub fn max_diagonals(bins: &BinTable, max_distance_bp: Option<u64>) -> Result<usize> {
    let Some(max) = max_distance_bp else {
        return Ok(bins.n_bins());
    };
    let size = resolution(bins);
    let d_max = (max / size) as usize + 1;
    if d_max <= 1 {
        return Err(Error::parameter(
            "max-distance",
            max,
            format!("at least one bin ({size} bp): no diagonal would be compared"),
        ));
    }
    Ok(d_max)
}

/// One chromosome's shape: `n` bins, diagonals `1..n_diags` compared (`0..n_diags` with
/// `main_diagonal`, for hicreppy's training), filter half-width `h`.
#[derive(Clone, Copy, Debug)]
struct Geometry {
    n: usize,
    n_diags: usize,
    h: usize,
    main_diagonal: bool,
}

/// One map's pixels of a chromosome on diagonals `1..n_diags`: rows `first..first + rows` of
/// the chromosome (bins from its first), each row's pixels as (diagonal, count), zero counts
/// dropped.
#[derive(Clone, Debug, Default)]
struct Band {
    first: usize,
    row_start: Vec<usize>,
    diagonal: Vec<u32>,
    count: Vec<f64>,
}

impl Band {
    /// Rows `rows` of the chromosome starting at bin `offset`.
    fn read(
        reader: &dyn MatrixReader,
        offset: usize,
        geometry: Geometry,
        rows: Range<usize>,
    ) -> Result<Band> {
        let mut band = Band {
            first: rows.start,
            row_start: vec![0],
            ..Band::default()
        };
        let end = offset + geometry.n;
        let first_diagonal = usize::from(!geometry.main_diagonal);
        // Pixels come sorted by (bin1, bin2): each row's band is one stretch of its pixels.
        reader.read_rows_owned(offset + rows.start..offset + rows.end, &mut |block| {
            let (bin1, bin2, count) = (&block.bin1, &block.bin2, &block.count);
            band.diagonal.reserve(block.len());
            band.count.reserve(block.len());
            let mut k = 0;
            while k < block.len() {
                let row = bin1[k];
                let row_end = k + bin1[k..].iter().take_while(|&&b| b == row).count();
                let i = row as usize;
                let local = i - offset;
                while band.first + band.row_start.len() - 1 <= local {
                    band.row_start.push(band.count.len());
                }
                // columns i + first_diagonal .. min(i + n_diags, chromosome end); a file that
                // stores both triangles hands its lower one over too, left out here
                let (low, high) = (i + first_diagonal, (i + geometry.n_diags).min(end));
                let row_bin2 = &bin2[k..row_end];
                let from = k + row_bin2.partition_point(|&j| (j as usize) < low);
                let to = k + row_bin2.partition_point(|&j| (j as usize) < high);
                let (columns, counts) = (&bin2[from..to], &count[from..to]);
                if counts.contains(&0.0) {
                    for (&j, &c) in columns.iter().zip(counts) {
                        if c != 0.0 {
                            band.diagonal.push((j as usize - i) as u32);
                            band.count.push(c);
                        }
                    }
                } else {
                    // the usual case (no stored zero): whole stretches, which vectorise
                    band.diagonal
                        .extend(columns.iter().map(|&j| (j as usize - i) as u32));
                    band.count.extend_from_slice(counts);
                }
                *band.row_start.last_mut().expect("one row at least") = band.count.len();
                k = row_end;
            }
            reader.recycle(block);
            Ok(())
        })?;
        while band.row_start.len() - 1 < rows.len() {
            band.row_start.push(band.count.len());
        }
        Ok(band)
    }

    /// The pixels of row `r` (chromosome bins), empty outside the band.
    fn row(&self, r: usize) -> (&[u32], &[f64]) {
        if r < self.first || r + 1 >= self.first + self.row_start.len() {
            return (&[], &[]);
        }
        let k = r - self.first;
        let span = self.row_start[k]..self.row_start[k + 1];
        (&self.diagonal[span.clone()], &self.count[span])
    }

    /// The farthest diagonal holding a pixel in rows `rows` (0 when none).
    fn farthest(&self, rows: Range<usize>) -> usize {
        let last = self.first + self.row_start.len() - 1;
        let (lo, hi) = (rows.start.max(self.first), rows.end.min(last));
        (lo..hi)
            .filter_map(|r| {
                let k = r - self.first;
                // each row's pixels come sorted by column: its last is its farthest
                (self.row_start[k + 1] > self.row_start[k])
                    .then(|| self.diagonal[self.row_start[k + 1] - 1] as usize)
            })
            .max()
            .unwrap_or(0)
    }

    fn sum(&self) -> f64 {
        self.count.iter().sum()
    }

    /// True when every count is a positive whole number (below 2^53): window sums of such
    /// counts are exact, and zero exactly where a window holds no pixel.
    fn whole_counts(&self) -> bool {
        self.count
            .iter()
            .all(|&c| c > 0.0 && c < 9_007_199_254_740_992.0 && (c as u64) as f64 == c)
    }

    /// A tenth of the band's contacts drawn without replacement (hicreppy's subsample).
    fn subsample(&self, rng: &mut impl rand::Rng) -> Band {
        let mut counts = self.count.clone();
        draw_without_replacement(&mut counts, (0.1 * self.sum()) as u64, rng);
        self.with_counts(&counts)
    }

    /// The band with `counts` instead of its counts (zero counts dropped).
    fn with_counts(&self, counts: &[f64]) -> Band {
        let mut band = Band {
            first: self.first,
            row_start: vec![0],
            ..Band::default()
        };
        for span in self.row_start.windows(2) {
            for (&d, &c) in self.diagonal[span[0]..span[1]]
                .iter()
                .zip(&counts[span[0]..span[1]])
            {
                if c != 0.0 {
                    band.diagonal.push(d);
                    band.count.push(c);
                }
            }
            band.row_start.push(band.count.len());
        }
        band
    }
}

/// The mean filter of one map, row by row (see the module documentation). With `TRACK`, the
/// numbers of pixels under each window sum are kept beside the sums, so that a window without a
/// pixel gives exactly 0 whatever the rounding of the sums; without it (a band of positive whole
/// counts, whose sums are exact) the sums alone say so.
struct Smoother<'a, const TRACK: bool> {
    band: &'a Band,
    geometry: Geometry,
    /// Row sums `R(r, e)`, `e` the offset from the diagonal in `1 - h ..= n_diags - 1 + h`, of
    /// the `2h + 2` latest rows (row `r` at slot `r mod (2h + 2)`), and their numbers of
    /// non-zero pixels.
    rows_sum: Vec<f64>,
    rows_nonzero: Vec<u32>,
    /// Column sums over the rows of the window, column `j` at slot `j mod columns_len`.
    columns_sum: Vec<f64>,
    columns_nonzero: Vec<u32>,
    /// The current row's pixels spread over `n_diags + 4h` places (scratch).
    spread_sum: Vec<f64>,
    spread_nonzero: Vec<u32>,
    /// The smoothed values of the current row at diagonals `0..n_diags` (0 unused).
    out: Vec<f64>,
    /// The current row.
    row: usize,
    /// Every count divided by this (the map's total, as hicrep; 1 when resampled).
    divisor: f64,
}

impl<'a, const TRACK: bool> Smoother<'a, TRACK> {
    fn width(g: Geometry) -> usize {
        g.n_diags - 1 + 2 * g.h
    }

    /// Ready to give row `first`.
    fn new(band: &'a Band, geometry: Geometry, first: usize, divisor: f64) -> Self {
        let g = geometry;
        let width = Self::width(g);
        let tracked = |len: usize| if TRACK { len } else { 0 };
        let mut smoother = Smoother {
            band,
            geometry,
            rows_sum: vec![0.0; (2 * g.h + 2) * width],
            rows_nonzero: vec![0; tracked((2 * g.h + 2) * width)],
            columns_sum: vec![0.0; g.n_diags + 4 * g.h + 2],
            columns_nonzero: vec![0; tracked(g.n_diags + 4 * g.h + 2)],
            // LANES - 1 places more: the lanes' last stretch runs past the row's end
            spread_sum: vec![0.0; g.n_diags + 4 * g.h + LANES - 1],
            spread_nonzero: vec![0; tracked(g.n_diags + 4 * g.h)],
            out: vec![0.0; g.n_diags],
            row: first,
            divisor,
        };
        for r in first.saturating_sub(g.h)..(first + g.h + 1).min(g.n) {
            smoother.add_row(r);
        }
        smoother.fill_out();
        smoother
    }

    /// Compute row `r`'s window sums along the row into its slot, and add them to the columns.
    fn add_row(&mut self, r: usize) {
        let h = self.geometry.h;
        let width = Self::width(self.geometry);
        // Diagonal d' at place d' + 2h.
        self.spread_sum.fill(0.0);
        let (diagonals, counts) = self.band.row(r);
        for (&d, &c) in diagonals.iter().zip(counts) {
            self.spread_sum[d as usize + 2 * h] = c;
        }
        // R(r, e) at index e + h - 1 = sum of diagonals e - h ..= e + h, places idx + 1 ..=
        // idx + 1 + 2h.
        let slot = (r % (2 * h + 2)) * width;
        let spread = &self.spread_sum;
        let out = &mut self.rows_sum[slot..slot + width];
        if TRACK {
            let mut sum: f64 = spread[1..=2 * h + 1].iter().sum();
            self.spread_nonzero.fill(0);
            for &d in diagonals {
                self.spread_nonzero[d as usize + 2 * h] = 1;
            }
            let nonzero_of = &self.spread_nonzero;
            let counts = &mut self.rows_nonzero[slot..slot + width];
            let mut nonzero: u32 = nonzero_of[1..=2 * h + 1].iter().sum();
            for idx in 0..width {
                if idx > 0 {
                    sum = sum + spread[idx + 1 + 2 * h] - spread[idx];
                    nonzero = nonzero + nonzero_of[idx + 1 + 2 * h] - nonzero_of[idx];
                }
                out[idx] = if nonzero == 0 { 0.0 } else { sum };
                counts[idx] = nonzero;
            }
        } else {
            // Whole counts: the running sums are exact in any order, so the row is cut into
            // LANES stretches summed side by side (independent chains of additions instead of
            // one).
            let stretch = width.div_ceil(LANES);
            let mut sums: [f64; LANES] = std::array::from_fn(|lane| {
                let start = lane * stretch;
                spread[start + 1..=start + 1 + 2 * h].iter().sum()
            });
            for t in 0..stretch {
                for (lane, sum) in sums.iter_mut().enumerate() {
                    let idx = lane * stretch + t;
                    if t > 0 {
                        *sum = *sum + spread[idx + 1 + 2 * h] - spread[idx];
                    }
                    if idx < width {
                        out[idx] = *sum;
                    }
                }
            }
        }
        self.add_to_columns(r, true);
    }

    /// Add row `r`'s window sums to the columns, or take them away.
    fn add_to_columns(&mut self, r: usize, add: bool) {
        let h = self.geometry.h;
        let width = Self::width(self.geometry);
        let slot = (r % (2 * h + 2)) * width;
        let len = self.columns_sum.len();
        // Column j = r + idx + 1 - h; columns before the first do not exist.
        let skip = h.saturating_sub(r + 1).min(width);
        let mut column = (r + skip + 1 - h) % len;
        // In runs that do not wrap around the ring; a row's window sum is 0 exactly where it
        // holds no pixel, so adding it everywhere changes nothing there (no branch).
        let mut idx = skip;
        while idx < width {
            let run = (width - idx).min(len - column);
            let sums = &self.rows_sum[slot + idx..slot + idx + run];
            let column_sums = &mut self.columns_sum[column..column + run];
            match (TRACK, add) {
                (false, true) => {
                    for (c, &s) in column_sums.iter_mut().zip(sums) {
                        *c += s;
                    }
                }
                (false, false) => {
                    for (c, &s) in column_sums.iter_mut().zip(sums) {
                        *c -= s;
                    }
                }
                (true, _) => {
                    let counts = &self.rows_nonzero[slot + idx..slot + idx + run];
                    let column_counts = &mut self.columns_nonzero[column..column + run];
                    for (k, (&s, &z)) in sums.iter().zip(counts).enumerate() {
                        if add {
                            column_sums[k] += s;
                            column_counts[k] += z;
                        } else {
                            let left = column_counts[k] - z;
                            column_counts[k] = left;
                            // no pixel left: exactly 0, whatever the rounding of the sums
                            column_sums[k] = if left == 0 { 0.0 } else { column_sums[k] - s };
                        }
                    }
                }
            }
            idx += run;
            column = (column + run) % len;
        }
    }

    /// The smoothed values of the current row.
    fn fill_out(&mut self) {
        let Geometry { n, n_diags, h, .. } = self.geometry;
        let i = self.row;
        let n_dim = |k: usize| (h + 1 + k.min(n - 1 - k).min(h)) as f64;
        let dim_i = n_dim(i);
        let scale = 1.0 / self.divisor;
        let len = self.columns_sum.len();
        self.out.fill(0.0);
        // Columns h ..= n - 1 - h have the full window: one divisor for all of them.
        let inner = dim_i * (2 * h + 1) as f64;
        // Diagonals 1.. up to the matrix's edge, in two runs of the column ring (no modulo).
        let last = n_diags.min(n - i);
        let mut d = 1;
        let mut column = (i + 1) % len;
        while d < last {
            let run = (last - d).min(len - column);
            let sums = &self.columns_sum[column..column + run];
            let out = &mut self.out[d..d + run];
            // count times 1 / total first, as hicrep (scipy divides so); a window without a
            // pixel gives 0
            let first = i + d;
            let interior = first >= h && first + run + h <= n;
            if TRACK {
                let nonzero = &self.columns_nonzero[column..column + run];
                for (k, ((o, &s), &z)) in out.iter_mut().zip(sums).zip(nonzero).enumerate() {
                    if z != 0 {
                        let den = if interior {
                            inner
                        } else {
                            dim_i * n_dim(first + k)
                        };
                        *o = s * scale / den;
                    }
                }
            } else if interior {
                for (o, &s) in out.iter_mut().zip(sums) {
                    *o = s * scale / inner;
                }
            } else {
                for (k, (o, &s)) in out.iter_mut().zip(sums).enumerate() {
                    *o = s * scale / (dim_i * n_dim(first + k));
                }
            }
            d += run;
            column = 0;
        }
    }

    /// Move to the next row.
    fn advance(&mut self) {
        let Geometry { n, h, .. } = self.geometry;
        let i = self.row;
        if i + h + 1 < n {
            self.add_row(i + h + 1);
        }
        if i >= h {
            self.add_to_columns(i - h, false);
        }
        self.row += 1;
        if self.row < n {
            self.fill_out();
        }
    }
}

/// Per-diagonal sums of two smoothed maps over the pixels where either is not zero.
#[derive(Clone, Debug)]
struct Strata {
    n: Vec<u64>,
    s1: Vec<f64>,
    s2: Vec<f64>,
    s11: Vec<f64>,
    s22: Vec<f64>,
    s12: Vec<f64>,
}

impl Strata {
    fn new(n_diags: usize) -> Strata {
        Strata {
            n: vec![0; n_diags],
            s1: vec![0.0; n_diags],
            s2: vec![0.0; n_diags],
            s11: vec![0.0; n_diags],
            s22: vec![0.0; n_diags],
            s12: vec![0.0; n_diags],
        }
    }

    /// Add one row of both smoothed maps (diagonals `1..`). A pixel where both are zero adds
    /// zeros to the sums (no change) and is not counted: no branch, so the loop vectorises.
    fn add_row(&mut self, x: &[f64], y: &[f64]) {
        let len = x.len().min(y.len()).min(self.n.len());
        let n = &mut self.n[1..len];
        let (s1, s2) = (&mut self.s1[1..len], &mut self.s2[1..len]);
        let (s11, s22, s12) = (
            &mut self.s11[1..len],
            &mut self.s22[1..len],
            &mut self.s12[1..len],
        );
        for (k, (&a, &b)) in x[1..len].iter().zip(&y[1..len]).enumerate() {
            n[k] += u64::from(a != 0.0 || b != 0.0);
            s1[k] += a;
            s2[k] += b;
            s11[k] += a * a;
            s22[k] += b * b;
            s12[k] += a * b;
        }
    }

    /// Add `other`'s sums (of as many diagonals or fewer: the others are zeros).
    fn merge(&mut self, other: &Strata) {
        for d in 0..other.n.len() {
            self.n[d] += other.n[d];
            self.s1[d] += other.s1[d];
            self.s2[d] += other.s2[d];
            self.s11[d] += other.s11[d];
            self.s22[d] += other.s22[d];
            self.s12[d] += other.s12[d];
        }
    }

    /// hicrep's `sccByDiag` from the sums.
    fn scc(&self) -> f64 {
        let finite_or_zero = |v: f64| if v.is_finite() { v } else { 0.0 };
        let (mut num, mut den) = (0.0, 0.0);
        for d in 1..self.n.len() {
            let n = self.n[d] as f64;
            let cov = self.s12[d] - self.s1[d] * self.s2[d] / n;
            let var1 = self.s11[d] - self.s1[d] * self.s1[d] / n;
            let var2 = self.s22[d] - self.s2[d] * self.s2[d] / n;
            let rho = finite_or_zero(cov / (var1 * var2).sqrt());
            let weight = if self.n[d] < 2 {
                0.0
            } else {
                finite_or_zero(n * ((1.0 + 1.0 / n) / 12.0))
            };
            num += rho * weight;
            den += weight;
        }
        num / den
    }
}

/// The per-diagonal sums of rows `rows` of two bands (each holding those rows and `h` around),
/// their counts divided by `divisors`.
fn strata(
    a: &Band,
    b: &Band,
    geometry: Geometry,
    rows: Range<usize>,
    divisors: [f64; 2],
) -> Strata {
    let first_piece = rows.start / PIECE_ROWS;
    let last_piece = rows.end.div_ceil(PIECE_ROWS);
    let whole = a.whole_counts() && b.whole_counts();
    let pieces: Vec<Strata> = (first_piece..last_piece)
        .into_par_iter()
        .map(|p| {
            let start = (p * PIECE_ROWS).max(rows.start);
            let end = ((p + 1) * PIECE_ROWS).min(rows.end);
            // A smoothed pixel's window spans diagonals d - 2h ..= d + 2h of the rows within h:
            // beyond the farthest pixel of those rows plus 2h every smoothed value is 0, which
            // adds nothing to the sums. Smooth up to there only (a band that stops short of the
            // largest distance costs what it holds).
            let around = start.saturating_sub(geometry.h)..end + geometry.h;
            let farthest = a.farthest(around.clone()).max(b.farthest(around));
            let piece = Geometry {
                n_diags: geometry.n_diags.min(farthest + 2 * geometry.h + 1),
                ..geometry
            };
            if whole {
                piece_strata::<false>(a, b, piece, start..end, divisors)
            } else {
                piece_strata::<true>(a, b, piece, start..end, divisors)
            }
        })
        .collect();
    let mut total = Strata::new(geometry.n_diags);
    for piece in &pieces {
        total.merge(piece);
    }
    total
}

/// The per-diagonal sums of rows `rows` (one piece), smoothed row by row.
fn piece_strata<const TRACK: bool>(
    a: &Band,
    b: &Band,
    geometry: Geometry,
    rows: Range<usize>,
    divisors: [f64; 2],
) -> Strata {
    let mut sums = Strata::new(geometry.n_diags);
    let mut x = Smoother::<TRACK>::new(a, geometry, rows.start, divisors[0]);
    let mut y = Smoother::<TRACK>::new(b, geometry, rows.start, divisors[1]);
    for i in rows.clone() {
        sums.add_row(&x.out, &y.out);
        if i + 1 < rows.end {
            x.advance();
            y.advance();
        }
    }
    sums
}

/// Without smoothing, hicrep's per-diagonal sums bit for bit: scipy sums each diagonal's
/// stored values as numpy's `add.reduceat` does ([`reduceat_sum`]), over the first map's values,
/// the second's, and their products where both have a pixel. (A diagonal whose values are all
/// equal has a variance of 0 only up to rounding, and hicrep's SCC depends on that rounding: so
/// the sums are made in its order.) Whole bands only.
fn unsmoothed_strata(a: &Band, b: &Band, geometry: Geometry, divisors: [f64; 2]) -> Strata {
    let n_diags = geometry.n_diags;
    // scipy divides a sparse matrix by a number as a product with its inverse
    let by_diagonal = |band: &Band, divisor: f64| {
        let scale = 1.0 / divisor;
        let mut lists: Vec<Vec<(u32, f64)>> = vec![Vec::new(); n_diags];
        for r in 0..geometry.n {
            let (diagonals, counts) = band.row(r);
            for (&d, &c) in diagonals.iter().zip(counts) {
                lists[d as usize].push((r as u32, c * scale));
            }
        }
        lists
    };
    let (xs, ys) = (by_diagonal(a, divisors[0]), by_diagonal(b, divisors[1]));
    let sums: Vec<[f64; 6]> = (0..n_diags)
        .into_par_iter()
        .map(|d| {
            let (x, y) = (&xs[d], &ys[d]);
            let values = |list: &[(u32, f64)], square: bool| -> Vec<f64> {
                list.iter()
                    .map(|&(_, v)| if square { v * v } else { v })
                    .collect()
            };
            let (mut i, mut j, mut union) = (0, 0, 0u64);
            let mut products = Vec::new();
            while i < x.len() || j < y.len() {
                union += 1;
                match (x.get(i), y.get(j)) {
                    (Some(p), Some(q)) if p.0 == q.0 => {
                        products.push(p.1 * q.1);
                        i += 1;
                        j += 1;
                    }
                    (Some(p), Some(q)) if p.0 < q.0 => i += 1,
                    (Some(_), None) => i += 1,
                    _ => j += 1,
                }
            }
            [
                union as f64,
                reduceat_sum(&values(x, false)),
                reduceat_sum(&values(y, false)),
                reduceat_sum(&values(x, true)),
                reduceat_sum(&values(y, true)),
                reduceat_sum(&products),
            ]
        })
        .collect();
    let mut strata = Strata::new(n_diags);
    for (d, s) in sums.iter().enumerate() {
        strata.n[d] = s[0] as u64;
        strata.s1[d] = s[1];
        strata.s2[d] = s[2];
        strata.s11[d] = s[3];
        strata.s22[d] = s[4];
        strata.s12[d] = s[5];
    }
    strata
}

/// The per-diagonal sums of two whole bands: smoothed row by row, or without smoothing in
/// hicrep's order.
fn band_strata(a: &Band, b: &Band, geometry: Geometry, divisors: [f64; 2]) -> Strata {
    if geometry.h == 0 {
        unsmoothed_strata(a, b, geometry, divisors)
    } else {
        strata(a, b, geometry, 0..geometry.n, divisors)
    }
}

/// The SCC of `a` and `b` (on the same bins: [`check_comparable`]) on chromosomes `chroms`
/// (ids into the bin table).
///
/// # Examples
///
/// The GM12878 map at 2 Mb against the same cells' subsampled pairs binned at 2 Mb: hicrep
/// 0.2.6 `hicrepSCC(h=1, dBPMax=20_000_000)` gives 0.983... on chr1 (the references of
/// `data/reference/hicrep/`).
///
/// ```
/// use contactmap::compare::hicrep::{scc, SccParams};
/// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
///
/// let a = open_matrix("data/hg19.GM12878-MboI.matrix.2000kb.cool", &OpenOptions::default())?;
/// let b = open_matrix("data/hg19.GM12878-MboI.matrix.2000kb.cool", &OpenOptions::default())?;
/// let params = SccParams { h: 1, max_distance_bp: Some(20_000_000), ..SccParams::default() };
/// let result = scc(a.as_ref(), b.as_ref(), &[0, 1], &params)?;
/// // a map against itself
/// assert!((result.chroms[0].scc - 1.0).abs() < 1e-12);
/// assert!((result.genome_wide - 1.0).abs() < 1e-12);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn scc(
    a: &dyn MatrixReader,
    b: &dyn MatrixReader,
    chroms: &[usize],
    params: &SccParams,
) -> Result<Scc> {
    check_comparable(a, b)?;
    let bins = a.bins();
    let d_max = max_diagonals(bins, params.max_distance_bp)?;
    let totals = if params.downsample {
        [1.0, 1.0]
    } else {
        [total_contacts(a)?, total_contacts(b)?]
    };
    // Per chromosome: its shape, and its sums once computed with whether each map was empty.
    let geometries: Vec<Geometry> = chroms
        .iter()
        .map(|&c| Geometry {
            n: bins.chrom_bins(c).len(),
            n_diags: d_max.min(bins.chrom_bins(c).len()),
            h: params.h,
            main_diagonal: false,
        })
        .collect();
    let mut computed: Vec<Option<(Strata, [bool; 2])>> = vec![None; chroms.len()];
    if params.downsample || params.h == 0 {
        // Whole chromosomes, where resampling or hicrep's unsmoothed sums need them.
        for (k, &c) in chroms.iter().enumerate() {
            let geometry = geometries[k];
            if geometry.n_diags < 2 {
                continue;
            }
            let offset = bins.chrom_bins(c).start;
            let whole = 0..geometry.n;
            let mut x = Band::read(a, offset, geometry, whole.clone())?;
            let mut y = Band::read(b, offset, geometry, whole)?;
            let empty = [&x, &y].map(|band| band.count.is_empty());
            let mut divisors = totals;
            if params.downsample && !empty.contains(&true) {
                divisors = [1.0, 1.0];
                let mut rng = stream_rng(params.seed, TAG_DOWNSAMPLE, c as u64);
                let (sa, sb) = (x.sum().round() as u64, y.sum().round() as u64);
                let (deeper, size) = if sa > sb { (&mut x, sb) } else { (&mut y, sa) };
                if sa != sb {
                    let mut counts = deeper.count.clone();
                    draw_with_replacement(&mut counts, size, &mut rng);
                    *deeper = deeper.with_counts(&counts);
                }
            }
            computed[k] = Some((band_strata(&x, &y, geometry, divisors), empty));
        }
    } else {
        // Segments of rows of every chromosome in turn, the next one (of this chromosome or
        // the next) read while the current one is smoothed, the two maps side by side.
        let segments = (0..chroms.len()).flat_map(|k| {
            let g = geometries[k];
            let n = if g.n_diags < 2 { 0 } else { g.n };
            (0..n)
                .step_by(SEGMENT_ROWS)
                .map(move |start| (k, start..(start + SEGMENT_ROWS).min(n)))
        });
        let read = |&(k, ref rows): &(usize, Range<usize>)| -> Result<(Band, Band)> {
            let (geometry, offset) = (geometries[k], bins.chrom_bins(chroms[k]).start);
            let around = rows.start.saturating_sub(params.h)..(rows.end + params.h).min(geometry.n);
            let (x, y) = rayon::join(
                || Band::read(a, offset, geometry, around.clone()),
                || Band::read(b, offset, geometry, around.clone()),
            );
            Ok((x?, y?))
        };
        read_ahead(segments, read, |(k, rows), (x, y)| {
            let piece = strata(&x, &y, geometries[k], rows, totals);
            let (sums, empty) = computed[k]
                .get_or_insert_with(|| (Strata::new(geometries[k].n_diags), [true, true]));
            sums.merge(&piece);
            empty[0] &= x.count.is_empty();
            empty[1] &= y.count.is_empty();
            Ok(())
        })?;
    }
    let mut out = Vec::with_capacity(chroms.len());
    for (k, &c) in chroms.iter().enumerate() {
        let mut result = ChromScc::unscored(bins, c);
        match &computed[k] {
            None => {
                result.note = Some("a chromosome of one bin: no diagonal to compare".into());
            }
            Some((_, empty)) if empty.contains(&true) => {
                let which = empty.iter().position(|&e| e).expect("one is empty");
                result.note = Some(format!(
                    "no contacts off the diagonal within the distance in {}",
                    [a, b][which].source()
                ));
            }
            Some((sums, _)) => {
                result.scc = sums.scc();
                if result.scc.is_nan() {
                    result.note = Some("no diagonal with two pixels or more".into());
                }
            }
        }
        out.push(result);
    }
    let genome_wide = length_weighted(&out);
    Ok(Scc {
        chroms: out,
        genome_wide,
    })
}

/// A map's total as hicrep divides by it: the file's `sum` attribute (cooler's info), else the
/// sum of its counts. The correlations do not depend on it, but the rounding of a diagonal whose
/// values are all equal does, and hicrep's result with it.
fn total_contacts(reader: &dyn MatrixReader) -> Result<f64> {
    let stored = reader
        .info()
        .attributes
        .iter()
        .find(|(key, _)| key == "sum")
        .and_then(|(_, value)| value.as_f64());
    match stored {
        Some(sum) if sum > 0.0 => Ok(sum),
        _ => Ok(reader.totals()?.1),
    }
}

/// How the smoothing `h` of [`compare_samples`] is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Smoothing {
    /// This half-width, in bins.
    Fixed(usize),
    /// HiCRep's training ([`train_h`]) on the first two samples, trying `h = 0 .. h_max - 1`.
    Trained {
        /// One more than the largest `h` tried.
        h_max: usize,
    },
}

/// The SCC of one pair of samples.
#[derive(Clone, Debug, PartialEq)]
pub struct PairScc {
    /// Index of the first sample.
    pub first: usize,
    /// Index of the second sample (`first < second`).
    pub second: usize,
    /// Per chromosome and genome-wide.
    pub scc: Scc,
}

/// The SCC of every pair of samples at one `h`.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleComparison {
    /// The parameters used (with the `h` chosen).
    pub params: SccParams,
    /// The training, when `h` was trained.
    pub training: Option<Training>,
    /// Pairs `(0, 1), (0, 2), ..., (1, 2), ...`.
    pub pairs: Vec<PairScc>,
}

/// The SCCs of samples two by two as a symmetric matrix (1 on the diagonal).
#[derive(Clone, Debug, PartialEq)]
pub struct SccTable {
    /// Sample names.
    pub names: Vec<String>,
    /// Row-major `n x n` SCCs.
    pub values: Vec<f64>,
}

impl SccTable {
    /// The matrix of pairs `(sample1, sample2, scc)` (rows of `contactmap hicrep`'s table for
    /// one chromosome): samples in the order they first appear; every pair of samples must
    /// appear once (either way round), else the reason.
    ///
    /// ```
    /// use contactmap::compare::hicrep::SccTable;
    ///
    /// let pair = |a: &str, b: &str, v: f64| (a.to_string(), b.to_string(), v);
    /// let rows = [pair("a", "b", 0.9), pair("a", "c", 0.5), pair("b", "c", f64::NAN)];
    /// let table = SccTable::from_pairs(&rows).unwrap();
    /// assert_eq!(table.names, ["a", "b", "c"]);
    /// assert_eq!(table.values[3], 0.9); // (b, a)
    /// // 1 - SCC, and 1 where the SCC is NaN
    /// assert_eq!(table.distances()[5], 1.0);
    /// assert!(SccTable::from_pairs(&rows[..2]).unwrap_err().contains("b and c"));
    /// ```
    pub fn from_pairs(rows: &[(String, String, f64)]) -> std::result::Result<SccTable, String> {
        let mut names: Vec<String> = Vec::new();
        let mut index = |name: &str| match names.iter().position(|n| n == name) {
            Some(k) => k,
            None => {
                names.push(name.to_string());
                names.len() - 1
            }
        };
        let pairs: Vec<(usize, usize, f64)> = rows
            .iter()
            .map(|(a, b, v)| (index(a), index(b), *v))
            .collect();
        let n = names.len();
        if n < 2 {
            return Err(format!(
                "{} sample(s) in the table: a comparison needs two or more",
                n
            ));
        }
        let mut values = vec![f64::NAN; n * n];
        let mut seen = vec![false; n * n];
        for k in 0..n {
            values[k * n + k] = 1.0;
        }
        for (a, b, v) in pairs {
            if a == b {
                return Err(format!("{} is compared with itself", names[a]));
            }
            if seen[a * n + b] {
                return Err(format!("{} and {} are compared twice", names[a], names[b]));
            }
            seen[a * n + b] = true;
            seen[b * n + a] = true;
            values[a * n + b] = v;
            values[b * n + a] = v;
        }
        for a in 0..n {
            for b in a + 1..n {
                if !seen[a * n + b] {
                    return Err(format!(
                        "no SCC for {} and {}: the table must hold every pair of its samples",
                        names[a], names[b]
                    ));
                }
            }
        }
        Ok(SccTable { names, values })
    }

    /// The distances `1 - SCC` (1 where the SCC is NaN; 0 on the diagonal), for clustering.
    pub fn distances(&self) -> Vec<f64> {
        let n = self.names.len();
        self.values
            .iter()
            .enumerate()
            .map(|(k, v)| match (k / n == k % n, v.is_nan()) {
                (true, _) => 0.0,
                (false, true) => 1.0,
                (false, false) => 1.0 - v,
            })
            .collect()
    }
}

/// The chromosome ids of `names` in `bins` (every chromosome, in order, when `names` is
/// empty); an unknown name is an error listing the chromosomes of `source`.
pub fn chrom_ids(bins: &BinTable, names: &[String], source: &str) -> Result<Vec<usize>> {
    if names.is_empty() {
        return Ok((0..bins.n_chroms()).collect());
    }
    names
        .iter()
        .map(|name| {
            bins.chrom_id(name).ok_or_else(|| {
                let known: Vec<&str> = bins.chroms().iter().map(|c| c.name.as_str()).collect();
                let hint = bins
                    .naming_hint(name)
                    .map(|h| format!(": {h}"))
                    .unwrap_or_default();
                Error::parameter(
                    "chroms",
                    name,
                    format!("chromosomes of {source} ({}){hint}", known.join(", ")),
                )
            })
        })
        .collect()
}

/// The SCC of every pair of `samples` (two or more maps on the same bins) on chromosomes
/// `chroms`, at one `h`: fixed, or trained on the first two samples (SCCs are comparable only
/// at one `h`). `params.h` is replaced by the `h` chosen.
///
/// # Examples
///
/// ```
/// use contactmap::compare::hicrep::{compare_samples, SccParams, Smoothing};
/// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
///
/// let open = || open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default());
/// let (a, b, c) = (open()?, open()?, open()?);
/// let samples: [&dyn MatrixReader; 3] = [a.as_ref(), b.as_ref(), c.as_ref()];
/// let params = SccParams { max_distance_bp: Some(50_000_000), ..SccParams::default() };
/// let result = compare_samples(&samples, &[0, 1], Smoothing::Fixed(1), &params)?;
/// assert_eq!(result.pairs.len(), 3);
/// assert_eq!((result.pairs[2].first, result.pairs[2].second), (1, 2));
/// // the same map three times: every SCC is 1
/// assert!(result.pairs.iter().all(|p| (p.scc.genome_wide - 1.0).abs() < 1e-12));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn compare_samples(
    samples: &[&dyn MatrixReader],
    chroms: &[usize],
    smoothing: Smoothing,
    params: &SccParams,
) -> Result<SampleComparison> {
    if samples.len() < 2 {
        return Err(Error::Argument(format!(
            "HiCRep compares two maps or more ({} given)",
            samples.len()
        )));
    }
    for other in &samples[1..] {
        check_comparable(samples[0], *other)?;
    }
    let (h, training) = match smoothing {
        Smoothing::Fixed(h) => (h, None),
        Smoothing::Trained { h_max } => {
            let trained = train_h(
                samples[0],
                samples[1],
                chroms,
                params.max_distance_bp,
                h_max,
                params.seed,
            )?;
            (trained.h, Some(trained))
        }
    };
    let params = SccParams {
        h,
        ..params.clone()
    };
    let mut pairs = Vec::new();
    for first in 0..samples.len() {
        for second in first + 1..samples.len() {
            let scc = scc(samples[first], samples[second], chroms, &params)?;
            pairs.push(PairScc { first, second, scc });
        }
    }
    Ok(SampleComparison {
        params,
        training,
        pairs,
    })
}

/// The mean of the chromosomes' SCCs weighted by their lengths, NaN ones left out.
fn length_weighted(chroms: &[ChromScc]) -> f64 {
    let mut scored = chroms.iter().filter(|c| !c.scc.is_nan());
    // one chromosome: its SCC exactly (x * w / w may differ from x in the last digit)
    if let (Some(only), None) = (scored.next(), scored.next()) {
        return only.scc;
    }
    let (mut num, mut den) = (0.0, 0.0);
    for c in chroms.iter().filter(|c| !c.scc.is_nan()) {
        num += c.scc * c.length_bp as f64;
        den += c.length_bp as f64;
    }
    if den == 0.0 { f64::NAN } else { num / den }
}

/// What the training of `h` saw: the genome-wide SCC of the subsamples at each `h` tried, and
/// the `h` chosen.
#[derive(Clone, Debug, PartialEq)]
pub struct Training {
    /// `(h, SCC)` for each `h` tried, in order.
    pub tried: Vec<(usize, f64)>,
    /// The chosen `h`.
    pub h: usize,
    /// The chromosomes used.
    pub chroms: Vec<String>,
    /// Whether the SCC levelled off (gained less than 0.01) within the range tried; `false`:
    /// the range ended first, and the chosen `h` is its end, not a plateau.
    pub levelled_off: bool,
}

/// Choose `h` as HiCRep's training does (hicreppy 0.1.0 `h_train`): for `h = 0, 1, ...` below
/// `h_max`, each chromosome of both maps (diagonals `0 ..= max_bins + h`, `max_bins = max
/// distance / bin size`) subsampled 10 times to 10% of its contacts without replacement, the
/// SCC of each subsample pair as hicreppy computes it ([`hicreppy_chrom_scc`]) averaged per chromosome
/// (NaN left out) and over chromosomes weighted by length; the first `h` whose SCC gains less
/// than 0.01 on the previous one stops the search, and the `h` before it is chosen (0 at least;
/// `h_max - 2` when none stops it, as hicreppy). Chromosomes shorter than the filter
/// (`2 h_max + 1` bins) or than the largest distance are left out, as hicreppy does (when that
/// leaves none, only the filter's limit is kept). The subsamples are drawn from `seed`
/// (hicreppy's are unseeded).
pub fn train_h(
    a: &dyn MatrixReader,
    b: &dyn MatrixReader,
    chroms: &[usize],
    max_distance_bp: Option<u64>,
    h_max: usize,
    seed: u64,
) -> Result<Training> {
    check_comparable(a, b)?;
    if h_max == 0 {
        return Err(Error::parameter(
            "h-max",
            h_max,
            "at least 1: the training tries h = 0 .. h-max - 1",
        ));
    }
    let bins = a.bins();
    max_diagonals(bins, max_distance_bp)?;
    let size = resolution(bins);
    let kernel = (2 * h_max as u64 + 1) * size;
    let long_enough = |min: u64| -> Vec<usize> {
        chroms
            .iter()
            .copied()
            .filter(|&c| bins.chroms()[c].length_bp >= min)
            .collect()
    };
    let mut used = long_enough(kernel.max(max_distance_bp.unwrap_or(0)));
    if used.is_empty() {
        used = long_enough(kernel);
    }
    if used.is_empty() {
        return Err(Error::parameter(
            "h-max",
            h_max,
            format!(
                "a filter that fits in a chromosome: every chromosome is shorter than {kernel} bp"
            ),
        ));
    }
    let mut tried = Vec::new();
    let mut previous = f64::NEG_INFINITY;
    let mut stop = None;
    for h in 0..h_max {
        let mut per_chrom = Vec::with_capacity(used.len());
        for &c in &used {
            let range = bins.chrom_bins(c);
            let n = range.len();
            let max_bins = max_distance_bp.map_or(n, |m| (m / size) as usize).min(n);
            let geometry = Geometry {
                n,
                n_diags: (max_bins + h + 1).min(n),
                h,
                main_diagonal: true,
            };
            let mut scc_of = ChromScc::unscored(bins, c);
            let x = Band::read(a, range.start, geometry, 0..n)?;
            let y = Band::read(b, range.start, geometry, 0..n)?;
            let samples: Vec<f64> = (0..10u64)
                .map(|s| {
                    let index = ((h as u64) << 40) | ((c as u64) << 8) | s;
                    let mut rng = stream_rng(seed, TAG_TRAINING, index);
                    let (sx, sy) = (x.subsample(&mut rng), y.subsample(&mut rng));
                    hicreppy_scc(&sx, &sy, geometry, max_bins)
                })
                .collect();
            let finite: Vec<f64> = samples.into_iter().filter(|v| !v.is_nan()).collect();
            if !finite.is_empty() {
                scc_of.scc = finite.iter().sum::<f64>() / finite.len() as f64;
            }
            per_chrom.push(scc_of);
        }
        let current = length_weighted(&per_chrom);
        tried.push((h, current));
        // As hicreppy: a NaN SCC never stops the search.
        if current - previous < 0.01 {
            stop = Some(h);
            break;
        }
        previous = current;
    }
    // hicreppy returns max(h - 1, 0) with h the last tried.
    let last = stop.unwrap_or(h_max - 1);
    Ok(Training {
        tried,
        levelled_off: stop.is_some(),
        h: last.saturating_sub(1),
        chroms: used
            .iter()
            .map(|&c| bins.chroms()[c].name.clone())
            .collect(),
    })
}

/// hicreppy 0.1.0's SCC of chromosome `chrom` of two maps (`get_scc` of the `smooth`ed
/// chromosomes trimmed to `max_distance / bin size + h` diagonals, whole, not subsampled): the
/// SCC that [`train_h`] computes on each subsample pair, given for checks against hicreppy.
pub fn hicreppy_chrom_scc(
    a: &dyn MatrixReader,
    b: &dyn MatrixReader,
    chrom: usize,
    max_distance_bp: u64,
    h: usize,
) -> Result<f64> {
    check_comparable(a, b)?;
    let bins = a.bins();
    let range = bins.chrom_bins(chrom);
    let n = range.len();
    let max_bins = ((max_distance_bp / resolution(bins)) as usize).min(n);
    let geometry = Geometry {
        n,
        n_diags: (max_bins + h + 1).min(n),
        h,
        main_diagonal: true,
    };
    let x = Band::read(a, range.start, geometry, 0..n)?;
    let y = Band::read(b, range.start, geometry, 0..n)?;
    Ok(hicreppy_scc(&x, &y, geometry, max_bins))
}

/// The SCC that hicreppy 0.1.0 trains h with (`smooth` then `get_scc`), on whole bands holding
/// diagonals `0 .. n_diags` (`max_bins + h` included): the mean filter is a valid convolution
/// divided by `(2h + 1)^2`, zero within `h` bins of the matrix's edges; per diagonal `d` in
/// `0 .. max_bins`, Pearson's correlation over all its `n - d` pixels (zeros too; NaN for a
/// constant diagonal, left out of the sum but not of the weights), weighted by `nk * var(ranks
/// / nk^2)` = `(nk^2 - 1) / (12 nk^3)`, `nk = n - d`, the weights normalised to sum to 1.
fn hicreppy_scc(a: &Band, b: &Band, geometry: Geometry, max_bins: usize) -> f64 {
    let Geometry { n, n_diags, h, .. } = geometry;
    let width = n_diags + 2 * h;
    // Row window sums R(t, e), e = u - t in -h ..= n_diags - 1 + h, at index e + h.
    let row_sums = |band: &Band| {
        let mut rows = vec![0.0f64; n * width];
        let mut dense = vec![0.0f64; n_diags];
        for t in 0..n {
            dense.fill(0.0);
            let (diagonals, counts) = band.row(t);
            for (&d, &c) in diagonals.iter().zip(counts) {
                dense[d as usize] = c;
            }
            for idx in 0..width {
                let e = idx as isize - h as isize;
                let lo = (e - h as isize).max(0);
                let hi = (e + h as isize).min(n_diags as isize - 1);
                if lo <= hi {
                    rows[t * width + idx] = dense[lo as usize..=hi as usize].iter().sum();
                }
            }
        }
        rows
    };
    let (ra, rb) = (row_sums(a), row_sums(b));
    let area = ((2 * h + 1) * (2 * h + 1)) as f64;
    let smoothed = |rows: &[f64], i: usize, d: usize| -> f64 {
        let j = i + d;
        if i < h || j < h || i + h >= n || j + h >= n {
            return 0.0;
        }
        // rows t = i - h ..= i + h at offset j - t = d + (i - t), index d + (i - t) + h
        let sum: f64 = (i - h..=i + h)
            .map(|t| rows[t * width + d + i + h - t])
            .sum();
        sum / area
    };
    let per_diagonal: Vec<(f64, f64)> = (0..max_bins.min(n))
        .into_par_iter()
        .map(|d| {
            let nk = n - d;
            let x: Vec<f64> = (0..nk).map(|i| smoothed(&ra, i, d)).collect();
            let y: Vec<f64> = (0..nk).map(|i| smoothed(&rb, i, d)).collect();
            let (mx, my) = (
                x.iter().sum::<f64>() / nk as f64,
                y.iter().sum::<f64>() / nk as f64,
            );
            let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
            for (u, v) in x.iter().zip(&y) {
                sxy += (u - mx) * (v - my);
                sxx += (u - mx) * (u - mx);
                syy += (v - my) * (v - my);
            }
            let corr = sxy / (sxx * syy).sqrt();
            let nk = nk as f64;
            let weight = nk * ((nk * nk - 1.0) / 12.0 / nk.powi(4));
            (corr, weight)
        })
        .collect();
    let total: f64 = per_diagonal.iter().map(|p| p.1).sum();
    per_diagonal
        .iter()
        .filter(|p| p.0.is_finite())
        .map(|p| p.0 * p.1 / total)
        .sum()
}

#[cfg(test)]
mod tests;
