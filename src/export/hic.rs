//! A Juicer `.hic` with the normalisation vectors and expected values Juicer stores
//! ([`write_hic`]).
//!
//! This module stands above both the formats ([`crate::io`]) and the algorithms
//! ([`crate::balance`]): writing a `.hic` as Juicer does means balancing every chromosome at every
//! resolution, and the formats floor imports no algorithm. The expected values a `.hic` stores are
//! the format's own record ([`crate::io::hic::expected`], as hictk keeps them in its `hic`
//! library), computed while the pixels stream.

use std::path::Path;
use std::sync::Mutex;

use crate::balance::{BalanceParams, Method, Scope, balance};
use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::io::hic::{
    HicNormVector, HicReader, HicWriteOptions, HicWriter, JuicerExpected, JuicerExpectedBuilder,
    MultiResolutionExpected,
};
use crate::io::{self, Inspect, MatrixReader};
use crate::matrix::pixels::Pixels;
use crate::matrix::{PixelBlock, invert_weight};

/// The normalisations a `.hic` gets by default (Juicer's set).
pub const DEFAULT_HIC_NORMALIZATIONS: [Method; 4] =
    [Method::Vc, Method::VcSqrt, Method::Kr, Method::Scale];

/// The normalisations to store in a `.hic`, from names (case-insensitive: VC, VC_SQRT, KR,
/// SCALE, ICE) or `none`, repeats dropped; none given is Juicer's set
/// ([`DEFAULT_HIC_NORMALIZATIONS`]).
///
/// ```
/// use contactmap::balance::Method;
/// use contactmap::export::parse_normalizations;
/// assert_eq!(parse_normalizations(&["kr".into(), "KR".into()])?, vec![Method::Kr]);
/// assert!(parse_normalizations(&["none".into()])?.is_empty());
/// assert!(parse_normalizations(&["XX".into()]).is_err());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn parse_normalizations(items: &[String]) -> Result<Vec<Method>> {
    if items.is_empty() {
        return Ok(DEFAULT_HIC_NORMALIZATIONS.to_vec());
    }
    let mut methods = Vec::new();
    for item in items {
        if item.trim().eq_ignore_ascii_case("none") {
            continue;
        }
        let method = Method::from_juicer_name(item).ok_or_else(|| {
            Error::Argument(format!(
                "'{item}' is not one of VC, VC_SQRT, KR, SCALE, ICE, none"
            ))
        })?;
        if !methods.contains(&method) {
            methods.push(method);
        }
    }
    Ok(methods)
}

/// A chromosome whose balancing did not converge: its vector is stored anyway, as the last
/// iteration left it (as Juicer does).
#[derive(Clone, Debug, PartialEq)]
pub struct Unconverged {
    /// The normalisation.
    pub method: Method,
    /// The resolution.
    pub resolution: u64,
    /// The chromosome's name.
    pub chrom: String,
}

impl std::fmt::Display for Unconverged {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} at {} bp: {} did not converge; its vector is stored as the last iteration left it",
            self.method.juicer_name(),
            self.resolution,
            self.chrom
        )
    }
}

