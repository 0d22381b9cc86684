//! Thresholds that separate strong boundaries from weak ones, as `cooltools insulation` applies
//! them to the boundary strengths of one window: Li's minimum cross-entropy method, Otsu's method
//! or a fixed value, reproducing scikit-image 0.26 (`skimage.filters.threshold_li` and
//! `threshold_otsu` with 256 bins) on float data.
//!
//! A bin is a boundary when its strength is at least the cutoff (`strength >= cutoff`); a NaN
//! strength or a NaN cutoff never is.
//!
//! NaNs are dropped before thresholding. scikit-image's Li does that itself; its Otsu does not
//! (cooltools 0.7.1 then fails on the NaN strengths every insulation table has), so for Otsu this
//! is contactmap's choice. Means are computed with numpy's pairwise summation so that the Li
//! iterations follow the peer's step by step.

use std::str::FromStr;

use crate::error::{Error, Result};

/// The rule that turns boundary strengths into a cutoff.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Threshold {
    /// Li's iterative minimum cross-entropy threshold (cooltools' default).
    Li,
    /// Otsu's threshold on a 256-bin histogram.
    Otsu,
    /// A fixed cutoff.
    Value(f64),
}

impl FromStr for Threshold {
    type Err = Error;

    /// `li` or `otsu` (any case), or a number.
    fn from_str(text: &str) -> Result<Threshold> {
        let trimmed = text.trim();
        match trimmed.to_ascii_lowercase().as_str() {
            "li" => Ok(Threshold::Li),
            "otsu" => Ok(Threshold::Otsu),
            _ => match trimmed.parse::<f64>() {
                Ok(value) if !value.is_nan() => Ok(Threshold::Value(value)),
                _ => Err(Error::Argument(format!(
                    "boundary threshold '{text}': expected 'Li', 'Otsu' or a number"
                ))),
            },
        }
    }
}

impl Threshold {
    /// The cutoff for these strengths (NaNs ignored; NaN when no strength is left for Li/Otsu).
    pub fn cutoff(&self, strengths: &[f64]) -> f64 {
        match self {
            Threshold::Li => threshold_li(strengths),
            Threshold::Otsu => threshold_otsu(strengths),
            Threshold::Value(v) => *v,
        }
    }
}

/// numpy's pairwise summation (`np.add.reduce` on a contiguous float64 array).
pub(crate) fn numpy_sum(a: &[f64]) -> f64 {
    0.0 + crate::numeric::pairwise_sum(a)
}

fn numpy_mean(a: &[f64]) -> f64 {
    numpy_sum(a) / a.len() as f64
}

/// Li's minimum cross-entropy threshold of the non-NaN `values`, as scikit-image's
/// `threshold_li` on float data (default tolerance: half the smallest gap between distinct
/// values; first guess: the mean). Special cases as the peer: no value gives NaN, a single
/// distinct value (infinities included) gives that value, no finite value gives 0.
pub fn threshold_li(values: &[f64]) -> f64 {
    let image: Vec<f64> = values.iter().copied().filter(|v| !v.is_nan()).collect();
    if image.is_empty() {
        return f64::NAN;
    }
    if image.iter().all(|&v| v == image[0]) {
        return image[0];
    }
    let mut image: Vec<f64> = image.into_iter().filter(|v| v.is_finite()).collect();
    if image.is_empty() {
        return 0.0;
    }
    let image_min = image.iter().copied().fold(f64::INFINITY, f64::min);
    for v in &mut image {
        *v -= image_min;
    }
    let mut sorted = image.clone();
    sorted.sort_by(f64::total_cmp);
    sorted.dedup();
    let tolerance = sorted
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min)
        / 2.0;
    let mut t_next = numpy_mean(&image);
    let mut t_curr = -2.0 * tolerance;
    let mut fore = Vec::with_capacity(image.len());
    let mut back = Vec::with_capacity(image.len());
    while (t_next - t_curr).abs() > tolerance {
        t_curr = t_next;
        fore.clear();
        back.clear();
        for &v in &image {
            if v > t_curr {
                fore.push(v);
            } else {
                back.push(v);
            }
        }
        let mean_fore = numpy_mean(&fore);
        let mean_back = numpy_mean(&back);
        if mean_back == 0.0 {
            break;
        }
        t_next = (mean_back - mean_fore) / (mean_back.ln() - mean_fore.ln());
    }
    t_next + image_min
}

