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
use crate::genome::BinTable;
use crate::genome::View;
use crate::io::bed::{BedRecord, BedpeRecord};

/// One pair of windows, in bins from the start of their view regions (`[start, end)`, possibly
/// outside the region).
#[derive(Clone, Debug, PartialEq)]
pub struct Pair {
    /// Index of the view region of the rows.
    pub region: usize,
    /// Index of the view region of the columns (the rows' in cis).
    pub col_region: usize,
    /// Rows (anchor 1).
    pub rows: (i64, i64),
    /// Columns (anchor 2).
    pub cols: (i64, i64),
    /// `c2 - c1`, the signed distance between the anchors' midpoints (bp); NaN in trans.
    pub distance: f64,
    /// The anchors' strands (`+` or `-`), where the features give them.
    pub strands: (Option<char>, Option<char>),
    /// The anchors' features: indices in the features given (a BEDPE line's twice).
    pub features: (usize, usize),
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

    /// True when the rows lie in `[0, row_bins)` and the columns in `[0, col_bins)`, the sizes
    /// of their regions (coolpuppy's bounds rule).
    pub fn fits(&self, row_bins: usize, col_bins: usize) -> bool {
        let (n, m) = (row_bins as i64, col_bins as i64);
        self.rows.0 >= 0 && self.rows.1 <= n && self.cols.0 >= 0 && self.cols.1 <= m
    }
}

/// Pairs drawn together: controls are drawn per batch (one per region for BEDPE and local BED,
/// one per distance lag for paired BED; in trans one per pair of regions for BEDPE, one per
/// pair of features for BED), in this order.
#[derive(Clone, Debug, PartialEq)]
pub struct Batch {
    /// The pairs, in coolpuppy's order.
    pub pairs: Vec<Pair>,
}

/// Why features were left out, counted.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Skipped {
    /// Features (BED) or pairs (BEDPE) on a chromosome the map does not have.
    pub unknown_chromosome: usize,
    /// The first few (up to 5) of those chromosomes' names, in the order met.
    pub unknown_names: Vec<String>,
    /// Features or pairs outside every view region (coolpuppy's rule: `start >= region start`
    /// and `end < region end`), or BEDPE pairs with anchors in two regions of one chromosome.
    pub outside_view: usize,
    /// BEDPE pairs of the other kind: anchors on two chromosomes in a cis pileup, on one in a
    /// trans pileup.
    pub other_kind: usize,
    /// Pairs whose anchors are closer than the minimum or farther than the maximum distance.
    pub distance: usize,
    /// Snippets whose window leaves their region (too close to its edge).
    pub at_edge: usize,
}

impl Skipped {
    /// Count a feature on chromosome `name`, which the map lacks.
    fn unknown(&mut self, name: &str) {
        self.unknown_chromosome += 1;
        if self.unknown_names.len() < 5 && !self.unknown_names.iter().any(|n| n == name) {
            self.unknown_names.push(name.to_string());
        }
    }
}

/// Where and how far snippets reach.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WindowParams {
    /// The map's bin size (bp).
    pub resolution: u64,
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
    let res = params.resolution as i64;
    let lo = view.regions()[region].start_bp as i64 / res;
    let (first, last) = match params.rescale_flank {
        Some(scale) => {
            let pad = scale * (end as f64 - start as f64);
            let from = (start as f64 - pad).round_ties_even() as i64;
            let to = (end as f64 + pad).round_ties_even() as i64;
            (from.div_euclid(res), -(-to).div_euclid(res))
        }
        None => {
            let centre = (midpoint(start, end) / params.resolution as f64).floor() as i64;
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
        return Err(Error::Data(format!(
            "{}: start {start} is after end {end}; a feature to rescale needs start <= end",
            what()
        )));
    }
    Ok(())
}

/// BEDPE pairs sorted by their anchors' starts `(start1, start2)` as given (stable: ties in
/// input order), as coolpuppy sorts them.
fn by_starts(mut pairs: Vec<(u64, u64, Pair)>) -> impl Iterator<Item = Pair> {
    pairs.sort_by_key(|p| (p.0, p.1));
    pairs.into_iter().map(|p| p.2)
}

