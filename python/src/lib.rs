//! `contactmap._native`: the library's functions as Python sees them. This crate only converts
//! (Python arguments to the library's parameters, its results to numpy arrays, lists and
//! strings); every computation is the library's, the same calls the command line makes. The
//! GIL is released while the library works, and numpy arrays take over the library's vectors
//! without a copy.

use std::ops::Range;

use contactmap::balance::{balance as balance_pixels, BalanceParams, Method, Scope};
use contactmap::compartments::cis::CisEigParams;
use contactmap::compartments::eigs::{eigs_cis as cis_eigs, eigs_trans as trans_eigs, Phasing};
use contactmap::compartments::phasing::SortMetric;
use contactmap::compartments::saddle::{
    digitize as digitize_track, saddle_cis, saddle_strength as saddle_strengths, saddle_trans,
    Binning, Saddle, SaddleParams,
};
use contactmap::compartments::trans::TransEigParams;
use contactmap::error::Error;
use contactmap::expected::{
    expected_cis as cis_expected, expected_trans as trans_expected, CisParams, RegionSpec, View,
};
use contactmap::io::tables::Column;
use contactmap::io::{
    self, load_pixels_for_balancing, query_dense_into, query_pixels, CheckedCounts, LoadedPixels,
    MatrixReader, OpenOptions, StreamedPixels,
};
use contactmap::tads::directionality::{directionality as di_table, DirectionalityParams};
use contactmap::tads::insulation::{insulation as insulation_table, InsulationParams, TrackValues};
use contactmap::tads::threshold::Threshold;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyFileNotFoundError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

create_exception!(
    contactmap,
    ContactmapError,
    PyValueError,
    "An input contactmap cannot use (a file, a region, a parameter): the command line's one-line message."
);

/// The library's error as a Python exception: a missing file as FileNotFoundError, anything
/// else as ContactmapError (a ValueError), with the command line's message.
fn py_err(error: Error) -> PyErr {
    if let Error::Io { source, .. } = &error {
        if source.kind() == std::io::ErrorKind::NotFound {
            return PyFileNotFoundError::new_err(error.to_string());
        }
    }
    ContactmapError::new_err(error.to_string())
}

/// Run `work` with the GIL released, on a thread of its own, while this thread watches for
/// Ctrl-C: on a signal whose handler raises (KeyboardInterrupt), the library is asked to stop
/// (`contactmap::interrupt`), its streaming loops return at their next block, and the
/// handler's exception is raised.
fn run<T: Send>(py: Python<'_>, work: impl FnOnce() -> Result<T, Error> + Send) -> PyResult<T> {
    let outcome = py.detach(|| {
        std::thread::scope(|scope| {
            let (done, result) = std::sync::mpsc::channel();
            scope.spawn(move || {
                let _ = done.send(std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)));
            });
            loop {
                match result.recv_timeout(std::time::Duration::from_millis(50)) {
                    Ok(outcome) => return Ok(outcome),
                    Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                        if let Err(signal) = Python::attach(|py| py.check_signals()) {
                            contactmap::interrupt::request();
                            let _ = result.recv();
                            contactmap::interrupt::clear();
                            return Err(signal);
                        }
                    }
                    Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                        return Ok(Err(Box::new("the worker thread ended without a result")
                            as Box<dyn std::any::Any + Send>));
                    }
                }
            }
        })
    })?;
    match outcome {
        Ok(result) => result.map_err(py_err),
        Err(panic) => {
            let message = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".to_string());
            Err(pyo3::panic::PanicException::new_err(message))
        }
    }
}

fn vec1<'py, T: numpy::Element>(py: Python<'py>, values: Vec<T>) -> Bound<'py, PyArray1<T>> {
    PyArray1::from_vec(py, values)
}

/// A view region from Python: (chrom, start, end, name).
type RegionTuple = (String, u64, u64, Option<String>);

/// Per bin: chromosome index, start, end.
type BinArrays<'py> = (
    Bound<'py, PyArray1<u32>>,
    Bound<'py, PyArray1<u64>>,
    Bound<'py, PyArray1<u64>>,
);

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

/// A named column: (name, numpy array).
type NamedColumn<'py> = (String, Bound<'py, PyAny>);

