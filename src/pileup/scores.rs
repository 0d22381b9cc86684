//! Scores of a pileup: coolpuppy 1.1.0's (`lib/numutils.py`) and Juicer APA's
//! (`APARegionStatistics`).
//!
//! All take the pileup as a square matrix; NaN pixels are left out of means and sums as numpy's
//! `nanmean` / `nansum` leave them out.

use ndarray::{Array2, ArrayView2, s};
use statrs::statistics::Statistics;

use crate::error::{Error, Result};

/// The mean of the non-NaN values of `values` (NaN when there are none).
fn nanmean<'a>(values: impl IntoIterator<Item = &'a f64>) -> f64 {
    values.into_iter().filter(|v| !v.is_nan()).mean()
}

fn nansum<'a>(values: impl IntoIterator<Item = &'a f64>) -> f64 {
    values.into_iter().filter(|v| !v.is_nan()).sum()
}

/// coolpuppy's `get_enrichment(amap, n)`: the mean of the central `n x n` pixels (for even `n`,
/// `(n + 1) x (n + 1)`, as coolpuppy slices). `None` when the pileup is smaller than that.
pub fn enrichment(pileup: ArrayView2<f64>, n: usize) -> Option<f64> {
    let c = pileup.nrows() / 2;
    if c < n {
        return None;
    }
    let (lo, hi) = (c - n / 2, c + n / 2 + 1);
    Some(nanmean(pileup.slice(s![lo..hi, lo..hi])))
}

/// coolpuppy's `get_cornerCV(amap, i)`: the coefficient of variation (population standard
/// deviation over mean) of the finite values of the top-left and bottom-right `i x i` corners.
pub fn corner_cv(pileup: ArrayView2<f64>, i: usize) -> f64 {
    let n = pileup.nrows();
    let i = i.min(n);
    let values: Vec<f64> = pileup
        .slice(s![..i, ..i])
        .iter()
        .chain(pileup.slice(s![n - i.., n - i..]).iter())
        .copied()
        .filter(|v| v.is_finite())
        .collect();
    values.iter().population_std_dev() / values.iter().mean()
}

/// The central part of a rescaled local pileup, `c = n / (2 flank + 1)` pixels in from each side;
/// `None` unless `n` is a multiple of `2 flank + 1`.
fn domain_edge(n: usize, rescale_flank: usize) -> Option<usize> {
    let parts = 2 * rescale_flank + 1;
    n.is_multiple_of(parts).then_some(n / parts)
}

/// coolpuppy's `get_local_enrichment(amap, flank)`: the mean of the domain (the central part of a
/// rescaled local pileup).
pub fn local_enrichment(pileup: ArrayView2<f64>, rescale_flank: usize) -> Option<f64> {
    let n = pileup.nrows();
    let c = domain_edge(n, rescale_flank)?;
    Some(nanmean(pileup.slice(s![c..n - c, c..n - c])))
}

/// coolpuppy's `get_domain_score(amap, flank)`: the domain's sum over the mean of the sums of the
/// blocks above it and to its right (`central / (top + right) * 2`).
pub fn domain_score(pileup: ArrayView2<f64>, rescale_flank: usize) -> Option<f64> {
    let n = pileup.nrows();
    let c = domain_edge(n, rescale_flank)?;
    let central = nansum(pileup.slice(s![c..n - c, c..n - c]));
    let top = nansum(pileup.slice(s![..c, c..n - c]));
    let right = nansum(pileup.slice(s![c..n - c, n - c..]));
    Some(central / (top + right) * 2.0)
}

