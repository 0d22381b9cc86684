use super::*;
use crate::io::predictions::{read_fasta, read_prediction};
use crate::io::structure::read_structure;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/protein");

fn truth(structure: &str, definition: ContactDefinition) -> TrueContacts {
    let structure = read_structure(format!("{DATA}/{structure}")).unwrap();
    TrueContacts::from_chain(structure.chain(None).unwrap(), definition).unwrap()
}

fn prediction(file: &str, fasta: &str) -> Prediction {
    let sequence = read_fasta(format!("{DATA}/{fasta}")).unwrap();
    read_prediction(format!("{DATA}/{file}"), None)
        .unwrap()
        .with_sequence(&sequence)
        .unwrap()
}

/// `(TP, n_scored)` of each list.
fn counts(score: &ContactScore) -> Vec<(usize, usize)> {
    score
        .lists
        .iter()
        .map(|list| (list.true_positives, list.n_scored))
        .collect()
}

#[test]
fn true_contact_counts_per_range() {
    let ranges = [
        SeparationRange::SHORT,
        SeparationRange::MEDIUM,
        SeparationRange::LONG,
        SeparationRange::ALL,
    ];
    for (structure, observed, expected) in [
        ("toxd/toxd.pdb.gz", 58, [15, 43, 57, 115]),
        ("1atzA/1atzA.pdb.gz", 75, [24, 27, 69, 120]),
        ("1aapA/1aapA.pdb.gz", 56, [13, 44, 57, 114]),
        ("1guuA/1guuA.pdb.gz", 50, [15, 17, 13, 45]),
        ("1a8o/1A8O.pdb.gz", 70, [16, 26, 35, 77]),
        ("1a8o/1A8O.cif.gz", 70, [16, 26, 35, 77]),
    ] {
        for test in [DistanceTest::Less, DistanceTest::LessOrEqual] {
            let definition = ContactDefinition {
                test,
                ..ContactDefinition::default()
            };
            let truth = truth(structure, definition);
            assert_eq!(truth.n_observed(), observed, "{structure}");
            let found = ranges.map(|range| truth.n_contacts(range));
            assert_eq!(found, expected, "{structure} {test:?}");
        }
    }
    let pdb = truth("1a8o/1A8O.pdb.gz", ContactDefinition::default());
    let cif = truth("1a8o/1A8O.cif.gz", ContactDefinition::default());
    assert_eq!(
        pdb.contacts(SeparationRange::new(1, None)),
        cif.contacts(SeparationRange::new(1, None))
    );
}

#[test]
fn method_p_long_range_precision() {
    let params = ScoreParams::default();
    for (structure, file, fasta, expected) in [
        (
            "toxd/toxd.pdb.gz",
            "toxd/toxd.mat.gz",
            "toxd/toxd.fasta",
            [(5, 5), (9, 11), (17, 29), (22, 59)],
        ),
        (
            "1atzA/1atzA.pdb.gz",
            "1atzA/1atzA.apc.mat.gz",
            "1atzA/1atzA.fasta",
            [(6, 7), (12, 15), (21, 37), (30, 75)],
        ),
        (
            "1atzA/1atzA.pdb.gz",
            "1atzA/1atzA.noapc.mat.gz",
            "1atzA/1atzA.fasta",
            [(4, 7), (5, 15), (9, 37), (11, 75)],
        ),
        (
            "1aapA/1aapA.pdb.gz",
            "1aapA/1aapA.rr.gz",
            "1aapA/1aapA.fasta",
            [(4, 5), (9, 11), (13, 28), (17, 56)],
        ),
        (
            "1guuA/1guuA.pdb.gz",
            "1guuA/1guuA.contact.rr",
            "1guuA/1guuA.fasta",
            [(1, 1); 4],
        ),
        (
            "1guuA/1guuA.pdb.gz",
            "1guuA/1guuA.npz",
            "1guuA/1guuA.fasta",
            [(5, 5), (10, 10), (13, 25), (13, 50)],
        ),
    ] {
        let truth = truth(structure, ContactDefinition::default());
        let score = score_contacts(&truth, &prediction(file, fasta), &params).unwrap();
        assert_eq!(counts(&score), expected, "{file}");
    }
}