/// A contact map opened by contactmap (`.cool`, `.mcool::/resolutions/R`, `.hic` with `@R`,
/// HiCExplorer `.h5`, text tables).
#[pyclass(frozen, module = "contactmap._native")]
struct NativeFile {
    reader: CheckedCounts,
}

impl NativeFile {
    fn raw(&self) -> &dyn MatrixReader {
        self.reader.inner()
    }

    /// What every analysis starts from: the view (regions given, or the chromosomes) and the
    /// weights `weight_name` (None: raw counts).
    fn view_and_weights(
        &self,
        view: Option<Vec<RegionTuple>>,
        weight_name: Option<&str>,
    ) -> Result<(View, Option<Vec<f64>>), Error> {
        Ok((view_of(&self.reader, view)?, self.weights_of(weight_name)?))
    }

    fn weights_of(&self, name: Option<&str>) -> Result<Option<Vec<f64>>, Error> {
        match name {
            None => Ok(None),
            Some(name) => {
                let reader = self.raw();
                if !reader.weight_names().iter().any(|n| n == name) {
                    return Err(Error::Invalid(format!(
                        "{}: no weight column '{name}' (the file has: {})",
                        reader.source(),
                        if reader.weight_names().is_empty() {
                            "none; balance it first".to_string()
                        } else {
                            reader.weight_names().join(", ")
                        }
                    )));
                }
                Ok(Some(reader.weights(name)?.values))
            }
        }
    }
}

fn range(pair: (usize, usize)) -> Range<usize> {
    pair.0..pair.1
}

#[pymethods]
impl NativeFile {
    #[new]
    fn new(py: Python<'_>, uri: &str) -> PyResult<Self> {
        let reader = run(py, || io::open_matrix(uri, &OpenOptions::default()))?;
        Ok(NativeFile {
            reader: CheckedCounts::new(reader),
        })
    }

    /// The URI as opened.
    fn uri(&self) -> String {
        self.raw().source().to_string()
    }

    /// The format and version, as `contactmap info` names it.
    fn format(&self) -> String {
        self.raw().info().format
    }

    /// (name, length in bp) per chromosome, in the file's order.
    fn chromosomes(&self) -> Vec<(String, u64)> {
        self.raw()
            .bins()
            .chroms()
            .iter()
            .map(|c| (c.name.clone(), c.length_bp))
            .collect()
    }

    /// The bin size in bp, or None for variable bins.
    fn resolution(&self) -> Option<u64> {
        self.raw().bins().bin_size_bp()
    }

