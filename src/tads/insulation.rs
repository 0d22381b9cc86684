//! The diamond insulation score (Crane et al. 2015, Nature) and insulating boundaries, exactly as
//! `cooltools.insulation` (cooltools 0.7.1, the peer) computes them.
//!
//! For a window of `w` bins, the diamond of bin `k` is the square of pixels `(i, j)` with
//! `k - w < i <= k <= j < k + w`, clipped to the view region, without the pixels closer to the
//! diagonal than `ignore_diags` (`j - i < ignore_diags`). Conventions and defaults, as the peer:
//!
//! - the diamond sum adds balanced values `count * w_i * w_j` (pixels touching a NaN-weight bin are
//!   left out) or raw counts when no weights are given (then no bin is bad);
//! - `n_valid_pixels` counts the diamond cells inside the region whose two bins are both good,
//!   whether the pixel is stored or not; the score is the sum over that count, divided by the
//!   NaN-median of the region's scores; zeros become NaN, then `log2`, and non-finite values NaN;
//! - with `min_dist_bad_bin > 0`, bins closer than that to a bad bin (the distance to a region
//!   edge counting as to a bad bin just outside it) get a NaN score and take no part in boundary
//!   calls (default 0: off);
//! - boundary strengths are the peak prominences ([`super::peaks`]) of `-log2 score` over the bins
//!   of each region whose `n_valid_pixels` is at least `min_frac_valid_pixels` (default 0.66)
//!   times the largest `n_valid_pixels` of the whole table for that window; `ignore_diags`
//!   defaults to 2;
//! - a bin is a boundary when its strength reaches the cutoff of the whole-genome strengths of
//!   the window ([`super::threshold`], Li by default).
//!
//! Computation: one streamed pass over the pixels serves every window. A pixel at distance
//! `d = j - i` (`ignore_diags <= d <= 2 (w - 1)`) lies in the diamonds of the contiguous centres
//! `max(i, j - w + 1) ..= min(i + w - 1, j)`, so it is added to a difference array at both ends
//! of that run; a compensated (Neumaier) prefix sum gives the diamond sums. Each slice of the
//! pass only holds the rows it touches. `n_valid_pixels` is the product of the good bins on each
//! side minus the excluded near-diagonal pairs, O(bins * ignore_diags^2).

use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::genome::View;
use crate::matrix::{PixelSlice, PixelSource};

use super::domains::Boundary;
use super::peaks::find_peak_prominence;
use super::threshold::Threshold;

/// Parameters of [`insulation`], defaults as `cooltools insulation`.
#[derive(Clone, Debug, PartialEq)]
pub struct InsulationParams {
    /// Diamond window sizes in bp, each a positive multiple of the bin size (no default).
    pub windows_bp: Vec<u64>,
    /// Diagonals left out of the diamonds (default 2).
    pub ignore_diags: usize,
    /// Fraction of the largest `n_valid_pixels` a bin needs to take part in boundary calls
    /// (default 0.66).
    pub min_frac_valid_pixels: f64,
    /// Bins closer than this to a bad bin get a NaN score (default 0: off).
    pub min_dist_bad_bin: usize,
    /// How strong a boundary must be (default Li).
    pub threshold: Threshold,
    /// Also return the raw diamond sums (`sum_counts`, `sum_balanced`).
    pub append_raw_scores: bool,
}

impl Default for InsulationParams {
    fn default() -> Self {
        InsulationParams {
            windows_bp: Vec::new(),
            ignore_diags: 2,
            min_frac_valid_pixels: 0.66,
            min_dist_bad_bin: 0,
            threshold: Threshold::Li,
            append_raw_scores: false,
        }
    }
}

impl InsulationParams {
    /// Check the values: at least one window, each positive; `min_frac_valid_pixels` in
    /// `0..=1`; a fixed threshold that is a number. [`insulation`] checks them first.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::tads::insulation::InsulationParams;
    ///
    /// let params = InsulationParams::new(vec![100_000]);
    /// assert!(params.check().is_ok());
    /// let bad = InsulationParams { min_frac_valid_pixels: 1.5, ..params };
    /// assert!(bad.check().unwrap_err().to_string().starts_with("min_frac_valid_pixels 1.5"));
    /// ```
    pub fn check(&self) -> Result<()> {
        if self.windows_bp.is_empty() {
            return Err(Error::parameter(
                "windows_bp",
                "[]",
                "expected at least one window",
            ));
        }
        if self.windows_bp.contains(&0) {
            return Err(Error::parameter(
                "windows_bp",
                0,
                "expected positive windows",
            ));
        }
        if !(0.0..=1.0).contains(&self.min_frac_valid_pixels) {
            return Err(Error::parameter(
                "min_frac_valid_pixels",
                self.min_frac_valid_pixels,
                "expected a fraction in 0..1",
            ));
        }
        if let Threshold::Value(v) = self.threshold {
            if v.is_nan() {
                return Err(Error::parameter(
                    "threshold",
                    v,
                    "expected a number, li or otsu",
                ));
            }
        }
        Ok(())
    }

    /// The defaults with these windows.
    pub fn new(windows_bp: Vec<u64>) -> Self {
        InsulationParams {
            windows_bp,
            ..Default::default()
        }
    }
}

