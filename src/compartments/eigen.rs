//! The eigenpairs of largest magnitude of a symmetric operator given only by its action on
//! vectors (scipy's `eigsh(which="LM")`, which cooltools calls): faer's Krylov-Schur iteration
//! for large operators, faer's dense decomposition for small ones.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::matrix_free::LinOp;
use faer::matrix_free::eigen::{
    PartialEigenParams, partial_self_adjoint_eigen, partial_self_adjoint_eigen_scratch,
};
use faer::{Col, Mat, MatMut, MatRef, Par, Side};
use rand::{Rng, SeedableRng};

/// A real symmetric linear operator of dimension [`SymmetricOperator::dim`].
pub trait SymmetricOperator: Sync {
    /// Dimension.
    fn dim(&self) -> usize;
    /// `y = A x`.
    fn apply(&self, x: &[f64], y: &mut [f64]);
}

/// Eigenpairs by decreasing absolute eigenvalue; vectors of unit norm, in the operator's
/// coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Eigenpairs {
    /// Eigenvalues.
    pub values: Vec<f64>,
    /// Eigenvectors.
    pub vectors: Vec<Vec<f64>>,
    /// Pairs whose residual stayed above the tolerance (the iteration ran out of restarts).
    pub unconverged: usize,
}

/// Operators of at most this dimension are decomposed densely.
pub const DENSE_MAX: usize = 128;

/// Largest subspace of the Krylov-Schur iteration (faer's default: 64, or twice the pairs).
const KRYLOV_DIM: usize = 64;

/// Relative residual at which a pair is accepted: `|A v - lambda v| <= TOL * |A|`.
const TOL: f64 = 1e-12;

struct Adapter<'a, O: SymmetricOperator>(&'a O);

impl<O: SymmetricOperator> std::fmt::Debug for Adapter<'_, O> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "operator of dimension {}", self.0.dim())
    }
}

impl<O: SymmetricOperator> LinOp<f64> for Adapter<'_, O> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }

    fn nrows(&self) -> usize {
        self.0.dim()
    }

    fn ncols(&self) -> usize {
        self.0.dim()
    }

    fn apply(
        &self,
        mut out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        _par: Par,
        _stack: &mut MemStack,
    ) {
        let n = self.0.dim();
        let mut x = vec![0.0; n];
        let mut y = vec![0.0; n];
        for c in 0..rhs.ncols() {
            for (i, slot) in x.iter_mut().enumerate() {
                *slot = rhs[(i, c)];
            }
            self.0.apply(&x, &mut y);
            for (i, &v) in y.iter().enumerate() {
                out[(i, c)] = v;
            }
        }
    }

    fn conj_apply(
        &self,
        out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        par: Par,
        stack: &mut MemStack,
    ) {
        self.apply(out, rhs, par, stack)
    }
}

