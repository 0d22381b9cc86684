//! Counter-based Gaussian noise for the Brownian dynamics: the same stream on every thread count
//! and on the GPU.
//!
//! A bead's noise at a step is a pure function of `(key, step, bead)`: Threefry-2x32 with 20
//! rounds (Salmon, Moraes, Dror & Shaw 2011, "Parallel random numbers: as easy as 1, 2, 3",
//! SC'11; the Random123 generator, which passes TestU01's BigCrush) turns the counter into random
//! words, and the Box-Muller transform turns them into normals. Nothing is carried from one bead
//! or one step to the next, so beads can be advanced in any order, by any number of threads or
//! GPU invocations, and a seed still fixes the trajectory.
//!
//! Layout (the GPU shader `sim/gpu/shaders/noise.wgsl` implements the same words):
//!
//! - key: `[k0, k1]` from a replica's generator ([`noise_key`]), with `k1 ^= step >> 32`;
//! - counters `[step as u32, 2 · bead]` and `[step as u32, 2 · bead + 1]` give four words
//!   `a, b, c, d`;
//! - uniforms `u = (w >> 8 + ½) / 2²⁴` lie in (0, 1) (never 0: the logarithm is finite);
//! - normals `r₁ cos 2πu_b, r₁ sin 2πu_b, r₂ cos 2πu_d` with `r = √(-2 ln u_a)`, `√(-2 ln u_c)`,
//!   in single precision on the CPU as on the GPU (the transform in double precision cost a fifth
//!   of a CPU step; single precision only trims the tails beyond 5.9 σ, a chance of 4·10⁻⁹ per
//!   draw).

use rand::Rng;

use super::SimRng;

/// Threefry-2x32 rotation constants (Random123).
const ROTATIONS: [u32; 8] = [13, 15, 26, 6, 17, 29, 16, 24];
/// Threefry's key-schedule parity constant.
const PARITY: u32 = 0x1BD1_1BDA;

/// Threefry-2x32 with 20 rounds: the two random words of `counter` under `key`.
#[inline]
pub fn threefry2x32(key: [u32; 2], counter: [u32; 2]) -> [u32; 2] {
    let schedule = [key[0], key[1], PARITY ^ key[0] ^ key[1]];
    let mut x0 = counter[0].wrapping_add(schedule[0]);
    let mut x1 = counter[1].wrapping_add(schedule[1]);
    for round in 0..20 {
        x0 = x0.wrapping_add(x1);
        x1 = x1.rotate_left(ROTATIONS[round % 8]) ^ x0;
        if round % 4 == 3 {
            let s = round / 4 + 1;
            x0 = x0.wrapping_add(schedule[s % 3]);
            x1 = x1
                .wrapping_add(schedule[(s + 1) % 3])
                .wrapping_add(s as u32);
        }
    }
    [x0, x1]
}

/// The noise key of a polymer, drawn from its generator.
pub fn noise_key(rng: &mut SimRng) -> [u32; 2] {
    let word: u64 = rng.gen();
    [word as u32, (word >> 32) as u32]
}

/// The four random words of `bead` at `step`.
#[inline]
pub fn bead_words(key: [u32; 2], step: u64, bead: u32) -> [u32; 4] {
    let key = [key[0], key[1] ^ (step >> 32) as u32];
    let low = step as u32;
    let [a, b] = threefry2x32(key, [low, bead.wrapping_mul(2)]);
    let [c, d] = threefry2x32(key, [low, bead.wrapping_mul(2).wrapping_add(1)]);
    [a, b, c, d]
}

/// A word as a uniform in (0, 1), from its 24 high bits.
#[inline]
fn uniform(word: u32) -> f32 {
    ((word >> 8) as f32 + 0.5) * (1.0 / 16_777_216.0)
}

/// Three independent standard normals from four random words (Box-Muller, single precision).
#[inline]
pub fn normals_from_words([a, b, c, d]: [u32; 4]) -> [f64; 3] {
    let r1 = (-2.0 * uniform(a).ln()).sqrt();
    let r2 = (-2.0 * uniform(c).ln()).sqrt();
    let (sin, cos) = (std::f32::consts::TAU * uniform(b)).sin_cos();
    let cos2 = (std::f32::consts::TAU * uniform(d)).cos();
    [(r1 * cos) as f64, (r1 * sin) as f64, (r2 * cos2) as f64]
}

/// Three independent standard normals for `bead` at `step`.
#[inline]
pub fn bead_normals(key: [u32; 2], step: u64, bead: u32) -> [f64; 3] {
    normals_from_words(bead_words(key, step, bead))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn threefry_matches_random123_known_answers() {
        // Random123's kat_vectors for threefry2x32 with 20 rounds: counter, key, output.
        assert_eq!(threefry2x32([0, 0], [0, 0]), [0x6b20_0159, 0x99ba_4efe]);
        assert_eq!(
            threefry2x32([u32::MAX; 2], [u32::MAX; 2]),
            [0x1cb9_96fc, 0xbb00_2be7]
        );
        assert_eq!(
            threefry2x32([0x1319_8a2e, 0x0370_7344], [0x243f_6a88, 0x85a3_08d3]),
            [0xc492_3a9c, 0x483d_f7a0]
        );
    }

    #[test]
    fn normals_have_unit_moments_and_no_correlation() {
        let key = [7, 11];
        let n = 100_000u32;
        let mut sum = [0.0; 3];
        let mut sum2 = [0.0; 3];
        let mut cross = 0.0;
        let mut lag = 0.0;
        let mut tail = 0usize;
        for bead in 0..n {
            let z = bead_normals(key, 3, bead);
            let next = bead_normals(key, 4, bead);
            for k in 0..3 {
                sum[k] += z[k];
                sum2[k] += z[k] * z[k];
                tail += (z[k].abs() > 3.0) as usize;
            }
            cross += z[0] * z[2];
            lag += z[1] * next[1];
        }
        let n = n as f64;
        for k in 0..3 {
            // Standard errors: 1 / sqrt(n) for the mean, sqrt(2 / n) for the second moment.
            assert!(
                (sum[k] / n).abs() < 5.0 / n.sqrt(),
                "{k}: mean {}",
                sum[k] / n
            );
            assert!(
                (sum2[k] / n - 1.0).abs() < 5.0 * (2.0 / n).sqrt(),
                "{k}: second moment {}",
                sum2[k] / n
            );
        }
        assert!((cross / n).abs() < 5.0 / n.sqrt(), "within a bead {cross}");
        assert!((lag / n).abs() < 5.0 / n.sqrt(), "between steps {lag}");
        // P(|z| > 3) = 0.0026998 over 3 n draws; binomial standard error.
        let p = 0.002_699_8;
        let expected = 3.0 * n * p;
        assert!(
            (tail as f64 - expected).abs() < 5.0 * (expected * (1.0 - p)).sqrt(),
            "{tail} draws beyond 3 sigma, expected {expected}"
        );
    }

    #[test]
    fn the_step_high_word_changes_the_stream() {
        let key = [1, 2];
        assert_ne!(bead_words(key, 5, 0), bead_words(key, 5 + (1 << 32), 0));
        assert_eq!(bead_words(key, 5, 9), bead_words(key, 5, 9));
        assert_ne!(bead_words(key, 5, 9), bead_words(key, 5, 10));
    }
}
