//! MDTraj's distances, operation for operation in single precision: one pair at a time (the
//! all-pairs paths) and over batches of displacements (the cell list's candidates), whose loops
//! the compiler turns into vector instructions. The batches round with [`round_even`] and
//! [`round_away`], which give `f32::round_ties_even` and `f32::round` exactly in operations
//! that vectorise on every x86-64 (`roundps` needs SSE4.1; without it the standard functions
//! are library calls, one per component).

/// The displacement from atom `i` to atom `j`.
#[inline(always)]
pub(super) fn displacement(xyz: &[[f32; 3]], i: u32, j: u32) -> [f32; 3] {
    let (p, q) = (xyz[i as usize], xyz[j as usize]);
    [q[0] - p[0], q[1] - p[1], q[2] - p[2]]
}

/// The squared length of `r`, summed `x, y, z` as MDTraj's SSE dot product sums.
#[inline(always)]
pub(super) fn norm2(r: [f32; 3]) -> f32 {
    r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
}

/// MDTraj's plain squared distance.
#[inline(always)]
pub(super) fn plain(xyz: &[[f32; 3]], i: u32, j: u32) -> f32 {
    norm2(displacement(xyz, i, j))
}

/// MDTraj's minimum image of the displacement `r` in a rectangular box (`_mm_round_ps`: ties
/// to even).
#[inline(always)]
pub(super) fn minimum_image(mut r: [f32; 3], edges: &[f32; 3]) -> [f32; 3] {
    for d in 0..3 {
        r[d] -= (r[d] * (1.0 / edges[d])).round_ties_even() * edges[d];
    }
    r
}

/// [`minimum_image`] rounding by [`round_even`]: the same squared length, in operations that
/// vectorise.
#[inline(always)]
pub(super) fn minimum_image_even(mut r: [f32; 3], edges: &[f32; 3]) -> [f32; 3] {
    for d in 0..3 {
        r[d] -= round_even(r[d] * (1.0 / edges[d])) * edges[d];
    }
    r
}

/// MDTraj's squared minimum-image distance in a rectangular box.
#[inline(always)]
pub(super) fn boxed(xyz: &[[f32; 3]], edges: &[f32; 3], i: u32, j: u32) -> f32 {
    norm2(minimum_image(displacement(xyz, i, j), edges))
}

/// MDTraj's minimum image in a triclinic cell: reduce by the box vectors, then the nearest of
/// 27 images (`round`: ties away from zero, as C's).
pub(super) fn triclinic(
    xyz: &[[f32; 3]],
    v: &[[f32; 3]; 3],
    recip: &[f32; 3],
    i: u32,
    j: u32,
) -> f32 {
    let mut r = displacement(xyz, i, j);
    for k in [2, 1, 0] {
        let n = (r[k] * recip[k]).round();
        for d in 0..3 {
            r[d] -= v[k][d] * n;
        }
    }
    let mut best = f32::MAX;
    for x in [-1.0f32, 0.0, 1.0] {
        let ra = [r[0] + v[0][0] * x, r[1] + v[0][1] * x, r[2] + v[0][2] * x];
        for y in [-1.0f32, 0.0, 1.0] {
            let rb = [
                ra[0] + v[1][0] * y,
                ra[1] + v[1][1] * y,
                ra[2] + v[1][2] * y,
            ];
            for z in [-1.0f32, 0.0, 1.0] {
                let rc = [
                    rb[0] + v[2][0] * z,
                    rb[1] + v[2][1] * z,
                    rb[2] + v[2][2] * z,
                ];
                best = best.min(norm2(rc));
            }
        }
    }
    best
}

/// 2^23: single-precision floats of this magnitude and above are integers.
const INTEGRAL: f32 = 8_388_608.0;

/// `x` rounded to the nearest integer, ties to even: `x.round_ties_even()` (but for the sign of
/// a zero result, which no squared distance sees), by the float addition's own rounding.
#[inline(always)]
pub(super) fn round_even(x: f32) -> f32 {
    // below 2^23 in magnitude, x + 2^23 (signed as x) lies where the floats are the integers,
    // rounded to the nearest, ties to even (2^23 is even); the subtraction is exact
    let shift = INTEGRAL.copysign(x);
    let rounded = (x + shift) - shift;
    if x.abs() < INTEGRAL { rounded } else { x }
}

