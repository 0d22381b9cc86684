//! Boundary and domain calls scored against a truth.
//!
//! Boundaries are points `(chrom, position_bp)`; [`boundary_position`] turns a BED record into
//! its midpoint `start + (end - start) / 2` (its start when zero-length). A call and a truth boundary on the same
//! chromosome match when `|call - truth| <= tolerance_bp`; each call matches at most one truth
//! boundary and vice versa, and [`score_boundaries`] finds a maximum such matching by a greedy
//! sweep over sorted positions (optimal in 1D; the proof is at `match_sorted` and a property test
//! checks it against brute-force maximum bipartite matching). Then
//! `precision = TP / n_calls`, `recall = TP / n_truth`, `F1 = 2 TP / (n_calls + n_truth)`; a ratio
//! whose denominator is 0 is reported as 0.
//!
//! Domains are half-open bp intervals `(chrom, start, end)`. [`domain_overlap`] reports, for each
//! truth domain, the best Jaccard index (intersection / union of bp) with any called domain on the
//! same chromosome, averaged over the truth domains (and the same from the calls' side), and the
//! Measure of Concordance of Zufferey et al. 2018 (Genome Biology 19:217, "Comprehensive
//! computational analysis of TAD callers"), after Pfitzner et al. 2009:
//!
//! ```text
//! MoC(P, Q) = ( sum_i sum_j F_ij^2 / (|P_i| |Q_j|) - 1 ) / ( sqrt(N_P N_Q) - 1 )
//! ```
//!
//! with `P_i`, `Q_j` the truth and called domains of a chromosome, `F_ij` the bp they share, and
//! `N_P`, `N_Q` their numbers; when both hold a single domain the sum itself is used (1 for
//! identical domains, as Pfitzner's `MoC = 1` for two single-cluster partitions). MoC is 1 for
//! identical sets and near 0 for unrelated ones; it is computed per chromosome (a chromosome with
//! domains in only one of the sets scores 0) and averaged over the chromosomes that have domains in
//! either set. It is defined for partitions, so it is reported only when the domains of each set
//! do not overlap each other on any chromosome (no nesting); gaps between domains are not filled
//! (Zufferey et al. count inter-TAD gaps as domains: give them explicitly to reproduce that).

use super::fraction::ratio;
use crate::io::bed::BedRecord;
use std::collections::BTreeMap;

/// Result of [`score_boundaries`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryMatch {
    /// Number of truth boundaries.
    pub n_truth: usize,
    /// Number of called boundaries.
    pub n_calls: usize,
    /// Matched pairs.
    pub true_positives: usize,
    /// `true_positives / n_calls` (0 without calls).
    pub precision: f64,
    /// `true_positives / n_truth` (0 without truth).
    pub recall: f64,
    /// Harmonic mean of precision and recall, `2 TP / (n_calls + n_truth)` (0 when both are 0).
    pub f1: f64,
}

/// Result of [`domain_overlap`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DomainOverlap {
    /// Mean over truth domains of the best Jaccard index with a called domain on the same
    /// chromosome (0 without truth domains).
    pub mean_best_jaccard_truth: f64,
    /// Mean over called domains of the best Jaccard index with a truth domain (0 without calls).
    pub mean_best_jaccard_calls: f64,
    /// Measure of Concordance, averaged over chromosomes; `None` when the domains of either set
    /// overlap each other on some chromosome, or when both sets are empty.
    pub moc: Option<f64>,
}