/// Otsu's threshold of the non-NaN `values` on a 256-bin histogram, as scikit-image's
/// `threshold_otsu(nbins=256)`: numpy's histogram over `[min, max]` (edges `min + k * step`,
/// the last edge exactly `max`), bin centres halfway between edges, float32 bin counts, and the
/// centre of the first bin maximising the between-class variance. A single distinct value gives
/// that value; no value, or an infinite one, gives NaN.
pub fn threshold_otsu(values: &[f64]) -> f64 {
    const NBINS: usize = 256;
    let image: Vec<f64> = values.iter().copied().filter(|v| !v.is_nan()).collect();
    if image.is_empty() {
        return f64::NAN;
    }
    if image.iter().all(|&v| v == image[0]) {
        return image[0];
    }
    let first = image.iter().copied().fold(f64::INFINITY, f64::min);
    let last = image.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(first.is_finite() && last.is_finite()) {
        return f64::NAN;
    }
    // np.linspace(first, last, NBINS + 1)
    let delta = last - first;
    let step = delta / NBINS as f64;
    let mut edges: Vec<f64> = (0..=NBINS)
        .map(|k| {
            if step == 0.0 {
                (k as f64 / NBINS as f64) * delta + first
            } else {
                k as f64 * step + first
            }
        })
        .collect();
    edges[NBINS] = last;
    // np.histogram's uniform-bin index computation with its edge corrections.
    let mut counts = vec![0u64; NBINS];
    for &v in &image {
        let mut index = ((v - first) / delta * NBINS as f64) as usize;
        if index >= NBINS {
            index = NBINS - 1;
        }
        if v < edges[index] {
            index -= 1;
        } else if index != NBINS - 1 && v >= edges[index + 1] {
            index += 1;
        }
        counts[index] += 1;
    }
    let centers: Vec<f64> = (0..NBINS)
        .map(|k| (edges[k] + edges[k + 1]) / 2.0)
        .collect();
    let counts: Vec<f32> = counts.iter().map(|&c| c as f32).collect();
    let weighted: Vec<f64> = counts
        .iter()
        .zip(&centers)
        .map(|(&c, &x)| c as f64 * x)
        .collect();
    let mut weight1 = vec![0f32; NBINS];
    let mut mean1 = vec![0f64; NBINS];
    let (mut w, mut s) = (0f32, 0f64);
    for k in 0..NBINS {
        w += counts[k];
        s += weighted[k];
        weight1[k] = w;
        mean1[k] = s / w as f64;
    }
    let mut weight2 = vec![0f32; NBINS];
    let mut mean2 = vec![0f64; NBINS];
    let (mut w, mut s) = (0f32, 0f64);
    for k in (0..NBINS).rev() {
        w += counts[k];
        s += weighted[k];
        weight2[k] = w;
        mean2[k] = s / w as f64;
    }
    let mut best = 0;
    let mut best_value = f64::NEG_INFINITY;
    for k in 0..NBINS - 1 {
        let diff = mean1[k] - mean2[k + 1];
        let variance = (weight1[k] * weight2[k + 1]) as f64 * (diff * diff);
        if variance.is_nan() {
            best = k;
            break;
        }
        if variance > best_value {
            best_value = variance;
            best = k;
        }
    }
    centers[best]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_rules() {
        assert_eq!("Li".parse::<Threshold>().unwrap(), Threshold::Li);
        assert_eq!("OTSU".parse::<Threshold>().unwrap(), Threshold::Otsu);
        assert_eq!("0.25".parse::<Threshold>().unwrap(), Threshold::Value(0.25));
        let message = "median".parse::<Threshold>().unwrap_err().to_string();
        assert!(message.contains("'median'") && message.contains("Li"));
        assert_eq!(Threshold::Value(2.0).cutoff(&[1.0, f64::NAN]), 2.0);
    }

    #[test]
    fn numpy_pairwise_sum_differs_from_naive_as_numpy() {
        // Not a comparison with numpy itself: checks the blocks add up to the total.
        let a: Vec<f64> = (0..1000).map(|k| (k as f64).sqrt()).collect();
        let naive: f64 = a.iter().sum();
        assert!((numpy_sum(&a) - naive).abs() < 1e-9 * naive);
    }

    fn arrays() -> Vec<Vec<f64>> {
        vec![
            vec![0.1, 0.5, 0.3, 2.0, 1.7, 0.05, f64::NAN, 0.9, 3.1, 0.2],
            (0..200)
                .map(|k| ((k * 37 % 101) as f64 / 17.0).powi(2) * 0.01)
                .collect(),
            vec![1.0, 1.0, 1.0],
            vec![f64::NAN, f64::NAN],
            vec![-2.0, -1.5, 0.0, 4.0, 4.5, 5.0, 12.0],
        ]
    }

    #[test]
    fn li_and_otsu_match_scikit_image() {
        // Produced with /work/venv/bin/python (scikit-image 0.26, numpy) by
        //   threshold_li(a) and threshold_otsu(a[~np.isnan(a)]) on the arrays above
        //   (the all-NaN array gives NaN for Li; Otsu of an empty array is our NaN).
        let expected: [(f64, f64); 5] = [
            (LI[0], OTSU[0]),
            (LI[1], OTSU[1]),
            (1.0, 1.0),
            (f64::NAN, f64::NAN),
            (LI[4], OTSU[4]),
        ];
        for (a, (li, otsu)) in arrays().iter().zip(expected) {
            let (ours_li, ours_otsu) = (threshold_li(a), threshold_otsu(a));
            assert!(
                (li.is_nan() && ours_li.is_nan()) || (ours_li - li).abs() <= 1e-12 * li.abs(),
                "li {ours_li} vs {li}"
            );
            assert!(
                (otsu.is_nan() && ours_otsu.is_nan()) || ours_otsu == otsu,
                "otsu {ours_otsu} vs {otsu}"
            );
        }
    }

    const LI: [f64; 5] = [
        0.9991416628789366,
        0.09409618771812187,
        1.0,
        f64::NAN,
        1.2682250404153206,
    ];
    const OTSU: [f64; 5] = [
        0.9018554687500001,
        0.14124675605536335,
        1.0,
        f64::NAN,
        -0.00390625,
    ];
}
