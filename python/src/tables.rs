//! cooltools' tables (expected, insulation, directionality) and balancing.

use contactmap::balance::store::balance_reader;
use contactmap::balance::{balance as balance_pixels, BalanceParams, BalanceResult, Method, Scope};
use contactmap::error::Error;
use contactmap::expected::{
    expected_cis as cis_expected, expected_trans as trans_expected, CisParams,
};
use contactmap::export::cooler::store_balanced;
use contactmap::io::cool::store::check_target;
use contactmap::io::{
    self, default_memory_budget, load_pixels_for_balancing, LoadedPixels, MatrixReader,
    OpenOptions, StreamedPixels,
};
use contactmap::tads::directionality::{directionality as di_table, DirectionalityParams};
use contactmap::tads::insulation::{insulation as insulation_table, InsulationParams, TrackValues};
use contactmap::tads::threshold::Threshold;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{column, run, vec1, ContactmapError, NamedColumn, RegionTuple};
use crate::file::NativeFile;

/// cooltools' `expected_cis`: (region1, region2, [(column, values)]).
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (file, view, weight_name, ignore_diags=2, smooth=true, aggregate_smoothed=true, smooth_sigma=0.1))]
pub(crate) fn expected_cis<'py>(
    py: Python<'py>,
    file: &NativeFile,
    view: Option<Vec<RegionTuple>>,
    weight_name: Option<String>,
    ignore_diags: usize,
    smooth: bool,
    aggregate_smoothed: bool,
    smooth_sigma: f64,
) -> PyResult<(Vec<String>, Vec<String>, Vec<NamedColumn<'py>>)> {
    let table = run(py, || {
        let reader: &dyn MatrixReader = &file.reader;
        let (view, weights) = file.view_and_weights(view, weight_name.as_deref())?;
        let params = CisParams {
            ignore_diags,
            smooth,
            aggregate_smoothed: smooth && aggregate_smoothed,
            smooth_sigma_log10: smooth_sigma,
        };
        let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader));
        cis_expected(&pixels, weights.as_deref(), &view, &params)
    })?;
    let names: Vec<String> = (0..table.n_rows())
        .map(|r| table.region_name(r).to_string())
        .collect();
    let columns = table
        .columns()
        .into_iter()
        .map(|(name, values)| (name, column(py, values)))
        .collect();
    Ok((names.clone(), names, columns))
}

/// cooltools' `expected_trans`: (region1, region2, [(column, values)]).
#[pyfunction]
#[pyo3(signature = (file, view, weight_name))]
pub(crate) fn expected_trans<'py>(
    py: Python<'py>,
    file: &NativeFile,
    view: Option<Vec<RegionTuple>>,
    weight_name: Option<String>,
) -> PyResult<(Vec<String>, Vec<String>, Vec<NamedColumn<'py>>)> {
    let table = run(py, || {
        let reader: &dyn MatrixReader = &file.reader;
        let (view, weights) = file.view_and_weights(view, weight_name.as_deref())?;
        let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader));
        trans_expected(&pixels, weights.as_deref(), &view)
    })?;
    let columns = table
        .columns()
        .into_iter()
        .map(|(name, values)| (name, column(py, values)))
        .collect();
    Ok((table.region1.clone(), table.region2.clone(), columns))
}

/// cooltools' `directionality`: per row the bin id, bad_bin_masked, the ratio and the index.
#[allow(clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (file, window_bp, view, weight_name, ignore_diags=None, min_dist_bad_bin=2))]
pub(crate) fn directionality<'py>(
    py: Python<'py>,
    file: &NativeFile,
    window_bp: u64,
    view: Option<Vec<RegionTuple>>,
    weight_name: Option<String>,
    ignore_diags: Option<usize>,
    min_dist_bad_bin: usize,
) -> PyResult<(
    Bound<'py, PyArray1<u64>>,
    Bound<'py, PyArray1<bool>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
)> {
    let table = run(py, || {
        let reader: &dyn MatrixReader = &file.reader;
        let (view, weights) = file.view_and_weights(view, weight_name.as_deref())?;
        // cooltools: the `weight` column's stored ignore_diags (we: else 2)
        let ignore_diags =
            ignore_diags.unwrap_or_else(|| reader.stored_ignore_diags("weight").unwrap_or(2));
        let params = DirectionalityParams {
            ignore_diags,
            min_dist_bad_bin,
            ..DirectionalityParams::new(window_bp)
        };
        let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader));
        di_table(&pixels, weights.as_deref(), &view, &params)
    })?;
    Ok((
        vec1(py, table.bins.iter().map(|&b| b as u64).collect()),
        vec1(py, table.bad_bin_masked),
        vec1(py, table.ratio),
        vec1(py, table.index),
    ))
}

