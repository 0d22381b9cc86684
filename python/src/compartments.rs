//! Compartments: cooltools' eigenvectors (cis and trans), digitized tracks and saddles.

use std::ops::Range;

use contactmap::compartments::cis::CisEigParams;
use contactmap::compartments::eigs::{eigs_cis as cis_eigs, eigs_trans as trans_eigs, Phasing};
use contactmap::compartments::phasing::SortMetric;
use contactmap::compartments::saddle::{
    digitize as digitize_track, saddle_cis, saddle_strength as saddle_strengths, saddle_trans,
    Binning, Saddle, SaddleParams,
};
use contactmap::compartments::trans::TransEigParams;
use contactmap::error::Error;
use contactmap::io::{LoadedPixels, MatrixReader, StreamedPixels};
use numpy::PyArray1;
use pyo3::prelude::*;

use crate::convert::{run, vec1, ContactmapError, RegionTuple};
use crate::file::NativeFile;

/// One region's eigenpairs: name, chrom, start, end (bp), first bin, end bin, eigenvalues,
/// eigenvectors (each over the region's bins).
type RegionEigsTuple = (
    String,
    String,
    u64,
    u64,
    usize,
    usize,
    Vec<f64>,
    Vec<Vec<f64>>,
);

/// cooltools' `eigs_cis`: per view region its eigenpairs (`RegionEigsTuple`), and
/// the warnings (unconverged or unoriented vectors).
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (file, view, weight_name, phasing_track=None, n_eigs=3, ignore_diags=None, clip_percentile=99.9, sort_metric=None))]
pub(crate) fn eigs_cis(
    py: Python<'_>,
    file: &NativeFile,
    view: Option<Vec<RegionTuple>>,
    weight_name: String,
    phasing_track: Option<Vec<f64>>,
    n_eigs: usize,
    ignore_diags: Option<usize>,
    clip_percentile: f64,
    sort_metric: Option<String>,
) -> PyResult<(Vec<RegionEigsTuple>, Vec<String>)> {
    let sort = sort_metric.map(|name| sort_metric_of(&name)).transpose()?;
    let (eigs, regions) = run(py, || {
        let reader: &dyn MatrixReader = &file.reader;
        let (view, weights) = file.view_and_weights(view, Some(&weight_name))?;
        let weights = weights.unwrap_or_default();
        check_track(reader, "phasing_track", phasing_track.as_deref())?;
        // cooltools' default: the weight column's ignore_diags attribute, else 2
        let ignore_diags =
            ignore_diags.unwrap_or_else(|| reader.stored_ignore_diags(&weight_name).unwrap_or(2));
        let params = CisEigParams {
            n_eigs,
            ignore_diags,
            clip_percentile,
        };
        let phasing = Phasing {
            track: phasing_track.as_deref(),
            sort,
        };
        let eigs = cis_eigs(reader, &weights, &view, phasing, &params)?;
        let chroms = reader.bins().chroms();
        let regions: Vec<(String, String, u64, u64, Range<usize>)> = view
            .regions()
            .iter()
            .map(|r| {
                let chrom = chroms[r.chrom_id].name.clone();
                (r.name.clone(), chrom, r.start_bp, r.end_bp, r.bins.clone())
            })
            .collect();
        Ok((eigs, regions))
    })?;
    let per_region = regions
        .into_iter()
        .zip(eigs.eigs)
        .map(|((name, chrom, start, end, bins), e)| {
            (
                name, chrom, start, end, bins.start, bins.end, e.values, e.vectors,
            )
        })
        .collect();
    Ok((per_region, eigs.warnings))
}

/// cooltools' `eigs_trans`: the eigenvalues, the eigenvectors over every bin, the warnings.
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (file, weight_name, phasing_track=None, n_eigs=3, perc_top=99.95, perc_bottom=1.0, sort_metric=None))]
pub(crate) fn eigs_trans(
    py: Python<'_>,
    file: &NativeFile,
    weight_name: String,
    phasing_track: Option<Vec<f64>>,
    n_eigs: usize,
    perc_top: f64,
    perc_bottom: f64,
    sort_metric: Option<String>,
) -> PyResult<(Vec<f64>, Vec<Vec<f64>>, Vec<String>)> {
    let sort = sort_metric.map(|name| sort_metric_of(&name)).transpose()?;
    let eigs = run(py, || {
        let reader: &dyn MatrixReader = &file.reader;
        let weights = file.weights_of(Some(&weight_name))?.unwrap_or_default();
        check_track(reader, "phasing_track", phasing_track.as_deref())?;
        let params = TransEigParams {
            n_eigs,
            perc_top,
            perc_bottom,
        };
        let phasing = Phasing {
            track: phasing_track.as_deref(),
            sort,
        };
        trans_eigs(reader, &weights, phasing, &params)
    })?;
    Ok((eigs.eigs.values, eigs.eigs.vectors, eigs.warnings))
}

