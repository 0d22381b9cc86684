//! BED interval files: reading records and writing lines.
//!
//! Coordinates are 0-based, half-open, as the UCSC BED specification. The reader accepts plain or
//! gzip-compressed files (recognised by their magic bytes), fields separated by tabs or runs of
//! whitespace, and skips blank lines, `#` comments and `track` / `browser` lines. Only the first
//! five columns are interpreted (chrom, start, end, name, score); further columns are ignored.
//! A score of `.` means "no score".

use std::io::{BufRead, Write};
use std::path::Path;

use crate::error::{Error, Result};
use crate::genome::{BinTable, RegionSpec, View};

/// One BED record (the first six columns).
#[derive(Clone, Debug, PartialEq)]
pub struct BedRecord {
    /// Chromosome name.
    pub chrom: String,
    /// Start, 0-based.
    pub start: u64,
    /// End, exclusive.
    pub end: u64,
    /// The 4th column, when present.
    pub name: Option<String>,
    /// The 5th column, when present and not `.`.
    pub score: Option<f64>,
    /// The 6th column (strand), when it is `+` or `-`.
    pub strand: Option<char>,
}

impl BedRecord {
    /// A record with only `chrom start end`.
    pub fn new(chrom: impl Into<String>, start: u64, end: u64) -> Self {
        BedRecord {
            chrom: chrom.into(),
            start,
            end,
            name: None,
            score: None,
            strand: None,
        }
    }

    /// Width in bp (`end - start`).
    pub fn width(&self) -> u64 {
        self.end - self.start
    }
}

/// Call `record` with the 1-based line number, the line and its fields for each line of the
/// BED-like file at `path` (plain or gzip) that holds a record: blank lines, `#` comments and
/// `track` / `browser` lines are skipped; fields are split at tabs when the line has one (and
/// trimmed), else at runs of whitespace. The one line reader under [`read_bed`],
/// [`read_bedpe`], [`read_bin_mask`] and the views of the analyses.
///
/// # Examples
///
/// ```
/// let path = std::env::temp_dir().join(format!("lines-{}.bed", std::process::id()));
/// std::fs::write(&path, "# comment\nchr1\t0\t100\tA\nchr2 5 15\n")?;
/// let mut widths = Vec::new();
/// contactmap::io::bed::for_each_line(&path, |_line_no, _line, fields| {
///     widths.push(fields.len());
///     Ok(())
/// })?;
/// assert_eq!(widths, [4, 3]);
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn for_each_line(
    path: &Path,
    mut record: impl FnMut(u64, &str, &[&str]) -> Result<()>,
) -> Result<()> {
    let reader = crate::io::plumbing::input::open_text(path)?;
    for (index, line) in reader.lines().enumerate() {
        let line_no = index as u64 + 1;
        let line = line.map_err(|e| Error::io(path, e))?;
        let line = line.trim_end_matches('\r');
        let trimmed = line.trim_start();
        if trimmed.is_empty()
            || trimmed.starts_with('#')
            || trimmed.starts_with("track")
            || trimmed.starts_with("browser")
        {
            continue;
        }
        let fields: Vec<&str> = if line.contains('\t') {
            line.split('\t').map(str::trim).collect()
        } else {
            line.split_whitespace().collect()
        };
        record(line_no, line, &fields)?;
    }
    Ok(())
}

/// The records of the BED file named `value` when a file of that name exists, `None` when none
/// does: for options that take a BED file or a literal list (`simulate polymer --ctcf`).
pub fn read_bed_if_file(value: &str) -> Result<Option<Vec<BedRecord>>> {
    let path = Path::new(value);
    if path.exists() {
        read_bed(path).map(Some)
    } else {
        Ok(None)
    }
}

