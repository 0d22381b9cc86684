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

use std::collections::BTreeMap;
use std::fs::File;

use hdf5::types::{TypeDescriptor, VarLenAscii, VarLenUnicode};

use crate::error::{Error, Result};
use crate::genome::{Bin, BinTable, Chrom};
use crate::io::cool::chunks::{self, Column};
use crate::io::cool::{self, BLOCK_PIXELS, CoolWriteOptions, DIVISIVE_BY_NAME};
use crate::io::hdf5_guard::{guarded, read_strings};
use crate::io::hic::HicReader;
use crate::io::{self, FileKind, InMemory, MatrixReader};
use crate::matrix::{CountType, MatrixBuilder, Weights};

mod cooler;
mod hic;
mod repair;

use cooler::*;
use hic::*;
pub use repair::{RepairOutcome, repair};

/// Findings listed per class and group; further occurrences are only counted.
pub const MAX_LISTED: u64 = 20;

/// Relative tolerance when comparing float counts (coarsening, `sum` attribute).
pub const FLOAT_TOLERANCE: f64 = 1e-6;

/// How serious a finding is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Severity {
    /// The file is read correctly by cooler, but is not as the format says.
    Warning,
    /// The file is invalid: a reader would fail or compute on wrong data.
    Error,
}

impl Severity {
    /// `warning` or `error`.
    pub fn name(self) -> &'static str {
        match self {
            Severity::Warning => "warning",
            Severity::Error => "error",
        }
    }
}

/// The kind of a defect.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Class {
    /// A missing group or dataset, a wrong type, columns of one table with different lengths.
    Schema,
    /// An attribute that disagrees with the data.
    Attribute,
    /// The chromosome table: empty or duplicated names, lengths <= 0.
    Chroms,
    /// The bin table: gaps, overlaps, disorder, bins outside their chromosome, wrong sizes.
    BinTable,
    /// `indexes/chrom_offset` inconsistent with the bins.
    ChromOffset,
    /// `indexes/bin1_offset` inconsistent with the bins or the pixels.
    Bin1Offset,
    /// `indexes/bin1_offset` with `nbins` entries (hic2cool 0.3 - 0.4): read by cooler.
    LegacyIndex,
    /// A chromosome whose bins start after 0 (a matrix cut out of it): read by cooler.
    CutBins,
    /// A pixel bin id outside the bin table.
    BinId,
    /// A pixel with `bin1 > bin2` in symmetric-upper storage.
    LowerTriangle,
    /// Pixels not sorted by `(bin1, bin2)`.
    Unsorted,
    /// Two pixels with the same `(bin1, bin2)`.
    Duplicate,
    /// A negative or non-finite count.
    Count,
    /// A weight column of the wrong length or with invalid values.
    Weight,
    /// A coarser resolution that is not the coarsening of the base resolution.
    Coarsening,
    /// An error while reading a `.hic` resolution or a HiCExplorer `.h5` matrix.
    HicRead,
}

impl Class {
    /// The class's name in reports (kebab case).
    pub fn name(self) -> &'static str {
        match self {
            Class::Schema => "schema",
            Class::Attribute => "attribute",
            Class::Chroms => "chroms",
            Class::BinTable => "bin-table",
            Class::ChromOffset => "chrom-offset",
            Class::Bin1Offset => "bin1-offset",
            Class::LegacyIndex => "legacy-index",
            Class::CutBins => "cut-bins",
            Class::BinId => "bin-id",
            Class::LowerTriangle => "lower-triangle",
            Class::Unsorted => "unsorted",
            Class::Duplicate => "duplicate",
            Class::Count => "count",
            Class::Weight => "weight",
            Class::Coarsening => "coarsening",
            Class::HicRead => "hic-read",
        }
    }

    /// How serious findings of this class are.
    pub fn severity(self) -> Severity {
        match self {
            Class::LegacyIndex | Class::CutBins => Severity::Warning,
            _ => Severity::Error,
        }
    }

    /// True when [`repair`] can correct this class of defect.
    pub fn is_repairable(self) -> bool {
        matches!(
            self,
            Class::Attribute
                | Class::ChromOffset
                | Class::Bin1Offset
                | Class::LegacyIndex
                | Class::LowerTriangle
                | Class::Unsorted
                | Class::Duplicate
                | Class::Coarsening
        )
    }
}

/// One problem found in a file.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    /// What kind of defect.
    pub class: Class,
    /// How serious.
    pub severity: Severity,
    /// The cooler group (`/`, `/resolutions/1000`) or `.hic` resolution it was found in.
    pub group: String,
    /// Where in the group: dataset and row, pixel index, chromosome.
    pub location: String,
    /// What was found and what was expected.
    pub message: String,
}

