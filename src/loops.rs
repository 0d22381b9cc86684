//! Loops (dots): cooltools 0.7.1's dot caller (`cooltools.api.dotfinder.dots`), step for step,
//! computed from the sparse band instead of dense tiles.
//!
//! 1. **Score** ([`scan`]): every pixel `(i, j)` of each view region with `0 < j - i < band`
//!    (`band` = max separation / bin size) gets, for each of the four HiCCUPS kernels
//!    ([`kernels`]: donut, vertical, horizontal, lower-left with half-widths `(w, p)`), a locally
//!    adjusted expected `E[j - i] / (w_i w_j) * KO / KE` in raw counts; pixels whose kernels
//!    reach `max_nans_tolerated` missing cells or have no finite `KO / KE` are not scored.
//! 2. **Histogram and thresholds** ([`fdr`]): per kernel, the scored pixels' raw counts per lambda
//!    bin (locally adjusted expected binned at `2^(k/3)`), then per bin the FDR threshold and
//!    the q-values of a Poisson test with the bin's right edge as mean.
//! 3. **Extract**: a second scoring pass keeps the pixels at or above the threshold of their
//!    lambda bin for every kernel (the *enriched pixels*), annotated with their q-values.
//! 4. **Cluster** ([`birch`]): per region, BIRCH on `(start1, start2)` with the clustering radius
//!    as threshold (scikit-learn's, including its order dependence); the brightest pixel of each
//!    cluster represents it (the first in (bin1, bin2) order on ties).
//! 5. **Filter** (HiCCUPS, Rao et al. 2014): keep a cluster's representative when its count
//!    exceeds 1.75 times the donut and lower-left expected, 1.5 times the vertical and horizontal
//!    ones, 2 times the donut or the lower-left one, and it is not a singleton or its four
//!    q-values sum to at most 0.02.
//!
//! The output rows are cooltools': the dots sorted by region name then cluster label, the
//! enriched pixels by `(bin1, bin2)`.
//!
//! Where cooltools fails, this does not: a pixel whose locally adjusted expected lies above the
//! last lambda edge (`2^((n - 1) / 3)`, 8192 for 40 bins) raises an error in cooltools (its
//! issues #511, #552); here the bins continue at the same ratio, so such a map is called, and any
//! map cooltools calls gets the same result. Tiles do not exist here, so nothing depends on a tile
//! size (cooltools' result does, when `max_nans_tolerated` lets pixels at a tile's padding be
//! scored with a truncated footprint).

pub mod birch;
mod calls;
pub mod fdr;
pub mod kernels;
pub mod lists;
pub mod merge;
pub mod scan;
pub mod tables;
#[cfg(test)]
mod tests;

pub use calls::{Dot, DotCalls, EnrichedPixel};

use std::collections::BTreeMap;

use crate::error::{Error, Result};
use crate::genome::View;
use crate::io::MatrixReader;
use fdr::{Histogram, KernelStats, LambdaBins};
use kernels::{Kernel, KernelType};
use scan::{RegionScan, ScanSettings, scan_region};

/// The dot caller's parameters; the defaults are the cooltools API's (`cooltools.dots`), which
/// differ from its command line's ([`DotsParams::cooltools_cli`]).
#[derive(Clone, Debug, PartialEq)]
pub struct DotsParams {
    /// Kernel outer half-width `w` (bins).
    pub w: usize,
    /// Kernel inner half-width `p` (bins).
    pub p: usize,
    /// Pixels are scored up to this separation (bp, exclusive in bins: `j - i < max / bin`).
    pub max_separation_bp: u64,
    /// A kernel footprint with this many missing cells rejects the pixel (cooltools: 1).
    pub max_nans_tolerated: usize,
    /// Finite lambda-bin edges (40 to 50).
    pub n_lambda_bins: usize,
    /// False discovery rate of each lambda bin.
    pub fdr: f64,
    /// BIRCH threshold in bp; `None`: no clustering (the enriched pixels are the result).
    pub clustering_radius_bp: Option<f64>,
    /// Apply the HiCCUPS enrichment filter to the clusters' representatives.
    pub cluster_filtering: bool,
}