/// Read every record of the BED file at `path` (plain or gzip), in file order.
///
/// Errors name the file and the 1-based line: fewer than 3 fields, a coordinate that is not a
/// non-negative integer, `start > end`, or a 5th column that is neither `.` nor a number.
///
/// # Examples
///
/// ```
/// let path = std::env::temp_dir().join(format!("read-{}.bed", std::process::id()));
/// std::fs::write(&path, "track name=x\nchr1\t100\t250\tpeak\t7\n")?;
/// let records = contactmap::io::bed::read_bed(&path)?;
/// assert_eq!((records[0].start, records[0].width()), (100, 150));
/// assert_eq!(records[0].score, Some(7.0));
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_bed(path: &Path) -> Result<Vec<BedRecord>> {
    let mut records = Vec::new();
    for_each_line(path, |line_no, line, fields| {
        records.push(parse_fields(line, fields).map_err(|m| Error::parse(path, line_no, m))?);
        Ok(())
    })?;
    Ok(records)
}

/// A BED file's records, each with all its fields as written, and its header line (column
/// names) when it has one.
#[derive(Clone, Debug, PartialEq)]
pub struct BedTable {
    /// The column names of the header line, if there is one: a first line whose start and end
    /// are not numbers (`chrom start end name ...`).
    pub header: Option<Vec<String>>,
    /// The records.
    pub records: Vec<BedRecord>,
    /// Per record, all its fields (the coordinates too), as written.
    pub fields: Vec<Vec<String>>,
}

/// Read the BED file at `path` as [`read_bed`] does, keeping each record's fields and the header
/// line's column names (a header is only taken before the first record).
///
/// # Examples
///
/// ```
/// let path = std::env::temp_dir().join(format!("table-{}.bed", std::process::id()));
/// std::fs::write(&path, "chrom\tstart\tend\tclass\nchr1\t100\t250\tCTCF\n")?;
/// let table = contactmap::io::bed::read_bed_table(&path)?;
/// assert_eq!(table.header.as_ref().unwrap()[3], "class");
/// assert_eq!((table.records[0].start, table.fields[0][3].as_str()), (100, "CTCF"));
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_bed_table(path: &Path) -> Result<BedTable> {
    let mut table = BedTable {
        header: None,
        records: Vec::new(),
        fields: Vec::new(),
    };
    for_each_line(path, |line_no, line, fields| {
        let number = |k: usize| fields.get(k).is_some_and(|f| f.parse::<u64>().is_ok());
        if table.records.is_empty() && table.header.is_none() && !number(1) && !number(2) {
            table.header = Some(fields.iter().map(|f| f.to_string()).collect());
            return Ok(());
        }
        let record = parse_fields(line, fields).map_err(|m| Error::parse(path, line_no, m))?;
        table.records.push(record);
        table
            .fields
            .push(fields.iter().map(|f| f.to_string()).collect());
        Ok(())
    })?;
    Ok(table)
}

/// The bins of `bins` that overlap an interval of the BED file at `path` (a blacklist), sorted
/// and unique. Lines whose coordinates are not numbers (a header) are skipped; an interval on a
/// chromosome the bins do not have is an error naming the file and line; intervals are clipped
/// to the span the bins cover (a cut map covers part of a chromosome).
///
/// # Examples
///
/// ```
/// use contactmap::genome::{BinTable, Chrom};
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 100)], 10)?;
/// let path = std::env::temp_dir().join(format!("mask-{}.bed", std::process::id()));
/// std::fs::write(&path, "chrom\tstart\tend\nchr1\t15\t31\n")?;
/// assert_eq!(contactmap::io::bed::read_bin_mask(&path, &bins)?, [1, 2, 3]);
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_bin_mask(path: &Path, bins: &BinTable) -> Result<Vec<usize>> {
    let mut masked = Vec::new();
    for_each_line(path, |line_no, _, fields| {
        if fields.len() < 3 {
            return Err(Error::parse(
                path,
                line_no,
                format!(
                    "expected 3 columns (chrom start end), found {}",
                    fields.len()
                ),
            ));
        }
        let (Ok(start), Ok(end)) = (fields[1].parse::<u64>(), fields[2].parse::<u64>()) else {
            return Ok(());
        };
        let chrom = fields[0];
        let Some(chrom_id) = bins.chrom_id(chrom) else {
            return Err(Error::parse(path, line_no, bins.missing_chrom(chrom)));
        };
        // Bins cover the chromosome's span only (all of it unless the matrix is a cut).
        let span = bins.span(chrom_id);
        let (start, end) = (start.max(span.start), end.min(span.end));
        if start < end && !bins.chrom_bins(chrom_id).is_empty() {
            let lo = bins.bin_at(chrom_id, start);
            let hi = bins.bin_at(chrom_id, end - 1) + 1;
            masked.extend(lo..hi);
        }
        Ok(())
    })?;
    masked.sort_unstable();
    masked.dedup();
    Ok(masked)
}