pub(crate) fn sort_metric_of(name: &str) -> PyResult<SortMetric> {
    match name {
        "spearmanr" => Ok(SortMetric::Spearman),
        "pearsonr" => Ok(SortMetric::Pearson),
        "var_explained" => Ok(SortMetric::VarExplained),
        "MAD_explained" => Ok(SortMetric::MadExplained),
        other => Err(ContactmapError::new_err(format!(
            "sort_metric '{other}': expected spearmanr, pearsonr, var_explained or MAD_explained"
        ))),
    }
}

/// A per-bin track (`name`, as the Python argument) must have one value per bin.
pub(crate) fn check_track(
    reader: &dyn MatrixReader,
    name: &str,
    track: Option<&[f64]>,
) -> Result<(), Error> {
    match track {
        Some(track) if track.len() != reader.bins().n_bins() => Err(Error::Argument(format!(
            "{name}: {} values for {} bins",
            track.len(),
            reader.bins().n_bins()
        ))),
        _ => Ok(()),
    }
}

pub(crate) fn binning(qrange: Option<(f64, f64)>, vrange: Option<(f64, f64)>) -> PyResult<Binning> {
    match (qrange, vrange) {
        (Some((lo, hi)), None) => Ok(Binning::Quantiles(lo, hi)),
        (None, Some((lo, hi))) => Ok(Binning::Values(lo, hi)),
        (None, None) => Ok(Binning::Quantiles(0.0, 1.0)),
        (Some(_), Some(_)) => Err(ContactmapError::new_err(
            "qrange and vrange: give one of them, not both",
        )),
    }
}

/// cooltools' `digitize`: the track's class per bin (`-1` for NaN) and the bin edges.
#[allow(clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (track, n_bins, qrange=None, vrange=None))]
pub(crate) fn digitize<'py>(
    py: Python<'py>,
    track: Vec<f64>,
    n_bins: usize,
    qrange: Option<(f64, f64)>,
    vrange: Option<(f64, f64)>,
) -> PyResult<(Bound<'py, PyArray1<i32>>, Bound<'py, PyArray1<f64>>)> {
    let binning = binning(qrange, vrange)?;
    let d = run(py, || digitize_track(&track, n_bins, binning))?;
    Ok((vec1(py, d.classes), vec1(py, d.edges)))
}

/// cooltools' `saddle`: the (n_bins + 2)^2 sums and counts of observed / expected by the
/// classes of `track` (cis: `expected[region][diagonal]`; trans: `expected[earlier][later]`).
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (file, track, expected, weight_name, view, trans=false, n_bins=50, qrange=None, vrange=None, min_diag=3, max_diag=None))]
pub(crate) fn saddle<'py>(
    py: Python<'py>,
    file: &NativeFile,
    track: Vec<f64>,
    expected: Vec<Vec<f64>>,
    weight_name: String,
    view: Option<Vec<RegionTuple>>,
    trans: bool,
    n_bins: usize,
    qrange: Option<(f64, f64)>,
    vrange: Option<(f64, f64)>,
    min_diag: usize,
    max_diag: Option<usize>,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    usize,
)> {
    let binning = binning(qrange, vrange)?;
    let (result, edges) = run(py, || {
        let reader: &dyn MatrixReader = &file.reader;
        let (view, weights) = file.view_and_weights(view, Some(&weight_name))?;
        let weights = weights.unwrap_or_default();
        check_track(reader, "track", Some(&track))?;
        let digitized = digitize_track(&track, n_bins, binning)?;
        let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader));
        let result = if trans {
            saddle_trans(&pixels, &weights, &digitized, &view, &expected)?
        } else {
            let params = SaddleParams {
                n_bins,
                binning,
                min_diag,
                max_diag,
            };
            saddle_cis(&pixels, &weights, &digitized, &view, &expected, &params)?
        };
        Ok((result, digitized.edges))
    })?;
    Ok((
        vec1(py, result.sum),
        vec1(py, result.count),
        vec1(py, edges),
        result.n_classes,
    ))
}

/// cooltools' `saddle_strength` of row-major sums and counts (`n` classes on a side).
#[pyfunction]
pub(crate) fn saddle_strength<'py>(
    py: Python<'py>,
    sum: Vec<f64>,
    count: Vec<f64>,
    n: usize,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    if sum.len() != n * n || count.len() != n * n {
        return Err(ContactmapError::new_err(format!(
            "saddle_strength: {} sums and {} counts for {n} x {n} classes",
            sum.len(),
            count.len()
        )));
    }
    let saddle = Saddle {
        n_classes: n,
        sum,
        count,
    };
    Ok(vec1(py, saddle_strengths(&saddle)))
}