/// The insulation columns of one window, one value per table row.
#[derive(Clone, Debug, PartialEq)]
pub struct InsulationTrack {
    /// Window in bp.
    pub window_bp: u64,
    /// Window in bins.
    pub window_bins: usize,
    /// `log2` of the median-normalised insulation score (NaN where undefined).
    pub log2_insulation_score: Vec<f64>,
    /// Number of diamond cells with two good bins.
    pub n_valid_pixels: Vec<f64>,
    /// Peak prominence of `-log2_insulation_score` at local minima, NaN elsewhere.
    pub boundary_strength: Vec<f64>,
    /// `boundary_strength >= cutoff`.
    pub is_boundary: Vec<bool>,
    /// The cutoff the threshold rule gave for this window.
    pub cutoff: f64,
    /// Diamond sums of raw counts (with `append_raw_scores`).
    pub sum_counts: Option<Vec<f64>>,
    /// Diamond sums of balanced values (with `append_raw_scores`; zeros without weights).
    pub sum_balanced: Option<Vec<f64>>,
}

/// The insulation table: one row per bin of each view region, in view order.
#[derive(Clone, Debug, PartialEq)]
pub struct InsulationTable {
    /// Genome-wide bin id of each row.
    pub bins: Vec<usize>,
    /// Index into `view.regions()` of each row.
    pub region: Vec<usize>,
    /// Whether the bin's weight is NaN (always false without weights).
    pub is_bad_bin: Vec<bool>,
    /// Distance of each row to the nearest bad bin of its region ([`dist_to_bad`]), when
    /// `min_dist_bad_bin > 0` (cooltools' `dist_bad_bin` column).
    pub dist_bad_bin: Option<Vec<usize>>,
    /// One track per window, in the order given.
    pub tracks: Vec<InsulationTrack>,
}

impl InsulationTable {
    /// Number of rows.
    pub fn n_rows(&self) -> usize {
        self.bins.len()
    }

    /// The boundaries of window `track` (rows with `is_boundary`), strength = boundary strength.
    pub fn boundaries(&self, track: usize) -> Vec<Boundary> {
        let t = &self.tracks[track];
        (0..self.bins.len())
            .filter(|&row| t.is_boundary[row])
            .map(|row| Boundary {
                bin: self.bins[row],
                strength: t.boundary_strength[row],
            })
            .collect()
    }

    /// The windows' columns after `chrom start end region is_bad_bin [dist_bad_bin]`, named and
    /// ordered as cooltools' `insulation` returns them: per window `log2_insulation_score_W`,
    /// `n_valid_pixels_W` (and `sum_counts_W`, `sum_balanced_W` when kept), then every
    /// `boundary_strength_W`, then every `is_boundary_W`.
    pub fn track_columns(&self) -> Vec<(String, TrackValues<'_>)> {
        let mut columns = Vec::new();
        for track in &self.tracks {
            let w = track.window_bp;
            columns.push((
                format!("log2_insulation_score_{w}"),
                TrackValues::Real(&track.log2_insulation_score),
            ));
            columns.push((
                format!("n_valid_pixels_{w}"),
                TrackValues::Real(&track.n_valid_pixels),
            ));
            if let (Some(counts), Some(balanced)) = (&track.sum_counts, &track.sum_balanced) {
                columns.push((format!("sum_counts_{w}"), TrackValues::Real(counts)));
                columns.push((format!("sum_balanced_{w}"), TrackValues::Real(balanced)));
            }
        }
        for track in &self.tracks {
            columns.push((
                format!("boundary_strength_{}", track.window_bp),
                TrackValues::Real(&track.boundary_strength),
            ));
        }
        for track in &self.tracks {
            columns.push((
                format!("is_boundary_{}", track.window_bp),
                TrackValues::Flag(&track.is_boundary),
            ));
        }
        columns
    }
}

/// One column of an insulation track ([`InsulationTable::track_columns`]).
#[derive(Clone, Copy, Debug)]
pub enum TrackValues<'a> {
    /// Real numbers (NaN for missing).
    Real(&'a [f64]),
    /// True / false.
    Flag(&'a [bool]),
}

/// Names of the view regions with fewer bins than `window_bins` (their diamonds are all
/// clipped), so a caller can warn or refuse.
pub fn regions_shorter_than(view: &View, window_bins: usize) -> Vec<&str> {
    view.regions()
        .iter()
        .filter(|r| r.n_bins() < window_bins)
        .map(|r| r.name.as_str())
        .collect()
}

/// Whether the window of `window_bins` bins (`window_bp`) fits the regions of `view`: an error
/// when it is longer than every region, or than any region of a view the user gave
/// (`explicit_view`: the regions were chosen, so a short one is a mistake); else a warning
/// naming the whole chromosomes shorter than it (their diamonds are truncated, as cooltools
/// computes them), or nothing.
///
/// # Examples
///
/// ```
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::tads::insulation::check_window_fits;
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 1_000), Chrom::new("chrM", 50)], 10)?;
/// let view = View::chromosomes(&bins);
/// let warning = check_window_fits(&view, 10, 100, false)?.unwrap();
/// assert!(warning.starts_with("chrM shorter than the 100 bp window"));
/// assert!(check_window_fits(&view, 10, 100, true).is_err());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn check_window_fits(
    view: &View,
    window_bins: usize,
    window_bp: u64,
    explicit_view: bool,
) -> Result<Option<String>> {
    let short = regions_shorter_than(view, window_bins);
    if short.is_empty() {
        return Ok(None);
    }
    let names = if short.len() <= 6 {
        short.join(", ")
    } else {
        format!("{}, ... ({} regions)", short[..6].join(", "), short.len())
    };
    if explicit_view || short.len() == view.len() {
        return Err(Error::Argument(format!(
            "region{} {names} shorter than the {window_bp} bp window ({window_bins} bins): use a smaller --window",
            if short.len() > 1 { "s" } else { "" },
        )));
    }
    Ok(Some(format!(
        "{names} shorter than the {window_bp} bp window: truncated diamonds (as cooltools)"
    )))
}