/// One BEDPE record: a pair of intervals (a loop: `chrom1 start1 end1 chrom2 start2 end2 ...`).
#[derive(Clone, Debug, PartialEq)]
pub struct BedpeRecord {
    /// First anchor.
    pub first: BedRecord,
    /// Second anchor.
    pub second: BedRecord,
    /// The columns after the sixth, as they are.
    pub rest: Vec<String>,
    /// The record's 1-based line in its file (for error messages).
    pub line: u64,
}

impl BedpeRecord {
    /// The record's fields as text: the six coordinates, then the other columns as they were.
    pub fn fields(&self) -> Vec<String> {
        let (a, b) = (&self.first, &self.second);
        let mut fields = vec![
            a.chrom.clone(),
            a.start.to_string(),
            a.end.to_string(),
            b.chrom.clone(),
            b.start.to_string(),
            b.end.to_string(),
        ];
        fields.extend(self.rest.iter().cloned());
        fields
    }

    /// The record as a tab-separated line (without its newline): the six coordinates, then the
    /// other columns as they were.
    pub fn tsv_line(&self) -> String {
        let (a, b) = (&self.first, &self.second);
        let mut line = format!(
            "{}\t{}\t{}\t{}\t{}\t{}",
            a.chrom, a.start, a.end, b.chrom, b.start, b.end
        );
        for field in &self.rest {
            line.push('\t');
            line.push_str(field);
        }
        line
    }
}

/// Read the BEDPE file at `path` (plain or gzip): the first six columns of each line; a header
/// line whose coordinates are not numbers (`chrom1 start1 end1 ...`, as HiCCUPS and cooltools
/// write) and `#` comments are skipped. Errors name the file and the 1-based line.
///
/// # Examples
///
/// ```
/// let path = std::env::temp_dir().join(format!("loops-{}.bedpe", std::process::id()));
/// std::fs::write(&path, "chrom1\tstart1\tend1\tchrom2\tstart2\tend2\nchr1\t0\t10\tchr1\t90\t100\n")?;
/// let loops = contactmap::io::bed::read_bedpe(&path)?;
/// assert_eq!((loops.len(), loops[0].second.start), (1, 90));
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_bedpe(path: &Path) -> Result<Vec<BedpeRecord>> {
    Ok(read_bedpe_table(path)?.records)
}

/// A BEDPE file's records and its header line, when it has one.
#[derive(Clone, Debug, PartialEq)]
pub struct BedpeTable {
    /// The column names of the header line (`chrom1 start1 end1 ...`), if there is one.
    pub header: Option<Vec<String>>,
    /// The records.
    pub records: Vec<BedpeRecord>,
}

impl BedpeTable {
    /// The index of the column named `name` among [`BedpeRecord::rest`] (the columns after the
    /// sixth), from the header.
    pub fn rest_column(&self, name: &str) -> Option<usize> {
        let header = self.header.as_ref()?;
        header.iter().skip(6).position(|h| h == name)
    }
}