/// The view regions of a BEDPE pair's anchors, when both are inside the view and the pair is of
/// the kind asked (`trans`: anchors on two chromosomes; cis: in one region), its anchors'
/// order checked; else `None`, counted in `skipped`.
fn pair_regions(
    bins: &BinTable,
    view: &View,
    pair: &BedpeRecord,
    trans: bool,
    params: &WindowParams,
    skipped: &mut Skipped,
) -> Result<Option<(usize, usize)>> {
    let (a, b) = (&pair.first, &pair.second);
    let (Some(chrom1), Some(chrom2)) = (bins.chrom_id(&a.chrom), bins.chrom_id(&b.chrom)) else {
        let missing = if bins.chrom_id(&a.chrom).is_none() {
            &a.chrom
        } else {
            &b.chrom
        };
        skipped.unknown(missing);
        return Ok(None);
    };
    let (Some(r1), Some(r2)) = (
        region_of(view, chrom1, a.start, a.end),
        region_of(view, chrom2, b.start, b.end),
    ) else {
        skipped.outside_view += 1;
        return Ok(None);
    };
    if (chrom1 != chrom2) != trans {
        skipped.other_kind += 1;
        return Ok(None);
    }
    if !trans && r1 != r2 {
        skipped.outside_view += 1; // anchors in two regions of the chromosome
        return Ok(None);
    }
    for anchor in [a, b] {
        check_order(
            anchor.start,
            anchor.end,
            &|| format!("line {}", pair.line),
            params,
        )?;
    }
    Ok(Some((r1, r2)))
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
    for (index, pair) in pairs.iter().enumerate() {
        let (a, b) = (&pair.first, &pair.second);
        let distance = midpoint(b.start, b.end) - midpoint(a.start, a.end);
        if !(params.min_dist..=params.max_dist).contains(&distance.abs()) {
            skipped.distance += 1;
            continue;
        }
        let Some((region, _)) = pair_regions(bins, view, pair, false, params, skipped)? else {
            continue;
        };
        by_region[region].push((
            a.start,
            b.start,
            Pair {
                region,
                col_region: region,
                rows: window(view, region, a.start, a.end, params),
                cols: window(view, region, b.start, b.end, params),
                distance,
                strands: (a.strand, b.strand),
                features: (index, index),
            },
        ));
    }
    Ok(by_region
        .into_iter()
        .map(|pairs| Batch {
            pairs: by_starts(pairs).collect(),
        })
        .collect())
}

/// The BED `features` of each view region (coolpuppy's rule), in start order (ties in input
/// order), each with its index in `features`.
fn bed_by_region<'a>(
    bins: &BinTable,
    view: &View,
    features: &'a [BedRecord],
    params: &WindowParams,
    skipped: &mut Skipped,
) -> Result<Vec<Vec<(usize, &'a BedRecord)>>> {
    let mut by_region: Vec<Vec<(usize, &BedRecord)>> = vec![Vec::new(); view.len()];
    for (k, feature) in features.iter().enumerate() {
        let Some(chrom_id) = bins.chrom_id(&feature.chrom) else {
            skipped.unknown(&feature.chrom);
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
                by_region[region].push((k, feature))
            }
            None => skipped.outside_view += 1,
        }
    }
    for features in &mut by_region {
        features.sort_by_key(|f| f.1.start);
    }
    Ok(by_region)
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
    let by_region = bed_by_region(bins, view, features, params, skipped)?;
    let mut out = Vec::new();
    for (region, features) in by_region.iter().enumerate() {
        let windows: Vec<(i64, i64)> = features
            .iter()
            .map(|(_, f)| window(view, region, f.start, f.end, params))
            .collect();
        if local {
            let pairs = features
                .iter()
                .zip(&windows)
                .map(|(&(k, f), &w)| Pair {
                    region,
                    col_region: region,
                    rows: w,
                    cols: w,
                    distance: 0.0,
                    strands: (f.strand, f.strand),
                    features: (k, k),
                })
                .collect();
            out.push(Batch { pairs });
            continue;
        }
        for lag in 1..features.len() {
            let mut pairs = Vec::new();
            for a in 0..features.len() - lag {
                let ((k1, f1), (k2, f2)) = (features[a], features[a + lag]);
                let distance = midpoint(f2.start, f2.end) - midpoint(f1.start, f1.end);
                if !(params.min_dist..=params.max_dist).contains(&distance.abs()) {
                    skipped.distance += 1;
                    continue;
                }
                pairs.push(Pair {
                    region,
                    col_region: region,
                    rows: windows[a],
                    cols: windows[a + lag],
                    distance,
                    strands: (f1.strand, f2.strand),
                    features: (k1, k2),
                });
            }
            out.push(Batch { pairs });
        }
    }
    Ok(out)
}