/// The window of the insulation and directionality callers when none is given: 10 bins
/// (`contactmap tads`' default; cooltools' insulation has none, TopDom's is
/// [`TopDomParams::default`](super::topdom::TopDomParams)'s 5).
pub const DEFAULT_WINDOW_BINS: usize = 10;

/// A window in bins: the one check of every window in bp (insulation, directionality, the
/// command line's --window); errors for a zero window, one that is not a multiple of the bin
/// size, or variable-size bins.
///
/// ```
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::tads::insulation::window_bins;
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 1_000_000)], 10_000).unwrap();
/// assert_eq!(window_bins(&bins, 50_000)?, 5);
/// assert!(window_bins(&bins, 15_000).is_err());
/// assert!(window_bins(&bins, 0).is_err());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn window_bins(bins: &BinTable, window_bp: u64) -> Result<usize> {
    let resolution = bins.resolution().ok_or_else(|| {
        Error::Unsupported(
            "the matrix has variable-size bins; windows need a fixed bin size".into(),
        )
    })?;
    if window_bp == 0 || resolution == 0 || !window_bp.is_multiple_of(resolution) {
        return Err(Error::Argument(format!(
            "window {window_bp} bp is not a positive multiple of the bin size {resolution} bp"
        )));
    }
    Ok((window_bp / resolution) as usize)
}

/// Checks the weights have one value per bin.
pub(super) fn check_weights(bins: &BinTable, weights: Option<&[f64]>) -> Result<()> {
    if let Some(w) = weights {
        if w.len() != bins.n_bins() {
            return Err(Error::Data(format!(
                "{} weights for {} bins",
                w.len(),
                bins.n_bins()
            )));
        }
    }
    Ok(())
}

/// Where each region's rows live in the accumulation arrays: region `r` owns rows
/// `offsets[r] .. offsets[r] + n_bins + pad` (the padding takes the difference-array entry one
/// past the region's last bin).
pub(super) struct Layout {
    pub starts: Vec<usize>,
    pub ends: Vec<usize>,
    pub offsets: Vec<usize>,
    /// First region holding each genome-wide bin (`u32::MAX`: none).
    first_region: Vec<u32>,
}

impl Layout {
    pub fn new(view: &View, n_bins: usize, pad: usize) -> Layout {
        let mut first_region = vec![u32::MAX; n_bins];
        let (mut starts, mut ends, mut offsets) = (Vec::new(), Vec::new(), Vec::new());
        let mut total = 0;
        for (index, region) in view.regions().iter().enumerate() {
            for slot in &mut first_region[region.bins.clone()] {
                if *slot == u32::MAX {
                    *slot = index as u32;
                }
            }
            starts.push(region.bins.start);
            ends.push(region.bins.end);
            offsets.push(total);
            total += region.bins.len() + pad;
        }
        Layout {
            starts,
            ends,
            offsets,
            first_region,
        }
    }

    /// Call `f(region, row_base)` for every region holding both bins `i <= j`, where the row of
    /// bin `k` of that region is `row_base + k`.
    #[inline]
    pub fn for_regions(&self, i: usize, j: usize, mut f: impl FnMut(usize, usize)) {
        let first = self.first_region[i];
        if first == u32::MAX {
            return;
        }
        let first = first as usize;
        for r in first..(first + 2).min(self.starts.len()) {
            if self.starts[r] <= i && j < self.ends[r] {
                f(r, self.offsets[r] - self.starts[r]);
            }
        }
    }
}

#[inline]
fn neumaier(sum: &mut f64, comp: &mut f64, x: f64) {
    let t = *sum + x;
    if sum.abs() >= x.abs() {
        *comp += (*sum - t) + x;
    } else {
        *comp += (x - t) + *sum;
    }
    *sum = t;
}

/// Compensated sums over a contiguous run of rows, `width` interleaved columns per row.
pub(super) struct Partial {
    lo: usize,
    width: usize,
    sum: Vec<f64>,
    comp: Vec<f64>,
}

impl Partial {
    pub fn new(width: usize) -> Partial {
        Partial {
            lo: 0,
            width,
            sum: Vec::new(),
            comp: Vec::new(),
        }
    }

    fn rows(&self) -> usize {
        self.sum.len() / self.width
    }

