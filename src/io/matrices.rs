//! The contact-matrix formats: cooler (`.cool`, `.mcool`), Juicer `.hic`, HiCExplorer `.h5`,
//! text tables; the reader trait they implement ([`MatrixReader`]), opening any of them by URI
//! ([`open_matrix`]), and what reads pixels from a reader (loading, queries, adapters).

pub mod cool;
pub mod hic;
pub mod hicexplorer;
pub mod info;
pub mod merged;
pub mod text;

pub(crate) mod adapters;
pub(crate) mod kind;
pub(crate) mod open;
pub(crate) mod pixels;
pub(crate) mod query;
pub(crate) mod reader;
pub(crate) mod uri;

pub use adapters::{CheckedCounts, Inspect};
pub use kind::{FileKind, detect_kind};
pub use open::{Levels, list_resolutions, open_levels, open_matrix, uri_at_resolution};
pub use pixels::{
    LoadedPixels, StreamedPixels, default_memory_budget, load_matrix, load_pixels,
    load_pixels_for_balancing, parse_memory_size,
};
pub use query::{QueryPixels, query_dense, query_dense_into, query_pixels};
pub use reader::{InMemory, MatrixInfo, MatrixReader, read_ahead, read_ahead_by};
pub use text::options::OpenOptions;
pub use uri::{parse_resolution_group, split_uri};
