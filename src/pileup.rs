//! Pileups (aggregate maps at features) as coolpuppy 1.1.0 computes them (`coolpup.py`,
//! `pileup()`), with Juicer APA's and coolpuppy's scores ([`scores`]).
//!
//! 1. **Windows** ([`windows`]): each feature or anchor at its midpoint's bin, `2 f + 1` bins
//!    (`f = flank / bin size`); pairs from BEDPE lines, from every two BED features within the
//!    distance limits, or each BED feature with itself (`local`). A window leaving its view
//!    region is skipped.
//! 2. **Snippets**: the balanced (or raw) map cut at each pair of windows; bins without a weight
//!    are NaN (balanced only), and so is every pixel `(i, j)` with `j - i < ignore_diags` (signed,
//!    as coolpuppy: in cis the lower triangle is always NaN). With an expected, each pixel is
//!    divided by the expected of its diagonal (observed / expected per snippet).
//! 3. **Mean**: per pixel, the sum of the snippets' non-NaN values over their number (so the
//!    pileup is the mean of the per-snippet observed / expected, not a ratio of sums); `+inf`
//!    becomes NaN at the end; a local pileup is made symmetric (mean of it and its transpose,
//!    NaN left out), which fills its lower triangle from the upper one.
//!
//! Snippets are summed as they are cut (never a stack of them in memory), on every core
//! ([`cut`]). Beside observed / expected, coolpuppy's other normalisations: shifted random
//! controls ([`shifts`]: the pileup is the mean snippet over the mean control) or none; snippets
//! of any size rescaled to one grid ([`rescale`]); groups by distance band or strands
//! ([`groups`]), each with its own pileup beside the one of all snippets.

pub mod cut;
pub mod groups;
pub mod rescale;
mod result;
pub mod scores;
pub mod shifts;
pub mod tables;
#[cfg(test)]
mod tests;
pub mod windows;

pub use result::{Pileup, Pileups};

use std::collections::BTreeMap;

use ndarray::Array2;

use crate::error::{Error, Result};
use crate::genome::View;
use crate::io::MatrixReader;
use crate::io::bed::{BedRecord, BedpeRecord, FeatureTable};
use cut::{Cutter, Make, Snip, Sums};
use groups::{GroupBy, GroupKey, band_of, distance_edges};
use shifts::{Mt19937, ShiftParams, batch_shifts};
use windows::{
    Batch, Pair, Skipped, WindowParams, bed_batches, bed_trans_batches, bedpe_batches,
    bedpe_trans_batches,
};

/// The features to pile up.
#[derive(Clone, Debug)]
pub enum Features {
    /// BED intervals: paired with each other, or each with itself (`local`).
    Bed {
        /// The intervals.
        features: Vec<BedRecord>,
        /// Each feature with itself (on-diagonal snippets).
        local: bool,
    },
    /// BEDPE pairs (off-diagonal snippets).
    Bedpe(Vec<BedpeRecord>),
}

impl Features {
    /// The features of a table io read and their grouping by the `groupby` columns (none
    /// when `groupby` is empty): BED intervals, each with itself on the diagonal with `local`
    /// (else paired with each other), or BEDPE pairs. `local` with pairs is an error (a caller
    /// that knows the file checks it first, to say how it was read).
    ///
    /// ```
    /// use contactmap::io::bed::{BedpeTable, FeatureTable};
    /// use contactmap::pileup::Features;
    /// let header = Some(["chrom1", "start1", "end1", "chrom2", "start2", "end2", "kind"].map(String::from).to_vec());
    /// let rows = vec![["chr1", "0", "10", "chr1", "90", "100", "a"].map(String::from).to_vec()];
    /// let table = FeatureTable::Bedpe(BedpeTable::from_rows("loops", header, rows)?);
    /// let (features, groups) = Features::of_table(table.clone(), &["kind".into()], false)?;
    /// assert!(matches!(features, Features::Bedpe(ref pairs) if pairs.len() == 1) && groups.is_some());
    /// assert!(Features::of_table(table, &[], true).is_err());
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn of_table(
        table: FeatureTable,
        groupby: &[String],
        local: bool,
    ) -> Result<(Features, Option<GroupBy>)> {
        Ok(match table {
            FeatureTable::Bed(table) => {
                let groups = (!groupby.is_empty())
                    .then(|| GroupBy::bed(&table, groupby, local))
                    .transpose()?;
                let features = Features::Bed {
                    features: table.records,
                    local,
                };
                (features, groups)
            }
            FeatureTable::Bedpe(_) if local => {
                return Err(Error::Argument(
                    "local pileups are of BED features on the diagonal; these features are \
                     BEDPE (pairs)"
                        .into(),
                ));
            }
            FeatureTable::Bedpe(table) => {
                let groups = (!groupby.is_empty())
                    .then(|| GroupBy::bedpe(&table, groupby))
                    .transpose()?;
                (Features::Bedpe(table.records), groups)
            }
        })
    }

