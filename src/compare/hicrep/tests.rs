//! The streamed SCC against a direct computation of hicrep's definition (window sums pixel by
//! pixel, Pearson's correlation from the centred values), and its invariants.

#![allow(clippy::needless_range_loop)] // the direct sums index as the definition does

use super::*;
use crate::genome::Chrom;
use crate::io::InMemory;
use crate::matrix::{CountType, MatrixBuilder};
use rand::{Rng, SeedableRng};

/// A map of chromosomes of `sizes` bins (100 bp), pixels within `band` of the diagonal drawn at
/// random (about half of them present), counts decaying with distance; `float` counts get a
/// fractional part.
fn random_map(sizes: &[usize], band: usize, seed: u64, float: bool) -> InMemory {
    let chroms: Vec<Chrom> = sizes
        .iter()
        .enumerate()
        .map(|(k, &n)| Chrom::new(format!("c{k}"), n as u64 * 100))
        .collect();
    let bins = BinTable::fixed(chroms, 100).unwrap();
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
    let kind = if float {
        CountType::Float
    } else {
        CountType::Integer
    };
    let mut builder = MatrixBuilder::new(bins.clone(), kind);
    for c in 0..bins.n_chroms() {
        let range = bins.chrom_bins(c);
        for i in range.clone() {
            for j in i..(i + band).min(range.end) {
                if rng.r#gen::<f64>() < 0.5 {
                    let mean = 40.0 / (1.0 + (j - i) as f64);
                    let mut count = (rng.r#gen::<f64>() * 2.0 * mean).floor() + 1.0;
                    if float {
                        count += rng.r#gen::<f64>();
                    }
                    builder.push(i as u64, j as u64, count).unwrap();
                }
            }
        }
    }
    InMemory::new(format!("random {seed}"), builder.build())
}

/// hicrep's SCC of a chromosome of `n` bins computed directly from its pixels `at_a(r, c)`,
/// `at_b(r, c)` (upper triangle, diagonals `1..n_diags`): smoothed values by window sums, then per
/// diagonal the Pearson correlation of the centred values over pixels where either is not 0.
fn direct(
    n: usize,
    n_diags: usize,
    h: usize,
    at_a: &dyn Fn(usize, usize) -> f64,
    at_b: &dyn Fn(usize, usize) -> f64,
) -> f64 {
    let smooth = |at: &dyn Fn(usize, usize) -> f64, i: usize, j: usize| {
        let mut s = 0.0;
        for r in i.saturating_sub(h)..(i + h + 1).min(n) {
            for c in j.saturating_sub(h)..(j + h + 1).min(n) {
                s += at(r, c);
            }
        }
        let dim = |k: usize| (h + 1 + k.min(n - 1 - k).min(h)) as f64;
        s / (dim(i) * dim(j))
    };
    let (mut num, mut den) = (0.0, 0.0);
    for d in 1..n_diags {
        let pairs: Vec<(f64, f64)> = (0..n - d)
            .map(|i| (smooth(at_a, i, i + d), smooth(at_b, i, i + d)))
            .filter(|&(x, y)| x != 0.0 || y != 0.0)
            .collect();
        let m = pairs.len() as f64;
        if pairs.len() < 2 {
            continue;
        }
        let (mx, my) = (
            pairs.iter().map(|p| p.0).sum::<f64>() / m,
            pairs.iter().map(|p| p.1).sum::<f64>() / m,
        );
        let cov: f64 = pairs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let vx: f64 = pairs.iter().map(|p| (p.0 - mx).powi(2)).sum();
        let vy: f64 = pairs.iter().map(|p| (p.1 - my).powi(2)).sum();
        let rho = cov / (vx * vy).sqrt();
        let rho = if rho.is_finite() { rho } else { 0.0 };
        let w = m * (1.0 + 1.0 / m) / 12.0;
        num += rho * w;
        den += w;
    }
    num / den
}

/// A chromosome's band of `reader`: `band[i][d]` the count at `(i, i + d)`, `d < n_diags`.
fn band_of(reader: &dyn MatrixReader, chrom: usize, n_diags: usize) -> Vec<Vec<f64>> {
    let range = reader.bins().chrom_bins(chrom);
    let mut band = vec![vec![0.0f64; n_diags]; range.len()];
    reader
        .read_pixels(range.clone(), range.clone(), &mut |block| {
            for k in 0..block.len() {
                let i = block.bin1[k] as usize - range.start;
                let j = block.bin2[k] as usize - range.start;
                if j > i && j - i < n_diags {
                    band[i][j - i] = block.count[k];
                }
            }
            Ok(())
        })
        .unwrap();
    band
}

