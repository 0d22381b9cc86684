//! Chromosomes, bin tables and genomic regions.
//!
//! Coordinates are 0-based and half-open, as in cooler and BED: a bin `start..end` covers the bases
//! `start, start + 1, ..., end - 1`. Bins are identified by their index in the genome-wide bin table,
//! chromosome after chromosome in the order of the chromosome table.
//!
//! Regions are written as cooler and bioframe write them: `chr2L`, `chr2L:1,000,000-2,000,000`,
//! `chr2L:1000000-2000000`, and `chr2L:1.5M-2M` (suffixes `k`, `kb`, `M`, `Mb`, `G`, `Gb`). A region
//! selects every bin that overlaps it, as `cooler dump --range` does.

use std::ops::Range;

use crate::error::{Error, Result};

/// A chromosome (or contig / scaffold): its name and length.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Chrom {
    /// Name as in the file ("chr2L", "1", "chrM" ...).
    pub name: String,
    /// Length in base pairs.
    pub length_bp: u64,
}

impl Chrom {
    /// A chromosome named `name` of `length_bp` base pairs.
    pub fn new(name: impl Into<String>, length_bp: u64) -> Self {
        Chrom {
            name: name.into(),
            length_bp,
        }
    }
}

/// One bin of the table: chromosome index and half-open coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bin {
    /// Index of the chromosome in the chromosome table.
    pub chrom_id: usize,
    /// 0-based start (inclusive).
    pub start: u64,
    /// End (exclusive).
    pub end: u64,
}

/// The genome-wide bin table: chromosomes cut into fixed-size or variable-size bins.
///
/// Bins are sorted by chromosome (in chromosome-table order), then by start; they tile each
/// chromosome's covered span without gaps or overlaps. The span is normally the whole chromosome;
/// a matrix cut out of a chromosome (HiCExplorer writes such files, cooler and cooltools compute on
/// them) covers `first start .. last end` only. Fixed bins are `bin_size_bp` long except the last of
/// each chromosome, which ends at the span's end.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BinTable {
    chroms: Vec<Chrom>,
    bin_size_bp: Option<u64>,
    /// First bin of each chromosome; `chrom_offsets[n_chroms] == n_bins`.
    chrom_offsets: Vec<usize>,
    /// Starts of every bin (used for variable bins; for fixed bins, computed on the fly).
    starts: Vec<u64>,
    ends: Vec<u64>,
    /// The part of each chromosome the bins cover (`0..length_bp` unless the matrix is a cut).
    spans: Vec<Range<u64>>,
}

/// The most bins a table may hold: bin ids are 32-bit in pixel keys (and in the .hic format), and
/// a human genome at 1 bp is 3.1e9 bins.
pub const MAX_BINS: usize = u32::MAX as usize;

fn too_many_bins(bin_size_bp: u64) -> Error {
    Error::Invalid(format!(
        "bins of {bin_size_bp} bp make more than {MAX_BINS} bins: the chromosome lengths or the \
         bin size are wrong"
    ))
}

impl BinTable {
    /// Chromosomes cut into bins of `bin_size_bp` base pairs.
    pub fn fixed(chroms: Vec<Chrom>, bin_size_bp: u64) -> Result<Self> {
        let spans = chroms.iter().map(|c| 0..c.length_bp).collect();
        BinTable::fixed_spans(chroms, bin_size_bp, spans)
    }

