//! numpy's rules for the few array operations whose last digits the peers' results depend on
//! (cooler's MAD filter, cooltools' compartments and saddles, hicrep's per-diagonal sums).

/// numpy's `linspace(start, stop, num)` (endpoint included), element for element.
pub fn linspace(start: f64, stop: f64, num: usize) -> Vec<f64> {
    let div = num.saturating_sub(1).max(1) as f64;
    let step = (stop - start) / div;
    let mut out: Vec<f64> = (0..num).map(|k| k as f64 * step + start).collect();
    if num > 1 {
        out[num - 1] = stop;
    }
    out
}

/// numpy's `median` (the mean of the two middle values for an even count; `NaN` when empty);
/// sorts `values` in place.
pub fn median(values: &mut [f64]) -> f64 {
    let n = values.len();
    if n == 0 {
        return f64::NAN;
    }
    values.sort_unstable_by(f64::total_cmp);
    if n % 2 == 1 {
        values[n / 2]
    } else {
        (values[n / 2 - 1] + values[n / 2]) / 2.0
    }
}

/// numpy's `percentile` interpolation (method `linear`) between the order statistics `a <= b`
/// at fraction `gamma`.
pub fn lerp(a: f64, b: f64, gamma: f64) -> f64 {
    let diff = b - a;
    if gamma >= 0.5 {
        b - diff * (1.0 - gamma)
    } else {
        a + diff * gamma
    }
}

/// numpy's `quantile(values, fraction)` (method `linear`) of `sorted` (ascending, not empty):
/// virtual index `(n - 1) * fraction`.
pub fn quantile_of_sorted(sorted: &[f64], fraction: f64) -> f64 {
    let n = sorted.len();
    let virtual_index = (n - 1) as f64 * fraction;
    let below = virtual_index.floor().clamp(0.0, (n - 1) as f64);
    let gamma = virtual_index - below;
    lerp(
        sorted[below as usize],
        sorted[(below as usize + 1).min(n - 1)],
        gamma,
    )
}

/// numpy's pairwise summation kernel (`pairwise_sum` of its add loop): below 8 values one by
/// one, up to 128 in 8 interleaved accumulators, beyond that the two halves (cut at a multiple of
/// 8) summed apart.
pub fn pairwise_sum(a: &[f64]) -> f64 {
    let n = a.len();
    if n < 8 {
        a.iter().fold(-0.0, |s, &x| s + x)
    } else if n <= 128 {
        let mut r = [0.0; 8];
        r.copy_from_slice(&a[..8]);
        let full = n - n % 8;
        let mut i = 8;
        while i < full {
            for (j, slot) in r.iter_mut().enumerate() {
                *slot += a[i + j];
            }
            i += 8;
        }
        let mut res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
        for &x in &a[full..] {
            res += x;
        }
        res
    } else {
        let mut n2 = n / 2;
        n2 -= n2 % 8;
        pairwise_sum(&a[..n2]) + pairwise_sum(&a[n2..])
    }
}

/// The sum numpy's `add.reduceat` gives a segment (scipy's row sums of a sparse matrix): its
/// first value, plus the pairwise sum of the others (0 for none).
///
/// ```
/// use contactmap::numeric::reduceat_sum;
/// let values: Vec<f64> = (0..300).map(|k| 0.1 * k as f64).collect();
/// let naive: f64 = values.iter().sum();
/// assert!((reduceat_sum(&values) - naive).abs() < 1e-9);
/// assert_eq!(reduceat_sum(&[]), 0.0);
/// ```
pub fn reduceat_sum(a: &[f64]) -> f64 {
    match a.split_first() {
        None => 0.0,
        Some((first, rest)) => first + pairwise_sum(rest),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn as_numpy() {
        // numpy.linspace(0, 1, 5); numpy.percentile([1, 2, 3, 4], 40) = 2.2
        assert_eq!(linspace(0.0, 1.0, 5), vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        assert!((quantile_of_sorted(&[1.0, 2.0, 3.0, 4.0], 0.4) - 2.2).abs() < 1e-15);
        assert_eq!(quantile_of_sorted(&[5.0], 0.3), 5.0);
        // numpy.median([3, 1, 4, 1]) = 2.0, numpy.median([]) = nan
        assert_eq!(median(&mut [3.0, 1.0, 4.0, 1.0]), 2.0);
        assert!(median(&mut []).is_nan());
    }
}
