//! Topologically associating domains (TADs) and their boundaries along the 1D chromosome order.
//!
//! Callers, each documented with its reference in its module:
//!
//! - [`insulation`]: the diamond insulation score (Crane 2015) exactly as `cooltools insulation`
//!   computes it, boundaries by peak prominence ([`peaks`]) and a Li / Otsu / fixed threshold
//!   ([`threshold`]);
//! - [`directionality`]: the directionality index (Dixon 2012) as cooltools computes it, and
//!   domains from a three-state hidden Markov model over it ([`hmm`]);
//! - [`topdom`]: TopDom (Shin 2016);
//! - [`armatus`]: Armatus (Filippova 2014), multi-scale domains by dynamic programming, nested
//!   across its resolution parameter.
//!
//! All callers take pixels through [`crate::matrix::PixelSource`] (or a [`band::CisBand`] built
//! from one) and a [`crate::genome::View`] of regions (whole chromosomes by default), and return
//! plain tables: per-bin tracks, [`Boundary`] and [`Domain`] lists. Bins are genome-wide indices
//! into the bin table; coordinates are 0-based half-open as BED.

pub mod armatus;
pub mod band;
pub mod call;
pub mod directionality;
pub mod hmm;
pub mod insulation;
pub mod peaks;
pub mod tables;
pub mod threshold;
pub mod topdom;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::{BinTable, Chrom};

    #[test]
    fn region_rows_are_the_runs_of_equal_regions() {
        assert_eq!(region_rows(&[0, 0, 1, 1, 1, 3]), vec![0..2, 2..5, 5..6]);
        assert!(region_rows(&[]).is_empty());
    }

    #[test]
    fn domains_between_boundaries_tile_each_region() {
        let bins = BinTable::fixed(vec![Chrom::new("a", 1000), Chrom::new("b", 500)], 100).unwrap();
        let view = View::chromosomes(&bins);
        let boundaries = [3, 7, 12].map(|bin| Boundary { bin, strength: 1.0 });
        let spans: Vec<(usize, usize)> = domains_between(&view, &boundaries, 1)
            .iter()
            .map(|d| (d.start_bin, d.end_bin))
            .collect();
        assert_eq!(spans, vec![(0, 3), (3, 7), (7, 10), (10, 12), (12, 15)]);
        let long: Vec<(usize, usize)> = domains_between(&view, &boundaries, 3)
            .iter()
            .map(|d| (d.start_bin, d.end_bin))
            .collect();
        assert_eq!(long, vec![(0, 3), (3, 7), (7, 10), (12, 15)]);
    }
}
