//! BG2, COO and dense pixel tables.

use std::collections::HashMap;

use super::lines::{Fields, LineReader, first_fields, parse_count, parse_number, parse_u64, show};
use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::matrix::{ContactMatrix, CountType, MatrixBuilder, ZeroCounts};

/// Relative tolerance of the symmetry check of dense matrices.
const DENSE_SYMMETRY_TOLERANCE: f64 = 1e-9;

/// Push a pixel into `builder`, remembering whether every count so far is whole.
fn push_pixel(
    builder: &mut MatrixBuilder,
    all_whole: &mut bool,
    bin1: u64,
    bin2: u64,
    count: f64,
) -> Result<()> {
    if count.fract() != 0.0 {
        *all_whole = false;
    }
    builder.push(bin1, bin2, count)
}

/// Finish a builder with the count type the counts call for, keeping the pixels listed with a
/// count of 0 (`cooler load -f bg2` and `-f coo` store them; a dense matrix pushes none).
fn finish(mut builder: MatrixBuilder, all_whole: bool) -> ContactMatrix {
    builder.set_count_type(if all_whole {
        CountType::Integer
    } else {
        CountType::Float
    });
    builder.build_with(ZeroCounts::Keep)
}

/// Finds the bin of a `(chrom, start, end)` triple, checking that it is exactly a bin.
struct BinLocator<'a> {
    bins: &'a BinTable,
    chrom_ids: HashMap<&'a [u8], usize>,
}

impl<'a> BinLocator<'a> {
    fn new(bins: &'a BinTable) -> Self {
        let chrom_ids = bins
            .chroms()
            .iter()
            .enumerate()
            .map(|(id, chrom)| (chrom.name.as_bytes(), id))
            .collect();
        BinLocator { bins, chrom_ids }
    }

    /// The bin id, or a message saying what was expected.
    fn locate(
        &self,
        chrom: &[u8],
        start: &[u8],
        end: &[u8],
        side: u8,
    ) -> std::result::Result<u64, String> {
        let Some(&chrom_id) = self.chrom_ids.get(chrom) else {
            let names: Vec<&str> = self
                .bins
                .chroms()
                .iter()
                .take(5)
                .map(|c| c.name.as_str())
                .collect();
            let more = if self.bins.n_chroms() > 5 {
                ", ..."
            } else {
                ""
            };
            let hint = self
                .bins
                .naming_hint(&show(chrom))
                .map(|h| format!(": {h}"))
                .unwrap_or_default();
            return Err(format!(
                "unknown chromosome '{}' in chrom{side} (the bin table has {}{more}){hint}",
                show(chrom),
                names.join(", ")
            ));
        };
        let (Some(start_bp), Some(end_bp)) = (parse_u64(start), parse_u64(end)) else {
            return Err(format!(
                "start{side} '{}' and end{side} '{}' must be whole numbers",
                show(start),
                show(end)
            ));
        };
        let chrom = &self.bins.chroms()[chrom_id];
        if start_bp >= chrom.length_bp {
            return Err(format!(
                "start{side} {start_bp} is past the end of {} ({} bp)",
                chrom.name, chrom.length_bp
            ));
        }
        let bin_id = self.bins.bin_at(chrom_id, start_bp);
        let bin = self.bins.bin(bin_id);
        if bin.start != start_bp {
            let rule = match self.bins.resolution() {
                Some(size) => format!(" (bins of {size} bp start at multiples of {size})"),
                None => String::new(),
            };
            return Err(format!(
                "start{side} {start_bp} is not the start of a bin of {}: expected {}{rule}",
                chrom.name, bin.start
            ));
        }
        if bin.end != end_bp {
            return Err(format!(
                "end{side} {end_bp} is not the end of the bin {}:{}-{}: expected {}",
                chrom.name, bin.start, bin.end, bin.end
            ));
        }
        Ok(bin_id as u64)
    }
}

pub(super) fn read_bg2(lines: &mut LineReader, bins: BinTable) -> Result<ContactMatrix> {
    let locator = BinLocator::new(&bins);
    let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
    let mut all_whole = true;
    let mut first_data_line = true;
    while lines.advance()? {
        let line = lines.current();
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        let (columns, n_columns) = first_fields::<7>(line);
        if n_columns < 7 {
            return Err(lines.error(format!(
                "expected 7 columns (chrom1 start1 end1 chrom2 start2 end2 count), found \
                 {n_columns}"
            )));
        }
        if std::mem::take(&mut first_data_line)
            && parse_number(columns[1]).is_none()
            && parse_number(columns[6]).is_none()
        {
            continue; // a header line
        }
        let bin1 = locator
            .locate(columns[0], columns[1], columns[2], 1)
            .map_err(|m| lines.error(m))?;
        let bin2 = locator
            .locate(columns[3], columns[4], columns[5], 2)
            .map_err(|m| lines.error(m))?;
        let count = parse_count(lines, columns[6])?;
        push_pixel(&mut builder, &mut all_whole, bin1, bin2, count)?;
    }
    Ok(finish(builder, all_whole))
}