/// The pairs of view regions on different chromosomes, in view order (`a < b`), as coolpuppy
/// visits them in trans.
fn trans_region_pairs(view: &View) -> Vec<(usize, usize)> {
    let regions = view.regions();
    let mut out = Vec::new();
    for a in 0..regions.len() {
        for b in a + 1..regions.len() {
            if regions[a].chrom_id != regions[b].chrom_id {
                out.push((a, b));
            }
        }
    }
    out
}

/// The trans pair of anchor `a` (rows) in its region and anchor `b` (columns) in its.
fn trans_pair(
    view: &View,
    (ra, a): (usize, &BedRecord),
    (rb, b): (usize, &BedRecord),
    features: (usize, usize),
    params: &WindowParams,
) -> Pair {
    Pair {
        region: ra,
        col_region: rb,
        rows: window(view, ra, a.start, a.end, params),
        cols: window(view, rb, b.start, b.end, params),
        distance: f64::NAN,
        strands: (a.strand, b.strand),
        features,
    }
}

/// Trans pairs of BED `features`: for every two regions on different chromosomes (view order),
/// every feature of the first (rows) with every feature of the second (columns), first-region
/// major, each pair its own batch (coolpuppy draws controls per pair in trans). No distance
/// limits.
pub fn bed_trans_batches(
    bins: &BinTable,
    view: &View,
    features: &[BedRecord],
    params: &WindowParams,
    skipped: &mut Skipped,
) -> Result<Vec<Batch>> {
    let by_region = bed_by_region(bins, view, features, params, skipped)?;
    let mut out = Vec::new();
    for (a, b) in trans_region_pairs(view) {
        for &(k1, f1) in &by_region[a] {
            for &(k2, f2) in &by_region[b] {
                out.push(Batch {
                    pairs: vec![trans_pair(view, (a, f1), (b, f2), (k1, k2), params)],
                });
            }
        }
    }
    Ok(out)
}

/// Trans pairs of BEDPE `pairs` (anchors on two chromosomes): one batch per pair of regions
/// on different chromosomes (view order), holding the pairs whose anchor 1 is in the first
/// region and anchor 2 in the second, then those given the other way round, each group sorted
/// by `(start1, start2)` as coolpuppy sorts them. The latter have their anchors swapped (the
/// earlier region's anchor as the rows): coolpuppy reads them at the wrong bins instead. No
/// distance limits (coolpuppy still applies `mindist` to the anchors' positions on their two
/// chromosomes).
pub fn bedpe_trans_batches(
    bins: &BinTable,
    view: &View,
    pairs: &[BedpeRecord],
    params: &WindowParams,
    skipped: &mut Skipped,
) -> Result<Vec<Batch>> {
    // per (earlier, later) region pair: the pairs as given, then the swapped ones, each with
    // its (start1, start2) as given to sort by
    type Sortable = Vec<(u64, u64, Pair)>;
    let mut by_pair: std::collections::HashMap<(usize, usize), [Sortable; 2]> =
        std::collections::HashMap::new();
    for (index, pair) in pairs.iter().enumerate() {
        let (a, b) = (&pair.first, &pair.second);
        let Some((r1, r2)) = pair_regions(bins, view, pair, true, params, skipped)? else {
            continue;
        };
        let swapped = r1 > r2;
        let ((ra, fa), (rb, fb)) = if swapped {
            ((r2, b), (r1, a))
        } else {
            ((r1, a), (r2, b))
        };
        by_pair.entry((ra, rb)).or_default()[swapped as usize].push((
            a.start,
            b.start,
            trans_pair(view, (ra, fa), (rb, fb), (index, index), params),
        ));
    }
    Ok(trans_region_pairs(view)
        .into_iter()
        .filter_map(|key| by_pair.remove(&key))
        .map(|groups| {
            let pairs = groups.into_iter().flat_map(by_starts).collect();
            Batch { pairs }
        })
        .collect())
}
