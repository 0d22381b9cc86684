//! Views: the genomic regions an analysis runs over (expected, TADs, loops, compartments,
//! pileups), as cooltools' view frames.
//!
//! A view is a list of named, non-overlapping regions sorted in the order of the chromosome table
//! (then by start), each inside one chromosome: whole chromosomes by default (named after the
//! chromosome), or the lines of a BED file (read by `crate::io::bed::read_view`: `chrom start end [name]`, 0-based half-open; a missing
//! name becomes the UCSC string `chrom:start-end`, as `bioframe.make_viewframe(name_style="ucsc")`).
//!
//! A region covers every bin that overlaps it (cooler's `extent`). When two regions meet inside a
//! bin, that bin belongs to both regions' bin ranges (so to both regions' pixel counts `n_total`),
//! while its pixels are assigned to the later region only: this is what cooltools does
//! (`assign_supports` overwrites earlier regions), and contactmap follows it so the tables agree.

use std::collections::HashSet;
use std::ops::Range;

use super::bins::BinTable;
use super::region::Region;
use crate::error::{Error, Result};

/// A region as given by the user (one BED line).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RegionSpec {
    /// Chromosome name.
    pub chrom: String,
    /// 0-based start in bp.
    pub start_bp: u64,
    /// Exclusive end in bp.
    pub end_bp: u64,
    /// Region name; `None` for the UCSC string `chrom:start-end`.
    pub name: Option<String>,
}

/// One region of a checked [`View`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ViewRegion {
    /// Unique name.
    pub name: String,
    /// Index of the chromosome in the bin table.
    pub chrom_id: usize,
    /// 0-based start in bp.
    pub start_bp: u64,
    /// Exclusive end in bp.
    pub end_bp: u64,
    /// The bins overlapping the region (genome-wide bin ids).
    pub bins: Range<usize>,
}

impl ViewRegion {
    /// Length in bp.
    pub fn length_bp(&self) -> u64 {
        self.end_bp - self.start_bp
    }

    /// Number of bins.
    pub fn n_bins(&self) -> usize {
        self.bins.len()
    }
}

/// A checked list of regions: sorted, non-overlapping, uniquely named, inside the chromosomes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct View {
    regions: Vec<ViewRegion>,
}

impl View {
    /// Every chromosome that has at least one bin, whole, named after the chromosome (cooltools'
    /// `make_cooler_view`).
    pub fn chromosomes(bins: &BinTable) -> View {
        let regions = bins
            .chroms()
            .iter()
            .enumerate()
            .filter(|(chrom_id, _)| !bins.chrom_bins(*chrom_id).is_empty())
            .map(|(chrom_id, chrom)| ViewRegion {
                name: chrom.name.clone(),
                chrom_id,
                start_bp: 0,
                end_bp: chrom.length_bp,
                bins: bins.chrom_bins(chrom_id),
            })
            .collect();
        View { regions }
    }

    /// Check `specs` against `bins` and build the view.
    ///
    /// Errors (one line, naming the region by its 1-based position and its coordinates): an
    /// unknown chromosome, an empty or out-of-bounds interval, regions out of order (they must
    /// follow the chromosome table, then start), overlapping regions, duplicate names.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::genome::{RegionSpec, View};
    /// use contactmap::genome::{BinTable, Chrom};
    /// let bins = BinTable::fixed(vec![Chrom::new("chr1", 1_000)], 100)?;
    /// let arm = |start_bp, end_bp, name: &str| RegionSpec {
    ///     chrom: "chr1".into(), start_bp, end_bp, name: Some(name.into()),
    /// };
    /// let view = View::new(&bins, &[arm(0, 400, "p"), arm(400, 1_000, "q")])?;
    /// assert_eq!(view.regions()[1].bins, 4..10);
    /// assert!(View::new(&bins, &[arm(400, 1_000, "q"), arm(0, 400, "p")]).is_err());
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn new(bins: &BinTable, specs: &[RegionSpec]) -> Result<View> {
        if specs.is_empty() {
            return Err(Error::Argument("the view has no region".into()));
        }
        let mut regions: Vec<ViewRegion> = Vec::with_capacity(specs.len());
        let mut names = HashSet::new();
        for (index, spec) in specs.iter().enumerate() {
            let label = format!(
                "view region {} ({}:{}-{})",
                index + 1,
                spec.chrom,
                spec.start_bp,
                spec.end_bp
            );
            let chrom_id = bins.chrom_id(&spec.chrom).ok_or_else(|| {
                Error::Argument(format!("{label}: {}", bins.missing_chrom(&spec.chrom)))
            })?;
            let length = bins.chroms()[chrom_id].length_bp;
            if spec.start_bp >= spec.end_bp {
                return Err(Error::Argument(format!("{label}: start is not before end")));
            }
            if spec.end_bp > length {
                return Err(Error::Argument(format!(
                    "{label}: ends past the length of {} ({length} bp)",
                    spec.chrom
                )));
            }
            if let Some(previous) = regions.last() {
                let key = (chrom_id, spec.start_bp);
                if key < (previous.chrom_id, previous.start_bp) {
                    return Err(Error::Argument(format!(
                        "{label}: regions must be sorted by chromosome (in the matrix's order) and start; it comes after '{}'",
                        previous.name
                    )));
                }
                if previous.chrom_id == chrom_id && spec.start_bp < previous.end_bp {
                    return Err(Error::Argument(format!(
                        "{label}: overlaps region '{}' ({}:{}-{})",
                        previous.name, spec.chrom, previous.start_bp, previous.end_bp
                    )));
                }
            }
            let name = spec
                .name
                .clone()
                .unwrap_or_else(|| format!("{}:{}-{}", spec.chrom, spec.start_bp, spec.end_bp));
            if !names.insert(name.clone()) {
                return Err(Error::Argument(format!(
                    "{label}: the name '{name}' is used twice"
                )));
            }
            let region = Region {
                chrom: spec.chrom.clone(),
                start: Some(spec.start_bp),
                end: Some(spec.end_bp),
            };
            let region_bins = bins.region_bins(&region)?;
            regions.push(ViewRegion {
                name,
                chrom_id,
                start_bp: spec.start_bp,
                end_bp: spec.end_bp,
                bins: region_bins,
            });
        }
        Ok(View { regions })
    }

