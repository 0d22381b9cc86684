//! Groups of snippets, as coolpuppy 1.1.0 forms them: by distance band (`--by-distance`), by
//! the anchors' strands (`--by-strand`) and by the values of feature columns (`--groupby`).
//! Every snippet also goes into the group of all of them.

use std::fmt;

use crate::error::{Error, Result};
use crate::io::bed::{BedTable, BedpeTable};

/// coolpuppy's names of a BED file's columns when it has no header line.
pub const BED_COLUMNS: [&str; 12] = [
    "chrom",
    "start",
    "end",
    "name",
    "score",
    "strand",
    "thickStart",
    "thickEnd",
    "itemRgb",
    "blockCount",
    "blockSizes",
    "blockStarts",
];

/// coolpuppy's names of a BEDPE file's columns when it has no header line.
pub const BEDPE_COLUMNS: [&str; 10] = [
    "chrom1", "start1", "end1", "chrom2", "start2", "end2", "name", "score", "strand1", "strand2",
];

/// Groups by the values of feature columns (coolpuppy's `groupby`).
///
/// Columns are named by the file's header line, or else by coolpuppy's positional names
/// ([`BED_COLUMNS`], [`BEDPE_COLUMNS`]). A BED pair's columns carry the anchor's suffix, as in
/// coolpuppy: `name1` is the upstream feature's `name`, `name2` the other's (in local pileups
/// both are the feature's own, and the bare name is taken too).
#[derive(Clone, Debug, PartialEq)]
pub struct GroupBy {
    /// The grouping columns, as given.
    pub names: Vec<String>,
    /// Per grouping column, the anchor whose feature it reads (0 or 1; always 0 for BEDPE).
    pub anchors: Vec<usize>,
    /// Per feature (BED line or BEDPE line, in the order given), its value in each grouping
    /// column.
    pub values: Vec<Vec<String>>,
}

impl GroupBy {
    /// The grouping `names` of BED features (`table`): each a column name with the anchor's
    /// suffix (`1` or `2`), or in `local` pileups also the bare column name.
    pub fn bed(table: &BedTable, names: &[String], local: bool) -> Result<GroupBy> {
        let columns = column_names(table.header.as_deref(), &BED_COLUMNS);
        let mut anchors = Vec::new();
        let mut indices = Vec::new();
        for name in names {
            let bare = local
                .then(|| columns.iter().position(|c| c == name))
                .flatten();
            let suffixed = name
                .strip_suffix(['1', '2'])
                .and_then(|base| columns.iter().position(|c| c == base))
                .map(|k| (k, usize::from(name.ends_with('2'))));
            let Some((k, anchor)) = bare.map(|k| (k, 0)).or(suffixed) else {
                return Err(unknown_column(name, &columns, true));
            };
            indices.push(k);
            anchors.push(anchor);
        }
        let values = column_values(table.fields.iter().cloned(), &indices, names, &columns)?;
        Ok(GroupBy {
            names: names.to_vec(),
            anchors,
            values,
        })
    }

    /// The grouping `names` of BEDPE pairs (`table`): column names of the file.
    pub fn bedpe(table: &BedpeTable, names: &[String]) -> Result<GroupBy> {
        let columns = column_names(table.header.as_deref(), &BEDPE_COLUMNS);
        let indices = names
            .iter()
            .map(|name| {
                columns
                    .iter()
                    .position(|c| c == name)
                    .ok_or_else(|| unknown_column(name, &columns, false))
            })
            .collect::<Result<Vec<usize>>>()?;
        let rows = table.records.iter().map(|record| {
            let line = record.tsv_line();
            line.split('\t').map(str::to_string).collect()
        });
        let values = column_values(rows, &indices, names, &columns)?;
        Ok(GroupBy {
            names: names.to_vec(),
            anchors: vec![0; names.len()],
            values,
        })
    }

    /// The group values of a pair of features (indices in the order given).
    pub fn values_of(&self, features: (usize, usize)) -> Vec<String> {
        self.anchors
            .iter()
            .enumerate()
            .map(|(k, &anchor)| {
                let f = if anchor == 0 { features.0 } else { features.1 };
                self.values[f][k].clone()
            })
            .collect()
    }
}

/// Per row (the fields of a feature), its values in the columns `indices` (named `names`
/// among `columns`); a row without one of them is an error.
fn column_values(
    rows: impl Iterator<Item = Vec<String>>,
    indices: &[usize],
    names: &[String],
    columns: &[String],
) -> Result<Vec<Vec<String>>> {
    rows.enumerate()
        .map(|(f, fields)| {
            indices
                .iter()
                .zip(names)
                .map(|(&k, name)| {
                    fields
                        .get(k)
                        .cloned()
                        .ok_or_else(|| missing_value(name, &columns[k], f))
                })
                .collect()
        })
        .collect()
}

/// A file's column names: its header's, else coolpuppy's positional ones.
fn column_names(header: Option<&[String]>, positional: &[&str]) -> Vec<String> {
    match header {
        Some(names) => names.to_vec(),
        None => positional.iter().map(|s| s.to_string()).collect(),
    }
}

