//! Differential loops: each loop's counts per replicate (the sum of its pixel neighbourhood in
//! the raw counts), with the expected count of the same pixels at their distances as the
//! normalisation (so that sequencing depth and a change of P(s) are not called changes of
//! loops), tested as [`super::fit_normalized`] and [`super::results`] do.

use ndarray::Array2;

use super::maps::{check_conditions, check_same_bins};
use super::model::{Params, Results};
use super::offsets::{condition_means, test_against_expected};
use super::tables::{number, sample_names};
use crate::error::{Error, Result};
use crate::expected::cis_curves;
use crate::expected::smooth::log_smooth;
use crate::io::{MatrixReader, StreamedPixels};
use crate::normalize::DiagonalCurve;

/// A loop between two bins of one chromosome (`bin1 <= bin2`, genome-wide ids).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LoopSite {
    /// Upstream anchor's bin.
    pub bin1: usize,
    /// Downstream anchor's bin.
    pub bin2: usize,
}

/// Settings of `diff loops`.
#[derive(Debug, Clone)]
pub struct LoopParams {
    /// Pixels each side of a loop's pixel summed with it (1: the 3 x 3 neighbourhood).
    pub half_width: usize,
    /// q-value under which a loop counts as changed (0.05).
    pub alpha: f64,
    /// Set aside the p-values of loops with a Cook's outlier (DESeq2's rule; true).
    pub cooks_filter: bool,
    /// The model's settings.
    pub model: Params,
}

impl Default for LoopParams {
    fn default() -> Self {
        LoopParams {
            half_width: 1,
            alpha: 0.05,
            cooks_filter: true,
            model: Params::default(),
        }
    }
}

/// Each loop's observed and expected counts per sample (one row per loop).
#[derive(Debug, Clone)]
pub struct LoopCounts {
    /// Raw counts summed over each loop's neighbourhood.
    pub observed: Array2<f64>,
    /// The expected raw count of the same pixels (the map's cis expected, `count.avg` smoothed
    /// as cooltools smooths it, at each pixel's diagonal, summed).
    pub expected: Array2<f64>,
}

/// The counts of `loops` in each of `readers` (maps on the same bins), `half_width` pixels
/// each side. Pixels below the diagonal or outside the loop's chromosome are not counted.
pub fn loop_counts(
    readers: &[&dyn MatrixReader],
    loops: &[LoopSite],
    half_width: usize,
) -> Result<LoopCounts> {
    // one map after another: each pass is parallel inside (the expected), and HDF5 reads hold
    // a process-wide lock that rayon tasks waiting on one another must not be caught behind
    let columns: Vec<(Vec<f64>, Vec<f64>)> = readers
        .iter()
        .map(|reader| one_map(*reader, loops, half_width))
        .collect::<Result<_>>()?;
    let shape = (loops.len(), readers.len());
    Ok(LoopCounts {
        observed: Array2::from_shape_fn(shape, |(l, s)| columns[s].0[l]),
        expected: Array2::from_shape_fn(shape, |(l, s)| columns[s].1[l]),
    })
}

/// Loops per batch of rows read together.
const BATCH: usize = 2048;

