//! Writers: `convert`, `zoomify`, `merge` (the command line's library calls) and cooler's
//! `create_cooler` (a map built from arrays).

use std::path::Path;

use contactmap::balance::Method;
use contactmap::error::Error;
use contactmap::export::cooler::balance_and_store;
use contactmap::export::{self, MatrixFormat, MatrixOutput, DEFAULT_HIC_NORMALIZATIONS};
use contactmap::genome::{Bin, BinTable, Chrom};
use contactmap::io::cool::resolutions::{fixed_resolution, mcool_resolutions};
use contactmap::io::cool::{write_cool, CoolWriteOptions};
use contactmap::io::merged::MergedReader;
use contactmap::io::{self, default_memory_budget, InMemory, MatrixReader, OpenOptions};
use contactmap::matrix::{CountType, MatrixBuilder, Weights, ZeroCounts};
use numpy::{PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::convert::{run, ContactmapError};

/// The three map formats a writer can produce, from the output's extension.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Cool,
    Mcool,
    Hic,
}

fn kind_of(path: &Path) -> Result<Kind, Error> {
    let name = path.to_string_lossy().to_ascii_lowercase();
    if name.ends_with(".mcool") {
        Ok(Kind::Mcool)
    } else if name.ends_with(".cool") {
        Ok(Kind::Cool)
    } else if name.ends_with(".hic") {
        Ok(Kind::Hic)
    } else {
        Err(Error::Argument(format!(
            "{}: the output is written as .cool, .mcool or .hic (give one of those extensions)",
            path.display()
        )))
    }
}

/// An error when the output `out` is one of the `inputs` (it would be replaced before it is
/// read): the same file, whatever its spelling or links (`io::same_file`).
fn refuse_input(out: &Path, inputs: &[&str]) -> Result<(), Error> {
    for uri in inputs {
        if io::same_file(Path::new(io::split_uri(uri).0), out) {
            return Err(Error::Argument(format!(
                "{}: this is an input too; write the output elsewhere",
                out.display()
            )));
        }
    }
    Ok(())
}

/// Normalisation names as methods (`export::parse_normalizations`); None is Juicer's set.
fn methods_of(names: Option<Vec<String>>) -> Result<Vec<Method>, Error> {
    export::parse_normalizations(&names.unwrap_or_default())
        .map_err(|e| Error::Argument(format!("normalizations: {e}")))
}

/// Write `reader` to `out` as its extension says, with `output` (the resolutions of an .mcool /
/// .hic from `resolutions`, the map's own when None); returns the warnings (unconverged
/// vectors).
fn write_map(
    reader: &dyn MatrixReader,
    out: &Path,
    resolutions: Option<Vec<String>>,
    output: MatrixOutput,
) -> Result<Vec<String>, Error> {
    let format = match kind_of(out)? {
        Kind::Cool => MatrixFormat::Cool,
        Kind::Mcool => MatrixFormat::Mcool,
        Kind::Hic => MatrixFormat::Hic,
    };
    if format == MatrixFormat::Cool && resolutions.is_some() {
        return Err(Error::Argument(
            "resolutions: a .cool holds one resolution; write an .mcool or a .hic".into(),
        ));
    }
    let output = MatrixOutput {
        resolutions: match (format, &resolutions) {
            (MatrixFormat::Cool, _) => Vec::new(),
            (_, None) => vec![fixed_resolution(reader.bins(), reader.source())?],
            (_, Some(items)) => mcool_resolutions(reader.bins(), reader.source(), items)?,
        },
        ..output
    };
    let unconverged = export::write_matrix(reader, out, format, &output)?;
    Ok(unconverged.iter().map(|u| u.to_string()).collect())
}

