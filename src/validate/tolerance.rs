//! How closely float counts must agree where the checks compare them.

/// Relative tolerance when comparing float counts (coarsening, `sum` attribute).
pub const FLOAT_TOLERANCE: f64 = 1e-6;