/// Match `calls` to `truth` one-to-one within `tolerance_bp` on the same chromosome and report
/// precision, recall and F1 (see the module docs).
///
/// # Examples
///
/// Each call matches at most one truth boundary: two calls near the same truth count once.
///
/// ```
/// use contactmap::score::boundaries::score_boundaries;
///
/// let at = |chrom: &str, position: u64| (chrom.to_string(), position);
/// let truth = [at("chr1", 100_000), at("chr1", 200_000), at("chr2", 50_000)];
/// let calls = [at("chr1", 95_000), at("chr1", 104_000), at("chr2", 70_000)];
/// let score = score_boundaries(&truth, &calls, 10_000);
/// assert_eq!((score.n_truth, score.n_calls, score.true_positives), (3, 3, 1));
/// assert_eq!((score.precision, score.recall), (1.0 / 3.0, 1.0 / 3.0));
/// // a wider tolerance reaches chr2's truth
/// assert_eq!(score_boundaries(&truth, &calls, 20_000).true_positives, 2);
/// ```
pub fn score_boundaries(
    truth: &[(String, u64)],
    calls: &[(String, u64)],
    tolerance_bp: u64,
) -> BoundaryMatch {
    let mut by_chrom: BTreeMap<&str, (Vec<u64>, Vec<u64>)> = BTreeMap::new();
    for (chrom, position) in truth {
        by_chrom
            .entry(chrom.as_str())
            .or_default()
            .0
            .push(*position);
    }
    for (chrom, position) in calls {
        by_chrom
            .entry(chrom.as_str())
            .or_default()
            .1
            .push(*position);
    }
    let mut true_positives = 0;
    for (mut t, mut c) in by_chrom.into_values() {
        t.sort_unstable();
        c.sort_unstable();
        true_positives += match_sorted(&t, &c, tolerance_bp);
    }
    let (n_truth, n_calls) = (truth.len(), calls.len());
    BoundaryMatch {
        n_truth,
        n_calls,
        true_positives,
        precision: ratio(true_positives, n_calls),
        recall: ratio(true_positives, n_truth),
        f1: ratio(2 * true_positives, n_calls + n_truth),
    }
}

/// Size of a maximum one-to-one matching between sorted `truth` and sorted `calls`, where a pair
/// may match when the positions differ by at most `tolerance`.
///
/// The sweep looks at the first remaining truth `t` and call `c`:
/// - `c < t - tolerance`: `c` cannot match `t` nor any later truth (all `>= t`): drop `c`;
/// - `c > t + tolerance`: `t` cannot match `c` nor any later call: drop `t`;
/// - otherwise match them. This is safe: take a maximum matching `M` of the remaining points. If
///   `M` pairs `t` with `c' >= c` and `c` with `t' >= t`, then `(t, c), (t', c')` is also valid
///   (`c' >= c >= t' - tolerance` and `c' <= t + tolerance <= t' + tolerance`) and as large; if
///   only one of `t`, `c` is matched in `M`, re-pairing it with the other keeps the size; if
///   neither is, `M` was not maximum. So some maximum matching contains `(t, c)`, and by induction
///   the sweep's matching is maximum.
fn match_sorted(truth: &[u64], calls: &[u64], tolerance: u64) -> usize {
    let (mut i, mut j, mut matched) = (0, 0, 0);
    while i < truth.len() && j < calls.len() {
        let (t, c) = (truth[i], calls[j]);
        if c.saturating_add(tolerance) < t {
            j += 1;
        } else if c > t.saturating_add(tolerance) {
            i += 1;
        } else {
            matched += 1;
            i += 1;
            j += 1;
        }
    }
    matched
}

/// Bp shared by two half-open intervals.
fn intersection(a: (u64, u64), b: (u64, u64)) -> u64 {
    a.1.min(b.1).saturating_sub(a.0.max(b.0))
}

/// Jaccard index of two half-open intervals (0 when both are empty).
fn jaccard(a: (u64, u64), b: (u64, u64)) -> f64 {
    let shared = intersection(a, b);
    let union = (a.1 - a.0) + (b.1 - b.0) - shared;
    if union == 0 {
        0.0
    } else {
        shared as f64 / union as f64
    }
}

/// Mean over `from` of the best Jaccard with any interval of `to`.
fn mean_best_jaccard(from: &[(u64, u64)], to: &[(u64, u64)]) -> f64 {
    from.iter()
        .map(|&a| to.iter().map(|&b| jaccard(a, b)).fold(0.0, f64::max))
        .sum()
}