impl DotsParams {
    /// The cooltools API defaults for `resolution`, with its recommended kernels (an error for
    /// bin sizes it has none for: give `w` and `p`).
    ///
    /// ```
    /// use contactmap::loops::DotsParams;
    /// let params = DotsParams::for_resolution(10_000)?;
    /// assert_eq!((params.w, params.p, params.max_separation_bp), (5, 2, 10_000_000));
    /// assert!(DotsParams::for_resolution(100_000).is_err());
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn for_resolution(resolution: u64) -> Result<DotsParams> {
        let (w, p) = kernels::recommended_w_p(resolution).ok_or_else(|| {
            Error::parameter(
                "w",
                "(none)",
                format!(
                    "cooltools recommends kernels for bins of 4-28 kb only (this map has {resolution} bp \
                     bins): give the kernel half-widths w and p (HiCCUPS uses w=7,p=4 at 5 kb, \
                     w=5,p=2 at 10 kb, w=3,p=1 at 25 kb)"
                ),
            )
        })?;
        Ok(DotsParams {
            w,
            p,
            ..DotsParams::default()
        })
    }

    /// cooltools' command-line defaults (`cooltools dots`): max separation 2 Mb, 45 lambda bins,
    /// FDR 0.02, clustering radius 39 kb, with the kernels of `self`.
    pub fn cooltools_cli(self) -> DotsParams {
        DotsParams {
            max_separation_bp: 2_000_000,
            n_lambda_bins: 45,
            fdr: 0.02,
            clustering_radius_bp: Some(39_000.0),
            ..self
        }
    }

    /// Check the values; an [`Error::Parameter`] names the first bad one.
    pub fn check(&self) -> Result<()> {
        Kernel::new(KernelType::Donut, self.w, self.p)?;
        if !(40..=50).contains(&self.n_lambda_bins) {
            return Err(Error::parameter(
                "n_lambda_bins",
                self.n_lambda_bins,
                "between 40 and 50 (cooltools' range)",
            ));
        }
        if !(self.fdr > 0.0 && self.fdr < 1.0) {
            return Err(Error::parameter("fdr", self.fdr, "between 0 and 1"));
        }
        if self.max_nans_tolerated == 0 || self.max_nans_tolerated > 2 * self.w + 1 {
            return Err(Error::parameter(
                "max_nans_tolerated",
                self.max_nans_tolerated,
                format!("from 1 to the kernel width 2w+1 = {}", 2 * self.w + 1),
            ));
        }
        if let Some(r) = self.clustering_radius_bp {
            if !(r > 0.0 && r.is_finite()) {
                return Err(Error::parameter(
                    "clustering_radius",
                    r,
                    "a positive distance in bp",
                ));
            }
        }
        Ok(())
    }
}

impl Default for DotsParams {
    /// cooltools' API defaults with the 10 kb kernels (w=5, p=2).
    fn default() -> Self {
        DotsParams {
            w: 5,
            p: 2,
            max_separation_bp: 10_000_000,
            max_nans_tolerated: 1,
            n_lambda_bins: 40,
            fdr: 0.1,
            clustering_radius_bp: Some(20_000.0),
            cluster_filtering: true,
        }
    }
}

