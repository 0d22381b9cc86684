use std::io::Read as _;

use super::tables::{dots_tsv, enriched_tsv};
use super::*;
use crate::expected::{CisParams, expected_cis};
use crate::io::{OpenOptions, load_pixels, open_matrix};

fn gz_text(path: &str) -> String {
    let mut text = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(path).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    text
}

/// scikit-learn 1.9 `Birch(threshold, n_clusters=None)` on the cases of
/// `data/reference/dots/birch_cases.txt.gz` (scripts/birch_reference.py): the same labels and
/// the same centres, bit for bit.
#[test]
fn birch_is_scikit_learn() {
    let text = gz_text("data/reference/dots/birch_cases.txt.gz");
    // (threshold, points, labels, centres)
    type Case = (f64, Vec<[f64; 2]>, Vec<usize>, Vec<[f64; 2]>);
    let mut cases: Vec<Case> = Vec::new();
    for line in text.lines() {
        let f: Vec<&str> = line.split(' ').collect();
        match f[0] {
            "case" => cases.push((f[2].parse().unwrap(), Vec::new(), Vec::new(), Vec::new())),
            "p" => {
                let case = cases.last_mut().unwrap();
                case.1.push([f[1].parse().unwrap(), f[2].parse().unwrap()]);
                case.2.push(f[3].parse().unwrap());
            }
            "c" => {
                let case = cases.last_mut().unwrap();
                case.3.push([f[1].parse().unwrap(), f[2].parse().unwrap()]);
            }
            other => panic!("{other}"),
        }
    }
    assert_eq!(cases.len(), 12);
    let mut splits = 0;
    for (k, (threshold, points, labels, centres)) in cases.iter().enumerate() {
        let fit = birch::birch(points, *threshold);
        assert_eq!(&fit.centres, centres, "case {k}");
        assert_eq!(&fit.labels, labels, "case {k}");
        splits += (centres.len() > 50) as usize;
    }
    assert!(splits >= 2, "the cases reach node splits");
}

/// Parse a cooltools dots table: header and rows of fields.
fn table(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut lines = text.lines();
    let head = lines
        .next()
        .unwrap()
        .split('\t')
        .map(String::from)
        .collect();
    let rows = lines
        .map(|l| l.split('\t').map(String::from).collect())
        .collect();
    (head, rows)
}

/// Same columns, same rows; numbers equal to 1e-9 relative, text equal.
fn assert_same_table(ours: &str, reference: &str, what: &str) {
    let (h1, r1) = table(ours);
    let (h2, r2) = table(reference);
    assert_eq!(h1, h2, "{what}: header");
    assert_eq!(r1.len(), r2.len(), "{what}: rows");
    for (k, (a, b)) in r1.iter().zip(&r2).enumerate() {
        for (c, (x, y)) in a.iter().zip(b).enumerate() {
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(u), Ok(v)) => assert!(
                    u == v || (u - v).abs() <= 1e-9 * u.abs().max(v.abs()),
                    "{what} row {k} {}: {x} vs {y}",
                    h1[c]
                ),
                _ => assert_eq!(x, y, "{what} row {k} {}", h1[c]),
            }
        }
    }
}

/// cooltools 0.7.1 `dots` on the yeast 10 kb map (its stored weights, API defaults, kernels
/// w=5, p=2): the same 161 enriched pixels and the same 2 dots, every column
/// (data/reference/dots, scripts/dots_reference.py).
#[test]
fn yeast_dots_are_cooltools() {
    let reader = open_matrix("data/yeast.10kb.cool", &OpenOptions::default()).unwrap();
    let weights = reader.weights("weight").unwrap().values;
    let view = View::chromosomes(reader.bins());
    let pixels = load_pixels(reader.as_ref(), u64::MAX).unwrap();
    let expected = expected_cis(&pixels, Some(&weights), &view, &CisParams::default())
        .unwrap()
        .average_by_region();
    let params = DotsParams::for_resolution(10_000).unwrap();
    let calls = call_dots(reader.as_ref(), &weights, &view, &expected, &params).unwrap();
    assert_eq!(calls.extra_lambda_bins, 0);
    assert_same_table(
        &enriched_tsv(&calls, reader.bins()),
        &gz_text("data/reference/dots/yeast_10kb.enriched.tsv.gz"),
        "enriched",
    );
    assert_same_table(
        &dots_tsv(&calls, reader.bins(), &view).unwrap(),
        &gz_text("data/reference/dots/yeast_10kb.dots.tsv.gz"),
        "dots",
    );
}

/// The lambda bin of a value by the exponent shortcut is pandas' `cut` (a search of the edges),
/// at the edges themselves, next to them and between them.
#[test]
fn lambda_index_is_a_search_of_the_edges() {
    let bins = fdr::LambdaBins::new(40);
    let search = |x: f64| bins.edges.partition_point(|&e| e < x) - 1;
    let mut values = vec![0.0, 0.3, 1.0, 1e300, f64::MIN_POSITIVE];
    for &e in &bins.edges[1..] {
        values.extend([e, e.next_down(), e.next_up(), e * 1.1, e * 0.97]);
    }
    for x in values {
        let want = search(x).min(bins.len());
        assert_eq!(bins.index(x), want, "{x:e}");
    }
}

