//! Features to snippet windows, as coolpuppy 1.1.0 places them (`coolpup.py`: `expand`,
//! `_get_snippet` bounds, the pair generators of `CoordCreator`).
//!
//! A feature (a BED interval or one anchor of a BEDPE pair) is placed at its midpoint
//! `c = (start + end) / 2` (a real number); its centre bin is `floor(c / res)` and its window the
//! `2 f + 1` bins around it, `f = flank / res` (the flank must be a whole number of bins). A
//! window that leaves its view region is skipped, never padded.
//!
//! Pairs: a BEDPE line is one pair (anchor 1 = the snippet's rows, anchor 2 its columns, never
//! reordered); BED features pair with each other (every two features of a region, the upstream
//! one, in start order, as the rows) or, with `local`, each with itself. Pairs (not local ones)
//! are kept when `min_dist <= |c2 - c1| <= max_dist`, both ends included.

use std::ops::Range;

use crate::expected::View;
use crate::genome::BinTable;
use crate::io::bed::{BedRecord, BedpeRecord};

/// One snippet to cut: its rows and columns (genome-wide bins) and its view region.
#[derive(Clone, Debug, PartialEq)]
pub struct PairWindow {
    /// Index of the view region.
    pub region: usize,
    /// Rows (anchor 1), genome-wide bins.
    pub rows: Range<usize>,
    /// Columns (anchor 2), genome-wide bins.
    pub cols: Range<usize>,
    /// `c2 - c1`, the signed distance between the anchors' midpoints (bp).
    pub distance: f64,
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
}

/// The region of `view` holding `[start, end)` on `chrom` by coolpuppy's rule
/// (`start >= region start`, `end < region end`).
fn region_of(view: &View, chrom_id: usize, start: u64, end: u64) -> Option<usize> {
    view.regions()
        .iter()
        .position(|r| r.chrom_id == chrom_id && start >= r.start_bp && end < r.end_bp)
}

/// The window of a feature `[start, end)` on chromosome `chrom_id`: genome-wide bins, or `None`
/// when it leaves `region`'s bins.
fn window(
    bins: &BinTable,
    view: &View,
    region: usize,
    (chrom_id, start, end): (usize, u64, u64),
    params: &WindowParams,
) -> Option<Range<usize>> {
    let centre_bin = (midpoint(start, end) / params.bin_size_bp as f64).floor() as i64;
    let offset = bins.chrom_bins(chrom_id).start as i64;
    let flank = params.flank_bins as i64;
    let (first, last) = (offset + centre_bin - flank, offset + centre_bin + flank + 1);
    let span = &view.regions()[region].bins;
    (first >= span.start as i64 && last <= span.end as i64).then_some(first as usize..last as usize)
}

/// A midpoint in bp.
fn midpoint(start: u64, end: u64) -> f64 {
    (start as f64 + end as f64) / 2.0
}

/// The snippet windows of BEDPE `pairs` (cis: both anchors in one region), in input order.
pub fn bedpe_windows(
    bins: &BinTable,
    view: &View,
    pairs: &[BedpeRecord],
    params: &WindowParams,
    skipped: &mut Skipped,
) -> Vec<PairWindow> {
    let mut out = Vec::new();
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
        let rows = window(bins, view, region, (chrom1, a.start, a.end), params);
        let cols = window(bins, view, region, (chrom2, b.start, b.end), params);
        match (rows, cols) {
            (Some(rows), Some(cols)) => out.push(PairWindow {
                region,
                rows,
                cols,
                distance,
            }),
            _ => skipped.at_edge += 1,
        }
    }
    out
}

/// The snippet windows of BED `features`: each feature with itself (`local`), or every two
/// features of a region (sorted by start, the upstream one as rows) within the distance limits.
pub fn bed_windows(
    bins: &BinTable,
    view: &View,
    features: &[BedRecord],
    local: bool,
    params: &WindowParams,
    skipped: &mut Skipped,
) -> Vec<PairWindow> {
    // per region, (chrom_id, start, end) in start order (stable: ties keep input order)
    let mut by_region: Vec<Vec<(usize, u64, u64)>> = vec![Vec::new(); view.len()];
    for feature in features {
        let Some(chrom_id) = bins.chrom_id(&feature.chrom) else {
            skipped.unknown_chromosome += 1;
            continue;
        };
        match region_of(view, chrom_id, feature.start, feature.end) {
            Some(region) => by_region[region].push((chrom_id, feature.start, feature.end)),
            None => skipped.outside_view += 1,
        }
    }
    let mut out = Vec::new();
    for (region, features) in by_region.iter_mut().enumerate() {
        features.sort_by_key(|f| f.1);
        let windows: Vec<Option<Range<usize>>> = features
            .iter()
            .map(|&feature| window(bins, view, region, feature, params))
            .collect();
        if local {
            for w in windows {
                match w {
                    Some(w) => out.push(PairWindow {
                        region,
                        rows: w.clone(),
                        cols: w,
                        distance: 0.0,
                    }),
                    None => skipped.at_edge += 1,
                }
            }
            continue;
        }
        for lag in 1..features.len() {
            for a in 0..features.len() - lag {
                let (f1, f2) = (features[a], features[a + lag]);
                let distance = midpoint(f2.1, f2.2) - midpoint(f1.1, f1.2);
                if !(params.min_dist..=params.max_dist).contains(&distance.abs()) {
                    skipped.distance += 1;
                    continue;
                }
                match (&windows[a], &windows[a + lag]) {
                    (Some(rows), Some(cols)) => out.push(PairWindow {
                        region,
                        rows: rows.clone(),
                        cols: cols.clone(),
                        distance,
                    }),
                    _ => skipped.at_edge += 1,
                }
            }
        }
    }
    out
}
