//! Balancing weights stored into coolers, shared by `balance --store` and `zoomify --balance`:
//! the attributes cooler writes beside a weight column.

use contactmap::balance::{BalanceParams, BalanceResult, Scope};
use contactmap::io::cool::store::AttrValue;

/// An integral value as an integer attribute (cooler stores its integer options as int64).
fn number_attr(value: f64) -> AttrValue {
    if value.fract() == 0.0 && value.abs() < 9e15 {
        AttrValue::Int(value as i64)
    } else {
        AttrValue::Float(value)
    }
}

/// cooler's attributes of a stored weight column.
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
