//! Reading a text matrix into memory, in its layout given, guessed from its name or sniffed from
//! its first lines.

use std::path::Path;

use super::bins::bin_table_for;
use super::format::{TextFormat, guess_format};
use super::lines::LineReader;
use super::options::OpenOptions;
use super::pairs::read_pairs;
use super::pixels::{read_bg2, read_coo, read_dense};
use crate::error::{Error, Result};
use crate::matrix::ContactMatrix;

/// Read a text matrix into memory (`path` `-` is standard input).
///
/// The format is `options.text_format`, else guessed from the name ([`guess_format`]), else sniffed
/// from the first lines: a `## pairs format`, `#columns:` or `#chromsize:` header means pairs, a
/// data line of 7 or more columns with numeric columns 2, 3, 5 and 6 means BG2, exactly 3 numeric
/// columns mean COO.
///
/// # Examples
///
/// The GM12878 map as BG2 text (`cooler dump --join`) with its bin table: the same pixels as
/// the cooler it was dumped from.
///
/// ```
/// use contactmap::io::text::read_matrix;
/// use contactmap::io::OpenOptions;
///
/// let options = OpenOptions {
///     bins_bed: Some("data/hg19.bins.2000kb.bed.gz".into()),
///     ..OpenOptions::default()
/// };
/// let matrix = read_matrix("data/hg19.GM12878-MboI.matrix.2000kb.bg2.gz", &options)?;
/// // data/reference/totals.tsv: 1561 bins, 38156 pixels, sum 100000
/// assert_eq!(matrix.bins().n_bins(), 1_561);
/// assert_eq!((matrix.nnz(), matrix.sum()), (38_156, 100_000.0));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn read_matrix(path: &str, options: &OpenOptions) -> Result<ContactMatrix> {
    let mut lines = LineReader::open(Path::new(path))?;
    let format = match options.text_format.or_else(|| guess_format(path)) {
        Some(format) => format,
        None => lines.sniff_format()?.ok_or_else(|| {
            Error::format(
                path,
                "cannot tell the text format from the name or the first lines: pass --format \
                 (bg2, coo, pairs or dense)",
            )
        })?,
    };
    match format {
        TextFormat::Bg2 => read_bg2(&mut lines, bin_table_for(path, "a BG2 table", options)?),
        TextFormat::Coo => read_coo(&mut lines, bin_table_for(path, "a COO table", options)?),
        TextFormat::Dense => {
            read_dense(&mut lines, bin_table_for(path, "a dense matrix", options)?)
        }
        TextFormat::Pairs => read_pairs(&mut lines, options),
    }
}
