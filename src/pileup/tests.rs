//! The pileups against coolpuppy 1.1.0 and cooltools 0.7.1 on the simulated extrusion map and
//! the yeast map (`data/reference/pileup/`, `scripts/pileup_reference.py`).

use super::*;
use crate::expected::{CisParams, expected_cis, expected_trans};
use crate::io::bed::{read_bed, read_bed_table, read_bedpe, read_bedpe_table};
use crate::io::{LoadedPixels, OpenOptions, StreamedPixels, open_matrix};

#[path = "../../tests/support/pileup_reference.rs"]
mod pileup_reference;
use pileup_reference::{RefGroup, reference_case};

/// The reference case `name` (of `pileups.tsv.gz`): its groups, the group of all last.
fn reference(name: &str) -> Vec<RefGroup> {
    reference_case("data/reference/pileup/pileups.tsv.gz".as_ref(), name)
}

/// A map and its cooltools expected (balanced).
fn map(path: &str) -> (Box<dyn MatrixReader>, Vec<f64>, View, Vec<Vec<f64>>) {
    let reader = open_matrix(path, &OpenOptions::default()).unwrap();
    let weights = reader.weights("weight").unwrap().values;
    let view = View::chromosomes(reader.bins());
    let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader.as_ref()));
    let expected = expected_cis(&pixels, Some(&weights), &view, &CisParams::default())
        .unwrap()
        .average_by_region();
    (reader, weights, view, expected)
}

const SIM: &str = "data/sim_extrusion.5kb.cool";
const YEAST: &str = "data/yeast.10kb.cool";

/// Our pileups of `features` on `map_path` with `params` (balanced unless `raw`; observed /
/// expected when `oe`) equal the reference `name`: per group (by label) the same `n` and
/// `control_n`, NaN where it has NaN, values to 1e-12 relative; returns them.
fn check(
    name: &str,
    map_path: &str,
    features: Features,
    params: PileupParams,
    raw: bool,
    oe: bool,
) -> Pileups {
    let (reader, weights, view, mut expected) = map(map_path);
    if params.trans {
        let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader.as_ref()));
        expected = expected_trans(&pixels, Some(&weights), &view)
            .unwrap()
            .average_by_pair(&view);
    }
    let weights = (!raw).then_some(&weights[..]);
    let expected = oe.then_some(&expected[..]);
    let pups = pileup(
        reader.as_ref(),
        weights,
        &view,
        &features,
        expected,
        &params,
    )
    .unwrap();
    let groups = reference(name);
    let labels: Vec<String> = pups.groups.iter().map(|p| p.key.to_string()).collect();
    let mut want_labels: Vec<String> = groups.iter().map(|g| g.label.clone()).collect();
    want_labels.sort();
    let mut got_labels = labels.clone();
    got_labels.sort();
    assert_eq!(got_labels, want_labels, "{name}: groups");
    assert_eq!(labels.last().unwrap(), "all");
    for group in &groups {
        let pup = &pups.groups[labels.iter().position(|l| *l == group.label).unwrap()];
        let what = format!("{name} group {}", group.label);
        assert_eq!(pup.n, group.n, "{what}: n");
        assert_eq!(pup.control_n, group.control_n, "{what}: control_n");
        assert_eq!(pup.data.nrows(), group.grid.len(), "{what}: size");
        compare_grid(&what, &pup.data, &group.grid);
    }
    check_scores(name, &pups.all().data);
    pups
}

fn compare_grid(what: &str, data: &Array2<f64>, grid: &[Vec<f64>]) {
    for (r, row) in grid.iter().enumerate() {
        for (c, &want) in row.iter().enumerate() {
            let got = data[[r, c]];
            assert!(
                (got.is_nan() && want.is_nan())
                    || (got - want).abs() <= 1e-12 * want.abs().max(got.abs()),
                "{what} [{r}, {c}]: {got} vs {want}"
            );
        }
    }
}

/// The scores of `data` that `scores.tsv` holds for case `name`.
fn check_scores(name: &str, data: &Array2<f64>) {
    let table = std::fs::read_to_string("data/reference/pileup/scores.tsv").unwrap();
    for line in table.lines().skip(1) {
        let f: Vec<&str> = line.split('\t').collect();
        if f[0] != name {
            continue;
        }
        let (k, want): (usize, f64) = (f[2].parse().unwrap(), f[3].parse().unwrap());
        let got = match f[1] {
            "enrichment" => scores::enrichment(data.view(), k).unwrap(),
            "corner_cv" => scores::corner_cv(data.view(), k),
            "insulation_strength" => scores::insulation_strength(data.view(), k, 2).unwrap(),
            "domain_score" => scores::domain_score(data.view(), k).unwrap(),
            "local_enrichment" => scores::local_enrichment(data.view(), k).unwrap(),
            other => panic!("{other}"),
        };
        assert!((got - want).abs() <= 1e-12 * want.abs(), "{line}: {got}");
    }
}

