//! The sums behind the expected: per diagonal of each region (cis), per pair of regions
//! (trans), in parallel over blocks of pixels.

use std::sync::Mutex;

use rayon::prelude::*;

use super::params::{CisParams, SMOOTH_POINTS_PER_SIGMA, SMOOTH_WINDOW_SIGMAS};
use super::result::{CisExpected, TransExpected};
use crate::error::{Error, Result};
use crate::genome::View;
use crate::matrix::{PixelSlice, PixelSource};
use crate::normalize::DiagonalCurve;

/// Region id of a bin outside every region (or masked).
const NO_REGION: u32 = u32::MAX;

/// Per-bin region ids for pixel assignment, with masked bins (NaN weight) excluded.
fn pixel_regions(view: &View, n_bins: usize, weights: Option<&[f64]>) -> Vec<u32> {
    view.bin_regions(n_bins)
        .iter()
        .enumerate()
        .map(|(bin, region)| match (region, weights) {
            (Some(_), Some(w)) if w[bin].is_nan() => NO_REGION,
            (Some(r), _) => *r as u32,
            (None, _) => NO_REGION,
        })
        .collect()
}

fn check_inputs<S: PixelSource>(pixels: &S, weights: Option<&[f64]>, view: &View) -> Result<()> {
    let n_bins = pixels.bins().n_bins();
    if let Some(w) = weights {
        if w.len() != n_bins {
            return Err(Error::Data(format!(
                "{} weights for {n_bins} bins",
                w.len()
            )));
        }
    }
    if view.len() >= NO_REGION as usize {
        return Err(Error::Unsupported(format!(
            "{} view regions are too many",
            view.len()
        )));
    }
    if let Some(region) = view.regions().iter().find(|r| r.bins.end > n_bins) {
        return Err(Error::Data(format!(
            "view region '{}' lies outside the matrix's {n_bins} bins",
            region.name
        )));
    }
    Ok(())
}

