//! Differences between conditions: `diff loops`, `diff boundaries`, `diff compartments`,
//! `diff regions`. The tables of the last three come back as the command line writes them.

use contactmap::compartments::cis::CisEigParams;
use contactmap::diff::boundaries::{
    boundaries_tsv, compare_boundaries, default_window_bp, BoundaryParams,
};
use contactmap::diff::calls::called_loops;
use contactmap::diff::compartments::{
    compare_compartments, compartments_tsv, switches_bed, CompartmentParams,
};
use contactmap::diff::loops::{compare_loops, sites_of, LoopParams};
use contactmap::diff::maps::check_same_bins;
use contactmap::diff::regions::{
    compare_regions, pairs_of, regions_tsv, sliding_pairs, RegionParams,
};
use contactmap::genome::View;
use contactmap::io::bed::read_bedpe;
use contactmap::io::{self, MatrixReader, OpenOptions};
use contactmap::tads::insulation::InsulationParams;
use contactmap::tads::threshold::Threshold;
use pyo3::prelude::*;
use pyo3::types::PyList;

use crate::convert::{run, vec1, NamedColumn};

/// `contactmap diff loops` on maps opened from `first` and `second` (URIs): the loops of the
/// BEDPE `loops`, or the dots called on each condition when `None`; the columns of
/// PREFIX.loops.bedpe.
#[pyfunction]
#[pyo3(signature = (first, second, loops=None, half_width=1, alpha=0.05, cooks_filter=true))]
pub(crate) fn diff_loops<'py>(
    py: Python<'py>,
    first: Vec<String>,
    second: Vec<String>,
    loops: Option<String>,
    half_width: usize,
    alpha: f64,
    cooks_filter: bool,
) -> PyResult<Vec<NamedColumn<'py>>> {
    let (records, comparison) = run(py, || {
        let open = |uris: &[String]| -> contactmap::error::Result<Vec<Box<dyn MatrixReader>>> {
            uris.iter()
                .map(|uri| io::open_matrix(uri, &OpenOptions::default()))
                .collect()
        };
        let (a, b) = (open(&first)?, open(&second)?);
        let a: Vec<&dyn MatrixReader> = a.iter().map(|r| r.as_ref()).collect();
        let b: Vec<&dyn MatrixReader> = b.iter().map(|r| r.as_ref()).collect();
        let (records, sites) = match &loops {
            Some(path) => {
                let records = read_bedpe(std::path::Path::new(path))?;
                let sites = sites_of(a[0].bins(), &records, path)?;
                (records, sites)
            }
            None => {
                let called = called_loops(&a, &b, None)?;
                (called.records, called.sites)
            }
        };
        let params = LoopParams {
            half_width,
            alpha,
            cooks_filter,
            ..LoopParams::default()
        };
        let comparison = compare_loops(&a, &b, &sites, &params)?;
        Ok((records, comparison))
    })?;
    let n = records.len();
    let text = |values: Vec<String>| -> PyResult<Bound<'py, PyAny>> {
        Ok(PyList::new(py, values)?.into_any())
    };
    let r = &comparison.results;
    let (low, high): (Vec<f64>, Vec<f64>) = (0..n).map(|l| comparison.interval(l)).unzip();
    let mut columns: Vec<NamedColumn<'py>> = vec![
        (
            "chrom1".into(),
            text(records.iter().map(|x| x.first.chrom.clone()).collect())?,
        ),
        (
            "start1".into(),
            vec1(py, records.iter().map(|x| x.first.start as i64).collect()).into_any(),
        ),
        (
            "end1".into(),
            vec1(py, records.iter().map(|x| x.first.end as i64).collect()).into_any(),
        ),
        (
            "chrom2".into(),
            text(records.iter().map(|x| x.second.chrom.clone()).collect())?,
        ),
        (
            "start2".into(),
            vec1(py, records.iter().map(|x| x.second.start as i64).collect()).into_any(),
        ),
        (
            "end2".into(),
            vec1(py, records.iter().map(|x| x.second.end as i64).collect()).into_any(),
        ),
        ("baseMean".into(), vec1(py, r.base_mean.clone()).into_any()),
        (
            "log2FoldChange".into(),
            vec1(py, r.log2_fold_change.clone()).into_any(),
        ),
        ("lfc_low".into(), vec1(py, low).into_any()),
        ("lfc_high".into(), vec1(py, high).into_any()),
        ("lfcSE".into(), vec1(py, r.lfc_se.clone()).into_any()),
        ("pvalue".into(), vec1(py, r.p_value.clone()).into_any()),
        ("qvalue".into(), vec1(py, r.q_value.clone()).into_any()),
        (
            "mean_A".into(),
            vec1(py, comparison.condition_means.column(0).to_vec()).into_any(),
        ),
        (
            "mean_B".into(),
            vec1(py, comparison.condition_means.column(1).to_vec()).into_any(),
        ),
        (
            "direction".into(),
            text(
                (0..n)
                    .map(|l| comparison.direction(l).to_string())
                    .collect(),
            )?,
        ),
    ];
    for (s, name) in comparison.sample_names().into_iter().enumerate() {
        let counts = comparison
            .counts
            .observed
            .column(s)
            .iter()
            .map(|c| *c as i64)
            .collect();
        columns.push((format!("count_{name}"), vec1(py, counts).into_any()));
    }
    Ok(columns)
}