/// A fixed pseudo-random start vector (a start orthogonal to an eigenvector never finds it;
/// the all-ones vector nearly is, for compartment vectors).
fn start_vector(n: usize) -> Vec<f64> {
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(0x5eed_c0de);
    (0..n).map(|_| rng.r#gen::<f64>() - 0.5).collect()
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// An estimate of `|A|` (a few power iterations): the scale of the tolerance.
fn norm_estimate<O: SymmetricOperator>(op: &O) -> f64 {
    let n = op.dim();
    let mut x = start_vector(n);
    let mut y = vec![0.0; n];
    let mut estimate = 0.0;
    for _ in 0..8 {
        let nx = norm(&x);
        if nx == 0.0 {
            break;
        }
        x.iter_mut().for_each(|v| *v /= nx);
        op.apply(&x, &mut y);
        estimate = norm(&y);
        std::mem::swap(&mut x, &mut y);
    }
    estimate
}

/// The `k` eigenpairs of largest magnitude of `op` (fewer when `k >= dim`).
pub fn largest_magnitude<O: SymmetricOperator>(op: &O, k: usize) -> Eigenpairs {
    let n = op.dim();
    let k = k.min(n);
    if k == 0 {
        return Eigenpairs {
            values: Vec::new(),
            vectors: Vec::new(),
            unconverged: 0,
        };
    }
    let max_dim = KRYLOV_DIM.max(2 * k);
    let mut pairs = if n <= DENSE_MAX.max(max_dim) {
        dense(op, k)
    } else {
        // faer's iteration can return one pair twice (and miss another) when eigenvalues of
        // both signs cluster; such an answer is caught and the iteration rerun with a larger
        // subspace
        let scale = norm_estimate(op).max(f64::MIN_POSITIVE);
        let mut dim = max_dim;
        loop {
            let pairs = krylov(op, k, dim, scale);
            if dim * 2 >= n || acceptable(op, &pairs, scale) {
                break pairs;
            }
            dim *= 2;
        }
    };
    // by decreasing |value|, as cooltools' get_eig orders them
    let mut order: Vec<usize> = (0..pairs.values.len()).collect();
    order.sort_by(|&a, &b| pairs.values[b].abs().total_cmp(&pairs.values[a].abs()));
    pairs.values = order.iter().map(|&i| pairs.values[i]).collect();
    pairs.vectors = order.iter().map(|&i| pairs.vectors[i].clone()).collect();
    pairs
}

fn dense<O: SymmetricOperator>(op: &O, k: usize) -> Eigenpairs {
    let n = op.dim();
    let mut a = Mat::<f64>::zeros(n, n);
    let mut e = vec![0.0; n];
    let mut y = vec![0.0; n];
    for j in 0..n {
        e[j] = 1.0;
        op.apply(&e, &mut y);
        e[j] = 0.0;
        for (i, &v) in y.iter().enumerate() {
            a[(i, j)] = v;
        }
    }
    let Ok(evd) = a.self_adjoint_eigen(Side::Lower) else {
        return Eigenpairs {
            values: vec![f64::NAN; k],
            vectors: vec![vec![f64::NAN; n]; k],
            unconverged: k,
        };
    };
    let s = evd.S();
    let u = evd.U();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| s[b].abs().total_cmp(&s[a].abs()));
    let chosen = &order[..k];
    Eigenpairs {
        values: chosen.iter().map(|&j| s[j]).collect(),
        vectors: chosen
            .iter()
            .map(|&j| (0..n).map(|i| u[(i, j)]).collect())
            .collect(),
        unconverged: 0,
    }
}

/// Distinct, orthogonal pairs with small residuals.
fn acceptable<O: SymmetricOperator>(op: &O, pairs: &Eigenpairs, scale: f64) -> bool {
    let mut y = vec![0.0; op.dim()];
    for (a, (value, v)) in pairs.values.iter().zip(&pairs.vectors).enumerate() {
        op.apply(v, &mut y);
        let residual = norm(
            &y.iter()
                .zip(v)
                .map(|(y, x)| y - value * x)
                .collect::<Vec<_>>(),
        );
        if residual > 1e-8 * scale {
            return false;
        }
        for w in &pairs.vectors[..a] {
            let dot: f64 = v.iter().zip(w).map(|(x, y)| x * y).sum();
            if dot.abs() > 1e-6 {
                return false;
            }
        }
    }
    true
}

fn krylov<O: SymmetricOperator>(op: &O, k: usize, max_dim: usize, scale: f64) -> Eigenpairs {
    let n = op.dim();
    let adapter = Adapter(op);
    let params = PartialEigenParams {
        max_dim,
        ..Default::default()
    };
    let par = Par::Seq; // the operator parallelises its own products
    let mut buffer = MemBuffer::new(partial_self_adjoint_eigen_scratch(&adapter, k, par, params));
    let stack = MemStack::new(&mut buffer);
    let v0 = start_vector(n);
    let v0 = Col::<f64>::from_fn(n, |i| v0[i]);
    let mut vectors = Mat::<f64>::zeros(n, k);
    let mut values = vec![0.0f64; k];
    let tol = TOL * scale;
    let info = partial_self_adjoint_eigen(
        vectors.as_mut(),
        &mut values,
        &adapter,
        v0.as_ref(),
        tol,
        par,
        stack,
        params,
    );
    let converged = info.n_converged_eigen.min(k);
    Eigenpairs {
        values: values[..converged].to_vec(),
        vectors: (0..converged)
            .map(|j| (0..n).map(|i| vectors[(i, j)]).collect())
            .collect(),
        unconverged: k - converged,
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // dense references index as the formulas do
mod tests {
    use super::*;

    /// A dense symmetric matrix as an operator (the naive reference).
    struct Dense(Vec<Vec<f64>>);

    impl SymmetricOperator for Dense {
        fn dim(&self) -> usize {
            self.0.len()
        }
        fn apply(&self, x: &[f64], y: &mut [f64]) {
            for (row, out) in self.0.iter().zip(y.iter_mut()) {
                *out = row.iter().zip(x).map(|(a, b)| a * b).sum();
            }
        }
    }

    fn random_symmetric(n: usize, seed: u64) -> Dense {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let mut m = vec![vec![0.0; n]; n];
        for i in 0..n {
            for j in 0..=i {
                let v: f64 = rng.r#gen::<f64>() - 0.5;
                m[i][j] = v;
                m[j][i] = v;
            }
        }
        // two dominant directions of opposite sign, as compartment matrices have
        for (scale, phase) in [(40.0, 0.1), (-25.0, 0.37)] {
            let u: Vec<f64> = (0..n).map(|i| (i as f64 * phase).sin()).collect();
            let nu = norm(&u);
            for i in 0..n {
                for j in 0..n {
                    m[i][j] += scale * u[i] * u[j] / (nu * nu);
                }
            }
        }
        Dense(m)
    }

    #[test]
    fn krylov_equals_dense_decomposition() {
        let op = random_symmetric(400, 7);
        let a = krylov(&op, 3, 64, norm_estimate(&op));
        let b = dense(&op, 3);
        assert_eq!(a.unconverged, 0);
        let mut av = a.values.clone();
        av.sort_by(|x, y| y.abs().total_cmp(&x.abs()));
        for (x, y) in av.iter().zip(&b.values) {
            assert!((x - y).abs() < 1e-9 * y.abs(), "{x} {y}");
        }
        assert!(b.values[1] < 0.0, "a negative eigenvalue among the largest");
        let sorted = largest_magnitude(&op, 3);
        for (e, v) in sorted.vectors.iter().enumerate() {
            let d = &b.vectors[e];
            let dot: f64 = v.iter().zip(d).map(|(x, y)| x * y).sum();
            assert!(
                (dot.abs() - 1.0).abs() < 1e-9,
                "vector {e}: |<a, b>| = {dot}"
            );
        }
    }
}
