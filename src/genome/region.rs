//! Genomic regions as cooler and bioframe write them (`chr2L:1,000,000-2,000,000`).

use super::units::parse_bp;
use crate::error::{Error, Result};

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