    fn local(&self) -> bool {
        matches!(self, Features::Bed { local: true, .. })
    }
}

/// Rescaling (coolpuppy's `--rescale`): each window reaches `flank` times its feature's length
/// each side, and every snippet is zoomed to `size x size`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RescaleParams {
    /// The window's reach each side, in lengths of its feature: 1.
    pub flank: f64,
    /// The side of the grid (odd): 99.
    pub size: usize,
}

impl Default for RescaleParams {
    fn default() -> Self {
        RescaleParams {
            flank: 1.0,
            size: 99,
        }
    }
}

/// The pileup's parameters; the defaults are coolpuppy's.
#[derive(Clone, Debug, PartialEq)]
pub struct PileupParams {
    /// Flank each side of the centre bin (bp, a multiple of the bin size): 100 kb.
    pub flank_bp: u64,
    /// Smallest distance between paired anchors' midpoints (bp, inclusive); `None`: coolpuppy's
    /// `auto`, `2 flank + 2 bin size`. Not used for local pileups.
    pub min_dist_bp: Option<f64>,
    /// Largest distance (bp, inclusive); `None`: no limit.
    pub max_dist_bp: Option<f64>,
    /// Pixels with `j - i` below this are NaN: 2.
    pub ignore_diags: usize,
    /// Snippets rescaled to one grid (the flank is then only used for the minimum distance).
    pub rescale: Option<RescaleParams>,
    /// Shifted random controls (not with an expected).
    pub shifts: Option<ShiftParams>,
    /// Groups by distance band: `Some(vec![])` for coolpuppy's default edges (0, 50 kb, 100 kb,
    /// 200 kb ...), else the edges (bp).
    pub by_distance: Option<Vec<u64>>,
    /// Groups by the anchors' strands.
    pub by_strand: bool,
    /// Snippets whose anchor 1 is on the minus strand flipped about the anti-diagonal.
    pub flip_negative_strand: bool,
    /// Groups by the values of feature columns (coolpuppy's `groupby`).
    pub groupby: Option<GroupBy>,
    /// Pairs between chromosomes instead of within them (coolpuppy's `trans`): BED features of
    /// two chromosomes paired (every feature of one with every feature of the other), or the
    /// BEDPE pairs with anchors on two chromosomes; observed / expected divides by the trans
    /// expected of the two regions, and no diagonal is left out.
    pub trans: bool,
    /// Normalise raw pileups by coverage (coolpuppy's `coverage_norm`): the summed snippets
    /// divided by the outer product of their rows' and columns' summed coverage, scaled to mean
    /// 1. Only with raw counts.
    pub coverage_norm: Option<CoverageNorm>,
}

/// Which coverage normalises (coolpuppy's `coverage_norm`: `total` or `cis`; cooltools'
/// `cov_tot_raw`, `cov_cis_raw`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoverageNorm {
    /// From every pixel of the bin's row and column.
    Total,
    /// From the pixels within the bin's chromosome.
    Cis,
}

impl Default for PileupParams {
    fn default() -> Self {
        PileupParams {
            flank_bp: 100_000,
            min_dist_bp: None,
            max_dist_bp: None,
            ignore_diags: 2,
            rescale: None,
            shifts: None,
            by_distance: None,
            by_strand: false,
            flip_negative_strand: false,
            groupby: None,
            trans: false,
            coverage_norm: None,
        }
    }
}

