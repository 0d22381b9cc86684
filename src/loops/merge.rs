//! Loop calls at 5, 10 and 25 kb merged into one list as Juicer's HiCCUPS merges its
//! resolutions (`HiCCUPSUtils.mergeAllResolutions`, Rao et al. 2014):
//!
//! 1. with 5 kb and 10 kb lists: the 5 kb calls that have a 10 kb call within 20 kb (confirmed),
//!    the 10 kb calls that have no 5 kb call within 20 kb (found only at 10 kb), and the 5 kb calls
//!    near the diagonal (the two anchors' starts less than 110 kb apart) or strong (count above
//!    100), whether confirmed or not; with only one of the two, all of its calls;
//! 2. with a 25 kb list: the 25 kb calls that have no call of step 1 within 50 kb (all of them
//!    when there was no 5 or 10 kb list).
//!
//! Distances are Euclidean between the calls' `(start1, start2)` in bp (Juicer compares the
//! upper-left corners of the pixels, not their centres), between calls on the same pair of
//! chromosomes. A call kept by several rules is kept once.
//!
//! Juicer defines the rule for these three resolutions only (it drops a list at any other
//! resolution when one of them is there, and merges lists without a rule when none is):
//! [`merge_resolutions`] refuses other resolutions rather than drop or pass them silently.

use std::collections::BTreeSet;

use super::calls::Dot;
use crate::error::{Error, Result};
use crate::genome::BinTable;

/// One call of a list at one resolution: what the merge rule looks at.
#[derive(Clone, Debug, PartialEq)]
pub struct ResolutionCall {
    /// First anchor's chromosome.
    pub chrom1: String,
    /// First anchor's start (bp).
    pub start1: u64,
    /// Second anchor's chromosome.
    pub chrom2: String,
    /// Second anchor's start (bp).
    pub start2: u64,
    /// The call's raw count (cooltools' `count`, HiCCUPS' `observed`).
    pub count: f64,
}

impl ResolutionCall {
    /// The calls of `dots` (their representative pixels) on `bins`.
    pub fn of_dots(dots: &[Dot], bins: &BinTable) -> Vec<ResolutionCall> {
        dots.iter()
            .map(|dot| {
                let (b1, b2) = (bins.bin(dot.pixel.bin1), bins.bin(dot.pixel.bin2));
                ResolutionCall {
                    chrom1: bins.chroms()[b1.chrom_id].name.clone(),
                    start1: b1.start,
                    chrom2: bins.chroms()[b2.chrom_id].name.clone(),
                    start2: b2.start,
                    count: dot.pixel.count as f64,
                }
            })
            .collect()
    }
}

/// The merge's thresholds; the defaults are Juicer's.
#[derive(Clone, Debug, PartialEq)]
pub struct MergeParams {
    /// 5 kb calls whose anchors' starts are closer than this (bp) are kept unconfirmed.
    pub near_diagonal_bp: u64,
    /// 5 kb calls with a count above this are kept unconfirmed.
    pub strong_count: f64,
}

impl Default for MergeParams {
    fn default() -> Self {
        MergeParams {
            near_diagonal_bp: 110_000,
            strong_count: 100.0,
        }
    }
}

/// The resolutions the rule knows (bp).
pub const MERGE_RESOLUTIONS: [u64; 3] = [5_000, 10_000, 25_000];

/// Which calls of `lists` (each a resolution in bp and its calls) the merged list keeps, as
/// `(list, call)` indices in list order, then call order. The resolutions must be distinct and
/// among 5, 10 and 25 kb.
///
/// # Examples
///
/// ```
/// use contactmap::loops::merge::{merge_resolutions, MergeParams, ResolutionCall};
///
/// let call = |start1: u64, start2: u64, count: f64| ResolutionCall {
///     chrom1: "chr1".into(), start1, chrom2: "chr1".into(), start2, count,
/// };
/// let five = [call(1_000_000, 1_500_000, 40.0), call(3_000_000, 3_600_000, 30.0)];
/// let ten = [call(1_010_000, 1_500_000, 90.0), call(5_000_000, 5_400_000, 80.0)];
/// let kept = merge_resolutions(&[(5_000, &five[..]), (10_000, &ten[..])], &MergeParams::default())?;
/// // the confirmed 5 kb call, and the 10 kb call found only at 10 kb
/// assert_eq!(kept, [(0, 0), (1, 1)]);
/// # Ok::<(), contactmap::error::Error>(())
/// ```
pub fn merge_resolutions(
    lists: &[(u64, &[ResolutionCall])],
    params: &MergeParams,
) -> Result<Vec<(usize, usize)>> {
    let resolutions: Vec<u64> = lists.iter().map(|&(r, _)| r).collect();
    check_resolutions(&resolutions)?;
    let mut at = [None; 3];
    for (index, resolution) in resolutions.iter().enumerate() {
        if let Some(slot) = MERGE_RESOLUTIONS.iter().position(|r| r == resolution) {
            at[slot] = Some(index);
        }
    }
    let calls = |slot: usize| at[slot].map(|index: usize| (index, lists[index].1));
    let mut kept = BTreeSet::new();
    match (calls(0), calls(1)) {
        (Some((i5, five)), Some((i10, ten))) => {
            for (k, call) in five.iter().enumerate() {
                let confirmed = any_within(call, ten, 20_000.0);
                let near_diagonal = call.start1.abs_diff(call.start2) < params.near_diagonal_bp;
                if confirmed || near_diagonal || call.count > params.strong_count {
                    kept.insert((i5, k));
                }
            }
            for (k, call) in ten.iter().enumerate() {
                if !any_within(call, five, 20_000.0) {
                    kept.insert((i10, k));
                }
            }
        }
        (Some((index, list)), None) | (None, Some((index, list))) => {
            kept.extend((0..list.len()).map(|k| (index, k)));
        }
        (None, None) => {}
    }
    if let Some((i25, coarse)) = calls(2) {
        let merged: Vec<&ResolutionCall> = kept.iter().map(|&(l, k)| &lists[l].1[k]).collect();
        for (k, call) in coarse.iter().enumerate() {
            if !merged.iter().any(|m| within(call, m, 50_000.0)) {
                kept.insert((i25, k));
            }
        }
    }
    Ok(dedup_locations(lists, kept))
}

