use super::kr::juicer_percentile;
use super::passes::*;
use super::*;
use crate::genome::BinTable;
use crate::genome::Chrom;
use crate::matrix::{CountType, PixelBlock, Pixels};
use crate::numeric::median;
use proptest::prelude::*;

/// Pixels from a dense symmetric matrix (upper triangle, zeros left out).
fn pixels_from_dense(bins: BinTable, dense: &[Vec<f64>]) -> Pixels {
    let n = dense.len();
    let mut block = PixelBlock::default();
    for (i, row) in dense.iter().enumerate() {
        for (j, &c) in row.iter().enumerate().skip(i) {
            if c != 0.0 {
                block.push(i as u64, j as u64, c);
            }
        }
    }
    let mut pixels = Pixels::with_capacity(bins, CountType::Float, n * n).unwrap();
    pixels.extend(&block).unwrap();
    pixels
}

fn bins_for(chrom_sizes: &[u64]) -> BinTable {
    let chroms = chrom_sizes
        .iter()
        .enumerate()
        .map(|(k, &n)| Chrom::new(format!("c{k}"), n * 10))
        .collect();
    BinTable::fixed(chroms, 10).unwrap()
}

/// A direct transcription of cooler's `balance_cooler` on a dense matrix (genome-wide or
/// cis-only, one chromosome after the other as cooler does).
fn naive_ice(dense: &[Vec<f64>], chrom_of: &[usize], params: &BalanceParams) -> Vec<f64> {
    let n = dense.len();
    let cis = params.scope == Scope::Cis;
    let keep = |i: usize, j: usize| {
        (i as i64 - j as i64).unsigned_abs() >= params.ignore_diags
            && (!cis || chrom_of[i] == chrom_of[j])
    };
    let mut bias = vec![1.0; n];
    let marginal = |i: usize, f: &dyn Fn(usize, usize) -> f64| -> f64 {
        (0..n).filter(|&j| keep(i, j)).map(|j| f(i, j)).sum()
    };
    for i in 0..n {
        let nnz = marginal(i, &|i, j| (dense[i][j] != 0.0) as u8 as f64);
        if nnz < params.min_nnz as f64 {
            bias[i] = 0.0;
        }
    }
    let mut marg: Vec<f64> = (0..n).map(|i| marginal(i, &|i, j| dense[i][j])).collect();
    let n_chroms = chrom_of.iter().max().map_or(0, |m| m + 1);
    if params.mad_max > 0.0 {
        for c in 0..n_chroms {
            let mut pos: Vec<f64> = (0..n)
                .filter(|&i| chrom_of[i] == c && marg[i] > 0.0)
                .map(|i| marg[i])
                .collect();
            let med = median(&mut pos);
            for i in 0..n {
                if chrom_of[i] == c {
                    marg[i] /= med;
                }
            }
        }
        let mut logs: Vec<f64> = marg.iter().filter(|&&m| m > 0.0).map(|m| m.ln()).collect();
        let med = median(&mut logs);
        let mut dev: Vec<f64> = logs.iter().map(|l| (l - med).abs()).collect();
        let mad = median(&mut dev);
        let cutoff = (med - params.mad_max * mad).exp();
        for i in 0..n {
            if marg[i] < cutoff {
                bias[i] = 0.0;
            }
        }
    }
    let groups: Vec<Vec<usize>> = if cis {
        (0..n_chroms)
            .map(|c| (0..n).filter(|&i| chrom_of[i] == c).collect())
            .collect()
    } else {
        vec![(0..n).collect()]
    };
    for group in groups {
        let mut scale = f64::NAN;
        for _ in 0..params.max_iters {
            let m: Vec<f64> = group
                .iter()
                .map(|&i| marginal(i, &|i, j| dense[i][j] * bias[i] * bias[j]))
                .collect();
            let nz: Vec<f64> = m.iter().copied().filter(|&v| v != 0.0).collect();
            if nz.is_empty() {
                for &i in &group {
                    bias[i] = f64::NAN;
                }
                break;
            }
            let mean = nz.iter().sum::<f64>() / nz.len() as f64;
            let var = nz.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / nz.len() as f64;
            for (k, &i) in group.iter().enumerate() {
                let r = m[k] / mean;
                bias[i] /= if r == 0.0 { 1.0 } else { r };
            }
            scale = mean;
            if var < params.tol {
                break;
            }
        }
        for &i in &group {
            if bias[i] == 0.0 {
                bias[i] = f64::NAN;
            }
            bias[i] /= scale.sqrt();
        }
    }
    bias
}

