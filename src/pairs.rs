//! Read pairs from the aligner to a map, as pairtools 1.1.2 defines them: each read's
//! alignments classified into a pair and its type ([`parse`]: pair types, walks policies,
//! rescued single ligations, flipping to the upper triangle), duplicates marked ([`dedup`]),
//! summary statistics ([`stats`]) and selections ([`select`]).
//!
//! Coordinates are pairtools': 1-based, the 5' end of each side's alignment; an unmapped side
//! is chromosome `!`, position 0, strand `-`. The records' reading and writing, the sort order
//! and the external sort are in [`crate::io::pairs`]; nothing here opens a file.

pub mod alignment;
pub mod dedup;
pub mod pandas;
pub mod parse;
pub mod select;
pub mod stats;
pub mod stream;
#[cfg(test)]
mod tests;
pub mod walks;
