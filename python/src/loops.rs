//! Loops and pileups: cooltools' `dots` and coolpuppy's `pileup`.

use contactmap::error::Error;
use contactmap::io::bed::{BedTable, BedpeTable, FeatureTable};
use contactmap::io::MatrixReader;
use contactmap::loops::lists::{merge_lists, ResolutionList};
use contactmap::loops::merge::MergeParams;
use contactmap::loops::{call_dots, DotsParams, EnrichedPixel};
use contactmap::pileup::shifts::ShiftParams;
use contactmap::pileup::{pileup as pile_up, CoverageNorm, Features, PileupParams, RescaleParams};
use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{array2, py_err, run, vec1, ContactmapError, NamedColumn, RegionTuple};
use crate::file::NativeFile;

/// The columns of enriched pixels: `bin1_id bin2_id count`, then per kernel
/// `la_exp.{kernel}.value`, then per kernel `la_exp.{kernel}.qval`, and `region` (the view
/// region's index).
fn pixel_columns<'py, 'a>(
    py: Python<'py>,
    kernels: &[&str],
    pixels: impl Iterator<Item = &'a EnrichedPixel> + Clone,
) -> Vec<NamedColumn<'py>> {
    let mut columns = vec![
        (
            "bin1_id".to_string(),
            vec1(py, pixels.clone().map(|p| p.bin1 as i64).collect()).into_any(),
        ),
        (
            "bin2_id".to_string(),
            vec1(py, pixels.clone().map(|p| p.bin2 as i64).collect()).into_any(),
        ),
        (
            "count".to_string(),
            vec1(py, pixels.clone().map(|p| p.count as i64).collect()).into_any(),
        ),
    ];
    for (suffix, of) in [
        (
            "value",
            (|p: &EnrichedPixel, k: usize| p.la_exp[k]) as fn(&EnrichedPixel, usize) -> f64,
        ),
        ("qval", |p: &EnrichedPixel, k: usize| p.qval[k]),
    ] {
        for (k, name) in kernels.iter().enumerate() {
            let values: Vec<f64> = pixels.clone().map(|p| of(p, k)).collect();
            columns.push((
                format!("la_exp.{name}.{suffix}"),
                vec1(py, values).into_any(),
            ));
        }
    }
    columns.push((
        "region".to_string(),
        vec1(py, pixels.map(|p| p.region as u32).collect()).into_any(),
    ));
    columns
}

/// cooltools' `dots`: the kernels' names, the view's region names, and the columns of the dots
/// (with clustering: the pixel columns, then `cstart1 cstart2 c_label c_size`) or of the
/// enriched pixels (`clustering_radius=None`).
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (file, view, weight_name, expected, w=None, p=None, max_separation_bp=10_000_000, max_nans_tolerated=1, n_lambda_bins=40, fdr=0.1, clustering_radius_bp=Some(20_000.0), cluster_filtering=true))]
pub(crate) fn dots<'py>(
    py: Python<'py>,
    file: &NativeFile,
    view: Option<Vec<RegionTuple>>,
    weight_name: String,
    expected: Vec<Vec<f64>>,
    w: Option<usize>,
    p: Option<usize>,
    max_separation_bp: u64,
    max_nans_tolerated: usize,
    n_lambda_bins: usize,
    fdr: f64,
    clustering_radius_bp: Option<f64>,
    cluster_filtering: bool,
) -> PyResult<(Vec<String>, Vec<String>, Vec<NamedColumn<'py>>)> {
    let (calls, regions) = run(py, || {
        let reader: &dyn MatrixReader = &file.reader;
        let (view, weights) = file.view_and_weights(view, Some(&weight_name))?;
        let resolution = reader.bins().resolution().ok_or_else(|| {
            Error::format(
                reader.source(),
                "dots needs fixed-size bins (kernels are counted in bins)",
            )
        })?;
        let defaults = match (w, p) {
            (Some(w), Some(p)) => DotsParams {
                w,
                p,
                ..DotsParams::default()
            },
            _ => DotsParams::for_resolution(resolution)?,
        };
        let params = DotsParams {
            max_separation_bp,
            max_nans_tolerated,
            n_lambda_bins,
            fdr,
            clustering_radius_bp,
            cluster_filtering,
            ..defaults
        };
        let calls = call_dots(
            reader,
            &weights.unwrap_or_default(),
            &view,
            &expected,
            &params,
        )?;
        let regions: Vec<String> = view.regions().iter().map(|r| r.name.clone()).collect();
        Ok((calls, regions))
    })?;
    let kernels: Vec<String> = calls.kernels.iter().map(|k| k.to_string()).collect();
    let columns = match &calls.dots {
        None => pixel_columns(py, &calls.kernels, calls.enriched.iter()),
        Some(dots) => {
            let mut columns = pixel_columns(py, &calls.kernels, dots.iter().map(|d| &d.pixel));
            for (name, values) in [
                ("cstart1", dots.iter().map(|d| d.centroid[0]).collect()),
                (
                    "cstart2",
                    dots.iter().map(|d| d.centroid[1]).collect::<Vec<f64>>(),
                ),
            ] {
                columns.push((name.to_string(), vec1(py, values).into_any()));
            }
            columns.push((
                "c_label".to_string(),
                vec1(py, dots.iter().map(|d| d.label as i64).collect()).into_any(),
            ));
            columns.push((
                "c_size".to_string(),
                vec1(py, dots.iter().map(|d| d.size as i64).collect()).into_any(),
            ));
            columns
        }
    };
    Ok((kernels, regions, columns))
}

