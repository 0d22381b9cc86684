//! Seeded random streams and exact draws, shared by the simulators (`sim`) and the samplers of
//! `compare` (downsampling, HiCRep's training): a ground-floor tool, so that no room imports
//! another only to borrow it.
//!
//! Reproducibility: every random process takes an explicit seed; independent streams (per
//! chromosome row, per purpose) are seeded from it by [`stream_seed`], so results never depend
//! on the number of threads. The generator is xoshiro256++ (`rand_xoshiro`).
//!
//! Poisson sampling ([`poisson`]) is exact: Knuth's multiplication method for means below 10 and
//! Hörmann's PTRS transformed rejection with squeeze (W. Hörmann 1993, "The transformed rejection
//! method for generating Poisson random variables", Insurance: Mathematics and Economics 12:39-45)
//! for larger means, the same split numpy uses. Both are exact (no normal approximation), cost
//! O(mean) and O(1) expected uniforms respectively, and need nothing beyond uniforms and
//! `ln_gamma`, so no distribution crate is needed.

use rand::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

/// The random generator of every seeded stream (the simulators, downsampling, HiCRep's training).
pub type SeededRng = Xoshiro256PlusPlus;

/// SplitMix64 finaliser: a bijective mix of 64 bits.
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The seed of the independent stream `(tag, index)` derived from the user's `seed`.
///
/// Streams with different tags or indices are decorrelated by SplitMix64 mixing; the mapping is
/// fixed, so a given `(seed, tag, index)` always gives the same stream.
pub fn stream_seed(seed: u64, tag: u64, index: u64) -> u64 {
    splitmix64(splitmix64(splitmix64(seed) ^ tag) ^ index)
}

/// A generator for the stream `(tag, index)` of `seed` (see [`stream_seed`]).
pub fn stream_rng(seed: u64, tag: u64, index: u64) -> SeededRng {
    SeededRng::seed_from_u64(stream_seed(seed, tag, index))
}

/// Means at or above this use PTRS; below, Knuth's method.
const PTRS_MIN_MEAN: f64 = 10.0;

/// One Poisson(`mean`) draw (0 for a mean of 0 or less, or NaN).
///
/// Exact for every mean: Knuth's method below 10, PTRS (Hörmann 1993) above; see the module docs.
pub fn poisson<R: Rng + ?Sized>(rng: &mut R, mean: f64) -> u64 {
    if mean.is_nan() || mean <= 0.0 {
        0
    } else if mean < PTRS_MIN_MEAN {
        poisson_knuth(rng, mean)
    } else {
        poisson_ptrs(rng, mean)
    }
}

/// Knuth: count uniforms multiplied until the product drops to `exp(-mean)`.
fn poisson_knuth<R: Rng + ?Sized>(rng: &mut R, mean: f64) -> u64 {
    let limit = (-mean).exp();
    let mut product: f64 = rng.r#gen();
    let mut k = 0;
    while product > limit {
        k += 1;
        product *= rng.r#gen::<f64>();
    }
    k
}

/// PTRS, transformed rejection with squeeze (Hörmann 1993, algorithm PTRS), for `mean >= 10`.
fn poisson_ptrs<R: Rng + ?Sized>(rng: &mut R, mean: f64) -> u64 {
    let sqrt_mean = mean.sqrt();
    let log_mean = mean.ln();
    let b = 0.931 + 2.53 * sqrt_mean;
    let a = -0.059 + 0.02483 * b;
    let inv_alpha = 1.1239 + 1.1328 / (b - 3.4);
    let v_r = 0.9277 - 3.6224 / (b - 2.0);
    loop {
        let u = rng.r#gen::<f64>() - 0.5;
        let v: f64 = rng.r#gen();
        let us = 0.5 - u.abs();
        let k = ((2.0 * a / us + b) * u + mean + 0.43).floor();
        if us >= 0.07 && v <= v_r {
            return k as u64;
        }
        if k < 0.0 || (us < 0.013 && v > us) {
            continue;
        }
        let log_accept = v.ln() + inv_alpha.ln() - (a / (us * us) + b).ln();
        if log_accept <= -mean + k * log_mean - statrs::function::gamma::ln_gamma(k + 1.0) {
            return k as u64;
        }
    }
}

/// One standard normal draw (Box-Muller, one of the pair).
pub fn standard_normal<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    // 1 - U is in (0, 1], so the logarithm is finite.
    let radius = (-2.0 * (1.0 - rng.r#gen::<f64>()).ln()).sqrt();
    radius * (std::f64::consts::TAU * rng.r#gen::<f64>()).cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn moments(mean: f64, n: usize, seed: u64) -> (f64, f64) {
        let mut rng = stream_rng(seed, 0, 0);
        let draws: Vec<f64> = (0..n).map(|_| poisson(&mut rng, mean) as f64).collect();
        let m = draws.iter().sum::<f64>() / n as f64;
        let v = draws.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1) as f64;
        (m, v)
    }

    #[test]
    fn poisson_mean_and_variance_match_for_both_methods() {
        let n = 200_000;
        for (i, &mean) in [0.05, 0.5, 3.0, 9.99, 10.0, 37.5, 1000.0, 1e6]
            .iter()
            .enumerate()
        {
            let (m, v) = moments(mean, n, 42 + i as u64);
            // Standard error of the mean: sqrt(mean / n); allow 5 of them.
            let se = (mean / n as f64).sqrt();
            assert!((m - mean).abs() < 5.0 * se, "mean {mean}: sample mean {m}");
            // Standard error of the variance: about mean * sqrt(2 / n) (+ mean / n); allow 5.
            let se_var = mean * (2.0 / n as f64).sqrt() + (mean / n as f64);
            assert!(
                (v - mean).abs() < 5.0 * se_var,
                "mean {mean}: sample variance {v}"
            );
        }
    }

    #[test]
    fn poisson_probabilities_match_the_pmf() {
        // PTRS at a moderate mean: P(k) for k near the mode, against the exact pmf.
        let mean = 12.0;
        let n = 400_000;
        let mut rng = stream_rng(7, 1, 0);
        let mut histogram = [0usize; 40];
        for _ in 0..n {
            let k = poisson(&mut rng, mean) as usize;
            if k < histogram.len() {
                histogram[k] += 1;
            }
        }
        for (k, &count) in histogram.iter().enumerate().take(25).skip(4) {
            let p = (-mean + k as f64 * mean.ln()
                - statrs::function::gamma::ln_gamma(k as f64 + 1.0))
            .exp();
            let observed = count as f64 / n as f64;
            let se = (p * (1.0 - p) / n as f64).sqrt();
            assert!((observed - p).abs() < 5.0 * se, "k={k}: {observed} vs {p}");
        }
        assert_eq!(poisson(&mut rng, 0.0), 0);
        assert_eq!(poisson(&mut rng, -1.0), 0);
        assert_eq!(poisson(&mut rng, f64::NAN), 0);
    }

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let draw = |tag, index| stream_rng(3, tag, index).r#gen::<u64>();
        assert_eq!(draw(1, 2), draw(1, 2));
        assert_ne!(draw(1, 2), draw(1, 3));
        assert_ne!(draw(1, 2), draw(2, 2));
        let mut rng = stream_rng(5, 0, 0);
        let n = 100_000;
        let z: Vec<f64> = (0..n).map(|_| standard_normal(&mut rng)).collect();
        let m = z.iter().sum::<f64>() / n as f64;
        let v = z.iter().map(|x| (x - m).powi(2)).sum::<f64>() / n as f64;
        assert!(m.abs() < 0.02 && (v - 1.0).abs() < 0.02, "{m} {v}");
    }
}