    /// The regions, in order.
    pub fn regions(&self) -> &[ViewRegion] {
        &self.regions
    }

    /// Number of regions.
    pub fn len(&self) -> usize {
        self.regions.len()
    }

    /// True when the view has no region (only possible for a matrix without bins).
    pub fn is_empty(&self) -> bool {
        self.regions.is_empty()
    }

    /// The region each bin's pixels are assigned to (`None` outside every region), later
    /// regions taking a bin shared with an earlier one, as cooltools' `assign_supports`.
    pub fn bin_regions(&self, n_bins: usize) -> Vec<Option<usize>> {
        let mut of = vec![None; n_bins];
        for (index, region) in self.regions.iter().enumerate() {
            for slot in &mut of[region.bins.clone()] {
                *slot = Some(index);
            }
        }
        of
    }

    /// The median region length in bp (the mean of the two middle ones for an even count).
    pub fn median_length_bp(&self) -> f64 {
        let mut lengths: Vec<u64> = self.regions.iter().map(|r| r.length_bp()).collect();
        lengths.sort_unstable();
        match lengths.len() {
            0 => 0.0,
            n if n % 2 == 1 => lengths[n / 2] as f64,
            n => (lengths[n / 2 - 1] + lengths[n / 2]) as f64 / 2.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::Chrom;

    fn bins() -> BinTable {
        BinTable::fixed(vec![Chrom::new("a", 1000), Chrom::new("b", 500)], 100).unwrap()
    }

    fn spec(chrom: &str, start: u64, end: u64, name: Option<&str>) -> RegionSpec {
        RegionSpec {
            chrom: chrom.into(),
            start_bp: start,
            end_bp: end,
            name: name.map(Into::into),
        }
    }

    #[test]
    fn whole_chromosomes_and_bed_regions() {
        let bins = bins();
        let view = View::chromosomes(&bins);
        assert_eq!(view.len(), 2);
        assert_eq!(view.regions()[1].bins, 10..15);
        let view = View::new(
            &bins,
            &[spec("a", 0, 450, None), spec("a", 450, 1000, Some("arm"))],
        )
        .unwrap();
        assert_eq!(view.regions()[0].name, "a:0-450");
        assert_eq!(view.regions()[0].bins, 0..5);
        assert_eq!(view.regions()[1].bins, 4..10);
        // The shared bin 4 goes to the later region.
        let of = view.bin_regions(bins.n_bins());
        assert_eq!(of[4], Some(1));
        assert_eq!(of[3], Some(0));
        assert_eq!(of[12], None);
        assert_eq!(view.median_length_bp(), 500.0);
    }

    #[test]
    fn bad_views_are_refused() {
        let bins = bins();
        let message = |specs: &[RegionSpec]| View::new(&bins, specs).unwrap_err().to_string();
        assert!(message(&[spec("z", 0, 10, None)]).contains("no chromosome 'z'"));
        assert!(
            message(&[spec("a", 0, 600, None), spec("a", 500, 900, None)]).contains("overlaps")
        );
        assert!(message(&[spec("b", 0, 100, None), spec("a", 0, 100, None)]).contains("sorted"));
        assert!(message(&[spec("a", 0, 2000, None)]).contains("past the length"));
        assert!(message(&[spec("a", 10, 10, None)]).contains("not before"));
        assert!(
            message(&[spec("a", 0, 10, Some("x")), spec("b", 0, 10, Some("x"))])
                .contains("used twice")
        );
    }
}
