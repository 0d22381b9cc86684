//! Features to snippet windows, as coolpuppy 1.1.0 places them (`coolpup.py`: `expand`,
//! `_get_snippet` bounds, the pair generators of `CoordCreator`).
//!
//! A feature (a BED interval or one anchor of a BEDPE pair) is placed at its midpoint
//! `c = (start + end) / 2` (a real number); its centre bin is `floor(c / res)` and its window the
//! `2 f + 1` bins around it, `f = flank / res` (the flank must be a whole number of bins). When
//! rescaling, the window is the feature widened by `rescale_flank` times its length each side
//! (ends rounded half to even, as bioframe's `expand`), then to whole bins outwards. Windows are
//! in bins from the start of their view region; one that leaves its region is skipped later,
//! never padded (shifted controls are drawn from every pair first, as coolpuppy draws them).
//!
//! Pairs: a BEDPE line is one pair (anchor 1 = the snippet's rows, anchor 2 its columns, never
//! reordered); BED features pair with each other (every two features of a region, the upstream
//! one, in start order, as the rows) or, with `local`, each with itself. Pairs (not local ones)
//! are kept when `min_dist <= |c2 - c1| <= max_dist`, both ends included.

use crate::error::{Error, Result};
use crate::expected::View;
use crate::genome::BinTable;
use crate::io::bed::{BedRecord, BedpeRecord};

/// One pair of windows, in bins from the start of its view region (`[start, end)`, possibly
/// outside the region).
#[derive(Clone, Debug, PartialEq)]
pub struct Pair {
    /// Index of the view region.
    pub region: usize,
    /// Rows (anchor 1).
    pub rows: (i64, i64),
    /// Columns (anchor 2).
    pub cols: (i64, i64),
    /// `c2 - c1`, the signed distance between the anchors' midpoints (bp).
    pub distance: f64,
    /// The anchors' strands (`+` or `-`), where the features give them.
    pub strands: (Option<char>, Option<char>),
}

impl Pair {
    /// The pair moved by `bins` along the diagonal.
    pub fn shifted(&self, bins: i64) -> Pair {
        Pair {
            rows: (self.rows.0 + bins, self.rows.1 + bins),
            cols: (self.cols.0 + bins, self.cols.1 + bins),
            ..self.clone()
        }
    }

    /// True when both windows lie in `[0, n_bins)` (coolpuppy's bounds rule).
    pub fn fits(&self, n_bins: usize) -> bool {
        let n = n_bins as i64;
        self.rows.0 >= 0 && self.rows.1 <= n && self.cols.0 >= 0 && self.cols.1 <= n
    }
}

/// Pairs drawn together: controls are drawn per batch (one per region for BEDPE and local BED,
/// one per distance lag for paired BED), in this order.
#[derive(Clone, Debug, PartialEq)]
pub struct Batch {
    /// Index of the view region.
    pub region: usize,
    /// The pairs, in coolpuppy's order.
    pub pairs: Vec<Pair>,
}

/// Why features were left out, counted.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Skipped {
    /// Features (BED) or pairs (BEDPE) on a chromosome the map does not have.
    pub unknown_chromosome: usize,
    /// Features or pairs outside every view region (coolpuppy's rule: `start >= region start`
    /// and `end < region end`), or BEDPE pairs with anchors on two chromosomes.
    pub outside_view: usize,
    /// Pairs whose anchors are closer than the minimum or farther than the maximum distance.
    pub distance: usize,
    /// Snippets whose window leaves their region (too close to its edge).
    pub at_edge: usize,
}

/// Where and how far snippets reach.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WindowParams {
    /// The map's bin size (bp).
    pub bin_size_bp: u64,
    /// Bins each side of the centre bin.
    pub flank_bins: usize,
    /// Smallest distance between paired anchors (bp, inclusive).
    pub min_dist: f64,
    /// Largest distance between paired anchors (bp, inclusive).
    pub max_dist: f64,
    /// When rescaling: the window reaches this many times the feature's length each side.
    pub rescale_flank: Option<f64>,
}

/// The region of `view` holding `[start, end)` on `chrom` by coolpuppy's rule
/// (`start >= region start`, `end < region end`).
fn region_of(view: &View, chrom_id: usize, start: u64, end: u64) -> Option<usize> {
    view.regions()
        .iter()
        .position(|r| r.chrom_id == chrom_id && start >= r.start_bp && end < r.end_bp)
}

/// A midpoint in bp.
fn midpoint(start: u64, end: u64) -> f64 {
    (start as f64 + end as f64) / 2.0
}

/// The window of a feature `[start, end)`, in bins from the start of `region`.
fn window(view: &View, region: usize, start: u64, end: u64, params: &WindowParams) -> (i64, i64) {
    let res = params.bin_size_bp as i64;
    let lo = view.regions()[region].start_bp as i64 / res;
    let (first, last) = match params.rescale_flank {
        Some(scale) => {
            let pad = scale * (end as f64 - start as f64);
            let from = (start as f64 - pad).round_ties_even() as i64;
            let to = (end as f64 + pad).round_ties_even() as i64;
            (from.div_euclid(res), -(-to).div_euclid(res))
        }
        None => {
            let centre = (midpoint(start, end) / params.bin_size_bp as f64).floor() as i64;
            let flank = params.flank_bins as i64;
            (centre - flank, centre + flank + 1)
        }
    };
    (first - lo, last - lo)
}