/// [`direct`] on chromosome `chrom` of two maps.
fn direct_scc(
    a: &dyn MatrixReader,
    b: &dyn MatrixReader,
    chrom: usize,
    h: usize,
    n_diags: usize,
) -> f64 {
    let n = a.bins().chrom_bins(chrom).len();
    let n_diags = n_diags.min(n);
    let (ba, bb) = (band_of(a, chrom, n_diags), band_of(b, chrom, n_diags));
    let at = |band: &Vec<Vec<f64>>, r: usize, c: usize| {
        if c > r && c - r < n_diags {
            band[r][c - r]
        } else {
            0.0
        }
    };
    direct(n, n_diags, h, &|r, c| at(&ba, r, c), &|r, c| at(&bb, r, c))
}

#[test]
fn streamed_scc_is_hicreps_definition() {
    for (seed, float) in [(1, false), (2, true)] {
        let a = random_map(&[90, 37, 5], 30, seed, float);
        let b = random_map(&[90, 37, 5], 30, seed + 100, float);
        for h in [0, 1, 3] {
            for max_distance in [Some(1_000), Some(2_500), None] {
                let params = SccParams {
                    h,
                    max_distance_bp: max_distance,
                    ..SccParams::default()
                };
                let got = scc(&a, &b, &[0, 1, 2], &params).unwrap();
                let n_diags = max_diagonals(a.bins(), max_distance).unwrap();
                for (c, result) in got.chroms.iter().enumerate() {
                    let want = direct_scc(&a, &b, c, h, n_diags);
                    assert!(
                        (result.scc - want).abs() < 1e-11,
                        "chrom {c} h {h} max {max_distance:?} float {float}: {} vs {want}",
                        result.scc
                    );
                }
                let lengths = [9000.0, 3700.0, 500.0];
                let want: f64 = got
                    .chroms
                    .iter()
                    .zip(lengths)
                    .map(|(c, l)| c.scc * l)
                    .sum::<f64>()
                    / lengths.iter().sum::<f64>();
                assert!((got.genome_wide - want).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn long_chromosomes_are_read_in_segments_with_the_same_result() {
    // 9,000 bins: three segments and many pieces; against the direct computation.
    let a = random_map(&[SEGMENT_ROWS * 2 + 808], 6, 5, false);
    let b = random_map(&[SEGMENT_ROWS * 2 + 808], 6, 6, false);
    for h in [0, 2] {
        let params = SccParams {
            h,
            max_distance_bp: Some(500),
            ..SccParams::default()
        };
        let got = scc(&a, &b, &[0], &params).unwrap().chroms[0].scc;
        let want = direct_scc(&a, &b, 0, h, 6);
        assert!((got - want).abs() < 1e-11, "h {h}: {got} vs {want}");
        let one_thread = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| scc(&a, &b, &[0], &params).unwrap().chroms[0].scc);
        assert_eq!(got.to_bits(), one_thread.to_bits());
    }
}

#[test]
fn pieces_smooth_only_as_far_as_their_pixels_reach() {
    // Pixels within 6 diagonals, but rows 300..340 (inside the second piece) reach 35: the
    // pieces stop at different diagonals, and the sums still equal the direct computation.
    let n = 3 * PIECE_ROWS + 17;
    let map = |seed: u64, float: bool| {
        let bins = BinTable::fixed(vec![Chrom::new("c0", n as u64 * 100)], 100).unwrap();
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let kind = if float {
            CountType::Float
        } else {
            CountType::Integer
        };
        let mut builder = MatrixBuilder::new(bins, kind);
        for i in 0..n {
            let reach = if (300..340).contains(&i) { 36 } else { 7 };
            for j in i..(i + reach).min(n) {
                if rng.r#gen::<f64>() < 0.5 {
                    let fraction = if float { rng.r#gen::<f64>() } else { 0.0 };
                    builder
                        .push(
                            i as u64,
                            j as u64,
                            (rng.r#gen::<f64>() * 9.0).floor() + 1.0 + fraction,
                        )
                        .unwrap();
                }
            }
        }
        InMemory::new(format!("reach {seed}"), builder.build())
    };
    for float in [false, true] {
        let (a, b) = (map(7, float), map(8, float));
        for h in [1, 3] {
            let params = SccParams {
                h,
                max_distance_bp: Some(5_000),
                ..SccParams::default()
            };
            let got = scc(&a, &b, &[0], &params).unwrap().chroms[0].scc;
            let want = direct_scc(&a, &b, 0, h, 51);
            assert!(
                (got - want).abs() < 1e-11,
                "h {h} float {float}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn a_map_against_itself_or_a_scaled_copy_scores_one() {
    let a = random_map(&[60, 40], 20, 3, false);
    let params = SccParams {
        h: 2,
        max_distance_bp: Some(1_500),
        ..SccParams::default()
    };
    let same = scc(&a, &a, &[0, 1], &params).unwrap();
    for c in &same.chroms {
        assert!((c.scc - 1.0).abs() < 1e-12, "{c:?}");
    }
}

#[test]
fn downsampling_resamples_the_deeper_map_reproducibly() {
    let a = random_map(&[80], 20, 7, false);
    let b = random_map(&[80], 20, 8, false);
    let params = SccParams {
        h: 1,
        max_distance_bp: Some(1_500),
        downsample: true,
        seed: 3,
    };
    let first = scc(&a, &b, &[0], &params).unwrap();
    let again = scc(&a, &b, &[0], &params).unwrap();
    assert_eq!(first, again);
    let other = scc(
        &a,
        &b,
        &[0],
        &SccParams {
            seed: 4,
            ..params.clone()
        },
    )
    .unwrap();
    assert_ne!(first.chroms[0].scc, other.chroms[0].scc);
    // A map downsampled against itself: resampling only happens where depths differ.
    let same = scc(&a, &a, &[0], &params).unwrap();
    assert!((same.chroms[0].scc - 1.0).abs() < 1e-12);
}

#[test]
fn empty_chromosomes_and_bad_distances_are_reported() {
    let a = random_map(&[50, 30], 10, 1, false);
    // b: the same bins, nothing on the second chromosome.
    let bins = a.bins().clone();
    let mut builder = MatrixBuilder::new(bins, CountType::Integer);
    builder.push(0, 3, 5.0).unwrap();
    builder.push(1, 2, 5.0).unwrap();
    let b = InMemory::new("b".into(), builder.build());
    let got = scc(&a, &b, &[1], &SccParams::default()).unwrap();
    assert!(got.chroms[0].scc.is_nan());
    assert!(
        got.chroms[0]
            .note
            .as_deref()
            .unwrap()
            .contains("no contacts"),
        "{:?}",
        got.chroms[0]
    );
    assert!(got.genome_wide.is_nan());
    let params = SccParams {
        max_distance_bp: Some(50),
        ..SccParams::default()
    };
    let message = scc(&a, &b, &[0], &params).unwrap_err().to_string();
    assert!(message.contains("max-distance 50"), "{message}");
    let other = random_map(&[50, 31], 10, 1, false);
    let message = scc(&a, &other, &[0], &SccParams::default())
        .unwrap_err()
        .to_string();
    assert!(message.contains("bins differ"), "{message}");
}

#[test]
fn training_stops_where_smoothing_stops_helping() {
    let a = random_map(&[200, 150], 40, 11, false);
    let b = random_map(&[200, 150], 40, 12, false);
    let trained = train_h(&a, &b, &[0, 1], Some(3_000), 6, 1).unwrap();
    // The chosen h is the one before the first gain under 0.01 (hicreppy's rule).
    let scores: Vec<f64> = trained.tried.iter().map(|t| t.1).collect();
    let stop = scores
        .windows(2)
        .position(|w| w[1] - w[0] < 0.01)
        .map(|k| k + 1);
    let want = stop.unwrap_or(5).saturating_sub(1);
    assert_eq!(trained.h, want, "{:?}", trained.tried);
    assert_eq!(
        train_h(&a, &b, &[0, 1], Some(3_000), 6, 1).unwrap(),
        trained
    );
}

#[test]
fn hicreppy_scc_of_whole_chromosomes_equals_hicreppy() {
    // data/reference/compare/hicreppy.tsv.gz: hicreppy 0.1.0's get_scc of the yeast map and a
    // copy thinned to 30% (seed 30), as scripts/compare_references.py made it.
    use crate::compare::sample::{SampleParams, Sampled, Target};
    use crate::io::{OpenOptions, open_matrix};
    use std::io::Read;
    let yeast = open_matrix("data/yeast.10kb.cool", &OpenOptions::default()).unwrap();
    let params = SampleParams {
        target: Target::Fraction(0.3),
        exact: false,
        seed: 30,
    };
    let thin = Sampled::new(yeast.as_ref(), params).unwrap();
    let mut text = String::new();
    flate2::read::GzDecoder::new(
        std::fs::File::open("data/reference/compare/hicreppy.tsv.gz").unwrap(),
    )
    .read_to_string(&mut text)
    .unwrap();
    let mut compared = 0;
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split('\t').collect();
        let (max_distance, h): (u64, usize) = (f[0].parse().unwrap(), f[1].parse().unwrap());
        let chrom = yeast.bins().chrom_id(f[2]).unwrap();
        let want: f64 = f[3].parse().unwrap();
        let got = hicreppy_chrom_scc(yeast.as_ref(), &thin, chrom, max_distance, h).unwrap();
        assert!(
            (got - want).abs() < 1e-9,
            "{} h {h} max {max_distance}: {got} vs hicreppy {want}",
            f[2]
        );
        compared += 1;
    }
    assert_eq!(compared, 84);
}