/// Read the BEDPE file at `path` as [`read_bedpe`] does, keeping the header line's column names.
///
/// # Examples
///
/// ```
/// let path = std::env::temp_dir().join(format!("dots-{}.bedpe", std::process::id()));
/// std::fs::write(&path, "chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tcount\nchr1\t0\t10\tchr1\t90\t100\t7\n")?;
/// let table = contactmap::io::bed::read_bedpe_table(&path)?;
/// assert_eq!(table.rest_column("count"), Some(0));
/// assert_eq!(table.records[0].rest[0], "7");
/// assert_eq!(table.records[0].tsv_line(), "chr1\t0\t10\tchr1\t90\t100\t7");
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_bedpe_table(path: &Path) -> Result<BedpeTable> {
    let mut records = Vec::new();
    let mut header = None;
    for_each_line(path, |line_no, _, fields| {
        if fields.len() < 6 {
            return Err(Error::parse(
                path,
                line_no,
                format!(
                    "expected at least 6 columns (chrom1 start1 end1 chrom2 start2 end2), found {}",
                    fields.len()
                ),
            ));
        }
        if records.is_empty()
            && fields[1].parse::<u64>().is_err()
            && fields[4].parse::<u64>().is_err()
        {
            header = Some(fields.iter().map(|f| f.to_string()).collect());
            return Ok(()); // header line
        }
        records.push(bedpe_record(fields, line_no).map_err(|m| Error::parse(path, line_no, m))?);
        Ok(())
    })?;
    Ok(BedpeTable { header, records })
}

/// A BEDPE record from a line's fields (at least 6); `line` is kept for error messages.
fn bedpe_record(fields: &[&str], line: u64) -> std::result::Result<BedpeRecord, String> {
    let anchor = |chrom: &str, start: &str, end: &str| {
        let (start, end) = interval(start, end)?;
        Ok::<_, String>(BedRecord::new(chrom, start, end))
    };
    Ok(BedpeRecord {
        first: anchor(fields[0], fields[1], fields[2])?,
        second: anchor(fields[3], fields[4], fields[5])?,
        rest: fields[6..].iter().map(|f| f.to_string()).collect(),
        line,
    })
}

impl BedTable {
    /// A table from rows of fields as written (a DataFrame's rows as text: `chrom start end
    /// ...`), with the column names `header`; errors name `source` and the 1-based row, as
    /// [`read_bed_table`]'s name the file and line.
    ///
    /// ```
    /// use contactmap::io::bed::BedTable;
    /// let rows = vec![vec!["chr1".to_string(), "10".into(), "20".into(), "a".into()]];
    /// let table = BedTable::from_rows("features", None, rows)?;
    /// assert_eq!((table.records[0].start, table.records[0].name.as_deref()), (10, Some("a")));
    /// let bad = vec![vec!["chr1".to_string(), "x".into(), "20".into()]];
    /// assert!(BedTable::from_rows("features", None, bad).is_err());
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn from_rows(
        source: &str,
        header: Option<Vec<String>>,
        rows: Vec<Vec<String>>,
    ) -> Result<BedTable> {
        let mut records = Vec::with_capacity(rows.len());
        for (k, row) in rows.iter().enumerate() {
            let fields: Vec<&str> = row.iter().map(|f| f.trim()).collect();
            let record = parse_fields(&fields.join("\t"), &fields)
                .map_err(|m| Error::parse(source, k as u64 + 1, m))?;
            records.push(record);
        }
        Ok(BedTable {
            header,
            records,
            fields: rows,
        })
    }
}

impl BedpeTable {
    /// A table from rows of fields as written (`chrom1 start1 end1 chrom2 start2 end2 ...`),
    /// with the column names `header`; errors name `source` and the 1-based row.
    pub fn from_rows(
        source: &str,
        header: Option<Vec<String>>,
        rows: Vec<Vec<String>>,
    ) -> Result<BedpeTable> {
        let mut records = Vec::with_capacity(rows.len());
        for (k, row) in rows.iter().enumerate() {
            let line = k as u64 + 1;
            if row.len() < 6 {
                return Err(Error::parse(
                    source,
                    line,
                    format!(
                        "expected at least 6 columns (chrom1 start1 end1 chrom2 start2 end2), found {}",
                        row.len()
                    ),
                ));
            }
            let fields: Vec<&str> = row.iter().map(|f| f.trim()).collect();
            records.push(bedpe_record(&fields, line).map_err(|m| Error::parse(source, line, m))?);
        }
        Ok(BedpeTable { header, records })
    }
}