#[test]
fn method_p_precision_values() {
    let truth = truth("toxd/toxd.pdb.gz", ContactDefinition::default());
    let prediction = prediction("toxd/toxd.mat.gz", "toxd/toxd.fasta");
    let score = score_contacts(&truth, &prediction, &ScoreParams::default()).unwrap();
    let precisions: Vec<f64> = score.lists.iter().map(|list| list.precision).collect();
    for (found, expected) in precisions.iter().zip([1.0, 0.818182, 0.586207, 0.372881]) {
        assert!((found - expected).abs() < 5e-7, "{found} vs {expected}");
    }
    assert_eq!(score.length, 59);
    assert_eq!(score.n_true, 57);
    let first = score.lists[0];
    assert!((first.recall - 5.0 / 57.0).abs() < 1e-12);
    assert!(first.mcc > 0.0 && first.mcc <= 1.0);
}

/// Xd against a naive transcription of the CASP definition, and the curve against the
/// list scores.
#[test]
fn xd_and_curve_against_naive() {
    let truth = truth("toxd/toxd.pdb.gz", ContactDefinition::default());
    let prediction = prediction("toxd/toxd.mat.gz", "toxd/toxd.fasta");
    let params = ScoreParams {
        range: SeparationRange::ALL,
        list_sizes: vec![ListSize::Fraction(0.2), ListSize::Fraction(1.0)],
        curve: Some(ListSize::Fraction(2.0)),
        ..ScoreParams::default()
    };
    let score = score_contacts(&truth, &prediction, &params).unwrap();
    // Naive: rank the observed pairs of the range, count distances per 4 A bin.
    let mut ranked: Vec<(i32, i32, f64)> = normalize_pairs(&prediction.pairs)
        .into_iter()
        .filter(|&(i, j, _)| j - i >= 6 && truth.distance(i, j).is_some())
        .collect();
    ranked.sort_by(|a, b| b.2.partial_cmp(&a.2).unwrap());
    let numbers = truth.numbers();
    let all: Vec<f64> = numbers
        .iter()
        .flat_map(|&i| numbers.iter().map(move |&j| (i, j)))
        .filter(|&(i, j)| j - i >= 6)
        .map(|(i, j)| truth.distance(i, j).unwrap())
        .collect();
    let percent_in = |distances: &[f64], bin: usize| {
        let lower = 4.0 * bin as f64;
        100.0
            * distances
                .iter()
                .filter(|&&d| d >= lower && d < lower + 4.0)
                .count() as f64
            / distances.len() as f64
    };
    for list in &score.lists {
        let top: Vec<f64> = ranked[..list.k]
            .iter()
            .map(|&(i, j, _)| truth.distance(i, j).unwrap())
            .collect();
        let mut naive = 0.0;
        for bin in 0..15 {
            let d_i = 4.0 * (bin + 1) as f64 / 60.0;
            naive += (percent_in(&top, bin) - percent_in(&all, bin)) / (d_i * 15.0);
        }
        assert!((list.xd - naive).abs() < 1e-9, "{} vs {naive}", list.xd);
        assert!(list.xd > 5.0, "a good list has a positive Xd: {}", list.xd);
        assert_eq!(score.curve[list.k - 1], list.true_positives);
    }
    assert_eq!(score.curve.len(), 118);
    assert!(
        score
            .curve
            .windows(2)
            .all(|w| w[1] >= w[0] && w[1] <= w[0] + 1)
    );
    // Listing every observed pair of the range reproduces the background: Xd = 0.
    let everything = Prediction {
        pairs: numbers
            .iter()
            .flat_map(|&i| numbers.iter().map(move |&j| (i, j, 1.0)))
            .filter(|&(i, j, _)| j - i >= 6)
            .collect(),
        sequence: prediction.sequence.clone(),
        length: None,
    };
    let params = ScoreParams {
        range: SeparationRange::ALL,
        list_sizes: vec![ListSize::Count(all.len())],
        ..ScoreParams::default()
    };
    let score = score_contacts(&truth, &everything, &params).unwrap();
    assert!(score.lists[0].xd.abs() < 1e-9, "{}", score.lists[0].xd);
}