/// cooltools' `insulation`: per row the bin id, the region's index, is_bad_bin, and the
/// windows' columns; plus the view's region names.
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (file, window_bp, view, weight_name, ignore_diags=None, min_frac_valid_pixels=0.66, min_dist_bad_bin=0, threshold="Li", append_raw_scores=false))]
pub(crate) fn insulation<'py>(
    py: Python<'py>,
    file: &NativeFile,
    window_bp: Vec<u64>,
    view: Option<Vec<RegionTuple>>,
    weight_name: Option<String>,
    ignore_diags: Option<usize>,
    min_frac_valid_pixels: f64,
    min_dist_bad_bin: usize,
    threshold: &str,
    append_raw_scores: bool,
) -> PyResult<(
    Bound<'py, PyArray1<u64>>,
    Bound<'py, PyArray1<u32>>,
    Bound<'py, PyArray1<bool>>,
    Vec<String>,
    Vec<NamedColumn<'py>>,
)> {
    let threshold: Threshold = threshold
        .parse()
        .map_err(|e: Error| ContactmapError::new_err(e.to_string()))?;
    let (table, regions) = run(py, || {
        let reader: &dyn MatrixReader = &file.reader;
        let (view, weights) = file.view_and_weights(view, weight_name.as_deref())?;
        // cooltools: the weight column's stored ignore_diags (we: else 2, and 2 on raw counts)
        let ignore_diags = ignore_diags.unwrap_or_else(|| {
            weight_name
                .as_deref()
                .and_then(|name| reader.stored_ignore_diags(name))
                .unwrap_or(2)
        });
        let params = InsulationParams {
            ignore_diags,
            min_frac_valid_pixels,
            min_dist_bad_bin,
            threshold,
            append_raw_scores,
            ..InsulationParams::new(window_bp)
        };
        let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader));
        let table = insulation_table(&pixels, weights.as_deref(), &view, &params)?;
        let regions: Vec<String> = view.regions().iter().map(|r| r.name.clone()).collect();
        Ok::<_, Error>((table, regions))
    })?;
    let columns = table
        .track_columns()
        .into_iter()
        .map(|(name, values)| {
            let array = match values {
                TrackValues::Real(v) => vec1(py, v.to_vec()).into_any(),
                TrackValues::Flag(v) => vec1(py, v.to_vec()).into_any(),
            };
            (name, array)
        })
        .collect();
    Ok((
        vec1(py, table.bins.iter().map(|&b| b as u64).collect()),
        vec1(py, table.region.iter().map(|&r| r as u32).collect()),
        vec1(py, table.is_bad_bin.clone()),
        regions,
        columns,
    ))
}

/// The balancing options as Python passes them: one dict, read by key (`_tables.balance` builds
/// it; a missing key is a TypeError naming it); `None` takes the method's reference default
/// (`BalanceParams::for_method`: cooler's for ICE, Juicer's for the others).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct BalanceOptions {
    method: String,
    cis_only: bool,
    ignore_diags: Option<u64>,
    mad_max: Option<f64>,
    min_nnz: Option<u64>,
    min_count: Option<f64>,
    tol: Option<f64>,
    max_iters: Option<usize>,
    rescale_marginals: Option<bool>,
}

