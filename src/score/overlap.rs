//! Two contact predictions compared with each other, without a structure: how much their top
//! lists agree.
//!
//! Each prediction is prepared as for scoring ([`crate::score::contacts::rank_pairs`]:
//! pairs made `i < j`, self pairs and NaN scores dropped, duplicates keeping their highest
//! score), restricted to a separation range and sorted by score, descending and stably. The top
//! `k` pairs of each are compared as sets: the overlap is their intersection, and the Jaccard
//! index is `|A ∩ B| / |A ∪ B|` (0 when both lists are empty). A list shorter than `k` (fewer
//! pairs in the range) is compared as it is.

use std::collections::HashSet;

use super::contacts::{ListSize, Prediction, Rounding, SeparationRange, rank_pairs};
use super::lists::{LabelledSize, NamedRange};
use crate::error::{Error, Result};
use crate::io::tables::real_text;

/// The agreement of two top lists.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overlap {
    /// The requested list size.
    pub k: usize,
    /// Pairs in the first list (`min(k, available)`).
    pub n_first: usize,
    /// Pairs in the second list.
    pub n_second: usize,
    /// Pairs in both.
    pub shared: usize,
    /// `shared / (n_first + n_second - shared)`.
    pub jaccard: f64,
}

/// The pairs `(i, j)`, `i < j`, of `prediction` in `range`, best first (see the module docs).
pub fn ranked_pairs(prediction: &Prediction, range: SeparationRange) -> Vec<(i32, i32)> {
    rank_pairs(prediction, range)
        .into_iter()
        .map(|(i, j, _)| (i, j))
        .collect()
}

/// The overlap of the top `k` of two ranked lists ([`ranked_pairs`]).
///
/// # Examples
///
/// Two predictions of the same target: the pairs are normalised (`j < i` swapped, self pairs
/// dropped) and ranked before the top lists are compared.
///
/// ```
/// use contactmap::score::contacts::{Prediction, SeparationRange};
/// use contactmap::score::overlap::{overlap, ranked_pairs};
///
/// let first = Prediction {
///     pairs: vec![(1, 30, 0.9), (2, 40, 0.8), (3, 50, 0.7), (4, 4, 1.0)],
///     sequence: None,
///     length: None,
/// };
/// let second = Prediction {
///     pairs: vec![(40, 2, 0.95), (5, 60, 0.9), (1, 30, 0.1)],
///     sequence: None,
///     length: None,
/// };
/// let a = ranked_pairs(&first, SeparationRange::LONG);
/// let b = ranked_pairs(&second, SeparationRange::LONG);
/// assert_eq!(a, [(1, 30), (2, 40), (3, 50)]);
/// assert_eq!(b, [(2, 40), (5, 60), (1, 30)]);
/// let top2 = overlap(&a, &b, 2);
/// assert_eq!((top2.shared, top2.jaccard), (1, 1.0 / 3.0));
/// let all = overlap(&a, &b, 10);
/// assert_eq!((all.n_first, all.shared, all.jaccard), (3, 2, 0.5));
/// ```
pub fn overlap(first: &[(i32, i32)], second: &[(i32, i32)], k: usize) -> Overlap {
    let first = &first[..k.min(first.len())];
    let second = &second[..k.min(second.len())];
    let set: HashSet<&(i32, i32)> = first.iter().collect();
    let shared = second.iter().filter(|pair| set.contains(pair)).count();
    let union = first.len() + second.len() - shared;
    Overlap {
        k,
        n_first: first.len(),
        n_second: second.len(),
        shared,
        jaccard: if union == 0 {
            0.0
        } else {
            shared as f64 / union as f64
        },
    }
}

/// One result of [`compare_predictions`]: the separation range, the list size as written, the
/// overlap.
pub type OverlapRow<'a> = (&'a NamedRange, &'a str, Overlap);

