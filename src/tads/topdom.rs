//! TopDom: domains from the local minima of a bin-level contact signal.
//!
//! Reference: Shin H, Shi Y, Dai C, Tjong H, Gong K, Alber F, Zhou XJ. "TopDom: an efficient and
//! deterministic method for identifying topological domains in genomes." Nucleic Acids Research
//! 44(7):e70 (2016). The semantics follow the reference R implementation (the `TopDom` package,
//! version 0.0.2 algorithm: `Which.Gap.Region2`, `Detect.Local.Extreme`, `Get.Pvalue`,
//! `Convert.Bin.To.Domain.TMP`), re-implemented here on a [`CisBand`].
//!
//! Method, for one region with window `w` (default 5 bins):
//!
//! 1. **binSignal** of bin `i`: the mean of the `w x w` "diamond" of pixels between the upstream
//!    bins `[i-w+1, i]` and the downstream bins `[i+1, i+w]`, both clipped at the region ends
//!    (so fewer pixels near the ends). The last bin of the region has no downstream bin: NaN.
//! 2. **Gap bins**: bins whose row sums to 0 over the bins `[i-w, i+w]` (TopDom's
//!    `Which.Gap.Region2`; masked bins, whose rows are 0, are gaps). Maximal stretches of
//!    non-gap bins spanning at least 4 bins (`end - start >= 3`) are *processed*; bins outside
//!    them are treated as gaps everywhere below, as TopDom does.
//! 3. **Local minima** of the binSignal in each processed stretch by TopDom's change-point
//!    detection: the signal is rescaled to unit mean absolute step (`Data.Norm`), change points
//!    are found greedily (`Change.Point`: a segment from the last change point grows while its
//!    length minus the summed distance of the inner points to the chord keeps increasing), and a
//!    change point lower than both neighbours, or the lowest point strictly between two change
//!    points when it is lower than both, is a local minimum. A stretch whose signal is constant
//!    has no minima (the R code stops with an error there).
//! 4. **Statistical filter** (default on, cutoff 0.05): each of the first `2w` off-diagonals of
//!    the region is z-scaled (mean and sample standard deviation over the whole diagonal, gap
//!    bins included, as R's `scale`; a constant diagonal gives NaN values, which are dropped).
//!    Within each processed stretch (pixels clipped to the stretch), the p-value of bin `i` is
//!    the one-sided Wilcoxon rank-sum test that the diamond values are *less* than the values of
//!    the upstream triangle (strict upper triangle of bins `[i-w, i]`) and the downstream
//!    triangle (strict upper triangle of `[i+1, i+w]`). As R's `wilcox.test(..., exact = FALSE)`
//!    (TopDom passes `exact = FALSE`, so never the exact distribution): the normal approximation
//!    with tie correction and continuity correction. Non-finite values are dropped; a test with
//!    an empty sample gives p = 1; the last bin of a stretch gets p = 1. Local minima with
//!    `p >= cutoff` are dropped.
//! 5. **Segments** (TopDom's `.domain` table, `Convert.Bin.To.Domain.TMP`): a segment starts at
//!    the first bin of every maximal run of gap bins (tag [`TopDomTag::Gap`]) and of every run of
//!    bins that are neither gap nor a kept minimum (tag [`TopDomTag::Domain`]); each segment
//!    extends to the start of the next, so a kept minimum is the *last* bin of the domain on its
//!    left (binSignal(i) measures the contacts across the edge between `i` and `i + 1`). With the
//!    filter, a domain segment all of whose bins have `p < cutoff` is re-tagged
//!    [`TopDomTag::Boundary`].
//! 6. **Boundaries**: the first bin of every segment that follows a kept minimum `m` (bin
//!    `m + 1`), with strength `-log10 p(m)` (NaN without the filter). Segment starts at the
//!    region start or right after a gap are not boundaries.
//!
//! Deviations from the R code, all in degenerate cases: runs are maximal contiguous runs (R's
//! `Which.process.region` may drop a lone last bin or duplicate a run), a constant signal gives
//! no minima instead of an error, and without the filter no domain is re-tagged as boundary.
//!
//! Conventions: all bin indices in the output are genome-wide (`band.first_bin + local`); per-bin
//! vectors are indexed by local bin. The band must hold at least `2w + 1` diagonals and the region
//! at least `2w` bins.