fn assert_close(got: &[f64], want: &[f64], tolerance: f64) {
    assert_eq!(got.len(), want.len());
    for (k, (a, b)) in got.iter().zip(want).enumerate() {
        assert_eq!(a.is_nan(), b.is_nan(), "bin {k}: {a} vs {b}");
        if !a.is_nan() {
            assert!(
                (a - b).abs() <= tolerance * b.abs(),
                "bin {k}: {a} vs {b} (relative {})",
                (a - b).abs() / b.abs()
            );
        }
    }
}

/// A small random symmetric "Hi-C-like" matrix: decaying with distance, some empty bins.
/// Balance a random dense matrix on chromosomes of `sizes` bins with Juicer's parameters for
/// `method` (per chromosome when `cis`), then check per group: converged, the balanced total
/// equals the raw one (Juicer's sum factor), and every balanced row is within `tolerance` of
/// their mean.
fn check_balanced(
    seed: u64,
    sizes: &[u64],
    cis: bool,
    method: Method,
    tolerance: f64,
) -> std::result::Result<(), TestCaseError> {
    let bins = bins_for(sizes);
    let dense = random_matrix(bins.n_bins(), seed, &[]);
    let pixels = pixels_from_dense(bins.clone(), &dense);
    let params = BalanceParams {
        scope: if cis { Scope::Cis } else { Scope::GenomeWide },
        ..BalanceParams::juicer(method)
    };
    let got = balance(&pixels, &params).unwrap();
    prop_assert!(got.converged);
    let w = &got.weights;
    let groups: Vec<Vec<usize>> = if params.scope == Scope::Cis {
        (0..bins.n_chroms())
            .map(|c| bins.chrom_bins(c).collect())
            .collect()
    } else {
        vec![(0..bins.n_bins()).collect()]
    };
    for group in groups {
        let valid: Vec<usize> = group.iter().copied().filter(|&i| !w[i].is_nan()).collect();
        prop_assert!(!valid.is_empty());
        let rows: Vec<f64> = valid
            .iter()
            .map(|&i| valid.iter().map(|&j| dense[i][j] * w[i] * w[j]).sum())
            .collect();
        let total: f64 = rows.iter().sum();
        let raw: f64 = valid
            .iter()
            .map(|&i| valid.iter().map(|&j| dense[i][j]).sum::<f64>())
            .sum();
        prop_assert!((total - raw).abs() <= 1e-9 * raw);
        let mean = total / rows.len() as f64;
        for r in rows {
            prop_assert!(
                (r - mean).abs() <= tolerance * mean,
                "row {r} vs mean {mean}"
            );
        }
    }
    Ok(())
}