/// Sorted intervals that do not overlap each other.
fn is_partition(sorted: &[(u64, u64)]) -> bool {
    sorted.windows(2).all(|w| w[1].0 >= w[0].1)
}

/// MoC of two non-overlapping interval sets of one chromosome (see the module docs).
fn moc(p: &[(u64, u64)], q: &[(u64, u64)]) -> f64 {
    if p.is_empty() || q.is_empty() {
        return 0.0;
    }
    let mut sum = 0.0;
    for &a in p {
        for &b in q {
            let shared = intersection(a, b);
            if shared > 0 {
                sum += (shared as f64).powi(2) / ((a.1 - a.0) as f64 * (b.1 - b.0) as f64);
            }
        }
    }
    let n = ((p.len() * q.len()) as f64).sqrt();
    if p.len() == 1 && q.len() == 1 {
        sum
    } else {
        (sum - 1.0) / (n - 1.0)
    }
}

/// Best-match Jaccard of domains in both directions and the Measure of Concordance (see the
/// module docs). Intervals are `(chrom, start_bp, end_bp)`, half-open, `start <= end`.
///
/// # Examples
///
/// ```
/// use contactmap::score::boundaries::domain_overlap;
///
/// let domain = |start: u64, end: u64| ("chr1".to_string(), start, end);
/// let truth = [domain(0, 100), domain(100, 200)];
/// let same = domain_overlap(&truth, &truth);
/// assert_eq!((same.mean_best_jaccard_truth, same.moc), (1.0, Some(1.0)));
/// // one call over both domains: each truth domain covers half of it
/// let merged = domain_overlap(&truth, &[domain(0, 200)]);
/// assert_eq!(merged.mean_best_jaccard_truth, 0.5);
/// assert_eq!(merged.mean_best_jaccard_calls, 0.5);
/// // nested calls are not a partition: no MoC
/// assert_eq!(domain_overlap(&truth, &[domain(0, 200), domain(0, 100)]).moc, None);
/// ```
pub fn domain_overlap(truth: &[(String, u64, u64)], calls: &[(String, u64, u64)]) -> DomainOverlap {
    type Sets = (Vec<(u64, u64)>, Vec<(u64, u64)>);
    let mut by_chrom: BTreeMap<&str, Sets> = BTreeMap::new();
    for (chrom, start, end) in truth {
        by_chrom
            .entry(chrom.as_str())
            .or_default()
            .0
            .push((*start, *end));
    }
    for (chrom, start, end) in calls {
        by_chrom
            .entry(chrom.as_str())
            .or_default()
            .1
            .push((*start, *end));
    }
    let (mut sum_truth, mut sum_calls) = (0.0, 0.0);
    let mut mocs = Vec::new();
    let mut partitions = true;
    for (mut p, mut q) in by_chrom.into_values() {
        p.sort_unstable();
        q.sort_unstable();
        sum_truth += mean_best_jaccard(&p, &q);
        sum_calls += mean_best_jaccard(&q, &p);
        partitions &= is_partition(&p) && is_partition(&q);
        mocs.push(moc(&p, &q));
    }
    let mean = |sum: f64, n: usize| if n == 0 { 0.0 } else { sum / n as f64 };
    DomainOverlap {
        mean_best_jaccard_truth: mean(sum_truth, truth.len()),
        mean_best_jaccard_calls: mean(sum_calls, calls.len()),
        moc: (partitions && !mocs.is_empty()).then(|| mocs.iter().sum::<f64>() / mocs.len() as f64),
    }
}

/// The position of a boundary record: its midpoint, or its start when zero-length.
pub fn boundary_position(record: &BedRecord) -> (String, u64) {
    (
        record.chrom.clone(),
        record.start + (record.end - record.start) / 2,
    )
}