fn one_map(
    reader: &dyn MatrixReader,
    loops: &[LoopSite],
    half_width: usize,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let bins = reader.bins();
    let w = half_width;
    let curves: Vec<DiagonalCurve> = cis_curves(&StreamedPixels::new(reader), None, 0)?
        .into_iter()
        .map(|mut curve| {
            curve.expected = smoothed(&curve.expected);
            curve
        })
        .collect();
    let mut observed = vec![0.0; loops.len()];
    let expected: Vec<f64> = loops
        .iter()
        .map(|l| window_expected(&curves, *l, w))
        .collect();
    let mut order: Vec<usize> = (0..loops.len()).collect();
    order.sort_by_key(|&k| (loops[k].bin1, loops[k].bin2));
    for batch in order.chunks(BATCH) {
        let first = loops[batch[0]].bin1.saturating_sub(w);
        let last = (loops[batch[batch.len() - 1]].bin1 + w + 1).min(bins.n_bins());
        let (low, high) = batch.iter().fold((usize::MAX, 0), |(low, high), &k| {
            (low.min(loops[k].bin2), high.max(loops[k].bin2))
        });
        let cols = low.saturating_sub(w)..(high + w + 1).min(bins.n_bins());
        let rows_of: Vec<usize> = batch.iter().map(|&k| loops[k].bin1).collect();
        let chromosome: Vec<std::ops::Range<usize>> = batch
            .iter()
            .map(|&k| bins.chrom_bins(bins.bin(loops[k].bin1).chrom_id))
            .collect();
        reader.read_pixels(first..last, cols, &mut |block| {
            for ((&i, &j), &count) in block.bin1.iter().zip(&block.bin2).zip(&block.count) {
                let (i, j) = (i as usize, j as usize);
                let from = rows_of.partition_point(|&r| r + w < i);
                for (slot, &k) in batch.iter().enumerate().skip(from) {
                    if rows_of[slot] > i + w {
                        break;
                    }
                    if loops[k].bin2.abs_diff(j) <= w
                        && chromosome[slot].contains(&i)
                        && chromosome[slot].contains(&j)
                    {
                        observed[k] += count;
                    }
                }
            }
            Ok(())
        })?;
    }
    Ok((observed, expected))
}

/// A curve of `count.avg` per diagonal smoothed as cooltools' `count.avg.smoothed` (a Gaussian
/// of 0.1 in log10 distance, 5 sigmas, 10 points per sigma): one loop's pixels hardly move it,
/// so a loop that gains contacts does not raise its own expected (nor its neighbours' at the
/// same distance).
pub fn smoothed(expected: &[f64]) -> Vec<f64> {
    let distances: Vec<f64> = (0..expected.len()).map(|d| d as f64).collect();
    log_smooth(&distances, &[expected], 0.1, 5.0, 10).remove(0)
}

/// The expected raw count of a loop's window: the smoothed `count.avg` of each pixel's
/// diagonal, over the pixels on or above the diagonal within the loop's chromosome.
fn window_expected(curves: &[DiagonalCurve], site: LoopSite, w: usize) -> f64 {
    let Some(curve) = curves.iter().find(|c| c.bins.contains(&site.bin1)) else {
        return f64::NAN;
    };
    let mut sum = 0.0;
    for i in site.bin1.saturating_sub(w)..=site.bin1 + w {
        for j in site.bin2.saturating_sub(w)..=site.bin2 + w {
            if j < i || !curve.bins.contains(&i) || !curve.bins.contains(&j) {
                continue;
            }
            let value = curve.expected[j - i];
            if value.is_finite() {
                sum += value;
            }
        }
    }
    sum
}

/// The comparison of loops between two conditions.
#[derive(Debug, Clone)]
pub struct LoopComparison {
    /// The counts per loop and sample.
    pub counts: LoopCounts,
    /// Per-loop results (the contrast: the second condition against the first).
    pub results: Results,
    /// Mean of each loop's normalised counts (observed over normalisation factor) in each
    /// condition.
    pub condition_means: Array2<f64>,
    /// The q-value cut that `direction` uses.
    pub alpha: f64,
    /// Replicates of the first condition (the first columns of the counts).
    pub n_first: usize,
}

/// The normal quantile of a two-sided 95% interval.
const Z_95: f64 = 1.959_963_984_540_054;

impl LoopComparison {
    /// The 95% interval of loop `l`'s log2 fold change: ±1.96 standard errors.
    pub fn interval(&self, l: usize) -> (f64, f64) {
        let (lfc, se) = (self.results.log2_fold_change[l], self.results.lfc_se[l]);
        (lfc - Z_95 * se, lfc + Z_95 * se)
    }

    /// The samples' names, in the counts' column order: `A1`, `A2`, ..., `B1`, ...
    pub fn sample_names(&self) -> Vec<String> {
        sample_names(self.counts.observed.ncols(), self.n_first)
    }

    /// `up` (higher in the second condition), `down`, or `-` (not changed at the q-value cut,
    /// or not tested).
    pub fn direction(&self, l: usize) -> &'static str {
        let q = self.results.q_value[l];
        if q.is_nan() || q >= self.alpha {
            "-"
        } else if self.results.log2_fold_change[l] > 0.0 {
            "up"
        } else {
            "down"
        }
    }
}