use super::band::CisBand;
use super::domains::{Boundary, Domain};
use crate::error::{Error, Result};
use statrs::distribution::{ContinuousCDF, Normal};

/// TopDom parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct TopDomParams {
    /// Window `w` in bins (default 5; the paper recommends 5 to 20).
    pub window_bins: usize,
    /// Drop local minima that fail the Wilcoxon test (default true).
    pub statistical_filter: bool,
    /// P-value cutoff of the filter (default 0.05): minima with `p >= cutoff` are dropped.
    pub pvalue_cutoff: f64,
}

impl TopDomParams {
    /// Check the values: a window of at least 1 bin; with the statistical filter, a p-value
    /// cutoff in `(0, 1]`. [`topdom`] checks them first.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::tads::topdom::TopDomParams;
    ///
    /// assert!(TopDomParams::default().check().is_ok());
    /// let bad = TopDomParams { window_bins: 0, ..TopDomParams::default() };
    /// assert_eq!(bad.check().unwrap_err().to_string(), "window_bins 0: expected at least 1 bin");
    /// ```
    pub fn check(&self) -> Result<()> {
        if self.window_bins == 0 {
            return Err(Error::parameter(
                "window_bins",
                0,
                "expected at least 1 bin",
            ));
        }
        if self.statistical_filter && !(self.pvalue_cutoff > 0.0 && self.pvalue_cutoff <= 1.0) {
            return Err(Error::parameter(
                "pvalue_cutoff",
                self.pvalue_cutoff,
                "expected a p-value in (0, 1]",
            ));
        }
        Ok(())
    }
}

impl Default for TopDomParams {
    fn default() -> Self {
        TopDomParams {
            window_bins: 5,
            statistical_filter: true,
            pvalue_cutoff: 0.05,
        }
    }
}

/// The tag of a TopDom segment (the `tag` column of TopDom's `.domain` file).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TopDomTag {
    /// A run of gap bins (empty rows, or a non-gap stretch too short to process).
    Gap,
    /// A domain.
    Domain,
    /// A domain segment whose bins all have significant p-values: a wide boundary region.
    Boundary,
}

/// TopDom's result for one region.
#[derive(Clone, Debug, PartialEq)]
pub struct TopDomRegion {
    /// Genome-wide index of the region's first bin.
    pub first_bin: usize,
    /// binSignal per local bin (mean contact frequency of the diamond; NaN for the last bin).
    pub bin_signal: Vec<f64>,
    /// Wilcoxon p-value per local bin (1 outside the processed stretches; NaN everywhere without
    /// the statistical filter).
    pub pvalue: Vec<f64>,
    /// Local minima found by change-point detection, per local bin, before the filter.
    pub is_local_min: Vec<bool>,
    /// Boundaries (genome-wide bins starting a segment after a kept minimum), sorted.
    pub boundaries: Vec<Boundary>,
    /// The segments tiling the region, in order, with genome-wide bins (`level` 0, `score` NaN).
    pub segments: Vec<(Domain, TopDomTag)>,
}