/// The error coolpuppy gives (bioframe's "starts exceed ends") for a feature to widen.
fn check_order(
    start: u64,
    end: u64,
    what: &dyn Fn() -> String,
    params: &WindowParams,
) -> Result<()> {
    if params.rescale_flank.is_some() && start > end {
        return Err(Error::Invalid(format!(
            "{}: start {start} is after end {end}; a feature to rescale needs start <= end",
            what()
        )));
    }
    Ok(())
}

/// The pairs of BEDPE `pairs` (cis: both anchors in one region), per region in view order,
/// sorted by `(start1, start2)` within it (ties in input order), as coolpuppy sorts them.
pub fn bedpe_batches(
    bins: &BinTable,
    view: &View,
    pairs: &[BedpeRecord],
    params: &WindowParams,
    skipped: &mut Skipped,
) -> Result<Vec<Batch>> {
    let mut by_region: Vec<Vec<(u64, u64, Pair)>> = vec![Vec::new(); view.len()];
    for pair in pairs {
        let (a, b) = (&pair.first, &pair.second);
        let distance = midpoint(b.start, b.end) - midpoint(a.start, a.end);
        if !(params.min_dist..=params.max_dist).contains(&distance.abs()) {
            skipped.distance += 1;
            continue;
        }
        let (Some(chrom1), Some(chrom2)) = (bins.chrom_id(&a.chrom), bins.chrom_id(&b.chrom))
        else {
            skipped.unknown_chromosome += 1;
            continue;
        };
        let region = region_of(view, chrom1, a.start, a.end);
        let Some(region) = region.filter(|&r| Some(r) == region_of(view, chrom2, b.start, b.end))
        else {
            skipped.outside_view += 1; // outside, or anchors in two regions (or chromosomes)
            continue;
        };
        for anchor in [a, b] {
            check_order(
                anchor.start,
                anchor.end,
                &|| format!("line {}", pair.line),
                params,
            )?;
        }
        by_region[region].push((
            a.start,
            b.start,
            Pair {
                region,
                rows: window(view, region, a.start, a.end, params),
                cols: window(view, region, b.start, b.end, params),
                distance,
                strands: (a.strand, b.strand),
            },
        ));
    }
    Ok(by_region
        .into_iter()
        .enumerate()
        .map(|(region, mut pairs)| {
            pairs.sort_by_key(|p| (p.0, p.1));
            Batch {
                region,
                pairs: pairs.into_iter().map(|p| p.2).collect(),
            }
        })
        .collect())
}

/// The pairs of BED `features`: each feature with itself (`local`; one batch per region), or
/// every two features of a region (sorted by start, the upstream one as rows) within the
/// distance limits (one batch per lag between their ranks).
pub fn bed_batches(
    bins: &BinTable,
    view: &View,
    features: &[BedRecord],
    local: bool,
    params: &WindowParams,
    skipped: &mut Skipped,
) -> Result<Vec<Batch>> {
    // per region, the features in start order (stable: ties keep input order)
    let mut by_region: Vec<Vec<&BedRecord>> = vec![Vec::new(); view.len()];
    for (k, feature) in features.iter().enumerate() {
        let Some(chrom_id) = bins.chrom_id(&feature.chrom) else {
            skipped.unknown_chromosome += 1;
            continue;
        };
        match region_of(view, chrom_id, feature.start, feature.end) {
            Some(region) => {
                check_order(
                    feature.start,
                    feature.end,
                    &|| format!("feature {}", k + 1),
                    params,
                )?;
                by_region[region].push(feature)
            }
            None => skipped.outside_view += 1,
        }
    }
    let mut out = Vec::new();
    for (region, features) in by_region.iter_mut().enumerate() {
        features.sort_by_key(|f| f.start);
        let windows: Vec<(i64, i64)> = features
            .iter()
            .map(|f| window(view, region, f.start, f.end, params))
            .collect();
        if local {
            let pairs = features
                .iter()
                .zip(&windows)
                .map(|(f, &w)| Pair {
                    region,
                    rows: w,
                    cols: w,
                    distance: 0.0,
                    strands: (f.strand, f.strand),
                })
                .collect();
            out.push(Batch { region, pairs });
            continue;
        }
        for lag in 1..features.len() {
            let mut pairs = Vec::new();
            for a in 0..features.len() - lag {
                let (f1, f2) = (features[a], features[a + lag]);
                let distance = midpoint(f2.start, f2.end) - midpoint(f1.start, f1.end);
                if !(params.min_dist..=params.max_dist).contains(&distance.abs()) {
                    skipped.distance += 1;
                    continue;
                }
                pairs.push(Pair {
                    region,
                    rows: windows[a],
                    cols: windows[a + lag],
                    distance,
                    strands: (f1.strand, f2.strand),
                });
            }
            out.push(Batch { region, pairs });
        }
    }
    Ok(out)
}
