//! The statistics of cooltools' dot caller: lambda bins (log-binned locally adjusted expected),
//! the histogram of observed counts per lambda bin, and per bin the FDR threshold and the
//! q-values (`histogram_scored_pixels`, `determine_thresholds`).
//!
//! For a lambda bin with right edge `λ` holding `N` pixels, `n(k)` of them with count `>= k`:
//! the expected number of pixels at or above `k` by chance is `N * P(X > k)` for `X ~ Poisson(λ)`
//! (cooltools uses scipy's `poisson.sf`, `P(X > k)`; HiCCUPS uses `P(X >= k)`, one count less
//! strict), the threshold is the smallest count `k` from which `fdr * n(k) - N * P(X > k)` stays
//! non-negative (a running maximum over counts), and the q-value of count `k` is the running
//! minimum of `N * P(X > k) / n(k)`, capped at 1.

use std::collections::BTreeMap;

use crate::error::{Error, Result};

/// cooltools' lambda-bin base, `2^(1/3)`.
fn base() -> f64 {
    2f64.powf(1.0 / 3.0)
}

/// Lambda bins beyond cooltools' last finite edge: a pixel whose locally adjusted expected
/// exceeds `2^((n - 1) / 3)` (cooltools refuses the map, issues #511, #552) falls in further bins
/// of the same progression, up to `2^(EXTRA_EDGES_TO / 3)`.
const EXTRA_EDGES_TO: usize = 192;

/// The lambda-bin edges: `-inf`, then `2^(t/3)` for `t = 0 .. n - 1` (numpy's `logspace(0, n - 1,
/// n, base=2^(1/3))`), continued past cooltools' last edge; bins are right-closed, as pandas'
/// `cut`.
///
/// pandas labels the bins of `cut` with edges rounded to 3 decimals (`_round_frac`, more when 3
/// would merge edges): cooltools takes each bin's Poisson mean from these labels (161.27 for
/// `2^(22/3) = 161.2698...`) and bins the enriched pixels by them again to look up their
/// q-values. [`LambdaBins::right`] and [`LambdaBins::label_index`] do the same.
#[derive(Clone, Debug, PartialEq)]
pub struct LambdaBins {
    /// `edges[0] = -inf`; bin `b` is `(edges[b], edges[b + 1]]`.
    pub edges: Vec<f64>,
    /// The edges as pandas labels them.
    pub labels: Vec<f64>,
    /// cooltools' number of finite edges (`n_lambda_bins`).
    pub n_lambda_bins: usize,
}

/// numpy's `around(x, decimals)`: scale, round half to even, scale back.
fn np_around(x: f64, decimals: i32) -> f64 {
    if decimals >= 0 {
        let f = 10f64.powi(decimals);
        (x * f).round_ties_even() / f
    } else {
        let f = 10f64.powi(-decimals);
        (x / f).round_ties_even() * f
    }
}

/// pandas' `_round_frac(x, precision)`.
fn round_frac(x: f64, precision: i32) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    let whole = x.trunc();
    let digits = if whole == 0.0 {
        -((x - whole).abs().log10().floor() as i32) - 1 + precision
    } else {
        precision
    };
    np_around(x, digits)
}

/// pandas' `_infer_precision(3, bins)`: the smallest precision from 3 keeping the edges apart.
fn infer_precision(bins: &[f64]) -> i32 {
    for precision in 3..20 {
        let mut levels: Vec<f64> = bins.iter().map(|&b| round_frac(b, precision)).collect();
        levels.sort_by(f64::total_cmp);
        levels.dedup();
        if levels.len() == bins.len() {
            return precision;
        }
    }
    3
}

impl LambdaBins {
    /// The bins of cooltools' `n_lambda_bins` (40 to 50).
    ///
    /// ```
    /// use contactmap::loops::fdr::LambdaBins;
    /// let bins = LambdaBins::new(40);
    /// assert_eq!(bins.index(0.0), 0);
    /// assert_eq!(bins.index(1.0), 0); // right-closed: (-inf, 1]
    /// assert_eq!(bins.index(1.1), 1);
    /// assert_eq!(bins.right(0), 1.0);
    /// assert_eq!(bins.right(22), 161.27); // 2^(22/3) = 161.2698..., as pandas labels it
    /// assert_eq!(bins.index(161.2699), 23);
    /// assert_eq!(bins.label_index(161.2699), 22);
    /// for x in [0.5, 1.0, 1.0000001, 2.0, 2.5198421, 7.9, 8.0, 8192.000000000007, 1e6] {
    ///     assert_eq!(bins.index(x), bins.edges.partition_point(|&e| e < x) - 1, "{x}");
    /// }
    /// ```
    pub fn new(n_lambda_bins: usize) -> LambdaBins {
        let b = base();
        let mut edges = vec![f64::NEG_INFINITY];
        for t in 0..EXTRA_EDGES_TO.max(n_lambda_bins) {
            edges.push(b.powf(t as f64));
        }
        // the precision pandas infers for cooltools' own edges (-inf, n edges, inf)
        let mut cooltools_edges = edges[..=n_lambda_bins].to_vec();
        cooltools_edges.push(f64::INFINITY);
        let precision = infer_precision(&cooltools_edges);
        let labels = edges.iter().map(|&e| round_frac(e, precision)).collect();
        LambdaBins {
            edges,
            labels,
            n_lambda_bins,
        }
    }

