//! Groups of snippets, as coolpuppy 1.1.0 forms them: by distance band (`--by-distance`) and by
//! the anchors' strands (`--by-strand`). Every snippet also goes into the group of all of them.

use std::fmt;

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

/// A group: its distance band and anchors' strands where those group; the group of all
/// snippets has neither.
#[derive(Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct GroupKey {
    /// The strands of anchor 1 and anchor 2 (`--by-strand`).
    pub strands: Option<(char, char)>,
    /// The distance band (`--by-distance`).
    pub band: Option<Band>,
}

impl GroupKey {
    /// The group of all snippets.
    pub fn all() -> GroupKey {
        GroupKey::default()
    }

    /// True for the group of all snippets.
    pub fn is_all(&self) -> bool {
        self.strands.is_none() && self.band.is_none()
    }
}

/// A distance in Mb as Python prints `bp / 1e6` (`0.05`, `1.0`).
fn megabases(bp: u64) -> String {
    crate::io::output::python_float(bp as f64 / 1e6)
}

impl fmt::Display for GroupKey {
    /// `all`, or the parts that group: orientation (`+-`) and separation (`0.1Mb-0.2Mb`,
    /// `0.4Mb+`), joined by `,`.
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
        };
        assert_eq!(key.to_string(), "+-,0.05Mb-0.1Mb");
        let key = GroupKey {
            strands: None,
            band: b(400_000, None),
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
