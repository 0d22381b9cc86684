//! Observed / expected maps.
//!
//! For a cis pixel `(i, j)` of region `r` at diagonal `d = j - i`, with observed value
//! `o = count * w[i] * w[j]` (balanced, the default) or `o = count` (raw):
//!
//! | method | value |
//! |---|---|
//! | `oe` | `o / E[r][d]` |
//! | `log2oe` | `log2(o / E[r][d])` |
//! | `zscore` | `(o - E[r][d]) / SD[r][d]` |
//!
//! `E[r][d]` is the expected value of diagonal `d` in region `r` as `cooltools expected-cis` defines
//! it (`balanced.avg` or `count.avg`: the diagonal's sum over its number of valid pixels, zeros
//! included), and `SD[r][d]` the standard deviation over the same valid pixels, zeros included:
//! `sqrt(sum(o^2) / n_valid - E^2)`. Only stored (non-zero) pixels are written, and pixels whose
//! value is not finite are dropped (masked bins, diagonals whose expected is NaN or zero — the
//! ignored diagonals among them — and, for `zscore`, diagonals without spread, such as the last
//! diagonal of a region, which holds one pixel). For cis pixels the `oe` values are those of cooltools'
//! `sandbox.obs_over_exp_cooler.obs_over_exp` (unsmoothed `balanced.avg`); unlike it, trans pixels
//! and pixels outside the regions are dropped rather than divided by a trans expected.

use std::ops::Range;

use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::io::{MatrixInfo, MatrixReader};
use crate::matrix::{CountType, Weights};
use crate::matrix::{PixelBlock, PixelSource};

/// What to compute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// observed / expected
    Oe,
    /// log2(observed / expected)
    Log2Oe,
    /// (observed - expected) / standard deviation of the diagonal
    Zscore,
}

/// The expected curve of one region: bins `bins`, one value per diagonal `0..bins.len()`.
#[derive(Clone, Debug, PartialEq)]
pub struct DiagonalCurve {
    /// Genome-wide bin ids of the region (half-open).
    pub bins: Range<usize>,
    /// Expected value per diagonal (`NaN` where undefined).
    pub expected: Vec<f64>,
    /// Number of valid pixels per diagonal (used by `zscore`).
    pub n_valid: Vec<f64>,
}

/// Applies a [`Method`] to pixel blocks, given the expected curves and optional weights.
#[derive(Clone, Debug)]
pub struct Normalizer {
    method: Method,
    weights: Option<Vec<f64>>,
    /// Region index of each bin (`u32::MAX`: in no region).
    region_of_bin: Vec<u32>,
    curves: Vec<DiagonalCurve>,
    /// Standard deviation per region and diagonal (zscore only).
    deviations: Option<Vec<Vec<f64>>>,
}

