//! Differential analysis between conditions with replicates: counts per feature (a loop, a
//! boundary, a bin) and per sample, modelled as DESeq2 models genes (Love, Huber & Anders 2014,
//! *Genome Biology* 15:550), the statistics equal to pydeseq2 0.5.4's on the same count matrix
//! (docs/diff.md says how closely, and where pydeseq2's optimiser stops short).
//!
//! The steps ([`fit`]): size factors by the median of ratios; a rough moments dispersion per
//! feature; its Cox-Reid maximum-likelihood dispersion; a trend `a₀ + a₁/mean` over the
//! features (a gamma GLM, refitted without outliers); the spread about the trend as a prior on
//! `log α`; each feature's posterior mode (or its own dispersion where that is more than two
//! spreads above the trend); the negative-binomial GLM of each feature by IRLS; Cook's
//! distances. Then [`results`]: the Wald test of a contrast, p-values of features with a
//! Cook's outlier set aside (where a condition has three or more replicates), and
//! Benjamini-Hochberg q-values.
//!
//! Defaults are pydeseq2's: `min_mu = 0.5`, `min_disp = 1e-8`, `max_disp = max(10, n_samples)`,
//! `beta_tol = 1e-8`. Unlike pydeseq2, q-values use no independent filtering (the features
//! here are chosen before the test, not every gene of a genome), and counts that are Cook's
//! outliers are not replaced (DESeq2 replaces them only with seven or more replicates). Features
//! with every count zero get no fit (`NaN`).
//!
//! Each feature is fitted on its own, in parallel; results do not depend on the thread count.
//!
//! The comparisons built on it: [`loops`] (each loop's counts against the expected at its
//! distance, [`offsets`]; the loops called by [`calls`] when none are given), [`boundaries`]
//! (the contacts across each boundary against its flanks), [`compartments`] (E1 per bin, tested
//! with limma's moderated t, [`moderated`], equal to limma's), [`regions`] (CHESS's structural
//! similarity, equal to chess-hic 0.3.8). [`maps`] checks what they read.

pub mod boundaries;
pub mod calls;
pub mod compartments;
mod dispersion;
mod glm;
mod linalg;
pub mod loops;
pub mod maps;
mod model;
pub mod moderated;
mod nb;
pub mod offsets;
pub mod regions;
mod size_factors;
mod special;
mod tables;
mod test;

pub use dispersion::Trend;
pub use model::{Design, Fit, Normalization, Params, Results, fit, fit_normalized, results};
pub use special::{tetragamma, trigamma, trigamma_inverse};
pub use test::benjamini_hochberg;

#[cfg(test)]
mod tests;