fn unknown_column(name: &str, columns: &[String], bed: bool) -> Error {
    let how = if bed {
        "a column of the features with the anchor's suffix (name1: the upstream feature's \
         name, name2: the other's)"
    } else {
        "a column of the features"
    };
    Error::parameter(
        "groupby",
        name,
        format!("{how}; the columns are {}", columns.join(", ")),
    )
}

fn missing_value(name: &str, column: &str, feature: usize) -> Error {
    Error::Data(format!(
        "--groupby {name}: feature {} has no column {column}",
        feature + 1
    ))
}

/// coolpuppy's default distance edges: 0, then 50 kb doubling 30 times.
pub fn default_distance_edges() -> Vec<u64> {
    std::iter::once(0)
        .chain((0..30).map(|k| 50_000u64 << k))
        .collect()
}

/// The edges of the distance bands: coolpuppy's default ones, or `custom` as coolpuppy takes
/// them (sorted, each below `min_dist` raised to it; the default ones are not raised).
pub fn distance_edges(custom: Option<&[u64]>, min_dist_bp: f64) -> Vec<u64> {
    let Some(edges) = custom else {
        return default_distance_edges();
    };
    let mut edges: Vec<u64> = edges
        .iter()
        .map(|&e| {
            if (e as f64) < min_dist_bp {
                min_dist_bp as u64
            } else {
                e
            }
        })
        .collect();
    edges.sort_unstable();
    edges
}

/// A distance band `[low, high)` (no upper edge past the last one).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Band {
    /// Included lower edge (bp).
    pub low: u64,
    /// Excluded upper edge (bp); `None` past the last edge.
    pub high: Option<u64>,
}

/// The band of a signed distance (numpy's `searchsorted(edges, d, side="right")`): `None` below
/// the first edge (negative distances too): such snippets are only in the group of all.
pub fn band_of(edges: &[u64], distance: f64) -> Option<Band> {
    let i = edges.partition_point(|&e| e as f64 <= distance);
    if i == 0 {
        return None;
    }
    Some(Band {
        low: edges[i - 1],
        high: edges.get(i).copied(),
    })
}

/// A group: its anchors' strands, distance band and grouping columns' values where those
/// group; the group of all snippets has none.
#[derive(Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct GroupKey {
    /// The strands of anchor 1 and anchor 2 (`--by-strand`).
    pub strands: Option<(char, char)>,
    /// The distance band (`--by-distance`).
    pub band: Option<Band>,
    /// The values of the grouping columns (`--groupby`), in their order.
    pub values: Vec<String>,
}

impl GroupKey {
    /// The group of all snippets.
    pub fn all() -> GroupKey {
        GroupKey::default()
    }

    /// True for the group of all snippets.
    pub fn is_all(&self) -> bool {
        self.strands.is_none() && self.band.is_none() && self.values.is_empty()
    }
}

/// A distance in Mb as Python prints `bp / 1e6` (`0.05`, `1.0`).
fn megabases(bp: u64) -> String {
    crate::io::output::python_float(bp as f64 / 1e6)
}

impl fmt::Display for GroupKey {
    /// `all`, or the parts that group: orientation (`+-`), separation (`0.1Mb-0.2Mb`,
    /// `0.4Mb+`) and the grouping columns' values, joined by `,`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_all() {
            return f.write_str("all");
        }
        let mut parts = Vec::new();
        if let Some((a, b)) = self.strands {
            parts.push(format!("{a}{b}"));
        }
        if let Some(band) = self.band {
            parts.push(match band.high {
                Some(high) => format!("{}Mb-{}Mb", megabases(band.low), megabases(high)),
                None => format!("{}Mb+", megabases(band.low)),
            });
        }
        parts.extend(self.values.iter().cloned());
        f.write_str(&parts.join(","))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// numpy's searchsorted(side="right") by hand: the band holds its lower edge, not its upper.
    #[test]
    fn bands_are_left_closed_and_the_last_is_open() {
        let edges = distance_edges(Some(&[0, 100_000, 50_000, 400_000]), 60_000.0);
        assert_eq!(edges, [60_000, 60_000, 100_000, 400_000]);
        assert_eq!(band_of(&edges, 59_999.0), None);
        assert_eq!(band_of(&edges, -5.0), None);
        let b = |low, high| Some(Band { low, high });
        assert_eq!(band_of(&edges, 60_000.0), b(60_000, Some(100_000)));
        assert_eq!(band_of(&edges, 100_000.0), b(100_000, Some(400_000)));
        assert_eq!(band_of(&edges, 1e9), b(400_000, None));
        let key = GroupKey {
            strands: Some(('+', '-')),
            band: b(50_000, Some(100_000)),
            values: vec!["CTCF".into()],
        };
        assert_eq!(key.to_string(), "+-,0.05Mb-0.1Mb,CTCF");
        let key = GroupKey {
            strands: None,
            band: b(400_000, None),
            values: Vec::new(),
        };
        assert_eq!(key.to_string(), "0.4Mb+");
        assert_eq!(GroupKey::all().to_string(), "all");
        assert_eq!(
            distance_edges(None, 1e6)[..4],
            [0, 50_000, 100_000, 200_000]
        );
        assert_eq!(default_distance_edges().len(), 31);
    }
}
