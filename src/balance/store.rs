//! Balancing the map of a reader, with what explains a failure to converge, and the attributes
//! cooler stores beside a weight column: the steps `balance` and `zoomify --balance` share (the
//! store itself is [`crate::export::cooler`]'s).

use super::params::{BalanceParams, Scope};
use super::result::BalanceResult;
use super::run::balance;
use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::io::cool::store::AttrValue;
use crate::io::{self, MatrixReader};
use crate::matrix::Weights;

/// A balancing of a map, with what explains a failure to converge.
#[derive(Clone, Debug)]
pub struct Balanced {
    /// The weights and the convergence report.
    pub result: BalanceResult,
    /// True when a genome-wide balancing failed on a map with more than one chromosome and no
    /// trans pixel: the chromosomes' scales are independent, so it cannot converge (balance
    /// each chromosome instead, [`Scope::Cis`]). Looked for only when it failed.
    pub disconnected: bool,
}

/// Balance the map of `reader` with `params`, its pixels held in memory when they fit
/// `max_memory_bytes` (else streamed from the file at every iteration).
///
/// # Examples
///
/// ```
/// use contactmap::balance::store::balance_reader;
/// use contactmap::balance::BalanceParams;
/// use contactmap::io::open_matrix;
///
/// let reader = open_matrix("data/CN.mm9.10000kb.cool", &Default::default())?;
/// let balanced = balance_reader(reader.as_ref(), &BalanceParams::default(), 1 << 30)?;
/// assert!(balanced.result.converged && !balanced.disconnected);
/// assert_eq!(balanced.result.weights.len(), reader.bins().n_bins());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn balance_reader(
    reader: &dyn MatrixReader,
    params: &BalanceParams,
    max_memory_bytes: u64,
) -> Result<Balanced> {
    let pixels = io::load_pixels_for_balancing(reader, max_memory_bytes)?;
    let result = balance(&pixels, params)?;
    let disconnected = !result.converged
        && params.scope == Scope::GenomeWide
        && reader.bins().chroms().len() > 1
        && !has_trans_pixels(reader)?;
    Ok(Balanced {
        result,
        disconnected,
    })
}

/// Whether any stored pixel joins two chromosomes (the read stops at the first).
fn has_trans_pixels(reader: &dyn MatrixReader) -> Result<bool> {
    let bins = reader.bins();
    let n = bins.n_bins();
    let mut found = false;
    for chrom in 0..bins.chroms().len() {
        let rows = bins.chrom_bins(chrom);
        let later = rows.end..n;
        if later.is_empty() {
            break;
        }
        let read = reader.read_pixels(rows, later, &mut |block| {
            found = !block.is_empty();
            if found {
                // Stop the stream: one pixel is enough.
                Err(Error::Invalid(String::new()))
            } else {
                Ok(())
            }
        });
        match read {
            _ if found => return Ok(true),
            Err(error) => return Err(error),
            Ok(()) => {}
        }
    }
    Ok(false)
}

impl BalanceResult {
    /// Which groups did not converge and by how much, for an error message: `var=.., tol=..`,
    /// or the chromosomes that did not (per-chromosome balancing).
    pub fn unconverged_detail(&self, bins: &BinTable, tol: f64) -> String {
        match &self.per_chrom {
            Some(per_chrom) => {
                let names: Vec<String> = per_chrom
                    .iter()
                    .zip(bins.chroms())
                    .filter(|(g, _)| !g.converged)
                    .map(|(g, c)| format!("{} var={:e}", c.name, g.var))
                    .collect();
                format!("tol={tol:e}; not converged: {}", names.join(", "))
            }
            None => format!("var={:e}, tol={tol:e}", self.var),
        }
    }
}

/// An integral value as an integer attribute (cooler stores its integer options as int64).
fn number_attr(value: f64) -> AttrValue {
    if value.fract() == 0.0 && value.abs() < 9e15 {
        AttrValue::Int(value as i64)
    } else {
        AttrValue::Float(value)
    }
}