fn bed(name: &str) -> Vec<crate::io::bed::BedRecord> {
    read_bed(format!("data/reference/pileup/{name}").as_ref()).unwrap()
}

fn loops() -> Vec<BedpeRecord> {
    read_bedpe("data/sim_extrusion.truth_loops.bedpe".as_ref()).unwrap()
}

fn paired(name: &str) -> Features {
    Features::Bed {
        features: bed(name),
        local: false,
    }
}

fn local(name: &str) -> Features {
    Features::Bed {
        features: bed(name),
        local: true,
    }
}

/// `params` with `n` shifted controls drawn from `seed`.
fn shifted(n: usize, seed: u32, params: PileupParams) -> PileupParams {
    PileupParams {
        shifts: Some(ShiftParams {
            n,
            seed,
            ..ShiftParams::default()
        }),
        ..params
    }
}

fn flank(flank_bp: u64) -> PileupParams {
    PileupParams {
        flank_bp,
        ..PileupParams::default()
    }
}

#[test]
fn bedpe_observed_over_expected_is_coolpuppy() {
    check(
        "bedpe_oe",
        SIM,
        Features::Bedpe(loops()),
        flank(20_000),
        false,
        true,
    );
}

#[test]
fn bed_pairs_raw_and_observed_over_expected_are_coolpuppy() {
    let params = PileupParams {
        max_dist_bp: Some(400_000.0),
        ..flank(30_000)
    };
    check("bed_raw", SIM, paired("anchors.bed"), params, true, false);
    let params = PileupParams {
        min_dist_bp: Some(100_000.0),
        ..flank(20_000)
    };
    check("bed_oe", SIM, paired("anchors.bed"), params, false, true);
    let params = PileupParams {
        max_dist_bp: Some(300_000.0),
        ..flank(30_000)
    };
    check(
        "yeast_bed_oe",
        YEAST,
        paired("yeast_anchors.bed"),
        params,
        false,
        true,
    );
}

#[test]
fn bed_local_observed_over_expected_is_coolpuppy() {
    check(
        "bed_local_oe",
        SIM,
        local("anchors.bed"),
        flank(50_000),
        false,
        true,
    );
}

#[test]
fn rescaled_pileups_are_coolpuppy() {
    let rescaled = |flank, size| PileupParams {
        rescale: Some(RescaleParams { flank, size }),
        ..PileupParams::default()
    };
    check(
        "bed_local_rescale_oe",
        SIM,
        local("domains.bed"),
        rescaled(1.0, 33),
        false,
        true,
    );
    let params = rescaled(1.0, 21);
    check(
        "yeast_local_rescale_oe",
        YEAST,
        local("yeast_domains.bed"),
        params,
        false,
        true,
    );
    let params = shifted(2, 3, rescaled(2.0, 11));
    check(
        "bedpe_rescale_shifts",
        SIM,
        Features::Bedpe(loops()),
        params,
        false,
        false,
    );
}

/// coolpuppy's shifted controls, drawn from numpy's generator with the same seed: the same
/// controls, so the same pileups; and a seed gives the same result every time.
#[test]
fn shifted_controls_are_coolpuppy_seed_for_seed() {
    let shifted = |n, seed, flank_bp| shifted(n, seed, flank(flank_bp));
    let first = check(
        "bed_shifts",
        SIM,
        paired("anchors.bed"),
        shifted(5, 7, 30_000),
        false,
        false,
    );
    let again = check(
        "bed_shifts",
        SIM,
        paired("anchors.bed"),
        shifted(5, 7, 30_000),
        false,
        false,
    );
    assert_eq!(first, again);
    check(
        "bed_local_shifts",
        SIM,
        local("anchors.bed"),
        shifted(3, 1, 50_000),
        false,
        false,
    );
    let params = PileupParams {
        max_dist_bp: Some(300_000.0),
        ..shifted(4, 5, 30_000)
    };
    check(
        "yeast_bed_shifts",
        YEAST,
        paired("yeast_anchors.bed"),
        params,
        false,
        false,
    );
    // another seed, other controls
    let (reader, weights, view, _) = map(SIM);
    let other = pileup(
        reader.as_ref(),
        Some(&weights),
        &view,
        &paired("anchors.bed"),
        None,
        &shifted(5, 8, 30_000),
    )
    .unwrap();
    assert_ne!(other.all().data, first.all().data);
}