    /// Make rows `lo..hi` available.
    fn cover(&mut self, lo: usize, hi: usize) {
        if self.sum.is_empty() {
            self.lo = lo;
            self.sum = vec![0.0; (hi - lo) * self.width];
            self.comp = vec![0.0; (hi - lo) * self.width];
            return;
        }
        if lo < self.lo {
            let shift = (self.lo - lo) * self.width;
            let mut sum = vec![0.0; shift];
            sum.extend_from_slice(&self.sum);
            let mut comp = vec![0.0; shift];
            comp.extend_from_slice(&self.comp);
            self.sum = sum;
            self.comp = comp;
            self.lo = lo;
        }
        let end = self.lo + self.rows();
        if hi > end {
            let len = (hi - self.lo) * self.width;
            self.sum.resize(len, 0.0);
            self.comp.resize(len, 0.0);
        }
    }

    /// Prepare to add to rows in `lo..hi` (cheap when already covered).
    #[inline]
    pub fn reserve(&mut self, lo: usize, hi: usize) {
        if self.sum.is_empty() || lo < self.lo || hi > self.lo + self.rows() {
            // Grow ahead to avoid many small resizes.
            let hi = if self.sum.is_empty() {
                hi
            } else {
                hi.max(self.lo + 2 * self.rows())
            };
            self.cover(lo, hi);
        }
    }

    /// Add `x` to column `col` of `row` (covered by an earlier `reserve`).
    #[inline]
    pub fn add(&mut self, row: usize, col: usize, x: f64) {
        let at = (row - self.lo) * self.width + col;
        neumaier(&mut self.sum[at], &mut self.comp[at], x);
    }

    /// Add a later partial into this one.
    pub fn merge(mut self, other: Partial) -> Partial {
        if other.sum.is_empty() {
            return self;
        }
        if self.sum.is_empty() {
            return other;
        }
        self.cover(other.lo, other.lo + other.rows());
        let base = (other.lo - self.lo) * self.width;
        for (k, (&s, &c)) in other.sum.iter().zip(&other.comp).enumerate() {
            neumaier(&mut self.sum[base + k], &mut self.comp[base + k], s);
            self.comp[base + k] += c;
        }
        self
    }

    /// The compensated value at `row`, column `col` (0 outside the covered rows).
    pub fn value(&self, row: usize, col: usize) -> f64 {
        if self.sum.is_empty() || row < self.lo || row >= self.lo + self.rows() {
            return 0.0;
        }
        let at = (row - self.lo) * self.width + col;
        self.sum[at] + self.comp[at]
    }

    /// The raw (sum, compensation) pair at `row`, column `col`.
    fn pair(&self, row: usize, col: usize) -> (f64, f64) {
        if self.sum.is_empty() || row < self.lo || row >= self.lo + self.rows() {
            return (0.0, 0.0);
        }
        let at = (row - self.lo) * self.width + col;
        (self.sum[at], self.comp[at])
    }
}

/// Distance of each bin to the nearest bad bin, a region edge counting as a bad bin just
/// outside it (cooltools' `dist_to_mask`).
pub fn dist_to_bad(bad: &[bool]) -> Vec<usize> {
    let n = bad.len();
    let mut left = vec![0; n];
    let mut last: isize = -1;
    for k in 0..n {
        if bad[k] {
            last = k as isize;
        }
        left[k] = (k as isize - last) as usize;
    }
    let mut next = n;
    for k in (0..n).rev() {
        if bad[k] {
            next = k;
        }
        left[k] = left[k].min(next - k);
    }
    left
}

/// Number of diamond cells with two good bins for every bin of one region (cooltools'
/// `get_n_pixels`): good bins on the left times good bins on the right, minus the good pairs
/// closer to the diagonal than `ignore_diags`.
pub fn n_valid_pixels(good: &[bool], window: usize, ignore_diags: usize) -> Vec<f64> {
    let n = good.len();
    let mut prefix = vec![0usize; n + 1];
    for k in 0..n {
        prefix[k + 1] = prefix[k] + good[k] as usize;
    }
    (0..n)
        .map(|k| {
            if window == 0 {
                return 0.0;
            }
            let left = prefix[k + 1] - prefix[(k + 1).saturating_sub(window)];
            let right = prefix[(k + window).min(n)] - prefix[k];
            let mut pairs = left * right;
            for is in 0..ignore_diags.min(window).min(k + 1) {
                if !good[k - is] {
                    continue;
                }
                for js in 0..(ignore_diags - is).min(window) {
                    if k + js >= n {
                        break;
                    }
                    if good[k + js] {
                        pairs -= 1;
                    }
                }
            }
            pairs as f64
        })
        .collect()
}