impl PileupParams {
    /// An error unless the flank is a whole number of bins of `resolution`, at least one
    /// (coolpuppy gives a map of another size, or fails, otherwise), and the other parameters
    /// are ones coolpuppy takes.
    pub fn check(&self, resolution: u64) -> Result<()> {
        if self.flank_bp == 0 || !self.flank_bp.is_multiple_of(resolution) {
            return Err(Error::parameter(
                "flank",
                self.flank_bp,
                format!("a whole number of bins ({resolution} bp here), at least one"),
            ));
        }
        if let Some(rescale) = &self.rescale {
            if rescale.size.is_multiple_of(2) {
                return Err(Error::parameter(
                    "rescale-size",
                    rescale.size,
                    "an odd number of pixels (the grid has a centre)",
                ));
            }
            if !(rescale.flank.is_finite() && rescale.flank >= 0.0) {
                return Err(Error::parameter(
                    "rescale-flank",
                    rescale.flank,
                    "a number of feature lengths, 0 or more",
                ));
            }
        }
        if let Some(shifts) = &self.shifts {
            if shifts.n == 0 {
                return Err(Error::parameter("nshifts", 0, "1 or more"));
            }
            if shifts.max_bp <= shifts.min_bp || shifts.max_bp - shifts.min_bp - 1 > u32::MAX as u64
            {
                return Err(Error::parameter(
                    "maxshift",
                    shifts.max_bp,
                    format!(
                        "more than --minshift ({}), by less than 2^32 bp",
                        shifts.min_bp
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Pile up `features` on `reader`'s map: balanced by `weights` (a weight per bin, NaN for a
/// masked bin) or raw counts (`None`), over the regions of `view`, divided by `expected` when
/// given, or by shifted controls with `params.shifts`. The `expected` is per view region, the
/// expected of each diagonal (`CisExpected::average_by_region`); with `params.trans`, per two
/// view regions `[a][b]` (`a < b`), their trans expected (`TransExpected::average_by_pair`).
///
/// # Examples
///
/// The loops a simulation held, piled up on its map as observed / expected: the centre (the
/// loops' own pixel) stands out.
///
/// ```
/// use contactmap::expected::{expected_cis, CisParams};
/// use contactmap::genome::View;
/// use contactmap::io::{open_matrix, LoadedPixels, OpenOptions, StreamedPixels};
/// use contactmap::pileup::{pileup, Features, PileupParams};
///
/// let reader = open_matrix("data/sim_extrusion.5kb.cool", &OpenOptions::default())?;
/// let weights = reader.weights("weight")?.values;
/// let view = View::chromosomes(reader.bins());
/// let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader.as_ref()));
/// let expected = expected_cis(&pixels, Some(&weights), &view, &CisParams::default())?;
/// let loops = contactmap::io::bed::read_bedpe("data/sim_extrusion.truth_loops.bedpe".as_ref())?;
/// let params = PileupParams { flank_bp: 20_000, ..PileupParams::default() };
/// let pups = pileup(reader.as_ref(), Some(&weights), &view, &Features::Bedpe(loops),
///                   Some(&expected.average_by_region()), &params)?;
/// let pup = pups.all();
/// assert_eq!((pup.data.dim(), pup.n), ((9, 9), 8));
/// assert!(pup.data[[4, 4]] > 5.0);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn pileup(
    reader: &dyn MatrixReader,
    weights: Option<&[f64]>,
    view: &View,
    features: &Features,
    expected: Option<&[Vec<f64>]>,
    params: &PileupParams,
) -> Result<Pileups> {
    let bins = reader.bins();
    let res = bins
        .resolution()
        .ok_or_else(|| Error::format(reader.source(), "pileups need fixed-size bins"))?;
    params.check(res)?;
    let local = features.local();
    if expected.is_some() && params.shifts.is_some() {
        return Err(Error::Argument(
            "shifted controls and an expected are two normalisations: give one".into(),
        ));
    }
    if local && params.by_distance.is_some() {
        return Err(Error::Argument(
            "local pileups have no distance to group by (--by-distance is for pairs)".into(),
        ));
    }
    if params.trans {
        if local {
            return Err(Error::Argument(
                "local pileups are on the diagonal, trans ones between chromosomes: give one"
                    .into(),
            ));
        }
        if params.by_distance.is_some() {
            return Err(Error::Argument(
                "trans pairs have no distance to group by (--by-distance is for cis pairs)".into(),
            ));
        }
        let mut chroms: Vec<usize> = view.regions().iter().map(|r| r.chrom_id).collect();
        chroms.dedup();
        if chroms.len() < 2 {
            return Err(Error::Argument(
                "trans pileups need a view of two chromosomes or more".into(),
            ));
        }
    }
    if let Some(groupby) = &params.groupby {
        let n = match features {
            Features::Bed { features, .. } => features.len(),
            Features::Bedpe(pairs) => pairs.len(),
        };
        if groupby.values.len() != n {
            return Err(Error::Argument(format!(
                "--groupby has the values of {} features for {n} features",
                groupby.values.len()
            )));
        }
    }
    if params.coverage_norm.is_some() && weights.is_some() {
        return Err(Error::Argument(
            "coverage normalisation is for raw counts (as in coolpuppy): add --raw".into(),
        ));
    }
    let coverage = match params.coverage_norm {
        None => None,
        Some(kind) => {
            let cov = crate::compare::coverage::coverage(reader, params.ignore_diags)?;
            Some(match kind {
                CoverageNorm::Total => cov.total,
                CoverageNorm::Cis => cov.cis,
            })
        }
    };
    let flank_bins = (params.flank_bp / res) as usize;
    let min_dist = params
        .min_dist_bp
        .unwrap_or((2 * params.flank_bp + 2 * res) as f64);
    let window_params = WindowParams {
        resolution: res,
        flank_bins,
        min_dist,
        max_dist: params.max_dist_bp.unwrap_or(f64::INFINITY),
        rescale_flank: params.rescale.map(|r| r.flank),
    };
    let mut skipped = Skipped::default();
    let batches = match (features, params.trans) {
        (Features::Bed { features, .. }, true) => {
            bed_trans_batches(bins, view, features, &window_params, &mut skipped)?
        }
        (Features::Bed { features, local }, false) => {
            bed_batches(bins, view, features, *local, &window_params, &mut skipped)?
        }
        (Features::Bedpe(pairs), true) => {
            bedpe_trans_batches(bins, view, pairs, &window_params, &mut skipped)?
        }
        (Features::Bedpe(pairs), false) => {
            bedpe_batches(bins, view, pairs, &window_params, &mut skipped)?
        }
    };
    let edges = params
        .by_distance
        .as_ref()
        .map(|e| distance_edges((!e.is_empty()).then_some(&e[..]), min_dist));
    let key_of = |pair: &Pair| -> Result<GroupKey> {
        let strands =
            if params.by_strand {
                match pair.strands {
                    (Some(a), Some(b)) => Some((a, b)),
                    _ => return Err(Error::Data(
                        "--by-strand needs the strand (+ or -) of every feature: a feature has \
                         none (BED column 6, BEDPE columns 9 and 10)"
                            .into(),
                    )),
                }
            } else {
                None
            };
        let band = edges.as_ref().and_then(|e| band_of(e, pair.distance));
        let values = match &params.groupby {
            Some(groupby) => groupby.values_of(pair.features),
            None => Vec::new(),
        };
        Ok(GroupKey {
            strands,
            band,
            values,
        })
    };
    // each pair's group (its controls keep it), then the groups, sorted, the one of all last
    let pair_keys = batches
        .iter()
        .map(|b| b.pairs.iter().map(key_of).collect::<Result<Vec<_>>>())
        .collect::<Result<Vec<_>>>()?;
    let mut keys = BTreeMap::new();
    for key in pair_keys.iter().flatten().filter(|k| !k.is_all()) {
        keys.insert(key.clone(), 0usize);
    }
    let n_groups = keys.len() + 1;
    for (k, slot) in keys.values_mut().enumerate() {
        *slot = k;
    }
    let all = n_groups - 1;
    // slots: group g's snippets at 2 g, its controls at 2 g + 1
    let mut snips: Vec<Vec<Snip>> = vec![Vec::new(); view.len()];
    let mut rng = params.shifts.as_ref().map(|s| Mt19937::new(s.seed));
    let mut controls_at_edge = 0;
    let mut below_diagonal = 0;
    let regions = view.regions();
    for (Batch { pairs }, batch_keys) in batches.iter().zip(&pair_keys) {
        let mut add = |pair: &Pair, key: &GroupKey, control: bool| -> bool {
            let (row_bins, col_bins) = (&regions[pair.region].bins, &regions[pair.col_region].bins);
            if !pair.fits(row_bins.len(), col_bins.len()) {
                return false;
            }
            let mut slots = vec![2 * all + control as usize];
            if !key.is_all() {
                slots.push(2 * keys[key] + control as usize);
            }
            let at = |bins: &std::ops::Range<usize>, (a, b): (i64, i64)| {
                bins.start + a as usize..bins.start + b as usize
            };
            snips[pair.region].push(Snip {
                rows: at(row_bins, pair.rows),
                cols: at(col_bins, pair.cols),
                region: pair.region,
                col_region: pair.col_region,
                slots,
                flip: params.flip_negative_strand && pair.strands.0 == Some('-'),
            });
            true
        };
        for (pair, key) in pairs.iter().zip(batch_keys) {
            if add(pair, key, false) {
                below_diagonal += (pair.distance < 0.0) as usize;
            } else {
                skipped.at_edge += 1;
            }
        }
        if let (Some(rng), Some(shifts)) = (rng.as_mut(), &params.shifts) {
            let moves = batch_shifts(rng, shifts, pairs.len(), res, params.trans);
            for (k, &bins) in moves.iter().enumerate() {
                let roi = k % pairs.len();
                if !add(&pairs[roi].shifted(bins), &batch_keys[roi], true) {
                    controls_at_edge += 1;
                }
            }
        }
    }
    let size = match params.rescale {
        Some(r) => r.size,
        None => 2 * flank_bins + 1,
    };
    let cutter = Cutter {
        reader,
        make: Make {
            weights,
            expected,
            ignore_diags: params.ignore_diags,
            rescale: params.rescale.map(|r| r.size),
            local,
            trans: params.trans,
            size,
            coverage: coverage.as_deref(),
        },
    };
    let mut sums: Vec<Sums> = Vec::new();
    for region_snips in snips {
        let part = cutter.sum(region_snips, 2 * n_groups)?;
        if sums.is_empty() {
            sums = part;
        } else {
            for (s, p) in sums.iter_mut().zip(&part) {
                s.merge(p);
            }
        }
    }
    let mut ordered: Vec<(GroupKey, usize)> = keys.into_iter().collect();
    ordered.push((GroupKey::all(), all));
    let groups = ordered
        .into_iter()
        .map(|(key, g)| {
            let (mut roi, mut control) = (sums[2 * g].clone(), sums[2 * g + 1].clone());
            let shifted = params.shifts.is_some();
            if coverage.is_some() {
                normalise_by_coverage(&mut roi);
                if shifted {
                    normalise_by_coverage(&mut control);
                }
            }
            let mut data = Array2::from_shape_fn((size, size), |(r, c)| {
                let mean = roi.sum[[r, c]] / roi.num[[r, c]] as f64;
                let value = if shifted {
                    mean / (control.sum[[r, c]] / control.num[[r, c]] as f64)
                } else {
                    mean
                };
                if value == f64::INFINITY {
                    f64::NAN
                } else {
                    value
                }
            });
            if local {
                rescale::symmetrise(&mut data);
            }
            Pileup {
                key,
                data,
                num: roi.num,
                n: roi.n,
                control_n: shifted.then_some(control.n),
            }
        })
        .collect();
    Ok(Pileups {
        groups,
        skipped,
        controls_at_edge,
        min_dist_bp: min_dist,
        below_diagonal,
        distance_edges: edges,
    })
}

/// coolpuppy's `norm_coverage`: the summed snippets over the outer product of the summed
/// coverage of their rows and columns, scaled to mean 1 (NaN left out of the mean); NaN sums
/// (0 / 0) become 0.
fn normalise_by_coverage(sums: &mut Sums) {
    let size = sums.sum.nrows();
    let outer = Array2::from_shape_fn((size, size), |(r, c)| sums.cov_start[r] * sums.cov_end[c]);
    let finite: Vec<f64> = outer.iter().copied().filter(|v| !v.is_nan()).collect();
    let mean = finite.iter().sum::<f64>() / finite.len() as f64;
    sums.sum.zip_mut_with(&outer, |s, &c| {
        let v = *s / (c / mean);
        *s = if v.is_nan() { 0.0 } else { v };
    });
}