/// Compute the cis expected of `pixels` over `view`: balanced with `weights` (multiplicative,
/// one per bin, NaN for masked bins), or raw counts when `weights` is `None`.
///
/// Needs fixed-size bins (distances in bp are `dist * resolution`, as cooltools writes them).
///
/// # Examples
///
/// A chromosome of 10 bins whose diagonal `d` holds `10 - d` everywhere: raw, every diagonal
/// averages `10 - d`; balanced with weights 0.5 and bin 0 masked, `0.25 (10 - d)` over the
/// `9 - d` valid pixels. The first two diagonals are ignored (NaN), as cooltools does.
///
/// ```
/// use contactmap::expected::{expected_cis, CisParams};
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 10_000)], 1_000)?;
/// let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
/// for i in 0..10u64 {
///     for j in i..10 {
///         builder.push(i, j, (10 - (j - i)) as f64)?;
///     }
/// }
/// let matrix = InMemory::new("example".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// let view = View::chromosomes(&bins);
/// let raw = expected_cis(&pixels, None, &view, &CisParams::default())?;
/// assert_eq!(raw.n_rows(), 10);
/// assert!(raw.count_avg[1].is_nan());
/// for d in 2..10 {
///     assert_eq!(raw.dist_bp[d], d as u64 * 1_000);
///     assert_eq!((raw.n_total[d], raw.n_valid[d]), (10 - d as u64, 10 - d as u64));
///     assert_eq!(raw.count_avg[d], (10 - d) as f64);
/// }
/// let mut weights = vec![0.5; 10];
/// weights[0] = f64::NAN;
/// let balanced = expected_cis(&pixels, Some(&weights), &view, &CisParams::default())?;
/// let average = balanced.balanced_avg.as_ref().expect("balanced columns");
/// for d in 2..9 {
///     assert_eq!(balanced.n_valid[d], 9 - d as u64);
///     assert_eq!(average[d], 0.25 * (10 - d) as f64);
/// }
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn expected_cis<S: PixelSource>(
    pixels: &S,
    weights: Option<&[f64]>,
    view: &View,
    params: &CisParams,
) -> Result<CisExpected> {
    params.check()?;
    check_inputs(pixels, weights, view)?;
    let bins = pixels.bins();
    let resolution = bins.resolution().ok_or_else(|| {
        Error::Unsupported(
            "expected needs fixed-size bins (distances are diagonals times the bin size)".into(),
        )
    })?;
    if !(params.smooth_sigma_log10 > 0.0 && params.smooth_sigma_log10.is_finite()) {
        return Err(Error::Argument(format!(
            "the smoothing sigma must be positive (got {})",
            params.smooth_sigma_log10
        )));
    }
    let region_of = pixel_regions(view, bins.n_bins(), weights);
    let mut base = Vec::with_capacity(view.len() + 1);
    let mut n_keys = 0usize;
    for region in view.regions() {
        base.push(n_keys);
        n_keys += region.n_bins();
    }
    base.push(n_keys);
    if n_keys > u32::MAX as usize {
        return Err(Error::Unsupported(format!(
            "{n_keys} (region, diagonal) pairs do not fit 32-bit keys"
        )));
    }
    let base32: Vec<u32> = base.iter().map(|&b| b as u32).collect();
    let sums = accumulate(pixels, n_keys, weights, |i, j| {
        let r = region_of[i];
        if r != NO_REGION && r == region_of[j] {
            Some(base32[r as usize] + (j - i) as u32)
        } else {
            None
        }
    })?;

    let balanced = weights.is_some();
    let mut table = CisExpected {
        resolution,
        region_names: view.regions().iter().map(|r| r.name.clone()).collect(),
        region: Vec::with_capacity(n_keys),
        dist: Vec::with_capacity(n_keys),
        dist_bp: Vec::with_capacity(n_keys),
        n_total: Vec::with_capacity(n_keys),
        n_valid: Vec::with_capacity(n_keys),
        count_sum: Vec::with_capacity(n_keys),
        balanced_sum: balanced.then(|| Vec::with_capacity(n_keys)),
        count_avg: Vec::with_capacity(n_keys),
        balanced_avg: balanced.then(|| Vec::with_capacity(n_keys)),
        avg_smoothed: None,
        avg_smoothed_agg: None,
    };
    let valid_per_region: Vec<Vec<u64>> = view
        .regions()
        .par_iter()
        .map(|region| {
            let good: Vec<bool> = region
                .bins
                .clone()
                .map(|bin| weights.is_none_or(|w| !w[bin].is_nan()))
                .collect();
            valid_pairs_per_diagonal(&good)
        })
        .collect();
    for (r, region) in view.regions().iter().enumerate() {
        let n = region.n_bins();
        for d in 0..n {
            let ignored = d < params.ignore_diags;
            let [count, balanced_value] = sums[base[r] + d];
            let n_total = (n - d) as u64;
            let n_valid = valid_per_region[r][d];
            let count_sum = if ignored { f64::NAN } else { count };
            table.region.push(r as u32);
            table.dist.push(d as u64);
            table.dist_bp.push(d as u64 * resolution);
            table.n_total.push(n_total);
            table.n_valid.push(n_valid);
            table.count_sum.push(count_sum);
            table.count_avg.push(count_sum / n_total as f64);
            if let (Some(sum), Some(avg)) = (&mut table.balanced_sum, &mut table.balanced_avg) {
                let value = if ignored { f64::NAN } else { balanced_value };
                sum.push(value);
                avg.push(value / n_valid as f64);
            }
        }
    }
    if params.smooth {
        let (smoothed, aggregated) = smooth_table(&table, view, &base, params);
        table.avg_smoothed = Some(smoothed);
        table.avg_smoothed_agg = aggregated;
    }
    Ok(table)
}

