//! Bin tables of text inputs: chromosome sizes files, bins BED files, and the choice between
//! them.

use std::collections::HashMap;
use std::path::Path;

use super::lines::{Fields, LineReader, parse_u64, show};
use super::options::OpenOptions;
use crate::error::{Error, Result};
use crate::genome::{Bin, BinTable, Chrom};

/// Read a chromosome sizes file: `name<TAB>length` per line (extra columns ignored, `#` comments
/// skipped, gzip allowed), in the order of the file.
pub fn read_chrom_sizes(path: &Path) -> Result<Vec<Chrom>> {
    let mut lines = LineReader::open(path)?;
    let mut chroms: Vec<Chrom> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    while lines.advance()? {
        let line = lines.current();
        if line.is_empty() || line[0] == b'#' {
            continue;
        }
        let mut fields = Fields::new(line);
        let (Some(name), Some(length)) = (fields.next(), fields.next()) else {
            return Err(lines.error(format!(
                "expected 2 columns (name length), found 1: '{}'",
                show(line)
            )));
        };
        let length_bp = match parse_u64(length) {
            Some(0) | None => {
                return Err(lines.error(format!(
                    "length '{}' of '{}' is not a positive whole number",
                    show(length),
                    show(name)
                )));
            }
            Some(n) => n,
        };
        let name = String::from_utf8_lossy(name).into_owned();
        if !seen.insert(name.clone()) {
            return Err(lines.error(format!("chromosome '{name}' appears twice")));
        }
        chroms.push(Chrom::new(name, length_bp));
    }
    if chroms.is_empty() {
        return Err(Error::format(
            path,
            "no chromosome in the chromosome sizes file (expected 'name<TAB>length' lines)",
        ));
    }
    Ok(chroms)
}

/// Read a bin table from a BED file: `chrom start end` per line (extra columns ignored, gzip
/// allowed; `#`, `track` and `browser` lines and one header line skipped).
///
/// Bins must be grouped by chromosome and tile each chromosome from 0; a chromosome's length is the
/// end of its last bin. A table of equal-size bins becomes a fixed table ([`BinTable::from_bins`]).
pub fn read_bins_bed(path: &Path) -> Result<BinTable> {
    let mut lines = LineReader::open(path)?;
    let mut chroms: Vec<Chrom> = Vec::new();
    let mut ids: HashMap<Vec<u8>, usize> = HashMap::new();
    let mut bins: Vec<Bin> = Vec::new();
    let mut first_data_line = true;
    while lines.advance()? {
        let line = lines.current();
        if line.is_empty()
            || line[0] == b'#'
            || line.starts_with(b"track")
            || line.starts_with(b"browser")
        {
            continue;
        }
        let fields: Vec<&[u8]> = Fields::new(line).take(3).collect();
        if fields.len() < 3 {
            return Err(lines.error(format!(
                "expected 3 columns (chrom start end), found {}",
                fields.len()
            )));
        }
        let (start, end) = match (parse_u64(fields[1]), parse_u64(fields[2])) {
            (Some(start), Some(end)) => (start, end),
            _ if first_data_line => {
                first_data_line = false;
                continue;
            }
            _ => {
                return Err(lines.error(format!(
                    "start '{}' and end '{}' must be whole numbers",
                    show(fields[1]),
                    show(fields[2])
                )));
            }
        };
        first_data_line = false;
        let chrom_id = match ids.get(fields[0]) {
            Some(&id) => id,
            None => {
                let id = chroms.len();
                ids.insert(fields[0].to_vec(), id);
                chroms.push(Chrom::new(String::from_utf8_lossy(fields[0]), 0));
                id
            }
        };
        let expected_start =
            match bins.last() {
                Some(last) if last.chrom_id == chrom_id => last.end,
                Some(_) if chroms[chrom_id].length_bp > 0 => return Err(lines.error(format!(
                    "chromosome '{}' appears again after other chromosomes: bins must be grouped \
                     by chromosome",
                    chroms[chrom_id].name
                ))),
                _ => 0,
            };
        if start != expected_start || end <= start {
            return Err(lines.error(format!(
                "bin {}:{start}-{end} does not continue the tiling of '{}': expected a bin starting \
                 at {expected_start} and ending after it",
                chroms[chrom_id].name, chroms[chrom_id].name
            )));
        }
        chroms[chrom_id].length_bp = end;
        bins.push(Bin {
            chrom_id,
            start,
            end,
        });
    }
    if bins.is_empty() {
        return Err(Error::format(
            path,
            "no bin in the bins BED file (expected 'chrom start end' lines)",
        ));
    }
    BinTable::from_bins(chroms, &bins, None).map_err(|e| Error::format(path, e.to_string()))
}