    /// The bin of `x` (pandas' `cut`: the number of edges below `x`, less one); [`Self::len`]
    /// above the last edge.
    #[inline]
    pub fn index(&self, x: f64) -> usize {
        if x <= 1.0 || x.is_nan() {
            return 0; // (-inf, 1] (and NaN, which cut leaves out; scored pixels have none)
        }
        // edges[k] = 2^((k - 1) / 3): start from the bin log2 suggests, then settle on the
        // exact edges (the guess is off by at most one)
        let last = self.edges.len() - 1;
        // 3 log2(x) from the exponent and the mantissa against 2^(1/3), 2^(2/3)
        let bits = x.to_bits();
        let exponent = ((bits >> 52) & 0x7ff) as i64 - 1023;
        let mantissa = f64::from_bits((bits & ((1u64 << 52) - 1)) | (1023u64 << 52));
        let third = (mantissa > 1.259_921_049_894_873_2) as i64
            + (mantissa > 1.587_401_051_968_199_4) as i64;
        let guess = (3 * exponent + third + 2).max(1) as usize;
        let mut k = guess.min(last);
        while k > 1 && self.edges[k - 1] >= x {
            k -= 1;
        }
        while k <= last && self.edges[k] < x {
            k += 1;
        }
        k - 1
    }

    /// The bin of `x` by the labels' rounded edges (how cooltools looks up q-values).
    pub fn label_index(&self, x: f64) -> usize {
        self.labels.partition_point(|&e| e < x).saturating_sub(1)
    }

    /// The right edge of bin `b` as labelled (cooltools' Poisson mean for the bin).
    pub fn right(&self, b: usize) -> f64 {
        self.labels[b + 1]
    }

    /// Number of bins (the last one ends at the last edge).
    pub fn len(&self) -> usize {
        self.edges.len() - 1
    }

    /// Never: there is always a bin.
    pub fn is_empty(&self) -> bool {
        false
    }
}

/// Counts below this are histogrammed in a dense table, the others in a map.
const DENSE_COUNTS: u64 = 1 << 16;

/// Scored pixels per (observed count, lambda bin), one table per kernel.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Histogram {
    /// Bins per count.
    n_bins: usize,
    /// Per kernel: dense `count * n_bins + bin` for counts below [`DENSE_COUNTS`].
    dense: Vec<Vec<u64>>,
    /// Per kernel: larger counts.
    sparse: Vec<BTreeMap<u64, Vec<u64>>>,
}

impl Histogram {
    /// An empty histogram for `n_kernels` kernels and `n_bins` lambda bins.
    pub fn new(n_kernels: usize, n_bins: usize) -> Histogram {
        Histogram {
            n_bins,
            dense: vec![Vec::new(); n_kernels],
            sparse: vec![BTreeMap::new(); n_kernels],
        }
    }

    /// Count one pixel of `count` in lambda bin `bin` (below the number of bins) for kernel
    /// `kernel`.
    #[inline]
    pub fn add(&mut self, kernel: usize, count: u64, bin: usize) {
        debug_assert!(bin < self.n_bins);
        if count < DENSE_COUNTS {
            let table = &mut self.dense[kernel];
            let k = count as usize * self.n_bins + bin;
            if k >= table.len() {
                table.resize((count as usize + 1) * self.n_bins, 0);
            }
            table[k] += 1;
        } else {
            self.sparse[kernel]
                .entry(count)
                .or_insert_with(|| vec![0; self.n_bins])[bin] += 1;
        }
    }

    /// The sum of two histograms.
    pub fn merge(mut self, other: Histogram) -> Histogram {
        for (kernel, table) in other.dense.into_iter().enumerate() {
            let mine = &mut self.dense[kernel];
            if mine.len() < table.len() {
                mine.resize(table.len(), 0);
            }
            for (m, t) in mine.iter_mut().zip(table) {
                *m += t;
            }
        }
        for (kernel, map) in other.sparse.into_iter().enumerate() {
            for (count, row) in map {
                let mine = self.sparse[kernel]
                    .entry(count)
                    .or_insert_with(|| vec![0; self.n_bins]);
                for (m, t) in mine.iter_mut().zip(row) {
                    *m += t;
                }
            }
        }
        self
    }

