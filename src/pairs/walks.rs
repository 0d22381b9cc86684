//! Walks reported whole (`--walks-policy all`): every ligation of a read pair with more than two
//! alignments, the part that both reads sequenced counted once (pairtools'
//! `parse_complex_walk`: an intramolecular deduplication that keeps the walk's order).
//!
//! Each side's alignments run from its read's 5' end. The pairs of consecutive alignments of
//! read 1 are compared from its 3' end with those of read 2 (`pairs_overlap`); where they
//! overlap, the overlapping ligations are reported once (`R1&2`). Without an overlap, the two
//! 3'-most alignments are tested for a partial overlap (`partial_overlap`). Then every remaining
//! ligation is reported: read 1's (`R1`), the overlap, read 2's (`R2`), numbered along the walk.
//! Positions are reported at the outer ends and strands as a pair's (`outer`, `pair`).

use super::alignment::Alignment;

/// A pair of a walk: the two alignments and the pair's index and type along the walk
/// (`R1`, `R2`, `R1-2`, `R1&2`).
pub type WalkPair = (Alignment, Alignment, (usize, &'static str));

/// Two alignments at the ends of the reads are one fragment read from both ends (pairtools'
/// `partial_overlap`).
fn partial_overlap(
    algn1: &Alignment,
    algn2: &Alignment,
    max_insert_size: i64,
    dedup_max_mismatch: i64,
) -> bool {
    let (unique1, unique2) = (algn1.is_mapped_unique(), algn2.is_mapped_unique());
    if !unique1 && !unique2 {
        return true;
    }
    if !unique1 || !unique2 {
        return false;
    }
    let mut overlap = algn1.chrom == algn2.chrom && algn1.strand != algn2.strand;
    let (min_algn_size, distance_outer_ends) = if algn1.strand == b'+' {
        (
            (algn1.pos3 - algn1.pos5).max(algn2.pos5 - algn2.pos3),
            algn2.pos5 - algn1.pos5,
        )
    } else {
        (
            (algn1.pos5 - algn1.pos3).max(algn2.pos3 - algn2.pos5),
            algn1.pos5 - algn2.pos5,
        )
    };
    overlap &= distance_outer_ends <= max_insert_size + dedup_max_mismatch;
    overlap &= distance_outer_ends >= min_algn_size - dedup_max_mismatch;
    overlap
}

/// Two consecutive alignments of read 1 are the same ligation as two of read 2 read from the
/// other end (pairtools' `pairs_overlap`).
fn pairs_overlap(left: (&Alignment, &Alignment), right: (&Alignment, &Alignment), r: i64) -> bool {
    let (left5, left3) = left;
    let (right5, right3) = right;
    let side_overlap =
        |a: &Alignment, b: &Alignment| match (a.is_mapped_unique(), b.is_mapped_unique()) {
            (false, false) => true,
            (true, true) => a.chrom == b.chrom && a.strand != b.strand,
            _ => false,
        };
    let same_pair = (left5.pos3 - right3.pos5).abs() <= r && (left3.pos5 - right5.pos3).abs() <= r;
    side_overlap(left5, right3) && side_overlap(left3, right5) && same_pair
}

/// pairtools' `format_pair` with `outer` positions and `pair` orientation: copies of the two
/// alignments, their types reset from mapping alone, an end replaced where asked, and the
/// second (or the first) side flipped as the pair's type says. (pairtools tests for `R1&R2`
/// where it writes `R1&2`, so overlapping pairs are not flipped; kept for identical output.)
fn format_pair(
    algn1: &Alignment,
    algn2: &Alignment,
    index: (usize, &'static str),
    algn1_pos3: Option<i64>,
    algn2_pos3: Option<i64>,
) -> WalkPair {
    let (mut a, mut b) = (algn1.clone(), algn2.clone());
    if let Some(pos3) = algn1_pos3 {
        a.pos3 = pos3;
    }
    if let Some(pos3) = algn2_pos3 {
        b.pos3 = pos3;
    }
    a.kind = a.mapping_kind();
    b.kind = b.mapping_kind();
    match index.1 {
        "R1" => {
            b.flip_orientation();
            b.flip_position();
        }
        "R2" => {
            a.flip_orientation();
            a.flip_position();
        }
        _ => {}
    }
    (a, b, index)
}

/// The pairs of a walk (pairtools' `parse_complex_walk` with its defaults), sorted by index.
pub fn complex_walk(
    algns1: &[Alignment],
    algns2: &[Alignment],
    max_insert_size: i64,
    dedup_max_mismatch: i64,
) -> Vec<WalkPair> {
    let r = dedup_max_mismatch;
    let mut output: Vec<WalkPair> = Vec::new();
    let (n1, n2) = (algns1.len(), algns2.len());
    // Indices from the end: element -k is [n - k].
    let from_end1 = |k: usize| &algns1[n1 - k];
    let from_end2 = |k: usize| &algns2[n2 - k];
    let current_left_pair = 1usize;
    let mut current_right_pair = 1usize;
    let mut remaining_right_pairs = n2 as i64 - 1;
    let remaining_left_pairs = n1 as i64 - 1;
    let mut checked_right_pairs = 0i64;
    let mut is_overlap = false;
    if n1 >= 2 && n2 >= 2 {
        while remaining_left_pairs > checked_right_pairs && remaining_right_pairs > 0 {
            let pair1 = (
                from_end1(current_left_pair + 1),
                from_end1(current_left_pair),
            );
            let pair2 = (
                from_end2(current_right_pair + 1),
                from_end2(current_right_pair),
            );
            is_overlap = pairs_overlap(pair1, pair2, r);
            if is_overlap {
                let mut last_left = current_left_pair;
                let mut last_right = current_right_pair;
                let mut checked = checked_right_pairs;
                while is_overlap && checked > 0 {
                    last_left += 1;
                    last_right -= 1;
                    let pair1 = (from_end1(last_left + 1), from_end1(last_left));
                    let pair2 = (from_end2(last_right + 1), from_end2(last_right));
                    is_overlap &= pairs_overlap(pair1, pair2, r);
                    checked -= 1;
                }
                if is_overlap {
                    current_right_pair += 1;
                    break;
                }
            }
            current_right_pair += 1;
            checked_right_pairs += 1;
            remaining_right_pairs -= 1;
        }
        if !is_overlap {
            current_right_pair = 1;
        }
    }
    let (last_reported_left, last_reported_right);
    if n2 == 0 {
        (last_reported_left, last_reported_right) = (1, 0);
    } else if current_right_pair == 1 {
        let (mut left, mut right) = (1usize, 1usize);
        if partial_overlap(&algns1[n1 - 1], &algns2[n2 - 1], max_insert_size, r) {
            if n1 >= 2 {
                output.push(format_pair(
                    &algns1[n1 - 2],
                    &algns1[n1 - 1],
                    (n1 - 1, "R1"),
                    None,
                    Some(algns2[n2 - 1].pos5),
                ));
                left = 2;
            }
            if n2 >= 2 {
                output.push(format_pair(
                    &algns2[n2 - 1],
                    &algns2[n2 - 2],
                    (n1, "R2"),
                    Some(algns1[n1 - 1].pos5),
                    None,
                ));
                right = 2;
            }
        } else {
            output.push(format_pair(
                &algns1[n1 - 1],
                &algns2[n2 - 1],
                (n1, "R1-2"),
                None,
                None,
            ));
        }
        (last_reported_left, last_reported_right) = (left, right);
    } else {
        (last_reported_left, last_reported_right) = (current_right_pair, current_right_pair);
    }
    for i in 0..n1.saturating_sub(last_reported_left) {
        output.push(format_pair(
            &algns1[i],
            &algns1[i + 1],
            (i + 1, "R1"),
            None,
            None,
        ));
    }
    for i_overlapping in 0..current_right_pair - 1 {
        let idx_left = n1 - current_right_pair + i_overlapping;
        let idx_right = n2 - 1 - i_overlapping;
        output.push(format_pair(
            &algns1[idx_left],
            &algns1[idx_left + 1],
            (idx_left + 1, "R1&2"),
            None,
            Some(algns2[idx_right - 1].pos5),
        ));
    }
    let n_right = current_right_pair.min(n2.saturating_sub(last_reported_right));
    let shift: i64 = if current_right_pair > 1 { -1 } else { 0 };
    for i in 0..n_right {
        let index = (n1 as i64 + n_right as i64 - i as i64 + shift) as usize;
        output.push(format_pair(
            &algns2[i + 1],
            &algns2[i],
            (index, "R2"),
            None,
            None,
        ));
    }
    // Stable, as Python's sort.
    output.sort_by_key(|pair| pair.2.0);
    output
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unique(chrom: usize, pos5: i64, pos3: i64, strand: u8) -> Alignment {
        Alignment {
            chrom: Some(chrom),
            pos5,
            pos3,
            pos: pos5,
            strand,
            mapq: 60,
            is_mapped: true,
            is_unique: true,
            kind: b'U',
            ..Alignment::empty()
        }
    }

    #[test]
    fn a_two_fragment_read_pair_is_one_pair_at_the_outer_ends() {
        // Read 1: A+ then B+; read 2: one alignment on B, pointing back to read 1's B part.
        let a = unique(0, 100, 149, b'+');
        let b1 = unique(1, 5000, 5049, b'+');
        let b2 = unique(1, 5300, 5251, b'-');
        let pairs = complex_walk(&[a.clone(), b1], &[b2], 750, 3);
        // The ends overlap partially (one fragment read from both ends): one pair R1, the 3'
        // side's position moved to read 2's 5' end and flipped.
        assert_eq!(pairs.len(), 1);
        let (p, q, index) = &pairs[0];
        assert_eq!(*index, (1, "R1"));
        assert_eq!((p.pos5, p.strand), (100, b'+'));
        assert_eq!((q.pos5, q.strand), (5300, b'-'));
    }

    #[test]
    fn three_fragments_without_overlap_give_three_pairs_in_walk_order() {
        let a = unique(0, 100, 149, b'+');
        let b = unique(1, 5000, 5049, b'+');
        let c = unique(2, 9000, 8951, b'-');
        let d = unique(2, 20000, 19951, b'-');
        // Read 1: a, b; read 2: c, d (d's fragment is far from b's: no overlap).
        let pairs = complex_walk(&[a, b], &[c, d], 750, 3);
        let indices: Vec<(usize, &str)> = pairs.iter().map(|p| p.2).collect();
        assert_eq!(indices, [(1, "R1"), (2, "R1-2"), (3, "R2")]);
    }
}
