//! Compartment eigenvectors of a matrix as it is read: each region of a view (cis) or the whole
//! map (trans) streamed from a reader into the eigensolver's matrix, with the bins' coverage, then
//! oriented by a phasing track, or by coverage when there is none. What `contactmap compartments`
//! computes; problems that do not stop the work come back as warnings.

use crate::error::Result;
use crate::expected::View;
use crate::io::{default_memory_budget, MatrixReader};
use crate::matrix::PixelBlock;

use super::cis::{cis_eig, CisEigParams, CisMatrixBuilder, RegionEigs};
use super::phasing::{self, SortMetric};
use super::trans::{trans_eig, DenseMatrix, TransEigParams};

/// How the eigenvectors are oriented: by `track` (GC content, gene density; one value per bin of
/// the map, NaN where unknown) and, with `sort`, reordered by their agreement with it; without a
/// track each vector's sign makes it correlate positively with the bins' coverage (not A/B).
#[derive(Clone, Copy, Debug, Default)]
pub struct Phasing<'a> {
    /// The phasing track, one value per bin of the map.
    pub track: Option<&'a [f64]>,
    /// Reorder the vectors by this agreement with the track (cooltools' `sort_metric`).
    pub sort: Option<SortMetric>,
}

/// Eigenvectors with the warnings met computing them (one line each, without a prefix).
#[derive(Clone, Debug)]
pub struct Eigs<T> {
    /// The eigenvectors: one [`RegionEigs`] per region for [`eigs_cis`], one for [`eigs_trans`].
    pub eigs: T,
    /// Vectors that did not reach the tolerance, vectors left unoriented.
    pub warnings: Vec<String>,
}

/// Eigenvectors of every region of `view` (cooltools `eigs_cis`), one region in memory at a
/// time, from the counts of `reader` times `weights` (cooler's multiplicative weights, NaN for
/// masked bins).
pub fn eigs_cis(
    reader: &dyn MatrixReader,
    weights: &[f64],
    view: &View,
    phasing: Phasing<'_>,
    params: &CisEigParams,
) -> Result<Eigs<Vec<RegionEigs>>> {
    params.check()?;
    let mut results = Vec::with_capacity(view.len());
    let mut warnings = Vec::new();
    for region in view.regions() {
        let range = region.bins.clone();
        let offset = range.start;
        let mut builder = CisMatrixBuilder::new(range.len(), params.ignore_diags);
        let mut coverage = vec![0.0f64; range.len()];
        reader.read_pixels(range.clone(), range.clone(), &mut |block| {
            add_coverage(&mut coverage, offset, block);
            for k in 0..block.len() {
                let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                let value = block.count[k] * weights[i] * weights[j];
                builder.push(i - offset, j - offset, value)?;
            }
            Ok(())
        })?;
        let matrix = builder.finish();
        let mut eigs = cis_eig(&matrix, params);
        if eigs.unconverged > 0 {
            warnings.push(format!(
                "region {}: {} of {} eigenvectors did not reach the tolerance; they are given as found",
                region.name, eigs.unconverged, params.n_eigs
            ));
        }
        let region_phasing = Phasing {
            track: phasing.track.map(|t| &t[range.clone()]),
            sort: phasing.sort,
        };
        warnings.extend(orient(&mut eigs, region_phasing, &coverage, &region.name));
        results.push(eigs);
    }
    Ok(Eigs {
        eigs: results,
        warnings,
    })
}

/// Add each pixel's raw count to the coverage of its two bins (`offset`: the first bin of
/// `coverage`).
fn add_coverage(coverage: &mut [f64], offset: usize, block: &PixelBlock) {
    for k in 0..block.len() {
        let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
        coverage[i - offset] += block.count[k];
        if i != j {
            coverage[j - offset] += block.count[k];
        }
    }
}

/// Orient (and with a sort metric, reorder) the vectors by the phasing track, else orient them
/// by coverage (Spearman, no reordering).
fn orient(
    eigs: &mut RegionEigs,
    phasing: Phasing<'_>,
    coverage: &[f64],
    region: &str,
) -> Vec<String> {
    let track = phasing.track;
    let (reference, sort) = match track {
        Some(track) => (track, phasing.sort),
        None => (coverage, None),
    };
    let mut warnings = Vec::new();
    let agreements = phasing::phase(&mut eigs.values, &mut eigs.vectors, reference, sort);
    for (k, (a, vector)) in agreements.iter().zip(&eigs.vectors).enumerate() {
        if track.is_some() && a.is_nan() && vector.iter().any(|v| v.is_finite()) {
            warnings.push(format!(
                "region {region}: the phasing track does not vary where E{} is defined; E{} is left unoriented",
                k + 1,
                k + 1
            ));
        }
    }
    warnings
}

/// The trans eigenvectors of the whole map (cooltools `eigs_trans`: dense, in memory), from the
/// counts of `reader` times `weights`.
pub fn eigs_trans(
    reader: &dyn MatrixReader,
    weights: &[f64],
    phasing: Phasing<'_>,
    params: &TransEigParams,
) -> Result<Eigs<RegionEigs>> {
    params.check()?;
    let bins = reader.bins();
    let n = bins.n_bins();
    let mut matrix = DenseMatrix::zeros(n, default_memory_budget() / 2)?;
    let mut coverage = vec![0.0f64; n];
    reader.read_pixels(0..n, 0..n, &mut |block| {
        add_coverage(&mut coverage, 0, block);
        for k in 0..block.len() {
            let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
            matrix.set(i, j, block.count[k] * weights[i] * weights[j]);
        }
        Ok(())
    })?;
    let chrom_of: Vec<u32> = (0..n).map(|b| bins.bin(b).chrom_id as u32).collect();
    let mut eigs = trans_eig(matrix, &chrom_of, params);
    let warnings = orient(&mut eigs, phasing, &coverage, "genome-wide trans");
    Ok(Eigs { eigs, warnings })
}
