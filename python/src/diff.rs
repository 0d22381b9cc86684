//! Differences between conditions: `diff loops`.

use contactmap::diff::calls::called_loops;
use contactmap::diff::loops::{compare_loops, sites_of, LoopParams};
use contactmap::io::bed::read_bedpe;
use contactmap::io::{self, MatrixReader, OpenOptions};
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
                let called = called_loops(&a, &b)?;
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
