use proptest::prelude::*;

use super::compute::*;
use super::*;
use crate::genome::View;
use crate::genome::{BinTable, Chrom, RegionSpec};
use crate::matrix::{ContactMatrix, CountType, MatrixBuilder, Pixels};

/// A random matrix, weights with masked bins, and a random view (possibly with regions
/// that meet inside a bin).
fn cases() -> impl Strategy<Value = (ContactMatrix, Vec<f64>, Vec<RegionSpec>)> {
    (
        prop::collection::vec(1u64..300, 1..4),
        5u64..40,
        any::<u64>(),
    )
        .prop_flat_map(|(lengths, resolution, seed)| {
            let chroms: Vec<Chrom> = lengths
                .iter()
                .enumerate()
                .map(|(i, &l)| Chrom::new(format!("c{i}"), l))
                .collect();
            let bins = BinTable::fixed(chroms, resolution).unwrap();
            let n = bins.n_bins() as u64;
            let triplets = prop::collection::vec((0..n, 0..n, 1u32..50), 0..300);
            let cuts =
                prop::collection::vec(prop::collection::vec(0.0f64..1.0, 0..4), lengths.len());
            (Just(bins), Just(seed), triplets, cuts)
        })
        .prop_map(|(bins, seed, triplets, cuts)| {
            let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
            for (i, j, c) in triplets {
                builder.push(i, j, c as f64).unwrap();
            }
            let weights: Vec<f64> = (0..bins.n_bins())
                .map(|k| {
                    if (seed >> (k % 61)) & 3 == 0 {
                        f64::NAN
                    } else {
                        0.25 + k as f64 / 7.0
                    }
                })
                .collect();
            let mut specs = Vec::new();
            for (chrom, fractions) in bins.chroms().iter().zip(cuts) {
                let mut points: Vec<u64> = fractions
                    .iter()
                    .map(|f| (f * chrom.length_bp as f64) as u64)
                    .chain([0, chrom.length_bp])
                    .collect();
                points.sort_unstable();
                points.dedup();
                for (k, pair) in points.windows(2).enumerate() {
                    // Leave some stretches out of the view.
                    if (seed >> (k + 3)) & 7 != 0 {
                        specs.push(RegionSpec {
                            chrom: chrom.name.clone(),
                            start_bp: pair[0],
                            end_bp: pair[1],
                            name: None,
                        });
                    }
                }
            }
            if specs.is_empty() {
                specs.push(RegionSpec {
                    chrom: bins.chroms()[0].name.clone(),
                    start_bp: 0,
                    end_bp: bins.chroms()[0].length_bp,
                    name: None,
                });
            }
            (builder.build(), weights, specs)
        })
}

fn pixels_of(matrix: &ContactMatrix) -> Pixels {
    let mut pixels =
        Pixels::with_capacity(matrix.bins().clone(), CountType::Integer, matrix.nnz()).unwrap();
    pixels.extend(&matrix.all_pixels()).unwrap();
    pixels
}

fn close(a: f64, b: f64) -> bool {
    (a.is_nan() && b.is_nan()) || (a - b).abs() <= 1e-12 * b.abs().max(1.0)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Per-diagonal and per-block sums equal a naive loop over the dense matrix.
    #[test]
    fn sums_equal_a_dense_computation((matrix, weights, specs) in cases(), balanced in any::<bool>()) {
        let bins = matrix.bins();
        let view = View::new(bins, &specs).unwrap();
        let pixels = pixels_of(&matrix);
        let w = balanced.then_some(weights.as_slice());
        let params = CisParams::default();
        let table = expected_cis(&pixels, w, &view, &params).unwrap();
        let owner = view.bin_regions(bins.n_bins());
        let good = |i: usize| w.is_none_or(|w| !w[i].is_nan());
        let mut row = 0;
        for (r, region) in view.regions().iter().enumerate() {
            let lo = region.bins.start;
            let n = region.n_bins();
            for d in 0..n {
                let (mut count, mut balanced_sum) = (0.0, 0.0);
                for i in 0..n - d {
                    let (a, b) = (lo + i, lo + i + d);
                    if owner[a] == Some(r) && owner[b] == Some(r) && good(a) && good(b) {
                        let c = matrix.get(a, b);
                        count += c;
                        if let Some(w) = w {
                            balanced_sum += c * w[a] * w[b];
                        }
                    }
                }
                let n_valid = (0..n - d).filter(|&i| good(lo + i) && good(lo + i + d)).count();
                prop_assert_eq!(table.region_name(row), region.name.as_str());
                prop_assert_eq!(table.dist[row], d as u64);
                prop_assert_eq!(table.n_total[row], (n - d) as u64);
                prop_assert_eq!(table.n_valid[row], n_valid as u64);
                if d < params.ignore_diags {
                    prop_assert!(table.count_sum[row].is_nan());
                } else {
                    prop_assert_eq!(table.count_sum[row], count);
                    prop_assert!(close(table.count_avg[row], count / (n - d) as f64));
                    if let Some(sums) = &table.balanced_sum {
                        prop_assert!(close(sums[row], balanced_sum), "{} vs {}", sums[row], balanced_sum);
                    }
                }
                row += 1;
            }
        }
        prop_assert_eq!(row, table.n_rows());

        let trans = expected_trans(&pixels, w, &view).unwrap();
        let regions = view.regions();
        let mut row = 0;
        for r1 in 0..regions.len() {
            for r2 in r1 + 1..regions.len() {
                if regions[r1].chrom_id == regions[r2].chrom_id {
                    continue;
                }
                let (mut count, mut balanced_sum) = (0.0, 0.0);
                for a in regions[r1].bins.clone() {
                    for b in regions[r2].bins.clone() {
                        if owner[a] == Some(r1) && owner[b] == Some(r2) && good(a) && good(b) {
                            let c = matrix.get(a, b);
                            count += c;
                            if let Some(w) = w {
                                balanced_sum += c * w[a] * w[b];
                            }
                        }
                    }
                }
                let n_good = |r: usize| regions[r].bins.clone().filter(|&b| good(b)).count() as u64;
                prop_assert_eq!(&trans.region1[row], &regions[r1].name);
                prop_assert_eq!(&trans.region2[row], &regions[r2].name);
                prop_assert_eq!(trans.n_valid[row], n_good(r1) * n_good(r2));
                prop_assert_eq!(trans.count_sum[row], count);
                if let Some(sums) = &trans.balanced_sum {
                    prop_assert!(close(sums[row], balanced_sum));
                }
                row += 1;
            }
        }
        prop_assert_eq!(row, trans.n_rows());
    }
}