impl BalanceOptions {
    fn params(&self) -> PyResult<BalanceParams> {
        let BalanceOptions {
            method,
            cis_only,
            ignore_diags,
            mad_max,
            min_nnz,
            min_count,
            tol,
            max_iters,
            rescale_marginals,
        } = self;
        let method = Method::from_juicer_name(method).ok_or_else(|| {
            ContactmapError::new_err(format!(
                "method '{method}': expected ice, kr, vc, vc_sqrt or scale"
            ))
        })?;
        let defaults = BalanceParams::for_method(method);
        Ok(BalanceParams {
            method,
            scope: if *cis_only {
                Scope::Cis
            } else {
                Scope::GenomeWide
            },
            ignore_diags: ignore_diags.unwrap_or(defaults.ignore_diags),
            mad_max: mad_max.unwrap_or(defaults.mad_max),
            min_nnz: min_nnz.unwrap_or(defaults.min_nnz),
            min_count: min_count.unwrap_or(defaults.min_count),
            tol: tol.unwrap_or(defaults.tol),
            max_iters: max_iters.unwrap_or(defaults.max_iters),
            rescale_marginals: rescale_marginals.unwrap_or(defaults.rescale_marginals),
            ..defaults
        })
    }
}

/// The weights and the summary dict of a balancing.
fn balanced<'py>(
    py: Python<'py>,
    params: &BalanceParams,
    result: BalanceResult,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyDict>)> {
    let summary = PyDict::new(py);
    summary.set_item("method", params.method.name())?;
    summary.set_item("converged", result.converged)?;
    summary.set_item("scale", result.scale)?;
    summary.set_item("var", result.var)?;
    summary.set_item("n_iterations", result.n_iterations)?;
    summary.set_item("n_masked", result.n_masked())?;
    Ok((vec1(py, result.weights), summary))
}

/// Balance a map: (weights, summary dict).
#[pyfunction]
pub(crate) fn balance<'py>(
    py: Python<'py>,
    file: &NativeFile,
    options: BalanceOptions,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyDict>)> {
    let params = options.params()?;
    let result = run(py, || {
        let pixels = load_pixels_for_balancing(&file.reader, u64::MAX)?;
        balance_pixels(&pixels, &params)
    })?;
    balanced(py, &params, result)
}

/// `contactmap balance URI --store`: balance the cooler at `uri` (a .cool or an .mcool
/// resolution, not open elsewhere in this process) and store the weights as the column `name`
/// with cooler's attributes; an existing column only with `overwrite`, unconverged weights only
/// with `store_unconverged`. The file is locked while this runs.
#[pyfunction]
pub(crate) fn balance_store<'py>(
    py: Python<'py>,
    uri: &str,
    name: &str,
    overwrite: bool,
    store_unconverged: bool,
    options: BalanceOptions,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyDict>)> {
    let params = options.params()?;
    let result = run(py, || {
        let (path, _) = io::split_uri(uri);
        if io::detect_kind(path)? != io::FileKind::Hdf5 {
            return Err(Error::Argument(format!(
                "{uri}: store=True writes into .cool / .mcool files only"
            )));
        }
        let _lock = io::WriteLock::acquire(std::path::Path::new(path))?;
        check_target(uri, name, overwrite)?;
        // the reader is closed before the file is opened to write
        let (balanced, bins) = {
            let reader = io::open_matrix(uri, &OpenOptions::default())?;
            let balanced = balance_reader(reader.as_ref(), &params, default_memory_budget())?;
            (balanced, reader.bins().clone())
        };
        let result = balanced.result;
        if !result.converged && !store_unconverged {
            return Err(Error::Argument(format!(
                "{uri}: {} balancing did not converge within {} iterations ({}); nothing \
                 stored: raise max_iters or tol{}, or pass store_unconverged=True",
                params.method.name(),
                params.max_iters,
                result.unconverged_detail(&bins, params.tol),
                if balanced.disconnected {
                    " (the map has no trans contacts: balance with cis_only=True)"
                } else {
                    ""
                }
            )));
        }
        store_balanced(uri, name, &params, &result, overwrite)?;
        Ok(result)
    })?;
    balanced(py, &params, result)
}
