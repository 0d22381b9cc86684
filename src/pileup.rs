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
//! Snippets are summed as they are cut (never a stack of them in memory).

pub mod scores;
pub mod tables;
#[cfg(test)]
mod tests;
pub mod windows;

use ndarray::Array2;

use crate::error::{Error, Result};
use crate::expected::View;
use crate::io::bed::{BedRecord, BedpeRecord};
use crate::io::MatrixReader;
use windows::{bed_windows, bedpe_windows, PairWindow, Skipped, WindowParams};

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
}

impl Default for PileupParams {
    fn default() -> Self {
        PileupParams {
            flank_bp: 100_000,
            min_dist_bp: None,
            max_dist_bp: None,
            ignore_diags: 2,
        }
    }
}

impl PileupParams {
    /// An error unless the flank is a whole number of bins of `bin_size_bp`, at least one
    /// (coolpuppy gives a map of another size, or fails, otherwise).
    pub fn check(&self, bin_size_bp: u64) -> Result<()> {
        if self.flank_bp == 0 || !self.flank_bp.is_multiple_of(bin_size_bp) {
            return Err(Error::parameter(
                "flank",
                self.flank_bp,
                format!("a whole number of bins ({bin_size_bp} bp here), at least one"),
            ));
        }
        Ok(())
    }
}

/// A pileup: the mean snippet and how many went into it.
#[derive(Clone, Debug, PartialEq)]
pub struct Pileup {
    /// The mean snippet (`2 f + 1` square).
    pub data: Array2<f64>,
    /// Per pixel, the number of snippets with a finite value there.
    pub num: Array2<u64>,
    /// Snippets piled up.
    pub n: usize,
    /// Features left out, by reason.
    pub skipped: Skipped,
    /// The minimum distance used (bp).
    pub min_dist_bp: f64,
    /// Snippets whose anchor 2 lies upstream of anchor 1 (BEDPE pairs given that way): below
    /// the diagonal, every pixel left out, yet counted in `n` (as coolpuppy counts them).
    pub below_diagonal: usize,
}

/// Per-snippet sums and counts.
struct Sums {
    sum: Array2<f64>,
    num: Array2<u64>,
    n: usize,
}

impl Sums {
    fn new(size: usize) -> Sums {
        Sums {
            sum: Array2::zeros((size, size)),
            num: Array2::zeros((size, size)),
            n: 0,
        }
    }
}

/// Pile up `features` on `reader`'s map: balanced by `weights` (a weight per bin, NaN for a
/// masked bin) or raw counts (`None`), over the regions of `view`, divided by `expected` (per
/// view region, the expected of each diagonal, as `contactmap expected` computes it) when given.
///
/// # Examples
///
/// The loops a simulation held, piled up on its map as observed / expected: the centre (the
/// loops' own pixel) stands out.
///
/// ```
/// use contactmap::expected::{expected_cis, CisParams, View};
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
/// let pup = pileup(reader.as_ref(), Some(&weights), &view, &Features::Bedpe(loops),
///                  Some(&expected.average_by_region()), &params)?;
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
) -> Result<Pileup> {
    let bins = reader.bins();
    let res = bins
        .bin_size_bp()
        .ok_or_else(|| Error::format(reader.source(), "pileups need fixed-size bins"))?;
    params.check(res)?;
    let flank_bins = (params.flank_bp / res) as usize;
    let min_dist = params
        .min_dist_bp
        .unwrap_or((2 * params.flank_bp + 2 * res) as f64);
    let window_params = WindowParams {
        bin_size_bp: res,
        flank_bins,
        min_dist,
        max_dist: params.max_dist_bp.unwrap_or(f64::INFINITY),
    };
    let mut skipped = Skipped::default();
    let (windows, local) = match features {
        Features::Bed { features, local } => (
            bed_windows(bins, view, features, *local, &window_params, &mut skipped),
            *local,
        ),
        Features::Bedpe(pairs) => (
            bedpe_windows(bins, view, pairs, &window_params, &mut skipped),
            false,
        ),
    };
    let size = 2 * flank_bins + 1;
    let cutter = Cutter {
        reader,
        weights,
        expected,
        ignore_diags: params.ignore_diags,
    };
    let mut sums = Sums::new(size);
    for window in &windows {
        cutter.add(window, &mut sums)?;
    }
    let mut data = Array2::from_shape_fn((size, size), |(r, c)| {
        let mean = sums.sum[[r, c]] / sums.num[[r, c]] as f64;
        if mean == f64::INFINITY {
            f64::NAN
        } else {
            mean
        }
    });
    if local {
        let t = data.t().to_owned();
        data.zip_mut_with(&t, |a, &b| {
            *a = match (a.is_nan(), b.is_nan()) {
                (true, true) => f64::NAN,
                (true, false) => b,
                (false, true) => *a,
                (false, false) => (*a + b) / 2.0,
            }
        });
    }
    let below_diagonal = windows.iter().filter(|w| w.distance < 0.0).count();
    Ok(Pileup {
        data,
        num: sums.num,
        n: sums.n,
        skipped,
        min_dist_bp: min_dist,
        below_diagonal,
    })
}

/// Cuts snippets out of the map and adds them to sums.
struct Cutter<'a> {
    reader: &'a dyn MatrixReader,
    weights: Option<&'a [f64]>,
    expected: Option<&'a [Vec<f64>]>,
    ignore_diags: usize,
}

impl Cutter<'_> {
    /// Add the snippet of `window` to `sums`.
    fn add(&self, window: &PairWindow, sums: &mut Sums) -> Result<()> {
        let (r0, c0) = (window.rows.start, window.cols.start);
        let (h, w) = (window.rows.len(), window.cols.len());
        let mut snippet = Array2::<f64>::zeros((h, w));
        // the upper triangle is what coolpuppy keeps of a cis snippet: the stored pixels
        self.reader
            .read_pixels(window.rows.clone(), window.cols.clone(), &mut |block| {
                for k in 0..block.len() {
                    let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                    let value = match self.weights {
                        Some(wt) => (wt[i] * wt[j]) * block.count[k],
                        None => block.count[k],
                    };
                    snippet[[i - r0, j - c0]] = value;
                }
                Ok(())
            })?;
        let expected = self.expected.map(|e| &e[window.region]);
        for ((p, q), value) in snippet.indexed_iter_mut() {
            let (i, j) = (r0 + p, c0 + q);
            let masked = self
                .weights
                .is_some_and(|wt| wt[i].is_nan() || wt[j].is_nan());
            if masked || (j as i64 - i as i64) < self.ignore_diags as i64 {
                *value = f64::NAN;
            } else if let Some(expected) = expected {
                *value /= expected.get(j - i).copied().unwrap_or(f64::NAN);
            }
        }
        for ((p, q), &value) in snippet.indexed_iter() {
            if !value.is_nan() {
                sums.sum[[p, q]] += value;
                if value.is_finite() {
                    sums.num[[p, q]] += 1;
                }
            }
        }
        sums.n += 1;
        Ok(())
    }
}