    /// Per bin: chromosome index, start, end (bp).
    fn bin_columns<'py>(&self, py: Python<'py>) -> BinArrays<'py> {
        let bins = self.raw().bins();
        let n = bins.n_bins();
        let (mut chrom, mut start, mut end) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        for bin in bins.iter() {
            chrom.push(bin.chrom_id as u32);
            start.push(bin.start);
            end.push(bin.end);
        }
        (vec1(py, chrom), vec1(py, start), vec1(py, end))
    }

    /// The file's attributes as JSON text.
    fn attributes_json(&self) -> String {
        let map: serde_json::Map<String, serde_json::Value> =
            self.raw().info().attributes.into_iter().collect();
        serde_json::Value::Object(map).to_string()
    }

    /// The weight columns (normalisations) the file has.
    fn weight_names(&self) -> Vec<String> {
        self.raw().weight_names()
    }

    /// The weights `name` (multiplicative, cooler's convention; NaN for masked bins).
    fn weights<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let values = run(py, || self.weights_of(Some(name)))?.unwrap_or_default();
        Ok(vec1(py, values))
    }

    /// The bins of a region (`chr2L`, `chr2L:1,000,000-2,000,000`): (first, end).
    fn region_bins(&self, region: &str) -> PyResult<(usize, usize)> {
        let bins = self
            .raw()
            .bins()
            .parse_region_bins(region)
            .map_err(py_err)?;
        Ok((bins.start, bins.end))
    }

    /// Stored pixel count and sum of counts.
    fn totals(&self, py: Python<'_>) -> PyResult<(u64, f64)> {
        run(py, || self.raw().totals())
    }

    /// The dense rectangle `rows x cols` of the symmetric matrix (`io::query_dense_into`),
    /// written into a numpy array that numpy allocates zeroed (huge pages, pages of empty
    /// parts never touched).
    #[pyo3(signature = (rows, cols, weight_name=None))]
    fn fetch_dense<'py>(
        &self,
        py: Python<'py>,
        rows: (usize, usize),
        cols: (usize, usize),
        weight_name: Option<&str>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let weights = run(py, || self.weights_of(weight_name))?;
        let (rows, cols) = (range(rows), range(cols));
        let shape = [rows.len(), cols.len()];
        let array = PyArray2::<f64>::zeros(py, shape, false);
        {
            let mut values = array.readwrite();
            let out = values
                .as_slice_mut()
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
            run(py, || {
                query_dense_into(self.raw(), rows, cols, weights.as_deref(), out)
            })?;
        }
        Ok(array)
    }

    /// The stored pixels of the query (`io::query_pixels`): bin1, bin2, count and balanced.
    #[allow(clippy::type_complexity)]
    #[pyo3(signature = (rows, cols, weight_name=None))]
    fn fetch_pixels<'py>(
        &self,
        py: Python<'py>,
        rows: (usize, usize),
        cols: (usize, usize),
        weight_name: Option<&str>,
    ) -> PyResult<(
        Bound<'py, PyArray1<i64>>,
        Bound<'py, PyArray1<i64>>,
        Bound<'py, PyArray1<f64>>,
        Option<Bound<'py, PyArray1<f64>>>,
    )> {
        let (bin1, bin2, count, balanced) = run(py, || {
            let weights = self.weights_of(weight_name)?;
            let q = query_pixels(self.raw(), range(rows), range(cols), weights.as_deref())?;
            // int64 as pandas and cooler have bin ids (converted in place, no new allocation)
            let ids = |v: Vec<u64>| -> Vec<i64> { v.into_iter().map(|b| b as i64).collect() };
            Ok((
                ids(q.pixels.bin1),
                ids(q.pixels.bin2),
                q.pixels.count,
                q.balanced,
            ))
        })?;
        Ok((
            vec1(py, bin1),
            vec1(py, bin2),
            vec1(py, count),
            balanced.map(|b| vec1(py, b)),
        ))
    }
}

/// The view: the regions given as (chrom, start, end, name) or the whole chromosomes.
fn view_of(reader: &dyn MatrixReader, regions: Option<Vec<RegionTuple>>) -> Result<View, Error> {
    match regions {
        None => Ok(View::chromosomes(reader.bins())),
        Some(regions) => {
            let specs: Vec<RegionSpec> = regions
                .into_iter()
                .map(|(chrom, start_bp, end_bp, name)| RegionSpec {
                    chrom,
                    start_bp,
                    end_bp,
                    name,
                })
                .collect();
            View::new(reader.bins(), &specs)
        }
    }
}

fn column<'py>(py: Python<'py>, values: Column<'_>) -> Bound<'py, PyAny> {
    match values {
        Column::Integer(v) => vec1(py, v.to_vec()).into_any(),
        Column::Real(v) => vec1(py, v.to_vec()).into_any(),
    }
}

/// cooltools' `expected_cis`: (region1, region2, [(column, values)]).
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (file, view, weight_name, ignore_diags=2, smooth=true, aggregate_smoothed=true, smooth_sigma=0.1))]
fn expected_cis<'py>(
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
fn expected_trans<'py>(
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
#[pyo3(signature = (file, window_bp, view, weight_name, ignore_diags=2, min_dist_bad_bin=2))]
fn directionality<'py>(
    py: Python<'py>,
    file: &NativeFile,
    window_bp: u64,
    view: Option<Vec<RegionTuple>>,
    weight_name: Option<String>,
    ignore_diags: usize,
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
#[pyo3(signature = (file, window_bp, view, weight_name, ignore_diags=2, min_frac_valid_pixels=0.66, min_dist_bad_bin=0, threshold="Li", append_raw_scores=false))]
fn insulation<'py>(
    py: Python<'py>,
    file: &NativeFile,
    window_bp: Vec<u64>,
    view: Option<Vec<RegionTuple>>,
    weight_name: Option<String>,
    ignore_diags: usize,
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

