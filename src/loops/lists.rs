//! Dot tables merged across resolutions (`dots --resolutions`, `dots-merge`): each table's rows
//! kept as they were written, chosen by Juicer's HiCCUPS rule ([`merge_resolutions`]) and given a
//! last column, `resolution`. A table comes from a call ([`ResolutionList::of_dots`]) or from a
//! file that io read ([`ResolutionList::of_table`]: cooltools' `count` or Juicer's `observed` is
//! the strength the rule reads).

use std::collections::BTreeSet;
use std::path::Path;

use super::calls::DotCalls;
use super::merge::{
    MergeParams, ResolutionCall, ResolutionProblem, merge_resolutions, resolution_problem,
    sort_merged,
};
use super::tables::dots_rows;
use crate::error::{Error, Result};
use crate::genome::{BinTable, View};
use crate::io::bed::BedpeTable;

/// One resolution's list of calls: its table's header and rows as written, where it came from
/// (named in messages) and what the merge rule reads of each row.
#[derive(Clone, Debug, PartialEq)]
pub struct ResolutionList {
    /// The file or level the calls come from.
    pub source: String,
    /// The calls' resolution (bp).
    pub resolution: u64,
    /// The table's header line (tab-separated, without a line end).
    pub header: String,
    /// One line per call (without line ends).
    pub rows: Vec<String>,
    /// What the merge rule reads of each row, in the same order.
    pub calls: Vec<ResolutionCall>,
}

impl ResolutionList {
    /// The clustered dots of `calls`, made on `bins` (fixed bins of `resolution` bp) and `view`,
    /// as rows of [`dots_tsv`](super::tables::dots_tsv); `source` names the level. `None`
    /// without clustering (the merge works on clustered dots).
    pub fn of_dots(
        source: &str,
        resolution: u64,
        calls: &DotCalls,
        bins: &BinTable,
        view: &View,
    ) -> Option<ResolutionList> {
        let (header, rows) = dots_rows(calls, bins, view)?;
        let dots = calls.dots.as_deref().unwrap_or_default();
        Some(ResolutionList {
            source: source.to_string(),
            resolution,
            header,
            rows,
            calls: ResolutionCall::of_dots(dots, bins),
        })
    }

    /// The calls of a dots table read from `path` (cooltools' or `contactmap dots`' columns,
    /// or Juicer's: the strength is `count`, else `observed`), at `resolution` when given, else
    /// at the width of its rows (which must then all be one width). Errors name the file (and
    /// the line of a count that is not a number).
    ///
    /// ```
    /// use contactmap::io::bed::read_bedpe_table;
    /// use contactmap::loops::lists::ResolutionList;
    /// use std::path::Path;
    /// let path = std::env::temp_dir().join(format!("cm-lists-{}.bedpe", std::process::id()));
    /// std::fs::write(&path, "chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tcount\n\
    ///                        chr1\t0\t5000\tchr1\t50000\t55000\t12\n")?;
    /// let list = ResolutionList::of_table(&path, &read_bedpe_table(&path)?, None)?;
    /// assert_eq!((list.resolution, list.calls[0].start2, list.calls[0].count), (5000, 50000, 12.0));
    /// assert_eq!(list.rows, ["chr1\t0\t5000\tchr1\t50000\t55000\t12"]);
    /// # std::fs::remove_file(&path)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn of_table(
        path: &Path,
        table: &BedpeTable,
        resolution: Option<u64>,
    ) -> Result<ResolutionList> {
        let column = table
            .rest_column("count")
            .or_else(|| table.rest_column("observed"))
            .ok_or_else(|| {
                Error::format(
                    path,
                    "no header line with a `count` (cooltools) or `observed` (Juicer) column: \
                     dots-merge reads dot tables as `contactmap dots` writes them",
                )
            })?;
        let mut widths = BTreeSet::new();
        let mut calls = Vec::new();
        let mut rows = Vec::new();
        for record in &table.records {
            let count_text = record.rest.get(column).map_or("", String::as_str);
            let count: f64 = count_text.parse().map_err(|_| {
                Error::parse(
                    path,
                    record.line,
                    format!("count '{count_text}' is not a number"),
                )
            })?;
            widths.insert(record.first.width());
            widths.insert(record.second.width());
            calls.push(ResolutionCall {
                chrom1: record.first.chrom.clone(),
                start1: record.first.start,
                chrom2: record.second.chrom.clone(),
                start2: record.second.start,
                count,
            });
            rows.push(record.tsv_line());
        }
        let name = path.display();
        let resolution = match (resolution, widths.len()) {
            (Some(r), _) => r,
            (None, 1) => *widths.first().expect("one width"),
            (None, 0) => {
                return Err(Error::Argument(format!(
                    "{name}: no calls to take the resolution from: give it as {name}@RESOLUTION"
                )));
            }
            (None, _) => {
                return Err(Error::Argument(format!(
                    "{name}: calls of several widths ({}): give the resolution as \
                     {name}@RESOLUTION",
                    widths
                        .iter()
                        .map(u64::to_string)
                        .collect::<Vec<_>>()
                        .join(", ")
                )));
            }
        };
        Ok(ResolutionList {
            source: name.to_string(),
            resolution,
            header: table.header.clone().unwrap_or_default().join("\t"),
            rows,
            calls,
        })
    }
}