/// `contactmap convert`: the map at `input` written to `output` (.cool, .mcool, .hic).
#[pyfunction]
#[pyo3(signature = (input, output, resolutions=None, assembly=None, normalizations=None, compression_level=6))]
pub(crate) fn convert(
    py: Python<'_>,
    input: &str,
    output: &str,
    resolutions: Option<Vec<String>>,
    assembly: Option<String>,
    normalizations: Option<Vec<String>>,
    compression_level: u32,
) -> PyResult<Vec<String>> {
    if compression_level > 9 {
        return Err(ContactmapError::new_err(format!(
            "compression_level {compression_level}: 0 to 9"
        )));
    }
    run(py, || {
        refuse_input(Path::new(output), &[input])?;
        let methods = methods_of(normalizations)?;
        let reader = io::open_matrix(input, &OpenOptions::default())?;
        let options = MatrixOutput {
            assembly: assembly.or_else(|| reader.info().assembly()),
            normalizations: methods,
            compression_level,
            ..MatrixOutput::default()
        };
        let mut warnings = write_map(reader.as_ref(), Path::new(output), resolutions, options)?;
        warnings.extend(reader.warnings());
        Ok(warnings)
    })
}

/// `contactmap zoomify`: the levels of `input` in an .mcool or .hic; with `balance`, every
/// level of an .mcool balanced (ICE, cooler's defaults) and stored as `weight`, a .hic given
/// an ICE vector. Returns the resolutions written and the warnings.
#[pyfunction]
#[pyo3(signature = (input, output, resolutions, balance=false, assembly=None))]
pub(crate) fn zoomify(
    py: Python<'_>,
    input: &str,
    output: &str,
    resolutions: Vec<String>,
    balance: bool,
    assembly: Option<String>,
) -> PyResult<(Vec<u64>, Vec<String>)> {
    run(py, || {
        refuse_input(Path::new(output), &[input])?;
        let out = Path::new(output);
        if kind_of(out)? == Kind::Cool {
            return Err(Error::Argument(format!(
                "{output}: zoomify writes an .mcool or a .hic"
            )));
        }
        let reader = io::open_matrix(input, &OpenOptions::default())?;
        let levels = mcool_resolutions(reader.bins(), reader.source(), &resolutions)?;
        let mut normalizations = DEFAULT_HIC_NORMALIZATIONS.to_vec();
        if balance {
            normalizations.push(Method::Ice);
        }
        let options = MatrixOutput {
            assembly: assembly.or_else(|| reader.info().assembly()),
            normalizations,
            ..MatrixOutput::default()
        };
        let levels_text = Some(levels.iter().map(|r| r.to_string()).collect());
        let mut warnings = write_map(reader.as_ref(), out, levels_text, options)?;
        warnings.extend(reader.warnings());
        drop(reader);
        if balance && kind_of(out)? == Kind::Mcool {
            for &resolution in &levels {
                let uri = format!("{output}::/resolutions/{resolution}");
                if let Some(result) = balance_and_store(&uri, default_memory_budget())? {
                    if !result.converged {
                        warnings.push(format!(
                            "{uri}: ICE did not converge (var={:e}); stored with converged=false",
                            result.var
                        ));
                    }
                }
            }
        }
        Ok((levels, warnings))
    })
}

/// `contactmap merge`: the sum of the maps `inputs` (same bins) written to `output`.
#[pyfunction]
#[pyo3(signature = (inputs, output, resolutions=None, assembly=None))]
pub(crate) fn merge(
    py: Python<'_>,
    inputs: Vec<String>,
    output: &str,
    resolutions: Option<Vec<String>>,
    assembly: Option<String>,
) -> PyResult<Vec<String>> {
    run(py, || {
        let uris: Vec<&str> = inputs.iter().map(String::as_str).collect();
        refuse_input(Path::new(output), &uris)?;
        if inputs.is_empty() {
            return Err(Error::Argument("merge: no input map".into()));
        }
        let opened: Vec<Box<dyn MatrixReader>> = inputs
            .iter()
            .map(|uri| io::open_matrix(uri, &OpenOptions::default()))
            .collect::<Result<_, Error>>()?;
        let options = MatrixOutput {
            assembly: assembly.or_else(|| opened[0].info().assembly()),
            weight_columns: Some(Vec::new()),
            ..MatrixOutput::default()
        };
        let reader = MergedReader::new(opened.iter().map(|r| r.as_ref()).collect())?;
        let mut warnings = write_map(&reader, Path::new(output), resolutions, options)?;
        for reader in &opened {
            warnings.extend(reader.warnings());
        }
        Ok(warnings)
    })
}

