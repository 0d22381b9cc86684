//! What a check finds and how it is reported: the classes of defects and their severity, the
//! findings, the [`Report`], and the collector that lists at most [`MAX_LISTED`] findings per
//! class and group.

use std::collections::BTreeMap;

/// Findings listed per class and group; further occurrences are only counted.
pub const MAX_LISTED: u64 = 20;

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

    /// True when [`repair`](super::repair) can correct this class of defect.
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

/// The result of [`validate`](super::validate).
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
pub(super) struct Collector {
    findings: Vec<Finding>,
    counts: BTreeMap<(String, Class), u64>,
    pub(super) notes: Vec<String>,
}

impl Collector {
    /// Record one occurrence; `describe` gives (location, message) and is called only for the
    /// occurrences listed.
    pub(super) fn add(
        &mut self,
        group: &str,
        class: Class,
        describe: impl FnOnce() -> (String, String),
    ) {
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

    pub(super) fn count(&self, group: &str, class: Class) -> u64 {
        self.counts
            .get(&(group.to_string(), class))
            .copied()
            .unwrap_or(0)
    }

    pub(super) fn into_report(self, path: &str, format: String, checked: Vec<String>) -> Report {
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