/// Maps and the weights of each (none when raw).
type Maps = (Vec<Box<dyn MatrixReader>>, Vec<Vec<f64>>);

/// Maps opened from URIs, with their weight column `weight_name` (`None`: raw counts).
fn open_maps(uris: &[String], weight_name: Option<&str>) -> contactmap::error::Result<Maps> {
    let mut readers = Vec::with_capacity(uris.len());
    let mut weights = Vec::with_capacity(uris.len());
    for uri in uris {
        let reader = io::open_matrix(uri, &OpenOptions::default())?;
        if let Some(name) = weight_name {
            weights.push(reader.weights(name)?.values);
        }
        readers.push(reader);
    }
    Ok((readers, weights))
}

/// `contactmap diff boundaries` on the maps `first` (A) and `second` (B): the text of
/// PREFIX.boundaries.tsv.
#[pyfunction]
#[pyo3(signature = (first, second, window_bp=None, threshold="li", ignore_diags=2, match_bins=2, alpha=0.05, weight_name="weight"))]
#[allow(clippy::too_many_arguments)] // the command's options, one by one
pub(crate) fn diff_boundaries(
    py: Python<'_>,
    first: Vec<String>,
    second: Vec<String>,
    window_bp: Option<u64>,
    threshold: &str,
    ignore_diags: usize,
    match_bins: usize,
    alpha: f64,
    weight_name: &str,
) -> PyResult<String> {
    let threshold = threshold.to_string();
    let weight_name = weight_name.to_string();
    run(py, move || {
        let uris: Vec<String> = first.iter().chain(&second).cloned().collect();
        let (readers, weights) = open_maps(&uris, Some(&weight_name))?;
        let refs: Vec<&dyn MatrixReader> = readers.iter().map(|r| r.as_ref()).collect();
        let bins = refs[0].bins();
        let window_bp = match window_bp {
            Some(w) => w,
            None => default_window_bp(bins)?,
        };
        let params = BoundaryParams {
            insulation: InsulationParams {
                ignore_diags,
                threshold: threshold.parse::<Threshold>()?,
                ..InsulationParams::new(vec![window_bp])
            },
            match_bins,
            alpha,
            ..BoundaryParams::new(window_bp)
        };
        let weight_refs: Vec<&[f64]> = weights.iter().map(|w| w.as_slice()).collect();
        let view = View::chromosomes(bins);
        let comparison = compare_boundaries(&refs, &weight_refs, first.len(), &view, &params)?;
        Ok(boundaries_tsv(bins, &comparison))
    })
}

