//! Compartment eigenvectors of a matrix as it is read: each region of a view (cis) or the whole
//! map (trans) streamed from a reader into the eigensolver's matrix, with the bins' coverage, then
//! oriented by a phasing track, or by coverage when there is none. What `contactmap compartments`
//! computes; problems that do not stop the work come back as warnings.

use crate::error::Result;
use crate::genome::View;
use crate::io::{MatrixReader, default_memory_budget};
use crate::matrix::PixelBlock;

use super::cis::{CisEigParams, CisMatrixBuilder, RegionEigs, cis_eig};
use super::phasing::{self, SortMetric};
use super::trans::{DenseMatrix, TransEigParams, trans_eig};

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
///
/// # Examples
///
/// chr2L of the dm6 map, phased by the track cooltools was given
/// (`data/reference/compartments/`): E1 is cooltools' phased E1.
///
/// ```
/// use std::io::BufRead;
/// use std::path::Path;
/// use contactmap::compartments::cis::CisEigParams;
/// use contactmap::compartments::eigs::{eigs_cis, Phasing};
/// use contactmap::genome::{RegionSpec, View};
/// use contactmap::io::tables::track_on_bins;
/// use contactmap::io::{open_matrix, open_text, MatrixReader, OpenOptions};
///
/// let uri = "data/cooler_test_file.mcool::/resolutions/100000";
/// let reader = open_matrix(uri, &OpenOptions::default())?;
/// let weights = reader.weights("weight")?.values;
/// let reference = Path::new("data/reference/compartments");
/// let mut track = track_on_bins(&reference.join("dm6_100kb.phasing.tsv.gz"), "track", reader.bins())?;
/// for (t, w) in track.iter_mut().zip(&weights) {
///     if w.is_nan() {
///         *t = f64::NAN; // cooltools masks the track on the map's bad bins
///     }
/// }
/// let chr2l = RegionSpec { chrom: "chr2L".into(), start_bp: 0, end_bp: 23_513_712, name: None };
/// let view = View::new(reader.bins(), &[chr2l])?;
/// let phasing = Phasing { track: Some(&track), sort: None };
/// let eigs = eigs_cis(&*reader, &weights, &view, phasing, &CisEigParams::default())?;
/// assert!(eigs.warnings.is_empty());
/// let e1 = &eigs.eigs[0].vectors[0];
/// // cooltools' E1, one line per bin of the map, chr2L first
/// let cooltools: Vec<f64> = open_text(&reference.join("dm6_100kb.eigs_cis_phased.vecs.tsv.gz"))?
///     .lines()
///     .skip(1)
///     .take(e1.len())
///     .map(|line| line.unwrap().split('\t').next().unwrap().parse().unwrap_or(f64::NAN))
///     .collect();
/// for (ours, theirs) in e1.iter().zip(&cooltools) {
///     assert_eq!(ours.is_nan(), theirs.is_nan());
///     assert!(ours.is_nan() || (ours - theirs).abs() < 1e-6, "{ours} vs {theirs}");
/// }
/// assert!((eigs.eigs[0].values[0] - 54.3958149).abs() < 1e-6);
/// # Ok::<(), contactmap::Error>(())
/// ```
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
///
/// # Examples
///
/// The mm9 map's trans eigenvalues are cooltools' (`eigs_trans`,
/// `data/reference/compartments/mm9_10Mb.eigs_trans.vals.tsv.gz`).
///
/// ```
/// use contactmap::compartments::eigs::{eigs_trans, Phasing};
/// use contactmap::compartments::trans::TransEigParams;
/// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
///
/// let reader = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
/// let weights = reader.weights("weight")?.values;
/// let eigs = eigs_trans(&*reader, &weights, Phasing::default(), &TransEigParams::default())?;
/// let cooltools = [40.95259534, 28.12646212, 12.72596468];
/// for (ours, theirs) in eigs.eigs.values.iter().zip(cooltools) {
///     assert!((ours - theirs).abs() < 1e-6 * theirs, "{ours} vs {theirs}");
/// }
/// assert_eq!(eigs.eigs.vectors[0].len(), 278);
/// # Ok::<(), contactmap::Error>(())
/// ```
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