/// Run TopDom on one region's band.
///
/// Errors with [`Error::Argument`] when the window is 0, the band holds fewer than
/// `2 * window_bins + 1` diagonals, or the region has fewer than `2 * window_bins` bins.
///
/// # Examples
///
/// ```
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
/// use contactmap::tads::band::cis_bands;
/// use contactmap::tads::topdom::{topdom, TopDomParams, TopDomTag};
///
/// // four 25-bin domains on a distance decay: boundaries at bins 25, 50 and 75
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 100_000)], 1_000)?;
/// let mut builder = MatrixBuilder::new(bins.clone(), CountType::Float);
/// for i in 0..100u64 {
///     for j in i..100 {
///         let enrichment = if i / 25 == j / 25 { 4.0 } else { 1.0 };
///         builder.push(i, j, enrichment * 100.0 / (j - i + 1) as f64)?;
///     }
/// }
/// let matrix = InMemory::new("domains".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// let view = View::chromosomes(&bins);
/// let params = TopDomParams::default(); // window 5 bins
/// let bands = cis_bands(&pixels, None, &view, 2 * params.window_bins + 1)?;
/// let region = topdom(&bands[0], &params)?;
/// let called: Vec<usize> = region.boundaries.iter().map(|b| b.bin).collect();
/// assert_eq!(called, [25, 50, 75]);
/// let domains = region.segments.iter().filter(|(_, tag)| *tag == TopDomTag::Domain).count();
/// assert_eq!(domains, 4);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn topdom(band: &CisBand, params: &TopDomParams) -> Result<TopDomRegion> {
    params.check()?;
    let w = params.window_bins;
    let n = band.n_bins;
    if band.width < 2 * w + 1 {
        return Err(Error::Argument(format!(
            "TopDom: window {w} needs a band of at least {} diagonals, got {}",
            2 * w + 1,
            band.width
        )));
    }
    if n < 2 * w {
        return Err(Error::Argument(format!(
            "TopDom: region starting at bin {} has {n} bins, fewer than twice the window ({})",
            band.first_bin,
            2 * w
        )));
    }

    let bin_signal = bin_signal(band, w);

    // Gap bins (Which.Gap.Region2), then the processed stretches (Which.process.region, 4+ bins).
    let is_gap: Vec<bool> = (0..n)
        .map(|i| {
            let lo = i.saturating_sub(w);
            let hi = (i + w).min(n - 1);
            (lo..=hi).map(|j| band.get(i, j)).sum::<f64>() == 0.0
        })
        .collect();
    let stretches: Vec<(usize, usize)> = runs(&is_gap, false)
        .into_iter()
        .filter(|&(s, e)| e - s >= 3)
        .collect();
    let mut processed = vec![false; n];
    let mut is_local_min = vec![false; n];
    for &(s, e) in &stretches {
        processed[s..=e].iter_mut().for_each(|p| *p = true);
        let ext = local_extremes(&bin_signal[s..=e]);
        for (k, &x) in ext.iter().enumerate() {
            is_local_min[s + k] = x == -1;
        }
    }

    let mut pvalue = vec![
        if params.statistical_filter {
            1.0
        } else {
            f64::NAN
        };
        n
    ];
    let mut kept = is_local_min.clone();
    if params.statistical_filter {
        let scaled = ScaledDiagonals::new(band, 2 * w);
        for &(s, e) in &stretches {
            for (i, p) in pvalue.iter_mut().enumerate().take(e).skip(s) {
                *p = stretch_pvalue(&scaled, s, e, i, w);
            }
        }
        for (k, p) in kept.iter_mut().zip(&pvalue) {
            *k = *k && *p < params.pvalue_cutoff;
        }
    }

    // Segments (Convert.Bin.To.Domain.TMP): starts of gap runs and of "other" runs.
    let gap_like: Vec<bool> = processed.iter().map(|p| !p).collect();
    let mut starts: Vec<(usize, TopDomTag)> = Vec::new();
    for i in 0..n {
        let tag = if gap_like[i] {
            TopDomTag::Gap
        } else if kept[i] {
            continue;
        } else {
            TopDomTag::Domain
        };
        let new_run = i == 0
            || match tag {
                TopDomTag::Gap => !gap_like[i - 1],
                _ => gap_like[i - 1] || kept[i - 1],
            };
        if new_run {
            starts.push((i, tag));
        }
    }
    if starts.first().is_none_or(|&(s, _)| s != 0) {
        // Cannot happen (a minimum is never the first bin of a stretch), but keep the tiling.
        starts.insert(0, (0, TopDomTag::Domain));
    }
    let mut segments = Vec::with_capacity(starts.len());
    let mut boundaries = Vec::new();
    for (k, &(s, mut tag)) in starts.iter().enumerate() {
        let e = starts.get(k + 1).map_or(n, |&(next, _)| next);
        if tag == TopDomTag::Domain
            && params.statistical_filter
            && pvalue[s..e].iter().all(|&p| p < params.pvalue_cutoff)
        {
            tag = TopDomTag::Boundary;
        }
        segments.push((
            Domain {
                start_bin: band.first_bin + s,
                end_bin: band.first_bin + e,
                level: 0,
                score: f64::NAN,
            },
            tag,
        ));
        if s > 0 && kept[s - 1] {
            boundaries.push(Boundary {
                bin: band.first_bin + s,
                strength: -pvalue[s - 1].log10(),
            });
        }
    }

    Ok(TopDomRegion {
        first_bin: band.first_bin,
        bin_signal,
        pvalue,
        is_local_min,
        boundaries,
        segments,
    })
}