/// Compares `loops` between the replicates of condition A (`first`) and B (`second`): counts,
/// normalisation factors (each loop's expected counts over their geometric mean across the
/// samples), the model and the Wald test of B against A.
pub fn compare_loops(
    first: &[&dyn MatrixReader],
    second: &[&dyn MatrixReader],
    loops: &[LoopSite],
    params: &LoopParams,
) -> Result<LoopComparison> {
    check_conditions(first.len() + second.len(), first.len())?;
    let readers: Vec<&dyn MatrixReader> = first.iter().chain(second).copied().collect();
    check_same_bins(&readers)?;
    let counts = loop_counts(&readers, loops, params.half_width)?;
    let bins = readers[0].bins();
    for (l, row) in counts.expected.rows().into_iter().enumerate() {
        if let Some(s) = row.iter().position(|e| e.is_nan() || *e <= 0.0) {
            let site = loops[l];
            return Err(Error::Data(format!(
                "loop {} ({}): {} has no contacts at its distance",
                l + 1,
                describe(bins, site),
                readers[s].source()
            )));
        }
    }
    let (results, factors) = test_against_expected(
        counts.observed.view(),
        counts.expected.view(),
        first.len(),
        &params.model,
        params.cooks_filter,
    )?;
    let condition_means = condition_means(counts.observed.view(), factors.view(), first.len());
    Ok(LoopComparison {
        counts,
        results,
        condition_means,
        alpha: params.alpha,
        n_first: first.len(),
    })
}

/// `chr:start-end x chr:start-end` of a loop's bins.
fn describe(bins: &crate::genome::BinTable, site: LoopSite) -> String {
    let (a, b) = (bins.bin(site.bin1), bins.bin(site.bin2));
    let name = &bins.chroms()[a.chrom_id].name;
    format!(
        "{name}:{}-{} x {name}:{}-{}",
        a.start, a.end, b.start, b.end
    )
}

/// The loops of BEDPE `records` on `bins`: each at the bins of its anchors' midpoints (as
/// `score loops` places them), upstream first. A loop between two chromosomes, on a chromosome
/// the map does not have, or past its chromosome's end is refused: `source` and the record's
/// number name it.
pub fn sites_of(
    bins: &crate::genome::BinTable,
    records: &[crate::io::bed::BedpeRecord],
    source: &str,
) -> Result<Vec<LoopSite>> {
    if records.is_empty() {
        return Err(Error::Data(format!("{source}: no loop in this file")));
    }
    records
        .iter()
        .enumerate()
        .map(|(k, record)| {
            let (a, b) = (&record.first, &record.second);
            let fail = |what: String| {
                Error::Data(format!("{source}: loop {} ({}:{}-{} x {}:{}-{}): {what}", k + 1, a.chrom, a.start, a.end, b.chrom, b.start, b.end))
            };
            if a.chrom != b.chrom {
                return Err(fail("its anchors are on two chromosomes; diff loops compares loops within chromosomes".to_string()));
            }
            let chrom_id = bins
                .chrom_id(&a.chrom)
                .ok_or_else(|| fail(format!("{} is not a chromosome of the maps", a.chrom)))?;
            let length = bins.chroms()[chrom_id].length_bp;
            for anchor in [a, b] {
                if anchor.end > length || anchor.start >= anchor.end {
                    return Err(fail(format!(
                        "an anchor lies outside {} (length {length})",
                        a.chrom
                    )));
                }
            }
            let bin = |r: &crate::io::bed::BedRecord| bins.bin_at(chrom_id, (r.start + r.end) / 2);
            let (x, y) = (bin(a), bin(b));
            Ok(LoopSite {
                bin1: x.min(y),
                bin2: x.max(y),
            })
        })
        .collect()
}

