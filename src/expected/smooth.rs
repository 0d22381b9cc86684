//! Smoothing in log space, as cooltools does it.
//!
//! - [`log_smooth`]: cooltools' `expected_smoothing.log_smooth` (0.7.1), the Gaussian kernel
//!   smoothing over `log10(distance)` behind the `*.avg.smoothed` columns. The kernel (standard
//!   deviation `sigma_log10`, cut at `window_sigma` sigmas) is evaluated at a thinned subset of the
//!   distances, uniformly spaced in log space (`points_per_sigma` per sigma, the first and last
//!   always kept), and the other distances are interpolated linearly in log-log space, with numpy's
//!   `interp` rules for infinite values (zeros become `-inf` logs and back). Distance 0 has no
//!   logarithm: its smoothed value is always `0`.
//! - [`robust_gauss_filter`]: cooltools' `numutils.robust_gauss_filter`, a Gaussian filter
//!   (scipy's `gaussian_filter1d`, truncated at 4 sigmas) that ignores the edges and non-finite
//!   values: the filtered values divided by the filtered validity mask. Used for P(s) slopes.

use rayon::prelude::*;

/// Smooth the functions `ys` (each as long as `xs`, `xs` increasing and non-negative) with a
/// Gaussian kernel over `log10(xs)`; returns one smoothed vector per function.
pub fn log_smooth(
    xs: &[f64],
    ys: &[&[f64]],
    sigma_log10: f64,
    window_sigma: f64,
    points_per_sigma: usize,
) -> Vec<Vec<f64>> {
    if xs.is_empty() {
        return ys.iter().map(|_| Vec::new()).collect();
    }
    let thinned = if points_per_sigma > 0 {
        log_thin(xs, sigma_log10 / points_per_sigma as f64)
    } else {
        xs.to_vec()
    };
    let log_xs: Vec<f64> = xs.iter().map(|x| x.log10()).collect();
    let half_window = sigma_log10 * window_sigma;
    // Each kernel evaluation is independent: parallel over the thinned points.
    let columns: Vec<Vec<f64>> = thinned
        .par_iter()
        .with_min_len(16)
        .map(|x| {
            let center = x.log10();
            let lo = log_xs.partition_point(|&v| v < center - half_window);
            let hi = log_xs
                .partition_point(|&v| v < center + half_window)
                .max(lo);
            let mut weights: Vec<f64> = log_xs[lo..hi]
                .iter()
                .map(|&v| {
                    let delta = center - v;
                    (-(delta * delta) / 2.0 / sigma_log10 / sigma_log10).exp()
                })
                .collect();
            let norm: f64 = weights.iter().sum();
            if norm > 0.0 {
                for w in &mut weights {
                    *w /= norm;
                }
                ys.iter()
                    .map(|y| {
                        y[lo..hi]
                            .iter()
                            .zip(&weights)
                            .map(|(value, w)| value * w)
                            .sum()
                    })
                    .collect()
            } else {
                vec![0.0; ys.len()]
            }
        })
        .collect();
    let smoothed: Vec<Vec<f64>> = (0..ys.len())
        .map(|k| columns.iter().map(|column| column[k]).collect())
        .collect();
    if points_per_sigma == 0 {
        return smoothed;
    }
    let log_thinned: Vec<f64> = thinned.iter().map(|x| x.ln()).collect();
    let log_all: Vec<f64> = xs.iter().map(|x| x.ln()).collect();
    smoothed
        .iter()
        .map(|row| {
            let log_row: Vec<f64> = row.iter().map(|v| v.ln()).collect();
            log_all
                .iter()
                .map(|&x| interp(x, &log_thinned, &log_row).exp())
                .collect()
        })
        .collect()
}

/// The elements of the sorted `xs` spaced at least `min_log10_step` apart in log10 (cooltools'
/// `_log_thin`): the first, every one more than `10^step` times the last kept, and the last.
fn log_thin(xs: &[f64], min_log10_step: f64) -> Vec<f64> {
    let min_ratio = 10f64.powf(min_log10_step);
    let mut thinned = vec![xs[0]];
    let mut previous = xs[0];
    for &x in &xs[1..] {
        if x > previous * min_ratio {
            thinned.push(x);
            previous = x;
        }
    }
    let last = xs[xs.len() - 1];
    if thinned[thinned.len() - 1] != last {
        thinned.push(last);
    }
    thinned
}

/// numpy's `interp(x, xp, fp)` for one point (`xp` strictly increasing), including its handling
/// of infinite values: exact knots return their value, and a `NaN` from `inf - inf` is retried
/// from the right knot, then replaced by the knot value when both are equal.
fn interp(x: f64, xp: &[f64], fp: &[f64]) -> f64 {
    let n = xp.len();
    if x.is_nan() {
        return x;
    }
    if n == 1 {
        return fp[0];
    }
    if x < xp[0] {
        return fp[0];
    }
    if x > xp[n - 1] {
        return fp[n - 1];
    }
    let j = xp.partition_point(|&v| v <= x) - 1;
    if j == n - 1 || xp[j] == x {
        return fp[j];
    }
    let slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j]);
    let mut value = slope * (x - xp[j]) + fp[j];
    if value.is_nan() {
        value = slope * (x - xp[j + 1]) + fp[j + 1];
        if value.is_nan() && fp[j] == fp[j + 1] {
            value = fp[j];
        }
    }
    value
}

