//! Per-bin weight columns (cooler's multiplicative convention).

use crate::error::{Error, Result};

/// A named per-bin weight column, in cooler's multiplicative convention:
/// `balanced[i, j] = count[i, j] * weight[i] * weight[j]`; `NaN` marks a masked bin.
#[derive(Clone, Debug, PartialEq)]
pub struct Weights {
    /// Column name (`weight`, `KR`, `VC`, `SCALE` ...).
    pub name: String,
    /// One value per bin.
    pub values: Vec<f64>,
    /// How the values were obtained, when they were not stored multiplicatively (e.g. ".hic KR
    /// vector, divisive: inverted on read").
    pub provenance: Option<String>,
}

impl Weights {
    /// Build multiplicative weights from a divisive vector (Juicer / hic2cool convention:
    /// `balanced = count / (v[i] * v[j])`). Zero, negative and non-finite entries become `NaN`.
    pub fn from_divisive(name: impl Into<String>, divisive: &[f64], provenance: String) -> Self {
        Weights {
            name: name.into(),
            values: divisive.iter().map(|&v| invert_weight(v)).collect(),
            provenance: Some(provenance),
        }
    }
}

/// Convert one weight between the divisive and multiplicative conventions: `1 / w`, with zero,
/// negative and non-finite weights (masked bins) becoming `NaN`.
pub fn invert_weight(weight: f64) -> f64 {
    if weight.is_finite() && weight > 0.0 {
        1.0 / weight
    } else {
        f64::NAN
    }
}

/// Add `weights` to `columns`, replacing a column of the same name; its length must be `n_bins`.
pub(crate) fn insert_weights(
    columns: &mut Vec<Weights>,
    n_bins: usize,
    weights: Weights,
) -> Result<()> {
    if weights.values.len() != n_bins {
        return Err(Error::Data(format!(
            "weight column '{}' has {} values for {n_bins} bins",
            weights.name,
            weights.values.len()
        )));
    }
    columns.retain(|w| w.name != weights.name);
    columns.push(weights);
    Ok(())
}