/// Call dots on `reader` balanced by `weights` (multiplicative, genome-wide), in the regions of
/// `view`, with `expected[r][d]` the balanced expected of region `r` at diagonal `d` (NaN for
/// ignored diagonals; cooltools' `balanced.avg`).
pub fn call_dots(
    reader: &dyn MatrixReader,
    weights: &[f64],
    view: &View,
    expected: &[Vec<f64>],
    params: &DotsParams,
) -> Result<DotCalls> {
    params.check()?;
    let bins_table = reader.bins();
    let resolution = bins_table.resolution().ok_or_else(|| {
        Error::format(
            reader.source(),
            "dots needs fixed-size bins (kernels are counted in bins)",
        )
    })?;
    if weights.len() != bins_table.n_bins() {
        return Err(Error::Data(format!(
            "{} weights for {} bins",
            weights.len(),
            bins_table.n_bins()
        )));
    }
    if expected.len() != view.regions().len() {
        return Err(Error::Data(format!(
            "expected for {} regions, the view has {}",
            expected.len(),
            view.regions().len()
        )));
    }
    let kernels = Kernel::hiccups(params.w, params.p)?;
    let band = (params.max_separation_bp as f64 / resolution as f64) as usize;
    let settings = ScanSettings {
        kernels: &kernels,
        band,
        max_nans_tolerated: params.max_nans_tolerated,
        min_count: 0,
        rows: None,
    };
    let lambda = LambdaBins::new(params.n_lambda_bins);
    let n_k = kernels.len();
    let scans: Vec<RegionScan<'_>> = view
        .regions()
        .iter()
        .zip(expected)
        .map(|(region, exp)| RegionScan {
            bins: region.bins.clone(),
            weights,
            expected: exp,
        })
        .collect();

    // 1. the histogram
    let beyond = |x: f64| {
        Error::Data(format!(
            "a locally adjusted expected of {x:e} is beyond the last lambda bin ({:e})",
            lambda.edges[lambda.edges.len() - 1]
        ))
    };
    let mut histogram = Histogram::new(n_k, lambda.len());
    let mut n_scored = 0u64;
    // per row, the largest count in each lambda bin of the first kernel: rows where none reaches
    // its bin's threshold hold no enriched pixel, and the extraction pass skips them
    let mut row_maxima = vec![Vec::new(); bins_table.n_bins()];
    for scan in &scans {
        let (h, n, maxima) = scan_region(
            reader,
            scan,
            &settings,
            || (Histogram::new(n_k, lambda.len()), 0u64, Vec::new()),
            |(h, n, maxima): &mut (Histogram, u64, Vec<(usize, Vec<u16>)>), pixel| {
                for (k, &x) in pixel.la_exp.iter().enumerate() {
                    let b = lambda.index(x);
                    if b >= lambda.len() {
                        return Err(beyond(x));
                    }
                    h.add(k, pixel.count, b);
                    if k == 0 {
                        if maxima.last().is_none_or(|(row, _)| *row != pixel.bin1) {
                            maxima.push((pixel.bin1, vec![0u16; lambda.len()]));
                        }
                        let max = &mut maxima.last_mut().expect("pushed").1[b];
                        *max = (*max).max(pixel.count.min(u16::MAX as u64) as u16);
                    }
                }
                *n += 1;
                Ok(())
            },
            |(a, na, mut ma), (b, nb, mut mb)| {
                ma.append(&mut mb);
                (a.merge(b), na + nb, ma)
            },
        )?;
        histogram = histogram.merge(h);
        n_scored += n;
        for (row, max) in maxima {
            row_maxima[row] = max;
        }
    }
    let stats = (0..n_k)
        .map(|k| fdr::kernel_stats(&histogram, k, &lambda, params.fdr))
        .collect::<Result<Vec<_>>>()?;
    let extra_lambda_bins = stats
        .iter()
        .map(|s| s.n_bins.saturating_sub(params.n_lambda_bins))
        .max()
        .unwrap_or(0);

    // 2. the enriched pixels: a pixel passes the threshold of its bin for every kernel, so at
    // least the largest of the kernels' smallest thresholds
    let min_count = stats
        .iter()
        .map(KernelStats::min_threshold)
        .max()
        .unwrap_or(0);
    let donut = &stats[0];
    let wanted: Vec<bool> = row_maxima
        .iter()
        .map(|max| {
            max.iter().enumerate().any(|(b, &m)| {
                b < donut.n_bins && (m == u16::MAX || m as u64 >= donut.thresholds[b])
            })
        })
        .collect();
    drop(row_maxima);
    let extraction = ScanSettings {
        min_count,
        rows: Some(&wanted),
        ..settings
    };
    let mut enriched = Vec::new();
    for (r, scan) in scans.iter().enumerate() {
        let mut found = scan_region(
            reader,
            scan,
            &extraction,
            Vec::new,
            |kept: &mut Vec<EnrichedPixel>, pixel| {
                for (k, &x) in pixel.la_exp.iter().enumerate() {
                    let b = lambda.index(x);
                    let s = &stats[k];
                    if b >= s.n_bins || pixel.count < s.thresholds[b] {
                        return Ok(());
                    }
                }
                // q-values by the bins' labels, as cooltools' merge on pd.cut(la, labels); a
                // pixel outside every labelled bin does not survive that merge
                let mut qval = Vec::with_capacity(n_k);
                for (k, &x) in pixel.la_exp.iter().enumerate() {
                    let b = lambda.label_index(x);
                    match stats[k].qvalue(pixel.count, b) {
                        Some(q) if b < stats[k].n_bins => qval.push(q),
                        _ => return Ok(()),
                    }
                }
                kept.push(EnrichedPixel {
                    bin1: pixel.bin1,
                    bin2: pixel.bin2,
                    count: pixel.count,
                    la_exp: pixel.la_exp.to_vec(),
                    qval,
                    region: r,
                });
                Ok(())
            },
            |mut a, mut b| {
                a.append(&mut b);
                a
            },
        )?;
        enriched.append(&mut found);
    }
    enriched.sort_by_key(|p| (p.bin1, p.bin2));

    // 3. clusters and their representatives
    let dots = params.clustering_radius_bp.map(|radius| {
        let dots = cluster(&enriched, view, bins_table, radius);
        if params.cluster_filtering {
            dots.into_iter().filter(hiccups_filter).collect()
        } else {
            dots
        }
    });
    Ok(DotCalls {
        kernels: kernels.iter().map(|k| k.kind.name()).collect(),
        n_scored,
        stats,
        enriched,
        dots,
        extra_lambda_bins,
    })
}