pub(super) fn read_coo(lines: &mut LineReader, bins: BinTable) -> Result<ContactMatrix> {
    let n_bins = bins.n_bins() as u64;
    let mut builder = MatrixBuilder::new(bins, CountType::Integer);
    let mut all_whole = true;
    let mut first_data_line = true;
    while lines.advance()? {
        let line = lines.current();
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        let (columns, n_columns) = first_fields::<3>(line);
        if n_columns < 3 {
            return Err(lines.error(format!(
                "expected 3 columns (bin1_id bin2_id count), found {n_columns}"
            )));
        }
        if std::mem::take(&mut first_data_line)
            && parse_number(columns[0]).is_none()
            && parse_number(columns[2]).is_none()
        {
            continue; // a header line
        }
        let mut ids = [0u64; 2];
        for (side, id) in ids.iter_mut().enumerate() {
            *id = parse_u64(columns[side]).ok_or_else(|| {
                lines.error(format!(
                    "bin{}_id '{}' is not a bin id (expected a whole number from 0)",
                    side + 1,
                    show(columns[side])
                ))
            })?;
            if *id >= n_bins {
                return Err(lines.error(format!(
                    "bin{}_id {} is out of range: the bin table has {n_bins} bins (ids 0 to {})",
                    side + 1,
                    *id,
                    n_bins.saturating_sub(1)
                )));
            }
        }
        let count = parse_count(lines, columns[2])?;
        push_pixel(&mut builder, &mut all_whole, ids[0], ids[1], count)?;
    }
    Ok(finish(builder, all_whole))
}