/// The smoothed averages per region and, when asked, over all regions (cooltools'
/// `per_region_smooth_cvd` and `genomewide_smooth_cvd`).
fn smooth_table(
    table: &CisExpected,
    view: &View,
    base: &[usize],
    params: &CisParams,
) -> (Vec<f64>, Option<Vec<f64>>) {
    let pixel_counts: &[u64] = if table.is_balanced() {
        &table.n_valid
    } else {
        &table.n_total
    };
    let contacts: Vec<f64> = table
        .summary()
        .iter()
        .map(|&v| if v.is_nan() { 0.0 } else { v })
        .collect();
    let smooth_pair = |n_pixels: &[f64], n_contacts: &[f64]| -> Vec<f64> {
        let xs: Vec<f64> = (0..n_pixels.len()).map(|d| d as f64).collect();
        let smoothed = super::smooth::log_smooth(
            &xs,
            &[n_contacts, n_pixels],
            params.smooth_sigma_log10,
            SMOOTH_WINDOW_SIGMAS,
            SMOOTH_POINTS_PER_SIGMA,
        );
        smoothed[0]
            .iter()
            .zip(&smoothed[1])
            .map(|(c, p)| c / p)
            .collect()
    };
    let per_region: Vec<Vec<f64>> = (0..view.len())
        .into_par_iter()
        .map(|r| {
            let rows = base[r]..base[r + 1];
            let n_pixels: Vec<f64> = pixel_counts[rows.clone()]
                .iter()
                .map(|&v| v as f64)
                .collect();
            smooth_pair(&n_pixels, &contacts[rows])
        })
        .collect();
    let smoothed: Vec<f64> = per_region.into_iter().flatten().collect();
    let aggregated = params.aggregate_smoothed.then(|| {
        let max_n = (0..view.len())
            .map(|r| base[r + 1] - base[r])
            .max()
            .unwrap_or(0);
        let mut n_pixels = vec![0u64; max_n];
        let mut n_contacts = vec![0.0f64; max_n];
        for r in 0..view.len() {
            for (d, row) in (base[r]..base[r + 1]).enumerate() {
                n_pixels[d] += pixel_counts[row];
                n_contacts[d] += contacts[row];
            }
        }
        let n_pixels: Vec<f64> = n_pixels.iter().map(|&v| v as f64).collect();
        let by_dist = smooth_pair(&n_pixels, &n_contacts);
        table.dist.iter().map(|&d| by_dist[d as usize]).collect()
    });
    (smoothed, aggregated)
}

/// Compute the trans expected of `pixels` between every pair of `view` regions on different
/// chromosomes: balanced with `weights`, or raw counts when `weights` is `None`.
///
/// # Examples
///
/// Two chromosomes of 4 and 3 bins whose trans pixels all hold 2: with one bin masked, the
/// block has `3 x 3` valid pixels, summing to 18.
///
/// ```
/// use contactmap::expected::expected_trans;
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
///
/// let chroms = vec![Chrom::new("chr1", 400), Chrom::new("chr2", 300)];
/// let bins = BinTable::fixed(chroms, 100)?;
/// let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
/// for i in 0..4u64 {
///     builder.push(i, i, 50.0)?; // cis: left out
///     for j in 4..7 {
///         builder.push(i, j, 2.0)?;
///     }
/// }
/// let matrix = InMemory::new("example".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// let view = View::chromosomes(&bins);
/// let raw = expected_trans(&pixels, None, &view)?;
/// assert_eq!((raw.region1[0].as_str(), raw.region2[0].as_str()), ("chr1", "chr2"));
/// assert_eq!((raw.n_valid[0], raw.count_sum[0], raw.count_avg[0]), (12, 24.0, 2.0));
/// let weights = [f64::NAN, 1.0, 1.0, 1.0, 0.5, 0.5, 0.5];
/// let balanced = expected_trans(&pixels, Some(&weights), &view)?;
/// assert_eq!((balanced.n_valid[0], balanced.count_sum[0]), (9, 18.0));
/// assert_eq!(balanced.balanced_avg.as_ref().unwrap()[0], 1.0);
/// assert_eq!(balanced.average_by_pair(&view)[0][1], 1.0);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn expected_trans<S: PixelSource>(
    pixels: &S,
    weights: Option<&[f64]>,
    view: &View,
) -> Result<TransExpected> {
    check_inputs(pixels, weights, view)?;
    let n_regions = view.len();
    let n_keys = n_regions
        .checked_mul(n_regions)
        .filter(|&n| n <= u32::MAX as usize)
        .ok_or_else(|| Error::Unsupported(format!("{n_regions} view regions are too many")))?;
    let region_of = pixel_regions(view, pixels.bins().n_bins(), weights);
    let chrom_of: Vec<usize> = view.regions().iter().map(|r| r.chrom_id).collect();
    let sums = accumulate(pixels, n_keys, weights, |i, j| {
        let (r1, r2) = (region_of[i], region_of[j]);
        if r1 != NO_REGION && r2 != NO_REGION && chrom_of[r1 as usize] != chrom_of[r2 as usize] {
            // Pixels are the upper triangle and the view is sorted: r1 < r2.
            Some(r1 * n_regions as u32 + r2)
        } else {
            None
        }
    })?;
    let balanced = weights.is_some();
    let good_bins: Vec<u64> = view
        .regions()
        .iter()
        .map(|r| {
            r.bins
                .clone()
                .filter(|&bin| weights.is_none_or(|w| !w[bin].is_nan()))
                .count() as u64
        })
        .collect();
    let mut table = TransExpected {
        region1: Vec::new(),
        region2: Vec::new(),
        n_valid: Vec::new(),
        count_sum: Vec::new(),
        balanced_sum: balanced.then(Vec::new),
        count_avg: Vec::new(),
        balanced_avg: balanced.then(Vec::new),
    };
    let regions = view.regions();
    for r1 in 0..n_regions {
        for r2 in r1 + 1..n_regions {
            if regions[r1].chrom_id == regions[r2].chrom_id {
                continue;
            }
            let n_valid = good_bins[r1] * good_bins[r2];
            let [count, balanced_value] = sums[r1 * n_regions + r2];
            table.region1.push(regions[r1].name.clone());
            table.region2.push(regions[r2].name.clone());
            table.n_valid.push(n_valid);
            table.count_sum.push(count);
            table.count_avg.push(count / n_valid as f64);
            if let (Some(sum), Some(avg)) = (&mut table.balanced_sum, &mut table.balanced_avg) {
                sum.push(balanced_value);
                avg.push(balanced_value / n_valid as f64);
            }
        }
    }
    Ok(table)
}

