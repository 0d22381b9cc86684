//! Criterion bench of protein contact scoring: a prediction of one million pairs (the 499,500
//! pairs of 1,000 residues with random scores, then as many again reversed, which the scorer
//! deduplicates) against a 1,000-residue synthetic chain (a random walk of Ca atoms 3.8 A apart
//! with a Cb beside each), CASP defaults (Cb < 8 A, long range, L/10 to L) and all four ranges;
//! and finding the true contacts of the chain.
//!
//! Run: `cargo bench -p contactmap-benches --bench contacts` (goal: under one second per scoring).

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};

use contactmap::io::predictions::Prediction;
use contactmap::io::structure::{Atom, Chain, Residue};
use contactmap::score::contacts::{
    ContactDefinition, ScoreParams, SeparationRange, TrueContacts, score_contacts,
};

use contactmap_benches as common;

const N_RESIDUES: i32 = 1_000;
const N_PAIRS: usize = 1_000_000;

fn atom(name: &str, xyz: [f64; 3]) -> Atom {
    Atom {
        name: name.into(),
        element: "C".into(),
        xyz,
    }
}

/// A compact random walk (steps of 3.8 A, biased back towards the origin so the chain folds on
/// itself and has long-range contacts).
fn chain() -> Chain {
    let mut random = common::Lcg::new(99);
    let mut position = [0.0f64; 3];
    let residues = (1..=N_RESIDUES)
        .map(|number| {
            let mut step = [0.0; 3];
            for (axis, s) in step.iter_mut().enumerate() {
                *s = random.next_unit() - 0.5 - 0.02 * position[axis];
            }
            let norm = step.iter().map(|s| s * s).sum::<f64>().sqrt();
            for axis in 0..3 {
                position[axis] += 3.8 * step[axis] / norm;
            }
            let cb = [position[0] + 1.5, position[1], position[2]];
            Residue {
                number,
                insertion: None,
                name: "ALA".into(),
                one_letter: 'A',
                atoms: vec![atom("CA", position), atom("CB", cb)],
            }
        })
        .collect();
    Chain {
        id: "A".into(),
        residues,
    }
}

fn prediction() -> Prediction {
    let mut random = common::Lcg::new(7);
    let mut pairs = Vec::with_capacity(N_PAIRS);
    'outer: for i in 1..=N_RESIDUES {
        for j in (i + 1)..=N_RESIDUES {
            pairs.push((i, j, random.next_unit()));
            if pairs.len() == N_PAIRS {
                break 'outer;
            }
        }
    }
    // Fewer than a million distinct pairs exist among 1,000 residues (499,500): repeat them
    // reversed, which the scorer must deduplicate.
    let distinct = pairs.len();
    for k in 0..(N_PAIRS - distinct) {
        let (i, j, _) = pairs[k];
        pairs.push((j, i, random.next_unit()));
    }
    Prediction {
        pairs,
        sequence: Some("A".repeat(N_RESIDUES as usize)),
        length: None,
    }
}

fn bench_contacts(c: &mut Criterion) {
    let chain = chain();
    let prediction = prediction();
    let truth = TrueContacts::from_chain(&chain, ContactDefinition::default()).expect("truth");
    let mut group = c.benchmark_group("contacts");
    group.sample_size(10);
    group.bench_function("true_contacts_1000_residues", |b| {
        b.iter(|| TrueContacts::from_chain(&chain, ContactDefinition::default()).expect("truth"))
    });
    group.throughput(Throughput::Elements(prediction.pairs.len() as u64));
    let params = ScoreParams::default();
    group.bench_function("score_1m_pairs_long_range", |b| {
        b.iter(|| score_contacts(&truth, &prediction, &params).expect("score"))
    });
    group.bench_function("score_1m_pairs_four_ranges", |b| {
        b.iter(|| {
            [
                SeparationRange::SHORT,
                SeparationRange::MEDIUM,
                SeparationRange::LONG,
                SeparationRange::ALL,
            ]
            .map(|range| {
                let params = ScoreParams {
                    range,
                    ..ScoreParams::default()
                };
                score_contacts(&truth, &prediction, &params).expect("score")
            })
        })
    });
    group.finish();
}

criterion_group!(benches, bench_contacts);
criterion_main!(benches);