/// numpy's `nanmedian` (mean of the two middle values for an even count; NaN when empty).
fn nanmedian(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| !x.is_nan()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

/// The insulation table of `source` over `view` for every window of `params`: balanced with
/// `weights` (multiplicative, NaN = bad bin) or raw counts when `weights` is `None`.
///
/// Errors: no window, a window that is zero or not a multiple of the bin size, variable-size
/// bins, weights of the wrong length.
///
/// # Examples
///
/// ```
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
/// use contactmap::tads::insulation::{insulation, InsulationParams};
/// use contactmap::tads::threshold::Threshold;
///
/// // four 25-bin domains on a distance decay, each denser than the one before: boundaries at
/// // bins 25, 50 and 75 (a map symmetric about its boundaries would give flat minima, two bins
/// // wide, which the peak finder does not call, as in cooltools)
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 100_000)], 1_000)?;
/// let mut builder = MatrixBuilder::new(bins.clone(), CountType::Float);
/// for i in 0..100u64 {
///     for j in i..100 {
///         let enrichment = if i / 25 == j / 25 { 2.0 + (i / 25) as f64 } else { 1.0 };
///         builder.push(i, j, enrichment * 100.0 / (j - i + 1) as f64)?;
///     }
/// }
/// let matrix = InMemory::new("domains".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// let view = View::chromosomes(&bins);
/// // every local minimum of the score is a boundary (a cutoff of 0)
/// let params = InsulationParams {
///     threshold: Threshold::Value(0.0),
///     ..InsulationParams::new(vec![5_000])
/// };
/// let table = insulation(&pixels, None, &view, &params)?;
/// assert_eq!(table.n_rows(), 100);
/// let track = &table.tracks[0];
/// assert_eq!(track.window_bins, 5);
/// let called: Vec<usize> = table.boundaries(0).iter().map(|b| b.bin).collect();
/// assert_eq!(called.len(), 3, "{called:?}");
/// for (bin, truth) in called.iter().zip([25, 50, 75]) {
///     assert!(truth - 1 <= *bin && *bin <= truth, "{called:?}");
///     // more insulated than the middle of a domain
///     assert!(track.log2_insulation_score[*bin] < track.log2_insulation_score[truth - 12]);
/// }
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn insulation<S: PixelSource>(
    source: &S,
    weights: Option<&[f64]>,
    view: &View,
    params: &InsulationParams,
) -> Result<InsulationTable> {
    let bins = source.bins();
    params.check()?;
    check_weights(bins, weights)?;
    let windows: Vec<usize> = params
        .windows_bp
        .iter()
        .map(|&w| window_bins(bins, w))
        .collect::<Result<_>>()?;
    let g = params.ignore_diags;
    let balanced = weights.is_some();
    let with_counts = !balanced || params.append_raw_scores;
    // Columns per window: balanced sum (with weights), then counts (when needed).
    let per_window = balanced as usize + with_counts as usize;
    let width = per_window * windows.len();
    let max_window = windows.iter().copied().max().unwrap_or(1);
    let max_dist = 2 * (max_window - 1);
    let layout = Layout::new(view, bins.n_bins(), 1);

    let fold = |mut part: Partial, slice: PixelSlice<'_>| {
        for p in 0..slice.len() {
            let i = slice.bin1[p] as usize;
            let j = slice.bin2[p] as usize;
            let d = j - i;
            if d < g || d > max_dist {
                continue;
            }
            let count = slice.count[p];
            let value = weights.map(|w| count * w[i] * w[j]);
            layout.for_regions(i, j, |_, base| {
                part.reserve(base + i, base + i + max_dist + 2);
                for (wi, &w) in windows.iter().enumerate() {
                    if d > 2 * (w - 1) {
                        continue;
                    }
                    let k_lo = i.max((j + 1).saturating_sub(w));
                    let k_hi = (i + w - 1).min(j);
                    let mut col = wi * per_window;
                    if let Some(v) = value {
                        if !v.is_nan() {
                            part.add(base + k_lo, col, v);
                            part.add(base + k_hi + 1, col, -v);
                        }
                        col += 1;
                    }
                    if with_counts {
                        part.add(base + k_lo, col, count);
                        part.add(base + k_hi + 1, col, -count);
                    }
                }
            });
        }
        part
    };
    let sums = source.pass(|| Partial::new(width), fold, Partial::merge)?;

    // Rows of the table.
    let mut table = InsulationTable {
        bins: Vec::new(),
        region: Vec::new(),
        is_bad_bin: Vec::new(),
        dist_bad_bin: None,
        tracks: Vec::new(),
    };
    for (r, region) in view.regions().iter().enumerate() {
        for bin in region.bins.clone() {
            table.bins.push(bin);
            table.region.push(r);
            table
                .is_bad_bin
                .push(weights.is_some_and(|w| w[bin].is_nan()));
        }
    }
    let n_rows = table.bins.len();
    let mut region_rows = Vec::with_capacity(view.len());
    let mut row = 0;
    for region in view.regions() {
        region_rows.push(row..row + region.n_bins());
        row += region.n_bins();
    }
    let dist: Vec<usize> = if params.min_dist_bad_bin > 0 {
        region_rows
            .iter()
            .flat_map(|rows| dist_to_bad(&table.is_bad_bin[rows.clone()]))
            .collect()
    } else {
        Vec::new()
    };

    for (wi, (&w, &window_bp)) in windows.iter().zip(&params.windows_bp).enumerate() {
        let mut score = vec![f64::NAN; n_rows];
        let mut n_valid = vec![0.0; n_rows];
        let mut sum_counts = vec![0.0; n_rows];
        let mut sum_balanced = vec![0.0; n_rows];
        for (r, rows) in region_rows.iter().enumerate() {
            let good: Vec<bool> = table.is_bad_bin[rows.clone()].iter().map(|b| !b).collect();
            let valid = n_valid_pixels(&good, w, g);
            n_valid[rows.clone()].copy_from_slice(&valid);
            let offset = layout.offsets[r];
            for col_in in 0..per_window {
                let col = wi * per_window + col_in;
                let (mut s, mut c) = (0.0, 0.0);
                for k in 0..rows.len() {
                    let (a, b) = sums.pair(offset + k, col);
                    neumaier(&mut s, &mut c, a);
                    neumaier(&mut s, &mut c, b);
                    let total = s + c;
                    if balanced && col_in == 0 {
                        sum_balanced[rows.start + k] = total;
                    } else {
                        sum_counts[rows.start + k] = total;
                    }
                }
            }
            let main = if balanced { &sum_balanced } else { &sum_counts };
            for k in rows.clone() {
                score[k] = main[k] / n_valid[k];
            }
            let median = nanmedian(&score[rows.clone()]);
            for k in rows.clone() {
                let mut v = score[k] / median;
                if v == 0.0 {
                    v = f64::NAN;
                }
                v = v.log2();
                if !v.is_finite() {
                    v = f64::NAN;
                }
                if params.min_dist_bad_bin > 0 && dist[k] < params.min_dist_bad_bin {
                    v = f64::NAN;
                }
                score[k] = v;
            }
        }

        // Boundaries: prominence of -score over the bins with enough valid pixels.
        let max_valid = n_valid.iter().copied().fold(f64::NAN, f64::max);
        let min_valid = max_valid * params.min_frac_valid_pixels;
        let mut strength = vec![f64::NAN; n_rows];
        for rows in &region_rows {
            let kept: Vec<usize> = rows
                .clone()
                .filter(|&k| {
                    n_valid[k] >= min_valid
                        && (params.min_dist_bad_bin == 0 || dist[k] >= params.min_dist_bad_bin)
                })
                .collect();
            let track: Vec<f64> = kept.iter().map(|&k| -score[k]).collect();
            for (pos, prom) in find_peak_prominence(&track) {
                strength[kept[pos]] = prom;
            }
        }
        let cutoff = params.threshold.cutoff(&strength);
        let is_boundary = strength.iter().map(|&s| s >= cutoff).collect();
        table.tracks.push(InsulationTrack {
            window_bp,
            window_bins: w,
            log2_insulation_score: score,
            n_valid_pixels: n_valid,
            boundary_strength: strength,
            is_boundary,
            cutoff,
            sum_counts: params.append_raw_scores.then_some(sum_counts),
            sum_balanced: params.append_raw_scores.then_some(sum_balanced),
        });
    }
    if params.min_dist_bad_bin > 0 {
        table.dist_bad_bin = Some(dist);
    }
    Ok(table)
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // index loops mirror the definitions being checked
pub(super) mod tests {
    use super::*;
    use crate::genome::Chrom;
    use crate::io::tables::Table;
    use crate::matrix::{CountType, PixelBlock, Pixels};
    use proptest::prelude::*;

