//! One entry point for every TAD caller: [`call`] runs a [`Caller`] (insulation, directionality
//! with Dixon's HMM, TopDom, Armatus) over the regions of a view and returns the same shape of
//! answer whatever the method: boundaries, domains, the method's per-bin track and what was
//! noticed on the way. What `contactmap tads` computes.

use crate::error::{Error, Result};
use crate::genome::View;
use crate::io::LoadedPixels;
use crate::matrix::pixels::PixelSource;

use super::armatus::{ArmatusParams, armatus, level_boundaries};
use super::band::cis_bands;
use super::directionality::{DirectionalityParams, DirectionalityTable, directionality};
use super::domains::{Boundary, Domain, domains_between};
use super::hmm::{DiState, HmmParams, dixon_domains};
use super::insulation::{InsulationParams, InsulationTable, insulation};
use super::topdom::{TopDomParams, TopDomRegion, TopDomTag, topdom};

/// A TAD caller and its parameters.
#[derive(Clone, Debug)]
pub enum Caller {
    /// Diamond insulation at one or more windows (cooltools `insulation`); boundaries and
    /// domains from the window at index `calls_window` of `params.windows_bp`.
    Insulation {
        /// The insulation parameters.
        params: InsulationParams,
        /// Which window's boundaries become the calls.
        calls_window: usize,
    },
    /// Directionality index and Dixon's HMM domains.
    Directionality {
        /// The directionality index parameters.
        params: DirectionalityParams,
        /// The HMM's parameters.
        hmm: HmmParams,
    },
    /// TopDom; regions with fewer than twice its window in bins are skipped (a warning).
    TopDom(TopDomParams),
    /// Armatus' multi-scale domains; the diagonals `d < ignore_diags` are cleared first and the
    /// boundaries are those of the domains at `boundary_level` (0: the coarsest gamma).
    Armatus {
        /// The Armatus parameters.
        params: ArmatusParams,
        /// Diagonals cleared before the domains are looked for.
        ignore_diags: usize,
        /// The gamma level whose domains give the boundaries.
        boundary_level: u32,
    },
}

/// The per-bin output of a caller.
#[derive(Clone, Debug)]
pub enum TadTrack {
    /// The insulation table and the view's region names.
    Insulation(InsulationTable, Vec<String>),
    /// The directionality table and each bin's HMM state (`None`: masked).
    Directionality(DirectionalityTable, Vec<Option<DiState>>),
    /// TopDom's regions (per-bin scores, boundaries, segments).
    TopDom(Vec<TopDomRegion>),
    /// Armatus' domains with the gamma each was found at.
    Armatus(Vec<(Domain, f64)>),
}

/// What a caller found.
#[derive(Clone, Debug)]
pub struct TadCalls {
    /// A label for the calls: the method and its window (`insulation_100000`, `armatus`).
    pub label: String,
    /// The boundaries.
    pub boundaries: Vec<Boundary>,
    /// The domains.
    pub domains: Vec<Domain>,
    /// The method's per-bin track.
    pub track: TadTrack,
    /// Problems that did not stop the work (regions skipped), one line each.
    pub warnings: Vec<String>,
    /// Facts worth a line (boundaries per insulation window).
    pub notes: Vec<String>,
}

