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
//! - beads go in groups of four, `g = bead / 4`; the counters `[step as u32, 6g + k]`,
//!   `k = 0..6`, give six word pairs `(a_k, b_k)`;
//! - uniforms `u = (w >> 8 + ½) / 2²⁴` lie in (0, 1) (never 0: the logarithm is finite);
//! - each pair gives two normals by Box-Muller, `r_k cos 2πu(b_k)` and `r_k sin 2πu(b_k)` with
//!   `r_k = √(-2 ln u(a_k))`: twelve normals per group, of which bead `4g + l` takes the three
//!   `3l, 3l + 1, 3l + 2` (a bead needs two pairs; a group of four needs six, not eight);
//! - the transform is single precision on the CPU as on the GPU (double precision cost a fifth
//!   of a CPU step; single precision only trims the tails beyond 5.9 σ, a chance of 4·10⁻⁹ per
//!   draw).

use rand::Rng;

use crate::random::SeededRng;

/// Threefry-2x32 rotation constants (Random123).
const ROTATIONS: [u32; 8] = [13, 15, 26, 6, 17, 29, 16, 24];
/// Threefry's key-schedule parity constant.
const PARITY: u32 = 0x1BD1_1BDA;

/// Threefry-2x32 with 20 rounds: the two random words of `counter` under `key` (the reference
/// for the lanes version, checked against Random123's known answers).
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
pub fn noise_key(rng: &mut SeededRng) -> [u32; 2] {
    let word: u64 = rng.r#gen();
    [word as u32, (word >> 32) as u32]
}

/// Beads per group sharing the six Box-Muller pairs of their counters.
pub const GROUP: usize = 4;

/// Threefry-2x32-20 on several counters side by side (the same words as [`threefry2x32`]), so
/// the compiler can keep the lanes in vector registers.
#[inline]
fn threefry_lanes<const L: usize>(key: [u32; 2], counters: [[u32; 2]; L]) -> [[u32; 2]; L] {
    let schedule = [key[0], key[1], PARITY ^ key[0] ^ key[1]];
    let mut x0: [u32; L] = std::array::from_fn(|l| counters[l][0].wrapping_add(schedule[0]));
    let mut x1: [u32; L] = std::array::from_fn(|l| counters[l][1].wrapping_add(schedule[1]));
    for round in 0..20 {
        let rotation = ROTATIONS[round % 8];
        for lane in 0..L {
            x0[lane] = x0[lane].wrapping_add(x1[lane]);
            x1[lane] = x1[lane].rotate_left(rotation) ^ x0[lane];
        }
        if round % 4 == 3 {
            let s = round / 4 + 1;
            for lane in 0..L {
                x0[lane] = x0[lane].wrapping_add(schedule[s % 3]);
                x1[lane] = x1[lane]
                    .wrapping_add(schedule[(s + 1) % 3])
                    .wrapping_add(s as u32);
            }
        }
    }
    std::array::from_fn(|lane| [x0[lane], x1[lane]])
}

/// The key of `step` (its high word folded into the key).
#[inline]
fn step_key(key: [u32; 2], step: u64) -> [u32; 2] {
    [key[0], key[1] ^ (step >> 32) as u32]
}

/// The four random words of `bead` at `step`: the two Box-Muller pairs its normals come from.
#[inline]
pub fn bead_words(key: [u32; 2], step: u64, bead: u32) -> [u32; 4] {
    let first = 6 * (bead / 4) + 3 * (bead % 4) / 2;
    let [[a, b], [c, d]] = threefry_lanes(
        step_key(key, step),
        [[step as u32, first], [step as u32, first + 1]],
    );
    [a, b, c, d]
}

/// A word as a uniform in (0, 1), from its 24 high bits.
#[inline]
fn uniform(word: u32) -> f32 {
    ((word >> 8) as f32 + 0.5) * (1.0 / 16_777_216.0)
}

/// The two normals of a Box-Muller pair of words.
#[inline]
fn box_muller([a, b]: [u32; 2]) -> [f32; 2] {
    let r = (-2.0 * uniform(a).ln()).sqrt();
    let (sin, cos) = (std::f32::consts::TAU * uniform(b)).sin_cos();
    [r * cos, r * sin]
}

/// Three independent standard normals for `bead` at `step`.
#[inline]
pub fn bead_normals(key: [u32; 2], step: u64, bead: u32) -> [f64; 3] {
    let [a, b, c, d] = bead_words(key, step, bead);
    let [n0, n1] = box_muller([a, b]);
    let [n2, n3] = box_muller([c, d]);
    // Bead 4g + l starts at normal 3l: the first of its first pair when l is even.
    let normals = if bead.is_multiple_of(2) {
        [n0, n1, n2]
    } else {
        [n1, n2, n3]
    };
    normals.map(f64::from)
}

/// The normals of the four beads `4 group .. 4 group + 4` at `step` ([`bead_normals`] of each,
/// the same bits), from the group's six pairs at once.
#[inline]
pub fn group_normals(key: [u32; 2], step: u64, group: u32) -> [[f64; 3]; GROUP] {
    let pairs = threefry_lanes(
        step_key(key, step),
        std::array::from_fn::<_, 6, _>(|k| [step as u32, 6 * group + k as u32]),
    );
    let normals: [[f32; 2]; 6] = pairs.map(box_muller);
    std::array::from_fn(|lane| {
        std::array::from_fn(|k| {
            let index = 3 * lane + k;
            f64::from(normals[index / 2][index % 2])
        })
    })
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
    fn lanes_and_groups_give_the_scalar_words() {
        let key = [0xdead_beef, 0x0bad_cafe];
        for step in [0u64, 77, (5u64 << 32) + 3] {
            for group in [0u32, 1, 12_345, (u32::MAX / 2) / 4] {
                let normals = group_normals(key, step, group);
                for lane in 0..GROUP as u32 {
                    let bead = 4 * group + lane;
                    let words = bead_words(key, step, bead);
                    let stepped = [key[0], key[1] ^ (step >> 32) as u32];
                    let first = 6 * group + 3 * lane / 2;
                    let [a, b] = threefry2x32(stepped, [step as u32, first]);
                    let [c, d] = threefry2x32(stepped, [step as u32, first + 1]);
                    assert_eq!(words, [a, b, c, d]);
                    let scalar = bead_normals(key, step, bead);
                    assert_eq!(
                        scalar.map(f64::to_bits),
                        normals[lane as usize].map(f64::to_bits)
                    );
                }
            }
        }
    }

    #[test]
    fn the_step_high_word_changes_the_stream() {
        let key = [1, 2];
        assert_ne!(bead_words(key, 5, 0), bead_words(key, 5 + (1 << 32), 0));
        assert_eq!(bead_words(key, 5, 9), bead_words(key, 5, 9));
        assert_ne!(bead_words(key, 5, 9), bead_words(key, 5, 10));
    }
}
