//! Loop (dot) calls scored against a truth, such as the loops a simulation held
//! (`simulate polymer --truth-loops`).
//!
//! A loop is a pair of anchors on two chromosomes; each anchor is placed at its midpoint
//! `start + (end - start) / 2`. A call and a truth loop match when their chromosomes are the same
//! and both anchors are at most `tolerance_bp` apart (the larger of the two distances, as
//! HiCCUPS' and cooltools' comparisons count them). Each call matches at most one truth loop and
//! vice versa: [`score_loops`] finds a maximum such matching (augmenting paths, Kuhn's
//! algorithm), so no assignment of calls to loops matches more.
//!
//! Truth loops may carry a weight (the fraction of samples that held them): with `min_fraction`,
//! those held less often are *weak*. They are not counted in the truth (recall asks only for the
//! strong ones), and a call that matches no strong loop but lies within the tolerance of a weak
//! one is left out of precision as well (it is neither a false positive nor a true one: the loop
//! is real, only rare). Then, over all loops and per distance class (by the separation of the
//! anchors, of the truth loop for recall and of the call for precision):
//! `precision = TP_calls / (n_calls - n_weak_calls)`, `recall = TP_truth / n_truth` and `F1` their
//! harmonic mean; a ratio whose denominator is 0 is 0.

use std::fmt::Write as _;

use super::boundaries::boundary_position;
use super::fraction::ratio;
use crate::error::{Error, Result};
use crate::io::bed::BedpeRecord;

/// A loop: two anchors' chromosomes and midpoints, and its weight (1 when none is given).
#[derive(Clone, Debug, PartialEq)]
pub struct Loop {
    /// Chromosome of the first anchor.
    pub chrom1: String,
    /// Midpoint of the first anchor (bp).
    pub mid1: u64,
    /// Chromosome of the second anchor.
    pub chrom2: String,
    /// Midpoint of the second anchor (bp).
    pub mid2: u64,
    /// The fraction of samples that held it (truth), or 1.
    pub fraction: f64,
}

impl Loop {
    /// The loop of a BEDPE record, its anchors ordered; `fraction` from its seventh column when
    /// `weighted` (an error naming `source` when that is not a number in `[0, 1]`).
    pub fn from_record(record: &BedpeRecord, weighted: bool, source: &str) -> Result<Loop> {
        let (a, b) = (&record.first, &record.second);
        let fraction = if weighted {
            let text = record.rest.first().ok_or_else(|| {
                Error::Data(format!(
                    "{source}: a truth loop has no 7th column (the fraction of samples, as \
                     `simulate polymer --truth-loops` writes): {} {} {}",
                    a.chrom, a.start, b.start
                ))
            })?;
            match text.parse::<f64>() {
                Ok(f) if (0.0..=1.0).contains(&f) => f,
                _ => {
                    return Err(Error::Data(format!(
                        "{source}: fraction '{text}' of the loop {} {} {} is not a number in [0, 1]",
                        a.chrom, a.start, b.start
                    )));
                }
            }
        } else {
            1.0
        };
        // each anchor at its midpoint, as `score boundaries` places a boundary
        let (first, second) = {
            let (a, b) = (boundary_position(a), boundary_position(b));
            if a <= b { (a, b) } else { (b, a) }
        };
        Ok(Loop {
            chrom1: first.0,
            mid1: first.1,
            chrom2: second.0,
            mid2: second.1,
            fraction,
        })
    }

    /// The separation of the anchors (`None` between chromosomes).
    pub fn separation(&self) -> Option<u64> {
        (self.chrom1 == self.chrom2).then(|| self.mid2.abs_diff(self.mid1))
    }

    /// Whether `other` is within `tolerance_bp` of this loop at both anchors.
    fn near(&self, other: &Loop, tolerance_bp: u64) -> bool {
        self.chrom1 == other.chrom1
            && self.chrom2 == other.chrom2
            && self.mid1.abs_diff(other.mid1) <= tolerance_bp
            && self.mid2.abs_diff(other.mid2) <= tolerance_bp
    }
}

