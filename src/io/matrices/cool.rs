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
mod hdf5_file;
mod reader;
pub mod resolutions;
pub mod store;
mod weights;
mod writer;

pub(crate) use hdf5_file::{create_excl, file_builder, file_len};
pub use reader::{BLOCK_PIXELS, CoolReader, HdfContent, inspect};
pub use weights::DIVISIVE_BY_NAME;
pub use writer::{CoolWriteOptions, write_cool, write_mcool};