/// The bin table of a BG2 / COO / dense input: `--bins`, else `--chrom-sizes` with `--bin-size`.
pub(super) fn bin_table_for(path: &str, what: &str, options: &OpenOptions) -> Result<BinTable> {
    if let Some(bed) = &options.bins_bed {
        let table = read_bins_bed(bed)?;
        if let Some(size) = options.text_resolution {
            // A BED cannot tell bin sizes apart when every chromosome is a single bin: the table
            // is the fixed one of the given size when its bins are the same.
            let fixed = BinTable::fixed(table.chroms().to_vec(), size)?;
            if fixed.n_bins() != table.n_bins() || !fixed.iter().eq(table.iter()) {
                return Err(Error::Argument(format!(
                    "{path}: --bin-size {size} disagrees with the bins of {} ({}): pass one of them",
                    bed.display(),
                    match table.resolution() {
                        Some(s) => format!("{s} bp bins"),
                        None => "variable-size bins".to_string(),
                    }
                )));
            }
            return Ok(fixed);
        }
        return Ok(table);
    }
    match (&options.chrom_sizes, options.text_resolution) {
        (Some(sizes), Some(size)) => BinTable::fixed(read_chrom_sizes(sizes)?, size),
        (Some(_), None) => Err(Error::Argument(format!(
            "{path}: --chrom-sizes needs a bin size to build the bin table of {what}: pass \
             --bin-size N"
        ))),
        _ => Err(Error::Argument(format!(
            "{path}: {what} does not carry its bin table: pass --bins BED, or --chrom-sizes FILE \
             --bin-size N"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use tempfile::TempDir;

    use super::super::read_matrix;
    use super::super::test_support::*;
    use super::*;

    #[test]
    fn chrom_sizes_and_bins_bed_are_checked() {
        let dir = TempDir::new().unwrap();
        let sizes = write_plain(&dir, "s", "# comment\nchr1\t100\tx\nchr2 50\n");
        assert_eq!(
            read_chrom_sizes(&sizes).unwrap(),
            vec![Chrom::new("chr1", 100), Chrom::new("chr2", 50)]
        );
        let bad = write_plain(&dir, "s", "chr1\t100\nchr1\t50\n");
        assert_eq!(
            parse_error(read_chrom_sizes(&bad)),
            (2, "chromosome 'chr1' appears twice".to_string())
        );
        let bad = write_plain(&dir, "s", "chr1\t1e6\n");
        assert_eq!(
            parse_error(read_chrom_sizes(&bad)),
            (
                1,
                "length '1e6' of 'chr1' is not a positive whole number".to_string()
            )
        );
        let bed = write_plain(
            &dir,
            "b",
            "chrom\tstart\tend\nc\t0\t10\nc\t10\t12\nd\t0\t3\n",
        );
        let table = read_bins_bed(&bed).unwrap();
        assert_eq!(table.n_bins(), 3);
        assert_eq!(table.resolution(), Some(10));
        assert_eq!(table.chroms()[0], Chrom::new("c", 12));
        let gap = write_plain(&dir, "b", "c\t0\t10\nc\t11\t20\n");
        let (line, message) = parse_error(read_bins_bed(&gap));
        assert_eq!(line, 2);
        assert!(
            message.contains("expected a bin starting at 10"),
            "{message}"
        );
        let regrouped = write_plain(&dir, "b", "c\t0\t10\nd\t0\t10\nc\t10\t20\n");
        let (line, message) = parse_error(read_bins_bed(&regrouped));
        assert_eq!(line, 3);
        assert!(
            message.contains("must be grouped by chromosome"),
            "{message}"
        );
    }

    #[test]
    fn bg2_needs_a_bin_table() {
        let dir = TempDir::new().unwrap();
        let path = write_plain(&dir, "m.bg2", "chr1\t0\t10\tchr1\t10\t20\t5\n");
        let message =
            argument_message(read_matrix(path.to_str().unwrap(), &OpenOptions::default()));
        assert!(
            message.ends_with(
                "a BG2 table does not carry its bin table: pass --bins BED, or --chrom-sizes \
                 FILE --bin-size N"
            ),
            "{message}"
        );
        let options = OpenOptions {
            chrom_sizes: Some(write_plain(&dir, "s", SMALL_SIZES)),
            ..OpenOptions::default()
        };
        let message = argument_message(read_matrix(path.to_str().unwrap(), &options));
        assert!(message.contains("pass --bin-size N"), "{message}");
        let options = OpenOptions {
            text_resolution: Some(1000),
            ..bins_options()
        };
        let message = argument_message(read_matrix(path.to_str().unwrap(), &options));
        assert!(message.contains("--bin-size 1000 disagrees"), "{message}");
    }
}
