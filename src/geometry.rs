//! Geometry several rooms share: cell lists, the pairs of points closer than a cutoff in O(N),
//! in open space or a periodic cube ([`cells`]). The polymer simulator's forces and contacts
//! (`sim`), polymer contact maps and statistics (`conformations`) all search pairs with it; it
//! stands on the ground floor so that none of them imports another room only to borrow it.

pub mod cells;

pub use cells::{CellList, Space};
