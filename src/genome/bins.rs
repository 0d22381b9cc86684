//! Chromosomes and bin tables: fixed or variable bins, genome-wide bin ids, regions to bins.

use std::ops::Range;

use super::region::Region;
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
/// them) covers `first start .. last end` only. Fixed bins are `resolution` long except the last of
/// each chromosome, which ends at the span's end.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BinTable {
    chroms: Vec<Chrom>,
    resolution: Option<u64>,
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

fn too_many_bins(resolution: u64) -> Error {
    Error::Argument(format!(
        "bins of {resolution} bp make more than {MAX_BINS} bins: the chromosome lengths or the \
         bin size are wrong"
    ))
}

impl BinTable {
    /// Chromosomes cut into bins of `resolution` base pairs.
    pub fn fixed(chroms: Vec<Chrom>, resolution: u64) -> Result<Self> {
        let spans = chroms.iter().map(|c| 0..c.length_bp).collect();
        BinTable::fixed_spans(chroms, resolution, spans)
    }

    /// Chromosomes cut into bins of `resolution` base pairs over `spans[c]` only: the bins of
    /// chromosome `c` start at `spans[c].start` and the last ends at `spans[c].end` (a matrix cut
    /// out of the chromosomes). An empty span gives the chromosome no bins.
    pub fn fixed_spans(
        chroms: Vec<Chrom>,
        resolution: u64,
        spans: Vec<Range<u64>>,
    ) -> Result<Self> {
        if resolution == 0 {
            return Err(Error::Argument("bin size must be positive".into()));
        }
        check_chrom_names(&chroms)?;
        if spans.len() != chroms.len() {
            return Err(Error::Argument(format!(
                "{} chromosome spans for {} chromosomes",
                spans.len(),
                chroms.len()
            )));
        }
        let mut chrom_offsets = Vec::with_capacity(chroms.len() + 1);
        let mut n = 0usize;
        for (chrom, span) in chroms.iter().zip(&spans) {
            if span.end > chrom.length_bp || span.start > span.end {
                return Err(Error::Argument(format!(
                    "bins of {} over {}-{}: not within the chromosome's {} bp",
                    chrom.name, span.start, span.end, chrom.length_bp
                )));
            }
            chrom_offsets.push(n);
            n = usize::try_from((span.end - span.start).div_ceil(resolution))
                .ok()
                .and_then(|bins| n.checked_add(bins))
                .filter(|&total| total <= MAX_BINS)
                .ok_or_else(|| too_many_bins(resolution))?;
        }
        chrom_offsets.push(n);
        Ok(BinTable {
            chroms,
            resolution: Some(resolution),
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
                return Err(Error::Data(format!(
                    "bin {index}: chromosome index {} out of range (there are {} chromosomes)",
                    bin.chrom_id,
                    chroms.len()
                )));
            }
            let expected_start = match previous {
                Some(p) if p.chrom_id == bin.chrom_id => p.end,
                Some(p) if p.chrom_id > bin.chrom_id => {
                    return Err(Error::Data(format!(
                        "bin {index}: bins are not sorted by chromosome"
                    )));
                }
                // The first bin of a chromosome may start anywhere (a cut-out matrix).
                _ => {
                    spans[bin.chrom_id] = bin.start..bin.start;
                    bin.start
                }
            };
            if bin.start != expected_start || bin.end <= bin.start {
                return Err(Error::Data(format!(
                    "bin {index} ({}:{}-{}): bins must tile the chromosome (expected a bin starting at {expected_start})",
                    chroms[bin.chrom_id].name, bin.start, bin.end
                )));
            }
            if bin.end > chroms[bin.chrom_id].length_bp {
                return Err(Error::Data(format!(
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
            resolution: None,
            chrom_offsets,
            starts,
            ends,
            spans,
        })
    }

    /// Build a table from explicit bins, detecting whether they are fixed-size.
    ///
    /// Readers use this: the candidate size is `resolution_hint` (a file's own bin-size attribute)
    /// or else the largest bin; if the bins equal `BinTable::fixed` with that size, the result is
    /// a fixed table, otherwise a variable one.
    pub fn from_bins(
        chroms: Vec<Chrom>,
        bins: &[Bin],
        resolution_hint: Option<u64>,
    ) -> Result<Self> {
        let variable = BinTable::variable(chroms, bins)?;
        let largest = bins.iter().map(|b| b.end - b.start).max();
        if let Some(size) = resolution_hint.filter(|&s| s > 0).or(largest) {
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
        if a.resolution() != b.resolution() {
            return Some(match (a.resolution(), b.resolution()) {
                (Some(x), Some(y)) => format!("bin size {y} instead of {x}"),
                _ => "variable bins on one side only".into(),
            });
        }
        if a.n_bins() != b.n_bins() {
            return Some(format!("{} bins instead of {}", b.n_bins(), a.n_bins()));
        }
        if a.resolution().is_none() {
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
    pub fn resolution(&self) -> Option<u64> {
        self.resolution
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
        match self.resolution {
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
        match self.resolution {
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
                        format!(
                            "'{coords}' is not a position range (expected start-end, e.g. 1,000,000-2,000,000)"
                        ),
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
            return Err(Error::Unsupported(
                "bin tables that do not cover whole chromosomes cannot be coarsened".into(),
            ));
        }
        match self.resolution {
            Some(size) if factor > 0 => match size.checked_mul(factor) {
                Some(coarse) => BinTable::fixed(self.chroms.clone(), coarse),
                None => Err(Error::Argument(format!(
                    "bins of {size} bp x {factor} overflow 64 bits"
                ))),
            },
            _ => Err(Error::Unsupported(
                "only fixed-size bin tables can be coarsened".into(),
            )),
        }
    }
}

fn check_chrom_names(chroms: &[Chrom]) -> Result<()> {
    let mut seen = std::collections::HashSet::new();
    for chrom in chroms {
        if chrom.name.is_empty() {
            return Err(Error::Data("empty chromosome name".into()));
        }
        if !seen.insert(chrom.name.as_str()) {
            return Err(Error::Data(format!(
                "chromosome '{}' appears twice in the chromosome table",
                chrom.name
            )));
        }
    }
    Ok(())
}
