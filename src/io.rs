//! Reading and writing contact-matrix files.
//!
//! Every reader implements [`MatrixReader`]: it exposes the bin table, the weight columns and a
//! streaming pixel query that hands sorted [`PixelBlock`](crate::matrix::PixelBlock)s to a
//! callback, so that callers never need a whole pixel table in memory. [`open_matrix`] picks the
//! reader from the URI:
//!
//! | input | how it is recognised | reader |
//! |---|---|---|
//! | `.cool`, `file.mcool::/resolutions/N`, `file.cool::/GROUP` | HDF5 magic bytes | [`cool`] |
//! | HiCExplorer / HiCMatrix `.h5` (CSR `matrix/` + `intervals/`) | HDF5 magic bytes, root groups `matrix` and `intervals`, no cooler group | [`hicexplorer`] |
//! | Juicer `.hic` v8 / v9 (`file.hic::/resolutions/N` or `file.hic` for its only resolution) | `HIC\0` magic | [`hic`] |
//! | BG2 / COO pixel tables, pairs, dense matrices (gzip or plain, `-` for stdin) | `--format` or extension | [`text`] |
//!
//! Protein inputs have their own readers: [`structure`] (PDB / mmCIF) and [`predictions`]
//! (CASP RR, CCMpred / PSICOV matrices, `i j score` tables, trRosetta `.npz`, `.npy` distance
//! maps).
//!
//! Format modules only read and write: they never compute biology.

pub mod atomic;
pub mod bed;
pub mod cool;
pub mod fasta;
pub mod frequencies;
pub mod hdf5_guard;
pub mod hic;
pub mod hicexplorer;
pub mod info;
pub mod merged;
pub mod npz;
pub mod output;
pub mod predictions;
pub mod structure;
pub mod tables;
pub mod text;
pub mod topology;
pub mod trajectory;

pub use atomic::{Temporary, WriteLock, is_special_file, same_file};

/// Inside `impl MatrixReader for W`, where `self.FIELD` is the wrapped reader: every method but
/// the pixel reads forwarded to it (totals, the stored pixels' sums, included). An adapter that
/// changes the pixels (progress, checks) writes only `read_pixels` and `read_stored_pixels`, and a
/// method added to the trait is forwarded by every adapter at once.
macro_rules! forward_reader_metadata {
    ($field:ident) => {
        fn source(&self) -> &str {
            self.$field.source()
        }

        fn bins(&self) -> &$crate::genome::BinTable {
            self.$field.bins()
        }

        fn count_type(&self) -> $crate::matrix::CountType {
            self.$field.count_type()
        }

        fn weight_names(&self) -> Vec<String> {
            self.$field.weight_names()
        }

        fn weights(&self, name: &str) -> $crate::error::Result<$crate::matrix::Weights> {
            self.$field.weights(name)
        }

        fn stored_weights(&self, name: &str) -> $crate::error::Result<$crate::matrix::Weights> {
            self.$field.stored_weights(name)
        }

        fn info(&self) -> $crate::io::MatrixInfo {
            self.$field.info()
        }

        fn weight_attribute(&self, name: &str, key: &str) -> Option<serde_json::Value> {
            self.$field.weight_attribute(name, key)
        }

        fn stores_both_triangles(&self) -> bool {
            self.$field.stores_both_triangles()
        }

        fn totals(&self) -> $crate::error::Result<(u64, f64)> {
            self.$field.totals()
        }

        fn warnings(&self) -> Vec<String> {
            self.$field.warnings()
        }

        fn recycle(&self, block: $crate::matrix::PixelBlock) {
            self.$field.recycle(block)
        }
    };
}

mod adapters;
mod input;
mod kind;
mod open;
mod pixels;
mod query;
mod reader;
#[cfg(test)]
mod tests;
mod uri;

pub use adapters::{CheckedCounts, Inspect};
pub use input::open_text;
pub use kind::{FileKind, detect_kind};
pub use open::{list_resolutions, open_matrix, uri_at_resolution};
pub use pixels::{
    LoadedPixels, StreamedPixels, default_memory_budget, load_matrix, load_pixels,
    load_pixels_for_balancing, parse_memory_size,
};
pub use query::{QueryPixels, query_dense, query_dense_into, query_pixels};
pub use reader::{InMemory, MatrixInfo, MatrixReader, read_ahead, read_ahead_by};
pub use text::options::OpenOptions;
pub use uri::{parse_resolution_group, split_uri};