/// The locally adjusted expected of every scored pixel, as cooltools defines it, computed cell by
/// cell from the dense matrix: the scan's band sums agree to 1e-12, both in the scoring pass
/// (every pixel) and in the extraction pass (pixels from a count up, the same values to the bit).
#[test]
fn scan_is_a_naive_sum_over_kernel_cells() {
    use scan::{RegionScan, ScanSettings, scan_region};
    let reader = open_matrix("data/yeast.10kb.cool", &OpenOptions::default()).unwrap();
    let mut weights = reader.weights("weight").unwrap().values;
    // more masked bins than the file has, to exercise the missing-cell paths
    for k in (0..weights.len()).step_by(97) {
        weights[k] = f64::NAN;
    }
    let view = View::chromosomes(reader.bins());
    let pixels = load_pixels(reader.as_ref(), u64::MAX).unwrap();
    let expected = expected_cis(&pixels, Some(&weights), &view, &CisParams::default())
        .unwrap()
        .average_by_region();
    let kernels = kernels::Kernel::hiccups(4, 2).unwrap();
    let band = 60;
    // the longest chromosome
    let r = (0..view.regions().len())
        .max_by_key(|&r| view.regions()[r].bins.len())
        .unwrap();
    let bins = view.regions()[r].bins.clone();
    let (s, n) = (bins.start, bins.len());
    let mut raw = vec![0.0; n * n];
    reader
        .read_pixels(bins.clone(), bins.clone(), &mut |block| {
            for k in 0..block.len() {
                let (a, b) = (block.bin1[k] as usize, block.bin2[k] as usize);
                raw[(a - s) * n + (b - s)] = block.count[k];
            }
            Ok(())
        })
        .unwrap();
    let exp = &expected[r];
    let cell = |a: i64, b: i64| -> Option<(f64, f64)> {
        if a < 0 || b < a || b >= n as i64 {
            return None;
        }
        let e = *exp.get((b - a) as usize)?;
        let (wa, wb) = (weights[s + a as usize], weights[s + b as usize]);
        (!(wa * wb).is_nan() && !e.is_nan())
            .then(|| (raw[a as usize * n + b as usize] * wa * wb, e))
    };
    let max_nans = 25;

    let mut naive = Vec::new();
    for i in 0..n as i64 {
        'pixel: for j in i + 1..(i + band as i64).min(n as i64) {
            let mut la = Vec::new();
            for kernel in &kernels {
                let (mut ko, mut ke, mut nn) = (0.0, 0.0, 0);
                for &(dy, dx) in &kernel.cells {
                    match cell(i + dy as i64, j + dx as i64) {
                        Some((o, e)) => {
                            ko += o;
                            ke += e;
                        }
                        None => nn += 1,
                    }
                }
                if nn >= max_nans || !(ko / ke).is_finite() {
                    continue 'pixel;
                }
                let e_raw = cell(i, j).map_or(0.0, |(_, e)| {
                    e / (weights[s + i as usize] * weights[s + j as usize])
                });
                la.push(e_raw * ko / ke);
            }
            naive.push((
                s + i as usize,
                s + j as usize,
                raw[i as usize * n + j as usize] as u64,
                la,
            ));
        }
    }
    let region = RegionScan {
        bins: bins.clone(),
        weights: &weights,
        expected: exp,
    };
    let scan = |min_count: u64| {
        let settings = ScanSettings {
            kernels: &kernels,
            band,
            max_nans_tolerated: max_nans,
            min_count,
            rows: None,
        };
        let mut found = scan_region(
            reader.as_ref(),
            &region,
            &settings,
            Vec::new,
            |v: &mut Vec<(usize, usize, u64, Vec<f64>)>, p| {
                v.push((p.bin1, p.bin2, p.count, p.la_exp.to_vec()));
                Ok(())
            },
            |mut a, mut b| {
                a.append(&mut b);
                a
            },
        )
        .unwrap();
        found.sort_by_key(|p| (p.0, p.1));
        found
    };
    let all = scan(0);
    assert_eq!(all.len(), naive.len());
    assert!(all.len() > 3_000, "{}", all.len());
    for (ours, theirs) in all.iter().zip(&naive) {
        assert_eq!((ours.0, ours.1, ours.2), (theirs.0, theirs.1, theirs.2));
        for (x, y) in ours.3.iter().zip(&theirs.3) {
            assert!((x - y).abs() <= 1e-12 * y.abs(), "{ours:?} vs {theirs:?}");
        }
    }
    let strong = scan(4);
    let expect: Vec<_> = all.iter().filter(|p| p.2 >= 4).cloned().collect();
    assert!(!expect.is_empty() && expect.len() < all.len());
    assert_eq!(strong, expect);
}