    /// Dense naive diamonds, O(n w^2) per region: (sum balanced or raw, sum counts, n valid).
    fn naive(
        dense: &[Vec<f64>],
        weights: Option<&[f64]>,
        first: usize,
        n: usize,
        w: usize,
        g: usize,
    ) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let mut sums = vec![0.0; n];
        let mut counts = vec![0.0; n];
        let mut valid = vec![0.0; n];
        for k in 0..n {
            for a in (k + 1).saturating_sub(w)..=k {
                for b in k..(k + w).min(n) {
                    if b - a < g {
                        continue;
                    }
                    let (ga, gb) = (first + a, first + b);
                    let good = weights.is_none_or(|wt| !wt[ga].is_nan() && !wt[gb].is_nan());
                    if good {
                        valid[k] += 1.0;
                    }
                    let c = dense[ga][gb];
                    counts[k] += c;
                    match weights {
                        Some(wt) => {
                            let v = c * wt[ga] * wt[gb];
                            if !v.is_nan() {
                                sums[k] += v;
                            }
                        }
                        None => sums[k] += c,
                    }
                }
            }
        }
        (sums, counts, valid)
    }

    fn case() -> impl Strategy<Value = (Vec<u64>, Vec<Vec<f64>>, Vec<f64>, usize, usize)> {
        (
            proptest::collection::vec(1u64..25, 1..4),
            1usize..8,
            0usize..4,
            any::<u64>(),
        )
            .prop_map(|(chroms, w, g, seed)| {
                let n: usize = chroms.iter().sum::<u64>() as usize;
                let mut state = seed | 1;
                let mut next = || {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    (state >> 11) as f64 / (1u64 << 53) as f64
                };
                let mut dense = vec![vec![0.0; n]; n];
                for i in 0..n {
                    for j in i..n {
                        if next() < 0.7 {
                            dense[i][j] = (next() * 20.0).floor();
                        }
                    }
                }
                let weights: Vec<f64> = (0..n)
                    .map(|_| {
                        if next() < 0.15 {
                            f64::NAN
                        } else {
                            0.5 + next()
                        }
                    })
                    .collect();
                (chroms, dense, weights, w, g)
            })
    }

    fn pixels_of(chroms: &[u64], dense: &[Vec<f64>]) -> Pixels {
        let chroms: Vec<Chrom> = chroms
            .iter()
            .enumerate()
            .map(|(k, &len)| Chrom::new(format!("c{k}"), len * 10))
            .collect();
        let bins = BinTable::fixed(chroms, 10).unwrap();
        let mut block = PixelBlock::default();
        for (i, row) in dense.iter().enumerate() {
            for (j, &c) in row.iter().enumerate().skip(i) {
                if c != 0.0 {
                    block.push(i as u64, j as u64, c);
                }
            }
        }
        let mut pixels = Pixels::with_capacity(bins, CountType::Float, block.len()).unwrap();
        pixels.extend(&block).unwrap();
        pixels
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a.is_nan() && b.is_nan()) || a == b || (a - b).abs() <= tol * a.abs().max(b.abs())
    }

    proptest! {
        #[test]
        fn diamonds_match_a_dense_naive_computation(
            (chroms, dense, weights, w, g) in case(),
            balanced in any::<bool>(),
        ) {
            let pixels = pixels_of(&chroms, &dense);
            let view = View::chromosomes(pixels.bins());
            let wts = balanced.then_some(weights.as_slice());
            let mut params = InsulationParams::new(vec![10 * w as u64, 10 * (w as u64 + 2)]);
            params.ignore_diags = g;
            params.append_raw_scores = true;
            let table = insulation(&pixels, wts, &view, &params).unwrap();
            for (t, &win) in table.tracks.iter().zip(&[w, w + 2]) {
                for region in view.regions() {
                    let first = region.bins.start;
                    let n = region.n_bins();
                    let (sums, counts, valid) = naive(&dense, wts, first, n, win, g);
                    let main = if balanced { t.sum_balanced.as_ref() } else { t.sum_counts.as_ref() };
                    for k in 0..n {
                        prop_assert!(close(main.unwrap()[first + k], sums[k], 1e-12));
                        prop_assert!(close(t.sum_counts.as_ref().unwrap()[first + k], counts[k], 1e-12));
                        prop_assert_eq!(t.n_valid_pixels[first + k], valid[k]);
                    }
                    // The score from the naive sums.
                    let raw: Vec<f64> = (0..n).map(|k| sums[k] / valid[k]).collect();
                    let median = nanmedian(&raw);
                    for k in 0..n {
                        let mut v = raw[k] / median;
                        if v == 0.0 { v = f64::NAN; }
                        v = v.log2();
                        if !v.is_finite() { v = f64::NAN; }
                        prop_assert!(close(t.log2_insulation_score[first + k], v, 1e-9),
                            "{} vs {}", t.log2_insulation_score[first + k], v);
                    }
                }
            }
        }

        #[test]
        fn n_valid_pixels_matches_naive(
            good in proptest::collection::vec(proptest::bool::weighted(0.8), 0..40),
            w in 1usize..9,
            g in 0usize..12,
        ) {
            let n = good.len();
            let fast = n_valid_pixels(&good, w, g);
            for k in 0..n {
                let mut count = 0.0;
                for a in (k + 1).saturating_sub(w)..=k {
                    for b in k..(k + w).min(n) {
                        if b - a >= g && good[a] && good[b] {
                            count += 1.0;
                        }
                    }
                }
                prop_assert_eq!(fast[k], count, "k {}", k);
            }
        }
    }

    #[test]
    fn shared_bins_and_windows_are_checked() {
        let bins = BinTable::fixed(vec![Chrom::new("a", 1000)], 100).unwrap();
        let mut block = PixelBlock::default();
        for i in 0..10u64 {
            for j in i..10 {
                block.push(i, j, (1 + i + j) as f64);
            }
        }
        let mut pixels = Pixels::with_capacity(bins.clone(), CountType::Float, 0).unwrap();
        pixels.extend(&block).unwrap();
        let view = View::chromosomes(&bins);
        let message = |windows: Vec<u64>| {
            insulation(&pixels, None, &view, &InsulationParams::new(windows))
                .unwrap_err()
                .to_string()
        };
        assert!(message(vec![]).contains("at least one window"));
        let m = message(vec![200, 250]);
        assert!(m.contains("250") && m.contains("100 bp"), "{m}");
        assert!(message(vec![0]).contains("windows_bp 0"));
        assert_eq!(regions_shorter_than(&view, 11), vec!["a"]);
        assert!(regions_shorter_than(&view, 10).is_empty());
        // Two regions sharing bin 4: each gets its own rows, as cooltools' concatenated tables.
        use crate::genome::RegionSpec;
        let spec = |s, e| RegionSpec {
            chrom: "a".into(),
            start_bp: s,
            end_bp: e,
            name: None,
        };
        let view = View::new(&bins, &[spec(0, 450), spec(450, 1000)]).unwrap();
        let mut params = InsulationParams::new(vec![300]);
        params.ignore_diags = 0;
        params.append_raw_scores = true;
        let table = insulation(&pixels, None, &view, &params).unwrap();
        assert_eq!(table.bins, vec![0, 1, 2, 3, 4, 4, 5, 6, 7, 8, 9]);
        let sums = table.tracks[0].sum_counts.as_ref().unwrap();
        let dense: Vec<Vec<f64>> = (0..10)
            .map(|i| {
                (0..10)
                    .map(|j| if j >= i { (1 + i + j) as f64 } else { 0.0 })
                    .collect()
            })
            .collect();
        let (a, _, _) = naive(&dense, None, 0, 5, 3, 0);
        let (b, _, _) = naive(&dense, None, 4, 6, 3, 0);
        let expected: Vec<f64> = a.into_iter().chain(b).collect();
        assert_eq!(sums, &expected);
    }

    /// Read a reference table; NaN for `nan`, 1/0 for True/False.
    pub(crate) fn reference(path: &str) -> (Table, Vec<String>) {
        let table = Table::read(path).unwrap();
        let header = table.header().to_vec();
        (table, header)
    }

    pub(crate) fn column(table: &Table, name: &str) -> Vec<f64> {
        let c = table.column(name).unwrap();
        (0..table.len())
            .map(|row| match table.text(row, c) {
                "True" => 1.0,
                "False" => 0.0,
                _ => table.number(row, c).unwrap(),
            })
            .collect()
    }

    pub(crate) fn max_rel(ours: &[f64], theirs: &[f64]) -> f64 {
        assert_eq!(ours.len(), theirs.len());
        let mut worst: f64 = 0.0;
        for (k, (&a, &b)) in ours.iter().zip(theirs).enumerate() {
            assert_eq!(a.is_nan(), b.is_nan(), "row {k}: {a} vs {b}");
            if !a.is_nan() && a != b {
                worst = worst.max((a - b).abs() / a.abs().max(b.abs()));
            }
        }
        worst
    }

    fn parity(uri: &str, reference_path: &str, windows: &[u64]) -> Vec<Vec<f64>> {
        use crate::io::{OpenOptions, StreamedPixels, open_matrix};
        let reader = open_matrix(uri, &OpenOptions::default()).unwrap();
        let weights = reader.weights("weight").unwrap().values;
        let source = StreamedPixels::new(reader.as_ref());
        let view = View::chromosomes(source.bins());
        let params = InsulationParams::new(windows.to_vec());
        let table = insulation(&source, Some(&weights), &view, &params).unwrap();
        let (reference, _) = reference(reference_path);
        assert_eq!(reference.len(), table.n_rows());
        let bad = column(&reference, "is_bad_bin");
        for (k, &b) in bad.iter().enumerate() {
            assert_eq!(table.is_bad_bin[k], b == 1.0);
        }
        let mut all_strengths = Vec::new();
        for (t, w) in table.tracks.iter().zip(windows) {
            let score = max_rel(
                &t.log2_insulation_score,
                &column(&reference, &format!("log2_insulation_score_{w}")),
            );
            let strength = max_rel(
                &t.boundary_strength,
                &column(&reference, &format!("boundary_strength_{w}")),
            );
            assert_eq!(
                t.n_valid_pixels,
                column(&reference, &format!("n_valid_pixels_{w}"))
            );
            let flags: Vec<bool> = column(&reference, &format!("is_boundary_{w}"))
                .iter()
                .map(|&v| v == 1.0)
                .collect();
            assert_eq!(t.is_boundary, flags, "boundaries of window {w}");
            eprintln!("{uri} window {w}: max rel diff score {score:.3e} strength {strength:.3e}");
            assert!(score <= 1e-8 && strength <= 1e-8);
            all_strengths.push(t.boundary_strength.clone());
        }
        all_strengths
    }

    #[test]
    fn dm6_matches_cooltools() {
        let strengths = parity(
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/data/cooler_test_file.mcool::/resolutions/100000"
            ),
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/data/reference/tads/dm6_100kb.insulation.Li.tsv.gz"
            ),
            &[300000, 500000, 1000000],
        );
        // skimage's threshold_otsu and threshold_li on the reference strengths with NaNs dropped,
        // computed with /work/venv/bin/python (scikit-image 0.26):
        //   s = t[f"boundary_strength_{w}"].values; s = s[~np.isnan(s)]; threshold_otsu(s)
        let expected = [
            (0.9937648891872031, 0.7483915516347815),
            (0.7694331384709923, 0.5497343469491627),
            (0.5860808409389304, 0.3515858061853357),
        ];
        for (s, (otsu, li)) in strengths.iter().zip(expected) {
            let ours_otsu = Threshold::Otsu.cutoff(s);
            let ours_li = Threshold::Li.cutoff(s);
            eprintln!("dm6 otsu {ours_otsu} vs {otsu}, li {ours_li} vs {li}");
            assert!((ours_otsu - otsu).abs() <= 1e-9 * otsu);
            assert!((ours_li - li).abs() <= 1e-9 * li);
        }
    }

    #[test]
    fn yeast_matches_cooltools() {
        parity(
            concat!(env!("CARGO_MANIFEST_DIR"), "/data/yeast.10kb.cool"),
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/data/reference/tads/yeast_10kb.insulation.Li.tsv.gz"
            ),
            &[30000, 50000, 100000],
        );
    }
}