/// The median width of `records` (the upper median for an even count), the bin size of calls
/// made one bin wide; `None` without records or for zero-width ones.
pub fn median_width(records: &[BedRecord]) -> Option<u64> {
    let mut widths: Vec<u64> = records.iter().map(BedRecord::width).collect();
    widths.sort_unstable();
    widths.get(widths.len() / 2).copied().filter(|&w| w > 0)
}

/// [`score_boundaries`] of BED records, by their [`boundary_position`]s.
///
/// # Examples
///
/// ```
/// use contactmap::io::bed::BedRecord;
/// use contactmap::score::boundaries::score_boundary_records;
///
/// let truth = [BedRecord::new("chr1", 100, 200), BedRecord::new("chr1", 1_000, 1_100)];
/// let calls = [BedRecord::new("chr1", 200, 300), BedRecord::new("chr2", 100, 200)];
/// let m = score_boundary_records(&truth, &calls, 100);
/// assert_eq!((m.true_positives, m.precision, m.recall), (1, 0.5, 0.5));
/// ```
pub fn score_boundary_records(
    truth: &[BedRecord],
    calls: &[BedRecord],
    tolerance_bp: u64,
) -> BoundaryMatch {
    let truth: Vec<(String, u64)> = truth.iter().map(boundary_position).collect();
    let calls: Vec<(String, u64)> = calls.iter().map(boundary_position).collect();
    score_boundaries(&truth, &calls, tolerance_bp)
}

/// [`domain_overlap`] of BED records.
pub fn domain_overlap_records(truth: &[BedRecord], calls: &[BedRecord]) -> DomainOverlap {
    let intervals = |records: &[BedRecord]| -> Vec<(String, u64, u64)> {
        records
            .iter()
            .map(|r| (r.chrom.clone(), r.start, r.end))
            .collect()
    };
    domain_overlap(&intervals(truth), &intervals(calls))
}