    /// Kernel `kernel`'s table: the counts present (ascending) and their row of pixels per bin.
    fn table(&self, kernel: usize) -> (Vec<u64>, Vec<Vec<u64>>) {
        let mut counts = Vec::new();
        let mut rows = Vec::new();
        for (count, row) in self.dense[kernel].chunks(self.n_bins).enumerate() {
            if row.iter().any(|&n| n > 0) {
                counts.push(count as u64);
                rows.push(row.to_vec());
            }
        }
        for (&count, row) in &self.sparse[kernel] {
            if row.iter().any(|&n| n > 0) {
                counts.push(count);
                rows.push(row.clone());
            }
        }
        (counts, rows)
    }
}

/// One kernel's thresholds and q-values.
#[derive(Clone, Debug, PartialEq)]
pub struct KernelStats {
    /// The observed counts present among the scored pixels, ascending.
    pub counts: Vec<u64>,
    /// The lambda bins kept (cooltools drops trailing empty bins): `0..n_bins`.
    pub n_bins: usize,
    /// Per bin: the smallest count that passes (the largest count plus one when none does).
    pub thresholds: Vec<u64>,
    /// Per bin: the number of pixels in it.
    pub pixels: Vec<u64>,
    /// `qvalues[row][bin]`, row the index of the count in `counts`.
    pub qvalues: Vec<Vec<f64>>,
}

impl KernelStats {
    /// The smallest threshold of a bin holding pixels: no pixel below it passes.
    pub fn min_threshold(&self) -> u64 {
        self.thresholds
            .iter()
            .zip(&self.pixels)
            .filter(|&(_, &n)| n > 0)
            .map(|(&t, _)| t)
            .min()
            .unwrap_or(0)
    }

    /// The q-value of a pixel with `count` in lambda bin `bin`; `None` when the count was not
    /// histogrammed.
    pub fn qvalue(&self, count: u64, bin: usize) -> Option<f64> {
        let row = self.counts.binary_search(&count).ok()?;
        self.qvalues[row].get(bin).copied()
    }
}

/// `P(X > k)` for `X ~ Poisson(mu)` (scipy's `poisson.sf`): the regularized lower incomplete
/// gamma function `P(k + 1, mu)`.
///
/// ```
/// use contactmap::loops::fdr::poisson_sf;
/// assert!((poisson_sf(0, 1.0) - (1.0 - (-1f64).exp())).abs() < 1e-15);
/// assert!((poisson_sf(2, 3.0) - 0.5768099188731565).abs() < 1e-14);
/// ```
pub fn poisson_sf(k: u64, mu: f64) -> f64 {
    if mu <= 0.0 {
        return 0.0;
    }
    if mu.is_infinite() {
        return 1.0;
    }
    statrs::function::gamma::gamma_lr(k as f64 + 1.0, mu)
}

/// cooltools' `determine_thresholds` for one kernel's histogram at FDR `fdr`.
pub fn kernel_stats(
    histogram: &Histogram,
    kernel: usize,
    bins: &LambdaBins,
    fdr: f64,
) -> Result<KernelStats> {
    let (counts, rows) = histogram.table(kernel);
    if counts.is_empty() {
        return Err(Error::Data(
            "no pixel could be scored: every pixel's kernels reach a masked bin, the diagonal or \
             the region's edge (check the balancing weights, the expected and --max-nans-tolerated)"
                .into(),
        ));
    }
    // trailing empty bins dropped
    let n_bins = (0..bins.len())
        .rev()
        .find(|&b| rows.iter().any(|row| row[b] > 0))
        .map_or(0, |b| b + 1);
    let high = counts[counts.len() - 1] + 1;
    let mut thresholds = vec![high; n_bins];
    let mut qvalues = vec![vec![f64::NAN; n_bins]; counts.len()];
    let mut pixels = vec![0u64; n_bins];
    for b in 0..n_bins {
        // reverse cumulative sums: pixels with count >= counts[r]
        let mut rcs = vec![0u64; counts.len()];
        let mut acc = 0u64;
        for r in (0..counts.len()).rev() {
            acc += rows[r][b];
            rcs[r] = acc;
        }
        pixels[b] = rcs[0];
        let norm = rcs[0] as f64;
        let lambda = bins.right(b);
        let mut running_max = f64::NEG_INFINITY;
        let mut running_min = f64::INFINITY;
        let mut found = false;
        for r in 0..counts.len() {
            let unit = norm * poisson_sf(counts[r], lambda);
            let diff = fdr * rcs[r] as f64 - unit;
            if diff > running_max {
                running_max = diff;
            }
            if !found && running_max >= 0.0 {
                thresholds[b] = counts[r];
                found = true;
            }
            let q = unit / rcs[r] as f64;
            if !q.is_nan() {
                if q < running_min {
                    running_min = q;
                }
                qvalues[r][b] = running_min.min(1.0);
            }
        }
    }
    Ok(KernelStats {
        counts,
        n_bins,
        thresholds,
        pixels,
        qvalues,
    })
}