/// One group's pileup: its label, strands (`+-`), distance band (bp, the upper edge None past
/// the last), grouping values, mean snippet, per-pixel snippet counts, n and control n.
type GroupTuple<'py> = (
    String,
    Option<String>,
    Option<(u64, Option<u64>)>,
    Vec<String>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<u64>>,
    usize,
    Option<usize>,
);

/// coolpuppy's `pileup` of features given as rows of text fields (a DataFrame's rows) with
/// their column names: per group a `GroupTuple` (the group of all snippets last), and what
/// was left out (a dict).
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (file, bedpe, header, rows, view, weight_name, expected, local=false, flank_bp=100_000, min_dist_bp=None, max_dist_bp=None, ignore_diags=2, rescale=None, shifts=None, by_distance=None, by_strand=false, flip_negative_strand=false, groupby=Vec::new(), trans=false, coverage_norm=None))]
pub(crate) fn pileup<'py>(
    py: Python<'py>,
    file: &NativeFile,
    bedpe: bool,
    header: Option<Vec<String>>,
    rows: Vec<Vec<String>>,
    view: Option<Vec<RegionTuple>>,
    weight_name: Option<String>,
    expected: Option<Vec<Vec<f64>>>,
    local: bool,
    flank_bp: u64,
    min_dist_bp: Option<f64>,
    max_dist_bp: Option<f64>,
    ignore_diags: usize,
    rescale: Option<(f64, usize)>,
    shifts: Option<(usize, u64, u64, u32)>,
    by_distance: Option<Vec<u64>>,
    by_strand: bool,
    flip_negative_strand: bool,
    groupby: Vec<String>,
    trans: bool,
    coverage_norm: Option<String>,
) -> PyResult<(Vec<GroupTuple<'py>>, Bound<'py, PyDict>)> {
    let coverage_norm = match coverage_norm.as_deref() {
        None => None,
        Some("total") => Some(CoverageNorm::Total),
        Some("cis") => Some(CoverageNorm::Cis),
        Some(other) => {
            return Err(ContactmapError::new_err(format!(
                "coverage_norm '{other}': expected 'total' or 'cis' (or False)"
            )))
        }
    };
    let pups = run(py, || {
        let reader: &dyn MatrixReader = &file.reader;
        let table = if bedpe {
            FeatureTable::Bedpe(BedpeTable::from_rows("features (BEDPE)", header, rows)?)
        } else {
            FeatureTable::Bed(BedTable::from_rows("features (BED)", header, rows)?)
        };
        let (features, groupby) = Features::of_table(table, &groupby, local)?;
        let (view, weights) = file.view_and_weights(view, weight_name.as_deref())?;
        let params = PileupParams {
            flank_bp,
            min_dist_bp,
            max_dist_bp,
            ignore_diags,
            rescale: rescale.map(|(flank, size)| RescaleParams { flank, size }),
            shifts: shifts.map(|(n, min_bp, max_bp, seed)| ShiftParams {
                n,
                min_bp,
                max_bp,
                seed,
            }),
            by_distance,
            by_strand,
            flip_negative_strand,
            groupby,
            trans,
            coverage_norm,
        };
        pile_up(
            reader,
            weights.as_deref(),
            &view,
            &features,
            expected.as_deref(),
            &params,
        )
    })?;
    let skipped = PyDict::new(py);
    let s = &pups.skipped;
    for (name, value) in [
        ("unknown_chromosome", s.unknown_chromosome),
        ("outside_view", s.outside_view),
        ("other_kind", s.other_kind),
        ("distance", s.distance),
        ("at_edge", s.at_edge),
        ("controls_at_edge", pups.controls_at_edge),
        ("below_diagonal", pups.below_diagonal),
    ] {
        skipped.set_item(name, value)?;
    }
    skipped.set_item("min_dist_bp", pups.min_dist_bp)?;
    let groups = pups
        .groups
        .into_iter()
        .map(|g| {
            (
                g.key.to_string(),
                g.key.strands.map(|(a, b)| format!("{a}{b}")),
                g.key.band.map(|b| (b.low, b.high)),
                g.key.values.clone(),
                array2(py, g.data),
                array2(py, g.num),
                g.n,
                g.control_n,
            )
        })
        .collect();
    Ok((groups, skipped))
}

/// One list of dots for [`merge_dots`]: its name (in messages), its resolution (bp), its
/// header and its rows (BEDPE's six fields first).
type DotList = (String, u64, Vec<String>, Vec<Vec<String>>);

/// `dots-merge` ([`merge_lists`]): the lists merged as Juicer's HiCCUPS merges its
/// resolutions; the merged table as TSV text.
#[pyfunction]
pub(crate) fn merge_dots(
    lists: Vec<DotList>,
    near_diagonal_bp: u64,
    strong_count: f64,
) -> PyResult<String> {
    let lists = lists
        .into_iter()
        .map(|(name, resolution, header, rows)| {
            let table = BedpeTable::from_rows(&name, Some(header), rows)?;
            ResolutionList::of_table(std::path::Path::new(&name), &table, Some(resolution))
        })
        .collect::<Result<Vec<_>, Error>>()
        .map_err(py_err)?;
    let params = MergeParams {
        near_diagonal_bp,
        strong_count,
    };
    let merged = merge_lists(&lists, &params).map_err(py_err)?;
    Ok(merged.to_tsv())
}
