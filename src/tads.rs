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
pub mod domains;
pub mod hmm;
pub mod insulation;
pub mod peaks;
pub mod tables;
pub mod threshold;
pub mod topdom;

pub use domains::{Boundary, Domain, domains_between, region_rows};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::{BinTable, Chrom, View};

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