/// The one-row TSV of `score boundaries`: `tolerance_bp n_truth n_calls true_positives
/// precision recall f1`, and with a domain `overlap` `mean_best_jaccard_truth
/// mean_best_jaccard_calls moc` (`nan` when MoC is undefined).
///
/// ```
/// use contactmap::io::bed::BedRecord;
/// use contactmap::score::boundaries::{boundary_table, score_boundary_records};
///
/// let truth = [BedRecord::new("chr1", 100, 200)];
/// let m = score_boundary_records(&truth, &truth, 0);
/// assert_eq!(
///     boundary_table(0, &m, None),
///     "tolerance_bp\tn_truth\tn_calls\ttrue_positives\tprecision\trecall\tf1\n0\t1\t1\t1\t1\t1\t1\n"
/// );
/// ```
pub fn boundary_table(
    tolerance_bp: u64,
    m: &BoundaryMatch,
    overlap: Option<&DomainOverlap>,
) -> String {
    let mut header =
        String::from("tolerance_bp\tn_truth\tn_calls\ttrue_positives\tprecision\trecall\tf1");
    let mut row = format!(
        "{tolerance_bp}\t{}\t{}\t{}\t{}\t{}\t{}",
        m.n_truth, m.n_calls, m.true_positives, m.precision, m.recall, m.f1
    );
    if let Some(overlap) = overlap {
        header.push_str("\tmean_best_jaccard_truth\tmean_best_jaccard_calls\tmoc");
        let moc = overlap
            .moc
            .map_or_else(|| "nan".to_string(), |v| v.to_string());
        row.push_str(&format!(
            "\t{}\t{}\t{moc}",
            overlap.mean_best_jaccard_truth, overlap.mean_best_jaccard_calls
        ));
    }
    format!("{header}\n{row}\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_and_bin_size_inference() {
        let record = |s, e| BedRecord::new("c", s, e);
        assert_eq!(boundary_position(&record(100, 200)).1, 150);
        assert_eq!(boundary_position(&record(100, 100)).1, 100);
        assert_eq!(boundary_position(&record(100, 101)).1, 100);
        let calls = [record(0, 10), record(20, 40), record(50, 60)];
        assert_eq!(median_width(&calls), Some(10));
        assert_eq!(median_width(&[]), None);
        assert_eq!(median_width(&[record(5, 5)]), None);
    }
    use proptest::prelude::*;

    fn points(chrom: &str, positions: &[u64]) -> Vec<(String, u64)> {
        positions.iter().map(|&p| (chrom.to_string(), p)).collect()
    }

    fn intervals(chrom: &str, spans: &[(u64, u64)]) -> Vec<(String, u64, u64)> {
        spans
            .iter()
            .map(|&(s, e)| (chrom.to_string(), s, e))
            .collect()
    }

    /// Maximum bipartite matching by augmenting paths (Kuhn), over all compatible pairs.
    fn brute_force(truth: &[u64], calls: &[u64], tolerance: u64) -> usize {
        fn augment(
            t: usize,
            truth: &[u64],
            calls: &[u64],
            tolerance: u64,
            seen: &mut [bool],
            owner: &mut [Option<usize>],
        ) -> bool {
            for c in 0..calls.len() {
                if truth[t].abs_diff(calls[c]) <= tolerance && !seen[c] {
                    seen[c] = true;
                    let current = owner[c];
                    if current.is_none_or(|o| augment(o, truth, calls, tolerance, seen, owner)) {
                        owner[c] = Some(t);
                        return true;
                    }
                }
            }
            false
        }
        let mut owner = vec![None; calls.len()];
        (0..truth.len())
            .filter(|&t| {
                let mut seen = vec![false; calls.len()];
                augment(t, truth, calls, tolerance, &mut seen, &mut owner)
            })
            .count()
    }

    #[test]
    fn hand_computed_boundary_scores() {
        let truth = points("chr1", &[100, 200, 300, 400]);
        let perfect = score_boundaries(&truth, &truth, 0);
        assert_eq!(perfect.true_positives, 4);
        assert_eq!(
            (perfect.precision, perfect.recall, perfect.f1),
            (1.0, 1.0, 1.0)
        );

        let shifted = points("chr1", &[110, 210, 310, 410]);
        assert_eq!(score_boundaries(&truth, &shifted, 10).f1, 1.0);
        assert_eq!(score_boundaries(&truth, &shifted, 9).f1, 0.0);

        // Half of the truth called, plus one false call: P = 2/3, R = 1/2, F1 = 4/7.
        let calls = points("chr1", &[100, 300, 1000]);
        let half = score_boundaries(&truth, &calls, 0);
        assert_eq!(half.true_positives, 2);
        assert!((half.precision - 2.0 / 3.0).abs() < 1e-12);
        assert_eq!(half.recall, 0.5);
        assert!((half.f1 - 4.0 / 7.0).abs() < 1e-12);

        // One-to-one: two calls near one truth count once.
        let crowded = points("chr1", &[99, 101]);
        let one = score_boundaries(&points("chr1", &[100]), &crowded, 5);
        assert_eq!(
            (one.true_positives, one.precision, one.recall),
            (1, 0.5, 1.0)
        );

        // Chromosomes must agree.
        let other = points("chr2", &[100, 200, 300, 400]);
        assert_eq!(score_boundaries(&truth, &other, 1000).true_positives, 0);

        let empty = score_boundaries(&[], &[], 0);
        assert_eq!((empty.precision, empty.recall, empty.f1), (0.0, 0.0, 0.0));
    }

    #[test]
    fn greedy_beats_a_naive_nearest_choice() {
        // Nearest-first would pair 10 with 12 and leave 14 unmatched: the sweep pairs 10-8.
        let truth = [10, 14];
        let calls = [8, 12];
        assert_eq!(match_sorted(&truth, &calls, 2), 2);
        assert_eq!(brute_force(&truth, &calls, 2), 2);
    }

    proptest! {
        #[test]
        fn sweep_is_a_maximum_matching(
            truth in proptest::collection::vec(0u64..60, 0..12),
            calls in proptest::collection::vec(0u64..60, 0..12),
            tolerance in 0u64..8,
        ) {
            let (mut t, mut c) = (truth.clone(), calls.clone());
            t.sort_unstable();
            c.sort_unstable();
            prop_assert_eq!(match_sorted(&t, &c, tolerance), brute_force(&truth, &calls, tolerance));
        }
    }

    #[test]
    fn hand_computed_domain_scores() {
        let truth = intervals("chr1", &[(0, 100), (100, 200)]);
        let same = domain_overlap(&truth, &truth);
        assert_eq!(same.mean_best_jaccard_truth, 1.0);
        assert_eq!(same.mean_best_jaccard_calls, 1.0);
        assert!((same.moc.unwrap() - 1.0).abs() < 1e-12);

        // One call over both truth domains: Jaccard 1/2 each; from the call's side 1/2.
        // MoC: (100^2 / (100 * 200) * 2 - 1) / (sqrt(2) - 1) = 0.
        let merged = intervals("chr1", &[(0, 200)]);
        let overlap = domain_overlap(&truth, &merged);
        assert!((overlap.mean_best_jaccard_truth - 0.5).abs() < 1e-12);
        assert!((overlap.mean_best_jaccard_calls - 0.5).abs() < 1e-12);
        assert!(overlap.moc.unwrap().abs() < 1e-12);

        // Calls shifted by 50 bp: [0,50) [50,150) [150,200) vs [0,100) [100,200).
        // Sum = 50^2/(100*50) + 50^2/(100*100) + 50^2/(100*100) + 50^2/(100*50) = 1.5;
        // MoC = 0.5 / (sqrt(6) - 1).
        let shifted = intervals("chr1", &[(0, 50), (50, 150), (150, 200)]);
        let o = domain_overlap(&truth, &shifted);
        assert!((o.moc.unwrap() - 0.5 / (6f64.sqrt() - 1.0)).abs() < 1e-12);
        // Truth [0,100): best is [0,50) or [50,150), both Jaccard 1/2; same for [100,200).
        assert!((o.mean_best_jaccard_truth - 0.5).abs() < 1e-12);
        // Calls: [0,50) 1/2, [50,150) 1/3, [150,200) 1/2.
        assert!((o.mean_best_jaccard_calls - (0.5 + 1.0 / 3.0 + 0.5) / 3.0).abs() < 1e-12);

        // Nested (overlapping) domains: no MoC.
        let nested = intervals("chr1", &[(0, 200), (0, 100)]);
        assert_eq!(domain_overlap(&truth, &nested).moc, None);

        // A chromosome in only one set scores 0 MoC there: the mean over 2 chromosomes is 1/2.
        let mut two = truth.clone();
        two.extend(intervals("chr2", &[(0, 100), (100, 200)]));
        let half = domain_overlap(&two, &truth);
        assert!((half.moc.unwrap() - 0.5).abs() < 1e-12);
        assert!((half.mean_best_jaccard_truth - 0.5).abs() < 1e-12);
        assert_eq!(half.mean_best_jaccard_calls, 1.0);

        assert_eq!(domain_overlap(&[], &[]).moc, None);
    }

    proptest! {
        /// Identical partitions have MoC 1 and best Jaccard 1, whatever the cut points.
        #[test]
        fn identical_partitions_are_concordant(cuts in proptest::collection::btree_set(1u64..1000, 1..20)) {
            let mut edges: Vec<u64> = vec![0];
            edges.extend(cuts);
            edges.push(1000);
            let spans: Vec<(u64, u64)> = edges.windows(2).map(|w| (w[0], w[1])).collect();
            let domains = intervals("c", &spans);
            let o = domain_overlap(&domains, &domains);
            prop_assert!((o.moc.unwrap() - 1.0).abs() < 1e-9);
            prop_assert!((o.mean_best_jaccard_truth - 1.0).abs() < 1e-12);
        }
    }
}