/// How [`score_loops`] matches and groups.
#[derive(Clone, Debug, PartialEq)]
pub struct LoopScoreParams {
    /// The largest distance between matched anchors (bp).
    pub tolerance_bp: u64,
    /// Truth loops held in a smaller fraction of samples are weak (see the module docs).
    pub min_fraction: f64,
    /// Edges of the distance classes (bp, increasing, from 0): class `k` holds separations in
    /// `[edges[k], edges[k + 1])`, the last class everything from its edge up.
    pub distance_edges: Vec<u64>,
}

/// One row of [`score_loops`]: a distance class, or all loops.
#[derive(Clone, Debug, PartialEq)]
pub struct LoopScoreRow {
    /// `all`, `trans` or the class as `FROM-TO` (`FROM+` for the last).
    pub class: String,
    /// Strong truth loops in the class.
    pub n_truth: usize,
    /// Calls in the class.
    pub n_calls: usize,
    /// Calls that match only weak truth loops (left out of precision).
    pub n_weak_calls: usize,
    /// Matched truth loops in the class.
    pub truth_matched: usize,
    /// Matched calls in the class.
    pub calls_matched: usize,
    /// `calls_matched / (n_calls - n_weak_calls)`.
    pub precision: f64,
    /// `truth_matched / n_truth`.
    pub recall: f64,
    /// The harmonic mean of precision and recall (0 when both are 0).
    pub f1: f64,
}

/// A maximum one-to-one matching of `calls` to `truth` within the tolerance: per call, the index
/// of its truth loop.
fn max_matching(calls: &[Loop], truth: &[Loop], tolerance_bp: u64) -> Vec<Option<usize>> {
    // candidate truth loops of each call, through a sort of the truth by (chroms, mid1)
    let mut order: Vec<usize> = (0..truth.len()).collect();
    let key = |l: &Loop| (l.chrom1.clone(), l.chrom2.clone(), l.mid1);
    order.sort_by_key(|&t| key(&truth[t]));
    let sorted: Vec<(String, String, u64)> = order.iter().map(|&t| key(&truth[t])).collect();
    let candidates: Vec<Vec<usize>> = calls
        .iter()
        .map(|c| {
            let lo = (
                c.chrom1.clone(),
                c.chrom2.clone(),
                c.mid1.saturating_sub(tolerance_bp),
            );
            let mut near = Vec::new();
            let mut k = sorted.partition_point(|k| *k < lo);
            while k < sorted.len()
                && sorted[k].0 == c.chrom1
                && sorted[k].1 == c.chrom2
                && sorted[k].2 <= c.mid1 + tolerance_bp
            {
                if truth[order[k]].near(c, tolerance_bp) {
                    near.push(order[k]);
                }
                k += 1;
            }
            near
        })
        .collect();
    let mut owner: Vec<Option<usize>> = vec![None; truth.len()];
    fn augment(
        call: usize,
        candidates: &[Vec<usize>],
        owner: &mut [Option<usize>],
        seen: &mut [bool],
    ) -> bool {
        for &t in &candidates[call] {
            if seen[t] {
                continue;
            }
            seen[t] = true;
            if owner[t].is_none_or(|other| augment(other, candidates, owner, seen)) {
                owner[t] = Some(call);
                return true;
            }
        }
        false
    }
    let mut seen = vec![false; truth.len()];
    for call in 0..calls.len() {
        if !candidates[call].is_empty() {
            seen.fill(false);
            augment(call, &candidates, &mut owner, &mut seen);
        }
    }
    let mut matched = vec![None; calls.len()];
    for (t, call) in owner.iter().enumerate() {
        if let Some(call) = call {
            matched[*call] = Some(t);
        }
    }
    matched
}