/// The comparison as BEDPE with a header line: each loop's anchors as given, `baseMean`,
/// `log2FoldChange` with its 95% interval (`lfc_low`, `lfc_high`: ±1.96 standard errors),
/// `lfcSE`, `pvalue`, `qvalue`, the mean normalised counts of each condition, `direction`,
/// then each sample's count (headed `count_A1` ...).
pub fn loops_bedpe(records: &[crate::io::bed::BedpeRecord], comparison: &LoopComparison) -> String {
    let mut out = String::from(
        "chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tbaseMean\tlog2FoldChange\tlfc_low\tlfc_high\tlfcSE\tpvalue\tqvalue\tmean_A\tmean_B\tdirection",
    );
    for name in comparison.sample_names() {
        out.push_str("\tcount_");
        out.push_str(&name);
    }
    out.push('\n');
    let r = &comparison.results;
    for (l, record) in records.iter().enumerate() {
        let (a, b) = (&record.first, &record.second);
        let (low, high) = comparison.interval(l);
        let fields = [
            number(r.base_mean[l]),
            number(r.log2_fold_change[l]),
            number(low),
            number(high),
            number(r.lfc_se[l]),
            number(r.p_value[l]),
            number(r.q_value[l]),
            number(comparison.condition_means[[l, 0]]),
            number(comparison.condition_means[[l, 1]]),
            comparison.direction(l).to_string(),
        ];
        out.push_str(&format!(
            "{}\t{}\t{}\t{}\t{}\t{}\t{}",
            a.chrom,
            a.start,
            a.end,
            b.chrom,
            b.start,
            b.end,
            fields.join("\t")
        ));
        for count in comparison.counts.observed.row(l) {
            out.push_str(&format!("\t{count}"));
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::{OpenOptions, open_matrix};

    /// Counts and expected against a dense copy of the map summed by hand: the upper triangle's
    /// pixels in each window, and per diagonal the mean over its pixels (cooltools' raw
    /// `count.avg`: every pixel of a diagonal counts, zeros included), smoothed.
    #[test]
    #[allow(clippy::needless_range_loop)] // the window's (i, j) index the dense copy
    fn window_sums_equal_a_dense_naive_sum() {
        let reader = open_matrix("data/sim_extrusion.5kb.cool", &OpenOptions::default()).unwrap();
        let n = reader.bins().n_bins();
        let mut dense = vec![vec![0.0; n]; n];
        reader
            .read_pixels(0..n, 0..n, &mut |block| {
                for ((&i, &j), &c) in block.bin1.iter().zip(&block.bin2).zip(&block.count) {
                    dense[i as usize][j as usize] += c;
                }
                Ok(())
            })
            .unwrap();
        let means: Vec<f64> = (0..n)
            .map(|d| (0..n - d).map(|i| dense[i][i + d]).sum::<f64>() / (n - d) as f64)
            .collect();
        let smooth = smoothed(&means);
        let diagonal_mean = |d: usize| smooth[d];
        let loops = [
            LoopSite { bin1: 20, bin2: 50 },
            LoopSite { bin1: 0, bin2: 3 },
            LoopSite {
                bin1: 100,
                bin2: 101,
            },
            LoopSite {
                bin1: 150,
                bin2: 199,
            },
            LoopSite { bin1: 54, bin2: 84 },
            LoopSite { bin1: 20, bin2: 50 },
        ];
        for w in [0, 1, 2] {
            let counts = loop_counts(&[reader.as_ref(), reader.as_ref()], &loops, w).unwrap();
            for (l, site) in loops.iter().enumerate() {
                let (mut observed, mut expected) = (0.0, 0.0);
                for i in site.bin1.saturating_sub(w)..=(site.bin1 + w).min(n - 1) {
                    for j in site.bin2.saturating_sub(w)..=(site.bin2 + w).min(n - 1) {
                        if j >= i {
                            observed += dense[i][j];
                            expected += diagonal_mean(j - i);
                        }
                    }
                }
                for sample in 0..2 {
                    assert_eq!(counts.observed[[l, sample]], observed, "loop {l}, w {w}");
                    let got = counts.expected[[l, sample]];
                    assert!(
                        (got - expected).abs() <= 1e-12 * expected,
                        "loop {l} w {w}: {got} {expected}"
                    );
                }
            }
        }
    }
}