    /// Chromosomes cut into bins of `bin_size_bp` base pairs over `spans[c]` only: the bins of
    /// chromosome `c` start at `spans[c].start` and the last ends at `spans[c].end` (a matrix cut
    /// out of the chromosomes). An empty span gives the chromosome no bins.
    pub fn fixed_spans(
        chroms: Vec<Chrom>,
        bin_size_bp: u64,
        spans: Vec<Range<u64>>,
    ) -> Result<Self> {
        if bin_size_bp == 0 {
            return Err(Error::Invalid("bin size must be positive".into()));
        }
        check_chrom_names(&chroms)?;
        if spans.len() != chroms.len() {
            return Err(Error::Invalid(format!(
                "{} chromosome spans for {} chromosomes",
                spans.len(),
                chroms.len()
            )));
        }
        let mut chrom_offsets = Vec::with_capacity(chroms.len() + 1);
        let mut n = 0usize;
        for (chrom, span) in chroms.iter().zip(&spans) {
            if span.end > chrom.length_bp || span.start > span.end {
                return Err(Error::Invalid(format!(
                    "bins of {} over {}-{}: not within the chromosome's {} bp",
                    chrom.name, span.start, span.end, chrom.length_bp
                )));
            }
            chrom_offsets.push(n);
            n = usize::try_from((span.end - span.start).div_ceil(bin_size_bp))
                .ok()
                .and_then(|bins| n.checked_add(bins))
                .filter(|&total| total <= MAX_BINS)
                .ok_or_else(|| too_many_bins(bin_size_bp))?;
        }
        chrom_offsets.push(n);
        Ok(BinTable {
            chroms,
            bin_size_bp: Some(bin_size_bp),
            chrom_offsets,
            starts: Vec::new(),
            ends: Vec::new(),
            spans,
        })
    }

    /// A table of variable-size bins given as `(chrom_id, start, end)` in genome order.
    ///
    /// The bins must tile a span of each chromosome: each starts where the previous ended. The
    /// span is normally the whole chromosome (the first bin starts at 0 and the last ends at the
    /// chromosome's length); a cut-out matrix may start later and end earlier.
    pub fn variable(chroms: Vec<Chrom>, bins: &[Bin]) -> Result<Self> {
        check_chrom_names(&chroms)?;
        let mut chrom_offsets = vec![0usize; chroms.len() + 1];
        let mut starts = Vec::with_capacity(bins.len());
        let mut ends = Vec::with_capacity(bins.len());
        let mut spans: Vec<Range<u64>> = vec![0..0; chroms.len()];
        let mut previous: Option<Bin> = None;
        for (index, bin) in bins.iter().enumerate() {
            if bin.chrom_id >= chroms.len() {
                return Err(Error::Invalid(format!(
                    "bin {index}: chromosome index {} out of range (there are {} chromosomes)",
                    bin.chrom_id,
                    chroms.len()
                )));
            }
            let expected_start = match previous {
                Some(p) if p.chrom_id == bin.chrom_id => p.end,
                Some(p) if p.chrom_id > bin.chrom_id => {
                    return Err(Error::Invalid(format!(
                        "bin {index}: bins are not sorted by chromosome"
                    )))
                }
                // The first bin of a chromosome may start anywhere (a cut-out matrix).
                _ => {
                    spans[bin.chrom_id] = bin.start..bin.start;
                    bin.start
                }
            };
            if bin.start != expected_start || bin.end <= bin.start {
                return Err(Error::Invalid(format!(
                    "bin {index} ({}:{}-{}): bins must tile the chromosome (expected a bin starting at {expected_start})",
                    chroms[bin.chrom_id].name, bin.start, bin.end
                )));
            }
            if bin.end > chroms[bin.chrom_id].length_bp {
                return Err(Error::Invalid(format!(
                    "bin {index} ({}:{}-{}) ends past the chromosome's length {}",
                    chroms[bin.chrom_id].name, bin.start, bin.end, chroms[bin.chrom_id].length_bp
                )));
            }
            // The end of this chromosome's bins so far; chromosomes without bins take the end
            // of the one before them (the running maximum below), in one pass.
            chrom_offsets[bin.chrom_id + 1] = index + 1;
            starts.push(bin.start);
            ends.push(bin.end);
            spans[bin.chrom_id].end = bin.end;
            previous = Some(*bin);
        }
        for c in 1..chrom_offsets.len() {
            chrom_offsets[c] = chrom_offsets[c].max(chrom_offsets[c - 1]);
        }
        Ok(BinTable {
            chroms,
            bin_size_bp: None,
            chrom_offsets,
            starts,
            ends,
            spans,
        })
    }