/// binSignal: mean of the diamond `[i-w+1, i] x [i+1, i+w]`, clipped; NaN for the last bin.
fn bin_signal(band: &CisBand, w: usize) -> Vec<f64> {
    let n = band.n_bins;
    (0..n)
        .map(|i| {
            if i + 1 >= n {
                return f64::NAN;
            }
            let lo = (i + 1).saturating_sub(w);
            let hi = (i + w).min(n - 1);
            let mut sum = 0.0;
            for r in lo..=i {
                for c in i + 1..=hi {
                    sum += band.get(r, c);
                }
            }
            sum / ((i + 1 - lo) * (hi - i)) as f64
        })
        .collect()
}

/// Maximal runs `(start, end)` (inclusive) of entries equal to `value`.
fn runs(flags: &[bool], value: bool) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, &f) in flags.iter().enumerate() {
        match (f == value, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                out.push((s, i - 1));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, flags.len() - 1));
    }
    out
}

/// TopDom's `Detect.Local.Extreme`: -1 at local minima, +1 at local maxima, 0 elsewhere.
fn local_extremes(signal: &[f64]) -> Vec<i8> {
    let n = signal.len();
    let mut ret = vec![0i8; n];
    if n == 0 {
        return ret;
    }
    let x: Vec<f64> = signal
        .iter()
        .map(|&v| if v.is_nan() { 0.0 } else { v })
        .collect();
    if n <= 3 {
        ret[first_arg(&x, |a, b| a < b)] = -1;
        ret[first_arg(&x, |a, b| a > b)] = 1;
        return ret;
    }
    // Data.Norm: unit mean absolute step (x positions are already unit-spaced).
    let mean_step = x.windows(2).map(|p| (p[1] - p[0]).abs()).sum::<f64>() / (n - 1) as f64;
    let scale = 1.0 / mean_step;
    if !scale.is_finite() {
        return ret;
    }
    let mut y = vec![x[0]; n];
    for i in 1..n {
        y[i] = y[i - 1] + (x[i] - x[i - 1]) * scale;
    }
    let cp = change_points(&y);
    if cp.len() <= 2 || cp.len() == n {
        return ret;
    }
    for k in 1..cp.len() - 1 {
        let c = cp[k];
        if y[c] >= y[c - 1] && y[c] >= y[c + 1] {
            ret[c] = 1;
        } else if y[c] < y[c - 1] && y[c] < y[c + 1] {
            ret[c] = -1;
        }
        let p = cp[k - 1];
        let seg = &y[p..=c];
        let min_val = y[p].min(y[c]);
        let max_val = y[p].max(y[c]);
        let imin = first_arg(seg, |a, b| a < b);
        if seg[imin] < min_val {
            ret[p + imin] = -1;
        }
        let imax = first_arg(seg, |a, b| a > b);
        if seg[imax] > max_val {
            ret[p + imax] = 1;
        }
    }
    ret
}