#[test]
fn groups_by_distance_and_strand_are_coolpuppy() {
    let params = PileupParams {
        min_dist_bp: Some(100_000.0),
        by_distance: Some(Vec::new()),
        ..flank(20_000)
    };
    let pups = check(
        "bed_by_distance_oe",
        SIM,
        paired("anchors.bed"),
        params,
        false,
        true,
    );
    assert_eq!(
        pups.distance_edges.as_ref().unwrap()[..3],
        [0, 50_000, 100_000]
    );
    let params = PileupParams {
        by_distance: Some(vec![600_000, 150_000, 300_000]),
        ..flank(30_000)
    };
    check(
        "bed_by_distance_raw",
        SIM,
        paired("anchors.bed"),
        params,
        true,
        false,
    );
    let params = PileupParams {
        min_dist_bp: Some(100_000.0),
        by_strand: true,
        flip_negative_strand: true,
        ..flank(20_000)
    };
    check(
        "bed_by_strand_flip_oe",
        SIM,
        paired("anchors.stranded.bed"),
        params,
        false,
        true,
    );
}

/// cooltools `pileup` keeps snippets near an edge (padded with NaN) and masks both triangles'
/// central diagonals; where every window is inside and off the diagonal band, or on the
/// diagonal (where a symmetric snippet's mean is our mirrored one), the mean of its stack is
/// our pileup.
#[test]
fn where_they_overlap_cooltools_pileup_is_ours() {
    for (name, path, features, flank_bp) in [
        ("cooltools_bedpe_oe", SIM, Features::Bedpe(loops()), 20_000),
        (
            "cooltools_yeast_local_oe",
            YEAST,
            local("yeast_anchors.bed"),
            30_000,
        ),
    ] {
        let (reader, weights, view, expected) = map(path);
        let pups = pileup(
            reader.as_ref(),
            Some(&weights),
            &view,
            &features,
            Some(&expected),
            &flank(flank_bp),
        )
        .unwrap();
        let want = reference(name);
        assert_eq!(pups.all().n, want[0].n, "{name}: n");
        compare_grid(name, &pups.all().data, &want[0].grid);
    }
}

/// coolpuppy's coverage normalisation of raw pileups (its coverage from cooltools `coverage`,
/// total: trans pixels count on the yeast map), with and without shifted controls.
#[test]
fn coverage_normalised_pileups_are_coolpuppy() {
    let cov = |params: PileupParams| PileupParams {
        coverage_norm: Some(CoverageNorm::Total),
        ..params
    };
    check(
        "bed_covnorm",
        SIM,
        paired("anchors.bed"),
        cov(flank(30_000)),
        true,
        false,
    );
    let params = shifted(3, 2, cov(flank(20_000)));
    check(
        "bedpe_covnorm_shifts",
        SIM,
        Features::Bedpe(loops()),
        params,
        true,
        false,
    );
    let params = PileupParams {
        max_dist_bp: Some(300_000.0),
        ..cov(flank(30_000))
    };
    check(
        "yeast_bed_covnorm",
        YEAST,
        paired("yeast_anchors.bed"),
        params,
        true,
        false,
    );
}

#[test]
fn groups_by_feature_columns_are_coolpuppy() {
    // BED without a header: coolpuppy's positional names, the anchor's suffix
    let path = "data/reference/pileup/anchors.grouped.bed";
    let table = read_bed_table(path.as_ref()).unwrap();
    let names = ["name1".to_string(), "name2".to_string()];
    let params = PileupParams {
        min_dist_bp: Some(100_000.0),
        groupby: Some(GroupBy::bed(&table, &names, false).unwrap()),
        ..flank(20_000)
    };
    let features = Features::Bed {
        features: table.records.clone(),
        local: false,
    };
    check("bed_groupby_oe", SIM, features, params, false, true);
    // BEDPE with a header: its names; the controls keep their pair's group
    let path = "data/reference/pileup/loops.grouped.bedpe";
    let table = read_bedpe_table(path.as_ref()).unwrap();
    let groupby = GroupBy::bedpe(&table, &["class".to_string()]).unwrap();
    let params = shifted(
        3,
        9,
        PileupParams {
            groupby: Some(groupby),
            ..flank(20_000)
        },
    );
    let pups = check(
        "bedpe_groupby_shifts",
        SIM,
        Features::Bedpe(table.records.clone()),
        params,
        false,
        false,
    );
    assert_eq!(pups.groups.len(), 3);
    // a column the file lacks, or a BED column without the anchor's suffix, is refused
    let bed_table = read_bed_table("data/reference/pileup/anchors.grouped.bed".as_ref()).unwrap();
    for name in ["class", "name", "name3"] {
        let err = GroupBy::bed(&bed_table, &[name.to_string()], false).unwrap_err();
        assert!(err.to_string().contains("name1"), "{err}");
    }
    assert!(GroupBy::bed(&bed_table, &["name".to_string()], true).is_ok());
    assert!(GroupBy::bedpe(&table, &["name".to_string()]).is_err());
}