    /// Build a table from explicit bins, detecting whether they are fixed-size.
    ///
    /// Readers use this: the candidate size is `bin_size_hint` (a file's own bin-size attribute)
    /// or else the largest bin; if the bins equal `BinTable::fixed` with that size, the result is
    /// a fixed table, otherwise a variable one.
    pub fn from_bins(chroms: Vec<Chrom>, bins: &[Bin], bin_size_hint: Option<u64>) -> Result<Self> {
        let variable = BinTable::variable(chroms, bins)?;
        let largest = bins.iter().map(|b| b.end - b.start).max();
        if let Some(size) = bin_size_hint.filter(|&s| s > 0).or(largest) {
            // A size that cannot tile the spans (too many bins) means variable bins.
            let fixed =
                BinTable::fixed_spans(variable.chroms.clone(), size, variable.spans.clone());
            if let Ok(fixed) = fixed {
                if fixed.n_bins() == bins.len() && fixed.iter().zip(bins).all(|(a, b)| a == *b) {
                    return Ok(fixed);
                }
            }
        }
        Ok(variable)
    }

    /// Why `other` is not this bin table (`None` when it is): the first difference of
    /// chromosomes, bin size or bins, worded for an error message.
    ///
    /// ```
    /// use contactmap::genome::{BinTable, Chrom};
    /// let a = BinTable::fixed(vec![Chrom::new("chr1", 1_000)], 100)?;
    /// let b = BinTable::fixed(vec![Chrom::new("chr1", 1_000)], 200)?;
    /// assert_eq!(a.difference(&a), None);
    /// assert_eq!(a.difference(&b).as_deref(), Some("bin size 200 instead of 100"));
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn difference(&self, other: &BinTable) -> Option<String> {
        let (a, b) = (self, other);
        if a.n_chroms() != b.n_chroms() {
            return Some(format!(
                "{} chromosomes instead of {}",
                b.n_chroms(),
                a.n_chroms()
            ));
        }
        for (x, y) in a.chroms().iter().zip(b.chroms()) {
            if x.name != y.name || x.length_bp != y.length_bp {
                return Some(format!(
                    "chromosome {} of {} bp where {} of {} bp was expected",
                    y.name, y.length_bp, x.name, x.length_bp
                ));
            }
        }
        if a.bin_size_bp() != b.bin_size_bp() {
            return Some(match (a.bin_size_bp(), b.bin_size_bp()) {
                (Some(x), Some(y)) => format!("bin size {y} instead of {x}"),
                _ => "variable bins on one side only".into(),
            });
        }
        if a.n_bins() != b.n_bins() {
            return Some(format!("{} bins instead of {}", b.n_bins(), a.n_bins()));
        }
        if a.bin_size_bp().is_none() {
            if let Some(k) = (0..a.n_bins()).find(|&k| a.bin(k) != b.bin(k)) {
                return Some(format!("bin {k} differs"));
            }
        }
        None
    }

    /// The chromosome table.
    pub fn chroms(&self) -> &[Chrom] {
        &self.chroms
    }

    /// Number of chromosomes.
    pub fn n_chroms(&self) -> usize {
        self.chroms.len()
    }

    /// Number of bins genome-wide.
    pub fn n_bins(&self) -> usize {
        *self.chrom_offsets.last().unwrap_or(&0)
    }

    /// The bin size for fixed tables, `None` for variable ones.
    pub fn bin_size_bp(&self) -> Option<u64> {
        self.bin_size_bp
    }

    /// Index of the chromosome called `name`.
    pub fn chrom_id(&self, name: &str) -> Option<usize> {
        self.chroms.iter().position(|c| c.name == name)
    }

    /// Why chromosome `name` is not found, for messages: `no chromosome 'chr21' in this matrix
    /// (it has 1, 2, ...)`, and when the matrix has it under the other naming (with or without
    /// UCSC's `chr` prefix, as Ensembl and NCBI name them), that and how to match the names.
    ///
    /// ```
    /// use contactmap::genome::{BinTable, Chrom};
    /// let bins = BinTable::fixed(vec![Chrom::new("21", 100), Chrom::new("22", 100)], 10)?;
    /// let message = bins.missing_chrom("chr21");
    /// assert!(message.contains("no chromosome 'chr21'"), "{message}");
    /// assert!(message.contains("'21'"), "{message}");
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn missing_chrom(&self, name: &str) -> String {
        let names: Vec<&str> = self
            .chroms
            .iter()
            .take(8)
            .map(|c| c.name.as_str())
            .collect();
        let more = if self.chroms.len() > 8 { ", ..." } else { "" };
        let mut message = format!(
            "no chromosome '{name}' in this matrix (it has {}{more})",
            names.join(", ")
        );
        if let Some(hint) = self.naming_hint(name) {
            message.push_str(": ");
            message.push_str(&hint);
        }
        message
    }