/// The expected that an analysis divides by (pileups, dots): in cis, per view region, the
/// expected of each diagonal (`[region][d]`, as [`CisExpected::average_by_region`]); with
/// `trans`, per two view regions (`[a][b]`, `a < b`, as [`TransExpected::average_by_pair`]).
/// Column `column` of a cooltools expected table when one is given (on the same bins and view),
/// else computed from `pixels` as `contactmap expected` computes it (balanced by `weights`, raw
/// counts without).
pub fn expected_to_divide_by<S: PixelSource>(
    pixels: &S,
    weights: Option<&[f64]>,
    view: &View,
    table: Option<&crate::io::tables::Table>,
    column: &str,
    trans: bool,
) -> Result<Vec<Vec<f64>>> {
    match (table, trans) {
        (Some(table), false) => super::table::region_column(table, pixels.bins(), view, column),
        (Some(table), true) => super::table::pair_column(table, view, column),
        (None, false) => {
            Ok(expected_cis(pixels, weights, view, &CisParams::default())?.average_by_region())
        }
        (None, true) => Ok(expected_trans(pixels, weights, view)?.average_by_pair(view)),
    }
}

/// Per-chromosome expected curves for observed / expected ([`crate::normalize`]): the cis
/// expected over whole chromosomes without smoothing, with `balanced.avg` (`count.avg` for raw
/// counts) and `n_valid` per diagonal.
///
/// # Examples
///
/// One curve per chromosome, one value per diagonal: the averages of cooltools'
/// `expected_cis` on the mm9 map (`data/reference/numerics/mm9_CN_10Mb.expected_cis.raw.tsv.gz`,
/// chr1: 20 bins, 1,114,921 contacts on the 18 pixels of diagonal 2).
///
/// ```
/// use contactmap::expected::cis_curves;
/// use contactmap::io::{load_pixels, open_matrix, MatrixReader, OpenOptions};
///
/// let reader = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
/// let pixels = load_pixels(&*reader, u64::MAX)?;
/// let curves = cis_curves(&pixels, None, 2)?;
/// assert_eq!(curves.len(), reader.bins().n_chroms());
/// let chr1 = &curves[0];
/// assert_eq!((chr1.bins.clone(), chr1.expected.len()), (0..20, 20));
/// assert!(chr1.expected[0].is_nan() && chr1.expected[1].is_nan());
/// assert_eq!((chr1.expected[2], chr1.n_valid[2]), (1_114_921.0 / 18.0, 18.0));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn cis_curves<S: PixelSource>(
    pixels: &S,
    weights: Option<&[f64]>,
    ignore_diags: usize,
) -> Result<Vec<DiagonalCurve>> {
    let view = View::chromosomes(pixels.bins());
    let params = CisParams {
        ignore_diags,
        smooth: false,
        aggregate_smoothed: false,
        ..CisParams::default()
    };
    let table = expected_cis(pixels, weights, &view, &params)?;
    let average = table.average();
    let mut start = 0;
    Ok(view
        .regions()
        .iter()
        .map(|region| {
            let rows = start..start + region.n_bins();
            start = rows.end;
            DiagonalCurve {
                bins: region.bins.clone(),
                expected: average[rows.clone()].to_vec(),
                n_valid: table.n_valid[rows].iter().map(|&n| n as f64).collect(),
            }
        })
        .collect())
}