/// The two interval formats a feature file can be in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeatureKind {
    /// One interval per line: `chrom start end ...`.
    Bed,
    /// A pair of intervals per line: `chrom1 start1 end1 chrom2 start2 end2 ...`.
    Bedpe,
}

/// How a feature file's format is chosen: given (`--features-format bed|bedpe`), or found by
/// [`detect_feature_kind`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FeatureFormat {
    /// From the file name's extension, else from the first data line.
    #[default]
    Auto,
    /// One interval per line.
    Bed,
    /// A pair of intervals per line.
    Bedpe,
}

/// The format a feature file is read in, and why: the reason goes into the messages of errors
/// met while reading it, so that a wrong guess is seen as one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FeatureDetection {
    /// The format the file is read in.
    pub kind: FeatureKind,
    /// Why, in words (`its extension is .bedpe`, ...).
    pub reason: String,
}

impl FeatureKind {
    /// `BED` or `BEDPE`.
    pub fn name(self) -> &'static str {
        match self {
            FeatureKind::Bed => "BED",
            FeatureKind::Bedpe => "BEDPE",
        }
    }
}

/// The format of the feature file at `path` under `format`: as given, else from the file name's
/// extension (`.bedpe`, `.bed`, `.narrowPeak`, `.broadPeak`, each also with `.gz`: coolpuppy
/// decides from the extension), else from its first data line (headers, `track` / `browser`
/// lines and `#` comments skipped): BEDPE when it has at least 6 columns and columns 5 and 6
/// are whole numbers with start <= end (a BED line's 6th column is the strand, never a number),
/// whatever column 4 holds (chromosome names such as Ensembl's `21` are numbers too). `None`
/// when the format is to be found and the file has no data line.
///
/// # Examples
///
/// ```
/// use contactmap::io::bed::{detect_feature_kind, FeatureFormat, FeatureKind};
///
/// let path = std::env::temp_dir().join(format!("kind-{}.txt", std::process::id()));
/// let kind = |p: &std::path::Path| detect_feature_kind(p, FeatureFormat::Auto).map(|d| d.unwrap().kind);
/// std::fs::write(&path, "chr1\t0\t10\tchr1\t90\t100\n")?;
/// assert_eq!(kind(&path)?, FeatureKind::Bedpe);
/// std::fs::write(&path, "21\t0\t10\t21\t90\t100\n")?; // Ensembl names
/// assert_eq!(kind(&path)?, FeatureKind::Bedpe);
/// std::fs::write(&path, "chr1\t0\t10\tpeak\t5\t+\n")?;
/// assert_eq!(kind(&path)?, FeatureKind::Bed);
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn detect_feature_kind(path: &Path, format: FeatureFormat) -> Result<Option<FeatureDetection>> {
    let given = |kind: FeatureKind| FeatureDetection {
        kind,
        reason: format!("the format was given as {}", kind.name()),
    };
    match format {
        FeatureFormat::Bed => return Ok(Some(given(FeatureKind::Bed))),
        FeatureFormat::Bedpe => return Ok(Some(given(FeatureKind::Bedpe))),
        FeatureFormat::Auto => {}
    }
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let stem = name
        .strip_suffix(".gz")
        .or_else(|| name.strip_suffix(".bgz"))
        .unwrap_or(&name);
    let extension = stem.rsplit_once('.').map(|(_, e)| e).unwrap_or("");
    let by_extension = match extension {
        "bedpe" => Some(FeatureKind::Bedpe),
        "bed" | "narrowpeak" | "broadpeak" => Some(FeatureKind::Bed),
        _ => None,
    };
    if let Some(kind) = by_extension {
        return Ok(Some(FeatureDetection {
            kind,
            reason: format!("its extension is .{extension}"),
        }));
    }
    let mut found = None;
    for_each_line(path, |line_no, _, fields| {
        let whole = |k: usize| fields.get(k).and_then(|f| f.parse::<u64>().ok());
        if found.is_some() || whole(1).is_none() || whole(2).is_none() {
            return Ok(()); // decided, or a header line
        }
        let pair = matches!((whole(4), whole(5)), (Some(start), Some(end)) if start <= end);
        found = Some(if pair {
            FeatureDetection {
                kind: FeatureKind::Bedpe,
                reason: format!(
                    "columns 5 and 6 of its first record (line {line_no}) are coordinates"
                ),
            }
        } else {
            FeatureDetection {
                kind: FeatureKind::Bed,
                reason: format!(
                    "its first record (line {line_no}) has no coordinates in columns 5 and 6"
                ),
            }
        });
        Ok(())
    })?;
    Ok(found)
}

