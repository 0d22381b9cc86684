//! Compartment eigenvectors of one cis region (cooltools' `cis_eig`), from its sparse pixels.
//!
//! See the [module documentation](super) for the steps. The region is held as its upper
//! triangle in compressed rows ([`CisMatrix`], 12 bytes a stored pixel); the centred
//! observed/expected matrix is never built: [`ObsExpOperator`] applies it to vectors.

use rayon::prelude::*;

use crate::compartments::eigen::{self, SymmetricOperator};
use crate::error::{Error, Result};
use crate::numeric::{lerp, linspace};

/// Parameters of [`cis_eig`], with cooltools' defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CisEigParams {
    /// Eigenvectors to compute (cooltools: 3).
    pub n_eigs: usize,
    /// Diagonals `|i - j| < ignore_diags` are set to 1 before normalising (cooltools: the
    /// weight column's `ignore_diags` attribute, else 2).
    pub ignore_diags: usize,
    /// Observed/expected values above this percentile of the valid block are clipped to it
    /// (cooltools: 99.9; 0 or >= 100: no clipping).
    pub clip_percentile: f64,
}

impl CisEigParams {
    /// Check the values: at least one eigenvector, a clip percentile that is a number >= 0.
    ///
    /// ```
    /// use contactmap::compartments::cis::CisEigParams;
    ///
    /// assert!(CisEigParams::default().check().is_ok());
    /// let none = CisEigParams { n_eigs: 0, ..CisEigParams::default() };
    /// assert_eq!(none.check().unwrap_err().to_string(), "n_eigs 0: expected at least 1");
    /// ```
    pub fn check(&self) -> crate::error::Result<()> {
        if self.n_eigs == 0 {
            return Err(crate::error::Error::parameter(
                "n_eigs",
                0,
                "expected at least 1",
            ));
        }
        if !self.clip_percentile.is_finite() || self.clip_percentile < 0.0 {
            return Err(crate::error::Error::parameter(
                "clip_percentile",
                self.clip_percentile,
                "expected a percentile in 0..100 (0 or 100: no clipping)",
            ));
        }
        Ok(())
    }
}

impl Default for CisEigParams {
    fn default() -> Self {
        CisEigParams {
            n_eigs: 3,
            ignore_diags: 2,
            clip_percentile: 99.9,
        }
    }
}

/// The upper triangle of one region's balanced matrix in compressed rows, without the
/// diagonals `d < ignore_diags` (they are set to 1 by the method), and each bin's balanced
/// sum over every stored pixel (what decides the valid bins).
#[derive(Clone, Debug)]
pub struct CisMatrix {
    n: usize,
    ignore_diags: usize,
    row_ptr: Vec<usize>,
    cols: Vec<u32>,
    values: Vec<f64>,
    coverage: Vec<f64>,
}

/// Builds a [`CisMatrix`] from pixels given in `(i, j)` order, `i <= j` (local bin indices).
#[derive(Debug)]
pub struct CisMatrixBuilder {
    matrix: CisMatrix,
    row: usize,
    last: Option<(usize, usize)>,
}

impl CisMatrixBuilder {
    /// A builder for a region of `n` bins.
    pub fn new(n: usize, ignore_diags: usize) -> Self {
        CisMatrixBuilder {
            matrix: CisMatrix {
                n,
                ignore_diags,
                row_ptr: vec![0],
                cols: Vec::new(),
                values: Vec::new(),
                coverage: vec![0.0; n],
            },
            row: 0,
            last: None,
        }
    }

    /// Add the balanced value of pixel `(i, j)`; non-finite and zero values (bins without a
    /// weight, empty pixels) are left out.
    pub fn push(&mut self, i: usize, j: usize, value: f64) -> Result<()> {
        let m = &mut self.matrix;
        if i > j || j >= m.n || self.last.is_some_and(|last| (i, j) <= last) {
            return Err(Error::Data(format!(
                "pixel ({i}, {j}) out of order or outside a region of {} bins",
                m.n
            )));
        }
        self.last = Some((i, j));
        if !value.is_finite() || value == 0.0 {
            return Ok(());
        }
        m.coverage[i] += value;
        if j != i {
            m.coverage[j] += value;
        }
        if j - i < m.ignore_diags {
            return Ok(());
        }
        while self.row < i {
            m.row_ptr.push(m.cols.len());
            self.row += 1;
        }
        m.cols.push(j as u32);
        m.values.push(value);
        Ok(())
    }