/// Longest sparse partial result kept before turning it dense (48 MB of entries).
const SPARSE_MAX_ENTRIES: usize = 1 << 21;

/// Sums `[count, balanced]` per key, for partial results of a pass.
enum Sums {
    /// The keys some consecutive slices touched, slice after slice (a key may appear once per
    /// slice, and twice within a slice with a zero second entry).
    Sparse(Vec<(u32, [f64; 2])>),
    /// Every key.
    Dense(Vec<[f64; 2]>),
}

/// A per-thread accumulator: dense sums kept at zero between slices, and the keys touched.
#[derive(Default)]
struct Scratch {
    sums: Vec<[f64; 2]>,
    touched: Vec<u32>,
}

fn add_sparse(dense: &mut [[f64; 2]], sparse: &[(u32, [f64; 2])]) {
    for &(key, [count, balanced]) in sparse {
        let cell = &mut dense[key as usize];
        cell[0] += count;
        cell[1] += balanced;
    }
}

/// Add two partial results, `a` holding earlier slices than `b`.
///
/// Sparse lists are concatenated while they stay below [`SPARSE_MAX_ENTRIES`] (or a quarter of
/// the keys, if more), then turned dense. Every sparse entry is added to the dense sums one at a
/// time in slice order, so the result is the sequential sum of the slices' partial sums (IEEE
/// addition is commutative, and adding a missing key's zero is exact) whatever the
/// representation. A streamed pass hands its blocks (1 M pixels for .cool files) over as sparse
/// lists, so when blocks are made of whole slices it gives bit-identical sums to an in-memory
/// pass; only dense partials of larger blocks would be added as totals.
fn merge(a: Sums, b: Sums, n_keys: usize) -> Sums {
    match (a, b) {
        (Sums::Sparse(a), b) if a.is_empty() => b,
        (a, Sums::Sparse(b)) if b.is_empty() => a,
        (Sums::Dense(mut dense), Sums::Sparse(sparse)) => {
            add_sparse(&mut dense, &sparse);
            Sums::Dense(dense)
        }
        (Sums::Sparse(sparse), Sums::Dense(later)) => {
            let mut dense = vec![[0.0; 2]; n_keys];
            add_sparse(&mut dense, &sparse);
            add_dense(&mut dense, &later);
            Sums::Dense(dense)
        }
        (Sums::Dense(mut a), Sums::Dense(b)) => {
            add_dense(&mut a, &b);
            Sums::Dense(a)
        }
        (Sums::Sparse(mut a), Sums::Sparse(b)) => {
            if a.len() + b.len() <= SPARSE_MAX_ENTRIES.max(n_keys / 4) {
                a.extend(b);
                Sums::Sparse(a)
            } else {
                let mut dense = vec![[0.0; 2]; n_keys];
                add_sparse(&mut dense, &a);
                add_sparse(&mut dense, &b);
                Sums::Dense(dense)
            }
        }
    }
}

fn add_dense(dense: &mut [[f64; 2]], later: &[[f64; 2]]) {
    for (x, y) in dense.iter_mut().zip(later) {
        x[0] += y[0];
        x[1] += y[1];
    }
}