/// Index of the first extreme element (`better(a, b)`: a beats b strictly).
fn first_arg(x: &[f64], better: impl Fn(f64, f64) -> bool) -> usize {
    let mut best = 0;
    for (i, &v) in x.iter().enumerate() {
        if better(v, x[best]) {
            best = i;
        }
    }
    best
}

/// TopDom's `Change.Point` on points `(k, y[k])`: indices of the change points, first and last
/// included.
fn change_points(y: &[f64]) -> Vec<usize> {
    let n = y.len();
    let mut cp = vec![0];
    let mut fv = vec![f64::NAN; n];
    fv[0] = 0.0;
    let mut i = 0;
    while i + 1 < n {
        let mut j = i + 1;
        let (xi, yi) = (i as f64, y[i]);
        fv[j] = ((j as f64 - xi).powi(2) + (y[j] - yi).powi(2)).sqrt();
        while j + 1 < n {
            j += 1;
            let (xj, yj) = (j as f64, y[j]);
            let dist = ((xj - xi).powi(2) + (yj - yi).powi(2)).sqrt();
            let err: f64 = (i + 1..j)
                .map(|k| ((yj - yi) * k as f64 - (xj - xi) * y[k] - xi * yj + xj * yi).abs())
                .sum::<f64>()
                / dist;
            fv[j] = dist - err;
            if fv[j].is_nan() || fv[j - 1].is_nan() || fv[j] < fv[j - 1] {
                j -= 1;
                cp.push(j);
                break;
            }
        }
        i = j;
    }
    cp.push(n - 1);
    cp
}

/// The first `max_d` off-diagonals of a band, each z-scaled (R's `scale`: sample sd).
struct ScaledDiagonals {
    diags: Vec<Vec<f64>>,
}

impl ScaledDiagonals {
    fn new(band: &CisBand, max_d: usize) -> Self {
        let n = band.n_bins;
        let mut diags = vec![Vec::new()];
        for d in 1..=max_d {
            let mut v: Vec<f64> = (0..n.saturating_sub(d))
                .map(|k| band.get(k, k + d))
                .collect();
            let m = v.len();
            if m > 0 {
                let mean = v.iter().sum::<f64>() / m as f64;
                let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (m as f64 - 1.0);
                let sd = var.sqrt();
                for x in &mut v {
                    // sd 0 or undefined gives NaN (or +-inf), dropped by the test.
                    *x = (*x - mean) / sd;
                }
            }
            diags.push(v);
        }
        ScaledDiagonals { diags }
    }

    /// Scaled value at local bins `a < b`, `b - a <= max_d`.
    fn get(&self, a: usize, b: usize) -> f64 {
        self.diags[b - a][a]
    }
}

/// TopDom's `Get.Pvalue` for bin `i` of the stretch `[s, e]`.
fn stretch_pvalue(scaled: &ScaledDiagonals, s: usize, e: usize, i: usize, w: usize) -> f64 {
    let mut diamond = Vec::with_capacity(w * w);
    let lo = i.saturating_sub(w - 1).max(s);
    let hi = (i + w).min(e);
    for r in lo..=i {
        for c in i + 1..=hi {
            diamond.push(scaled.get(r, c));
        }
    }
    let mut within = Vec::with_capacity(w * (w + 1));
    let up_lo = i.saturating_sub(w).max(s);
    for a in up_lo..=i {
        for b in a + 1..=i {
            within.push(scaled.get(a, b));
        }
    }
    for a in i + 1..=hi {
        for b in a + 1..=hi {
            within.push(scaled.get(a, b));
        }
    }
    diamond.retain(|v| v.is_finite());
    within.retain(|v| v.is_finite());
    let p = rank_sum_less(&diamond, &within);
    if p.is_nan() { 1.0 } else { p }
}