impl Normalizer {
    /// A normalizer over `n_bins` bins. `weights` balances the counts (`None`: raw counts).
    /// Regions must not overlap, and each curve must cover every diagonal of its region.
    ///
    /// # Examples
    ///
    /// A chromosome whose diagonal `d` holds `10 - d` everywhere is its own expected: observed /
    /// expected is 1 on every diagonal that has an expected value (the first two are ignored),
    /// and its z-score undefined (no spread: every pixel dropped).
    ///
    /// ```
    /// use contactmap::expected::cis_curves;
    /// use contactmap::genome::{BinTable, Chrom};
    /// use contactmap::io::{load_pixels, InMemory, MatrixReader};
    /// use contactmap::normalize::{Method, Normalizer};
    /// use contactmap::matrix::{CountType, MatrixBuilder};
    ///
    /// let bins = BinTable::fixed(vec![Chrom::new("chr1", 10_000)], 1_000)?;
    /// let mut builder = MatrixBuilder::new(bins, CountType::Integer);
    /// for i in 0..10u64 {
    ///     for j in i..10 {
    ///         builder.push(i, j, (10 - (j - i)) as f64)?;
    ///     }
    /// }
    /// let matrix = InMemory::new("example".into(), builder.build());
    /// let pixels = load_pixels(&matrix, u64::MAX)?;
    /// let curves = cis_curves(&pixels, None, 2)?;
    /// let block = matrix.matrix().all_pixels();
    ///
    /// let oe = Normalizer::new(Method::Oe, 10, None, curves.clone())?;
    /// let normalized = oe.apply(&block)?;
    /// assert_eq!(normalized.len(), 8 * 9 / 2); // diagonals 2..10
    /// assert!(normalized.count.iter().all(|&v| v == 1.0));
    /// assert!(normalized.bin1.iter().zip(&normalized.bin2).all(|(i, j)| j - i >= 2));
    ///
    /// let mut zscore = Normalizer::new(Method::Zscore, 10, None, curves)?;
    /// assert!(zscore.needs_deviations());
    /// zscore.compute_deviations(&pixels)?;
    /// assert!(zscore.apply(&block)?.is_empty());
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn new(
        method: Method,
        n_bins: usize,
        weights: Option<Vec<f64>>,
        curves: Vec<DiagonalCurve>,
    ) -> Result<Self> {
        if let Some(w) = &weights {
            if w.len() != n_bins {
                return Err(Error::Data(format!(
                    "{} weights for {n_bins} bins",
                    w.len()
                )));
            }
        }
        let mut region_of_bin = vec![u32::MAX; n_bins];
        for (r, curve) in curves.iter().enumerate() {
            if curve.bins.end > n_bins {
                return Err(Error::Data(format!(
                    "expected region {r} (bins {}..{}) is past the {n_bins} bins of the matrix",
                    curve.bins.start, curve.bins.end
                )));
            }
            if curve.expected.len() < curve.bins.len() || curve.n_valid.len() < curve.bins.len() {
                return Err(Error::Data(format!(
                    "expected region {r} has {} diagonals for {} bins",
                    curve.expected.len(),
                    curve.bins.len()
                )));
            }
            for slot in &mut region_of_bin[curve.bins.clone()] {
                if *slot != u32::MAX {
                    return Err(Error::Data(format!(
                        "expected regions overlap (region {r} and region {})",
                        *slot
                    )));
                }
                *slot = r as u32;
            }
        }
        Ok(Normalizer {
            method,
            weights,
            region_of_bin,
            curves,
            deviations: None,
        })
    }

    /// True when [`Normalizer::compute_deviations`] must run before [`Normalizer::apply`].
    pub fn needs_deviations(&self) -> bool {
        self.method == Method::Zscore && self.deviations.is_none()
    }

    /// One pass over the pixels for the per-diagonal standard deviations (`zscore`).
    pub fn compute_deviations(&mut self, source: &impl PixelSource) -> Result<()> {
        let sizes: Vec<usize> = self.curves.iter().map(|c| c.bins.len()).collect();
        let offsets: Vec<usize> = sizes
            .iter()
            .scan(0, |total, &n| {
                let start = *total;
                *total += n;
                Some(start)
            })
            .collect();
        let total: usize = sizes.iter().sum();
        let this = &*self;
        let squares = source.pass(
            || vec![0.0f64; total],
            |mut acc, slice| {
                for (i, j, count) in slice.iter() {
                    if let Some((r, d, value)) = this.observed(i, j, count) {
                        acc[offsets[r] + d] += value * value;
                    }
                }
                acc
            },
            |mut a, b| {
                a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
                a
            },
        )?;
        let deviations = self
            .curves
            .iter()
            .enumerate()
            .map(|(r, curve)| {
                (0..curve.bins.len())
                    .map(|d| {
                        let n = curve.n_valid[d];
                        let mean = curve.expected[d];
                        let variance = squares[offsets[r] + d] / n - mean * mean;
                        if n > 0.0 && variance > 0.0 {
                            variance.sqrt()
                        } else {
                            f64::NAN
                        }
                    })
                    .collect()
            })
            .collect();
        self.deviations = Some(deviations);
        Ok(())
    }

    /// Region, diagonal and observed value of a cis pixel in a region; `None` otherwise.
    fn observed(&self, i: usize, j: usize, count: f64) -> Option<(usize, usize, f64)> {
        let r = self.region_of_bin[i];
        if r == u32::MAX || self.region_of_bin[j] != r {
            return None;
        }
        let value = match &self.weights {
            Some(w) => count * w[i] * w[j],
            None => count,
        };
        value.is_finite().then_some((r as usize, j - i, value))
    }

    /// Transform a sorted block of stored pixels; pixels without a finite value are dropped.
    pub fn apply(&self, block: &PixelBlock) -> Result<PixelBlock> {
        if self.needs_deviations() {
            return Err(Error::Argument(
                "zscore needs the per-diagonal deviations: call compute_deviations first".into(),
            ));
        }
        let mut out = PixelBlock::with_capacity(block.len());
        for k in 0..block.len() {
            let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
            let Some((r, d, observed)) = self.observed(i, j, block.count[k]) else {
                continue;
            };
            let expected = self.curves[r].expected[d];
            let value = match self.method {
                Method::Oe => observed / expected,
                Method::Log2Oe => (observed / expected).log2(),
                Method::Zscore => {
                    let sd = self.deviations.as_ref().map_or(f64::NAN, |s| s[r][d]);
                    (observed - expected) / sd
                }
            };
            if value.is_finite() {
                out.push(block.bin1[k], block.bin2[k], value);
            }
        }
        Ok(out)
    }
}