/// The merged list: the kept rows, each with its list's resolution as a last column, sorted by
/// chromosome (in order of first appearance), start1, start2, resolution.
#[derive(Clone, Debug, PartialEq)]
pub struct MergedList {
    /// The header: the lists' own, then `resolution`.
    pub header: String,
    /// The kept rows, each ending with its resolution.
    pub rows: Vec<String>,
    /// Per list: how many of its calls were kept, of how many, at which resolution.
    pub kept: Vec<(usize, usize, u64)>,
}

impl MergedList {
    /// The table as text: the header line, then the rows.
    pub fn to_tsv(&self) -> String {
        let mut text = format!("{}\n", self.header);
        for row in &self.rows {
            text.push_str(row);
            text.push('\n');
        }
        text
    }

    /// One line: `merged N loops: K of M at R bp, ...`.
    pub fn summary(&self) -> String {
        let counts: Vec<String> = self
            .kept
            .iter()
            .map(|(n, of, resolution)| format!("{n} of {of} at {resolution} bp"))
            .collect();
        format!("merged {} loops: {}", self.rows.len(), counts.join(", "))
    }
}

/// `lists` merged as HiCCUPS merges its resolutions ([`merge_resolutions`]). Errors name the
/// lists: a resolution the rule does not define, two lists at one resolution, lists with rows
/// whose columns differ (tables without rows may carry another column order: cooltools' empty
/// result).
///
/// ```
/// use contactmap::loops::lists::{ResolutionList, merge_lists};
/// use contactmap::loops::merge::{MergeParams, ResolutionCall};
/// let list = |resolution: u64, start1: u64| ResolutionList {
///     source: format!("{resolution}.bedpe"),
///     resolution,
///     header: "chrom1\tstart1\tcount".into(),
///     rows: vec![format!("chr1\t{start1}\t50")],
///     calls: vec![ResolutionCall {
///         chrom1: "chr1".into(), start1, chrom2: "chr1".into(), start2: 2_000_000, count: 50.0,
///     }],
/// };
/// // the 5 kb call is confirmed at 10 kb (within 20 kb): kept; the 10 kb one is not kept
/// let merged = merge_lists(&[list(5_000, 1_000_000), list(10_000, 1_010_000)], &MergeParams::default())?;
/// assert_eq!(merged.to_tsv(), "chrom1\tstart1\tcount\tresolution\nchr1\t1000000\t50\t5000\n");
/// assert_eq!(merged.summary(), "merged 1 loops: 1 of 1 at 5000 bp, 0 of 1 at 10000 bp");
/// assert!(merge_lists(&[list(5_000, 0), list(5_000, 1)], &MergeParams::default()).is_err());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn merge_lists(lists: &[ResolutionList], params: &MergeParams) -> Result<MergedList> {
    let resolutions: Vec<u64> = lists.iter().map(|list| list.resolution).collect();
    match resolution_problem(&resolutions) {
        None => {}
        Some(ResolutionProblem::Undefined(k)) => {
            return Err(Error::Argument(format!(
                "{}: calls at {} bp: the HiCCUPS merge is defined for 5, 10 and 25 kb calls",
                lists[k].source, lists[k].resolution
            )));
        }
        Some(ResolutionProblem::Repeated(first, k)) => {
            return Err(Error::Argument(format!(
                "{} and {} are both at {} bp: give one list per resolution",
                lists[first].source, lists[k].source, lists[k].resolution
            )));
        }
    }
    let with_rows: Vec<&ResolutionList> = lists.iter().filter(|t| !t.rows.is_empty()).collect();
    let header = with_rows
        .first()
        .copied()
        .or(lists.first())
        .map_or("", |t| &t.header);
    if let Some(other) = with_rows.iter().find(|t| t.header != header) {
        return Err(Error::Data(format!(
            "{} and {} have different columns: merge lists written the same way (cooltools' \
             dots tables, all with or all without --no-cluster)",
            with_rows[0].source, other.source
        )));
    }
    let calls: Vec<(u64, &[ResolutionCall])> =
        lists.iter().map(|t| (t.resolution, &t.calls[..])).collect();
    let mut kept = merge_resolutions(&calls, params)?;
    sort_merged(&calls, &mut kept);
    let rows = kept
        .iter()
        .map(|&(l, k)| format!("{}\t{}", lists[l].rows[k], lists[l].resolution))
        .collect();
    let counts = lists
        .iter()
        .enumerate()
        .map(|(l, t)| {
            let n = kept.iter().filter(|&&(kl, _)| kl == l).count();
            (n, t.calls.len(), t.resolution)
        })
        .collect();
    Ok(MergedList {
        header: format!("{header}\tresolution"),
        rows,
        kept: counts,
    })
}
