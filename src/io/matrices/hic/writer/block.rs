//! One block of a `.hic` matrix: its number in the grid and its encoding (version 9).
//!
//! A block's records are `(x, y, value)` in the matrix's own bins (`x` a bin of the first
//! chromosome, `y` of the second; `x <= y` on intra-chromosomal matrices, the triangle Juicer
//! stores). They are sorted by `(y, x)` and duplicates (pixels of a finer resolution that fall on
//! the same coarse pixel) summed, then written in whichever of the two representations of the
//! specification is smaller: a list of rows, or a dense rectangle (empty cells as `short`
//! `-32768` or `float` NaN, as readers expect). Values are `short` when every value is a whole
//! number in `-32767..=32767`, else `float`; positions are `short` unless a row offset, a column
//! offset or a count needs an `int`. The raw block is then zlib-compressed.

use std::io::Write;

use flate2::Compression;
use flate2::write::ZlibEncoder;

/// One record of a block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Record {
    pub(super) x: u32,
    pub(super) y: u32,
    pub(super) value: f64,
}

/// `(column, number)` of the block holding record `(x, y)` (version 9): intra-chromosomal
/// matrices number their blocks by position along the diagonal and by a depth that doubles away
/// from it, inter-chromosomal ones on a square grid. The column (position along the diagonal,
/// or `x / size`) tells when the block is complete: every record of column `k` has
/// `x < (k + 1) * size`.
pub(super) fn block_coordinates(
    intra: bool,
    x: u64,
    y: u64,
    size: u64,
    columns: u64,
) -> (u64, u64) {
    if intra {
        let along = (x + y) / 2 / size;
        (along, depth(x.abs_diff(y), size) * columns + along)
    } else {
        let column = x / size;
        (column, (y / size) * columns + column)
    }
}

/// Depth of an intra-chromosomal block holding records `distance` bins off the diagonal:
/// `floor(log2(1 + distance / sqrt(2) / size))`.
pub(super) fn depth(distance: u64, size: u64) -> u64 {
    (1.0 + distance as f64 / std::f64::consts::SQRT_2 / size as f64).log2() as u64
}

/// Sort `records` by `(y, x)`, sum duplicates, and return the number of distinct records.
///
/// Records arrive with `x` non-decreasing (rows of the input in order), so a stable counting
/// sort on `y` alone gives `(y, x)` order; it is used when the block's rows are not much more
/// numerous than its records, a comparison sort otherwise.
pub(super) fn sort_and_sum(records: &mut Vec<Record>) -> usize {
    let x_sorted = records.windows(2).all(|w| w[0].x <= w[1].x);
    let (y0, y1) = records
        .iter()
        .fold((u32::MAX, 0), |(lo, hi), r| (lo.min(r.y), hi.max(r.y)));
    let n_rows = if records.is_empty() {
        0
    } else {
        (y1 - y0) as usize + 1
    };
    if x_sorted && n_rows <= 4 * records.len() + 64 {
        let mut starts = vec![0usize; n_rows + 1];
        for r in records.iter() {
            starts[(r.y - y0) as usize + 1] += 1;
        }
        for k in 1..starts.len() {
            starts[k] += starts[k - 1];
        }
        let mut sorted = vec![
            Record {
                x: 0,
                y: 0,
                value: 0.0
            };
            records.len()
        ];
        for r in records.iter() {
            let slot = &mut starts[(r.y - y0) as usize];
            sorted[*slot] = *r;
            *slot += 1;
        }
        *records = sorted;
    } else {
        records.sort_unstable_by_key(|r| ((r.y as u64) << 32) | r.x as u64);
    }
    let mut kept = 0usize;
    for k in 0..records.len() {
        if kept > 0 && records[kept - 1].x == records[k].x && records[kept - 1].y == records[k].y {
            records[kept - 1].value += records[k].value;
        } else {
            records[kept] = records[k];
            kept += 1;
        }
    }
    records.truncate(kept);
    kept
}

/// Little-endian appends.
fn put_i16(out: &mut Vec<u8>, v: i16) {
    out.extend_from_slice(&v.to_le_bytes());
}
fn put_i32(out: &mut Vec<u8>, v: i32) {
    out.extend_from_slice(&v.to_le_bytes());
}
fn put_f32(out: &mut Vec<u8>, v: f32) {
    out.extend_from_slice(&v.to_le_bytes());
}
fn put_position(out: &mut Vec<u8>, wide: bool, v: u32) {
    if wide {
        put_i32(out, v as i32);
    } else {
        put_i16(out, v as i16);
    }
}

