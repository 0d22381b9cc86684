//! The directionality index (Dixon et al. 2012, Nature), exactly as cooltools 0.7.1 (the peer,
//! `cooltools.api.directionality.directionality`) computes it.
//!
//! For bin `k` and a window of `w` bins, the upstream sum `a` adds the pixels `(k - s, k)` and
//! the downstream sum `b` the pixels `(k, k + s)`, for `ignore_diags <= s < w` (the peer's
//! window, not twice it), inside the view region. Conventions, as the peer:
//!
//! - values are balanced (`count * w_i * w_j`, pixels touching a NaN-weight bin left out) or raw
//!   counts when no weights are given;
//! - the ratio is `(b - a) / (a + b)`; the index is the signed chi-square
//!   `sign(b - a) * ((a - e)^2 + (b - e)^2) / e` with `e = (a + b) / 2`;
//! - bins within `min_dist_bad_bin - 1` bins of a bad bin, or of a region edge (the peer pads the
//!   mask with bad bins), are masked (`bad_bin_masked`) and get NaN; every non-finite value is
//!   NaN. Default `min_dist_bad_bin` 2.
//!
//! One streamed pass over the pixels with compensated sums; each slice holds only the rows it
//! touches.

use crate::error::{Error, Result};
use crate::genome::View;
use crate::matrix::{PixelSlice, PixelSource};

use super::insulation::{Layout, Partial, check_weights, window_bins};

/// Parameters of [`directionality`].
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionalityParams {
    /// Window in bp, a positive multiple of the bin size.
    pub window_bp: u64,
    /// Diagonals left out (distance `s < ignore_diags`).
    pub ignore_diags: usize,
    /// Mask bins closer than this to a bad bin or a region edge (default 2).
    pub min_dist_bad_bin: usize,
}

impl DirectionalityParams {
    /// Check the values: a window of at least 1 bp (a multiple of the bin size, which
    /// [`directionality`] checks with the bins).
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::tads::directionality::DirectionalityParams;
    ///
    /// let bad = DirectionalityParams { window_bp: 0, ignore_diags: 2, min_dist_bad_bin: 0 };
    /// assert_eq!(bad.check().unwrap_err().to_string(), "window_bp 0: expected a positive window");
    /// ```
    pub fn check(&self) -> Result<()> {
        if self.window_bp == 0 {
            return Err(Error::parameter(
                "window_bp",
                0,
                "expected a positive window",
            ));
        }
        Ok(())
    }

    /// Defaults (`ignore_diags` 2, `min_dist_bad_bin` 2) with this window.
    pub fn new(window_bp: u64) -> Self {
        DirectionalityParams {
            window_bp,
            ignore_diags: 2,
            min_dist_bad_bin: 2,
        }
    }
}

/// The directionality table: one row per bin of each view region, in view order.
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionalityTable {
    /// Genome-wide bin id of each row.
    pub bins: Vec<usize>,
    /// Index into `view.regions()` of each row.
    pub region: Vec<usize>,
    /// Bins masked for being near a bad bin or a region edge.
    pub bad_bin_masked: Vec<bool>,
    /// Directionality ratio `(b - a) / (a + b)`.
    pub ratio: Vec<f64>,
    /// Directionality index (signed chi-square).
    pub index: Vec<f64>,
    /// Window in bp.
    pub window_bp: u64,
}

/// The peer's `bad_bin_neighbor`: bad bins and their neighbours closer than `min_dist`, bins
/// near the region edges included.
fn bad_bin_neighbors(bad: &[bool], min_dist: usize) -> Vec<bool> {
    let n = bad.len();
    (0..n)
        .map(|k| {
            (0..min_dist).any(|s| {
                if s == 0 {
                    bad[k]
                } else {
                    k < s || bad[k - s] || k + s >= n || bad[k + s]
                }
            })
        })
        .collect()
}