/// cooler's attributes of a stored weight column: the options (`tol`, `min_nnz`, `min_count`,
/// `mad_max`, `cis_only`, `ignore_diags`, `trans_only` when set), the result (`scale`,
/// `converged`, `var`: one per chromosome for per-chromosome balancing) and the `method`.
pub fn stored_attributes(
    params: &BalanceParams,
    result: &BalanceResult,
) -> Vec<(String, AttrValue)> {
    let mut attrs = vec![
        ("tol".to_string(), AttrValue::Float(params.tol)),
        ("min_nnz".to_string(), AttrValue::Int(params.min_nnz as i64)),
        ("min_count".to_string(), number_attr(params.min_count)),
        ("mad_max".to_string(), number_attr(params.mad_max)),
        (
            "cis_only".to_string(),
            AttrValue::Bool(params.scope == Scope::Cis),
        ),
        (
            "ignore_diags".to_string(),
            AttrValue::Int(params.ignore_diags as i64),
        ),
    ];
    match &result.per_chrom {
        Some(per_chrom) => {
            attrs.push((
                "scale".to_string(),
                AttrValue::Floats(per_chrom.iter().map(|g| g.scale).collect()),
            ));
            attrs.push((
                "converged".to_string(),
                AttrValue::Bools(per_chrom.iter().map(|g| g.converged).collect()),
            ));
            attrs.push((
                "var".to_string(),
                AttrValue::Floats(per_chrom.iter().map(|g| g.var).collect()),
            ));
        }
        None => {
            attrs.push(("scale".to_string(), AttrValue::Float(result.scale)));
            attrs.push(("converged".to_string(), AttrValue::Bool(result.converged)));
            attrs.push(("var".to_string(), AttrValue::Float(result.var)));
        }
    }
    if params.scope == Scope::Trans {
        attrs.push(("trans_only".to_string(), AttrValue::Bool(true)));
    }
    attrs.push((
        "method".to_string(),
        AttrValue::Str(params.method.name().to_string()),
    ));
    attrs
}

/// The weights as a table `chrom start end NAME` with a header line (`nan` for masked bins,
/// shortest round-trip digits otherwise), given to `write` in pieces of about 1 MiB.
pub fn weights_table(
    bins: &BinTable,
    weights: &Weights,
    mut write: impl FnMut(&[u8]) -> Result<()>,
) -> Result<()> {
    let mut text = Vec::with_capacity(1 << 20);
    text.extend_from_slice(format!("chrom\tstart\tend\t{}\n", weights.name).as_bytes());
    for (bin_id, &w) in weights.values.iter().enumerate() {
        let bin = bins.bin(bin_id);
        let name = &bins.chroms()[bin.chrom_id].name;
        let value = if w.is_nan() {
            "nan".to_string()
        } else {
            format!("{w:?}")
        };
        text.extend_from_slice(format!("{name}\t{}\t{}\t{value}\n", bin.start, bin.end).as_bytes());
        if text.len() > (1 << 20) {
            write(&text)?;
            text.clear();
        }
    }
    write(&text)
}

impl BalanceResult {
    /// The report of a balancing of the map at `uri` with `params` as JSON (what `balance
    /// --json` prints): method, scope, convergence, iterations, masked bins, scale and variance,
    /// per chromosome for per-chromosome balancing (non-finite numbers as null).
    pub fn report_json(
        &self,
        uri: &str,
        params: &BalanceParams,
        bins: &BinTable,
    ) -> serde_json::Value {
        let result = self;
        // serde_json writes non-finite numbers as null
        let mut value = serde_json::json!({
            "uri": uri,
            "method": params.method.name(),
            "scope": params.scope.name(),
            "converged": result.converged,
            "n_iterations": result.n_iterations,
            "masked_bins": result.n_masked(),
            "n_bins": result.weights.len(),
            "scale": result.scale,
            "var": result.var,
        });
        if let Some(per_chrom) = &result.per_chrom {
            value["per_chromosome"] = per_chrom
                .iter()
                .zip(bins.chroms())
                .map(|(g, chrom)| {
                    serde_json::json!({
                        "chrom": chrom.name,
                        "converged": g.converged,
                        "n_iterations": g.n_iterations,
                        "scale": g.scale,
                        "var": g.var,
                    })
                })
                .collect();
        }
        value
    }

    /// The same report as `#` lines (what `balance` prints on standard error).
    pub fn report_text(&self, params: &BalanceParams, bins: &BinTable) -> String {
        let result = self;
        let scope = params.scope.name();
        let mut text = format!(
            "# method={} scope={scope} converged={} n_iterations={} masked_bins={}/{}",
            params.method.name(),
            result.converged,
            result.n_iterations,
            result.n_masked(),
            result.weights.len()
        );
        match &result.per_chrom {
            None => text.push_str(&format!(" scale={:?} var={:e}\n", result.scale, result.var)),
            Some(per_chrom) => {
                text.push('\n');
                for (g, chrom) in per_chrom.iter().zip(bins.chroms()) {
                    text.push_str(&format!(
                        "# {} converged={} n_iterations={} scale={:?} var={:e}\n",
                        chrom.name, g.converged, g.n_iterations, g.scale, g.var
                    ));
                }
            }
        }
        text
    }
}