    /// When chromosome `name` is missing but the matrix has it with or without the `chr`
    /// prefix: what differs and how to match the names. `None` otherwise.
    pub fn naming_hint(&self, name: &str) -> Option<String> {
        let (other, fix) = match name.strip_prefix("chr") {
            Some(bare) => (bare.to_string(), "sed 's/^chr//'"),
            None => (format!("chr{name}"), "sed 's/^/chr/'"),
        };
        self.chrom_id(&other)?;
        Some(format!(
            "the matrix names it '{other}': the names differ by the 'chr' prefix (rename them \
             in the other file, e.g. with {fix})"
        ))
    }

    /// First bin of each chromosome, plus the total number of bins at the end (cooler's
    /// `indexes/chrom_offset`).
    pub fn chrom_offsets(&self) -> &[usize] {
        &self.chrom_offsets
    }

    /// The bins of chromosome `chrom_id`.
    pub fn chrom_bins(&self, chrom_id: usize) -> Range<usize> {
        self.chrom_offsets[chrom_id]..self.chrom_offsets[chrom_id + 1]
    }

    /// The part of chromosome `chrom_id` its bins cover: `0..length_bp` unless the matrix was
    /// cut out of the chromosome (empty when the chromosome has no bins).
    pub fn span(&self, chrom_id: usize) -> Range<u64> {
        self.spans[chrom_id].clone()
    }

    /// True when some chromosome's bins do not cover it whole (a cut-out matrix).
    pub fn is_cut(&self) -> bool {
        self.chroms
            .iter()
            .zip(&self.spans)
            .any(|(c, s)| s.start != 0 || s.end != c.length_bp)
    }

    /// The chromosome of bin `bin_id`.
    pub fn chrom_of(&self, bin_id: usize) -> usize {
        // partition_point gives the first chromosome whose offset is > bin_id.
        self.chrom_offsets.partition_point(|&o| o <= bin_id) - 1
    }

    /// Bin `bin_id` (panics when out of range; check against `n_bins` first).
    pub fn bin(&self, bin_id: usize) -> Bin {
        let chrom_id = self.chrom_of(bin_id);
        match self.bin_size_bp {
            Some(size) => {
                let local = (bin_id - self.chrom_offsets[chrom_id]) as u64;
                let span = &self.spans[chrom_id];
                let start = span.start + local * size;
                Bin {
                    chrom_id,
                    start,
                    end: (start + size).min(span.end),
                }
            }
            None => Bin {
                chrom_id,
                start: self.starts[bin_id],
                end: self.ends[bin_id],
            },
        }
    }