/// `x` rounded to the nearest integer, ties away from zero: `x.round()` (but for the sign of a
/// zero result).
#[inline(always)]
pub(super) fn round_away(x: f32) -> f32 {
    let even = round_even(x);
    // `x - even` is exact (|x - even| <= 1/2 and a multiple of x's spacing); at a tie, the
    // integer away from zero is x + 1/2 (exact: it is an integer below 2^23 + 1)
    if (x - even).abs() == 0.5 {
        x + 0.5f32.copysign(x)
    } else {
        even
    }
}

/// Displacements, one per component, of the candidate pairs of a batch.
#[derive(Debug, Default)]
pub(super) struct Displacements {
    pub(super) x: Vec<f32>,
    pub(super) y: Vec<f32>,
    pub(super) z: Vec<f32>,
}

impl Displacements {
    /// Adds the displacement from atom `i` to atom `j` ([`displacement`]).
    #[inline(always)]
    pub(super) fn push(&mut self, xyz: &[[f32; 3]], i: u32, j: u32) {
        let r = displacement(xyz, i, j);
        self.x.push(r[0]);
        self.y.push(r[1]);
        self.z.push(r[2]);
    }

    pub(super) fn len(&self) -> usize {
        self.x.len()
    }

    pub(super) fn clear(&mut self) {
        self.x.clear();
        self.y.clear();
        self.z.clear();
    }
}

/// Pairs measured together (two or more vector registers of single-precision lanes).
const LANES: usize = 8;

/// One value per pair of a group of [`LANES`].
type Lanes = [f32; LANES];

/// `f` of each lane (straight-line code the compiler turns into vector instructions).
#[inline(always)]
fn lanes(f: impl Fn(usize) -> f32) -> Lanes {
    std::array::from_fn(f)
}

/// Whether the squared distance `kernel` gives each displacement of `r` (a group of [`LANES`]
/// at a time, the last one padded) is below `below`, into `hit`.
#[inline(always)]
fn batched(
    r: &Displacements,
    below: f32,
    hit: &mut Vec<bool>,
    kernel: impl Fn([Lanes; 3]) -> Lanes,
) {
    let n = r.len();
    hit.clear();
    for start in (0..n).step_by(LANES) {
        let len = LANES.min(n - start);
        let load = |v: &[f32]| {
            let mut lanes = [0.0; LANES];
            lanes[..len].copy_from_slice(&v[start..start + len]);
            lanes
        };
        let d2 = kernel([load(&r.x), load(&r.y), load(&r.z)]);
        hit.extend(d2[..len].iter().map(|&d| d < below));
    }
}

/// The squared lengths of the vectors `r` (MDTraj's sum, [`norm2`]).
#[inline(always)]
fn lanes_norm2(r: &[Lanes; 3]) -> Lanes {
    lanes(|l| r[0][l] * r[0][l] + r[1][l] * r[1][l] + r[2][l] * r[2][l])
}

/// For each displacement, whether its squared distance in a rectangular box ([`boxed`]) is
/// below `below`, into `hit`.
pub(super) fn boxed_below(r: &Displacements, edges: &[f32; 3], below: f32, hit: &mut Vec<bool>) {
    let inverse = edges.map(|e| 1.0 / e);
    batched(r, below, hit, |r| {
        let image: [Lanes; 3] = std::array::from_fn(|d| {
            lanes(|l| r[d][l] - round_even(r[d][l] * inverse[d]) * edges[d])
        });
        lanes_norm2(&image)
    });
}

/// For each displacement, whether its squared distance in a triclinic cell ([`triclinic`]) is
/// below `below`, into `hit`: the same operations, the nearest of the 27 images kept as
/// `_mm_min_ps` keeps it.
pub(super) fn triclinic_below(
    r: &Displacements,
    v: &[[f32; 3]; 3],
    recip: &[f32; 3],
    below: f32,
    hit: &mut Vec<bool>,
) {
    batched(r, below, hit, |mut r| {
        for k in [2, 1, 0] {
            let n = lanes(|l| round_away(r[k][l] * recip[k]));
            for d in 0..3 {
                r[d] = lanes(|l| r[d][l] - v[k][d] * n[l]);
            }
        }
        let mut best = [f32::MAX; LANES];
        for x in [-1.0f32, 0.0, 1.0] {
            let ra: [Lanes; 3] = std::array::from_fn(|d| lanes(|l| r[d][l] + v[0][d] * x));
            for y in [-1.0f32, 0.0, 1.0] {
                let rb: [Lanes; 3] = std::array::from_fn(|d| lanes(|l| ra[d][l] + v[1][d] * y));
                for z in [-1.0f32, 0.0, 1.0] {
                    let rc: [Lanes; 3] = std::array::from_fn(|d| lanes(|l| rb[d][l] + v[2][d] * z));
                    let d2 = lanes_norm2(&rc);
                    best = lanes(|l| if d2[l] < best[l] { d2[l] } else { best[l] });
                }
            }
        }
        best
    });
}