fn random_matrix(n: usize, seed: u64, empty: &[usize]) -> Vec<Vec<f64>> {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15).wrapping_add(1);
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut dense = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in i..n {
            let expected = 200.0 / (1.0 + (j - i) as f64).powf(1.1);
            let value = (expected * (0.2 + 1.6 * next())).floor();
            let value = if empty.contains(&i) || empty.contains(&j) {
                0.0
            } else {
                value
            };
            dense[i][j] = value;
            dense[j][i] = value;
        }
    }
    dense
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn ice_matches_a_naive_dense_transcription_of_cooler(
        seed in 0u64..1000,
        sizes in proptest::collection::vec(3u64..14, 1..4),
        empty in proptest::collection::vec(0usize..40, 0..3),
        cis in any::<bool>(),
        ignore_diags in 0u64..3,
        min_nnz in 0u64..6,
    ) {
        let bins = bins_for(&sizes);
        let n = bins.n_bins();
        let dense = random_matrix(n, seed, &empty);
        let pixels = pixels_from_dense(bins.clone(), &dense);
        let chrom_of: Vec<usize> = (0..n).map(|b| bins.chrom_of(b)).collect();
        let params = BalanceParams {
            scope: if cis { Scope::Cis } else { Scope::GenomeWide },
            ignore_diags,
            min_nnz,
            tol: 1e-12,
            max_iters: 500,
            ..BalanceParams::default()
        };
        let got = balance(&pixels, &params).unwrap();
        let want = naive_ice(&dense, &chrom_of, &params);
        assert_close(&got.weights, &want, 1e-9);
    }

    #[test]
    fn kr_balances_rows_and_keeps_the_sum(
        seed in 0u64..1000,
        sizes in proptest::collection::vec(4u64..14, 1..3),
        cis in any::<bool>(),
    ) {
        check_balanced(seed, &sizes, cis, Method::Kr, 1e-5)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn scale_balances_rows_and_keeps_the_sum(
        seed in 0u64..1000,
        sizes in proptest::collection::vec(4u64..14, 1..3),
        cis in any::<bool>(),
    ) {
        // The rows are balanced to SCALE's row-sum tolerance (5 tol = 0.25%).
        check_balanced(seed, &sizes, cis, Method::Scale, 5.0 * super::params::SCALE_TOL)?;
    }
}

#[test]
fn an_already_balanced_matrix_converges_in_one_iteration() {
    // A ring: every bin touches its two neighbours with the same count, and itself.
    let n = 12;
    let mut dense = vec![vec![0.0; n]; n];
    for i in 0..n {
        dense[i][i] = 4.0;
        dense[i][(i + 1) % n] = 3.0;
        dense[(i + 1) % n][i] = 3.0;
    }
    let bins = bins_for(&[n as u64]);
    let pixels = pixels_from_dense(bins, &dense);
    let params = BalanceParams {
        ignore_diags: 0,
        min_nnz: 0,
        ..BalanceParams::default()
    };
    let result = balance(&pixels, &params).unwrap();
    assert!(result.converged);
    assert_eq!(result.n_iterations, 1);
    assert_eq!(result.var, 0.0);
    // Row sums are 4 + 3 + 3 = 10: the scale, and the weights 1 / sqrt(10).
    assert!((result.scale - 10.0).abs() < 1e-12);
    for w in &result.weights {
        assert!((w - 1.0 / 10f64.sqrt()).abs() < 1e-15);
    }
    // VC and KR agree on such a matrix: all weights equal and the balanced sum is the raw sum.
    for method in [Method::Vc, Method::VcSqrt, Method::Kr] {
        let result = balance(&pixels, &BalanceParams::juicer(method)).unwrap();
        assert!(result.converged);
        for w in &result.weights {
            assert!((w - 1.0).abs() < 1e-9, "{method:?}: {w}");
        }
    }
}

#[test]
fn vc_is_the_inverse_row_sum_scaled_to_keep_the_total() {
    let bins = bins_for(&[7, 5]);
    let dense = random_matrix(12, 7, &[3]);
    let pixels = pixels_from_dense(bins.clone(), &dense);
    for (method, power) in [(Method::Vc, 1.0), (Method::VcSqrt, 0.5)] {
        let result = balance(&pixels, &BalanceParams::juicer(method)).unwrap();
        let sums: Vec<f64> = dense.iter().map(|r| r.iter().sum()).collect();
        assert!(result.weights[3].is_nan());
        // w_i * sum_i^power is the same constant for every valid bin ...
        let constant = result.weights[0] * sums[0].powf(power);
        for i in (0..12).filter(|&i| i != 3) {
            assert!((result.weights[i] * sums[i].powf(power) - constant).abs() < 1e-12 * constant);
        }
        // ... chosen so that the balanced matrix sums to the raw one.
        let w = &result.weights;
        let (mut balanced, mut raw) = (0.0, 0.0);
        for i in (0..12).filter(|&i| i != 3) {
            for j in (0..12).filter(|&j| j != 3) {
                balanced += dense[i][j] * w[i] * w[j];
                raw += dense[i][j];
            }
        }
        assert!((balanced - raw).abs() < 1e-9 * raw);
    }
}

