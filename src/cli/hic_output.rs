//! Writing a Juicer `.hic` (used by `convert`): the matrices at every resolution, then, read back
//! from the file being written, the normalisation vectors and expected values Juicer stores.
//!
//! Steps: [`HicWriter`] streams the input into blocks at every resolution while Juicer's raw
//! expected values of every resolution accumulate from the same stream, and closes the file with
//! a footer that has no normalisation yet. Each resolution is then read back one chromosome at a time
//! (its intra-chromosomal pixels only, on a bin table of that chromosome alone, so memory follows
//! the largest chromosome) and each normalisation asked
//! for (VC, VC_SQRT, KR, SCALE by default, with Juicer's parameters: `balance --method M
//! --cis-only`) is computed and its divisive vector kept (`1 / weight`, NaN for masked bins),
//! with the expected values of the normalised counts. The footer is then rewritten with all of
//! them. Every vector is stored, even for a chromosome where KR or SCALE did not converge, and
//! such chromosomes are reported on standard error.

use std::ops::Range;
use std::path::Path;
use std::sync::Mutex;

use crate::balance::{balance, BalanceParams, Method, Scope};
use crate::error::{Error, Result};
use crate::expected::juicer::{JuicerExpected, JuicerExpectedBuilder, MultiResolutionExpected};
use crate::genome::BinTable;
use crate::io::hic::{HicNormVector, HicReader, HicWriteOptions, HicWriter};
use crate::io::{self, MatrixReader};
use crate::matrix::pixels::Pixels;
use crate::matrix::{invert_weight, PixelBlock};

/// Juicer's name of a normalisation method.
pub fn juicer_name(method: Method) -> &'static str {
    match method {
        Method::Ice => "ICE",
        Method::Vc => "VC",
        Method::VcSqrt => "VC_SQRT",
        Method::Kr => "KR",
        Method::Scale => "SCALE",
    }
}

/// The normalisations a `.hic` gets by default (Juicer's set).
pub const DEFAULT_NORMALIZATIONS: [Method; 4] =
    [Method::Vc, Method::VcSqrt, Method::Kr, Method::Scale];

/// Parse `--normalizations`: names (case-insensitive: VC, VC_SQRT, KR, SCALE, ICE) or `none`.
pub fn parse_normalizations(items: &[String]) -> Result<Vec<Method>> {
    if items.is_empty() {
        return Ok(DEFAULT_NORMALIZATIONS.to_vec());
    }
    let mut methods = Vec::new();
    for item in items {
        let method = match item.trim().to_ascii_uppercase().replace('-', "_").as_str() {
            "NONE" => continue,
            "VC" => Method::Vc,
            "VC_SQRT" => Method::VcSqrt,
            "KR" => Method::Kr,
            "SCALE" => Method::Scale,
            "ICE" => Method::Ice,
            _ => {
                return Err(Error::Invalid(format!(
                    "--normalizations: '{item}' is not one of VC, VC_SQRT, KR, SCALE, ICE, none"
                )))
            }
        };
        if !methods.contains(&method) {
            methods.push(method);
        }
    }
    Ok(methods)
}

/// A chromosome whose balancing did not converge.
#[derive(Clone, Debug, PartialEq)]
struct Unconverged {
    method: Method,
    bin_size_bp: u64,
    chrom: String,
}

/// Write `reader` as a `.hic` at `path` (under a temporary name, renamed when complete) with
/// `resolutions` and the normalisations `methods`; once it is written, name on standard error the
/// chromosomes whose balancing did not converge (their vectors are stored anyway).
pub fn write_hic(
    reader: &dyn MatrixReader,
    path: &Path,
    resolutions: &[u64],
    methods: &[Method],
    options: &HicWriteOptions,
) -> Result<()> {
    // Juicer, hictk and our reader hold chromosome lengths in 32 bits; the expected values are
    // sized from them.
    if let Some(chrom) = reader
        .bins()
        .chroms()
        .iter()
        .find(|c| c.length_bp > u64::from(u32::MAX))
    {
        return Err(crate::Error::format(
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
            let tap = ExpectedTap {
                inner: reader,
                expected: Mutex::new(MultiResolutionExpected::new(
                    reader.bins(),
                    writer.resolutions(),
                )),
            };
            writer.write_matrices(&tap)?;
            let expected = tap
                .expected
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
    for u in &unconverged {
        eprintln!(
            "contactmap: WARNING: {} at {} bp: {} did not converge; its vector is stored as the \
             last iteration left it",
            juicer_name(u.method),
            u.bin_size_bp,
            u.chrom
        );
    }
    Ok(())
}

/// A reader that passes its pixels on and adds them to Juicer's raw expected values at every
/// resolution.
struct ExpectedTap<'a> {
    inner: &'a dyn MatrixReader,
    expected: Mutex<MultiResolutionExpected>,
}

impl MatrixReader for ExpectedTap<'_> {
    io::forward_reader_metadata!(inner);

    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.inner.read_pixels(rows, cols, &mut |block| {
            self.expected
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .add(block);
            sink(block)
        })
    }
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
                        bin_size_bp: resolution,
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
                name: juicer_name(method).into(),
                chrom: chrom_id,
                bin_size_bp: resolution,
                values: divisive,
            });
        }
    }
    Ok(LevelVectors {
        normalized: methods
            .iter()
            .zip(&per_method)
            .map(|(&m, builder)| (juicer_name(m).to_string(), builder.finish()))
            .collect(),
        vectors,
        unconverged,
    })
}