#[test]
fn conkit_documentation_toxd() {
    // Separation >= 5, all ranges, top int(59 * f) for f = 0.5, 1.0, 1.5.
    let truth = truth("toxd/toxd.pdb.gz", ContactDefinition::default());
    let prediction = prediction("toxd/toxd.mat.gz", "toxd/toxd.fasta");
    let params = ScoreParams {
        range: SeparationRange::new(5, None),
        list_sizes: vec![
            ListSize::Fraction(0.5),
            ListSize::Fraction(1.0),
            ListSize::Fraction(1.5),
        ],
        ..ScoreParams::default()
    };
    let score = score_contacts(&truth, &prediction, &params).unwrap();
    assert_eq!(counts(&score), [(24, 29), (35, 59), (38, 88)]);
}

#[test]
fn coneva_conventions() {
    // Round half up, L = observed residues; coneva.pl prints percentages.
    let params = ScoreParams {
        length: TargetLength::Observed,
        rounding: Rounding::HalfUp,
        ..ScoreParams::default()
    };
    for (structure, file, fasta, expected, percentages) in [
        (
            "1aapA/1aapA.pdb.gz",
            "1aapA/1aapA.rr.gz",
            "1aapA/1aapA.fasta",
            [(5, 6), (9, 11), (13, 28), (17, 56)],
            [83.33, 81.82, 46.43, 30.36],
        ),
        (
            "toxd/toxd.pdb.gz",
            "toxd/toxd.mat.gz",
            "toxd/toxd.fasta",
            [(6, 6), (10, 12), (17, 29), (22, 58)],
            [100.0, 83.33, 58.62, 37.93],
        ),
    ] {
        let truth = truth(structure, ContactDefinition::default());
        let score = score_contacts(&truth, &prediction(file, fasta), &params).unwrap();
        assert_eq!(counts(&score), expected, "{file}");
        for (list, percentage) in score.lists.iter().zip(percentages) {
            assert!(((list.precision * 100.0 * 100.0).round() / 100.0 - percentage).abs() < 1e-9);
        }
    }
}

#[test]
fn disteval_conventions() {
    // Banker's rounding of 0.2 L, separations >= 12 and >= 24, Top-L/5 and Top-NC.
    let truth = truth("1guuA/1guuA.pdb.gz", ContactDefinition::default());
    let list_sizes = vec![ListSize::Fraction(0.2), ListSize::TrueContacts];
    for (file, expected12, expected24) in [
        ("1guuA/1guuA.contact.rr", [(9, 9), (9, 9)], [(1, 1), (1, 1)]),
        (
            "1guuA/1guuA.predicted.npy",
            [(9, 10), (18, 30)],
            [(5, 10), (5, 13)],
        ),
        (
            "1guuA/1guuA.npz",
            [(10, 10), (24, 30)],
            [(10, 10), (11, 13)],
        ),
    ] {
        let prediction = prediction(file, "1guuA/1guuA.fasta");
        for (min, expected) in [(12, expected12), (24, expected24)] {
            let params = ScoreParams {
                range: SeparationRange::new(min, None),
                rounding: Rounding::Banker,
                list_sizes: list_sizes.clone(),
                ..ScoreParams::default()
            };
            let score = score_contacts(&truth, &prediction, &params).unwrap();
            assert_eq!(counts(&score), expected, "{file} sep >= {min}");
        }
    }
}

