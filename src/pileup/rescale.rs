//! Snippets of any size to one grid, as coolpuppy 1.1.0 rescales them (`numutils.rescale` over
//! cooltools' `zoom_array`: scipy's order-1 zoom, corners aligned, to a multiple of the target
//! size, then block means).
//!
//! Per axis, `n` values become `f`: when `f < n`, first `T = f * ceil(n / f)` samples then the
//! mean of each `T / f` consecutive ones; otherwise `T = f` samples. Sample `k` sits at
//! `x = k (n - 1) / (T - 1)` and is `a[i] (1 - t) + a[i + 1] t` with `i = floor(x)`, `t = x - i`
//! (a value past the end counts 0). Rows are zoomed first, then columns. NaN pixels are zoomed as
//! 0 and, separately, as a mask: an output pixel that takes any weight from a NaN is NaN.

use ndarray::Array2;

/// One axis zoomed from `a.len()` values to `f` (see the module's description).
pub(crate) fn zoom_axis(a: &[f64], f: usize) -> Vec<f64> {
    let n = a.len();
    let m = if f < n { n.div_ceil(f) } else { 1 };
    let t_len = f * m;
    let step = if t_len > 1 {
        (n as f64 - 1.0) / (t_len as f64 - 1.0)
    } else {
        0.0
    };
    let samples: Vec<f64> = (0..t_len)
        .map(|k| {
            let x = k as f64 * step;
            let i = x.floor();
            let t = x - i;
            let i = i as usize;
            let next = a.get(i + 1).copied().unwrap_or(0.0);
            a.get(i).copied().unwrap_or(0.0) * (1.0 - t) + next * t
        })
        .collect();
    if m == 1 {
        return samples;
    }
    samples
        .chunks(m)
        .map(|block| block.iter().sum::<f64>() / m as f64)
        .collect()
}

/// `a` zoomed to `size x size`, rows first.
fn zoom(a: &Array2<f64>, size: usize) -> Array2<f64> {
    let w = a.ncols();
    let mut rows_zoomed = Array2::<f64>::zeros((size, w));
    for c in 0..w {
        let column: Vec<f64> = a.column(c).to_vec();
        for (r, v) in zoom_axis(&column, size).into_iter().enumerate() {
            rows_zoomed[[r, c]] = v;
        }
    }
    let mut out = Array2::<f64>::zeros((size, size));
    for r in 0..size {
        let row: Vec<f64> = rows_zoomed.row(r).to_vec();
        out.row_mut(r)
            .assign(&ndarray::Array1::from(zoom_axis(&row, size)));
    }
    out
}

/// The mean of `a` and its transpose where both are numbers, the one that is where only one is
/// (coolpuppy's `np.nanmean([a, a.T], axis=0)`): a local snippet's lower triangle filled from its
/// upper one.
pub fn symmetrise(a: &mut Array2<f64>) {
    let t = a.t().to_owned();
    a.zip_mut_with(&t, |x, &y| {
        *x = match (x.is_nan(), y.is_nan()) {
            (true, true) => f64::NAN,
            (true, false) => y,
            (false, true) => *x,
            (false, false) => (*x + y) / 2.0,
        }
    });
}

/// A snippet rescaled to `size x size` (coolpuppy's `rescale`): symmetrised first when `local`;
/// an empty or all-NaN snippet becomes zeros (and so counts, as in coolpuppy).
pub fn rescale_snippet(snippet: &Array2<f64>, size: usize, local: bool) -> Array2<f64> {
    if snippet.is_empty() || snippet.iter().all(|v| v.is_nan()) {
        return Array2::zeros((size, size));
    }
    let mut values = snippet.clone();
    if local {
        symmetrise(&mut values);
    }
    let mask = values.mapv(|v| if v.is_nan() { 1.0 } else { 0.0 });
    let filled = values.mapv(|v| {
        if v.is_nan() {
            0.0
        } else {
            v.clamp(f64::MIN, f64::MAX)
        }
    });
    let mut out = zoom(&filled, size);
    let mask = zoom(&mask, size);
    out.zip_mut_with(&mask, |v, &m| {
        if m > 0.0 {
            *v = f64::NAN
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    /// Naive linear interpolation with aligned corners: the end points are kept, a constant stays
    /// constant, a line stays a line (closed forms).
    #[test]
    fn zooming_keeps_corners_constants_and_lines() {
        let line: Vec<f64> = (0..7).map(|i| 2.0 * i as f64 + 1.0).collect();
        let up = zoom_axis(&line, 13);
        assert_eq!((up[0], up[12]), (1.0, 13.0));
        for (k, v) in up.iter().enumerate() {
            assert!((v - (1.0 + k as f64)).abs() < 1e-12, "{k}: {v}");
        }
        // 10 to 3: 3 x 4 = 12 samples of the line, then means of 4
        let line: Vec<f64> = (0..10).map(|i| i as f64).collect();
        let down = zoom_axis(&line, 3);
        let x = |k: usize| k as f64 * 9.0 / 11.0;
        let want: Vec<f64> = (0..3)
            .map(|b| (0..4).map(|k| x(4 * b + k)).sum::<f64>() / 4.0)
            .collect();
        for (got, want) in down.iter().zip(&want) {
            assert!((got - want).abs() < 1e-12);
        }
        assert_eq!(zoom_axis(&[5.0; 4], 9), vec![5.0; 9]);
    }

    #[test]
    fn nan_spreads_to_every_pixel_it_touches_and_all_nan_gives_zeros() {
        let a = array![[1.0, f64::NAN, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]];
        let out = rescale_snippet(&a, 5, false);
        // columns 0..=2 of the output row 0 take weight from input column 1 except the corners
        assert_eq!(out[[0, 0]], 1.0);
        assert!(out[[0, 1]].is_nan() && out[[0, 2]].is_nan() && out[[0, 3]].is_nan());
        assert_eq!(out[[0, 4]], 3.0);
        assert!(out.row(2).iter().all(|v| v.is_finite()));
        let empty = Array2::from_elem((4, 4), f64::NAN);
        assert_eq!(
            rescale_snippet(&empty, 3, false),
            Array2::<f64>::zeros((3, 3))
        );
    }
}
