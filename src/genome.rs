//! Chromosomes, bin tables and genomic regions.
//!
//! Coordinates are 0-based and half-open, as in cooler and BED: a bin `start..end` covers the bases
//! `start, start + 1, ..., end - 1`. Bins are identified by their index in the genome-wide bin table,
//! chromosome after chromosome in the order of the chromosome table.
//!
//! Regions are written as cooler and bioframe write them: `chr2L`, `chr2L:1,000,000-2,000,000`,
//! `chr2L:1000000-2000000`, and `chr2L:1.5M-2M` (suffixes `k`, `kb`, `M`, `Mb`, `G`, `Gb`). A region
//! selects every bin that overlaps it, as `cooler dump --range` does.
//!
//! Also here, for every room: views ([`view`], cooltools' view frames: the regions an analysis
//! runs over) and distances written and read for people ([`units`]).

mod bins;
mod region;
pub mod units;
pub mod view;

pub use bins::{Bin, BinTable, Chrom, MAX_BINS};
pub use region::Region;
pub use units::{format_bp, format_distance, parse_bp, parse_distance};
pub use view::{RegionSpec, View, ViewRegion};

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
        assert_eq!(t.resolution(), Some(100));
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
        assert_eq!(t.resolution(), None);
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
                .resolution(),
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
        assert_eq!(table.resolution(), Some(20));
    }
}