/// The overlap of the top lists of two predictions `[(name, prediction); 2]` of one target, for
/// every separation range and list size (`k` from `length`, else the length their sequence or
/// matrix implies, rounded by `rounding`), with the length used. Refused, naming both: predictions that carry
/// different sequences or imply different lengths, an unknown L, a list size `NC` (it needs a
/// structure).
///
/// # Examples
///
/// ```
/// use contactmap::score::contacts::{Prediction, Rounding};
/// use contactmap::score::lists::{parse_list_size, parse_range};
/// use contactmap::score::overlap::compare_predictions;
///
/// let a = Prediction { pairs: vec![(1, 10, 0.9), (2, 20, 0.8)], ..Default::default() };
/// let b = Prediction { pairs: vec![(2, 20, 0.7), (3, 30, 0.6)], ..Default::default() };
/// let (ranges, sizes) = ([parse_range("all")?], [parse_list_size("L/10")?]);
/// let (length, rows) =
///     compare_predictions([("a.rr", &a), ("b.rr", &b)], Some(20), &ranges, &sizes, Rounding::Floor)?;
/// let (_, _, result) = &rows[0];
/// assert_eq!((length, result.k, result.shared), (20, 2, 1));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn compare_predictions<'a>(
    predictions: [(&str, &Prediction); 2],
    length: Option<usize>,
    ranges: &'a [NamedRange],
    sizes: &'a [LabelledSize],
    rounding: Rounding,
) -> Result<(usize, Vec<OverlapRow<'a>>)> {
    let [(first_name, first), (second_name, second)] = predictions;
    // What each file says of its target: the length of its sequence, else its matrix size.
    let implied: Vec<Option<usize>> = [first, second]
        .iter()
        .map(|p| p.sequence.as_ref().map(|s| s.chars().count()).or(p.length))
        .collect();
    let different = |what: String| {
        Error::Data(format!(
            "{first_name} and {second_name} {what}: they are not predictions for the same target"
        ))
    };
    if let (Some(a), Some(b)) = (&first.sequence, &second.sequence) {
        if !a.eq_ignore_ascii_case(b) {
            return Err(different(format!(
                "carry different sequences ({} and {} residues)",
                a.len(),
                b.len()
            )));
        }
    }
    if let (Some(a), Some(b)) = (implied[0], implied[1]) {
        if a != b {
            return Err(different(format!("cover {a} and {b} residues")));
        }
    }
    let length = match length {
        Some(length) => length,
        None => implied[0].or(implied[1]).ok_or_else(|| {
            Error::Argument("L is unknown: give the target sequence (--fasta) or --length".into())
        })?,
    };
    let mut results = Vec::new();
    for named in ranges {
        let a = ranked_pairs(first, named.range);
        let b = ranked_pairs(second, named.range);
        for (label, size) in sizes {
            let k = match *size {
                ListSize::Fraction(fraction) => rounding.apply(length as f64 * fraction),
                ListSize::Count(count) => count,
                ListSize::TrueContacts => {
                    return Err(Error::parameter(
                        "sizes",
                        "NC",
                        "list size NC needs a structure (use score contacts)",
                    ));
                }
            };
            results.push((named, label.as_str(), overlap(&a, &b, k)));
        }
    }
    Ok((length, results))
}

/// The rows of [`compare_predictions`] as the TSV of `score overlap --tsv`: `first second range
/// min_sep max_sep list k n_first n_second shared jaccard`.
///
/// ```
/// use contactmap::score::contacts::{Prediction, Rounding};
/// use contactmap::score::lists::{parse_list_size, parse_range};
/// use contactmap::score::overlap::{compare_predictions, overlap_tsv};
/// let a = Prediction { pairs: vec![(1, 10, 0.9), (2, 20, 0.8)], ..Default::default() };
/// let (ranges, sizes) = ([parse_range("all")?], [parse_list_size("L/10")?]);
/// let (_, rows) = compare_predictions([("a", &a), ("a", &a)], Some(20), &ranges, &sizes, Rounding::Floor)?;
/// assert_eq!(overlap_tsv("a", "a", &rows).lines().nth(1), Some("a\ta\tall\t6\tinf\tL/10\t2\t2\t2\t2\t1"));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn overlap_tsv(first: &str, second: &str, results: &[OverlapRow<'_>]) -> String {
    let mut text = String::from(
        "first\tsecond\trange\tmin_sep\tmax_sep\tlist\tk\tn_first\tn_second\tshared\tjaccard\n",
    );
    for (named, label, result) in results {
        text.push_str(&format!(
            "{}\t{}\t{}\t{}\t{}\t{label}\t{}\t{}\t{}\t{}\t{}\n",
            first,
            second,
            named.name,
            named.range.min,
            named.range.max_text(),
            result.k,
            result.n_first,
            result.n_second,
            result.shared,
            real_text(result.jaccard),
        ));
    }
    text
}

