//! The options of opening a matrix: the resolution of a multi-resolution file, and what inputs
//! that do not carry their own bin table (text tables, pairs) need.

use std::path::PathBuf;

use super::format::TextFormat;

/// Options for opening a matrix ([`open_matrix`](crate::io::open_matrix)): the resolution of a
/// multi-resolution file, and what inputs without their own bin table (text tables, pairs) need.
#[derive(Clone, Debug, Default)]
pub struct OpenOptions {
    /// Text format; guessed from the extension and the first data line when `None`.
    pub text_format: Option<TextFormat>,
    /// The resolution (bp) pairs and BG2 / COO tables given with `chrom_sizes` are binned at
    /// (`--bin-size`, hictk load's name; [`resolution`](Self::resolution) chooses a level of a
    /// file that has several).
    pub text_resolution: Option<u64>,
    /// Chromosome sizes file (`name<TAB>length`).
    pub chrom_sizes: Option<PathBuf>,
    /// Bin table BED (`chrom start end`), for COO and dense tables.
    pub bins_bed: Option<PathBuf>,
    /// 1-based columns of chrom1, pos1, chrom2, pos2 in a pairs file (default: from the
    /// `#columns:` header, else the 4DN layout 2, 3, 4, 5).
    pub pairs_columns: Option<[usize; 4]>,
    /// Pairs positions are 0-based (cooler `cload pairs --zero-based`); default 1-based, as the
    /// 4DN pairs specification and cooler's default.
    pub pairs_zero_based: bool,
    /// The resolution (bin size in bp) to open in a multi-resolution file (`.mcool`, `.hic`), as
    /// a URI's `::/resolutions/N` names it (hictk's `--resolution`); for a single-resolution
    /// map, the bin size it must have. `None`: the URI alone decides.
    pub resolution: Option<u64>,
}