/// coolpuppy's `get_insulation_strength(amap, ignore_central, ignore_diags)`: the mean of the two
/// diagonal quadrants over the mean of the two off-diagonal ones, each `(n - ignore_central) / 2`
/// wide, after the `ignore_diags` central diagonals are set aside. `None` when `ignore_central`
/// is even and not 0.
pub fn insulation_strength(
    pileup: ArrayView2<f64>,
    ignore_central: usize,
    ignore_diags: usize,
) -> Option<f64> {
    if ignore_central != 0 && ignore_central.is_multiple_of(2) {
        return None;
    }
    let n = pileup.nrows();
    let mut a: Array2<f64> = pileup.to_owned();
    for ((r, c), v) in a.indexed_iter_mut() {
        if r.abs_diff(c) < ignore_diags {
            *v = f64::NAN;
        }
    }
    let i = n.saturating_sub(ignore_central) / 2;
    // numpy's `a[-0:]` is the whole axis: so is `n - i` when `i` is 0
    let far = if i == 0 { 0 } else { n - i };
    let near = if i == 0 { n } else { i };
    let intra = nanmean(
        a.slice(s![..near, ..near])
            .iter()
            .chain(a.slice(s![far.., far..]).iter()),
    );
    let inter = nanmean(
        a.slice(s![..near, far..])
            .iter()
            .chain(a.slice(s![far.., ..near]).iter()),
    );
    Some(intra / inter)
}

/// Juicer APA's scores of an aggregate (`APARegionStatistics`): the centre pixel over the mean of
/// the other pixels (`P2M`), over the mean of each `width x width` corner (`P2UL`, `P2UR`, `P2LL`,
/// `P2LR`: upper-left is the first rows and columns, lower-left the last rows and first
/// columns, the corner nearest the diagonal), and the lower-left corner's z-score
/// (`ZscoreLL`, sample standard deviation). Juicer sets NaN pixels to 0 before summing: so do these.
#[derive(Clone, Debug, PartialEq)]
pub struct ApaScores {
    /// Peak to mean of the rest.
    pub p2m: f64,
    /// Peak to upper-left corner.
    pub p2ul: f64,
    /// Peak to upper-right corner.
    pub p2ur: f64,
    /// Peak to lower-left corner (Juicer's APA score).
    pub p2ll: f64,
    /// Peak to lower-right corner.
    pub p2lr: f64,
    /// `(peak - mean(LL)) / sd(LL)`.
    pub zscore_ll: f64,
}

/// [`ApaScores`] of `pileup` (square, odd size) with corners `width` pixels wide.
pub fn apa_scores(pileup: ArrayView2<f64>, width: usize) -> ApaScores {
    let a = pileup.mapv(|v| if v.is_nan() { 0.0 } else { v });
    let l = a.nrows();
    let w = width.min(l);
    let centre = a[[l / 2, l / 2]];
    let total: f64 = a.iter().sum();
    let corner = |rows: std::ops::Range<usize>, cols: std::ops::Range<usize>| -> Vec<f64> {
        a.slice(s![rows, cols]).iter().copied().collect()
    };
    let mean = |v: &[f64]| v.iter().mean();
    let (ul, ur) = (corner(0..w, 0..w), corner(0..w, l - w..l));
    let (ll, lr) = (corner(l - w..l, 0..w), corner(l - w..l, l - w..l));
    let (ll_mean, sd) = (mean(&ll), ll.iter().std_dev());
    ApaScores {
        p2m: centre / ((total - centre) / (l * l - 1) as f64),
        p2ul: centre / mean(&ul),
        p2ur: centre / mean(&ur),
        p2ll: centre / ll_mean,
        p2lr: centre / mean(&lr),
        zscore_ll: (centre - ll_mean) / sd,
    }
}

/// The scores of a pileup by name, in the order `contactmap pileup` writes them: for a local
/// pileup coolpuppy's insulation strength; otherwise coolpuppy's enrichment of the central
/// `center` pixels (`enrichment_{center}x{center}`) and corner CV (4 x 4 corners), then Juicer
/// APA's scores with its corner width for `resolution`.
pub fn pileup_scores(
    pileup: ArrayView2<f64>,
    local: bool,
    rescale_flank: Option<f64>,
    center: usize,
    resolution: u64,
) -> Result<Vec<(String, f64)>> {
    if let (true, Some(flank)) = (local, rescale_flank) {
        // the domain is the central third (flank 1) ...: defined for whole flanks
        let whole = (flank.fract() == 0.0).then_some(flank as usize);
        let score = |f: fn(ArrayView2<f64>, usize) -> Option<f64>| {
            whole.and_then(|w| f(pileup, w)).unwrap_or(f64::NAN)
        };
        return Ok(vec![
            ("domain_score".into(), score(domain_score)),
            ("local_enrichment".into(), score(local_enrichment)),
        ]);
    }
    if local {
        let value = insulation_strength(pileup, 0, 2).unwrap_or(f64::NAN);
        return Ok(vec![("insulation_strength".into(), value)]);
    }
    let value = enrichment(pileup, center).ok_or_else(|| {
        Error::parameter(
            "center",
            center,
            format!(
                "the pileup is {} pixels wide: the centre square must fit in half of it",
                pileup.nrows()
            ),
        )
    })?;
    let apa = apa_scores(pileup, apa_corner_width(resolution));
    Ok(vec![
        (format!("enrichment_{center}x{center}"), value),
        ("corner_cv".into(), corner_cv(pileup, 4)),
        ("P2M".into(), apa.p2m),
        ("P2UL".into(), apa.p2ul),
        ("P2UR".into(), apa.p2ur),
        ("P2LL".into(), apa.p2ll),
        ("P2LR".into(), apa.p2lr),
        ("ZscoreLL".into(), apa.zscore_ll),
    ])
}

