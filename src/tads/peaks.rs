//! Local maxima of a 1D track and their topographic prominence, as cooltools'
//! `lib.peaks.find_peak_prominence(arr, max_dist=None)` (cooltools 0.7.1) computes them.
//!
//! Conventions, all taken from the peer so that boundary strengths agree exactly:
//!
//! - local maxima are found on the track with its NaNs removed, with strict inequalities on both
//!   sides (a plateau is not a maximum; the first and last finite values never are);
//! - for each maximum, the nearest strictly higher value is searched to the left and to the right
//!   on the full track (NaNs compare false, so they never stop the search);
//! - the left prominence is the height minus the NaN-ignoring minimum over `[left higher, peak)`,
//!   the right one over `[peak, right higher)`; the prominence is the NaN-ignoring minimum of the
//!   two (NaN when both sides lack a higher value);
//! - the first maximum with no higher value on either side (the global maximum) gets its height
//!   minus the lowest local minimum (strict, on the NaN-free track), or minus the lowest value of
//!   the whole track when there is no local minimum.

/// Minimum ignoring NaN; NaN when every value is NaN (numpy's `nanmin`).
fn nanmin(values: impl IntoIterator<Item = f64>) -> f64 {
    values
        .into_iter()
        .filter(|v| !v.is_nan())
        .fold(f64::NAN, |m, v| if m.is_nan() || v < m { v } else { m })
}