/// cooltools' `eigs_cis`: per view region its eigenpairs (`RegionEigsTuple`), and
/// the warnings (unconverged or unoriented vectors).
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (file, view, weight_name, phasing_track=None, n_eigs=3, ignore_diags=None, clip_percentile=99.9, sort_metric=None))]
fn eigs_cis(
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
        let ignore_diags = ignore_diags.unwrap_or_else(|| {
            reader
                .weight_attribute(&weight_name, "ignore_diags")
                .and_then(|v| v.as_u64())
                .map_or(2, |v| v as usize)
        });
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
fn eigs_trans(
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

fn sort_metric_of(name: &str) -> PyResult<SortMetric> {
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
fn check_track(reader: &dyn MatrixReader, name: &str, track: Option<&[f64]>) -> Result<(), Error> {
    match track {
        Some(track) if track.len() != reader.bins().n_bins() => Err(Error::Invalid(format!(
            "{name}: {} values for {} bins",
            track.len(),
            reader.bins().n_bins()
        ))),
        _ => Ok(()),
    }
}

fn binning(qrange: Option<(f64, f64)>, vrange: Option<(f64, f64)>) -> PyResult<Binning> {
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
fn digitize<'py>(
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
fn saddle<'py>(
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
fn saddle_strength<'py>(
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

/// Balance a map: (weights, summary dict). Parameters left out take the method's reference
/// defaults (`BalanceParams::for_method`: cooler's for ICE, Juicer's for the others).
#[allow(clippy::too_many_arguments)]
#[pyfunction]
#[pyo3(signature = (file, method="ice", cis_only=false, ignore_diags=None, mad_max=None, min_nnz=None, min_count=None, tol=None, max_iters=None, rescale_marginals=None))]
fn balance<'py>(
    py: Python<'py>,
    file: &NativeFile,
    method: &str,
    cis_only: bool,
    ignore_diags: Option<u64>,
    mad_max: Option<f64>,
    min_nnz: Option<u64>,
    min_count: Option<f64>,
    tol: Option<f64>,
    max_iters: Option<usize>,
    rescale_marginals: Option<bool>,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyDict>)> {
    let method = Method::from_juicer_name(method).ok_or_else(|| {
        ContactmapError::new_err(format!(
            "method '{method}': expected ice, kr, vc, vc_sqrt or scale"
        ))
    })?;
    let defaults = BalanceParams::for_method(method);
    let params = BalanceParams {
        method,
        scope: if cis_only {
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
    };
    let result = run(py, || {
        let pixels = load_pixels_for_balancing(&file.reader, u64::MAX)?;
        balance_pixels(&pixels, &params)
    })?;
    let summary = PyDict::new(py);
    summary.set_item("method", method.name())?;
    summary.set_item("converged", result.converged)?;
    summary.set_item("scale", result.scale)?;
    summary.set_item("var", result.var)?;
    summary.set_item("n_iterations", result.n_iterations)?;
    summary.set_item("n_masked", result.n_masked())?;
    Ok((vec1(py, result.weights), summary))
}

/// The resolutions of a multi-resolution file (`.mcool`, `.hic`), ascending; empty for a
/// single-resolution file.
#[pyfunction]
fn resolutions(py: Python<'_>, path: &str) -> PyResult<Vec<u64>> {
    run(py, || io::list_resolutions(path))
}

/// The native part of the `contactmap` package.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ContactmapError", m.py().get_type::<ContactmapError>())?;
    m.add_class::<NativeFile>()?;
    m.add_function(wrap_pyfunction!(expected_cis, m)?)?;
    m.add_function(wrap_pyfunction!(insulation, m)?)?;
    m.add_function(wrap_pyfunction!(expected_trans, m)?)?;
    m.add_function(wrap_pyfunction!(directionality, m)?)?;
    m.add_function(wrap_pyfunction!(eigs_cis, m)?)?;
    m.add_function(wrap_pyfunction!(eigs_trans, m)?)?;
    m.add_function(wrap_pyfunction!(digitize, m)?)?;
    m.add_function(wrap_pyfunction!(saddle, m)?)?;
    m.add_function(wrap_pyfunction!(saddle_strength, m)?)?;
    m.add_function(wrap_pyfunction!(balance, m)?)?;
    m.add_function(wrap_pyfunction!(resolutions, m)?)?;
    Ok(())
}