/// Run `caller` on the regions of `view`, from `pixels` times `weights` (cooler's
/// multiplicative weights; `None`: raw counts).
///
/// # Examples
///
/// Three blocks of 10 bins on one chromosome, each half as dense as the one before: insulation at a
/// 3-bin window finds the two boundaries between them (every peak kept: a strength cutoff of 0).
///
/// ```
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
/// use contactmap::tads::call::{call, Caller};
/// use contactmap::tads::insulation::InsulationParams;
/// use contactmap::tads::threshold::Threshold;
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 30_000)], 1_000)?;
/// let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
/// for i in 0..30u64 {
///     for j in i..30 {
///         let count = match (i / 10, j / 10) {
///             (a, b) if a == b => 100.0 / 2f64.powi(a as i32),
///             _ => 1.0,
///         };
///         builder.push(i, j, count)?;
///     }
/// }
/// let matrix = InMemory::new("blocks".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// let view = View::chromosomes(&bins);
/// let params = InsulationParams {
///     windows_bp: vec![3_000],
///     ignore_diags: 0,
///     threshold: Threshold::Value(0.0),
///     ..InsulationParams::default()
/// };
/// let caller = Caller::Insulation { params, calls_window: 0 };
/// let calls = call(&pixels, None, &view, &caller)?;
/// assert_eq!(calls.label, "insulation_3000");
/// let called: Vec<usize> = calls.boundaries.iter().map(|b| b.bin).collect();
/// assert_eq!(called.len(), 2, "{called:?}");
/// assert!((9..=10).contains(&called[0]) && (19..=20).contains(&called[1]), "{called:?}");
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn call(
    pixels: &LoadedPixels<'_>,
    weights: Option<&[f64]>,
    view: &View,
    caller: &Caller,
) -> Result<TadCalls> {
    match caller {
        Caller::Insulation {
            params,
            calls_window,
        } => call_insulation(pixels, weights, view, params, *calls_window),
        Caller::Directionality { params, hmm } => {
            let table = directionality(pixels, weights, view, params)?;
            let calls = dixon_domains(&table, hmm)?;
            Ok(TadCalls {
                label: format!("directionality_{}", params.window_bp),
                boundaries: calls.boundaries,
                domains: calls.domains,
                track: TadTrack::Directionality(table, calls.states),
                warnings: Vec::new(),
                notes: Vec::new(),
            })
        }
        Caller::TopDom(params) => call_topdom(pixels, weights, view, params),
        Caller::Armatus {
            params,
            ignore_diags,
            boundary_level,
        } => {
            let mut bands = cis_bands(pixels, weights, view, params.max_domain_bins)?;
            let mut domains = Vec::new();
            for band in &mut bands {
                band.clear_near_diagonal(*ignore_diags);
                domains.extend(armatus(band, params)?);
            }
            let boundaries = level_boundaries(&domains, *boundary_level, view);
            let with_gamma = domains
                .iter()
                .map(|d| (*d, params.gammas[d.level as usize]))
                .collect();
            Ok(TadCalls {
                label: "armatus".into(),
                boundaries,
                domains,
                track: TadTrack::Armatus(with_gamma),
                warnings: Vec::new(),
                notes: Vec::new(),
            })
        }
    }
}

fn call_insulation(
    pixels: &LoadedPixels<'_>,
    weights: Option<&[f64]>,
    view: &View,
    params: &InsulationParams,
    calls_window: usize,
) -> Result<TadCalls> {
    let Some(&window_bp) = params.windows_bp.get(calls_window) else {
        return Err(Error::parameter(
            "calls_window",
            calls_window,
            format!(
                "expected the index of one of the {} windows",
                params.windows_bp.len()
            ),
        ));
    };
    let table = insulation(pixels, weights, view, params)?;
    let boundaries = table.boundaries(calls_window);
    let domains = domains_between(view, &boundaries, 1);
    let notes = table
        .tracks
        .iter()
        .map(|track| {
            format!(
                "window {}: {} boundaries (strength cutoff {})",
                track.window_bp,
                track.is_boundary.iter().filter(|&&b| b).count(),
                track.cutoff
            )
        })
        .collect();
    Ok(TadCalls {
        label: format!("insulation_{window_bp}"),
        boundaries,
        domains,
        track: TadTrack::Insulation(
            table,
            view.regions().iter().map(|r| r.name.clone()).collect(),
        ),
        warnings: Vec::new(),
        notes,
    })
}

fn call_topdom(
    pixels: &LoadedPixels<'_>,
    weights: Option<&[f64]>,
    view: &View,
    params: &TopDomParams,
) -> Result<TadCalls> {
    let bands = cis_bands(pixels, weights, view, 2 * params.window_bins + 1)?;
    let mut regions = Vec::with_capacity(bands.len());
    let mut warnings = Vec::new();
    for (band, region) in bands.iter().zip(view.regions()) {
        if band.n_bins < 2 * params.window_bins {
            warnings.push(format!(
                "{} has fewer than {} bins: skipped by TopDom",
                region.name,
                2 * params.window_bins
            ));
            continue;
        }
        regions.push(topdom(band, params)?);
    }
    let boundaries = regions
        .iter()
        .flat_map(|r| r.boundaries.iter().copied())
        .collect();
    let domains = regions
        .iter()
        .flat_map(|r| r.segments.iter())
        .filter(|(_, tag)| matches!(tag, TopDomTag::Domain))
        .map(|(domain, _)| *domain)
        .collect();
    // Labelled by the window in bp (in bins where bins vary in size).
    let label = match pixels.bins().resolution() {
        Some(resolution) => format!("topdom_{}", params.window_bins as u64 * resolution),
        None => format!("topdom_{}bins", params.window_bins),
    };
    Ok(TadCalls {
        label,
        boundaries,
        domains,
        track: TadTrack::TopDom(regions),
        warnings,
        notes: Vec::new(),
    })
}
