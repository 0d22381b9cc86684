//! What the dot caller returns: the enriched pixels, the dots, the statistics per kernel.

use super::fdr::KernelStats;

/// An enriched pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct EnrichedPixel {
    /// Row bin (genome-wide).
    pub bin1: usize,
    /// Column bin.
    pub bin2: usize,
    /// Raw count.
    pub count: u64,
    /// Locally adjusted expected per kernel (cooltools' order).
    pub la_exp: Vec<f64>,
    /// q-value per kernel.
    pub qval: Vec<f64>,
    /// Index of its view region.
    pub region: usize,
}

/// A dot: the brightest enriched pixel of a cluster.
#[derive(Clone, Debug, PartialEq)]
pub struct Dot {
    /// The representative pixel.
    pub pixel: EnrichedPixel,
    /// The cluster's centroid `(start1, start2)` in bp (BIRCH's subcluster centre).
    pub centroid: [f64; 2],
    /// The cluster's label within its region.
    pub label: usize,
    /// Pixels in the cluster.
    pub size: usize,
}

/// What the dot caller found.
#[derive(Clone, Debug, PartialEq)]
pub struct DotCalls {
    /// The kernels' names, in column order.
    pub kernels: Vec<&'static str>,
    /// Pixels scored (per kernel they are the same).
    pub n_scored: u64,
    /// Per kernel: counts, thresholds and q-values per lambda bin.
    pub stats: Vec<KernelStats>,
    /// The enriched pixels, by `(bin1, bin2)`.
    pub enriched: Vec<EnrichedPixel>,
    /// The dots (when clustering was asked for), cooltools' order.
    pub dots: Option<Vec<Dot>>,
    /// Lambda bins past cooltools' last edge that hold pixels (0 when cooltools would run).
    pub extra_lambda_bins: usize,
}
