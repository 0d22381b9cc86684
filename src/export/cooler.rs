//! Computed results stored into an existing cooler: balancing weights with the attributes cooler
//! writes beside them (`cooler balance`; `zoomify --balance`), and per-bin coverage
//! (`cooltools coverage --store`). The formats floor writes the columns
//! ([`crate::io::cool::store`]); this room knows what they hold.

use crate::balance::store::{balance_reader, stored_attributes};
use crate::balance::{BalanceParams, BalanceResult};
use crate::compare::coverage::Coverage;
use crate::error::Result;
use crate::io::MatrixReader;
use crate::io::cool::CoolReader;
use crate::io::cool::store::{AttrValue, BinColumn, store_bin_columns, store_weights};
use crate::matrix::Weights;

/// Store the weights of `result` as the column `name` of the cooler at `uri` (a .cool, or an
/// .mcool resolution), with the attributes cooler writes beside it ([`stored_attributes`]);
/// `overwrite` replaces an existing column.
pub fn store_balanced(
    uri: &str,
    name: &str,
    params: &BalanceParams,
    result: &BalanceResult,
    overwrite: bool,
) -> Result<()> {
    let weights = Weights {
        name: name.to_string(),
        values: result.weights.clone(),
        provenance: None,
    };
    store_weights(uri, &weights, &stored_attributes(params, result), overwrite)
}

/// ICE with cooler's defaults on the cooler at `uri`, stored as `weight`, unless the file
/// already has a `weight` column (a copied one is kept, as `cooler zoomify --balance` does).
/// Returns the result when it balanced (`converged` says whether it converged; the weights
/// are stored either way, with `converged=false`).
pub fn balance_and_store(uri: &str, max_memory_bytes: u64) -> Result<Option<BalanceResult>> {
    let params = BalanceParams::default();
    let result = {
        let reader = CoolReader::open(uri)?;
        if reader.weight_names().iter().any(|n| n == "weight") {
            return Ok(None);
        }
        balance_reader(&reader, &params, max_memory_bytes)?.result
    };
    store_balanced(uri, "weight", &params, &result, true)?;
    Ok(Some(result))
}

/// Store the coverage in the cooler at `uri` as cooltools `coverage --store` does: columns
/// `bins/cov_cis_raw` and `bins/cov_tot_raw` (64-bit integers) with the cooler attribute `cis`
/// (the number of cis contacts, half the cis coverage's sum), or for a coverage balanced by
/// `weight_name` W the float columns `bins/cov_cis_W` and `bins/cov_tot_W`. Existing columns of
/// those names are replaced (as cooltools does).
///
/// ```
/// use contactmap::compare::coverage::coverage;
/// use contactmap::export::cooler::store_coverage;
/// use contactmap::io::{open_matrix, OpenOptions};
///
/// let dir = std::env::temp_dir().join(format!("contactmap-coverage-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("mm9.cool");
/// std::fs::copy("data/CN.mm9.10000kb.cool", &path)?;
/// let uri = path.to_str().unwrap();
/// let cov = coverage(open_matrix(uri, &OpenOptions::default())?.as_ref(), 2)?;
/// store_coverage(uri, &cov, None)?;
/// let file = hdf5::File::open(&path)?;
/// let total: Vec<i64> = file.dataset("bins/cov_tot_raw")?.read_raw()?;
/// assert!(total.iter().zip(&cov.total).all(|(&a, &b)| a as f64 == b));
/// let cis: i64 = file.attr("cis")?.read_scalar()?;
/// assert_eq!(cis as f64, (cov.cis.iter().sum::<f64>() / 2.0).floor());
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn store_coverage(uri: &str, cov: &Coverage, weight_name: Option<&str>) -> Result<()> {
    match weight_name {
        None => {
            let int = |v: &[f64]| -> Vec<i64> { v.iter().map(|&x| x as i64).collect() };
            let (cis, total) = (int(&cov.cis), int(&cov.total));
            let n_cis = (cov.cis.iter().sum::<f64>() / 2.0).floor() as i64;
            store_bin_columns(
                uri,
                &[
                    ("cov_cis_raw", BinColumn::Int(&cis)),
                    ("cov_tot_raw", BinColumn::Int(&total)),
                ],
                &[("cis".to_string(), AttrValue::Int(n_cis))],
            )
        }
        Some(name) => store_bin_columns(
            uri,
            &[
                (&format!("cov_cis_{name}"), BinColumn::Float(&cov.cis)),
                (&format!("cov_tot_{name}"), BinColumn::Float(&cov.total)),
            ],
            &[],
        ),
    }
}