/// The raw (uncompressed) block of `records`, sorted by `(y, x)` without duplicates.
pub(super) fn encode_raw(records: &[Record]) -> Vec<u8> {
    let x0 = records.iter().map(|r| r.x).min().unwrap_or(0);
    let x_max = records.iter().map(|r| r.x).max().unwrap_or(0);
    let y0 = records.first().map_or(0, |r| r.y);
    let y_max = records.last().map_or(0, |r| r.y);
    let short_values = records
        .iter()
        .all(|r| r.value.fract() == 0.0 && r.value.abs() <= i16::MAX as f64);
    // rows and the longest row
    let mut n_rows = 0u64;
    let mut longest = 0u64;
    let mut run = 0u64;
    for (k, r) in records.iter().enumerate() {
        if k == 0 || records[k - 1].y != r.y {
            n_rows += 1;
            run = 0;
        }
        run += 1;
        longest = longest.max(run);
    }
    let short_limit = i16::MAX as u64;
    let wide_x = (x_max - x0) as u64 > short_limit || longest > short_limit;
    let wide_y = (y_max - y0) as u64 > short_limit || n_rows > short_limit;
    let value_bytes: u64 = if short_values { 2 } else { 4 };
    let (px, py) = (if wide_x { 4u64 } else { 2 }, if wide_y { 4u64 } else { 2 });
    let n = records.len() as u64;
    let list_bytes = py + n_rows * (py + px) + n * (px + value_bytes);
    let width = (x_max - x0) as u64 + 1;
    let height = (y_max - y0) as u64 + 1;
    let dense_bytes = 6 + width.saturating_mul(height).saturating_mul(value_bytes);
    let dense = dense_bytes < list_bytes && width <= short_limit;

    let mut out = Vec::with_capacity(15 + list_bytes.min(dense_bytes) as usize);
    put_i32(&mut out, records.len() as i32);
    put_i32(&mut out, x0 as i32);
    put_i32(&mut out, y0 as i32);
    out.push(u8::from(!short_values));
    out.push(u8::from(wide_x));
    out.push(u8::from(wide_y));
    out.push(if dense { 2 } else { 1 });
    if dense {
        let cells = (width * height) as usize;
        put_i32(&mut out, cells as i32);
        put_i16(&mut out, width as i16);
        let mut next = records.iter().peekable();
        for cell in 0..cells {
            let (x, y) = (
                x0 + (cell as u64 % width) as u32,
                y0 + (cell as u64 / width) as u32,
            );
            let value = match next.peek() {
                Some(r) if r.x == x && r.y == y => next.next().map(|r| r.value),
                _ => None,
            };
            match (value, short_values) {
                (Some(v), true) => put_i16(&mut out, v as i16),
                (None, true) => put_i16(&mut out, i16::MIN),
                (Some(v), false) => put_f32(&mut out, v as f32),
                (None, false) => put_f32(&mut out, f32::NAN),
            }
        }
    } else {
        put_position(&mut out, wide_y, n_rows as u32);
        let mut k = 0;
        while k < records.len() {
            let y = records[k].y;
            let end = k + records[k..].iter().take_while(|r| r.y == y).count();
            put_position(&mut out, wide_y, y - y0);
            put_position(&mut out, wide_x, (end - k) as u32);
            for r in &records[k..end] {
                put_position(&mut out, wide_x, r.x - x0);
                if short_values {
                    put_i16(&mut out, r.value as i16);
                } else {
                    put_f32(&mut out, r.value as f32);
                }
            }
            k = end;
        }
    }
    out
}

/// Sort, sum, encode and compress one block.
pub(super) fn compress_block(records: &mut Vec<Record>, level: u32) -> Vec<u8> {
    sort_and_sum(records);
    let raw = encode_raw(records);
    let mut encoder = ZlibEncoder::new(
        Vec::with_capacity(raw.len() / 3 + 64),
        Compression::new(level),
    );
    encoder
        .write_all(&raw)
        .expect("writing to memory cannot fail");
    encoder.finish().expect("writing to memory cannot fail")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(x: u32, y: u32, value: f64) -> Record {
        Record { x, y, value }
    }

    #[test]
    fn counting_and_comparison_sorts_agree_with_a_naive_sort() {
        let mut state = 7u64;
        let mut next = move |m: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % m
        };
        for case in 0..200 {
            let n = next(60) as usize;
            let spread = if case % 2 == 0 { 8 } else { 100_000 };
            let mut records: Vec<Record> = (0..n)
                .map(|_| rec(next(6) as u32, next(spread) as u32, next(5) as f64))
                .collect();
            if case % 3 != 0 {
                records.sort_by_key(|r| r.x); // as the writer receives them
            }
            let mut naive: std::collections::BTreeMap<(u32, u32), f64> = Default::default();
            for r in &records {
                *naive.entry((r.y, r.x)).or_default() += r.value;
            }
            sort_and_sum(&mut records);
            let got: Vec<((u32, u32), f64)> =
                records.iter().map(|r| ((r.y, r.x), r.value)).collect();
            let want: Vec<((u32, u32), f64)> = naive.into_iter().collect();
            assert_eq!(got, want, "case {case}");
        }
    }

    #[test]
    fn duplicates_are_summed_in_row_order() {
        let mut records = vec![
            rec(3, 5, 1.0),
            rec(1, 2, 2.0),
            rec(3, 5, 4.0),
            rec(0, 5, 1.5),
        ];
        assert_eq!(sort_and_sum(&mut records), 3);
        assert_eq!(
            records,
            vec![rec(1, 2, 2.0), rec(0, 5, 1.5), rec(3, 5, 5.0)]
        );
    }

    #[test]
    fn numbering_follows_the_specification() {
        // inter: row-major grid of 10-bin squares, 4 columns
        assert_eq!(block_coordinates(false, 25, 17, 10, 4), (2, 6));
        // intra: along the diagonal, depth 0 near it
        assert_eq!(block_coordinates(true, 12, 13, 10, 5), (1, 1));
        // |x - y| = 30: log2(1 + 30 / sqrt2 / 10) = 1.63 -> depth 1
        assert_eq!(block_coordinates(true, 0, 30, 10, 5), (1, 6));
    }

    #[test]
    fn representation_and_widths_follow_the_values() {
        // integer counts in a compact square: dense with shorts
        let dense: Vec<Record> = (0..4)
            .flat_map(|y| (0..4).map(move |x| rec(x, y, (x + y) as f64)))
            .collect();
        let raw = encode_raw(&dense);
        assert_eq!(&raw[12..16], &[0, 0, 0, 2]);
        // two far-apart records: list of rows; a float value
        let sparse = vec![rec(0, 0, 1.0), rec(40_000, 50_000, 2.5)];
        let raw = encode_raw(&sparse);
        assert_eq!(&raw[12..16], &[1, 1, 1, 1]);
    }
}