/// Whether the file at `path` holds BED or BEDPE records: [`detect_feature_kind`] with the
/// format to be found. `None` for a file without a data line.
///
/// # Examples
///
/// ```
/// use contactmap::io::bed::{feature_kind, FeatureKind};
///
/// let path = std::env::temp_dir().join(format!("kind-{}.txt", std::process::id()));
/// std::fs::write(&path, "chr1\t0\t10\tchr1\t90\t100\n")?;
/// assert_eq!(feature_kind(&path)?, Some(FeatureKind::Bedpe));
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn feature_kind(path: &Path) -> Result<Option<FeatureKind>> {
    Ok(detect_feature_kind(path, FeatureFormat::Auto)?.map(|d| d.kind))
}

/// A feature file's records: intervals (BED) or pairs of intervals (BEDPE).
#[derive(Clone, Debug, PartialEq)]
pub enum FeatureTable {
    /// One interval per line.
    Bed(BedTable),
    /// A pair of intervals per line.
    Bedpe(BedpeTable),
}

/// Read the feature file at `path` in the format [`detect_feature_kind`] finds under `format`;
/// an error met while reading a line says in which format the file was read and why, and how
/// to read it in the other (`--features-format`). The detection is returned with the table.
///
/// # Examples
///
/// ```
/// use contactmap::io::bed::{read_features, FeatureFormat, FeatureTable};
///
/// let path = std::env::temp_dir().join(format!("features-{}.tsv", std::process::id()));
/// std::fs::write(&path, "chrom1\tstart1\tend1\tchrom2\tstart2\tend2\n21\t0\t10\t21\t90\t100\n")?;
/// let (table, _) = read_features(&path, FeatureFormat::Auto)?;
/// assert!(matches!(table, FeatureTable::Bedpe(t) if t.records.len() == 1));
/// let error = read_features(&path, FeatureFormat::Bed).unwrap_err().to_string();
/// assert!(error.contains("read as BED"), "{error}");
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_features(
    path: &Path,
    format: FeatureFormat,
) -> Result<(FeatureTable, FeatureDetection)> {
    let detection = detect_feature_kind(path, format)?
        .ok_or_else(|| Error::format(path, "no feature in this file (no data line)"))?;
    let read = match detection.kind {
        FeatureKind::Bed => read_bed_table(path).map(FeatureTable::Bed),
        FeatureKind::Bedpe => read_bedpe_table(path).map(FeatureTable::Bedpe),
    };
    let table = read.map_err(|error| match error {
        Error::Parse {
            path,
            line,
            message,
        } => {
            let other = match detection.kind {
                FeatureKind::Bed => FeatureKind::Bedpe,
                FeatureKind::Bedpe => FeatureKind::Bed,
            };
            let hint = match format {
                FeatureFormat::Auto => format!(
                    "; --features-format {} reads it as {}",
                    other.name().to_ascii_lowercase(),
                    other.name()
                ),
                _ => String::new(),
            };
            Error::Parse {
                path,
                line,
                message: format!(
                    "{message} (read as {}: {}{hint})",
                    detection.kind.name(),
                    detection.reason
                ),
            }
        }
        other => other,
    })?;
    Ok((table, detection))
}