    /// Iterator over all bins in order.
    pub fn iter(&self) -> impl Iterator<Item = Bin> + '_ {
        (0..self.n_bins()).map(|bin_id| self.bin(bin_id))
    }

    /// The bin of chromosome `chrom_id` that contains position `pos_bp` (clamped to the first and
    /// the last bin).
    pub fn bin_at(&self, chrom_id: usize, pos_bp: u64) -> usize {
        let range = self.chrom_bins(chrom_id);
        if range.is_empty() {
            return range.start;
        }
        match self.bin_size_bp {
            Some(size) => {
                let local = pos_bp.saturating_sub(self.spans[chrom_id].start) / size;
                (range.start + local as usize).min(range.end - 1)
            }
            None => {
                let ends = &self.ends[range.clone()];
                (range.start + ends.partition_point(|&e| e <= pos_bp)).min(range.end - 1)
            }
        }
    }

    /// The bins overlapping `region`, as a half-open range of bin ids.
    pub fn region_bins(&self, region: &Region) -> Result<Range<usize>> {
        if self.chrom_id(&region.chrom).is_none() {
            // "chr1:xyz-100" was kept whole as a name; if "chr1" exists, the coordinates are bad.
            if let Some((prefix, coords)) = region.chrom.rsplit_once(':') {
                if self.chrom_id(prefix).is_some() {
                    return Err(Error::region(
                        region.to_string(),
                        format!("'{coords}' is not a position range (expected start-end, e.g. 1,000,000-2,000,000)"),
                    ));
                }
            }
        }
        let chrom_id = self
            .chrom_id(&region.chrom)
            .ok_or_else(|| Error::region(region.to_string(), self.missing_chrom(&region.chrom)))?;
        let length = self.chroms[chrom_id].length_bp;
        let start = region.start.unwrap_or(0);
        let end = region.end.unwrap_or(length);
        if end > length {
            return Err(Error::region(
                region.to_string(),
                format!(
                    "end {end} is past the length of {} ({length})",
                    region.chrom
                ),
            ));
        }
        if start >= end {
            let range = self.chrom_bins(chrom_id);
            if start == end && range.is_empty() {
                return Ok(range);
            }
            return Err(Error::region(
                region.to_string(),
                format!("start {start} is not before end {end}"),
            ));
        }
        // The bins overlapping start..end; none when the region lies outside a cut-out span.
        let span = &self.spans[chrom_id];
        let range = self.chrom_bins(chrom_id);
        if start >= span.end || end <= span.start {
            let at = if end <= span.start {
                range.start
            } else {
                range.end
            };
            return Ok(at..at);
        }
        let lo = self.bin_at(chrom_id, start);
        let hi = self.bin_at(chrom_id, end - 1) + 1;
        Ok(lo..hi)
    }

    /// Parse `text` as a region and return its bins.
    pub fn parse_region_bins(&self, text: &str) -> Result<Range<usize>> {
        self.region_bins(&Region::parse(text)?)
    }

    /// Coarsen a fixed table to `factor` times its bin size.
    pub fn coarsen(&self, factor: u64) -> Result<BinTable> {
        if self.is_cut() {
            return Err(Error::Invalid(
                "bin tables that do not cover whole chromosomes cannot be coarsened".into(),
            ));
        }
        match self.bin_size_bp {
            Some(size) if factor > 0 => match size.checked_mul(factor) {
                Some(coarse) => BinTable::fixed(self.chroms.clone(), coarse),
                None => Err(Error::Invalid(format!(
                    "bins of {size} bp x {factor} overflow 64 bits"
                ))),
            },
            _ => Err(Error::Invalid(
                "only fixed-size bin tables can be coarsened".into(),
            )),
        }
    }
}

fn check_chrom_names(chroms: &[Chrom]) -> Result<()> {
    let mut seen = std::collections::HashSet::new();
    for chrom in chroms {
        if chrom.name.is_empty() {
            return Err(Error::Invalid("empty chromosome name".into()));
        }
        if !seen.insert(chrom.name.as_str()) {
            return Err(Error::Invalid(format!(
                "chromosome '{}' appears twice in the chromosome table",
                chrom.name
            )));
        }
    }
    Ok(())
}

/// A genomic region: a whole chromosome or an interval on it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Region {
    /// Chromosome name.
    pub chrom: String,
    /// 0-based start; `None` for the chromosome's start.
    pub start: Option<u64>,
    /// Exclusive end; `None` for the chromosome's end.
    pub end: Option<u64>,
}