/// One bin column of `n` values as u64 (`what` names it in errors).
fn unsigned(what: &str, values: &PyReadonlyArray1<'_, i64>) -> PyResult<Vec<u64>> {
    let slice = values
        .as_slice()
        .map_err(|e| ContactmapError::new_err(format!("{what}: {e}")))?;
    slice
        .iter()
        .enumerate()
        .map(|(k, &v)| {
            u64::try_from(v).map_err(|_| {
                ContactmapError::new_err(format!("{what}[{k}] = {v}: not a non-negative number"))
            })
        })
        .collect()
}

/// cooler's `create_cooler`: a .cool at `path` from the bins (chromosome index into `chroms`,
/// start, end; weight columns) and the pixels (bin ids, counts; summed where repeated, lower
/// triangle pixels mirrored, zeros kept as cooler keeps them).
#[allow(clippy::too_many_arguments)]
#[pyfunction]
#[pyo3(signature = (path, chroms, bin_chrom, bin_start, bin_end, weights, bin1, bin2, count, integer, assembly=None))]
pub(crate) fn create_cooler(
    py: Python<'_>,
    path: &str,
    chroms: Vec<(String, u64)>,
    bin_chrom: PyReadonlyArray1<'_, i64>,
    bin_start: PyReadonlyArray1<'_, i64>,
    bin_end: PyReadonlyArray1<'_, i64>,
    weights: Vec<(String, Vec<f64>)>,
    bin1: PyReadonlyArray1<'_, i64>,
    bin2: PyReadonlyArray1<'_, i64>,
    count: PyReadonlyArray1<'_, f64>,
    integer: bool,
    assembly: Option<String>,
) -> PyResult<()> {
    let (chrom_ids, starts, ends) = (
        unsigned("bins chrom", &bin_chrom)?,
        unsigned("bins start", &bin_start)?,
        unsigned("bins end", &bin_end)?,
    );
    let (ids1, ids2) = (unsigned("bin1_id", &bin1)?, unsigned("bin2_id", &bin2)?);
    if ids1.len() != ids2.len() || ids1.len() != count.len() {
        return Err(ContactmapError::new_err(format!(
            "pixels: {} bin1_id, {} bin2_id and {} count values",
            ids1.len(),
            ids2.len(),
            count.len()
        )));
    }
    let counts = count
        .as_slice()
        .map_err(|e| ContactmapError::new_err(format!("count: {e}")))?;
    run(py, || {
        let chroms: Vec<Chrom> = chroms.into_iter().map(|(n, l)| Chrom::new(n, l)).collect();
        let mut bins = Vec::with_capacity(starts.len());
        for (k, ((&chrom, &start), &end)) in chrom_ids.iter().zip(&starts).zip(&ends).enumerate() {
            if chrom as usize >= chroms.len() {
                return Err(Error::Data(format!(
                    "bins row {k}: chromosome index {chrom} of {} chromosomes",
                    chroms.len()
                )));
            }
            bins.push(Bin {
                chrom_id: chrom as usize,
                start,
                end,
            });
        }
        let table = BinTable::from_bins(chroms, &bins, None)?;
        let n = table.n_bins() as u64;
        let mut builder = MatrixBuilder::new(
            table,
            if integer {
                CountType::Integer
            } else {
                CountType::Float
            },
        );
        for (name, values) in weights {
            builder.add_weights(Weights {
                name,
                values,
                provenance: None,
            })?;
        }
        for (k, ((&a, &b), &c)) in ids1.iter().zip(&ids2).zip(counts).enumerate() {
            if a >= n || b >= n {
                return Err(Error::Data(format!(
                    "pixels row {k}: bin ids ({a}, {b}) for {n} bins"
                )));
            }
            builder.push(a, b, c)?;
        }
        let matrix = builder.build_with(ZeroCounts::Keep);
        let reader = InMemory::new(path.to_string(), matrix);
        write_cool(
            &reader,
            Path::new(path),
            &CoolWriteOptions {
                assembly,
                weight_columns: None,
            },
        )
    })
}
