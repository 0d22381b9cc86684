//! Read pairs: the `.pairs` format (4DN pairs v1.0, as pairtools writes it) and the aligner's
//! SAM / BAM that `contactmap pairs parse` reads.
//!
//! [`header`] keeps a pairs header's lines, [`records`] reads records with their line numbers
//! and finds the columns by name, [`order`] is pairtools' sort order, [`sort`] sorts and merges
//! in bounded memory (runs on disk), [`alignments`] reads SAM / BAM (noodles) grouped by read
//! name, and [`open`] opens pairs files (outputs are [`crate::io::output::Output::open_blocked`]:
//! BGZF for `.gz`, so that tabix and pairix can index them). The pairs algorithms (classification, dedup, stats, select) are in
//! [`crate::pairs`]; nothing here computes them.

pub mod alignments;
pub mod header;
pub mod open;
pub mod order;
pub mod records;
pub mod sort;

pub use alignments::{AlignmentReader, AlignmentRecord, ReadGroup, RecordNeeds};
pub use header::{PairsHeader, STANDARD_COLUMNS, UNMAPPED_CHROM};
pub use open::open_pairs;
pub use order::{SortKey, in_sorted_order};
pub use records::{PairColumns, PairRecord, PairsReader, parse_position};
pub use sort::{SortOptions, merge_sorted, sort_pairs};
