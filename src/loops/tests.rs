use std::io::Read as _;

use super::tables::{dots_tsv, enriched_tsv};
use super::*;
use crate::expected::{expected_cis, CisParams};
use crate::io::{load_pixels, open_matrix, OpenOptions};

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
    let params = DotsParams::for_bin_size(10_000).unwrap();
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
