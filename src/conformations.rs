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

mod map;
pub mod stats;

pub use map::*;

use crate::error::{Error, Result};
use crate::io::trajectory::Conformation;

/// A contact radius: positive and finite (an error naming `--contact-radius` otherwise).
fn check_radius(radius: f64) -> Result<()> {
    if radius.is_finite() && radius > 0.0 {
        Ok(())
    } else {
        Err(Error::parameter(
            "contact-radius",
            radius,
            "a positive distance",
        ))
    }
}

/// The beads of the first conformation (looked at, not taken), or the stream's first error, or
/// an error for an empty stream.
fn first_beads<I: Iterator<Item = Result<Conformation>>>(
    conformations: &mut std::iter::Peekable<I>,
) -> Result<usize> {
    match conformations.peek() {
        Some(Ok(first)) => Ok(first.positions.len()),
        Some(Err(_)) => Err(conformations
            .next()
            .and_then(Result::err)
            .expect("an error")),
        None => Err(Error::Invalid("no conformation in the trajectory".into())),
    }
}

/// Every conformation has the first one's `n_beads` beads: `keep` of
/// [`crate::io::trajectory::for_each_chunk`].
fn same_beads(c: &Conformation, n_beads: usize) -> Result<bool> {
    if c.positions.len() != n_beads {
        return Err(Error::Invalid(format!(
            "{}: {} beads, where the first conformation has {n_beads}",
            c.label,
            c.positions.len()
        )));
    }
    Ok(true)
}