pub(super) fn read_dense(lines: &mut LineReader, bins: BinTable) -> Result<ContactMatrix> {
    let n_bins = bins.n_bins();
    // The upper triangle read so far, in CSR, to check each lower value against its mirror.
    let mut row_starts: Vec<usize> = vec![0];
    let mut columns: Vec<u32> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    let mut all_whole = true;
    let mut row = 0usize;
    while lines.advance()? {
        let line = lines.current();
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        if row >= n_bins {
            return Err(lines.error(format!(
                "more rows than bins: the matrix must have {n_bins} rows, one per bin"
            )));
        }
        let mut n_columns = 0usize;
        for (column, field) in Fields::new(line).enumerate() {
            n_columns += 1;
            if column >= n_bins {
                continue;
            }
            let value = parse_count(lines, field)?;
            if column < row {
                let (lo, hi) = (row_starts[column], row_starts[column + 1]);
                let mirror = match columns[lo..hi].binary_search(&(row as u32)) {
                    Ok(k) => values[lo + k],
                    Err(_) => 0.0,
                };
                if (value - mirror).abs() > DENSE_SYMMETRY_TOLERANCE * value.abs().max(mirror.abs())
                {
                    return Err(lines.error(format!(
                        "the matrix is not symmetric: value {} at row {}, column {} differs from \
                         {mirror} at row {}, column {} (rows and columns are 1-based)",
                        show(field),
                        row + 1,
                        column + 1,
                        column + 1,
                        row + 1
                    )));
                }
            } else if value != 0.0 {
                if value.fract() != 0.0 {
                    all_whole = false;
                }
                columns.push(column as u32);
                values.push(value);
            }
        }
        if n_columns != n_bins {
            return Err(lines.error(format!(
                "expected {n_bins} columns (one per bin), found {n_columns}"
            )));
        }
        row_starts.push(columns.len());
        row += 1;
    }
    if row != n_bins {
        return Err(Error::format(
            &lines.path,
            format!("expected {n_bins} rows (one per bin), found {row}"),
        ));
    }
    let mut builder = MatrixBuilder::new(bins, CountType::Integer);
    for bin1 in 0..n_bins {
        for k in row_starts[bin1]..row_starts[bin1 + 1] {
            builder.push(bin1 as u64, u64::from(columns[k]), values[k])?;
        }
    }
    Ok(finish(builder, all_whole))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use tempfile::TempDir;

    use super::super::test_support::*;
    use super::super::{TextFormat, read_bins_bed, read_matrix};
    use crate::error::Error;
    use crate::genome::Chrom;
    use crate::io::OpenOptions;
    use crate::matrix::CountType;

    #[test]
    fn bg2_fixture_matches_cooler_figures() {
        let matrix = fixture_matrix();
        assert_fixture_figures(&matrix);
        let table = read_bins_bed(Path::new(BINS)).unwrap();
        assert_eq!(matrix.bins(), &table);
        assert_eq!(table.chroms()[0], Chrom::new("chr1", 249_250_621));
        assert_eq!(table.chroms()[24], Chrom::new("chrM", 16_571));
    }

    #[test]
    fn bg2_gz_and_plain_give_the_same_matrix() {
        let dir = TempDir::new().unwrap();
        let plain = write_plain(&dir, "plain.bg2", &gunzip(BG2));
        let from_plain = read_matrix(plain.to_str().unwrap(), &bins_options()).unwrap();
        assert_eq!(from_plain, fixture_matrix());
        // The chromosome sizes + bin size route builds the same table.
        let sizes: String = fixture_matrix()
            .bins()
            .chroms()
            .iter()
            .map(|c| format!("{}\t{}\n", c.name, c.length_bp))
            .collect();
        let options = OpenOptions {
            chrom_sizes: Some(write_gz(&dir, "hg19.sizes.gz", &sizes)),
            text_resolution: Some(2_000_000),
            ..OpenOptions::default()
        };
        assert_eq!(read_matrix(BG2, &options).unwrap(), from_plain);
    }

    #[test]
    fn bg2_header_comments_and_whitespace_are_accepted() {
        let dir = TempDir::new().unwrap();
        let options = small_options(&dir, TextFormat::Bg2);
        let text = "chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tcount\n\
                    # a comment\n\
                    chr1\t0\t10\tchr2\t40\t50\t3\tignored\n\
                    chr1 90 100   chr1 0 10 2.5\r\n\
                    \n\
                    chr2\t40\t50\tchr1\t0\t10\t1\n";
        let matrix = read_str(&dir, text, &options).unwrap();
        assert_eq!(matrix.bins().n_bins(), 15);
        assert_eq!(matrix.get(0, 14), 4.0);
        assert_eq!(matrix.get(0, 9), 2.5);
        assert_eq!(matrix.nnz(), 2);
        assert_eq!(matrix.count_type(), CountType::Float);
    }

    #[test]
    fn malformed_bg2_lines_are_reported() {
        let dir = TempDir::new().unwrap();
        let options = small_options(&dir, TextFormat::Bg2);
        let good = "chr1\t0\t10\tchr1\t10\t20\t5\n";
        let cases = [
            (
                "chr1\t0\t10\n",
                "expected 7 columns (chrom1 start1 end1 chrom2 start2 end2 count), found 3",
            ),
            (
                "chr1\t0\t10\tchr1\t10\t20\tmany\n",
                "count 'many' is not a number (expected a count >= 0)",
            ),
            (
                "chr1\t0\t10\tchr1\t10\t20\t-2\n",
                "count -2 is negative (expected a count >= 0)",
            ),
            (
                "chr1\t0\t10\tchr1\t10\t20\tinf\n",
                "count 'inf' is not finite (expected a count >= 0)",
            ),
            (
                "chr1\t0\t10\tchr3\t10\t20\t1\n",
                "unknown chromosome 'chr3' in chrom2 (the bin table has chr1, chr2)",
            ),
            (
                "chr1\t5\t15\tchr1\t10\t20\t1\n",
                "start1 5 is not the start of a bin of chr1: expected 0 (bins of 10 bp start at \
                 multiples of 10)",
            ),
            (
                "chr1\t0\t10\tchr2\t40\t60\t1\n",
                "end2 60 is not the end of the bin chr2:40-50: expected 50",
            ),
            (
                "chr1\t0\t10\tchr2\t50\t60\t1\n",
                "start2 50 is past the end of chr2 (50 bp)",
            ),
            (
                "chr1\tx\t10\tchr1\t10\t20\t1\n",
                "start1 'x' and end1 '10' must be whole numbers",
            ),
        ];
        for (bad, expected) in cases {
            let text = format!("{good}# comment\n{bad}");
            let (line, message) = parse_error(read_str(&dir, &text, &options));
            assert_eq!(line, 3, "{bad}");
            assert_eq!(message, expected);
        }
        // A first line with positions is data, not a header: its bad count is reported.
        let (line, message) = parse_error(read_str(
            &dir,
            "chr1\t0\t10\tchr1\t10\t20\tmany\n",
            &options,
        ));
        assert_eq!((line, message.as_str()), (1, cases[1].1));
    }

    #[test]
    fn malformed_coo_lines_are_reported() {
        let dir = TempDir::new().unwrap();
        let options = small_options(&dir, TextFormat::Coo);
        let matrix = read_str(
            &dir,
            "bin1_id\tbin2_id\tcount\n0\t14\t2\n3 1 1.5\n",
            &options,
        )
        .unwrap();
        assert_eq!(matrix.get(14, 0), 2.0);
        assert_eq!(matrix.get(1, 3), 1.5);
        let cases = [
            (
                "0\t15\t1\n",
                "bin2_id 15 is out of range: the bin table has 15 bins (ids 0 to 14)",
            ),
            (
                "-1\t0\t1\n",
                "bin1_id '-1' is not a bin id (expected a whole number from 0)",
            ),
            (
                "0\t1\n",
                "expected 3 columns (bin1_id bin2_id count), found 2",
            ),
            (
                "0\t1\tNaN\n",
                "count 'NaN' is not finite (expected a count >= 0)",
            ),
        ];
        for (bad, expected) in cases {
            let (line, message) = parse_error(read_str(&dir, &format!("0\t0\t1\n{bad}"), &options));
            assert_eq!(line, 2, "{bad}");
            assert_eq!(message, expected);
        }
    }

    #[test]
    fn dense_matrices_must_be_square_and_symmetric() {
        let dir = TempDir::new().unwrap();
        let bins = write_plain(&dir, "b.bed", "a\t0\t10\na\t10\t25\nb\t0\t5\n");
        let options = OpenOptions {
            text_format: Some(TextFormat::Dense),
            bins_bed: Some(bins),
            ..OpenOptions::default()
        };
        let matrix = read_str(&dir, "1 2 0\n2 0 3\n0 3 4\n", &options).unwrap();
        assert_eq!(matrix.bins().resolution(), None);
        assert_eq!(matrix.nnz(), 4);
        assert_eq!(matrix.get(2, 1), 3.0);
        assert_eq!(matrix.count_type(), CountType::Integer);
        let (line, message) = parse_error(read_str(&dir, "1 2 0\n2 0 3\n0 3.5 4\n", &options));
        assert_eq!(line, 3);
        assert_eq!(
            message,
            "the matrix is not symmetric: value 3.5 at row 3, column 2 differs from 3 at row 2, \
             column 3 (rows and columns are 1-based)"
        );
        let (line, message) = parse_error(read_str(&dir, "1 2 0\n2 0\n", &options));
        assert_eq!(line, 2);
        assert_eq!(message, "expected 3 columns (one per bin), found 2");
        let (line, message) = parse_error(read_str(&dir, "1 2 0\n2 0 3\n0 3 4\n0 0 0\n", &options));
        assert_eq!(line, 4);
        assert!(message.starts_with("more rows than bins"), "{message}");
        match read_str(&dir, "1 2 0\n2 0 3\n", &options) {
            Err(Error::Format { message, .. }) => {
                assert_eq!(message, "expected 3 rows (one per bin), found 2")
            }
            other => panic!("expected a format error, got {other:?}"),
        }
    }

    /// `data/text/bg2_zeros.bg2.gz`: 715 pixels touching chr21, 179 of them listed with a count of
    /// 0, a third written in the lower triangle; `bg2_zeros.cooler-dump.coo` is `cooler dump` of
    /// `cooler load -f bg2` of it (cooler 0.11, scripts/fixtures/bg2_zeros.py).
    #[test]
    fn zero_counts_are_kept_as_cooler_load_keeps_them() {
        let data = concat!(env!("CARGO_MANIFEST_DIR"), "/data/text/");
        let dump = std::fs::read_to_string(format!("{data}bg2_zeros.cooler-dump.coo")).unwrap();
        let reference: Vec<(u64, u64, f64)> = dump
            .lines()
            .map(|line| {
                let f: Vec<&str> = line.split('\t').collect();
                (
                    f[0].parse().unwrap(),
                    f[1].parse().unwrap(),
                    f[2].parse().unwrap(),
                )
            })
            .collect();
        assert_eq!(reference.len(), 715);
        assert_eq!(reference.iter().filter(|p| p.2 == 0.0).count(), 179);
        let bg2 = read_matrix(&format!("{data}bg2_zeros.bg2.gz"), &bins_options()).unwrap();
        let coo =
            read_matrix(&format!("{data}bg2_zeros.cooler-dump.coo"), &bins_options()).unwrap();
        for matrix in [&bg2, &coo] {
            let pixels = matrix.all_pixels();
            let ours: Vec<(u64, u64, f64)> = (0..pixels.len())
                .map(|k| (pixels.bin1[k], pixels.bin2[k], pixels.count[k]))
                .collect();
            assert_eq!(ours, reference);
            assert_eq!(matrix.nnz(), 715);
            assert_eq!(matrix.sum(), 1086.0);
            assert_eq!(matrix.count_type(), CountType::Integer);
        }
    }
}