/// The directionality ratio and index of `source` over `view`: balanced with `weights`
/// (multiplicative, NaN = bad bin) or raw counts when `weights` is `None`.
///
/// Errors: a window that is zero or not a multiple of the bin size, variable-size bins, weights
/// of the wrong length.
///
/// # Examples
///
/// Bins just after a boundary see their domain downstream (positive index), bins just before
/// it see theirs upstream (negative).
///
/// ```
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
/// use contactmap::tads::directionality::{directionality, DirectionalityParams};
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
/// let table = directionality(&pixels, None, &view, &DirectionalityParams::new(5_000))?;
/// assert_eq!((table.bins.len(), table.window_bp), (100, 5_000));
/// for boundary in [25, 50, 75] {
///     assert!(table.index[boundary + 1] > 0.0 && table.ratio[boundary + 1] > 0.0);
///     assert!(table.index[boundary - 2] < 0.0 && table.ratio[boundary - 2] < 0.0);
/// }
/// // bins closer than 2 to the region's edges are masked
/// assert!(table.bad_bin_masked[0] && table.index[0].is_nan());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn directionality<S: PixelSource>(
    source: &S,
    weights: Option<&[f64]>,
    view: &View,
    params: &DirectionalityParams,
) -> Result<DirectionalityTable> {
    params.check()?;
    let bins = source.bins();
    check_weights(bins, weights)?;
    let w = window_bins(bins, params.window_bp)?;
    let g = params.ignore_diags;
    let layout = Layout::new(view, bins.n_bins(), 0);

    // Column 0: upstream sum a (at bin j), column 1: downstream sum b (at bin i).
    let fold = |mut part: Partial, slice: PixelSlice<'_>| {
        for p in 0..slice.len() {
            let i = slice.bin1[p] as usize;
            let j = slice.bin2[p] as usize;
            let d = j - i;
            if d < g || d >= w {
                continue;
            }
            let count = slice.count[p];
            let value = match weights {
                Some(wt) => count * wt[i] * wt[j],
                None => count,
            };
            if value.is_nan() {
                continue;
            }
            layout.for_regions(i, j, |_, base| {
                part.reserve(base + i, base + i + w + 1);
                part.add(base + j, 0, value);
                part.add(base + i, 1, value);
            });
        }
        part
    };
    let sums = source.pass(|| Partial::new(2), fold, Partial::merge)?;

    let mut table = DirectionalityTable {
        bins: Vec::new(),
        region: Vec::new(),
        bad_bin_masked: Vec::new(),
        ratio: Vec::new(),
        index: Vec::new(),
        window_bp: params.window_bp,
    };
    for (r, region) in view.regions().iter().enumerate() {
        let bad: Vec<bool> = region
            .bins
            .clone()
            .map(|bin| weights.is_some_and(|wt| wt[bin].is_nan()))
            .collect();
        let masked = bad_bin_neighbors(&bad, params.min_dist_bad_bin);
        let offset = layout.offsets[r];
        for (k, bin) in region.bins.clone().enumerate() {
            let a = sums.value(offset + k, 0);
            let b = sums.value(offset + k, 1);
            let ratio = (b - a) / (a + b);
            let e = (a + b) / 2.0;
            let sign = if b > a {
                1.0
            } else if b < a {
                -1.0
            } else if b == a {
                0.0
            } else {
                f64::NAN
            };
            let index = sign * ((a - e) * (a - e) + (b - e) * (b - e)) / e;
            let clean = |v: f64| {
                if masked[k] || !v.is_finite() {
                    f64::NAN
                } else {
                    v
                }
            };
            table.bins.push(bin);
            table.region.push(r);
            table.bad_bin_masked.push(masked[k]);
            table.ratio.push(clean(ratio));
            table.index.push(clean(index));
        }
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::super::insulation::tests::{column, max_rel};
    use super::*;
    use crate::io::tables::Table;
    use crate::io::{OpenOptions, StreamedPixels, open_matrix};

    #[test]
    fn edges_and_bad_bins_are_masked_as_the_peer() {
        let bad = [false, false, true, false, false, false, false];
        assert_eq!(
            bad_bin_neighbors(&bad, 2),
            vec![true, true, true, true, false, false, true]
        );
        assert_eq!(bad_bin_neighbors(&bad, 0), vec![false; 7]);
        assert_eq!(bad_bin_neighbors(&bad, 1), bad.to_vec());
    }

    #[test]
    fn sums_match_a_dense_naive_computation() {
        use crate::genome::{BinTable, Chrom};
        use crate::matrix::{CountType, PixelBlock, Pixels};
        let bins = BinTable::fixed(vec![Chrom::new("a", 230), Chrom::new("b", 170)], 10).unwrap();
        let n = bins.n_bins();
        let value = |i: usize, j: usize| ((i * 7 + j * 3) % 11) as f64;
        let mut block = PixelBlock::default();
        for i in 0..n {
            for j in i..n {
                if value(i, j) != 0.0 {
                    block.push(i as u64, j as u64, value(i, j));
                }
            }
        }
        let mut pixels = Pixels::with_capacity(bins.clone(), CountType::Float, 0).unwrap();
        pixels.extend(&block).unwrap();
        let weights: Vec<f64> = (0..n)
            .map(|k| {
                if k % 9 == 4 {
                    f64::NAN
                } else {
                    1.0 + k as f64 / 50.0
                }
            })
            .collect();
        let view = View::chromosomes(&bins);
        let params = DirectionalityParams {
            window_bp: 50,
            ignore_diags: 1,
            min_dist_bad_bin: 2,
        };
        let table = directionality(&pixels, Some(&weights), &view, &params).unwrap();
        let balanced = |i: usize, j: usize| value(i, j) * weights[i] * weights[j];
        for (row, &bin) in table.bins.iter().enumerate() {
            let range = view.regions()[table.region[row]].bins.clone();
            let (mut a, mut b) = (0.0, 0.0);
            for s in 1..5 {
                if bin >= range.start + s && !balanced(bin - s, bin).is_nan() {
                    a += balanced(bin - s, bin);
                }
                if bin + s < range.end && !balanced(bin, bin + s).is_nan() {
                    b += balanced(bin, bin + s);
                }
            }
            let local = bin - range.start;
            let near_bad = (bin.saturating_sub(1)..=bin + 1).any(|k| k % 9 == 4)
                || local == 0
                || bin + 1 == range.end;
            assert_eq!(table.bad_bin_masked[row], near_bad, "bin {bin}");
            let e = (a + b) / 2.0;
            let (ratio, index) = if near_bad {
                (f64::NAN, f64::NAN)
            } else {
                (
                    (b - a) / (a + b),
                    (b - a).signum() * ((a - e).powi(2) + (b - e).powi(2)) / e,
                )
            };
            assert!(max_rel(&[table.ratio[row]], &[ratio]) < 1e-12);
            assert!(max_rel(&[table.index[row]], &[index]) < 1e-12);
        }
    }

    fn parity(uri: &str, reference_path: &str, window_bp: u64) {
        let reader = open_matrix(uri, &OpenOptions::default()).unwrap();
        let weights = reader.weights("weight").unwrap().values;
        let source = StreamedPixels::new(reader.as_ref());
        let view = View::chromosomes(source.bins());
        let table = directionality(
            &source,
            Some(&weights),
            &view,
            &DirectionalityParams::new(window_bp),
        )
        .unwrap();
        let reference = Table::read(reference_path).unwrap();
        let masked: Vec<bool> = column(&reference, "bad_bin_masked")
            .iter()
            .map(|&v| v == 1.0)
            .collect();
        assert_eq!(table.bad_bin_masked, masked);
        let ratio = max_rel(
            &table.ratio,
            &column(&reference, &format!("directionality_ratio_{window_bp}")),
        );
        let index = max_rel(
            &table.index,
            &column(&reference, &format!("directionality_index_{window_bp}")),
        );
        eprintln!("{uri}: max rel diff ratio {ratio:.3e} index {index:.3e}");
        assert!(ratio <= 1e-8 && index <= 1e-8);
    }

    #[test]
    fn dm6_matches_cooltools() {
        parity(
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/data/cooler_test_file.mcool::/resolutions/100000"
            ),
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/data/reference/tads/dm6_100kb.directionality_500000.tsv.gz"
            ),
            500000,
        );
    }

    #[test]
    fn yeast_matches_cooltools() {
        parity(
            concat!(env!("CARGO_MANIFEST_DIR"), "/data/yeast.10kb.cool"),
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/data/reference/tads/yeast_10kb.directionality_50000.tsv.gz"
            ),
            50000,
        );
    }
}