/// A reader whose pixels are the normalised values of another reader's (float counts, no weight
/// column; pixels the normaliser drops, masked bins, are left out): what `contactmap normalize`
/// writes to a .cool or a table with any of the io writers.
pub struct NormalizedReader<'a> {
    inner: &'a dyn MatrixReader,
    normalizer: &'a Normalizer,
    source: String,
}

impl<'a> NormalizedReader<'a> {
    /// The pixels of `inner` through `normalizer`; `source` names the result in messages.
    ///
    /// # Examples
    ///
    /// Observed / expected of the balanced mm9 map, as cooltools computes it
    /// (`data/reference/CN.mm9.10000kb.cis_oe.tsv`, `obs_over_exp` of cooltools' sandbox: its
    /// first pixel is `(0, 2)`, 1.5293759028435407).
    ///
    /// ```
    /// use contactmap::expected::cis_curves;
    /// use contactmap::io::{load_pixels, open_matrix, MatrixReader, OpenOptions};
    /// use contactmap::normalize::{Method, NormalizedReader, Normalizer};
    ///
    /// let reader = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
    /// let weights = reader.weights("weight")?.values;
    /// let pixels = load_pixels(&*reader, u64::MAX)?;
    /// let curves = cis_curves(&pixels, Some(&weights), 2)?;
    /// let n = reader.bins().n_bins();
    /// let normalizer = Normalizer::new(Method::Oe, n, Some(weights), curves)?;
    /// let oe = NormalizedReader::new(&*reader, &normalizer, "mm9 o/e".into());
    /// let mut values = Vec::new();
    /// oe.read_pixels(0..n, 0..n, &mut |block| {
    ///     for k in 0..block.len() {
    ///         values.push((block.bin1[k], block.bin2[k], block.count[k]));
    ///     }
    ///     Ok(())
    /// })?;
    /// assert_eq!(values.len(), 1_440); // the lines of the reference
    /// let (i, j, value) = values[0];
    /// assert_eq!((i, j), (0, 2));
    /// assert!((value - 1.5293759028435407).abs() < 1e-10 * value);
    /// assert!(oe.weight_names().is_empty());
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn new(inner: &'a dyn MatrixReader, normalizer: &'a Normalizer, source: String) -> Self {
        NormalizedReader {
            inner,
            normalizer,
            source,
        }
    }
}