/// One-sided ("less": `x` tends to be smaller than `y`) Wilcoxon rank-sum p-value, as R's
/// `wilcox.test(x, y, alternative = "less", exact = FALSE, correct = TRUE)`: the normal
/// approximation of `W = R_x - n_x (n_x + 1) / 2` with tie-corrected variance and a continuity
/// correction of 0.5. NaN when a sample is empty (R stops with an error there).
pub(crate) fn rank_sum_less(x: &[f64], y: &[f64]) -> f64 {
    let (nx, ny) = (x.len(), y.len());
    if nx == 0 || ny == 0 {
        return f64::NAN;
    }
    let mut all: Vec<(f64, bool)> = x
        .iter()
        .map(|&v| (v, true))
        .chain(y.iter().map(|&v| (v, false)))
        .collect();
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
    let n = all.len();
    let mut rank_x = 0.0;
    let mut ties = 0.0;
    let mut k = 0;
    while k < n {
        let mut l = k;
        while l + 1 < n && all[l + 1].0 == all[k].0 {
            l += 1;
        }
        let t = (l - k + 1) as f64;
        let mid_rank = (k + l) as f64 / 2.0 + 1.0;
        rank_x += mid_rank * all[k..=l].iter().filter(|v| v.1).count() as f64;
        ties += t * t * t - t;
        k = l + 1;
    }
    let (nxf, nyf, nf) = (nx as f64, ny as f64, n as f64);
    let w = rank_x - nxf * (nxf + 1.0) / 2.0;
    let z = w - nxf * nyf / 2.0;
    let sigma = ((nxf * nyf / 12.0) * ((nf + 1.0) - ties / (nf * (nf - 1.0)))).sqrt();
    let z = (z + 0.5) / sigma;
    let normal = Normal::standard();
    normal.cdf(z)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Power-law decay times `enrich` inside blocks starting at `edges`.
    fn block_band(n: usize, width: usize, edges: &[usize], enrich: f64) -> CisBand {
        let block = |i: usize| edges.iter().filter(|&&e| e <= i).count();
        let mut band = CisBand::zeros(100, n, width);
        for i in 0..n {
            for j in i..(i + width).min(n) {
                let mut v = 10.0 * (1.0 + (j - i) as f64).powf(-1.0);
                if block(i) == block(j) {
                    v *= enrich;
                }
                band.add(i, j, v);
            }
        }
        band
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn bin_signal_matches_dense_diamond_mean() {
        let (n, width, w) = (23, 9, 4);
        let mut band = CisBand::zeros(0, n, width);
        let mut dense = vec![vec![0.0; n]; n];
        let mut state = 12345u64;
        for i in 0..n {
            for j in i..(i + width).min(n) {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let v = (state >> 33) as f64 / (1u64 << 31) as f64;
                band.add(i, j, v);
                dense[i][j] = v;
                dense[j][i] = v;
            }
        }
        let sig = bin_signal(&band, w);
        for i in 0..n {
            if i == n - 1 {
                assert!(sig[i].is_nan());
                continue;
            }
            let mut vals = Vec::new();
            for r in 0..n {
                for c in 0..n {
                    if r + w > i && r <= i && c > i && c <= i + w {
                        vals.push(dense[r][c]);
                    }
                }
            }
            let mean = vals.iter().sum::<f64>() / vals.len() as f64;
            assert!(
                (sig[i] - mean).abs() < 1e-12,
                "bin {i}: {} vs {mean}",
                sig[i]
            );
        }
    }

    #[test]
    fn rank_sum_matches_r_normal_approximation() {
        // Reference: scipy.stats.mannwhitneyu(x, y, alternative='less', method='asymptotic',
        // use_continuity=True).pvalue (scipy 1.17.1), which is R's
        // wilcox.test(x, y, alternative = "less", exact = FALSE) with ties.
        let x = [1.0, 2.0, 2.0, 3.5, -1.0, 0.0, 2.0];
        let y = [2.0, 4.0, 5.0, 3.5, 6.0, 2.0, 7.0, 8.0, 0.5];
        assert!((rank_sum_less(&x, &y) - 0.013_753_267_957_799_957).abs() < 1e-12);
        assert!((rank_sum_less(&y, &x) - 0.989_605_035_418_807_8).abs() < 1e-12);
        let a = [0.3, -0.2, 1.1, 0.9, 0.0, 0.0];
        let b = [0.1, 0.5, -0.4, 0.0, 1.2, 0.8, 0.7, -1.0, 0.2, 0.6];
        assert!((rank_sum_less(&a, &b) - 0.521_688_904_114_382).abs() < 1e-12);
        assert!(rank_sum_less(&[], &b).is_nan());
    }

    #[test]
    fn block_edges_are_called_as_boundaries() {
        let edges = [0, 12, 24, 36, 48];
        let band = block_band(60, 11, &edges, 3.0);
        let out = topdom(&band, &TopDomParams::default()).unwrap();
        let called: Vec<usize> = out.boundaries.iter().map(|b| b.bin - 100).collect();
        assert_eq!(called.len(), 4, "{called:?}");
        for (c, e) in called.iter().zip(&edges[1..]) {
            assert!(c.abs_diff(*e) <= 1, "called {called:?}");
        }
        assert!(
            out.boundaries
                .iter()
                .all(|b| b.strength > -(0.05f64.log10()))
        );
        // Segments tile the region.
        assert_eq!(out.segments[0].0.start_bin, 100);
        assert_eq!(out.segments.last().unwrap().0.end_bin, 160);
        for pair in out.segments.windows(2) {
            assert_eq!(pair[0].0.end_bin, pair[1].0.start_bin);
        }
        let doms = out
            .segments
            .iter()
            .filter(|s| s.1 == TopDomTag::Domain)
            .count();
        assert_eq!(doms, 5);
        // Without the filter the same minima are kept, strengths are NaN.
        let raw = topdom(
            &band,
            &TopDomParams {
                statistical_filter: false,
                ..TopDomParams::default()
            },
        )
        .unwrap();
        assert_eq!(raw.boundaries.len(), 4);
        assert!(raw.boundaries.iter().all(|b| b.strength.is_nan()));
    }

    #[test]
    fn empty_rows_are_gaps() {
        let mut band = CisBand::zeros(0, 60, 11);
        let full = block_band(60, 11, &[0, 12, 24, 36, 48], 3.0);
        for i in 0..60 {
            for j in i..(i + 11).min(60) {
                if !(20..30).contains(&i) && !(20..30).contains(&j) {
                    band.add(i, j, full.get(i, j));
                }
            }
        }
        let out = topdom(&band, &TopDomParams::default()).unwrap();
        let gaps: Vec<(usize, usize)> = out
            .segments
            .iter()
            .filter(|s| s.1 == TopDomTag::Gap)
            .map(|s| (s.0.start_bin, s.0.end_bin))
            .collect();
        assert_eq!(gaps, vec![(20, 30)]);
        assert!(out.boundaries.iter().all(|b| !(20..=30).contains(&b.bin)));
    }

    #[test]
    fn too_narrow_band_or_short_region_is_invalid() {
        let band = block_band(60, 10, &[0, 30], 2.0);
        let err = topdom(&band, &TopDomParams::default()).unwrap_err();
        assert!(err.to_string().contains("11 diagonals"), "{err}");
        let band = block_band(9, 11, &[0], 2.0);
        assert!(topdom(&band, &TopDomParams::default()).is_err());
    }
}
