//! The checks both the map and the statistics make of a stream of conformations: the contact
//! radius, the first conformation's number of beads, the same number in every later one.

use crate::error::{Error, Result};
use crate::io::trajectory::Conformation;

/// A contact radius: positive and finite (an error naming `--contact-radius` otherwise).
pub(super) fn check_radius(radius: f64) -> Result<()> {
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
pub(super) fn first_beads<I: Iterator<Item = Result<Conformation>>>(
    conformations: &mut std::iter::Peekable<I>,
) -> Result<usize> {
    match conformations.peek() {
        Some(Ok(first)) => Ok(first.positions.len()),
        Some(Err(_)) => Err(conformations
            .next()
            .and_then(Result::err)
            .expect("an error")),
        None => Err(Error::Data("no conformation in the trajectory".into())),
    }
}

/// Every conformation has the first one's `n_beads` beads: `keep` of
/// [`crate::io::trajectory::for_each_chunk`].
pub(super) fn same_beads(c: &Conformation, n_beads: usize) -> Result<bool> {
    if c.positions.len() != n_beads {
        return Err(Error::Data(format!(
            "{}: {} beads, where the first conformation has {n_beads}",
            c.label,
            c.positions.len()
        )));
    }
    Ok(true)
}