#[test]
fn streamed_and_in_memory_passes_agree() {
    let bins = BinTable::fixed(vec![Chrom::new("a", 30_000), Chrom::new("b", 20_000)], 10).unwrap();
    let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
    for i in 0..bins.n_bins() as u64 {
        for j in (i..(i + 120).min(bins.n_bins() as u64)).step_by(2) {
            builder.push(i, j, ((i * 7 + j) % 13) as f64).unwrap();
        }
    }
    let reader = crate::io::InMemory::new("test".into(), builder.build());
    let memory = crate::io::load_pixels(&reader, u64::MAX).unwrap();
    let streamed = crate::io::load_pixels(&reader, 0).unwrap();
    assert!(matches!(streamed, crate::io::LoadedPixels::Streamed(_)));
    let weights: Vec<f64> = (0..bins.n_bins())
        .map(|k| {
            if k % 17 == 3 {
                f64::NAN
            } else {
                1.0 / (1.0 + (k % 11) as f64)
            }
        })
        .collect();
    let view = View::chromosomes(&bins);
    let params = CisParams::default();
    let a = expected_cis(&memory, Some(&weights), &view, &params).unwrap();
    let b = expected_cis(&streamed, Some(&weights), &view, &params).unwrap();
    // Integer counts add up exactly; balanced sums may differ by rounding only.
    assert_eq!(
        a.count_sum.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        b.count_sum.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
    for (x, y) in a.balanced_sum.unwrap().iter().zip(b.balanced_sum.unwrap()) {
        assert!(close(*x, y), "{x} vs {y}");
    }
    let t1 = expected_trans(&memory, None, &view).unwrap();
    let t2 = expected_trans(&streamed, None, &view).unwrap();
    assert_eq!(t1, t2);
}

#[test]
fn curves_for_observed_over_expected() {
    let bins = BinTable::fixed(vec![Chrom::new("a", 50), Chrom::new("b", 30)], 10).unwrap();
    let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
    for i in 0..5u64 {
        for j in i..5 {
            builder.push(i, j, (1 + j - i) as f64).unwrap();
        }
    }
    let pixels = pixels_of(&builder.build());
    let curves = cis_curves(&pixels, None, 2).unwrap();
    assert_eq!(curves.len(), 2);
    assert_eq!(curves[0].bins, 0..5);
    assert_eq!(curves[1].bins, 5..8);
    assert!(curves[0].expected[1].is_nan());
    // Diagonal 2 of chromosome a: three pixels of count 3.
    assert_eq!(curves[0].expected[2], 3.0);
    assert_eq!(curves[0].n_valid[2], 3.0);
    assert_eq!(curves[1].expected[2], 0.0);
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let bins = BinTable::fixed(vec![Chrom::new("a", 40_000), Chrom::new("b", 30_000)], 10).unwrap();
    let mut builder = MatrixBuilder::new(bins.clone(), CountType::Float);
    let mut state = 3u64;
    for i in 0..bins.n_bins() as u64 {
        for j in i..(i + 60).min(bins.n_bins() as u64) {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            builder.push(i, j, (state >> 40) as f64 / 977.0).unwrap();
        }
    }
    let pixels = pixels_of(&builder.build());
    assert!(pixels.len() > 4 * crate::matrix::pixels::SLICE_PIXELS);
    let weights: Vec<f64> = (0..bins.n_bins())
        .map(|k| 1.0 / (1.0 + (k % 13) as f64))
        .collect();
    let view = View::chromosomes(&bins);
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                expected_cis(&pixels, Some(&weights), &view, &CisParams::default()).unwrap()
            })
    };
    let one = run(1);
    let three = run(3);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(
        bits(one.balanced_sum.as_ref().unwrap()),
        bits(three.balanced_sum.as_ref().unwrap())
    );
    assert_eq!(
        bits(one.avg_smoothed_agg.as_ref().unwrap()),
        bits(three.avg_smoothed_agg.as_ref().unwrap())
    );
}

fn naive_valid(good: &[bool]) -> Vec<u64> {
    let n = good.len();
    (0..n)
        .map(|d| (0..n - d).filter(|&i| good[i] && good[i + d]).count() as u64)
        .collect()
}

#[test]
fn valid_pairs_match_the_naive_count() {
    let mut state = 7u64;
    for n in [1usize, 2, 5, 63, 64, 65, 130, 500] {
        for density in [0.0, 0.02, 0.3, 0.5, 0.8, 0.99, 1.0] {
            let good: Vec<bool> = (0..n)
                .map(|_| {
                    state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
                    ((state >> 11) as f64 / (1u64 << 53) as f64) < density
                })
                .collect();
            assert_eq!(
                valid_pairs_per_diagonal(&good),
                naive_valid(&good),
                "n {n} density {density}"
            );
            assert_eq!(
                bitset_autocorrelation(&good),
                naive_valid(&good),
                "bitset n {n} density {density}"
            );
        }
    }
}