/// `start` and `end` as numbers, `start <= end`.
fn interval(start: &str, end: &str) -> std::result::Result<(u64, u64), String> {
    let coordinate = |what: &str, text: &str| {
        text.parse::<u64>()
            .map_err(|_| format!("{what} '{text}' is not a non-negative whole number"))
    };
    let (start, end) = (coordinate("start", start)?, coordinate("end", end)?);
    if start > end {
        return Err(format!("start {start} is after end {end}"));
    }
    Ok((start, end))
}

/// The record of one line's `fields`.
fn parse_fields(line: &str, fields: &[&str]) -> std::result::Result<BedRecord, String> {
    if fields.len() < 3 {
        return Err(format!(
            "expected at least 3 columns (chrom start end), found {}: '{line}'",
            fields.len()
        ));
    }
    let (start, end) = interval(fields[1], fields[2])?;
    let name = fields.get(3).map(|s| s.to_string());
    let score = match fields.get(4) {
        None | Some(&".") => None,
        Some(text) => Some(
            text.parse::<f64>()
                .map_err(|_| format!("score '{text}' is neither '.' nor a number"))?,
        ),
    };
    let strand = match fields.get(5) {
        None | Some(&".") => None,
        Some(&"+") => Some('+'),
        Some(&"-") => Some('-'),
        Some(text) => return Err(format!("strand '{text}' is not +, - or .")),
    };
    Ok(BedRecord {
        chrom: fields[0].to_string(),
        start,
        end,
        name,
        score,
        strand,
    })
}

/// Write `chrom start end` and then `extra` fields, tab-separated, as one line.
pub fn write_bed_line(
    out: &mut impl Write,
    chrom: &str,
    start: u64,
    end: u64,
    extra: &[&str],
) -> std::io::Result<()> {
    write!(out, "{chrom}\t{start}\t{end}")?;
    for field in extra {
        write!(out, "\t{field}")?;
    }
    writeln!(out)
}

/// BED text of bin ranges: one line `chrom start end extra...` per `(first, end, extra)`, the
/// bins `first..end` (one chromosome) of `bins`.
///
/// # Examples
///
/// ```
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::bed::bins_bed;
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 1_000)], 100)?;
/// let text = bins_bed(&bins, [(2, 5, vec!["1".to_string()])].into_iter());
/// assert_eq!(text, b"chr1\t200\t500\t1\n");
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn bins_bed(
    bins: &BinTable,
    rows: impl Iterator<Item = (usize, usize, Vec<String>)>,
) -> Vec<u8> {
    let mut text = Vec::new();
    for (first, end, extra) in rows {
        let (a, b) = (bins.bin(first), bins.bin(end - 1));
        let chrom = &bins.chroms()[a.chrom_id].name;
        let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
        write_bed_line(&mut text, chrom, a.start, b.end, &extra).expect("writing to memory");
    }
    text
}