#[test]
fn an_empty_chromosome_gets_nan_weights_and_the_others_are_balanced() {
    let bins = bins_for(&[30, 4, 30]);
    let empty: Vec<usize> = (30..34).collect();
    let dense = random_matrix(64, 3, &empty);
    let pixels = pixels_from_dense(bins, &dense);
    for scope in [Scope::GenomeWide, Scope::Cis] {
        let params = BalanceParams {
            scope,
            ..BalanceParams::default()
        };
        let result = balance(&pixels, &params).unwrap();
        assert!(result.converged);
        assert!(result.weights[30..34].iter().all(|w| w.is_nan()));
        let n_finite = result.weights.iter().filter(|w| w.is_finite()).count();
        assert!(n_finite >= 50, "{n_finite}");
        if scope == Scope::Cis {
            let per_chrom = result.per_chrom.as_ref().unwrap();
            assert!(per_chrom[1].scale.is_nan());
            assert_eq!(per_chrom[1].var, 0.0);
            assert!(per_chrom[1].converged);
            assert!(per_chrom[0].scale.is_finite());
        }
    }
    // Without the min_nnz filter an empty bin is never masked: cooler then keeps its
    // initial bias (1 / sqrt(scale)); so do we.
    let params = BalanceParams {
        min_nnz: 0,
        mad_max: 0.0,
        ..BalanceParams::default()
    };
    let result = balance(&pixels, &params).unwrap();
    assert!((result.weights[31] - 1.0 / result.scale.sqrt()).abs() < 1e-15);
}

#[test]
fn trans_only_balances_the_trans_marginals() {
    let bins = bins_for(&[6, 6, 5]);
    let dense = random_matrix(17, 11, &[]);
    let pixels = pixels_from_dense(bins.clone(), &dense);
    let params = BalanceParams {
        scope: Scope::Trans,
        min_nnz: 0,
        mad_max: 0.0,
        tol: 1e-14,
        max_iters: 2000,
        ..BalanceParams::default()
    };
    let result = balance(&pixels, &params).unwrap();
    assert!(result.converged);
    let w = &result.weights;
    // cooler's chromosome weights make the trans marginals of (b * cw) equal: check that.
    let cw: Vec<f64> = (0..17)
        .map(|b| {
            let n_c = bins.chrom_bins(bins.chrom_of(b)).len() as f64;
            1.0 / (1.0 - n_c / 17.0)
        })
        .collect();
    let rows: Vec<f64> = (0..17)
        .map(|i| {
            (0..17)
                // Trans pixels, minus the first two diagonals (cooler's filter is positional).
                .filter(|&j| bins.chrom_of(i) != bins.chrom_of(j) && i.abs_diff(j) >= 2)
                .map(|j| dense[i][j] * w[i] * cw[i] * w[j] * cw[j])
                .sum()
        })
        .collect();
    for r in &rows {
        assert!(
            (r - rows[0]).abs() < 1e-6 * rows[0],
            "{rows:?} {}",
            result.scale
        );
    }
}

#[test]
fn bad_parameters_are_rejected() {
    let bins = bins_for(&[5]);
    let pixels = pixels_from_dense(bins, &random_matrix(5, 1, &[]));
    for params in [
        BalanceParams {
            tol: 0.0,
            ..BalanceParams::default()
        },
        BalanceParams {
            max_iters: 0,
            ..BalanceParams::default()
        },
        BalanceParams {
            blacklist: vec![5],
            ..BalanceParams::default()
        },
    ] {
        assert!(balance(&pixels, &params).is_err());
    }
}

