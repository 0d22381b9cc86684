//! The order of a sorted pairs file, as `pairtools sort` makes it: `chrom1` then `chrom2` as
//! bytes (the C locale: `chr10` before `chr2`), then `pos1` and `pos2` as numbers, then
//! `pair_type` as bytes; records equal on all five keep their input order (a stable sort).
//! The header then says `#sorted: chr1-chr2-pos1-pos2`.

use std::cmp::Ordering;

use super::records::{PairColumns, PairRecord, parse_position};

/// The sort key of a record, borrowed from it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SortKey<'a> {
    /// `chrom1`.
    pub chrom1: &'a [u8],
    /// `chrom2`.
    pub chrom2: &'a [u8],
    /// `pos1`.
    pub pos1: u64,
    /// `pos2`.
    pub pos2: u64,
    /// `pair_type` (empty when the file has none).
    pub pair_type: &'a [u8],
}

impl<'a> SortKey<'a> {
    /// The key of `record` (positions that are not integers count as 0, as `sort -n` counts
    /// them; readers check positions before sorting).
    pub fn of(record: &'a PairRecord, columns: &PairColumns) -> SortKey<'a> {
        SortKey {
            chrom1: record.field(columns.chrom1),
            chrom2: record.field(columns.chrom2),
            pos1: parse_position(record.field(columns.pos1)).unwrap_or(0),
            pos2: parse_position(record.field(columns.pos2)).unwrap_or(0),
            pair_type: columns.pair_type.map_or(&[][..], |i| record.field(i)),
        }
    }
}

impl Ord for SortKey<'_> {
    fn cmp(&self, other: &Self) -> Ordering {
        self.chrom1
            .cmp(other.chrom1)
            .then_with(|| self.chrom2.cmp(other.chrom2))
            .then_with(|| self.pos1.cmp(&other.pos1))
            .then_with(|| self.pos2.cmp(&other.pos2))
            .then_with(|| self.pair_type.cmp(other.pair_type))
    }
}

impl PartialOrd for SortKey<'_> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Whether `next` may follow `previous` in a file that says `#sorted: chr1-chr2-pos1-pos2`:
/// the four keys not decreasing (the pair type is not looked at).
pub fn in_sorted_order(previous: &SortKey<'_>, next: &SortKey<'_>) -> bool {
    (
        previous.chrom1,
        previous.chrom2,
        previous.pos1,
        previous.pos2,
    ) <= (next.chrom1, next.chrom2, next.pos1, next.pos2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::pairs::PairsHeader;

    fn columns() -> PairColumns {
        PairColumns::of(&PairsHeader::default(), "t").unwrap()
    }

    #[test]
    fn chromosomes_sort_as_bytes_and_positions_as_numbers() {
        let c = columns();
        let lines: [&[u8]; 5] = [
            b".\tchr2\t5\tchr2\t9\t+\t+\tUU",
            b".\tchr10\t100\tchr2\t1\t+\t+\tUU",
            b".\tchr10\t20\tchr2\t1\t+\t+\tUU",
            b".\t!\t0\tchr1\t3\t-\t+\tNU",
            b".\tchr10\t20\tchr2\t1\t+\t+\tRU",
        ];
        let records: Vec<PairRecord> = lines
            .iter()
            .enumerate()
            .map(|(i, l)| PairRecord::from_line(l, i as u64))
            .collect();
        let mut order: Vec<usize> = (0..records.len()).collect();
        order.sort_by(|&a, &b| SortKey::of(&records[a], &c).cmp(&SortKey::of(&records[b], &c)));
        // '!' < 'chr10' < 'chr2'; 20 < 100 as numbers; RU < UU.
        assert_eq!(order, [3, 4, 2, 1, 0]);
    }

    #[test]
    fn sorted_order_looks_at_chromosomes_and_positions_only() {
        let c = columns();
        let a = PairRecord::from_line(b".\tchr1\t5\tchr2\t9\t+\t+\tUU", 1);
        let b = PairRecord::from_line(b".\tchr1\t5\tchr2\t9\t-\t+\tRU", 2);
        let d = PairRecord::from_line(b".\tchr1\t5\tchr2\t1\t+\t+\tUU", 3);
        assert!(in_sorted_order(&SortKey::of(&a, &c), &SortKey::of(&b, &c)));
        assert!(!in_sorted_order(&SortKey::of(&b, &c), &SortKey::of(&d, &c)));
    }
}