/// The view ([`View`], cooltools' view frame) of the BED file at `path` (`chrom start end
/// [name]`, plain or gzip; `#`, `track` and `browser` lines skipped), checked against `bins` as
/// [`View::new`] does; errors name the file (and the line for a malformed one).
///
/// # Examples
///
/// ```
/// use contactmap::io::bed::read_view;
/// use contactmap::genome::{BinTable, Chrom};
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 1_000)], 100)?;
/// let path = std::env::temp_dir().join(format!("view-{}.bed", std::process::id()));
/// std::fs::write(&path, "chr1\t0\t500\tarm_p\nchr1\t500\t1000\n")?;
/// let view = read_view(&path, &bins)?;
/// assert_eq!(view.regions()[1].name, "chr1:500-1000");
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_view(path: &Path, bins: &BinTable) -> Result<View> {
    let mut specs = Vec::new();
    for_each_line(path, |line_no, _, fields| {
        if !(3..=4).contains(&fields.len()) {
            return Err(Error::parse(
                path,
                line_no,
                format!(
                    "expected 3 or 4 columns (chrom start end [name]), found {}",
                    fields.len()
                ),
            ));
        }
        let number = |text: &str, what: &str| {
            text.parse::<u64>().map_err(|_| {
                Error::parse(
                    path,
                    line_no,
                    format!("{what} '{text}' is not a non-negative integer"),
                )
            })
        };
        specs.push(RegionSpec {
            chrom: fields[0].to_string(),
            start_bp: number(fields[1], "start")?,
            end_bp: number(fields[2], "end")?,
            name: fields.get(3).map(|n| n.to_string()),
        });
        Ok(())
    })?;
    View::new(bins, &specs).map_err(|e| Error::format(path, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn reads_records_skipping_headers_and_comments() {
        let dir = tempfile::tempdir().unwrap();
        let path = write(
            dir.path(),
            "a.bed",
            "track name=x\nbrowser position chr1\n# comment\n\nchr1\t0\t100\n\
             chr1 100 200 b1 3.5 + extra\nchr2\t5\t5\tz\t.\r\n",
        );
        let records = read_bed(&path).unwrap();
        assert_eq!(
            records,
            vec![
                BedRecord::new("chr1", 0, 100),
                BedRecord {
                    chrom: "chr1".into(),
                    start: 100,
                    end: 200,
                    name: Some("b1".into()),
                    score: Some(3.5),
                    strand: Some('+'),
                },
                BedRecord {
                    chrom: "chr2".into(),
                    start: 5,
                    end: 5,
                    name: Some("z".into()),
                    score: None,
                    strand: None,
                },
            ]
        );
        assert_eq!(records[1].width(), 100);
    }

    #[test]
    fn reads_gzip() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.bed.gz");
        let mut encoder = flate2::write::GzEncoder::new(
            std::fs::File::create(&path).unwrap(),
            flate2::Compression::default(),
        );
        encoder.write_all(b"chrX\t10\t20\n").unwrap();
        encoder.finish().unwrap();
        assert_eq!(
            read_bed(&path).unwrap(),
            vec![BedRecord::new("chrX", 10, 20)]
        );
    }

    #[test]
    fn bad_lines_name_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        for (text, expected) in [
            ("chr1\t0\t10\nchr1\tx\t10\n", ":2: start 'x'"),
            ("chr1\t0\n", ":1: expected at least 3 columns"),
            ("chr1\t-5\t10\n", ":1: start '-5'"),
            ("chr1\t0\t10.5\n", ":1: end '10.5'"),
            ("#h\nchr1\t20\t10\n", ":2: start 20 is after end 10"),
            ("chr1\t0\t10\tn\tlots\n", ":1: score 'lots'"),
        ] {
            let path = write(dir.path(), "bad.bed", text);
            let message = read_bed(&path).unwrap_err().to_string();
            assert!(
                message.contains(&format!("bad.bed{expected}")),
                "{message} should contain {expected}"
            );
        }
        let missing = read_bed(&dir.path().join("missing.bed")).unwrap_err();
        assert!(missing.to_string().contains("missing.bed"));
    }

    #[test]
    fn masks_the_bins_a_blacklist_overlaps() {
        use crate::genome::Chrom;
        let bins = BinTable::fixed(vec![Chrom::new("a", 100), Chrom::new("b", 55)], 10).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = write(
            dir.path(),
            "black.bed",
            "track name=x\nchrom\tstart\tend\na\t15\t31\tfoo\nb\t50\t1000\n#c\t0\t1\na\t40\t40\n",
        );
        assert_eq!(read_bin_mask(&path, &bins).unwrap(), vec![1, 2, 3, 15]);
        let path = write(dir.path(), "black.bed", "a 0 10\nchrZ\t0\t10\n");
        let err = read_bin_mask(&path, &bins).unwrap_err().to_string();
        assert!(err.contains(":2:") && err.contains("chrZ"), "{err}");
    }

    #[test]
    fn writes_lines() {
        let mut out = Vec::new();
        write_bed_line(&mut out, "chr1", 0, 10, &[]).unwrap();
        write_bed_line(&mut out, "chr2", 5, 15, &["0", "x"]).unwrap();
        assert_eq!(out, b"chr1\t0\t10\nchr2\t5\t15\t0\tx\n");
    }
}