/// The local maxima of `values` and their prominences, as `(position, prominence)` sorted by
/// position. Positions index `values` (NaNs included); prominences may be NaN (see the module
/// documentation for the exact rules).
pub fn find_peak_prominence(values: &[f64]) -> Vec<(usize, f64)> {
    let finite: Vec<usize> = (0..values.len()).filter(|&k| !values[k].is_nan()).collect();
    let m = finite.len();
    let mut maxima = Vec::new();
    let mut minima = Vec::new();
    for t in 1..m.saturating_sub(1) {
        let (prev, here, next) = (
            values[finite[t - 1]],
            values[finite[t]],
            values[finite[t + 1]],
        );
        if prev < here && here > next {
            maxima.push(finite[t]);
        }
        if prev > here && here < next {
            minima.push(finite[t]);
        }
    }
    let n = values.len();
    let mut result = Vec::with_capacity(maxima.len());
    let mut global: Option<usize> = None;
    for (index, &pos) in maxima.iter().enumerate() {
        let height = values[pos];
        let left = (0..pos).rev().find(|&j| values[j] > height);
        let right = (pos + 1..n).find(|&j| values[j] > height);
        let left_prom = left.map_or(f64::NAN, |l| {
            height - nanmin(values[l..pos].iter().copied())
        });
        let right_prom = right.map_or(f64::NAN, |r| {
            height - nanmin(values[pos..r].iter().copied())
        });
        if left.is_none() && right.is_none() && global.is_none() {
            global = Some(index);
        }
        result.push((pos, nanmin([left_prom, right_prom])));
    }
    if let Some(index) = global {
        let pos = maxima[index];
        let lowest = if minima.is_empty() {
            nanmin(values.iter().copied())
        } else {
            nanmin(minima.iter().map(|&k| values[k]))
        };
        result[index].1 = values[pos] - lowest;
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn same(a: f64, b: f64) -> bool {
        (a.is_nan() && b.is_nan()) || a == b
    }

    #[test]
    fn hand_computed_cases() {
        // 0 3 1 5 2 4 0: maxima at 1 (3), 3 (5, global), 5 (4).
        let v = [0.0, 3.0, 1.0, 5.0, 2.0, 4.0, 0.0];
        let peaks = find_peak_prominence(&v);
        // pos 1: left none; right higher at 3, min over [1,3) = 1 -> 2.
        // pos 3: global; lowest local minimum is min(1, 2) = 1 -> 4.
        // pos 5: left higher at 3, min over [3,5) = 2 -> 2; right none -> 2.
        assert_eq!(peaks, vec![(1, 2.0), (3, 4.0), (5, 2.0)]);

        // NaNs are skipped to find maxima but kept for the searches.
        let v = [1.0, f64::NAN, 2.0, f64::NAN, 0.5, 3.0, 1.0];
        let peaks = find_peak_prominence(&v);
        // finite track 1 2 0.5 3 1: maxima at 2 and 5, local minimum at 4 (0.5).
        assert_eq!(peaks, vec![(2, 1.5), (5, 2.5)]);

        // No local minimum: the global maximum uses the lowest value.
        let v = [0.0, 2.0, 1.0];
        assert_eq!(find_peak_prominence(&v), vec![(1, 2.0)]);
        // Plateaus are not maxima.
        assert!(find_peak_prominence(&[0.0, 1.0, 1.0, 0.0]).is_empty());
        assert!(find_peak_prominence(&[]).is_empty());
        assert!(find_peak_prominence(&[f64::NAN, 1.0]).is_empty());
        // Two equal highest peaks: the first is the global one, the second has no higher value.
        let v = [0.0, 2.0, 1.0, 2.0, 0.5];
        let peaks = find_peak_prominence(&v);
        assert_eq!(peaks[0], (1, 1.0));
        assert!(peaks[1].1.is_nan());
    }

    /// The definition, written independently: scan every position of the NaN-free track.
    fn brute_force(values: &[f64]) -> Vec<(usize, f64)> {
        let idx: Vec<usize> = (0..values.len()).filter(|&k| !values[k].is_nan()).collect();
        let is_max = |t: usize| {
            t > 0 && t + 1 < idx.len() && {
                let h = values[idx[t]];
                values[idx[t - 1]] < h && values[idx[t + 1]] < h
            }
        };
        let is_min = |t: usize| {
            t > 0 && t + 1 < idx.len() && {
                let h = values[idx[t]];
                values[idx[t - 1]] > h && values[idx[t + 1]] > h
            }
        };
        let mins: Vec<f64> = (0..idx.len())
            .filter(|&t| is_min(t))
            .map(|t| values[idx[t]])
            .collect();
        let mut out = Vec::new();
        let mut seen_global = false;
        for t in (0..idx.len()).filter(|&t| is_max(t)) {
            let p = idx[t];
            let h = values[p];
            let mut left = None;
            let mut j = p;
            while j > 0 {
                j -= 1;
                if values[j] > h {
                    left = Some(j);
                    break;
                }
            }
            let right = (p + 1..values.len()).find(|&j| values[j] > h);
            let lo = |range: std::ops::Range<usize>| {
                let finite: Vec<f64> = values[range]
                    .iter()
                    .copied()
                    .filter(|v| !v.is_nan())
                    .collect();
                finite.iter().copied().fold(f64::INFINITY, f64::min)
            };
            let prom = match (left, right) {
                (None, None) if !seen_global => {
                    seen_global = true;
                    let low = if mins.is_empty() {
                        lo(0..values.len())
                    } else {
                        mins.iter().copied().fold(f64::INFINITY, f64::min)
                    };
                    h - low
                }
                (None, None) => f64::NAN,
                (Some(l), None) => h - lo(l..p),
                (None, Some(r)) => h - lo(p..r),
                (Some(l), Some(r)) => (h - lo(l..p)).min(h - lo(p..r)),
            };
            out.push((p, prom));
        }
        out
    }

    proptest! {
        #[test]
        fn matches_brute_force(raw in proptest::collection::vec(0u8..12, 0..60)) {
            // Small integers make ties common; 11 stands for NaN.
            let values: Vec<f64> = raw.iter().map(|&v| if v == 11 { f64::NAN } else { v as f64 }).collect();
            let ours = find_peak_prominence(&values);
            let reference = brute_force(&values);
            prop_assert_eq!(ours.len(), reference.len());
            for (a, b) in ours.iter().zip(&reference) {
                prop_assert_eq!(a.0, b.0);
                prop_assert!(same(a.1, b.1), "{:?} vs {:?}", a, b);
            }
        }
    }
}