impl Region {
    /// Parse `chrom`, `chrom:start-end` or `chrom:start` (to the chromosome's end).
    ///
    /// Numbers may contain thousands separators (`,` or `_`) and a unit suffix (`k`, `kb`, `M`,
    /// `Mb`, `G`, `Gb`, case-insensitive). A chromosome name that itself contains ':' can be given
    /// whole (with no coordinates) and is kept as it is when the part after the last ':' is not a
    /// coordinate range.
    pub fn parse(text: &str) -> Result<Region> {
        let text_trim = text.trim();
        if text_trim.is_empty() {
            return Err(Error::region(text, "empty region"));
        }
        let Some((chrom, coords)) = text_trim.rsplit_once(':') else {
            return Ok(Region {
                chrom: text_trim.to_string(),
                start: None,
                end: None,
            });
        };
        if chrom.is_empty() {
            return Err(Error::region(text, "missing chromosome name before ':'"));
        }
        let looks_numeric = coords
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_digit() || c == '-');
        if !looks_numeric {
            return Ok(Region {
                chrom: text_trim.to_string(),
                start: None,
                end: None,
            });
        }
        let (start_text, end_text) = match coords.split_once('-') {
            Some((s, e)) => (s, Some(e)),
            None => (coords, None),
        };
        let start = parse_bp(start_text).map_err(|m| Error::region(text, m))?;
        let end = match end_text {
            Some(e) => Some(parse_bp(e).map_err(|m| Error::region(text, m))?),
            None => None,
        };
        if let Some(end) = end {
            if end <= start {
                return Err(Error::region(
                    text,
                    format!("start {start} is not before end {end}"),
                ));
            }
        }
        Ok(Region {
            chrom: chrom.to_string(),
            start: Some(start),
            end,
        })
    }
}

impl std::fmt::Display for Region {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.start, self.end) {
            (None, None) => write!(f, "{}", self.chrom),
            (Some(s), None) => write!(f, "{}:{s}", self.chrom),
            (s, Some(e)) => write!(f, "{}:{}-{e}", self.chrom, s.unwrap_or(0)),
        }
    }
}

/// A distance for people: `250 kb`, `1.2 Mb`, `800 bp` (at most two decimals, trailing zeros
/// dropped).
pub fn format_bp(value: f64) -> String {
    let (scaled, unit) = in_units(value);
    let digits = format!("{scaled:.2}");
    let trimmed = digits.trim_end_matches('0').trim_end_matches('.');
    format!("{trimmed} {unit}")
}

/// `value` bp in the largest of Mb, kb and bp that keeps it at least 1.
fn in_units(value: f64) -> (f64, &'static str) {
    if value.abs() >= 1e6 {
        (value / 1e6, "Mb")
    } else if value.abs() >= 1e3 {
        (value / 1e3, "kb")
    } else {
        (value, "bp")
    }
}

/// A distance that is not a round number of bins (the effective distance of a log bin) to three
/// significant digits: `10.9 kb`, `892 kb`, `4.43 Mb`.
pub fn format_distance(value: f64) -> String {
    let (scaled, unit) = in_units(value);
    let decimals = if scaled.abs() >= 100.0 {
        0
    } else if scaled.abs() >= 10.0 {
        1
    } else {
        2
    };
    let digits = format!("{scaled:.decimals$}");
    let trimmed = if digits.contains('.') {
        digits.trim_end_matches('0').trim_end_matches('.')
    } else {
        &digits
    };
    format!("{trimmed} {unit}")
}

/// The number and unit multiplier of a distance such as `1,000,000`, `1.5M` or `200kb`: digit
/// separators (`,` `_`) removed, lower-cased, a `gb` / `mb` / `kb` / `bp` / `g` / `m` / `k`
/// suffix split off.
fn split_unit(text: &str) -> (String, f64) {
    let lower: String = text
        .trim()
        .chars()
        .filter(|&c| c != ',' && c != '_')
        .collect::<String>()
        .to_ascii_lowercase();
    [
        ("gb", 1e9),
        ("mb", 1e6),
        ("kb", 1e3),
        ("bp", 1.0),
        ("g", 1e9),
        ("m", 1e6),
        ("k", 1e3),
    ]
    .iter()
    .find_map(|(suffix, m)| {
        lower
            .strip_suffix(suffix)
            .map(|n| (n.trim().to_string(), *m))
    })
    .unwrap_or((lower.clone(), 1.0))
}