#[test]
fn cb_distances_match_disteval_true_map() {
    // 1guuA.true.npy is DISTEVAL's float16 Cb (Ca for Gly) distance map of 1guuA.pdb.
    let bytes = std::fs::read(format!("{DATA}/1guuA/1guuA.true.npy")).unwrap();
    let map = crate::io::predictions::parse_npy(&bytes, std::path::Path::new("t")).unwrap();
    let truth = truth("1guuA/1guuA.pdb.gz", ContactDefinition::default());
    assert_eq!(truth.numbers(), (1..=50).collect::<Vec<_>>());
    for i in 1..=50 {
        for j in i + 1..=50 {
            let ours = truth.distance(i, j).unwrap();
            let theirs = map.values[(i as usize - 1) * 50 + j as usize - 1];
            // float16 keeps 11 significant bits: relative error below 2^-11.
            assert!(
                (ours - theirs).abs() <= ours * 2f64.powi(-11),
                "{i}-{j}: {ours} {theirs}"
            );
        }
    }
}

#[test]
fn own_contacts_score_precision_one() {
    let truth = truth("1atzA/1atzA.pdb.gz", ContactDefinition::default());
    let pairs = truth
        .contacts(SeparationRange::ALL)
        .into_iter()
        .map(|(i, j)| (j, i, 1.0)) // written j > i on purpose
        .collect();
    let prediction = Prediction {
        pairs,
        sequence: None,
        length: None,
    };
    for range in [
        SeparationRange::SHORT,
        SeparationRange::MEDIUM,
        SeparationRange::LONG,
    ] {
        let params = ScoreParams {
            range,
            length: TargetLength::Observed,
            list_sizes: vec![ListSize::TrueContacts],
            ..ScoreParams::default()
        };
        let list = score_contacts(&truth, &prediction, &params).unwrap().lists[0];
        assert_eq!(
            (list.precision, list.recall, list.f1, list.mcc),
            (1.0, 1.0, 1.0, 1.0)
        );
    }
}

#[test]
fn normalization_rules() {
    let pairs = [
        (5, 1, 0.2),
        (1, 5, 0.9),
        (2, 2, 1.0),
        (3, 9, f64::NAN),
        (1, 7, 0.5),
    ];
    assert_eq!(normalize_pairs(&pairs), vec![(1, 5, 0.9), (1, 7, 0.5)]);
}

#[test]
fn unobserved_pairs_take_a_slot_when_kept() {
    // toxd: residue 1 (PCA) is unobserved.
    let truth = truth("toxd/toxd.pdb.gz", ContactDefinition::default());
    assert_eq!(truth.is_contact(1, 40), None);
    let prediction = Prediction {
        pairs: vec![(1, 40, 2.0), (16, 40, 1.0)],
        sequence: None,
        length: None,
    };
    let mut params = ScoreParams {
        length: TargetLength::Residues(10),
        list_sizes: vec![ListSize::Count(1)],
        ..ScoreParams::default()
    };
    assert_eq!(truth.is_contact(16, 40), Some(true));
    let dropped = score_contacts(&truth, &prediction, &params).unwrap();
    assert_eq!(dropped.lists[0].true_positives, 1);
    params.drop_unobserved = false;
    let kept = score_contacts(&truth, &prediction, &params).unwrap();
    assert_eq!(kept.lists[0].true_positives, 0);
}

#[test]
fn other_atoms_and_errors() {
    let cb = truth("toxd/toxd.pdb.gz", ContactDefinition::default());
    let heavy = truth(
        "toxd/toxd.pdb.gz",
        ContactDefinition {
            atom: ContactAtom::Heavy,
            ..ContactDefinition::default()
        },
    );
    let ca = truth(
        "toxd/toxd.pdb.gz",
        ContactDefinition {
            atom: ContactAtom::Ca,
            ..ContactDefinition::default()
        },
    );
    // The closest heavy-atom pair is never farther than the Cb or Ca pair.
    for &i in cb.numbers() {
        for &j in cb.numbers() {
            if let (Some(h), Some(b), Some(a)) =
                (heavy.distance(i, j), cb.distance(i, j), ca.distance(i, j))
            {
                assert!(h <= b + 1e-12 && h <= a + 1e-12);
            }
        }
    }
    assert!(heavy.n_contacts(SeparationRange::ALL) > cb.n_contacts(SeparationRange::ALL));
    let no_sequence = Prediction::default();
    assert!(score_contacts(&cb, &no_sequence, &ScoreParams::default()).is_err());
    let structure = read_structure(format!("{DATA}/toxd/toxd.pdb.gz")).unwrap();
    let bad = ContactDefinition {
        cutoff_angstrom: f64::NAN,
        ..ContactDefinition::default()
    };
    assert!(TrueContacts::from_chain(&structure.chains[0], bad).is_err());
}

