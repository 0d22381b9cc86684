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
//! The modules stand in folders by domain, re-exported here by name (`io::cool`, `io::structure`
//! ...): [`matrices`] (the contact-matrix formats, the reader trait, opening by URI, pixel
//! queries), [`protein`] (structures, predictions, sequences, contact frequencies),
//! [`trajectory`] (polymer and MD trajectories, topologies), [`bed`] (genomic intervals:
//! BED, BEDPE, views) and [`plumbing`] (atomic outputs and locks, compressed input, tables,
//! the libhdf5 guard) that the others share.
//!
//! Format modules only read and write: they never compute biology.

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

pub mod bed;
pub mod matrices;
pub mod pairs;
pub mod plumbing;
pub mod protein;
#[cfg(test)]
mod tests;
pub mod trajectory;

pub use matrices::{
    CheckedCounts, FileKind, InMemory, Inspect, Levels, LoadedPixels, MatrixInfo, MatrixReader,
    OpenOptions, QueryPixels, StreamedPixels, cool, default_memory_budget, detect_kind, hic,
    hicexplorer, info, list_resolutions, load_matrix, load_pixels, load_pixels_for_balancing,
    merged, open_levels, open_matrix, parse_memory_size, parse_resolution_group, query_dense,
    query_dense_into, query_pixels, read_ahead, read_ahead_by, split_uri, text, uri_at_resolution,
};
pub use plumbing::{
    Temporary, WriteLock, atomic, hdf5_guard, is_special_file, open_text, output, same_file, tables,
};
pub use protein::{fasta, frequencies, npz, predictions, structure};
pub use trajectory::topology;