/// One pass over the pixels: for each pixel with a key, add its count (and its balanced value
/// `count * w1 * w2` when weighted) to the key's sums.
fn accumulate<S, K>(
    pixels: &S,
    n_keys: usize,
    weights: Option<&[f64]>,
    key_of: K,
) -> Result<Vec<[f64; 2]>>
where
    S: PixelSource,
    K: Fn(usize, usize) -> Option<u32> + Sync,
{
    let pool: Mutex<Vec<Scratch>> = Mutex::new(Vec::new());
    let take = || {
        pool.lock()
            .unwrap_or_else(|e| e.into_inner())
            .pop()
            .unwrap_or_default()
    };
    let fold = |acc: Sums, slice: PixelSlice<'_>| {
        let mut scratch = take();
        if scratch.sums.len() < n_keys {
            scratch.sums.resize(n_keys, [0.0; 2]);
        }
        let Scratch { sums, touched } = &mut scratch;
        match weights {
            Some(w) => {
                for (i, j, count) in slice.iter() {
                    if let Some(key) = key_of(i, j) {
                        let cell = &mut sums[key as usize];
                        if cell[0] == 0.0 && cell[1] == 0.0 {
                            touched.push(key);
                        }
                        cell[0] += count;
                        cell[1] += count * w[i] * w[j];
                    }
                }
            }
            None => {
                for (i, j, count) in slice.iter() {
                    if let Some(key) = key_of(i, j) {
                        let cell = &mut sums[key as usize];
                        if cell[0] == 0.0 {
                            touched.push(key);
                        }
                        cell[0] += count;
                    }
                }
            }
        }
        // A key whose sum returned to zero may be listed twice: its second entry is zero.
        let part: Vec<(u32, [f64; 2])> = touched
            .drain(..)
            .map(|key| (key, std::mem::take(&mut sums[key as usize])))
            .collect();
        pool.lock().unwrap_or_else(|e| e.into_inner()).push(scratch);
        merge(acc, Sums::Sparse(part), n_keys)
    };
    let total = pixels.pass(
        || Sums::Sparse(Vec::new()),
        fold,
        |a, b| merge(a, b, n_keys),
    )?;
    Ok(match total {
        Sums::Dense(dense) => dense,
        Sums::Sparse(sparse) => {
            let mut dense = vec![[0.0; 2]; n_keys];
            add_sparse(&mut dense, &sparse);
            dense
        }
    })
}

/// For each distance `d` in `0..good.len()`, the number of positions `i` with `good[i]` and
/// `good[i + d]`: the valid pixels on diagonal `d` of a region whose bins are `good` or masked.
///
/// Exact integers (cooltools gets the same numbers through an FFT and rounding).
pub fn valid_pairs_per_diagonal(good: &[bool]) -> Vec<u64> {
    let n = good.len();
    let n_good = good.iter().filter(|&&g| g).count();
    let n_bad = n - n_good;
    if n_bad == 0 {
        return (0..n).map(|d| (n - d) as u64).collect();
    }
    if n_good == 0 {
        return vec![0; n];
    }
    // Autocorrelation of the sparser set; the other follows by inclusion-exclusion.
    let use_good = n_good <= n_bad;
    let members: Vec<bool> = good.iter().map(|&g| g == use_good).collect();
    let m = n_good.min(n_bad) as u128;
    let pairs = if m * m <= (n as u128 * n as u128) / 64 {
        let positions: Vec<usize> = (0..n).filter(|&i| members[i]).collect();
        let mut auto = vec![0u64; n];
        auto[0] = positions.len() as u64;
        for (a, &pa) in positions.iter().enumerate() {
            for &pb in &positions[a + 1..] {
                auto[pb - pa] += 1;
            }
        }
        auto
    } else {
        bitset_autocorrelation(&members)
    };
    if use_good {
        return pairs;
    }
    // good pairs = all pairs - pairs with a masked left bin - with a masked right bin + both.
    let mut masked_before = vec![0u64; n + 1];
    for i in 0..n {
        masked_before[i + 1] = masked_before[i] + u64::from(!good[i]);
    }
    (0..n)
        .map(|d| {
            let left = masked_before[n - d];
            let right = masked_before[n] - masked_before[d];
            (n - d) as u64 + pairs[d] - left - right
        })
        .collect()
}

/// `auto[d] = #{i : bits[i] && bits[i + d]}` with 64-bit words and popcounts (parallel over d).
pub(super) fn bitset_autocorrelation(bits: &[bool]) -> Vec<u64> {
    let n = bits.len();
    let n_words = n.div_ceil(64);
    let mut words = vec![0u64; n_words + 1];
    for (i, _) in bits.iter().enumerate().filter(|&(_, &b)| b) {
        words[i / 64] |= 1 << (i % 64);
    }
    (0..n)
        .into_par_iter()
        .with_min_len(64)
        .map(|d| {
            let (q, r) = (d / 64, d % 64);
            let mut count = 0u64;
            for k in 0..n_words - q {
                let shifted = if r == 0 {
                    words[k + q]
                } else {
                    (words[k + q] >> r) | (words[k + q + 1] << (64 - r))
                };
                count += u64::from((words[k] & shifted).count_ones());
            }
            count
        })
        .collect()
}