/// Score `calls` against `truth` (see the module docs): the rows of the distance classes that
/// hold a loop, `trans` when some loop joins two chromosomes, then `all`.
///
/// # Examples
///
/// Two true loops, one weak; three calls: one near the strong loop, one near the weak loop, one
/// far from both.
///
/// ```
/// use contactmap::score::loops::{score_loops, Loop, LoopScoreParams};
/// let l = |m1: u64, m2: u64, fraction: f64| Loop {
///     chrom1: "chr1".into(), mid1: m1, chrom2: "chr1".into(), mid2: m2, fraction,
/// };
/// let truth = [l(100_000, 400_000, 0.6), l(1_000_000, 1_500_000, 0.05)];
/// let calls = [l(110_000, 390_000, 1.0), l(1_000_000, 1_510_000, 1.0), l(2_000_000, 2_300_000, 1.0)];
/// let params = LoopScoreParams { tolerance_bp: 20_000, min_fraction: 0.2, distance_edges: vec![0] };
/// let rows = score_loops(&truth, &calls, &params)?;
/// let all = rows.last().unwrap();
/// assert_eq!((all.n_truth, all.n_calls, all.n_weak_calls, all.calls_matched), (1, 3, 1, 1));
/// assert_eq!((all.precision, all.recall), (0.5, 1.0));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn score_loops(
    truth: &[Loop],
    calls: &[Loop],
    params: &LoopScoreParams,
) -> Result<Vec<LoopScoreRow>> {
    let edges = &params.distance_edges;
    if edges.first() != Some(&0) || edges.windows(2).any(|w| w[0] >= w[1]) {
        return Err(Error::parameter(
            "distance_classes",
            format!("{edges:?}"),
            "class edges must start at 0 and increase",
        ));
    }
    if !(0.0..=1.0).contains(&params.min_fraction) {
        return Err(Error::parameter(
            "min_fraction",
            params.min_fraction,
            "must be in [0, 1]",
        ));
    }
    let (strong, weak): (Vec<Loop>, Vec<Loop>) = truth
        .iter()
        .cloned()
        .partition(|l| l.fraction >= params.min_fraction);
    let matched = max_matching(calls, &strong, params.tolerance_bp);
    let mut truth_matched = vec![false; strong.len()];
    for t in matched.iter().flatten() {
        truth_matched[*t] = true;
    }
    let weak_call: Vec<bool> = calls
        .iter()
        .zip(&matched)
        .map(|(c, m)| m.is_none() && weak.iter().any(|w| w.near(c, params.tolerance_bp)))
        .collect();
    // class of a loop: an index into the edges, or edges.len() for trans
    let class = |l: &Loop| match l.separation() {
        None => edges.len(),
        Some(s) => edges.partition_point(|&e| e <= s) - 1,
    };
    let bp = |x: u64| crate::genome::format_bp(x as f64).replace(' ', "");
    let label = |k: usize| -> String {
        if k == edges.len() {
            "trans".into()
        } else if k + 1 == edges.len() {
            format!("{}+", bp(edges[k]))
        } else {
            format!("{}-{}", bp(edges[k]), bp(edges[k + 1]))
        }
    };
    let row = |class_name: String, in_class: &dyn Fn(&Loop) -> bool| {
        let n_truth = strong.iter().filter(|l| in_class(l)).count();
        let truth_hit = strong
            .iter()
            .zip(&truth_matched)
            .filter(|(l, m)| **m && in_class(l))
            .count();
        let mut n_calls = 0;
        let mut n_weak = 0;
        let mut calls_hit = 0;
        for ((c, m), &w) in calls.iter().zip(&matched).zip(&weak_call) {
            if in_class(c) {
                n_calls += 1;
                n_weak += w as usize;
                calls_hit += m.is_some() as usize;
            }
        }
        let precision = ratio(calls_hit, n_calls - n_weak);
        let recall = ratio(truth_hit, n_truth);
        let f1 = if precision + recall > 0.0 {
            2.0 * precision * recall / (precision + recall)
        } else {
            0.0
        };
        LoopScoreRow {
            class: class_name,
            n_truth,
            n_calls,
            n_weak_calls: n_weak,
            truth_matched: truth_hit,
            calls_matched: calls_hit,
            precision,
            recall,
            f1,
        }
    };
    let mut rows = Vec::new();
    for k in 0..=edges.len() {
        let in_class = |l: &Loop| class(l) == k;
        if strong.iter().any(in_class) || calls.iter().any(in_class) {
            rows.push(row(label(k), &in_class));
        }
    }
    rows.push(row("all".into(), &|_| true));
    Ok(rows)
}

