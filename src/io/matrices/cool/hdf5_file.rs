//! The HDF5 files of coolers: opened without file locking, created exclusively, and their size
//! on disk.

use std::path::Path;

use crate::error::{Error, Result};

/// HDF5 file options: no file locking. We only read whole files or write fresh temporary ones,
/// locking fails on many network file systems, and a lock would be held by any child process
/// that inherits libhdf5's descriptor (libhdf5 does not open files close-on-exec).
pub(crate) fn file_builder() -> hdf5::FileBuilder {
    let mut builder = hdf5::File::with_options();
    builder.fapl().file_locking(false);
    builder
}
/// Create a new HDF5 file at `path` exclusively (libhdf5's `H5F_ACC_EXCL`, which opens with
/// `O_EXCL`: it fails on any existing name, a planted link included), for the temporaries of
/// [`crate::io::plumbing::atomic`].
pub(crate) fn create_excl(path: &Path) -> Result<hdf5::File> {
    file_builder()
        .create_excl(path)
        .map_err(|e| Error::hdf5(path, "creating the file", e))
}
/// The size of the file at `path` (0 when it cannot be read: the reads that follow say why).
pub(crate) fn file_len(path: &str) -> u64 {
    std::fs::metadata(path).map_or(0, |m| m.len())
}