/// Juicer APA's corner width for a bin size: 3 at 5 kb, 6 otherwise (its `-q` defaults).
pub fn apa_corner_width(resolution: u64) -> usize {
    if resolution == 5_000 { 3 } else { 6 }
}

/// A group's pileup and its scores by name.
pub type GroupScores<'a> = (&'a super::result::Pileup, Vec<(String, f64)>);

/// The scores of every group of `pileups` ([`pileup_scores`] of each), in the groups' order.
pub fn group_scores(
    pileups: &super::result::Pileups,
    local: bool,
    rescale_flank: Option<f64>,
    center: usize,
    resolution: u64,
) -> Result<Vec<GroupScores<'_>>> {
    pileups
        .groups
        .iter()
        .map(|p| {
            pileup_scores(p.data.view(), local, rescale_flank, center, resolution).map(|s| (p, s))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::Array2;

    #[test]
    fn apa_scores_of_juicers_worked_example() {
        // 5 x 5, centre 100, the rest 1..24 row by row (the spec's example: corners of 2)
        let mut a = Array2::<f64>::zeros((5, 5));
        let mut k = 1.0;
        for ((r, c), v) in a.indexed_iter_mut() {
            if (r, c) == (2, 2) {
                *v = 100.0;
            } else {
                *v = k;
                k += 1.0;
            }
        }
        let s = apa_scores(a.view(), 2);
        // LL = rows 3-4, cols 0-1 = {15, 16, 20, 21}, worked by hand
        let ll = [15.0, 16.0, 20.0, 21.0];
        let m: f64 = ll.iter().sum::<f64>() / 4.0;
        let sd = (ll.iter().map(|v| (v - m).powi(2)).sum::<f64>() / 3.0).sqrt();
        assert!((s.p2ll - 100.0 / m).abs() < 1e-12);
        assert!((s.zscore_ll - (100.0 - m) / sd).abs() < 1e-12);
        assert!((s.p2m - 100.0 / (300.0 / 24.0)).abs() < 1e-12);
        assert!((s.p2ul - 100.0 / 4.0).abs() < 1e-12); // {1, 2, 6, 7}
    }

    #[test]
    fn enrichment_and_corners_by_hand() {
        let a = Array2::from_shape_fn((5, 5), |(r, c)| (r * 5 + c) as f64);
        assert_eq!(enrichment(a.view(), 1), Some(12.0));
        assert_eq!(enrichment(a.view(), 3), None); // c = 2 < 3, as coolpuppy refuses
        let mut b = Array2::from_elem((7, 7), 1.0);
        b[[3, 3]] = 10.0;
        assert_eq!(enrichment(b.view(), 3), Some(2.0));
        // corners all 1: no variation
        assert_eq!(corner_cv(b.view(), 2), 0.0);
        // a domain of 2s in a 3 x 3 grid of 1s: 2 * 1 / (1 + 1) * 2
        let mut d = Array2::from_elem((3, 3), 1.0);
        d[[1, 1]] = 2.0;
        assert_eq!(domain_score(d.view(), 1), Some(2.0));
        assert_eq!(local_enrichment(d.view(), 1), Some(2.0));
        assert_eq!(domain_score(Array2::<f64>::zeros((4, 4)).view(), 1), None);
    }
}