/// `kept` (as [`merge_resolutions`] returns it) in the merged list's order: by first chromosome
/// (in order of first appearance in `lists`), `start1`, second chromosome, `start2`, then
/// resolution.
pub fn sort_merged(lists: &[(u64, &[ResolutionCall])], kept: &mut [(usize, usize)]) {
    let mut chroms: Vec<&str> = Vec::new();
    for call in lists.iter().flat_map(|(_, calls)| calls.iter()) {
        if !chroms.contains(&call.chrom1.as_str()) {
            chroms.push(&call.chrom1);
        }
    }
    let order = |name: &str| chroms.iter().position(|&c| c == name);
    kept.sort_by_key(|&(l, k)| {
        let c = &lists[l].1[k];
        (
            order(&c.chrom1),
            c.start1,
            order(&c.chrom2),
            c.start2,
            lists[l].0,
        )
    });
}

/// Why the rule cannot merge a set of lists, with the lists' indices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResolutionProblem {
    /// The list at this index is at a resolution other than 5, 10 or 25 kb.
    Undefined(usize),
    /// The second list is at the first one's resolution.
    Repeated(usize, usize),
}

/// The first reason, in list order, why [`merge_resolutions`] cannot merge lists at
/// `resolutions` (`None` when they are distinct and among 5, 10 and 25 kb): callers word it,
/// with the lists' names when they have them.
///
/// ```
/// use contactmap::loops::merge::{ResolutionProblem, resolution_problem};
/// assert_eq!(resolution_problem(&[5_000, 25_000]), None);
/// assert_eq!(resolution_problem(&[5_000, 7_000]), Some(ResolutionProblem::Undefined(1)));
/// assert_eq!(resolution_problem(&[10_000, 5_000, 10_000]), Some(ResolutionProblem::Repeated(0, 2)));
/// ```
pub fn resolution_problem(resolutions: &[u64]) -> Option<ResolutionProblem> {
    resolutions
        .iter()
        .enumerate()
        .find_map(|(index, resolution)| {
            if !MERGE_RESOLUTIONS.contains(resolution) {
                return Some(ResolutionProblem::Undefined(index));
            }
            let first = resolutions[..index].iter().position(|r| r == resolution)?;
            Some(ResolutionProblem::Repeated(first, index))
        })
}

/// An error unless `resolutions` are distinct and among 5, 10 and 25 kb (what
/// [`merge_resolutions`] accepts).
pub fn check_resolutions(resolutions: &[u64]) -> Result<()> {
    match resolution_problem(resolutions) {
        None => Ok(()),
        Some(ResolutionProblem::Undefined(index)) => Err(Error::Argument(format!(
            "the HiCCUPS merge is defined for 5, 10 and 25 kb calls; got a list at {} bp",
            resolutions[index]
        ))),
        Some(ResolutionProblem::Repeated(_, index)) => Err(Error::Argument(format!(
            "two lists at {} bp: give one list per resolution",
            resolutions[index]
        ))),
    }
}

/// Whether `a` and `b` lie on the same chromosome pair within `radius` bp.
fn within(a: &ResolutionCall, b: &ResolutionCall, radius: f64) -> bool {
    let d1 = a.start1 as f64 - b.start1 as f64;
    let d2 = a.start2 as f64 - b.start2 as f64;
    a.chrom1 == b.chrom1 && a.chrom2 == b.chrom2 && d1.hypot(d2) <= radius
}

