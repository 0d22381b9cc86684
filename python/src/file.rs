//! Opening a map and fetching from it: `NativeFile` (hictkpy's `File`, cooler's `Cooler`).

use std::ops::Range;

use contactmap::error::Error;
use contactmap::genome::BinTable;
use contactmap::genome::{RegionSpec, View};
use contactmap::io::{
    self, query_dense_into, query_pixels, CheckedCounts, MatrixReader, OpenOptions,
};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::convert::{py_err, run, vec1, RegionTuple};

/// A contact map opened by contactmap (`.cool`, `.mcool::/resolutions/R`, `.hic` with `@R`,
/// HiCExplorer `.h5`, text tables).
#[pyclass(frozen, module = "contactmap._native")]
pub(crate) struct NativeFile {
    pub(crate) reader: CheckedCounts,
}

impl NativeFile {
    pub(crate) fn raw(&self) -> &dyn MatrixReader {
        self.reader.inner()
    }

    /// What every analysis starts from: the view (regions given, or the chromosomes) and the
    /// weights `weight_name` (None: raw counts).
    pub(crate) fn view_and_weights(
        &self,
        view: Option<Vec<RegionTuple>>,
        weight_name: Option<&str>,
    ) -> Result<(View, Option<Vec<f64>>), Error> {
        Ok((view_of(&self.reader, view)?, self.weights_of(weight_name)?))
    }

    pub(crate) fn weights_of(&self, name: Option<&str>) -> Result<Option<Vec<f64>>, Error> {
        match name {
            None => Ok(None),
            Some(name) => {
                let reader = self.raw();
                if !reader.weight_names().iter().any(|n| n == name) {
                    return Err(Error::Argument(format!(
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

pub(crate) fn range(pair: (usize, usize)) -> Range<usize> {
    pair.0..pair.1
}

#[pymethods]
impl NativeFile {
    #[new]
    #[pyo3(signature = (uri, resolution=None))]
    fn new(py: Python<'_>, uri: &str, resolution: Option<u64>) -> PyResult<Self> {
        let options = OpenOptions {
            resolution,
            ..OpenOptions::default()
        };
        let reader = run(py, || io::open_matrix(uri, &options))?;
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
        self.raw().bins().resolution()
    }

    /// Per bin: chromosome index, start, end (bp).
    fn bin_columns<'py>(&self, py: Python<'py>) -> BinArrays<'py> {
        bin_arrays(py, self.raw().bins())
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
pub(crate) fn view_of(
    reader: &dyn MatrixReader,
    regions: Option<Vec<RegionTuple>>,
) -> Result<View, Error> {
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

/// The resolutions of a multi-resolution file (`.mcool`, `.hic`), ascending; empty for a
/// single-resolution file.
#[pyfunction]
pub(crate) fn resolutions(py: Python<'_>, path: &str) -> PyResult<Vec<u64>> {
    run(py, || io::list_resolutions(path))
}

/// Per bin: chromosome index, start, end.
pub(crate) type BinArrays<'py> = (
    Bound<'py, PyArray1<u32>>,
    Bound<'py, PyArray1<u64>>,
    Bound<'py, PyArray1<u64>>,
);

/// The columns of a bin table: chromosome index, start, end (bp).
pub(crate) fn bin_arrays<'py>(py: Python<'py>, bins: &BinTable) -> BinArrays<'py> {
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