    /// The matrix.
    pub fn finish(mut self) -> CisMatrix {
        let m = &mut self.matrix;
        while m.row_ptr.len() < m.n + 1 {
            m.row_ptr.push(m.cols.len());
        }
        self.matrix
    }
}

impl CisMatrix {
    fn row(&self, i: usize) -> (&[u32], &[f64]) {
        let r = self.row_ptr[i]..self.row_ptr[i + 1];
        (&self.cols[r.clone()], &self.values[r])
    }
}

/// Eigenvalues and eigenvectors of a region, cooltools' layout: `values[k]` and `vectors[k]`
/// (one value per bin of the region, NaN at bins left out) for `k < n_eigs`, ordered by
/// decreasing absolute eigenvalue, each vector of norm `sqrt(|value|)`; NaN where not computed.
#[derive(Clone, Debug, PartialEq)]
pub struct RegionEigs {
    /// Eigenvalues.
    pub values: Vec<f64>,
    /// Eigenvectors.
    pub vectors: Vec<Vec<f64>>,
    /// Eigenpairs the iteration did not bring below its tolerance (reported, still given).
    pub unconverged: usize,
}

impl RegionEigs {
    /// All NaN: cooltools' answer for a region too small or too empty.
    pub fn nan(n_eigs: usize, n_bins: usize) -> Self {
        RegionEigs {
            values: vec![f64::NAN; n_eigs],
            vectors: vec![vec![f64::NAN; n_bins]; n_eigs],
            unconverged: 0,
        }
    }

    /// cooltools' layout of the eigenpairs of an operator on the bins `kept` of a region of
    /// `n_bins`: each vector scaled to norm `sqrt(|value|)`, NaN at the other bins, NaN pairs
    /// past those found.
    pub fn from_eigenpairs(
        n_eigs: usize,
        n_bins: usize,
        kept: &[usize],
        pairs: &eigen::Eigenpairs,
    ) -> Self {
        let mut out = RegionEigs::nan(n_eigs, n_bins);
        out.unconverged = pairs.unconverged;
        for (e, (value, vector)) in pairs.values.iter().zip(&pairs.vectors).enumerate() {
            let norm = vector.iter().map(|v| v * v).sum::<f64>().sqrt();
            let scale = value.abs().sqrt() / norm;
            out.values[e] = *value;
            for (k, &bin) in kept.iter().enumerate() {
                out.vectors[e][bin] = vector[k] * scale;
            }
        }
        out
    }
}

/// The distance groups of cooltools' `observed_over_expected`: `[0] + _logbins_numba(1, n,
/// 1.03)`, edges of `[lo, hi)` groups of diagonals.
pub fn distance_groups(n: usize) -> Vec<usize> {
    let mut edges = vec![0usize];
    if n < 1 {
        return edges;
    }
    let count = ((n as f64).ln() / 1.03f64.ln()) as usize;
    let mut points: Vec<usize> = linspace(0.0, (n as f64).log10(), count)
        .into_iter()
        .map(|e| 10f64.powf(e).round_ties_even() as usize)
        .collect();
    points.sort_unstable();
    points.dedup();
    if points.first() != Some(&1) || points.last() != Some(&n) {
        // numpy's assertion holds for every n >= 2; for n = 1 the only group is diagonal 0
        points = vec![1];
    }
    edges.extend(points);
    edges
}

/// The region's valid bins and the prefix counts used to count valid pairs by distance.
struct Valid {
    mask: Vec<bool>,
    /// `prefix[k]`: valid bins among `0..k`.
    prefix: Vec<u64>,
}

impl Valid {
    fn new(mask: Vec<bool>) -> Self {
        let mut prefix = Vec::with_capacity(mask.len() + 1);
        let mut c = 0u64;
        prefix.push(0);
        for &m in &mask {
            c += m as u64;
            prefix.push(c);
        }
        Valid { mask, prefix }
    }

    fn count(&self) -> usize {
        *self.prefix.last().expect("prefix has n + 1 entries") as usize
    }

    /// Valid pairs `(j, j + d)` with both valid and `lo <= d < hi`.
    fn pairs_at(&self, lo: usize, hi: usize) -> u64 {
        let n = self.mask.len();
        if lo >= hi || lo >= n {
            return 0;
        }
        let prefix = &self.prefix;
        let mask = &self.mask;
        (0..n - lo)
            .into_par_iter()
            .with_min_len(4096)
            .filter(|&j| mask[j])
            .map(|j| prefix[(j + hi).min(n)] - prefix[j + lo])
            .sum()
    }
}

