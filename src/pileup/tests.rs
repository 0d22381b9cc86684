//! The pileups against coolpuppy 1.1.0 on the simulated extrusion map
//! (`data/reference/pileup/`, `scripts/pileup_reference.py`).

use std::io::Read as _;

use super::*;
use crate::expected::{expected_cis, CisParams};
use crate::io::bed::{read_bed, read_bedpe};
use crate::io::{open_matrix, LoadedPixels, OpenOptions, StreamedPixels};

/// coolpuppy's pileup `name`: its `n` and grid.
fn reference(name: &str) -> (usize, Vec<Vec<f64>>) {
    let mut text = String::new();
    let path = format!("data/reference/pileup/{name}.tsv.gz");
    flate2::read::GzDecoder::new(std::fs::File::open(path).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    let mut lines = text.lines();
    let n = lines
        .next()
        .unwrap()
        .trim_start_matches("# n=")
        .parse()
        .unwrap();
    let grid = lines
        .map(|l| l.split('\t').map(|v| v.parse().unwrap()).collect())
        .collect();
    (n, grid)
}

/// Our pileup of `features` with `params` (balanced unless `raw`; observed / expected when
/// `oe`) equals coolpuppy's `name`: the same `n`, NaN where it has NaN, values to 1e-12; and
/// so do the scores of it that `scores.tsv` holds.
fn check(name: &str, features: Features, params: PileupParams, raw: bool, oe: bool) {
    let reader = open_matrix("data/sim_extrusion.5kb.cool", &OpenOptions::default()).unwrap();
    let weights = reader.weights("weight").unwrap().values;
    let view = View::chromosomes(reader.bins());
    let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader.as_ref()));
    let expected = expected_cis(&pixels, Some(&weights), &view, &CisParams::default())
        .unwrap()
        .average_by_region();
    let weights = (!raw).then_some(&weights[..]);
    let expected = oe.then_some(&expected[..]);
    let pup = pileup(
        reader.as_ref(),
        weights,
        &view,
        &features,
        expected,
        &params,
    )
    .unwrap();
    let (n, grid) = reference(name);
    assert_eq!(pup.n, n, "{name}: n");
    assert_eq!(pup.data.nrows(), grid.len(), "{name}: size");
    for (r, row) in grid.iter().enumerate() {
        for (c, &want) in row.iter().enumerate() {
            let got = pup.data[[r, c]];
            assert!(
                (got.is_nan() && want.is_nan())
                    || (got - want).abs() <= 1e-12 * want.abs().max(got.abs()),
                "{name} [{r}, {c}]: {got} vs coolpuppy {want}"
            );
        }
    }
    let table = std::fs::read_to_string("data/reference/pileup/scores.tsv").unwrap();
    let mut checked = 0;
    for line in table.lines().skip(1) {
        let f: Vec<&str> = line.split('\t').collect();
        if f[0] != name {
            continue;
        }
        let (k, want): (usize, f64) = (f[2].parse().unwrap(), f[3].parse().unwrap());
        let got = match f[1] {
            "enrichment" => scores::enrichment(pup.data.view(), k).unwrap(),
            "corner_cv" => scores::corner_cv(pup.data.view(), k),
            "insulation_strength" => scores::insulation_strength(pup.data.view(), k, 2).unwrap(),
            other => panic!("{other}"),
        };
        assert!((got - want).abs() <= 1e-12 * want.abs(), "{line}: {got}");
        checked += 1;
    }
    assert!(checked > 0, "{name}: scores");
}

fn anchors() -> Vec<crate::io::bed::BedRecord> {
    read_bed("data/reference/pileup/anchors.bed".as_ref()).unwrap()
}

#[test]
fn bedpe_observed_over_expected_is_coolpuppy() {
    let loops = read_bedpe("data/sim_extrusion.truth_loops.bedpe".as_ref()).unwrap();
    let params = PileupParams {
        flank_bp: 20_000,
        ..PileupParams::default()
    };
    check("bedpe_oe", Features::Bedpe(loops), params, false, true);
}

#[test]
fn bed_pairs_raw_and_observed_over_expected_are_coolpuppy() {
    let features = Features::Bed {
        features: anchors(),
        local: false,
    };
    let params = PileupParams {
        flank_bp: 30_000,
        max_dist_bp: Some(400_000.0),
        ..PileupParams::default()
    };
    check("bed_raw", features.clone(), params, true, false);
    let params = PileupParams {
        flank_bp: 20_000,
        min_dist_bp: Some(100_000.0),
        ..PileupParams::default()
    };
    check("bed_oe", features, params, false, true);
}

#[test]
fn bed_local_observed_over_expected_is_coolpuppy() {
    let features = Features::Bed {
        features: anchors(),
        local: true,
    };
    let params = PileupParams {
        flank_bp: 50_000,
        ..PileupParams::default()
    };
    check("bed_local_oe", features, params, false, true);
}