fn any_within(call: &ResolutionCall, others: &[ResolutionCall], radius: f64) -> bool {
    others.iter().any(|other| within(call, other, radius))
}

/// `kept` in order, a call at the same resolution and place as an earlier one left out (Juicer
/// removes duplicate features).
fn dedup_locations(
    lists: &[(u64, &[ResolutionCall])],
    kept: BTreeSet<(usize, usize)>,
) -> Vec<(usize, usize)> {
    let mut seen = BTreeSet::new();
    kept.into_iter()
        .filter(|&(l, k)| {
            let c = &lists[l].1[k];
            seen.insert((l, c.chrom1.clone(), c.start1, c.chrom2.clone(), c.start2))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn call(start1: u64, start2: u64, count: f64) -> ResolutionCall {
        ResolutionCall {
            chrom1: "chr1".into(),
            start1,
            chrom2: "chr1".into(),
            start2,
            count,
        }
    }

    /// The rule written out as the issue states it, call by call, on lists of one chromosome.
    fn naive(
        five: &[ResolutionCall],
        ten: &[ResolutionCall],
        coarse: &[ResolutionCall],
    ) -> Vec<(usize, usize)> {
        let dist = |a: &ResolutionCall, b: &ResolutionCall| {
            ((a.start1 as f64 - b.start1 as f64).powi(2)
                + (a.start2 as f64 - b.start2 as f64).powi(2))
            .sqrt()
        };
        let mut out = Vec::new();
        let mut merged = Vec::new();
        for (k, c) in five.iter().enumerate() {
            let confirmed = ten.iter().any(|t| dist(c, t) <= 20_000.0);
            let near = (c.start2 as i64 - c.start1 as i64).abs() < 110_000;
            if confirmed || near || c.count > 100.0 {
                out.push((0, k));
                merged.push(c.clone());
            }
        }
        for (k, t) in ten.iter().enumerate() {
            if five.iter().all(|c| dist(c, t) > 20_000.0) {
                out.push((1, k));
                merged.push(t.clone());
            }
        }
        for (k, c) in coarse.iter().enumerate() {
            if merged.iter().all(|m| dist(c, m) > 50_000.0) {
                out.push((2, k));
            }
        }
        out
    }

    fn calls(step: u64) -> impl Strategy<Value = Vec<ResolutionCall>> {
        prop::collection::vec((0u64..40, 1u64..30, 0u32..200), 0..12).prop_map(move |v| {
            let mut seen = BTreeSet::new();
            v.into_iter()
                .filter(|&(a, d, _)| seen.insert((a, d)))
                .map(|(a, d, c)| call(a * step, (a + d) * step, c as f64))
                .collect()
        })
    }

    proptest! {
        #[test]
        fn merge_is_the_rule_call_by_call(
            five in calls(5_000), ten in calls(10_000), coarse in calls(25_000)
        ) {
            let got = merge_resolutions(
                &[(5_000, &five[..]), (10_000, &ten[..]), (25_000, &coarse[..])],
                &MergeParams::default(),
            ).unwrap();
            prop_assert_eq!(got, naive(&five, &ten, &coarse));
        }
    }

    #[test]
    fn juicer_edges_and_single_lists() {
        let p = MergeParams::default();
        // exactly 20 kb apart is confirmed (<=); 110 kb from the diagonal is not near (<)
        let five = [
            call(0, 200_000, 5.0),
            call(500_000, 610_000, 5.0),
            call(900_000, 1_009_000, 5.0),
        ];
        let ten = [call(20_000, 200_000, 5.0)];
        let kept = merge_resolutions(&[(10_000, &ten[..]), (5_000, &five[..])], &p).unwrap();
        assert_eq!(kept, [(1, 0), (1, 2)]);
        // a 25 kb call 50 kb from a kept call is dropped; any other chromosome pair is far
        let coarse = [call(70_000, 200_000, 1.0), call(70_001, 200_000, 1.0)];
        let mut other = call(0, 200_000, 1.0);
        other.chrom2 = "chr2".into();
        let coarse_other = [coarse[0].clone(), coarse[1].clone(), other];
        let kept =
            merge_resolutions(&[(10_000, &ten[..]), (25_000, &coarse_other[..])], &p).unwrap();
        assert_eq!(kept, [(0, 0), (1, 1), (1, 2)]);
        // only 25 kb: all of it
        let kept = merge_resolutions(&[(25_000, &coarse[..])], &p).unwrap();
        assert_eq!(kept, [(0, 0), (0, 1)]);
        // resolutions the rule does not know, twice the same
        assert!(merge_resolutions(&[(20_000, &ten[..])], &p).is_err());
        assert!(merge_resolutions(&[(5_000, &five[..]), (5_000, &five[..])], &p).is_err());
    }
}
