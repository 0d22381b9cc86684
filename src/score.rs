//! Scores that compare calls with a truth.
//!
//! - [`boundaries`]: TAD boundaries and domains against a reference (for example the truth of a
//!   simulated map, [`crate::sim::blocks`]): one-to-one boundary matching within a tolerance
//!   (precision, recall, F1), best-match Jaccard of domains and the Measure of Concordance (MoC).
//!
//! Protein contact scoring (precision of the top L/k predicted contacts and friends) and
//! map-vs-map scores will live beside it in later modules.
//!
//! Scores take plain tables (chromosome names and bp positions), never files.

pub mod boundaries;

pub use boundaries::{domain_overlap, score_boundaries, BoundaryMatch, DomainOverlap};