#[test]
fn rounding() {
    assert_eq!(Rounding::Floor.apply(5.9), 5);
    assert_eq!(Rounding::HalfUp.apply(5.5), 6);
    assert_eq!(Rounding::Banker.apply(2.5), 2);
    assert_eq!(Rounding::Banker.apply(3.5), 4);
}

mod properties {
    use super::*;
    use crate::io::structure::{Atom, Chain, Residue};
    use proptest::prelude::*;

    /// A chain of `n` residues on a random walk with 3.8 A steps, Ca only.
    fn chain(directions: &[(f64, f64)]) -> Chain {
        let mut xyz = [0.0f64; 3];
        let residues = directions
            .iter()
            .enumerate()
            .map(|(index, &(theta, phi))| {
                xyz[0] += 3.8 * theta.sin() * phi.cos();
                xyz[1] += 3.8 * theta.sin() * phi.sin();
                xyz[2] += 3.8 * theta.cos();
                Residue {
                    number: index as i32 + 1,
                    insertion: None,
                    name: "ALA".into(),
                    one_letter: 'A',
                    atoms: vec![Atom {
                        name: "CA".into(),
                        element: "C".into(),
                        xyz,
                    }],
                }
            })
            .collect();
        Chain {
            id: "A".into(),
            residues,
        }
    }

    proptest! {
        #[test]
        fn matches_a_naive_stable_ranking(
            directions in prop::collection::vec((0.0..std::f64::consts::PI, 0.0..std::f64::consts::TAU), 20..40),
            raw in prop::collection::vec((1i32..45, 1i32..45, 0u8..4), 0..200),
            k in 0usize..60,
        ) {
            let definition = ContactDefinition { atom: ContactAtom::Ca, ..Default::default() };
            let truth = TrueContacts::from_chain(&chain(&directions), definition).unwrap();
            // Few distinct scores: many ties, broken by first occurrence.
            let pairs: Vec<(i32, i32, f64)> =
                raw.iter().map(|&(i, j, s)| (i, j, f64::from(s))).collect();
            let range = SeparationRange::new(3, None);
            let params = ScoreParams {
                range,
                length: TargetLength::Observed,
                list_sizes: vec![ListSize::Count(k)],
                ..ScoreParams::default()
            };
            let prediction = Prediction { pairs: pairs.clone(), sequence: None, length: None };
            let list = score_contacts(&truth, &prediction, &params).unwrap().lists[0];

            // Naive: best score of each unordered pair, ranked by (score desc, first index).
            let mut best: Vec<((i32, i32), f64, usize)> = Vec::new();
            for (index, &(i, j, score)) in pairs.iter().enumerate() {
                let key = (i.min(j), i.max(j));
                if i == j { continue; }
                match best.iter_mut().find(|entry| entry.0 == key) {
                    Some(entry) => entry.1 = entry.1.max(score),
                    None => best.push((key, score, index)),
                }
            }
            best.retain(|((i, j), _, _)| {
                range.contains(*i, *j) && truth.is_contact(*i, *j).is_some()
            });
            best.sort_by(|a, b| b.1.partial_cmp(&a.1).unwrap().then(a.2.cmp(&b.2)));
            let top = &best[..k.min(best.len())];
            let tp = top.iter().filter(|((i, j), _, _)| truth.is_contact(*i, *j) == Some(true)).count();
            prop_assert_eq!(list.n_scored, top.len());
            prop_assert_eq!(list.true_positives, tp);
            prop_assert!((0.0..=1.0).contains(&list.precision));
            prop_assert!((-1.0..=1.0).contains(&list.mcc));
        }
    }
}