#[test]
fn juicer_percentile_interpolates_as_commons_math() {
    let mut v = vec![5.0, 1.0, 4.0, 2.0, 3.0];
    // pos = 10 * 6 / 100 = 0.6 < 1: the minimum.
    assert_eq!(juicer_percentile(&mut v, 10.0), 1.0);
    // pos = 50 * 6 / 100 = 3: the third value.
    assert_eq!(juicer_percentile(&mut v, 50.0), 3.0);
    // pos = 25 * 6 / 100 = 1.5: halfway between the first and second.
    assert_eq!(juicer_percentile(&mut v, 25.0), 1.5);
}

#[test]
fn partial_sums_do_not_depend_on_how_pixels_are_sliced() {
    let n = 9000;
    let mut a = BinSums {
        start: 100,
        dense: vec![0.0; 50],
        n_bins: n,
        ..BinSums::default()
    };
    a.add(120, 1.0);
    a.add(8000, 2.0);
    a.add(5, 3.0);
    let mut b = BinSums {
        start: 4000,
        dense: vec![0.0; 10],
        n_bins: n,
        ..BinSums::default()
    };
    b.add(4005, 4.0);
    b.add(120, 5.0);
    let full = BinSums::default().merge(a).merge(b).into_vec(n);
    assert_eq!(full[120], 6.0);
    assert_eq!(full[8000], 2.0);
    assert_eq!(full[5], 3.0);
    assert_eq!(full[4005], 4.0);
    assert_eq!(full.iter().sum::<f64>(), 15.0);
}

/// The same pixels, streamed as a file is (no in-memory copy offered to the balancers).
struct Streaming<'a>(&'a Pixels);

impl crate::matrix::PixelSource for Streaming<'_> {
    fn bins(&self) -> &BinTable {
        self.0.bins()
    }

    fn count_type(&self) -> CountType {
        self.0.count_type()
    }

    fn pass<T, I, F, R>(&self, init: I, fold: F, reduce: R) -> crate::error::Result<T>
    where
        T: Send,
        I: Fn() -> T + Sync,
        F: Fn(T, crate::matrix::PixelSlice<'_>) -> T + Sync,
        R: Fn(T, T) -> T + Sync,
    {
        self.0.pass(init, fold, reduce)
    }
}

#[test]
fn ice_on_the_compact_copy_equals_ice_on_streamed_pixels() {
    // 6,000 bins on three chromosomes: a band of 40 diagonals, and far pixels (beyond the
    // sums' dense windows, and trans) on every 7th row; integer counts (kept in 4 bytes) and
    // fractional ones (kept in 8)
    let bins = bins_for(&[2500, 2000, 1500]);
    let n = bins.n_bins();
    for fractional in [false, true] {
        let mut block = PixelBlock::default();
        let mut state = 12345u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as f64 / (1u64 << 31) as f64
        };
        for i in 0..n {
            let mut columns: Vec<usize> = (i..(i + 40).min(n)).collect();
            if i % 7 == 0 {
                columns.extend(
                    [i + 4500, i + 5200, i + 5900]
                        .into_iter()
                        .filter(|&j| j < n),
                );
            }
            for j in columns {
                let base = 300.0 / (1.0 + (j - i) as f64) * (0.5 + next());
                let count = if fractional { base } else { base.floor() };
                if count > 0.0 {
                    block.push(i as u64, j as u64, count);
                }
            }
        }
        let mut pixels =
            Pixels::with_capacity(bins.clone(), CountType::Float, block.len()).unwrap();
        pixels.extend(&block).unwrap();
        assert!(pixels.len() > 2 * (1 << 16));
        for scope in [Scope::GenomeWide, Scope::Cis, Scope::Trans] {
            let params = BalanceParams {
                scope,
                max_iters: 50,
                ..BalanceParams::default()
            };
            let compact = balance(&pixels, &params).unwrap();
            let streamed = balance(&Streaming(&pixels), &params).unwrap();
            assert_eq!(compact.n_iterations, streamed.n_iterations);
            assert_close(&compact.weights, &streamed.weights, 1e-12);
        }
    }
}
