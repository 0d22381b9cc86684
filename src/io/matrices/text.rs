//! Text pixel tables, pairs and dense matrices: readers and writers.
//!
//! # Layouts
//!
//! Columns are separated by tabs; a line without any tab is split on runs of spaces instead. Empty
//! lines and lines starting with `#` are skipped. Every input may be gzip-compressed (recognised by
//! its magic bytes `1f 8b`, whatever its name); `-` is standard input for readers and standard
//! output for writers.
//!
//! | [`TextFormat`] | columns | bin table from |
//! |---|---|---|
//! | [`Bg2`](TextFormat::Bg2) | `chrom1 start1 end1 chrom2 start2 end2 count [ignored...]`, as `cooler dump --join` writes and `cooler load -f bg2` reads | `--bins BED`, or `--chrom-sizes FILE --bin-size N` |
//! | [`Coo`](TextFormat::Coo) | `bin1_id bin2_id count [ignored...]` with 0-based bin ids, as `cooler dump` writes | same |
//! | [`Pairs`](TextFormat::Pairs) | 4DN `.pairs` (`readID chr1 pos1 chr2 pos2 ...`) or any pair text (`--pairs-columns`) | `--bin-size N` with `#chromsize:` header lines, `--chrom-sizes FILE` or `--bins BED` |
//! | [`Dense`](TextFormat::Dense) | a square `n_bins x n_bins` matrix of numbers, one row per line | `--bins BED`, or `--chrom-sizes FILE --bin-size N` |
//!
//! BG2 and COO tables may start with one header line (a first data line whose first position or
//! bin id and whose count are both not numbers is skipped). Each BG2 pixel must name a bin of the
//! table exactly: a known chromosome, a start that is a bin start and the end of that bin. Pixels
//! may come in any order and in either triangle: lower-triangle pixels are mirrored and duplicates
//! summed (see [`MatrixBuilder`](crate::matrix::MatrixBuilder)). Counts must be finite and
//! non-negative. A pixel listed with a count of 0 is kept as an explicit pixel, as
//! `cooler load -f bg2` and `cooler load -f coo` keep it (cooler 0.11); a dense matrix has no
//! explicit pixels (its zeros are absent pixels), and binned pairs count at least 1 per pixel. The
//! matrix gets [`CountType::Integer`](crate::matrix::CountType::Integer) when every count is a whole
//! number, [`CountType::Float`](crate::matrix::CountType::Float) otherwise.
//!
//! A dense matrix must be symmetric: its upper triangle is read and every lower-triangle value must
//! equal its mirror (to a relative tolerance of 1e-9, so that matrices printed from floating-point
//! computations pass), else the line is reported.
//!
//! # Binning pairs
//!
//! Pairs are binned exactly as `cooler cload pairs` (cooler 0.11) bins them with its default
//! options:
//!
//! - positions are **1-based** (the 4DN pairs convention and cooler's default without
//!   `--zero-based`, which `OpenOptions::pairs_zero_based` mirrors): a pair at `pos` falls in the bin containing the 0-based coordinate `pos - 1`,
//!   i.e. bin `chrom_offset + (pos - 1) / resolution` for fixed bins;
//! - pairs with a chromosome that is not in the chromosome table are dropped (cooler drops them
//!   silently); position 0 and positions past the chromosome's length are errors (cooler raises
//!   `BadInputError` for them, except for `pos == length + 1`, which it accepts and bins out of
//!   range: that is an error here too);
//! - each pair counts 1; pairs in the lower triangle are reflected (`unique` copy status), so the
//!   stored count of pixel `(i, j)` is the number of pairs in `(i, j)` plus those in `(j, i)`.
//!
//! The chromosome table is, in order of precedence: `--bins BED` (its bins are used as they are),
//! `--chrom-sizes FILE`, the `#chromsize: name length` header lines. The column layout is
//! `--pairs-columns` (1-based `chrom1,pos1,chrom2,pos2`), else the `#columns:` header line
//! (`chr1 pos1 chr2 pos2`), else the 4DN default `2,3,4,5`. Pairs are streamed: memory is the
//! binned pixel map, not the pairs.
//!
//! # Writing
//!
//! [`write_text`] streams the pixels of any [`MatrixReader`](crate::io::MatrixReader): BG2 (exactly `cooler dump --join`),
//! COO (exactly `cooler dump`) or the full symmetric dense matrix (at most
//! [`MAX_DENSE_BINS`] bins). Integer counts are printed without a decimal point; real counts with
//! the shortest representation that reads back to the same `f64` (Rust's `{:?}`, which keeps a
//! `.0` on whole numbers as `cooler dump` does). A file is written to a temporary file next to the
//! target and renamed when complete; a name ending in `.gz` is gzip-compressed.
//!
//! # Threads
//!
//! A gzip-compressed input is inflated on one helper thread while the calling thread parses, so
//! that decompression and parsing overlap. Chunks are handed over in order: results never depend
//! on the scheduling.

mod bins;
pub mod dump;
mod format;
mod lines;
pub(super) mod options;
mod pairs;
mod pixels;
mod read;
#[cfg(test)]
mod test_support;
mod write;

pub use bins::{read_bins_bed, read_chrom_sizes};
pub use format::{TextFormat, guess_format};
pub use read::read_matrix;
pub use write::{MAX_DENSE_BINS, write_text};

#[cfg(test)]
mod tests {
    use tempfile::TempDir;

    use super::options::OpenOptions;
    use super::*;
    use crate::error::Error;
    use test_support::*;

    #[test]
    fn formats_are_guessed_from_names_and_sniffed_from_content() {
        assert_eq!(guess_format("a.bg2"), Some(TextFormat::Bg2));
        assert_eq!(guess_format("a.BEDPE.gz"), Some(TextFormat::Bg2));
        assert_eq!(guess_format("x/y.pairs.gz"), Some(TextFormat::Pairs));
        assert_eq!(guess_format("y.pairsam"), Some(TextFormat::Pairs));
        assert_eq!(guess_format("y.coo"), Some(TextFormat::Coo));
        assert_eq!(guess_format("y.pixels.gz"), Some(TextFormat::Coo));
        assert_eq!(guess_format("y.mat"), Some(TextFormat::Dense));
        assert_eq!(guess_format("y.matrix.gz"), Some(TextFormat::Dense));
        assert_eq!(guess_format("y.dense"), Some(TextFormat::Dense));
        assert_eq!(guess_format("y.txt.gz"), None);
        assert_eq!(guess_format("-"), None);

        let dir = TempDir::new().unwrap();
        let options = OpenOptions {
            text_format: None,
            ..small_options(&dir, TextFormat::Bg2)
        };
        // BG2 with a header, COO, both from a neutral name.
        let bg2 = "chrom1 start1 end1 chrom2 start2 end2 count\nchr1 0 10 chr1 10 20 5\n";
        assert_eq!(read_str(&dir, bg2, &options).unwrap().get(0, 1), 5.0);
        assert_eq!(
            read_str(&dir, "#x\n\n0\t1\t5\n", &options)
                .unwrap()
                .get(0, 1),
            5.0
        );
        match read_str(&dir, "a b c d\n", &options) {
            Err(Error::Format { message, .. }) => {
                assert!(message.contains("pass --format"), "{message}")
            }
            other => panic!("expected a format error, got {other:?}"),
        }
        // Line numbers count from the start of the file after sniffing.
        let (line, _) = parse_error(read_str(&dir, "0\t1\t5\n0\t1\n", &options));
        assert_eq!(line, 2);
    }
}