/// The clipped, centred observed/expected matrix of a region restricted to its kept bins,
/// applied to vectors: `y = (S - 1) x` where `S` holds the stored pixels' observed/expected,
/// the ignored diagonals' `1 / mean` band, and 0 elsewhere.
pub struct ObsExpOperator<'a> {
    matrix: &'a CisMatrix,
    /// Observed/expected of each stored value (same layout as `matrix.values`).
    oe: Vec<f64>,
    /// `band[d]`: the value of every valid pair at distance `d < ignore_diags`.
    band: Vec<f64>,
    /// Kept bins (valid, not an all-zero row), in order.
    kept: Vec<usize>,
    /// Rows per parallel task, balanced by stored pixels.
    tasks: Vec<std::ops::Range<usize>>,
}

impl SymmetricOperator for ObsExpOperator<'_> {
    fn dim(&self) -> usize {
        self.kept.len()
    }

    fn apply(&self, x: &[f64], y: &mut [f64]) {
        let n = self.matrix.n;
        let mut full = vec![0.0f64; n];
        for (k, &bin) in self.kept.iter().enumerate() {
            full[bin] = x[k];
        }
        let full = &full;
        let sum_x: f64 = x.iter().sum();
        let acc = self
            .tasks
            .par_iter()
            .fold(
                || vec![0.0f64; n],
                |mut acc, rows| {
                    for i in rows.clone() {
                        let (cols, _) = self.matrix.row(i);
                        let start = self.matrix.row_ptr[i];
                        let values = &self.oe[start..start + cols.len()];
                        let xi = full[i];
                        let mut yi = 0.0;
                        for (&j, &v) in cols.iter().zip(values) {
                            let j = j as usize;
                            yi += v * full[j];
                            if j != i {
                                acc[j] += v * xi;
                            }
                        }
                        acc[i] += yi;
                    }
                    acc
                },
            )
            .reduce_with(|mut a, b| {
                for (x, y) in a.iter_mut().zip(&b) {
                    *x += y;
                }
                a
            })
            .unwrap_or_else(|| vec![0.0; n]);
        let mut acc = acc;
        for (d, &b) in self.band.iter().enumerate() {
            if b == 0.0 {
                continue;
            }
            for i in 0..n.saturating_sub(d) {
                acc[i] += b * full[i + d];
                if d > 0 {
                    acc[i + d] += b * full[i];
                }
            }
        }
        for (k, &bin) in self.kept.iter().enumerate() {
            y[k] = acc[bin] - sum_x;
        }
    }
}

