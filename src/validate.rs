//! File checks and repairs: `contactmap validate`, in the spirit of `hictk validate` and
//! `hictk fix-mcool`.
//!
//! [`validate`] checks a `.cool`, `.mcool` (every `/resolutions/N`, and the legacy numeric
//! multi-resolution layout `/0`, `/1`, ...) or Juicer `.hic` end to end and returns a [`Report`]
//! listing every problem found with its location (group, dataset and row, pixel index, or
//! chromosome). Coolers are read through libhdf5 directly (not through
//! [`crate::io::cool::CoolReader`], which refuses or fixes some defects on open), so that the checks
//! see the stored data:
//!
//! - schema: the groups and datasets of the cooler schema with numeric or string types, columns of
//!   a table of equal length;
//! - attributes: `nbins`, `nchroms`, `nnz`, `bin-size`, `storage-mode` and `sum` agreeing with the
//!   data;
//! - chromosomes: non-empty unique names, lengths > 0;
//! - bin table: per chromosome contiguous from 0 to the chromosome's length, ordered, fixed-size
//!   bins agreeing with `bin-size`;
//! - indexes: `chrom_offset` and `bin1_offset` of the right length, monotone and consistent with the
//!   bins and the pixels (a `bin1_offset` with `nbins` entries instead of `nbins + 1`, as hic2cool
//!   0.3 - 0.4 wrote, is a warning: cooler reads it);
//! - pixels: bin ids in range, `bin1 <= bin2` in symmetric-upper storage, sorted by
//!   `(bin1, bin2)` without duplicates, each pixel in the row `bin1_offset` puts it in; counts
//!   finite and >= 0;
//! - weight columns (float columns of `bins/`): one value per bin, finite or NaN, > 0 (0 is allowed
//!   in divisive Juicer columns, where it marks a masked bin);
//! - `.mcool`: each coarser resolution's bins are the coarsening of the base (finest) resolution's
//!   and its pixels equal the base pixels summed into the coarse bins (counts compared with a
//!   relative tolerance of 1e-6 for float counts, exactly for integers).
//!
//! A `.hic` file is opened with [`crate::io::hic::HicReader`] (header, footer and master index are
//! checked there) and every resolution's pixels are streamed end to end; any error is reported
//! with its resolution, and counts must be finite and >= 0.
//!
//! Findings are capped at [`MAX_LISTED`] per class and group; the rest are counted.
//!
//! [`repair`] writes a corrected copy of a cooler through the library's writer
//! ([`crate::io::cool::write_cool`] / [`crate::io::cool::write_mcool`]): pixels resorted,
//! duplicates summed, lower-triangle pixels transposed, indexes and attributes rebuilt, and for an
//! `.mcool` every zoom level regenerated from the base resolution. It refuses defects that cannot
//! be repaired (negative or non-finite counts, a broken chromosome or bin table, bin ids out of
//! range, bad weights).

use crate::error::{Error, Result};
use crate::io::{self, FileKind};

mod cooler;
mod hic;
mod repair;
mod report;
mod tolerance;

use cooler::validate_hdf5;
use hic::validate_hic;
pub use repair::{RepairOutcome, repair};
pub use report::{Class, Finding, MAX_LISTED, Report, Severity};
pub use tolerance::FLOAT_TOLERANCE;

/// Check the matrix file at `uri` (`file.cool`, `file.mcool`, `file.hic`, or one group:
/// `file.mcool::/resolutions/N`, `file.hic::/resolutions/N`).
///
/// Returns the report (possibly with findings); an error means the file could not be checked
/// at all: not a matrix file, not readable, or a defect that stops the check.
///
/// # Examples
///
/// ```
/// let report = contactmap::validate::validate("data/yeast.10kb.cool")?;
/// assert_eq!(report.format, "cool");
/// assert!(report.is_valid(), "{:?}", report.findings);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn validate(uri: &str) -> Result<Report> {
    let (path, group) = io::split_uri(uri);
    match io::detect_kind(path)? {
        FileKind::Hdf5 => validate_hdf5(path, group),
        FileKind::Hic => validate_hic(uri, path, group),
        FileKind::Text => Err(Error::format(
            path,
            "not a .cool, .mcool or .hic file (neither HDF5 nor .hic magic bytes): validate checks binary matrix files",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::report::Collector;
    use super::*;
    use crate::genome::{BinTable, Chrom};
    use crate::io::InMemory;
    use crate::io::cool::{self, CoolWriteOptions};
    use crate::matrix::{CountType, MatrixBuilder};
    use std::path::Path;

    fn small_cool(dir: &Path) -> std::path::PathBuf {
        let bins = BinTable::fixed(vec![Chrom::new("a", 50), Chrom::new("b", 30)], 10).unwrap();
        let mut builder = MatrixBuilder::new(bins, CountType::Integer);
        for i in 0..8u64 {
            for j in i..8 {
                builder.push(i, j, (1 + i + j) as f64).unwrap();
            }
        }
        let path = dir.join("small.cool");
        let matrix = InMemory::new("small".into(), builder.build());
        cool::write_cool(&matrix, &path, &CoolWriteOptions::default()).unwrap();
        path
    }

    #[test]
    fn the_collector_lists_twenty_and_counts_the_rest() {
        let mut collector = Collector::default();
        for k in 0..25 {
            collector.add("/", Class::Unsorted, || (format!("row {k}"), "x".into()));
        }
        collector.add("/", Class::LegacyIndex, || ("i".into(), "y".into()));
        let report = collector.into_report("f", "cool".into(), vec!["/".into()]);
        assert_eq!(report.findings.len(), 20 + 1 + 1);
        assert_eq!(report.n_errors(), 25);
        assert_eq!(report.n_warnings(), 1);
        assert!(!report.is_valid());
        assert!(
            report
                .findings
                .iter()
                .any(|f| f.message.starts_with("5 more unsorted findings"))
        );
    }

    #[test]
    fn a_written_cooler_is_valid_and_a_broken_sum_is_found() {
        let dir = tempfile::tempdir().unwrap();
        let path = small_cool(dir.path());
        let uri = path.to_string_lossy().into_owned();
        let report = validate(&uri).unwrap();
        assert!(report.is_valid(), "{:?}", report.findings);
        assert_eq!(report.checked, vec!["/".to_string()]);
        {
            let mut builder = hdf5::File::with_options();
            builder.fapl().file_locking(false);
            let file = builder.open_rw(&path).unwrap();
            file.attr("sum").unwrap().write_scalar(&7i64).unwrap();
        }
        let report = validate(&uri).unwrap();
        assert_eq!(report.findings.len(), 1, "{:?}", report.findings);
        assert_eq!(report.findings[0].class, Class::Attribute);
        assert_eq!(report.findings[0].location, "sum");
    }

    #[test]
    fn repair_refuses_to_overwrite_its_input() {
        let dir = tempfile::tempdir().unwrap();
        let path = small_cool(dir.path());
        let link = dir.path().join("link.cool");
        std::fs::hard_link(&path, &link).unwrap();
        let uri = path.to_string_lossy().into_owned();
        let report = validate(&uri).unwrap();
        assert!(repair(&uri, &report, &path).is_err());
        assert!(repair(&uri, &report, &link).is_err());
    }
}