/// `contactmap diff compartments` on the maps `first` (A) and `second` (B), E1 oriented by
/// `track` (one value per bin) where given: the texts of PREFIX.compartments.tsv and
/// PREFIX.switches.bed.
#[pyfunction]
#[pyo3(signature = (first, second, track=None, ignore_diags=2, clip_percentile=99.9, alpha=0.05, weight_name="weight"))]
#[allow(clippy::too_many_arguments)] // the command's options, one by one
pub(crate) fn diff_compartments(
    py: Python<'_>,
    first: Vec<String>,
    second: Vec<String>,
    track: Option<Vec<f64>>,
    ignore_diags: usize,
    clip_percentile: f64,
    alpha: f64,
    weight_name: &str,
) -> PyResult<(String, String)> {
    let weight_name = weight_name.to_string();
    run(py, move || {
        let uris: Vec<String> = first.iter().chain(&second).cloned().collect();
        let (readers, weights) = open_maps(&uris, Some(&weight_name))?;
        let refs: Vec<&dyn MatrixReader> = readers.iter().map(|r| r.as_ref()).collect();
        let bins = refs[0].bins();
        let track = match track {
            Some(values) if values.len() != bins.n_bins() => {
                return Err(contactmap::error::Error::Argument(format!(
                    "the phasing track has {} values for {} bins",
                    values.len(),
                    bins.n_bins()
                )));
            }
            // the track masked where the first map has no weight, as the command line does
            Some(values) => Some(
                values
                    .iter()
                    .zip(&weights[0])
                    .map(|(t, w)| if w.is_nan() { f64::NAN } else { *t })
                    .collect::<Vec<f64>>(),
            ),
            None => None,
        };
        let params = CompartmentParams {
            eigs: CisEigParams {
                n_eigs: 1,
                ignore_diags,
                clip_percentile,
            },
            alpha,
        };
        params.eigs.check()?;
        let weight_refs: Vec<&[f64]> = weights.iter().map(|w| w.as_slice()).collect();
        let view = View::chromosomes(bins);
        let comparison = compare_compartments(
            &refs,
            &weight_refs,
            first.len(),
            &view,
            track.as_deref(),
            &params,
        )?;
        Ok((
            compartments_tsv(bins, &comparison),
            switches_bed(bins, &comparison),
        ))
    })
}

/// `contactmap diff regions` (CHESS) of `reference` against `query`: the pairs of the BEDPE
/// `pairs`, or windows of `window_bp` every `step_bp`; the text of PREFIX.regions.tsv.
#[pyfunction]
#[pyo3(signature = (reference, query, pairs=None, window_bp=None, step_bp=None, raw=false, weight_name="weight", min_bins=20, mappability_cutoff=0.1, relative_window=1.0, absolute_window=None))]
#[allow(clippy::too_many_arguments)] // the command's options, one by one
pub(crate) fn diff_regions(
    py: Python<'_>,
    reference: String,
    query: String,
    pairs: Option<String>,
    window_bp: Option<u64>,
    step_bp: Option<u64>,
    raw: bool,
    weight_name: &str,
    min_bins: usize,
    mappability_cutoff: f64,
    relative_window: f64,
    absolute_window: Option<usize>,
) -> PyResult<String> {
    let weight_name = (!raw).then(|| weight_name.to_string());
    run(py, move || {
        let (readers, weights) = open_maps(&[reference, query], weight_name.as_deref())?;
        let (a, b) = (readers[0].as_ref(), readers[1].as_ref());
        check_same_bins(&[a, b])?;
        let pairs = match (pairs, window_bp) {
            (Some(path), _) => {
                let records = read_bedpe(std::path::Path::new(&path))?;
                pairs_of(a, b, &records, &path)?
            }
            (None, Some(window)) => sliding_pairs(a.bins(), window, step_bp.unwrap_or(window)),
            (None, None) => {
                return Err(contactmap::error::Error::Argument(
                    "give pairs or window_bp".into(),
                ))
            }
        };
        let params = RegionParams {
            min_bins,
            mappability_cutoff,
            relative_window,
            absolute_window,
        };
        let weight = |k: usize| weights.get(k).map(|w| w.as_slice());
        let similarity = compare_regions(a, weight(0), b, weight(1), &pairs, &params)?;
        Ok(regions_tsv(a.bins(), &pairs, &similarity))
    })
}
