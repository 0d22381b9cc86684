//! What every format shares: outputs written atomically and locks ([`atomic`]), BGZF inflated in
//! pieces on worker threads ([`bgzf_blocks`]), standard output
//! and whole-file writes ([`output`]), compressed or standard input ([`open_text`]), tables with a
//! header ([`tables`]), a fast hasher for per-record maps ([`hash`]), and the deadline on libhdf5's metadata reads ([`hdf5_guard`]).

pub mod atomic;
pub mod bgzf_blocks;
pub mod hash;
pub mod hdf5_guard;
pub mod output;
pub mod tables;

pub(crate) mod input;

pub use atomic::{Temporary, WriteLock, is_special_file, same_file};
pub use input::{is_bgzf, open_text, worker_count};