/// The result of [`validate`].
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// The file checked.
    pub path: String,
    /// `cool`, `mcool`, `mcool (legacy numeric layout)` or `hic (version N)`.
    pub format: String,
    /// The groups (coolers) or `.hic` resolutions checked.
    pub checked: Vec<String>,
    /// Findings, at most [`MAX_LISTED`] per class and group, then one line counting the rest.
    pub findings: Vec<Finding>,
    /// Number of occurrences of every class found, per group (listed or not).
    pub occurrences: Vec<(String, Class, u64)>,
    /// Remarks: checks that could not be made and why.
    pub notes: Vec<String>,
}

impl Report {
    /// The report as the text `contactmap validate` prints: one line per finding (`severity
    /// class group location message`, tab-separated), the notes, then a summary line.
    ///
    /// ```
    /// let report = contactmap::validate::validate("data/yeast.10kb.cool")?;
    /// assert!(report.to_text().ends_with(": 0 errors, 0 warnings\n"));
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn to_text(&self) -> String {
        let report = self;
        let mut text = String::new();
        for f in &report.findings {
            text.push_str(&format!(
                "{}\t{}\t{}\t{}\t{}\n",
                f.severity.name(),
                f.class.name(),
                f.group,
                f.location,
                f.message
            ));
        }
        for note in &report.notes {
            text.push_str(&format!("note: {note}\n"));
        }
        text.push_str(&format!(
            "{}: {} ({}; checked {}): {} errors, {} warnings\n",
            report.path,
            if report.is_valid() {
                "valid"
            } else {
                "INVALID"
            },
            report.format,
            report.checked.join(", "),
            report.n_errors(),
            report.n_warnings()
        ));
        text
    }

    /// True when no finding is an error (warnings allowed).
    pub fn is_valid(&self) -> bool {
        self.findings.iter().all(|f| f.severity < Severity::Error)
    }

    /// Number of error occurrences (listed or not).
    pub fn n_errors(&self) -> u64 {
        self.occurrences
            .iter()
            .filter(|(_, c, _)| c.severity() == Severity::Error)
            .map(|(_, _, n)| n)
            .sum()
    }

    /// Number of warning occurrences (listed or not).
    pub fn n_warnings(&self) -> u64 {
        self.occurrences
            .iter()
            .filter(|(_, c, _)| c.severity() == Severity::Warning)
            .map(|(_, _, n)| n)
            .sum()
    }

    /// The report as one JSON document.
    pub fn to_json(&self) -> serde_json::Value {
        use serde_json::json;
        json!({
            "file": self.path,
            "format": self.format,
            "checked": self.checked,
            "valid": self.is_valid(),
            "errors": self.n_errors(),
            "warnings": self.n_warnings(),
            "findings": self.findings.iter().map(|f| json!({
                "class": f.class.name(),
                "severity": f.severity.name(),
                "group": f.group,
                "location": f.location,
                "message": f.message,
            })).collect::<Vec<_>>(),
            "occurrences": self.occurrences.iter().map(|(g, c, n)| json!({
                "group": g, "class": c.name(), "count": n,
            })).collect::<Vec<_>>(),
            "notes": self.notes,
        })
    }
}

/// Collects findings, listing at most [`MAX_LISTED`] per (group, class).
#[derive(Default)]
struct Collector {
    findings: Vec<Finding>,
    counts: BTreeMap<(String, Class), u64>,
    notes: Vec<String>,
}

impl Collector {
    /// Record one occurrence; `describe` gives (location, message) and is called only for the
    /// occurrences listed.
    fn add(&mut self, group: &str, class: Class, describe: impl FnOnce() -> (String, String)) {
        let n = self.counts.entry((group.to_string(), class)).or_default();
        *n += 1;
        if *n <= MAX_LISTED {
            let (location, message) = describe();
            self.findings.push(Finding {
                class,
                severity: class.severity(),
                group: group.to_string(),
                location,
                message,
            });
        }
    }

    fn count(&self, group: &str, class: Class) -> u64 {
        self.counts
            .get(&(group.to_string(), class))
            .copied()
            .unwrap_or(0)
    }

    fn into_report(self, path: &str, format: String, checked: Vec<String>) -> Report {
        let mut findings = self.findings;
        for ((group, class), &n) in &self.counts {
            if n > MAX_LISTED {
                findings.push(Finding {
                    class: *class,
                    severity: class.severity(),
                    group: group.clone(),
                    location: "(summary)".into(),
                    message: format!(
                        "{} more {} findings not listed ({n} in all)",
                        n - MAX_LISTED,
                        class.name()
                    ),
                });
            }
        }
        Report {
            path: path.to_string(),
            format,
            checked,
            findings,
            occurrences: self
                .counts
                .into_iter()
                .map(|((g, c), n)| (g, c, n))
                .collect(),
            notes: self.notes,
        }
    }
}

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
    use super::*;
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
