//! Orienting eigenvectors: the sign that correlates positively with a phasing track (cooltools'
//! `_phase_eigs` with its default Spearman correlation).

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

/// Spearman's correlation of `a` and `b` over the positions where both are finite.
pub fn spearman(a: &[f64], b: &[f64]) -> f64 {
    let (x, y): (Vec<f64>, Vec<f64>) = a
        .iter()
        .zip(b)
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .map(|(x, y)| (*x, *y))
        .unzip();
    pearson(&ranks(&x), &ranks(&y))
}

/// Flip `vector` in place so that it correlates positively (Spearman) with `track`; returns
/// the correlation before flipping (NaN: the vector is left as it is).
pub fn orient(vector: &mut [f64], track: &[f64]) -> f64 {
    let r = spearman(track, vector);
    if r < 0.0 {
        vector.iter_mut().for_each(|v| *v = -*v);
    }
    r
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
    fn orient_flips_anticorrelated() {
        let track = [0.1, 0.5, 0.9];
        let mut v = [1.0, 0.0, -1.0];
        orient(&mut v, &track);
        assert_eq!(v, [-1.0, 0.0, 1.0]);
    }
}
