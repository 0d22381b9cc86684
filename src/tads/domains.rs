//! Boundaries and domains, the tables every TAD caller returns, and the domains between
//! boundaries.

use std::ops::Range;

use crate::genome::View;

/// A boundary call: one bin, with the caller's strength (NaN when the method has none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Boundary {
    /// Genome-wide bin index of the boundary bin.
    pub bin: usize,
    /// Strength (insulation: peak prominence of -log2 insulation; TopDom: -log10 p-value; ...).
    pub strength: f64,
}

/// A domain: a run of bins `[start_bin, end_bin)` inside one view region.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Domain {
    /// First bin (genome-wide index).
    pub start_bin: usize,
    /// One past the last bin.
    pub end_bin: usize,
    /// Nesting level: 0 for the outermost (or only) level, larger for domains nested inside.
    pub level: u32,
    /// Caller-specific score (NaN when the method has none).
    pub score: f64,
}

impl Domain {
    /// Number of bins.
    pub fn n_bins(&self) -> usize {
        self.end_bin - self.start_bin
    }
}

/// The runs of consecutive equal values of `region` (a table's region index per row), as row
/// ranges in order: the rows of each region of a per-bin table.
pub fn region_rows(region: &[usize]) -> Vec<Range<usize>> {
    let mut rows = Vec::new();
    let mut start = 0;
    while start < region.len() {
        let end = start
            + region[start..]
                .iter()
                .take_while(|&&r| r == region[start])
                .count();
        rows.push(start..end);
        start = end;
    }
    rows
}

/// Domains between consecutive boundaries of each region: a boundary bin closes the domain on its
/// left and opens the next one (the boundary bin belongs to the domain on its right). Stretches
/// before the first and after the last boundary of a region are domains too, when they hold at
/// least `min_bins` bins; shorter domains are dropped. `boundaries` must be sorted by bin.
pub fn domains_between(view: &View, boundaries: &[Boundary], min_bins: usize) -> Vec<Domain> {
    let mut domains = Vec::new();
    for region in view.regions() {
        let mut start = region.bins.start;
        let inside = boundaries
            .iter()
            .filter(|b| region.bins.contains(&b.bin))
            .map(|b| b.bin)
            .chain(std::iter::once(region.bins.end));
        for edge in inside {
            if edge > start && edge - start >= min_bins.max(1) {
                domains.push(Domain {
                    start_bin: start,
                    end_bin: edge,
                    level: 0,
                    score: f64::NAN,
                });
            }
            start = start.max(edge);
        }
    }
    domains
}
