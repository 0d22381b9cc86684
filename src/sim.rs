//! Simulated contact maps with a known ground truth, for testing and benchmarking callers.
//!
//! - [`blocks`]: block-structured Hi-C-like maps: a power-law distance decay, domains (TADs,
//!   optionally nested) with enriched contacts, per-bin coverage biases and dead bins, Poisson
//!   counts. The true domains and boundaries come with the map.
//!
//! - the polymer simulator: [`polymer`] (a bead-spring chain under Brownian dynamics; its pair
//!   forces and contacts through the ground floor's cell lists, [`crate::geometry::cells`]),
//!   [`extrusion`] (1D loop extrusion), [`ensemble`] (replicas in parallel, sampled into a binned
//!   contact map), [`noise`] (counter-based Gaussian noise, the same on any thread count and on
//!   the GPU) and [`analysis`] (P(s), radii of gyration and the closed forms they are checked
//!   against);
//! - [`spec`]: the simulator's parameters as a user gives them (the command line's options);
//! - [`mod@reference`]: a Monte Carlo sampler of the same chain's equilibrium, against which the
//!   dynamics are checked.
//!
//! Randomness: every random process takes an explicit seed and draws from the ground floor's
//! seeded streams ([`crate::random`]), so results never depend on the number of threads.

pub mod analysis;
pub mod blocks;
pub mod ensemble;
pub mod extrusion;
pub mod files;
pub mod gpu;
pub mod noise;
pub mod polymer;
pub mod reference;
pub mod relaxation;
pub mod spec;

pub use blocks::{BlockMap, BlockMapParams, block_map};
