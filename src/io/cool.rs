//! cooler `.cool` / `.mcool` files (HDF5): reader and writer.
//!
//! Layout (cooler schema, format versions 1 to 3): a cooler group holds `chroms/{name,length}`,
//! `bins/{chrom,start,end,<weight columns>}`, `pixels/{bin1_id,bin2_id,count}` sorted by
//! `(bin1_id, bin2_id)`, and `indexes/{chrom_offset,bin1_offset}`; its attributes describe it
//! (`format`, `format-version`, `bin-type`, `bin-size`, `storage-mode`, `nbins`, `nnz`, ...). A
//! multi-resolution `.mcool` holds one cooler per group `/resolutions/<bin size>`. URIs name the
//! group after `::`, as cooler does: `file.mcool::/resolutions/10000`, `file.cool::/some/group`.
//!
//! The reader accepts old files without a `format` attribute, `format-version` stored as a string,
//! 32- or 64-bit ids and offsets, integer or float counts, and `bins/chrom` stored as an HDF5 enum
//! or as plain integers. Pixel columns are decoded in parallel ([`chunks`]); a query streams blocks
//! of at most [`BLOCK_PIXELS`] pixels, so memory stays bounded on any file size.
//!
//! Weights are handed out multiplicative (cooler's convention). A column is divisive in the file
//! when its `divisive_weights` attribute says so; without the attribute, columns named `KR`, `VC`
//! and `VC_SQRT` are divisive (cooler's own rule, for 4DN / hic2cool files), and so is `SCALE` in a
//! file written by hic2cool (Juicer's SCALE is divisive; cooler would misread it as multiplicative).
//! Divisive columns are inverted on read, and `info` says so. The writer stores `KR`, `VC` and
//! `VC_SQRT` divisive (with `divisive_weights = true`) so that cooler, which divides by those columns
//! whatever the attribute says, balances them correctly; other columns are stored multiplicative.
//!
//! The writer produces format-version 3 files as cooler 0.11 writes them (same dataset names,
//! types, shuffle + deflate level 6 compression and root attributes); `bins/chrom` is stored as
//! `int32` with an `enum_path` attribute pointing to `/chroms/name`, a layout cooler reads
//! natively. Output goes to a temporary file renamed into place when complete.

mod chunk_writer;
pub mod chunks;
pub mod resolutions;
pub mod store;
mod writer;

use std::fs::File;
use std::ops::Range;
use std::path::Path;

use hdf5::types::{TypeDescriptor, VarLenAscii, VarLenUnicode};

use crate::error::{Error, Result};
use crate::genome::{Bin, BinTable, Chrom};
use crate::io::{MatrixInfo, MatrixReader, hdf5_guard};
use crate::matrix::{CountType, PixelBlock, Weights};
use chunks::Column;
pub use writer::{CoolWriteOptions, write_cool, write_mcool};

/// Maximum number of pixels in one streamed block.
pub const BLOCK_PIXELS: usize = 1 << 20;

/// Weight columns that cooler itself reads as divisive, by name (`cooler.api._4DN_DIVISIVE_WEIGHTS`).
pub const DIVISIVE_BY_NAME: [&str; 3] = ["KR", "VC", "VC_SQRT"];

mod reader;
pub use reader::{CoolReader, HdfContent, inspect};

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
/// [`crate::io::atomic`].
pub(crate) fn create_excl(path: &Path) -> Result<hdf5::File> {
    file_builder()
        .create_excl(path)
        .map_err(|e| Error::hdf5(path, "creating the file", e))
}
/// The size of the file at `path` (0 when it cannot be read: the reads that follow say why).
pub(crate) fn file_len(path: &str) -> u64 {
    std::fs::metadata(path).map_or(0, |m| m.len())
}