/// cooltools' `cis_eig` on one region (see the [module documentation](super)).
pub fn cis_eig(matrix: &CisMatrix, params: &CisEigParams) -> RegionEigs {
    let n = matrix.n;
    let ignore = params.ignore_diags;
    let n_eigs = params.n_eigs;
    let valid = Valid::new(matrix.coverage.iter().map(|&c| c > 0.0).collect());
    let n_valid = valid.count();
    if n <= ignore + 3 || n_valid <= ignore + 3 {
        return RegionEigs::nan(n_eigs, n);
    }

    // mean of each distance group over its valid pairs (the ignored diagonals count as 1)
    let edges = distance_groups(n);
    let n_groups = edges.len() - 1;
    let mut group_of = vec![0u32; n];
    for g in 0..n_groups {
        for slot in &mut group_of[edges[g]..edges[g + 1].min(n)] {
            *slot = g as u32;
        }
    }
    let stored_sums = (0..n)
        .into_par_iter()
        .with_min_len(256)
        .fold(
            || vec![0.0f64; n_groups],
            |mut acc, i| {
                let (cols, values) = matrix.row(i);
                for (&j, &v) in cols.iter().zip(values) {
                    acc[group_of[j as usize - i] as usize] += v;
                }
                acc
            },
        )
        .reduce(
            || vec![0.0f64; n_groups],
            |mut a, b| {
                for (x, y) in a.iter_mut().zip(&b) {
                    *x += y;
                }
                a
            },
        );
    let mut means = vec![1.0f64; n_groups];
    for g in 0..n_groups {
        let (lo, hi) = (edges[g], edges[g + 1]);
        let pairs = valid.pairs_at(lo, hi);
        let ones = valid.pairs_at(lo, hi.min(ignore)) as f64;
        if pairs == 0 {
            continue;
        }
        let mean = (stored_sums[g] + ones) / pairs as f64;
        if mean != 0.0 {
            means[g] = mean;
        }
    }
    let mut oe: Vec<f64> = vec![0.0; matrix.values.len()];
    oe.par_chunks_mut(1 << 16)
        .enumerate()
        .for_each(|(chunk, out)| {
            let start = chunk << 16;
            // the row of each value: find the first row by bisection, then walk
            let mut i = matrix.row_ptr.partition_point(|&p| p <= start) - 1;
            for (k, slot) in out.iter_mut().enumerate() {
                let at = start + k;
                while matrix.row_ptr[i + 1] <= at {
                    i += 1;
                }
                let d = matrix.cols[at] as usize - i;
                *slot = matrix.values[at] / means[group_of[d] as usize];
            }
        });
    let mut band: Vec<f64> = (0..ignore.min(n))
        .map(|d| 1.0 / means[group_of[d] as usize])
        .collect();

    // clip at the percentile of the dense valid block (unstored pairs are zeros)
    if params.clip_percentile > 0.0 && params.clip_percentile < 100.0 {
        let q = clip_value(matrix, &oe, &band, &valid, params.clip_percentile);
        oe.par_iter_mut().for_each(|v| *v = v.clamp(0.0, q));
        for b in &mut band {
            *b = b.clamp(0.0, q);
        }
    }

    // rows of OE - 1 that are all zero (every valid pair exactly 1) are left out, as cooltools'
    // get_eig(mask_zero_rows=True) does
    let mut ones = vec![0u64; n];
    for i in 0..n {
        let (cols, _) = matrix.row(i);
        let start = matrix.row_ptr[i];
        for (k, &j) in cols.iter().enumerate() {
            if oe[start + k] == 1.0 {
                ones[i] += 1;
                ones[j as usize] += 1;
            }
        }
    }
    for (d, &b) in band.iter().enumerate() {
        if b == 1.0 {
            for i in 0..n - d {
                if valid.mask[i] && valid.mask[i + d] {
                    ones[i] += 1;
                    if d > 0 {
                        ones[i + d] += 1;
                    }
                }
            }
        }
    }
    let kept: Vec<usize> = (0..n)
        .filter(|&i| valid.mask[i] && ones[i] < n_valid as u64)
        .collect();
    let operator = ObsExpOperator {
        tasks: row_tasks(matrix),
        matrix,
        oe,
        band,
        kept,
    };
    let dim = operator.dim();
    if dim == 0 {
        return RegionEigs::nan(n_eigs, n);
    }
    // scipy's eigsh asks for at most dim - 1 eigenpairs
    let k = n_eigs.min(dim.saturating_sub(1));
    let solved = eigen::largest_magnitude(&operator, k);
    RegionEigs::from_eigenpairs(n_eigs, n, &operator.kept, &solved)
}

/// Rows grouped into parallel tasks of about equal stored pixels.
fn row_tasks(matrix: &CisMatrix) -> Vec<std::ops::Range<usize>> {
    let n = matrix.n;
    let total = matrix.cols.len() + n;
    let n_tasks = (rayon::current_num_threads() * 4).max(1);
    let per_task = total.div_ceil(n_tasks).max(1);
    let mut tasks = Vec::new();
    let mut start = 0;
    let mut load = 0;
    for i in 0..n {
        load += matrix.row_ptr[i + 1] - matrix.row_ptr[i] + 1;
        if load >= per_task {
            tasks.push(start..i + 1);
            start = i + 1;
            load = 0;
        }
    }
    if start < n {
        tasks.push(start..n);
    }
    tasks
}