#[test]
fn trans_pileups_are_coolpuppy() {
    let trans = |params: PileupParams| PileupParams {
        trans: true,
        ..params
    };
    check(
        "yeast_trans_oe",
        YEAST,
        paired("yeast_anchors.bed"),
        trans(flank(30_000)),
        false,
        true,
    );
    // controls: coolpuppy draws a second shift per control in trans and leaves it unused
    check(
        "yeast_trans_shifts",
        YEAST,
        paired("yeast_anchors.bed"),
        shifted(2, 4, trans(flank(30_000))),
        false,
        false,
    );
    let pairs = read_bedpe("data/reference/pileup/yeast_trans.bedpe".as_ref()).unwrap();
    let pups = check(
        "yeast_trans_bedpe_raw",
        YEAST,
        Features::Bedpe(pairs.clone()),
        trans(flank(20_000)),
        true,
        false,
    );
    // a pair given the other way round (chrIV first) is piled up as its mirror, the rows on
    // the earlier chromosome (coolpuppy reads such a pair at the wrong bins)
    let mut reversed = pairs.clone();
    for pair in &mut reversed {
        std::mem::swap(&mut pair.first, &mut pair.second);
    }
    let (reader, _, view, _) = map(YEAST);
    let swapped = pileup(
        reader.as_ref(),
        None,
        &view,
        &Features::Bedpe(reversed),
        None,
        &trans(flank(20_000)),
    )
    .unwrap();
    assert_eq!(swapped.all().n, pups.all().n);
    compare_grid(
        "reversed pairs",
        &swapped.all().data,
        &pups
            .all()
            .data
            .rows()
            .into_iter()
            .map(|r| r.to_vec())
            .collect::<Vec<_>>(),
    );
    // the cis pairs of a BEDPE are left out of a trans pileup, and counted
    let mixed = [pairs.clone(), loops_on(&pairs[0].first.chrom)].concat();
    let pups = pileup(
        reader.as_ref(),
        None,
        &view,
        &Features::Bedpe(mixed),
        None,
        &trans(flank(20_000)),
    )
    .unwrap();
    assert_eq!((pups.all().n, pups.skipped.other_kind), (12, 2));
    // a view of one chromosome, local and by-distance pileups are refused in trans
    let spec = |chrom: &str, end_bp| crate::genome::RegionSpec {
        chrom: chrom.into(),
        start_bp: 0,
        end_bp,
        name: None,
    };
    let one = View::new(reader.bins(), &[spec("chrII", 800_000)]).unwrap();

    let refused = |view: &View, features: &Features, params: PileupParams| {
        pileup(reader.as_ref(), None, view, features, None, &params).is_err()
    };
    assert!(refused(
        &one,
        &paired("yeast_anchors.bed"),
        trans(flank(20_000))
    ));
    assert!(refused(
        &view,
        &local("yeast_anchors.bed"),
        trans(flank(20_000))
    ));
    let by_distance = PileupParams {
        by_distance: Some(Vec::new()),
        ..trans(flank(20_000))
    };
    assert!(refused(&view, &paired("yeast_anchors.bed"), by_distance));
}

/// Two cis pairs on `chrom`.
fn loops_on(chrom: &str) -> Vec<BedpeRecord> {
    let anchor = |start| crate::io::bed::BedRecord::new(chrom, start, start + 5_000);
    [(100_000, 200_000), (300_000, 450_000)]
        .into_iter()
        .map(|(a, b)| BedpeRecord {
            first: anchor(a),
            second: anchor(b),
            rest: Vec::new(),
            line: 1,
        })
        .collect()
}
