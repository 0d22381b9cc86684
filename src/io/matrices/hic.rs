//! Juicer `.hic` reader (format versions 8 and 9) and writer (version 9, [`HicWriter`]).
//!
//! A `.hic` file (Durand et al. 2016, "Juicer provides a one-click system for analyzing
//! loop-resolution Hi-C experiments", *Cell Systems* 3:95) stores, for every pair of chromosomes and
//! every resolution, the contact matrix cut into zlib-compressed blocks, with an index of the blocks,
//! expected values and normalisation vectors. This module follows the Aiden lab specification,
//! <https://github.com/aidenlab/hic-format> (`HiCFormatV8.md`, `HiCFormatV9.md`); hictk and straw
//! were read to check our understanding of it. Only base-pair resolutions are read; fragment
//! resolutions are skipped.
//!
//! # Method
//!
//! [`HicReader::open`] reads the header (version, genome, attributes, chromosomes, resolutions),
//! the master index of chromosome-pair matrices in the footer, skips the expected-value sections
//! and reads the index of normalisation vectors (version 8: at the end of the footer; version 9: at
//! the position the header gives). The block index of a chromosome pair is read on first use and
//! cached. Every length read from the file is checked against the file size before anything is
//! allocated, so a truncated or corrupt file gives an [`Error::Format`] naming what was being
//! read, never a panic: chromosome lengths above `u32::MAX` (hictk's limit) and headers whose
//! chromosomes make more bins than the file's size can hold data for are refused before any
//! per-bin allocation. Names and other file bytes quoted in messages have their control
//! characters escaped, so a message is always one line.
//!
//! A pixel query is answered one row chromosome at a time, in bands of rows sized so that a band
//! holds about [`BAND_BUDGET_BYTES`] of compressed blocks. For each band, the blocks (of every
//! chromosome pair `(i, j >= i)`) whose first possible row falls in the band are read with
//! positioned reads and inflated and decoded in parallel (rayon); their pixels are filtered to the
//! query, the band's own pixels are sorted by `(bin1, bin2)` and handed to the sink, and pixels of
//! later rows wait in the bucket of their band. Each block is thus read once, and memory stays
//! proportional to a band, not to the file. Results do not depend on the number of threads.
//!
//! # Coordinates
//!
//! Bins are fixed-size and 0-based, as [`BinTable::fixed`] makes them. Juicer's `All`
//! pseudo-chromosome (index 0) is left out of the bin table, as hictk does; the other chromosomes
//! keep their order. Blocks of the matrix of chromosomes `(i, j)`, `i <= j` in file order, hold
//! records `(x, y)` with `x` a bin of `i` and `y` a bin of `j`, so genome-wide `bin1 =
//! offset[i] + x` and `bin2 = offset[j] + y`. Intra-chromosomal matrices store one triangle; either
//! orientation is accepted and pixels are always returned with `bin1 <= bin2`. Some writers store
//! both triangles: a pixel is then read once, from its upper record (`x <= y`, the `bin1 <= bin2`
//! pixels hictk returns). Records past the last bin of their chromosome are dropped, as hictk and
//! hic2cool drop them, and counted for [`MatrixReader::warnings`] (one line per file); records at
//! negative bins are an error. Version 8 blocks and
//! version 9 inter-chromosomal blocks form a square grid (`block = (y / blockBinCount) *
//! blockColumnCount + x / blockBinCount`); version 9 intra-chromosomal blocks are rotated, numbered
//! by position along the diagonal and a depth that doubles away from it.
//!
//! # Weights and counts
//!
//! `.hic` normalisation vectors (KR, VC, VC_SQRT, SCALE, ...) are divisive: `balanced = count /
//! (v[i] * v[j])`. They are inverted on read into cooler's multiplicative convention with
//! [`Weights::from_divisive`] (zero, negative and non-finite values become `NaN`); chromosomes
//! without a vector get `NaN`. Version 8 stores vectors as `float64`, version 9 as `float32`.
//! Counts are reported as [`CountType::Integer`]: raw Juicer counts are whole numbers, and hictk
//! converts the raw matrix to cooler's `int32` counts too.
//!
//! # Layout
//!
//! Reading, bottom up (each module imports only those before it): `bytes` (the bounds-checked
//! sequential reader, the quoting of names read from the file), `blocks` (the block index entries,
//! block geometry, inflating and decoding), `norms` (the normalisation-vector index and the
//! expected-value records), `header` (the header and the footer's master index) and `reader`
//! ([`HicReader`]: opening, query plans, streaming, vectors and expected values on demand).
//! Writing: `expected` (Juicer's expected values, accumulated as pixels stream) and `writer`
//! ([`HicWriter`]). Tests build files with the test-only `synthetic` writer.
//!
//! [`Error::Format`]: crate::error::Error::Format
//! [`MatrixReader::warnings`]: crate::io::MatrixReader::warnings
//! [`BinTable::fixed`]: crate::genome::BinTable::fixed
//! [`Weights::from_divisive`]: crate::matrix::Weights::from_divisive
//! [`CountType::Integer`]: crate::matrix::CountType::Integer

mod blocks;
mod bytes;
pub mod expected;
mod header;
mod norms;
mod reader;
mod writer;

pub use expected::{JuicerExpected, JuicerExpectedBuilder, MultiResolutionExpected};
pub use norms::HicExpected;
pub(crate) use reader::list_numbers;
pub use reader::{BAND_BUDGET_BYTES, HicReader};
pub use writer::{BATCH_RECORDS, HicNormVector, HicWriteOptions, HicWriter};

#[cfg(test)]
mod synthetic;
#[cfg(test)]
mod tests;