impl MatrixReader for NormalizedReader<'_> {
    fn source(&self) -> &str {
        &self.source
    }

    fn bins(&self) -> &BinTable {
        self.inner.bins()
    }

    fn count_type(&self) -> CountType {
        CountType::Float
    }

    fn weight_names(&self) -> Vec<String> {
        Vec::new()
    }

    fn weights(&self, name: &str) -> Result<Weights> {
        Err(Error::Argument(format!(
            "a normalised matrix has no weight column '{name}'"
        )))
    }

    fn info(&self) -> MatrixInfo {
        self.inner.info()
    }

    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.inner.read_pixels(rows, cols, &mut |block| {
            let out = self.normalizer.apply(block)?;
            if out.is_empty() { Ok(()) } else { sink(&out) }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::{BinTable, Chrom};
    use crate::matrix::{CountType, MatrixBuilder, Pixels};

    /// A 2-chromosome matrix and its expected computed naively from the dense matrix.
    fn fixture() -> (Pixels, PixelBlock, Vec<DiagonalCurve>, Vec<f64>) {
        let bins = BinTable::fixed(vec![Chrom::new("a", 60), Chrom::new("b", 40)], 10).unwrap();
        let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
        for i in 0..10u64 {
            for j in i..10 {
                if (i * 3 + j) % 4 != 0 {
                    builder.push(i, j, (1 + (i + 2 * j) % 5) as f64).unwrap();
                }
            }
        }
        let matrix = builder.build();
        let weights: Vec<f64> = (0..10)
            .map(|k| {
                if k == 2 {
                    f64::NAN
                } else {
                    1.0 + k as f64 / 10.0
                }
            })
            .collect();
        let n = bins.n_bins();
        let dense = matrix.dense(0..n, 0..n);
        let curves = [0..6, 6..10]
            .into_iter()
            .map(|range| {
                let len = range.len();
                let mut expected = vec![0.0; len];
                let mut n_valid = vec![0.0; len];
                for d in 0..len {
                    let (mut sum, mut valid) = (0.0, 0.0);
                    for i in range.start..range.end - d {
                        let v = dense[[i, i + d]] * weights[i] * weights[i + d];
                        if !v.is_nan() {
                            sum += v;
                            valid += 1.0;
                        }
                    }
                    expected[d] = sum / valid;
                    n_valid[d] = valid;
                }
                DiagonalCurve {
                    bins: range,
                    expected,
                    n_valid,
                }
            })
            .collect();
        let all = matrix.all_pixels();
        let mut pixels = Pixels::with_capacity(bins, CountType::Integer, all.len()).unwrap();
        pixels.extend(&all).unwrap();
        (pixels, all, curves, weights)
    }

    #[test]
    fn oe_divides_by_the_diagonal_mean_and_drops_trans_and_masked_pixels() {
        let (_, all, curves, weights) = fixture();
        let normalizer =
            Normalizer::new(Method::Oe, 10, Some(weights.clone()), curves.clone()).unwrap();
        let out = normalizer.apply(&all).unwrap();
        for k in 0..out.len() {
            let (i, j) = (out.bin1[k] as usize, out.bin2[k] as usize);
            assert!(i != 2 && j != 2);
            let r = usize::from(i >= 6);
            assert_eq!(usize::from(j >= 6), r, "trans pixel kept");
            let observed = all.count[all
                .bin1
                .iter()
                .zip(&all.bin2)
                .position(|(&a, &b)| (a, b) == (i as u64, j as u64))
                .unwrap()]
                * weights[i]
                * weights[j];
            let expected = curves[r].expected[j - i];
            assert!((out.count[k] - observed / expected).abs() < 1e-12);
        }
        // The mean of o/e over the valid pixels of a diagonal (zeros included) is 1.
        let mut sums = [0.0; 6];
        for k in 0..out.len() {
            if out.bin1[k] < 6 {
                sums[(out.bin2[k] - out.bin1[k]) as usize] += out.count[k];
            }
        }
        for (d, sum) in sums.iter().enumerate() {
            if curves[0].expected[d] > 0.0 {
                assert!(
                    (sum / curves[0].n_valid[d] - 1.0).abs() < 1e-12,
                    "diagonal {d}"
                );
            }
        }
    }

    #[test]
    fn zscores_have_zero_mean_and_unit_variance_per_diagonal() {
        let (pixels, all, curves, weights) = fixture();
        let mut normalizer =
            Normalizer::new(Method::Zscore, 10, Some(weights), curves.clone()).unwrap();
        assert!(normalizer.apply(&all).is_err());
        normalizer.compute_deviations(&pixels).unwrap();
        let out = normalizer.apply(&all).unwrap();
        // Over all valid pixels of diagonal d (absent ones have z = -E/SD): mean 0, variance 1.
        let deviations = normalizer.deviations.clone().unwrap();
        for (d, &sd) in deviations[0].iter().enumerate().take(4).skip(1) {
            let (e, n) = (curves[0].expected[d], curves[0].n_valid[d]);
            let present: Vec<f64> = (0..out.len())
                .filter(|&k| {
                    out.bin1[k] < 6 && out.bin2[k] < 6 && (out.bin2[k] - out.bin1[k]) as usize == d
                })
                .map(|k| out.count[k])
                .collect();
            let absent = n - present.len() as f64;
            let mean = (present.iter().sum::<f64>() + absent * (-e / sd)) / n;
            let var = (present.iter().map(|z| z * z).sum::<f64>() + absent * (e / sd).powi(2)) / n
                - mean * mean;
            assert!(
                mean.abs() < 1e-9 && (var - 1.0).abs() < 1e-9,
                "diagonal {d}: mean {mean}, var {var}"
            );
        }
    }

    #[test]
    fn overlapping_regions_are_refused() {
        let curve = |bins: Range<usize>| DiagonalCurve {
            expected: vec![1.0; bins.len()],
            n_valid: vec![1.0; bins.len()],
            bins,
        };
        assert!(Normalizer::new(Method::Oe, 10, None, vec![curve(0..6), curve(5..10)]).is_err());
        assert!(Normalizer::new(Method::Oe, 10, None, vec![curve(0..11)]).is_err());
    }
}