/// Write `reader` as a `.hic` at `path` (under a temporary name, renamed when complete) with
/// `resolutions` and the normalisations `methods` (Juicer's parameters:
/// [`BalanceParams::for_method`] on each chromosome's own pixels); returns the chromosomes whose
/// balancing did not converge (their vectors are stored anyway).
///
/// Steps: [`HicWriter`] streams the input into blocks at every resolution while Juicer's raw
/// expected values of every resolution accumulate from the same stream, and closes the file with
/// a footer that has no normalisation yet. Each resolution is then read back one chromosome at a
/// time (its intra-chromosomal pixels only, on a bin table of that chromosome alone, so memory
/// follows the largest chromosome) and each normalisation is computed and its divisive vector kept
/// (`1 / weight`, NaN for masked bins), with the expected values of the normalised counts. The
/// footer is then rewritten with all of them.
///
/// # Examples
///
/// ```
/// use contactmap::balance::Method;
/// use contactmap::export::write_hic;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::hic::{HicReader, HicWriteOptions};
/// use contactmap::io::{InMemory, MatrixReader};
/// use contactmap::matrix::{CountType, MatrixBuilder};
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 10_000)], 1_000)?;
/// let mut builder = MatrixBuilder::new(bins, CountType::Integer);
/// for i in 0..10u64 {
///     for j in i..10 {
///         builder.push(i, j, (10 - (j - i)) as f64)?;
///     }
/// }
/// let matrix = InMemory::new("example".into(), builder.build());
/// let dir = std::env::temp_dir().join(format!("contactmap-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("map.hic");
/// let unconverged = write_hic(
///     &matrix,
///     &path,
///     &[1_000, 2_000],
///     &[Method::Vc, Method::Kr],
///     &HicWriteOptions::default(),
/// )?;
/// assert!(unconverged.is_empty());
/// let level = HicReader::open(&path, Some(2_000))?;
/// assert_eq!(level.bins().n_bins(), 5);
/// assert!(level.weight_names().contains(&"KR".to_string()));
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_hic(
    reader: &dyn MatrixReader,
    path: &Path,
    resolutions: &[u64],
    methods: &[Method],
    options: &HicWriteOptions,
) -> Result<Vec<Unconverged>> {
    // Juicer, hictk and our reader hold chromosome lengths in 32 bits; the expected values are
    // sized from them.
    if let Some(chrom) = reader
        .bins()
        .chroms()
        .iter()
        .find(|c| c.length_bp > u64::from(u32::MAX))
    {
        return Err(Error::format(
            reader.source(),
            format!(
                "chromosome {} ({} bp) is too long for a .hic file (at most {} bp)",
                chrom.name.escape_default(),
                chrom.length_bp,
                u32::MAX
            ),
        ));
    }
    let mut unconverged = Vec::new();
    io::atomic::with_temporary(
        path,
        |tmp| HicWriter::create(tmp, reader.bins(), resolutions, options),
        |tmp, mut writer| {
            // Juicer's raw expected values of every resolution, from the pixels as they stream
            // into the writer (which reads them with `read_pixels` once).
            let expected = Mutex::new(MultiResolutionExpected::new(
                reader.bins(),
                writer.resolutions(),
            ));
            writer.write_matrices(&Inspect::new(reader, |block| {
                expected
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .add(block);
                Ok(())
            }))?;
            let expected = expected
                .into_inner()
                .unwrap_or_else(|e| e.into_inner())
                .finish();
            writer.write_footer(&expected, &[], &[])?;
            let mut normalized = Vec::new();
            let mut vectors = Vec::new();
            if !methods.is_empty() {
                for &resolution in &writer.resolutions().to_vec() {
                    let level = HicReader::open(tmp, Some(resolution))?;
                    let vectors_of_level = juicer_vectors(&level, resolution, methods)?;
                    normalized.extend(vectors_of_level.normalized);
                    vectors.extend(vectors_of_level.vectors);
                    unconverged.extend(vectors_of_level.unconverged);
                }
            }
            writer.write_footer(&expected, &normalized, &vectors)
        },
    )?;
    Ok(unconverged)
}

/// The vectors of one resolution.
struct LevelVectors {
    normalized: Vec<(String, JuicerExpected)>,
    vectors: Vec<HicNormVector>,
    unconverged: Vec<Unconverged>,
}

/// Expected values and normalisation vectors of one resolution, one chromosome at a time.
fn juicer_vectors(
    reader: &dyn MatrixReader,
    resolution: u64,
    methods: &[Method],
) -> Result<LevelVectors> {
    let bins = reader.bins();
    let mut per_method: Vec<JuicerExpectedBuilder> = methods
        .iter()
        .map(|_| JuicerExpectedBuilder::new(bins, resolution))
        .collect();
    let mut vectors = Vec::new();
    let mut unconverged = Vec::new();
    for (chrom_id, chrom) in bins.chroms().iter().enumerate() {
        let range = bins.chrom_bins(chrom_id);
        let offset = range.start as u64;
        let local = BinTable::fixed(vec![chrom.clone()], resolution)?;
        let mut pixels = Pixels::with_capacity(local.clone(), reader.count_type(), 0)?;
        let mut shifted = PixelBlock::default();
        reader.read_pixels(range.clone(), range.clone(), &mut |block| {
            shifted.bin1.clear();
            shifted.bin2.clear();
            shifted.count.clear();
            for k in 0..block.len() {
                shifted.push(
                    block.bin1[k] - offset,
                    block.bin2[k] - offset,
                    block.count[k],
                );
            }
            pixels.extend(&shifted)
        })?;
        let slice = pixels.as_slice();
        for (m, &method) in methods.iter().enumerate() {
            let weights = if slice.is_empty() {
                vec![f64::NAN; range.len()]
            } else {
                let params = BalanceParams {
                    scope: Scope::Cis,
                    ..BalanceParams::for_method(method)
                };
                let result = balance(&pixels, &params)?;
                if !result.converged {
                    unconverged.push(Unconverged {
                        method,
                        resolution,
                        chrom: chrom.name.clone(),
                    });
                }
                result.weights
            };
            // The divisive vector as stored (float32), and the expected of the counts a reader
            // normalises with it.
            let divisive: Vec<f64> = weights
                .iter()
                .map(|&w| f64::from(invert_weight(w) as f32))
                .collect();
            per_method[m].add_chrom_pixels(chrom_id, slice, Some(&divisive));
            vectors.push(HicNormVector {
                name: method.juicer_name().into(),
                chrom: chrom_id,
                resolution,
                values: divisive,
            });
        }
    }
    Ok(LevelVectors {
        normalized: methods
            .iter()
            .zip(&per_method)
            .map(|(&m, builder)| (m.juicer_name().to_string(), builder.finish()))
            .collect(),
        vectors,
        unconverged,
    })
}
