//! The few dense operations the per-feature fits need on matrices as small as their design (a
//! few coefficients): `XᵀWX`, a Cholesky factor, solves, inverses and log-determinants. Row-major
//! `Vec<f64>`, `p x p`.

/// `XᵀWX` (+ `ridge` on the diagonal) of a design `x` (`n_samples` rows of `p`, row-major) with
/// per-sample weights `w`.
pub fn weighted_gram(x: &[f64], p: usize, w: &[f64], ridge: f64) -> Vec<f64> {
    let mut out = vec![0.0; p * p];
    for (row, &weight) in x.chunks_exact(p).zip(w) {
        for a in 0..p {
            for b in 0..p {
                out[a * p + b] += row[a] * weight * row[b];
            }
        }
    }
    for a in 0..p {
        out[a * p + a] += ridge;
    }
    out
}

/// `Xᵀv` of a design `x` (`n` rows of `p`).
pub fn transpose_times(x: &[f64], p: usize, v: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; p];
    for (row, &value) in x.chunks_exact(p).zip(v) {
        for a in 0..p {
            out[a] += row[a] * value;
        }
    }
    out
}

/// `Xβ` of a design `x` (`n` rows of `p`).
pub fn times(x: &[f64], p: usize, beta: &[f64]) -> Vec<f64> {
    x.chunks_exact(p)
        .map(|row| row.iter().zip(beta).map(|(a, b)| a * b).sum())
        .collect()
}

/// The lower Cholesky factor of the symmetric `p x p` matrix `a`, or `None` when `a` is not
/// positive definite.
pub fn cholesky(a: &[f64], p: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; p * p];
    for i in 0..p {
        for j in 0..=i {
            let mut sum = a[i * p + j];
            for k in 0..j {
                sum -= l[i * p + k] * l[j * p + k];
            }
            if i == j {
                if sum <= 0.0 || !sum.is_finite() {
                    return None;
                }
                l[i * p + i] = sum.sqrt();
            } else {
                l[i * p + j] = sum / l[j * p + j];
            }
        }
    }
    Some(l)
}

/// Solves `LLᵀx = b` for a Cholesky factor `l`.
pub fn cholesky_solve(l: &[f64], p: usize, b: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; p];
    for i in 0..p {
        let mut sum = b[i];
        for k in 0..i {
            sum -= l[i * p + k] * y[k];
        }
        y[i] = sum / l[i * p + i];
    }
    let mut x = vec![0.0; p];
    for i in (0..p).rev() {
        let mut sum = y[i];
        for k in i + 1..p {
            sum -= l[k * p + i] * x[k];
        }
        x[i] = sum / l[i * p + i];
    }
    x
}

/// The inverse of the symmetric positive-definite matrix whose Cholesky factor is `l`.
pub fn cholesky_inverse(l: &[f64], p: usize) -> Vec<f64> {
    let mut inverse = vec![0.0; p * p];
    for column in 0..p {
        let mut unit = vec![0.0; p];
        unit[column] = 1.0;
        for (row, value) in cholesky_solve(l, p, &unit).into_iter().enumerate() {
            inverse[row * p + column] = value;
        }
    }
    inverse
}

/// `log det A` from the Cholesky factor `l` of `A`.
pub fn cholesky_log_det(l: &[f64], p: usize) -> f64 {
    2.0 * (0..p).map(|i| l[i * p + i].ln()).sum::<f64>()
}

/// `aᵀ M b` for a `p x p` matrix `m`.
pub fn bilinear(a: &[f64], m: &[f64], b: &[f64]) -> f64 {
    let p = a.len();
    (0..p)
        .map(|i| a[i] * (0..p).map(|j| m[i * p + j] * b[j]).sum::<f64>())
        .sum()
}

/// `M v` for a `p x p` matrix `m`.
pub fn matrix_vector(m: &[f64], v: &[f64]) -> Vec<f64> {
    let p = v.len();
    (0..p)
        .map(|i| (0..p).map(|j| m[i * p + j] * v[j]).sum())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_solves_inverts_and_takes_log_det_of_a_known_matrix() {
        // A = [[4, 2, 0.4], [2, 5, 1], [0.4, 1, 3]]: det by the rule of Sarrus
        let a = [4.0, 2.0, 0.4, 2.0, 5.0, 1.0, 0.4, 1.0, 3.0];
        let det = 4.0 * (5.0 * 3.0 - 1.0) - 2.0 * (2.0 * 3.0 - 0.4) + 0.4 * (2.0 - 5.0 * 0.4);
        let l = cholesky(&a, 3).unwrap();
        assert!((cholesky_log_det(&l, 3) - f64::ln(det)).abs() < 1e-14);
        let x = cholesky_solve(&l, 3, &[1.0, 2.0, 3.0]);
        let back = matrix_vector(&a, &x);
        for (got, want) in back.iter().zip([1.0, 2.0, 3.0]) {
            assert!((got - want).abs() < 1e-14);
        }
        let inverse = cholesky_inverse(&l, 3);
        for i in 0..3 {
            for j in 0..3 {
                let product: f64 = (0..3).map(|k| a[i * 3 + k] * inverse[k * 3 + j]).sum();
                assert!((product - f64::from(u8::from(i == j))).abs() < 1e-14);
            }
        }
        assert!(cholesky(&[1.0, 2.0, 2.0, 1.0], 2).is_none(), "indefinite");
    }

    #[test]
    fn weighted_gram_and_products_match_the_written_out_sums() {
        let x = [1.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let w = [2.0, 3.0, 5.0];
        assert_eq!(weighted_gram(&x, 2, &w, 0.5), vec![10.5, 8.0, 8.0, 8.5]);
        assert_eq!(transpose_times(&x, 2, &w), vec![10.0, 8.0]);
        assert_eq!(times(&x, 2, &[1.0, 2.0]), vec![1.0, 3.0, 3.0]);
    }
}