/// The rows of [`score_loops`] as a tab-separated table with a header line.
pub fn loop_score_table(rows: &[LoopScoreRow], tolerance_bp: u64, min_fraction: f64) -> String {
    let mut text = String::from(
        "class\ttolerance_bp\tmin_fraction\tn_truth\tn_calls\tn_weak_calls\ttruth_matched\t\
         calls_matched\tprecision\trecall\tf1\n",
    );
    for r in rows {
        writeln!(
            text,
            "{}\t{tolerance_bp}\t{min_fraction}\t{}\t{}\t{}\t{}\t{}\t{:.6}\t{:.6}\t{:.6}",
            r.class,
            r.n_truth,
            r.n_calls,
            r.n_weak_calls,
            r.truth_matched,
            r.calls_matched,
            r.precision,
            r.recall,
            r.f1
        )
        .expect("writing to a string");
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn at(m1: u64, m2: u64) -> Loop {
        Loop {
            chrom1: "chr1".into(),
            mid1: m1,
            chrom2: "chr1".into(),
            mid2: m2,
            fraction: 1.0,
        }
    }

    /// The largest matching by trying every assignment (small inputs only).
    fn brute_force(calls: &[Loop], truth: &[Loop], tolerance: u64, used: &mut Vec<bool>) -> usize {
        let Some((first, rest)) = calls.split_first() else {
            return 0;
        };
        let mut best = brute_force(rest, truth, tolerance, used);
        for t in 0..truth.len() {
            if !used[t] && truth[t].near(first, tolerance) {
                used[t] = true;
                best = best.max(1 + brute_force(rest, truth, tolerance, used));
                used[t] = false;
            }
        }
        best
    }

    proptest! {
        /// The matching is one-to-one, within the tolerance, and as large as any.
        #[test]
        fn matching_is_maximum(
            calls in prop::collection::vec((0u64..12, 0u64..12), 0..7),
            truth in prop::collection::vec((0u64..12, 0u64..12), 0..7),
            tolerance in 0u64..4,
        ) {
            let calls: Vec<Loop> = calls.into_iter().map(|(a, b)| at(a, b)).collect();
            let truth: Vec<Loop> = truth.into_iter().map(|(a, b)| at(a, b)).collect();
            let matched = max_matching(&calls, &truth, tolerance);
            let mut seen = std::collections::HashSet::new();
            for (c, t) in matched.iter().enumerate() {
                if let Some(t) = t {
                    prop_assert!(seen.insert(*t));
                    prop_assert!(truth[*t].near(&calls[c], tolerance));
                }
            }
            let best = brute_force(&calls, &truth, tolerance, &mut vec![false; truth.len()]);
            prop_assert_eq!(seen.len(), best);
        }
    }

    /// Per class counts: the truth loop's class for recall, the call's for precision; trans
    /// loops in their own row.
    #[test]
    fn classes_and_trans() {
        let truth = [at(0, 50_000), at(0, 500_000), at(0, 5_000_000)];
        let mut trans = at(0, 0);
        trans.chrom2 = "chr2".into();
        let calls = [at(10_000, 60_000), at(0, 600_000), trans];
        let params = LoopScoreParams {
            tolerance_bp: 20_000,
            min_fraction: 0.0,
            distance_edges: vec![0, 100_000, 1_000_000],
        };
        let rows = score_loops(&truth, &calls, &params).unwrap();
        let names: Vec<&str> = rows.iter().map(|r| r.class.as_str()).collect();
        assert_eq!(names, ["0bp-100kb", "100kb-1Mb", "1Mb+", "trans", "all"]);
        let counts: Vec<(usize, usize, usize, usize)> = rows
            .iter()
            .map(|r| (r.n_truth, r.n_calls, r.truth_matched, r.calls_matched))
            .collect();
        assert_eq!(
            counts,
            [
                (1, 1, 1, 1),
                (1, 1, 0, 0),
                (1, 0, 0, 0),
                (0, 1, 0, 0),
                (3, 3, 1, 1)
            ]
        );
        let all = &rows[4];
        assert!((all.f1 - 1.0 / 3.0).abs() < 1e-12);
        let bad = LoopScoreParams {
            distance_edges: vec![10],
            ..params
        };
        assert!(score_loops(&truth, &calls, &bad).is_err());
    }
}