/// The smallest single-precision `x` whose square root is at least `cutoff` (positive).
pub(super) fn sqrt_threshold(cutoff: f32) -> f32 {
    let mut x = cutoff * cutoff;
    while x > 0.0 && x.sqrt() >= cutoff {
        x = f32::from_bits(x.to_bits() - 1);
    }
    while x.sqrt() < cutoff {
        x = f32::from_bits(x.to_bits() + 1);
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_squared_threshold_is_the_square_roots_comparison() {
        for cutoff in [0.45f32, 0.8, 0.1, 1.0, 0.333_333, 12.0] {
            let below = sqrt_threshold(cutoff);
            assert!(below.sqrt() >= cutoff);
            let previous = f32::from_bits(below.to_bits() - 1);
            assert!(previous.sqrt() < cutoff);
            // every float near the square: both tests agree
            let mut x = f32::from_bits((cutoff * cutoff).to_bits() - 50);
            for _ in 0..100 {
                assert_eq!(x < below, x.sqrt() < cutoff, "{x} {cutoff}");
                x = f32::from_bits(x.to_bits() + 1);
            }
        }
    }

    /// `a` and `b` equal, zeros of either sign alike.
    fn same(a: f32, b: f32) -> bool {
        a == b || (a.is_nan() && b.is_nan())
    }

    #[test]
    fn the_vectorised_roundings_are_the_standard_ones() {
        let check = |x: f32| {
            assert!(
                same(round_even(x), x.round_ties_even()),
                "{x:e} ties to even"
            );
            assert!(same(round_away(x), x.round()), "{x:e} away from zero");
        };
        // every float from 1/4 to 4 and from 2^22 to 2^24 (spacings 1/2, 1, 2), either sign,
        // and a sample of all
        let ranges = (0x3e80_0000u32..0x4080_0000).chain(0x4a80_0000..0x4b80_0000);
        for bits in ranges.chain((0..u32::MAX).step_by(4099)) {
            check(f32::from_bits(bits));
            check(-f32::from_bits(bits));
        }
        for x in [
            0.5f32,
            1.5,
            2.5,
            -0.5,
            -2.5,
            0.499_999_97,
            8_388_607.5,
            -8_388_607.5,
            f32::MAX,
            f32::MIN_POSITIVE,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ] {
            check(x);
        }
    }

    #[test]
    fn the_batches_are_the_pairwise_formulas() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(10);
        for _ in 0..200 {
            let edges = [0; 3].map(|_| rng.gen_range(0.5f32..6.0));
            let v = [
                [edges[0], 0.0, 0.0],
                [rng.gen_range(-0.5f32..0.5) * edges[0], edges[1], 0.0],
                [
                    rng.gen_range(-0.5f32..0.5) * edges[0],
                    rng.gen_range(-0.5f32..0.5) * edges[1],
                    edges[2],
                ],
            ];
            let recip = [1.0 / v[0][0], 1.0 / v[1][1], 1.0 / v[2][2]];
            let xyz: Vec<[f32; 3]> = (0..40)
                .map(|_| [0; 3].map(|_| rng.gen_range(-15.0f32..15.0)))
                .collect();
            let below = rng.gen_range(0.01f32..4.0);
            let mut r = Displacements::default();
            let mut pairs = Vec::new();
            for i in 0..40 {
                for j in 0..40 {
                    r.push(&xyz, i, j);
                    pairs.push((i, j));
                }
            }
            let mut hit = Vec::new();
            boxed_below(&r, &edges, below, &mut hit);
            for (&(i, j), &h) in pairs.iter().zip(&hit) {
                assert_eq!(h, boxed(&xyz, &edges, i, j) < below);
            }
            triclinic_below(&r, &v, &recip, below, &mut hit);
            for (&(i, j), &h) in pairs.iter().zip(&hit) {
                assert_eq!(h, triclinic(&xyz, &v, &recip, i, j) < below);
            }
        }
    }
}