/// Parse a distance in bp that need not be whole, such as `1.5Mb`, `200,000` or `2.5k`.
///
/// ```
/// use contactmap::genome::parse_distance;
/// assert_eq!(parse_distance("1.5Mb"), Some(1.5e6));
/// assert_eq!(parse_distance("2.5k"), Some(2500.0));
/// assert_eq!(parse_distance("ten"), None);
/// ```
pub fn parse_distance(text: &str) -> Option<f64> {
    let (number, multiplier) = split_unit(text);
    number.parse::<f64>().ok().map(|value| value * multiplier)
}

/// Parse a base-pair position such as `1,000,000`, `1_000_000`, `1.5M`, `200kb`.
pub fn parse_bp(text: &str) -> std::result::Result<u64, String> {
    let (number, multiplier) = split_unit(text);
    let number = number.as_str();
    if number.is_empty() {
        return Err(format!("'{text}' is not a position"));
    }
    if number.starts_with('-') && number[1..].parse::<f64>().is_ok() {
        return Err(format!(
            "'{text}' is negative: base-pair positions and sizes are 0 or more"
        ));
    }
    if multiplier == 1.0 {
        return number.parse::<u64>().map_err(|_| {
            format!("'{text}' is not a position (expected a whole number of base pairs)")
        });
    }
    let value: f64 = number
        .parse()
        .map_err(|_| format!("'{text}' is not a position"))?;
    let bp = value * multiplier;
    if !(bp >= 0.0 && bp.fract() == 0.0 && bp < 9.0e18) {
        return Err(format!("'{text}' is not a whole number of base pairs"));
    }
    Ok(bp as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> BinTable {
        BinTable::fixed(vec![Chrom::new("chr1", 1050), Chrom::new("chr2", 300)], 100).unwrap()
    }

    #[test]
    fn fixed_bins_tile_each_chromosome() {
        let t = table();
        assert_eq!(t.n_bins(), 11 + 3);
        assert_eq!(t.chrom_offsets(), &[0, 11, 14]);
        assert_eq!(
            t.bin(10),
            Bin {
                chrom_id: 0,
                start: 1000,
                end: 1050
            }
        );
        assert_eq!(
            t.bin(11),
            Bin {
                chrom_id: 1,
                start: 0,
                end: 100
            }
        );
        let all: Vec<Bin> = t.iter().collect();
        assert_eq!(all.len(), t.n_bins());
        for (i, b) in all.iter().enumerate() {
            assert_eq!(*b, t.bin(i));
        }
    }

    #[test]
    fn a_cut_out_table_covers_its_span_only() {
        // chr1 cut to 250..1000 in bins of 100, chr2 whole.
        let chroms = vec![Chrom::new("chr1", 1050), Chrom::new("chr2", 300)];
        let bins: Vec<Bin> = [(250, 350), (350, 450), (450, 550), (550, 650), (650, 750)]
            .iter()
            .chain(&[(750, 850), (850, 950), (950, 1000)])
            .map(|&(start, end)| Bin {
                chrom_id: 0,
                start,
                end,
            })
            .chain((0..3).map(|i| Bin {
                chrom_id: 1,
                start: i * 100,
                end: i * 100 + 100,
            }))
            .collect();
        let t = BinTable::from_bins(chroms.clone(), &bins, Some(100)).unwrap();
        assert_eq!(t.bin_size_bp(), Some(100));
        assert!(t.is_cut());
        assert_eq!(t.span(0), 250..1000);
        assert_eq!(t.chrom_offsets(), &[0, 8, 11]);
        assert_eq!(t.iter().collect::<Vec<_>>(), bins);
        // Overlap, as cooler's region query: nothing outside the span.
        assert_eq!(t.parse_region_bins("chr1:0-250").unwrap(), 0..0);
        assert_eq!(t.parse_region_bins("chr1:1000-1050").unwrap(), 8..8);
        assert_eq!(t.parse_region_bins("chr1:0-260").unwrap(), 0..1);
        assert_eq!(t.parse_region_bins("chr1:340-360").unwrap(), 0..2);
        assert_eq!(t.parse_region_bins("chr1").unwrap(), 0..8);
        assert!(t.coarsen(2).is_err());
        // The same bins given as a variable table agree.
        let v = BinTable::variable(chroms, &bins).unwrap();
        assert_eq!(v.span(0), 250..1000);
        assert_eq!(v.parse_region_bins("chr1:0-250").unwrap(), 0..0);
        assert_eq!(v.parse_region_bins("chr1:340-360").unwrap(), 0..2);
    }

    #[test]
    fn regions_select_overlapping_bins() {
        let t = table();
        assert_eq!(t.parse_region_bins("chr1").unwrap(), 0..11);
        assert_eq!(t.parse_region_bins("chr1:150-250").unwrap(), 1..3);
        assert_eq!(t.parse_region_bins("chr1:100-200").unwrap(), 1..2);
        assert_eq!(t.parse_region_bins("chr2:0-300").unwrap(), 11..14);
        assert_eq!(t.parse_region_bins("chr1:1,000-1,050").unwrap(), 10..11);
        assert!(t.parse_region_bins("chr3").is_err());
        assert!(t.parse_region_bins("chr2:0-301").is_err());
        assert!(t.parse_region_bins("chr2:200-100").is_err());
    }

    #[test]
    fn positions_accept_separators_and_units() {
        assert_eq!(parse_bp("1,000,000").unwrap(), 1_000_000);
        assert_eq!(parse_bp("1.5M").unwrap(), 1_500_000);
        assert_eq!(parse_bp("200kb").unwrap(), 200_000);
        assert!(parse_bp("abc").is_err());
        assert!(parse_bp("1.5").is_err());
        assert_eq!(format_bp(1.2e6), "1.2 Mb");
        assert_eq!(format_bp(250_000.0), "250 kb");
        assert_eq!(format_bp(800.0), "800 bp");
        assert_eq!(format_bp(1e7), "10 Mb");
        let r = Region::parse("chr2L:1,000,000-2,000,000").unwrap();
        assert_eq!((r.start, r.end), (Some(1_000_000), Some(2_000_000)));
        assert_eq!(Region::parse("contig:alt").unwrap().chrom, "contig:alt");
    }

    #[test]
    fn variable_bins_are_checked_and_fixed_ones_detected() {
        let chroms = vec![Chrom::new("a", 10), Chrom::new("b", 5)];
        let bins = [
            Bin {
                chrom_id: 0,
                start: 0,
                end: 4,
            },
            Bin {
                chrom_id: 0,
                start: 4,
                end: 10,
            },
            Bin {
                chrom_id: 1,
                start: 0,
                end: 5,
            },
        ];
        let t = BinTable::from_bins(chroms.clone(), &bins, None).unwrap();
        assert_eq!(t.bin_size_bp(), None);
        assert_eq!(t.bin_at(0, 5), 1);
        assert_eq!(t.chrom_of(2), 1);
        let gap = [
            Bin {
                chrom_id: 0,
                start: 0,
                end: 4,
            },
            Bin {
                chrom_id: 0,
                start: 5,
                end: 10,
            },
        ];
        assert!(BinTable::variable(chroms.clone(), &gap).is_err());
        // A late first bin is a cut-out matrix, not a gap.
        let late = [Bin {
            chrom_id: 0,
            start: 1,
            end: 10,
        }];
        assert_eq!(
            BinTable::variable(chroms.clone(), &late).unwrap().span(0),
            1..10
        );
        let fixed = [
            Bin {
                chrom_id: 0,
                start: 0,
                end: 5,
            },
            Bin {
                chrom_id: 0,
                start: 5,
                end: 10,
            },
            Bin {
                chrom_id: 1,
                start: 0,
                end: 5,
            },
        ];
        assert_eq!(
            BinTable::from_bins(chroms.clone(), &fixed, None)
                .unwrap()
                .bin_size_bp(),
            Some(5)
        );
        // A chromosome shorter than one bin: the hint (the file's bin-size) decides.
        let short = [
            Bin {
                chrom_id: 0,
                start: 0,
                end: 10,
            },
            Bin {
                chrom_id: 1,
                start: 0,
                end: 5,
            },
        ];
        let table = BinTable::from_bins(chroms, &short, Some(20)).unwrap();
        assert_eq!(table.bin_size_bp(), Some(20));
    }
}