/// scipy's `gaussian_filter1d(values, sigma, mode="constant", cval=0, truncate=4)`.
fn gaussian_filter(values: &[f64], sigma: f64) -> Vec<f64> {
    let radius = (4.0 * sigma + 0.5) as usize;
    let sigma2 = sigma * sigma;
    let mut kernel: Vec<f64> = (0..=2 * radius)
        .map(|k| {
            let x = k as f64 - radius as f64;
            (-0.5 / sigma2 * (x * x)).exp()
        })
        .collect();
    let total: f64 = kernel.iter().sum();
    for k in &mut kernel {
        *k /= total;
    }
    let n = values.len() as isize;
    let at = |i: isize| {
        if (0..n).contains(&i) {
            values[i as usize]
        } else {
            0.0
        }
    };
    (0..n)
        .map(|i| {
            // scipy's symmetric-kernel loop: centre first, then mirrored pairs.
            let mut sum = at(i) * kernel[radius];
            for j in 1..=radius {
                sum += (at(i + j as isize) + at(i - j as isize)) * kernel[radius + j];
            }
            sum
        })
        .collect()
}

/// cooltools' `robust_gauss_filter`: a Gaussian filter whose edges and non-finite values count
/// as missing, not as zeros (filtered values over the filtered validity mask).
pub fn robust_gauss_filter(values: &[f64], sigma: f64) -> Vec<f64> {
    let finite: Vec<f64> = values
        .iter()
        .map(|&v| if v.is_finite() { v } else { 0.0 })
        .collect();
    let mask: Vec<f64> = values
        .iter()
        .map(|v| if v.is_finite() { 1.0 } else { 0.0 })
        .collect();
    let a = gaussian_filter(&finite, sigma);
    let b = gaussian_filter(&mask, sigma);
    a.iter().zip(&b).map(|(x, y)| x / y).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numpy_interp_rules() {
        let xp = [0.0, 1.0];
        assert_eq!(
            interp(0.5, &xp, &[f64::NEG_INFINITY, 0.0]),
            f64::NEG_INFINITY
        );
        assert_eq!(
            interp(0.5, &xp, &[0.0, f64::NEG_INFINITY]),
            f64::NEG_INFINITY
        );
        assert_eq!(
            interp(0.5, &xp, &[f64::NEG_INFINITY, f64::NEG_INFINITY]),
            f64::NEG_INFINITY
        );
        assert_eq!(interp(0.25, &xp, &[1.0, 3.0]), 1.5);
        assert_eq!(interp(-1.0, &xp, &[1.0, 3.0]), 1.0);
        assert_eq!(interp(2.0, &xp, &[1.0, 3.0]), 3.0);
        let xp = [f64::NEG_INFINITY, 0.0, 1.0];
        assert_eq!(
            interp(f64::NEG_INFINITY, &xp, &[f64::NEG_INFINITY, 1.0, 2.0]),
            f64::NEG_INFINITY
        );
    }

    #[test]
    fn thinning_keeps_ends_and_log_spacing() {
        let xs: Vec<f64> = (0..1000).map(f64::from).collect();
        let thinned = log_thin(&xs, 0.01);
        assert_eq!(thinned[0], 0.0);
        assert_eq!(*thinned.last().unwrap(), 999.0);
        // Every integer up to ~43 is kept (consecutive ratios above 10^0.01).
        assert_eq!(&thinned[..10], &xs[..10]);
        assert!(thinned.len() < 400);
    }

    #[test]
    fn smoothing_a_power_law_keeps_it() {
        // A pure power law is smoothed into (nearly) itself away from the edges.
        let xs: Vec<f64> = (0..2000).map(f64::from).collect();
        let ys: Vec<f64> = xs
            .iter()
            .map(|x| if *x > 0.0 { x.powf(-1.0) } else { 0.0 })
            .collect();
        let ones = vec![1.0; xs.len()];
        let smoothed = log_smooth(&xs, &[&ys, &ones], 0.1, 5.0, 10);
        assert_eq!(smoothed[0][0], 0.0);
        for i in [100usize, 300, 600] {
            let ratio = smoothed[0][i] / smoothed[1][i] / ys[i];
            assert!((ratio - 1.0).abs() < 0.05, "{i}: {ratio}");
        }
    }

    #[test]
    fn robust_filter_ignores_edges_and_nans() {
        let flat = robust_gauss_filter(&[2.0; 7], 2.0);
        assert!(flat.iter().all(|v| (v - 2.0).abs() < 1e-12));
        let holes = robust_gauss_filter(&[1.0, f64::NAN, 1.0, f64::INFINITY, 1.0], 1.3);
        assert!(holes.iter().all(|v| (v - 1.0).abs() < 1e-12));
    }
}