/// The rows of [`compare_predictions`] as the aligned table `score overlap` prints: the two files
/// (A, B), L, then one row per range x list size.
///
/// ```
/// use contactmap::score::contacts::{Prediction, Rounding};
/// use contactmap::score::lists::{parse_list_size, parse_range};
/// use contactmap::score::overlap::{compare_predictions, overlap_text};
/// let a = Prediction { pairs: vec![(1, 10, 0.9), (2, 20, 0.8)], ..Default::default() };
/// let (ranges, sizes) = ([parse_range("all")?], [parse_list_size("L/10")?]);
/// let (length, rows) =
///     compare_predictions([("a", &a), ("a", &a)], Some(20), &ranges, &sizes, Rounding::Floor)?;
/// let text = overlap_text("a", "a", length, &rows);
/// assert!(text.ends_with("  all    L/10  2  2  2       2   1.0000\n"), "{text}");
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn overlap_text(
    first: &str,
    second: &str,
    length: usize,
    results: &[OverlapRow<'_>],
) -> String {
    let mut rows = vec![
        ["range", "list", "k", "A", "B", "shared", "Jaccard"]
            .map(String::from)
            .to_vec(),
    ];
    for (named, label, result) in results {
        rows.push(vec![
            named.name.clone(),
            label.to_string(),
            result.k.to_string(),
            result.n_first.to_string(),
            result.n_second.to_string(),
            result.shared.to_string(),
            format!("{:.4}", result.jaccard),
        ]);
    }
    let mut text = format!("A = {}\nB = {}\n  L = {length}\n", first, second);
    for line in crate::io::tables::aligned(&rows).lines() {
        text.push_str("  ");
        text.push_str(line);
        text.push('\n');
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn prediction(pairs: &[(i32, i32, f64)]) -> Prediction {
        Prediction {
            pairs: pairs.to_vec(),
            sequence: None,
            length: None,
        }
    }

    #[test]
    fn small_example() {
        let a = prediction(&[(1, 30, 0.9), (2, 40, 0.8), (3, 50, 0.7), (1, 5, 1.0)]);
        let b = prediction(&[(40, 2, 0.95), (1, 30, 0.5), (4, 60, 0.6), (3, 50, 0.1)]);
        let (a, b) = (
            ranked_pairs(&a, SeparationRange::LONG),
            ranked_pairs(&b, SeparationRange::LONG),
        );
        assert_eq!(a, [(1, 30), (2, 40), (3, 50)]);
        assert_eq!(b, [(2, 40), (4, 60), (1, 30), (3, 50)]);
        let top2 = overlap(&a, &b, 2);
        assert_eq!((top2.shared, top2.n_first, top2.n_second), (1, 2, 2));
        assert!((top2.jaccard - 1.0 / 3.0).abs() < 1e-15);
        let top4 = overlap(&a, &b, 4);
        assert_eq!((top4.shared, top4.n_first, top4.n_second), (3, 3, 4));
        assert!((top4.jaccard - 0.75).abs() < 1e-15);
        assert_eq!(overlap(&[], &[], 5).jaccard, 0.0);
    }

    proptest! {
        /// Against a naive set computation; a list against itself has Jaccard 1.
        #[test]
        fn jaccard_against_naive(
            a in proptest::collection::vec((1i32..40, 1i32..40, 0.0f64..1.0), 0..80),
            b in proptest::collection::vec((1i32..40, 1i32..40, 0.0f64..1.0), 0..80),
            k in 0usize..60,
        ) {
            let range = SeparationRange::new(3, None);
            let (ra, rb) = (ranked_pairs(&prediction(&a), range), ranked_pairs(&prediction(&b), range));
            let found = overlap(&ra, &rb, k);
            let sa: std::collections::BTreeSet<_> = ra.iter().take(k).collect();
            let sb: std::collections::BTreeSet<_> = rb.iter().take(k).collect();
            let shared = sa.intersection(&sb).count();
            let union = sa.union(&sb).count();
            prop_assert_eq!(found.shared, shared);
            let naive = if union == 0 { 0.0 } else { shared as f64 / union as f64 };
            prop_assert!((found.jaccard - naive).abs() < 1e-15);
            let own = overlap(&ra, &ra, k);
            prop_assert!(own.jaccard == 1.0 || own.n_first == 0);
        }
    }
}