/// `np.percentile(OE[mask][:, mask], p)`: the dense valid block holds each stored value twice
/// (once on the diagonal), the band values on every valid pair at their distance, and zeros.
fn clip_value(matrix: &CisMatrix, oe: &[f64], band: &[f64], valid: &Valid, p: f64) -> f64 {
    let n_valid = valid.count() as u64;
    let total = n_valid * n_valid;
    // (value, multiplicity) sources, each sorted ascending
    let mut off: Vec<f64> = Vec::with_capacity(oe.len());
    let mut diag: Vec<f64> = Vec::new();
    for i in 0..matrix.n {
        let (cols, _) = matrix.row(i);
        let start = matrix.row_ptr[i];
        for (k, &j) in cols.iter().enumerate() {
            if j as usize == i {
                diag.push(oe[start + k]);
            } else {
                off.push(oe[start + k]);
            }
        }
    }
    off.par_sort_unstable_by(f64::total_cmp);
    diag.sort_unstable_by(f64::total_cmp);
    let mut bands: Vec<(f64, u64)> = band
        .iter()
        .enumerate()
        .map(|(d, &b)| {
            let pairs = valid.pairs_at(d, d + 1);
            (b, if d == 0 { pairs } else { 2 * pairs })
        })
        .collect();
    bands.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    let virtual_index = (total - 1) as f64 * (p / 100.0);
    let below = virtual_index.floor();
    let gamma = virtual_index - below;
    let below = below as u64;
    // values at ascending ranks `below` and `below + 1`, found walking down from the largest
    // (the rank sought is near the top); from the top, rank r is index total - 1 - r
    let above = (below + 1).min(total - 1);
    let targets = [total - 1 - above, total - 1 - below];
    let mut found = [0.0f64; 2]; // past every stored value: the zeros
    let (mut a, mut b, mut c) = (off.len(), diag.len(), bands.len());
    let mut seen = 0u64;
    let mut slot = 0;
    while slot < 2 {
        let tops = [
            (a > 0).then(|| off[a - 1]),
            (b > 0).then(|| diag[b - 1]),
            (c > 0).then(|| bands[c - 1].0),
        ];
        let Some((source, value)) = tops
            .into_iter()
            .enumerate()
            .filter_map(|(s, v)| v.map(|v| (s, v)))
            .max_by(|x, y| x.1.total_cmp(&y.1))
        else {
            break;
        };
        let weight = match source {
            0 => {
                a -= 1;
                2
            }
            1 => {
                b -= 1;
                1
            }
            _ => {
                c -= 1;
                bands[c].1
            }
        };
        seen += weight;
        while slot < 2 && targets[slot] < seen {
            found[slot] = value;
            slot += 1;
        }
    }
    lerp(found[1], found[0], gamma)
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // dense references index as the formulas do
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// cooltools' cis_eig step by step on a dense matrix (the naive reference).
    fn dense_cis_eig(a: &[Vec<f64>], params: &CisEigParams) -> (Vec<f64>, Vec<Vec<f64>>) {
        let n = a.len();
        let mut a: Vec<Vec<f64>> = a.to_vec();
        let mask: Vec<bool> = (0..n)
            .map(|j| (0..n).map(|i| a[i][j]).sum::<f64>() > 0.0)
            .collect();
        for d in 0..params.ignore_diags.min(n) {
            for i in 0..n - d {
                a[i][i + d] = 1.0;
                a[i + d][i] = 1.0;
            }
        }
        let edges = distance_groups(n);
        for g in 0..edges.len() - 1 {
            let (mut sum, mut count) = (0.0, 0usize);
            for d in edges[g]..edges[g + 1] {
                for j in 0..n - d {
                    if mask[j] && mask[j + d] {
                        sum += a[j + d][j];
                        count += 1;
                    }
                }
            }
            if count == 0 || sum == 0.0 {
                continue;
            }
            let mean = sum / count as f64;
            for d in edges[g]..edges[g + 1] {
                for j in 0..n - d {
                    if mask[j] && mask[j + d] {
                        a[j + d][j] /= mean;
                        if d > 0 {
                            a[j][j + d] /= mean;
                        }
                    }
                }
            }
        }
        let valid: Vec<usize> = (0..n).filter(|&i| mask[i]).collect();
        if params.clip_percentile > 0.0 && params.clip_percentile < 100.0 {
            let mut block: Vec<f64> = valid
                .iter()
                .flat_map(|&i| valid.iter().map(move |&j| (i, j)))
                .map(|(i, j)| a[i][j])
                .collect();
            block.sort_by(f64::total_cmp);
            let vi = (block.len() - 1) as f64 * (params.clip_percentile / 100.0);
            let lo = vi.floor();
            let q = lerp(
                block[lo as usize],
                block[(lo as usize + 1).min(block.len() - 1)],
                vi - lo,
            );
            for row in &mut a {
                for v in row.iter_mut() {
                    *v = v.clamp(0.0, q);
                }
            }
        }
        struct D(Vec<Vec<f64>>);
        impl SymmetricOperator for D {
            fn dim(&self) -> usize {
                self.0.len()
            }
            fn apply(&self, x: &[f64], y: &mut [f64]) {
                for (row, out) in self.0.iter().zip(y.iter_mut()) {
                    *out = row.iter().zip(x).map(|(a, b)| a * b).sum();
                }
            }
        }
        let m = D(valid
            .iter()
            .map(|&i| valid.iter().map(|&j| a[i][j] - 1.0).collect())
            .collect());
        let k = params.n_eigs.min(valid.len() - 1);
        let pairs = eigen::largest_magnitude(&m, k);
        let vectors = pairs
            .vectors
            .iter()
            .zip(&pairs.values)
            .map(|(v, l)| {
                let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                let mut full = vec![f64::NAN; n];
                for (k, &i) in valid.iter().enumerate() {
                    full[i] = v[k] / norm * l.abs().sqrt();
                }
                full
            })
            .collect();
        (pairs.values, vectors)
    }

    /// A banded random map with power-law decay, compartment-like checkerboard and empty bins.
    fn random_map(n: usize, seed: u64) -> Vec<Vec<f64>> {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let kind: Vec<f64> = (0..n)
            .map(|i| if (i / 17) % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let empty: Vec<bool> = (0..n).map(|_| rng.r#gen::<f64>() < 0.05).collect();
        let mut a = vec![vec![0.0; n]; n];
        for i in 0..n {
            for j in i..n.min(i + n / 2) {
                if empty[i] || empty[j] || rng.r#gen::<f64>() < 0.3 {
                    continue;
                }
                let d = (j - i) as f64 + 1.0;
                let v = (1.0 + 0.5 * kind[i] * kind[j]) / d * (0.5 + rng.r#gen::<f64>());
                a[i][j] = v;
                a[j][i] = v;
            }
        }
        a
    }

    #[test]
    fn sparse_operator_equals_dense_cooltools_steps() {
        for (seed, n, ignore, clip) in [
            (1, 300, 2, 99.9),
            (2, 260, 0, 90.0),
            (3, 200, 3, 0.0),
            (4, 90, 1, 99.0),
        ] {
            let a = random_map(n, seed);
            let params = CisEigParams {
                n_eigs: 3,
                ignore_diags: ignore,
                clip_percentile: clip,
            };
            let mut builder = CisMatrixBuilder::new(n, ignore);
            for i in 0..n {
                for j in i..n {
                    builder.push(i, j, a[i][j]).unwrap();
                }
            }
            let got = cis_eig(&builder.finish(), &params);
            let (values, vectors) = dense_cis_eig(&a, &params);
            assert_eq!(got.unconverged, 0);
            for e in 0..3 {
                assert!(
                    (got.values[e] - values[e]).abs() <= 1e-9 * values[e].abs(),
                    "seed {seed}: {:?} vs {values:?}",
                    got.values
                );
                let (g, w) = (&got.vectors[e], &vectors[e]);
                let dot: f64 = g
                    .iter()
                    .zip(w)
                    .filter(|(x, _)| x.is_finite())
                    .map(|(x, y)| x * y)
                    .sum();
                let sign = dot.signum();
                for (x, y) in g.iter().zip(w) {
                    assert_eq!(x.is_nan(), y.is_nan());
                    if x.is_finite() {
                        assert!(
                            (x - sign * y).abs() <= 1e-8 * values[e].abs().sqrt(),
                            "seed {seed} E{}: {x} vs {y}",
                            e + 1
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn distance_groups_as_numpy() {
        // cooltools.lib.numutils._logbins_numba(1, n, 1.03): (n, edges, sum, last four)
        for (n, len, sum, last) in [
            (7, 7, 28, [4, 5, 6, 7]),
            (1000, 148, 33540, [915, 942, 971, 1000]),
            (25000, 256, 853824, [22869, 23558, 24268, 25000]),
            (250000, 334, 8552767, [228713, 235599, 242693, 250000]),
        ] {
            let g = distance_groups(n);
            assert_eq!(g[0], 0, "prepended 0");
            assert_eq!(g.len() - 1, len, "n = {n}");
            assert_eq!(g.iter().sum::<usize>(), sum, "n = {n}");
            assert_eq!(g[g.len() - 4..], last, "n = {n}");
        }
    }

    #[test]
    fn too_small_regions_are_nan() {
        let mut b = CisMatrixBuilder::new(5, 2);
        b.push(0, 3, 1.0).unwrap();
        let e = cis_eig(&b.finish(), &CisEigParams::default());
        assert!(e.values.iter().all(|v| v.is_nan()));
        let mut b = CisMatrixBuilder::new(4, 2);
        b.push(1, 3, 1.0).unwrap();
        assert!(b.push(0, 2, 1.0).is_err(), "out of order");
    }
}
