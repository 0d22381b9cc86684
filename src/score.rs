//! Scores that compare calls with a truth.
//!
//! - [`boundaries`]: TAD boundaries and domains against a reference (for example the truth of a
//!   simulated map, [`crate::sim::blocks`]): one-to-one boundary matching within a tolerance
//!   (precision, recall, F1), best-match Jaccard of domains and the Measure of Concordance (MoC).
//! - [`contacts`]: predicted residue contacts against the contacts of a known protein structure
//!   (precision of the top L/k pairs per separation range, recall, F1, MCC), with the
//!   conventions of CASP, ConKit, ConEVA and DISTEVAL as options; [`register`] places a
//!   structure's residues on the prediction's sequence, and [`overlap`] compares two
//!   predictions' top lists with each other.
//! - [`compartments`]: compartment eigenvectors against known A/B types (simulated block
//!   copolymers): sign accuracy and correlation.
//!
//! Map-vs-map scores will live beside them in later modules.
//!
//! Scores take plain tables (chromosome names and bp positions) or parsed structures and
//! predictions, never files.

pub mod boundaries;
pub mod compartments;
pub mod contacts;
mod fraction;
pub mod frequency;
pub mod lists;
pub mod loops;
pub mod overlap;
pub mod register;
pub mod target;

pub use boundaries::{BoundaryMatch, DomainOverlap, domain_overlap, score_boundaries};
