//! Contact maps of sets of 3D conformations (a polymer simulation's trajectory), as polychrom
//! counts them (`polychrom.contactmaps.binnedContactMap` and `monomerResolutionContactMap`):
//!
//! - two beads `i < j` of a conformation are in contact when their distance is at most the
//!   contact radius (`scipy.spatial.KDTree.query_pairs(r)`, which polychrom's
//!   `calculate_contacts` calls; here through cell lists, [`crate::geometry::cells`]);
//! - beads are binned per chain: chain `[start, end)` is cut into `ceil((end - start) / m)`
//!   bins of `m` beads from its start, and a bead belongs to the last bin that starts at or
//!   before it (beads between two chains fall into the earlier chain's last bin, as in
//!   polychrom; the last edge is the last chain's end plus one);
//! - each contact adds one to its pair of bins, `bin(i) <= bin(j)`, summed over conformations.
//!
//! polychrom returns the dense symmetric matrix `triangle + triangle.T`, whose diagonal is
//! therefore twice the count of contacts within a bin; here the upper triangle is the map (a
//! `.cool` stores each contact once: the diagonal pixel is the number of contacts within the bin).
//!
//! Conformations stream ([`crate::io::trajectory::for_each_chunk`]): a chunk's contacts are
//! found in parallel and counted while the next chunk is read, so memory holds two chunks and
//! the map's pixels.
//!
//! Polymer statistics of the same conformations ([`stats`]): P(s) as polychrom's
//! `contact_scaling`, `<R^2(s)>` and `<Rg^2(s)>` of subchains as its `R2_scaling` and
//! `Rg2_scaling`, and each conformation's `Rg^2`.

mod beads;
mod map;
pub mod stats;

pub use map::{
    ChainBins, EnsembleMap, MapParams, chains_of_lengths, contact_map, contact_pairs,
    for_each_contact,
};