/// cooltools' `clustering_step`: BIRCH per region on `(start1, start2)`, then the brightest pixel
/// of each cluster, sorted by region name and label.
fn cluster(
    enriched: &[EnrichedPixel],
    view: &View,
    bins: &crate::genome::BinTable,
    radius: f64,
) -> Vec<Dot> {
    let mut by_region: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (k, pixel) in enriched.iter().enumerate() {
        by_region.entry(pixel.region).or_default().push(k);
    }
    // (region name, label) -> (representative, centroid, size)
    let mut groups: BTreeMap<(String, usize), (usize, [f64; 2], usize)> = BTreeMap::new();
    for (&region, members) in &by_region {
        let points: Vec<[f64; 2]> = members
            .iter()
            .map(|&k| {
                let p = &enriched[k];
                [bins.bin(p.bin1).start as f64, bins.bin(p.bin2).start as f64]
            })
            .collect();
        let fit = birch::birch(&points, radius);
        let mut sizes: BTreeMap<usize, usize> = BTreeMap::new();
        for &label in &fit.labels {
            *sizes.entry(label).or_default() += 1;
        }
        let name = &view.regions()[region].name;
        for (&k, &label) in members.iter().zip(&fit.labels) {
            let entry = groups.entry((name.clone(), label)).or_insert((
                k,
                fit.centres[label],
                sizes[&label],
            ));
            if enriched[k].count > enriched[entry.0].count {
                entry.0 = k;
            }
        }
    }
    groups
        .into_iter()
        .map(|((_, label), (k, centroid, size))| Dot {
            pixel: enriched[k].clone(),
            centroid,
            label,
            size,
        })
        .collect()
}

/// cooltools' `cluster_filtering_hiccups` with its default factors.
fn hiccups_filter(dot: &Dot) -> bool {
    let count = dot.pixel.count as f64;
    let la = &dot.pixel.la_exp;
    let q = &dot.pixel.qval;
    let (donut, vertical, horizontal, lowleft) = (la[0], la[1], la[2], la[3]);
    count > 1.75 * lowleft
        && count > 1.75 * donut
        && count > 1.5 * vertical
        && count > 1.5 * horizontal
        && (count > 2.0 * lowleft || count > 2.0 * donut)
        && (dot.size > 1 || (q[3] + q[0] + q[1] + q[2]) <= 0.02)
}
