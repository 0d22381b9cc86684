//! Orienting eigenvectors: the sign that correlates positively with a phasing track, and
//! optionally their order by that correlation (cooltools' `_phase_eigs`, Spearman by default).

/// Ranks of `values` (1-based, ties averaged: scipy's `rankdata(method="average")`).
pub fn ranks(values: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut out = vec![0.0; values.len()];
    let mut start = 0;
    while start < order.len() {
        let mut end = start + 1;
        while end < order.len() && values[order[end]] == values[order[start]] {
            end += 1;
        }
        // ranks start + 1 ..= end, averaged
        let rank = (start + 1 + end) as f64 / 2.0;
        for &k in &order[start..end] {
            out[k] = rank;
        }
        start = end;
    }
    out
}

/// Pearson's correlation of `x` and `y` (NaN when either is constant or empty).
pub fn pearson(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    if x.is_empty() {
        return f64::NAN;
    }
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        let (da, db) = (a - mx, b - my);
        sxy += da * db;
        sxx += da * da;
        syy += db * db;
    }
    let r = sxy / (sxx * syy).sqrt();
    r.clamp(-1.0, 1.0)
}

/// The pairs `(a[k], b[k])` where both are finite, as two columns.
pub fn finite_pairs(a: &[f64], b: &[f64]) -> (Vec<f64>, Vec<f64>) {
    a.iter()
        .zip(b)
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .map(|(x, y)| (*x, *y))
        .unzip()
}

/// Spearman's correlation of `a` and `b` over the positions where both are finite.
pub fn spearman(a: &[f64], b: &[f64]) -> f64 {
    agreement(a, b, SortMetric::Spearman)
}

/// How a vector's agreement with the phasing track is measured (cooltools' `sort_metric`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SortMetric {
    /// Spearman's correlation (cooltools' default for the sign).
    Spearman,
    /// Pearson's correlation.
    Pearson,
    /// `sign(r) r^2 var(vector)`: the variance of the vector the track explains.
    VarExplained,
    /// `COMED(track, vector) MAD(vector)`: the robust (median) counterpart.
    MadExplained,
}

/// numpy's median of a copy of `values`.
fn median(values: &[f64]) -> f64 {
    crate::numeric::median(&mut values.to_vec())
}

/// cooltools' `MAD`: the median absolute deviation from the median.
fn mad(values: &[f64]) -> f64 {
    let m = median(values);
    median(&values.iter().map(|v| (v - m).abs()).collect::<Vec<_>>())
}

/// cooltools' `COMED`: `median((x - med x)(y - med y)) / MAD(x) / MAD(y)`.
fn comedian(x: &[f64], y: &[f64]) -> f64 {
    let (mx, my) = (median(x), median(y));
    let products: Vec<f64> = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).collect();
    median(&products) / mad(x) / mad(y)
}

/// The agreement of `vector` with `track` under `metric`, over the bins where both are finite;
/// its sign is the orientation.
pub fn agreement(track: &[f64], vector: &[f64], metric: SortMetric) -> f64 {
    let (x, y) = finite_pairs(track, vector);
    match metric {
        SortMetric::Spearman => pearson(&ranks(&x), &ranks(&y)),
        SortMetric::Pearson => pearson(&x, &y),
        SortMetric::VarExplained => {
            let r = pearson(&x, &y);
            let n = y.len() as f64;
            let mean = y.iter().sum::<f64>() / n;
            let var = y.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
            r.signum() * r * r * var
        }
        SortMetric::MadExplained => comedian(&x, &y) * mad(&y),
    }
}

/// cooltools' `_phase_eigs`: each vector is flipped to agree with `track` (by `sort`'s metric,
/// Spearman without one); with `sort`, the eigenpairs are then reordered by decreasing absolute
/// agreement (stable; vectors without any value last). A vector whose agreement is NaN is left as
/// it is (cooltools would multiply it by NaN). Returns the agreements, in the final order.
pub fn phase(
    values: &mut Vec<f64>,
    vectors: &mut Vec<Vec<f64>>,
    track: &[f64],
    sort: Option<SortMetric>,
) -> Vec<f64> {
    let metric = sort.unwrap_or(SortMetric::Spearman);
    let mut agreements: Vec<f64> = vectors
        .iter_mut()
        .map(|vector| {
            let a = agreement(track, vector, metric);
            if a < 0.0 {
                vector.iter_mut().for_each(|v| *v = -*v);
            }
            a
        })
        .collect();
    if sort.is_some() {
        let key = |a: f64| {
            if a.is_nan() {
                f64::NEG_INFINITY
            } else {
                a.abs()
            }
        };
        let mut order: Vec<usize> = (0..agreements.len()).collect();
        order.sort_by(|&i, &j| key(agreements[j]).total_cmp(&key(agreements[i])));
        *values = order.iter().map(|&i| values[i]).collect();
        *vectors = order
            .iter()
            .map(|&i| std::mem::take(&mut vectors[i]))
            .collect();
        agreements = order.iter().map(|&i| agreements[i]).collect();
    }
    agreements
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_average_ties_as_scipy() {
        // scipy.stats.rankdata([3, 1, 4, 1, 5]) = [3, 1.5, 4, 1.5, 5]
        assert_eq!(
            ranks(&[3.0, 1.0, 4.0, 1.0, 5.0]),
            vec![3.0, 1.5, 4.0, 1.5, 5.0]
        );
    }

    #[test]
    fn spearman_of_monotone_and_reversed() {
        let a = [1.0, 2.0, 3.0, 4.0, f64::NAN];
        let b = [1.0, 4.0, 9.0, 16.0, 0.0];
        assert!((spearman(&a, &b) - 1.0).abs() < 1e-15);
        let c = [4.0, 3.0, 2.0, 1.0, 7.0];
        assert!((spearman(&a, &c) + 1.0).abs() < 1e-15);
        // scipy.stats.spearmanr([1, 2, 3, 4, 5], [2, 1, 4, 3, 5]) = 0.8
        let r = spearman(&[1.0, 2.0, 3.0, 4.0, 5.0], &[2.0, 1.0, 4.0, 3.0, 5.0]);
        assert!((r - 0.8).abs() < 1e-12, "{r}");
    }

    #[test]
    fn robust_statistics_as_numpy() {
        // numpy.median([3, 1, 4, 1]) = 2.0; cooltools MAD([1, 2, 3, 4, 100]) = 1.0
        assert_eq!(median(&[3.0, 1.0, 4.0, 1.0]), 2.0);
        assert_eq!(mad(&[1.0, 2.0, 3.0, 4.0, 100.0]), 1.0);
        // COMED of a line with itself is 1; var_explained of y = 2x: r = 1, var(y)
        let x = [1.0, 2.0, 3.0, 4.0, 5.0];
        let y: Vec<f64> = x.iter().map(|v| 2.0 * v).collect();
        assert!((comedian(&x, &y) - 1.0).abs() < 1e-15);
        assert!((agreement(&x, &y, SortMetric::VarExplained) - 8.0).abs() < 1e-12);
    }

    #[test]
    fn phase_flips_anticorrelated() {
        let track = [0.1, 0.5, 0.9];
        let mut values = vec![2.0];
        let mut vectors = vec![vec![1.0, 0.0, -1.0]];
        phase(&mut values, &mut vectors, &track, None);
        assert_eq!(vectors[0], [-1.0, 0.0, 1.0]);
    }
}
