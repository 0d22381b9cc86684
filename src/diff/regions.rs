//! Structural similarity of regions between two maps, as CHESS (Galan et al. 2020, *Nature
//! Genetics* 52:1247; chess-hic 0.3.8, `chess sim`) computes it: each region's
//! observed/expected sub-matrix in the reference and in the query, compared by the structural
//! similarity index (SSIM) over a window as large as the matrix, the signal-to-noise of their
//! difference, and each SSIM's z-score against all the pairs compared.
//!
//! Every convention is CHESS's, so that the numbers equal chess-hic 0.3.8's on the same maps and
//! pairs (`data/diff/chess/`, docs/diff.md):
//!
//! - observed/expected as FAN-C computes it for CHESS: balanced counts (a NaN weight reads as 0;
//!   without weights, raw counts), divided by the chromosome's mean at that diagonal over every
//!   pair of bins at that distance that both have a stored pixel anywhere in the map (trans
//!   included), the main diagonal included, nothing smoothed;
//! - a region takes every bin it overlaps; in its matrix a pixel not stored reads 1, a pixel of a
//!   bin without weight 0;
//! - fewer than 20 bins gives no answer; rows whose every value is 1 (no stored pixel inside the
//!   region) are masked: more than 10% of them in either map gives no answer, else the rows
//!   masked in either map are removed from both;
//! - SSIM with a uniform window of the matrix's size (one less when even), sample covariances,
//!   `C₁ = (0.01 R)²`, `C₂ = (0.03 R)²`, `R` the range of both matrices, averaged over the
//!   window's positions inside the matrix; a query region on the other strand is reversed;
//! - SN: the mean over cells of `|mean| / variance` of the difference in the 7 x 7 block around
//!   each cell (cut at the edges, NaN cells left out);
//! - `z_ssim` against the mean and population standard deviation of every finite SSIM.

use crate::error::{Error, Result};
use crate::io::MatrixReader;

/// One pair of regions to compare: a region of the reference map and one of the query map.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionPair {
    /// The pair's name (CHESS's ID column).
    pub id: String,
    /// The reference's region: chromosome id, start and end in bp (half-open).
    pub reference: (usize, u64, u64),
    /// The query's region.
    pub query: (usize, u64, u64),
    /// The regions lie on different strands: the query's matrix is reversed.
    pub reversed: bool,
}

/// Settings of [`compare_regions`], CHESS's defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionParams {
    /// Regions of fewer bins get no answer (20).
    pub min_bins: usize,
    /// Largest fraction of masked rows (0.1).
    pub mappability_cutoff: f64,
    /// The SSIM window as a fraction of the matrix's size (1).
    pub relative_window: f64,
    /// The SSIM window in bins, instead of `relative_window`.
    pub absolute_window: Option<usize>,
}

impl Default for RegionParams {
    fn default() -> Self {
        RegionParams {
            min_bins: 20,
            mappability_cutoff: 0.1,
            relative_window: 1.0,
            absolute_window: None,
        }
    }
}

/// The answer for every pair, in order (NaN where there is none).
#[derive(Debug, Clone, PartialEq)]
pub struct RegionSimilarity {
    /// Structural similarity of the two observed/expected matrices.
    pub ssim: Vec<f64>,
    /// CHESS's signal-to-noise of their difference.
    pub signal_to_noise: Vec<f64>,
    /// `(ssim - mean) / sd` over every finite `ssim` (population sd).
    pub z_ssim: Vec<f64>,
}

/// A map's observed/expected as FAN-C computes it for CHESS: the expected per chromosome and
/// diagonal, and the bias of each bin.
#[derive(Clone)]
pub struct ObservedOverExpected<'a> {
    reader: &'a dyn MatrixReader,
    /// Each bin's bias: its weight (0 when NaN), or 1 without weights.
    bias: Vec<f64>,
    /// Per chromosome, the expected at each diagonal up to the largest needed.
    expected: Vec<Vec<f64>>,
}

impl<'a> ObservedOverExpected<'a> {
    /// The expected of `reader` balanced by `weights` (raw counts when `None`) at every diagonal
    /// below `max_diagonal`, in one pass over the map.
    pub fn new(
        reader: &'a dyn MatrixReader,
        weights: Option<&[f64]>,
        max_diagonal: usize,
    ) -> Result<Self> {
        let bins = reader.bins();
        let n = bins.n_bins();
        let bias: Vec<f64> = match weights {
            Some(w) => w
                .iter()
                .map(|&v| if v.is_finite() { v } else { 0.0 })
                .collect(),
            None => vec![1.0; n],
        };
        let n_chroms = bins.n_chroms();
        let mut sums: Vec<Vec<f64>> = (0..n_chroms)
            .map(|c| vec![0.0; bins.chrom_bins(c).len().min(max_diagonal)])
            .collect();
        let mut mappable = vec![false; n];
        reader.read_pixels(0..n, 0..n, &mut |block| {
            for k in 0..block.len() {
                let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                mappable[i] = true;
                mappable[j] = true;
                let chrom = bins.chrom_of(i);
                if chrom != bins.chrom_of(j) || j - i >= max_diagonal {
                    continue;
                }
                let product = bias[i] * bias[j];
                sums[chrom][j - i] += block.count[k] * product;
            }
            Ok(())
        })?;
        let expected = sums
            .into_iter()
            .enumerate()
            .map(|(c, sum)| {
                let range = bins.chrom_bins(c);
                let flags = &mappable[range];
                sum.iter()
                    .enumerate()
                    .map(|(d, s)| {
                        let possible = (0..flags.len() - d)
                            .filter(|&k| flags[k] && flags[k + d])
                            .count();
                        if possible > 0 {
                            s / possible as f64
                        } else {
                            0.0
                        }
                    })
                    .collect()
            })
            .collect();
        Ok(ObservedOverExpected {
            reader,
            bias,
            expected,
        })
    }

    /// The dense observed/expected matrix of bins `lo..hi` (one chromosome), 1 where no pixel
    /// is stored.
    pub fn matrix(&self, lo: usize, hi: usize) -> Result<Vec<Vec<f64>>> {
        let n = hi - lo;
        let mut m = vec![vec![1.0; n]; n];
        let bins = self.reader.bins();
        let expected = &self.expected[bins.chrom_of(lo)];
        self.reader.read_pixels(lo..hi, lo..hi, &mut |block| {
            for k in 0..block.len() {
                let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                let product = self.bias[i] * self.bias[j];
                let value = block.count[k] * product / expected[j - i];
                m[i - lo][j - lo] = value;
                m[j - lo][i - lo] = value;
            }
            Ok(())
        })?;
        Ok(m)
    }
}

/// The bins `lo..hi` a region of `chrom` from `start` to `end` bp overlaps (CHESS takes every
/// bin it touches); `None` when it overlaps none.
fn region_bins(
    reader: &dyn MatrixReader,
    (chrom, start, end): (usize, u64, u64),
) -> Option<(usize, usize)> {
    let bins = reader.bins();
    let range = bins.chrom_bins(chrom);
    let overlapping: Vec<usize> = range
        .filter(|&b| {
            let bin = bins.bin(b);
            bin.start < end && bin.end > start
        })
        .collect();
    Some((*overlapping.first()?, *overlapping.last()? + 1))
}

/// Compare every pair of regions of `reference` and `query` (balanced by their weights, or raw
/// counts where `None`), as `chess sim` does.
pub fn compare_regions(
    reference: &dyn MatrixReader,
    reference_weights: Option<&[f64]>,
    query: &dyn MatrixReader,
    query_weights: Option<&[f64]>,
    pairs: &[RegionPair],
    params: &RegionParams,
) -> Result<RegionSimilarity> {
    let mut windows = Vec::with_capacity(pairs.len());
    let mut largest = 1;
    for pair in pairs {
        let bins = (
            region_bins(reference, pair.reference),
            region_bins(query, pair.query),
        );
        if let (Some((a, b)), Some((c, d))) = bins {
            largest = largest.max(b - a).max(d - c);
        }
        windows.push(bins);
    }
    let reference_oe = ObservedOverExpected::new(reference, reference_weights, largest)?;
    let query_oe = ObservedOverExpected::new(query, query_weights, largest)?;
    let mut ssim = vec![f64::NAN; pairs.len()];
    let mut signal_to_noise = vec![f64::NAN; pairs.len()];
    for (p, pair) in pairs.iter().enumerate() {
        let (Some((a, b)), Some((c, d))) = windows[p] else {
            continue;
        };
        let x = reference_oe.matrix(a, b)?;
        let y = query_oe.matrix(c, d)?;
        if let Some((s, sn)) = compare_matrices(x, y, pair.reversed, params) {
            ssim[p] = s;
            signal_to_noise[p] = sn;
        }
    }
    let finite: Vec<f64> = ssim.iter().copied().filter(|v| !v.is_nan()).collect();
    let mean = finite.iter().sum::<f64>() / finite.len() as f64;
    let sd = (finite.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / finite.len() as f64).sqrt();
    let z_ssim = ssim.iter().map(|s| (s - mean) / sd).collect();
    Ok(RegionSimilarity {
        ssim,
        signal_to_noise,
        z_ssim,
    })
}

/// CHESS's comparison of two observed/expected matrices: `(ssim, SN)`, or `None` where it
/// gives no answer (too small, too many masked rows).
pub fn compare_matrices(
    reference: Vec<Vec<f64>>,
    query: Vec<Vec<f64>>,
    reversed: bool,
    params: &RegionParams,
) -> Option<(f64, f64)> {
    let (mut x, mut y) = (reference, query);
    if x.len() < params.min_bins || y.len() < params.min_bins {
        return None;
    }
    if x.len() < y.len() {
        x = resize_nearest(&x, y.len());
    } else if y.len() < x.len() {
        y = resize_nearest(&y, x.len());
    }
    if reversed {
        y.reverse();
        for row in &mut y {
            row.reverse();
        }
    }
    let n = x.len();
    let masked = |m: &[Vec<f64>]| -> Vec<usize> {
        (0..n)
            .filter(|&col| m.iter().map(|row| row[col]).sum::<f64>() == n as f64)
            .collect()
    };
    let (masked_x, masked_y) = (masked(&x), masked(&y));
    let cutoff = params.mappability_cutoff;
    if masked_x.len() as f64 / n as f64 > cutoff || masked_y.len() as f64 / n as f64 > cutoff {
        return None;
    }
    let kept: Vec<usize> = (0..n)
        .filter(|k| !masked_x.contains(k) && !masked_y.contains(k))
        .collect();
    let keep = |m: &[Vec<f64>]| -> Vec<Vec<f64>> {
        kept.iter()
            .map(|&i| kept.iter().map(|&j| m[i][j]).collect())
            .collect()
    };
    let (x, y) = (keep(&x), keep(&y));
    let n = kept.len();
    let mut window = match params.absolute_window {
        Some(w) if w > 0 => w,
        _ => (n as f64 * params.relative_window) as usize,
    };
    if window % 2 == 0 {
        window = window.saturating_sub(1);
    }
    let window = window.max(3);
    if window > n {
        return None;
    }
    Some((ssim(&x, &y, window), signal_to_noise(&x, &y)))
}

/// scikit-image's nearest-neighbour `resize` (order 0) of a square matrix to `n` x `n`: output
/// index `o` takes input `⌊(o + ½) n_in / n⌋`.
fn resize_nearest(m: &[Vec<f64>], n: usize) -> Vec<Vec<f64>> {
    let n_in = m.len();
    let source = |o: usize| (((o as f64 + 0.5) * n_in as f64 / n as f64) as usize).min(n_in - 1);
    (0..n)
        .map(|i| (0..n).map(|j| m[source(i)][source(j)]).collect())
        .collect()
}

/// The mean SSIM over every position of a `w` x `w` uniform window inside both matrices
/// (scikit-image's `structural_similarity` with `data_range` the range of both, sample
/// covariances, K₁ 0.01, K₂ 0.03). NaN anywhere gives NaN.
pub fn ssim(x: &[Vec<f64>], y: &[Vec<f64>], w: usize) -> f64 {
    let n = x.len();
    let extreme = |f: fn(f64, f64) -> f64, start: f64| {
        x.iter().chain(y).flatten().fold(start, |acc, &v| {
            if v.is_nan() || acc.is_nan() {
                f64::NAN
            } else {
                f(acc, v)
            }
        })
    };
    let range = extreme(f64::max, f64::NEG_INFINITY) - extreme(f64::min, f64::INFINITY);
    let (c1, c2) = ((0.01 * range).powi(2), (0.03 * range).powi(2));
    let np = (w * w) as f64;
    let cov_norm = np / (np - 1.0);
    let mut total = 0.0;
    let mut count = 0usize;
    for i in 0..=n - w {
        for j in 0..=n - w {
            let (mut sx, mut sy, mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for a in i..i + w {
                for b in j..j + w {
                    let (u, v) = (x[a][b], y[a][b]);
                    sx += u;
                    sy += v;
                    sxx += u * u;
                    syy += v * v;
                    sxy += u * v;
                }
            }
            let (ux, uy) = (sx / np, sy / np);
            let vx = cov_norm * (sxx / np - ux * ux);
            let vy = cov_norm * (syy / np - uy * uy);
            let vxy = cov_norm * (sxy / np - ux * uy);
            let s = ((2.0 * ux * uy + c1) * (2.0 * vxy + c2))
                / ((ux * ux + uy * uy + c1) * (vx + vy + c2));
            total += s;
            count += 1;
        }
    }
    total / count as f64
}

/// CHESS's signal-to-noise of `x - y`: over every cell, `|mean| / variance` (population) of the
/// difference in the 7 x 7 block centred on it (cut at the edges; NaN cells left out), averaged
/// over the cells where it is a number (NaN when none is).
pub fn signal_to_noise(x: &[Vec<f64>], y: &[Vec<f64>]) -> f64 {
    let n = x.len();
    let half = 3usize;
    let difference: Vec<Vec<f64>> = x
        .iter()
        .zip(y)
        .map(|(a, b)| a.iter().zip(b).map(|(u, v)| u - v).collect())
        .collect();
    let (mut total, mut count) = (0.0, 0usize);
    for i in 0..n {
        for j in 0..n {
            let mut values = Vec::with_capacity(49);
            for row in difference
                .iter()
                .take((i + half + 1).min(n))
                .skip(i.saturating_sub(half))
            {
                for &v in row
                    .iter()
                    .take((j + half + 1).min(n))
                    .skip(j.saturating_sub(half))
                {
                    if !v.is_nan() {
                        values.push(v);
                    }
                }
            }
            if values.is_empty() {
                continue;
            }
            let m = values.len() as f64;
            let mean = values.iter().sum::<f64>() / m;
            let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / m;
            let ratio = mean.abs() / variance;
            if !ratio.is_nan() {
                total += ratio;
                count += 1;
            }
        }
    }
    if count == 0 {
        f64::NAN
    } else {
        total / count as f64
    }
}

/// CHESS's pairs of regions from BEDPE records: `chrom1 start1 end1` the reference's region,
/// `chrom2 start2 end2` the query's, then the pair's ID (the record's number when absent), a
/// score (ignored) and the two strands (`+` when absent). A chromosome the maps lack is refused
/// with `source` and the record's line.
pub fn pairs_of(
    reference: &dyn MatrixReader,
    query: &dyn MatrixReader,
    records: &[crate::io::bed::BedpeRecord],
    source: &str,
) -> Result<Vec<RegionPair>> {
    let locate = |reader: &dyn MatrixReader, record: &crate::io::bed::BedRecord, line: u64| {
        let bins = reader.bins();
        let chrom = bins.chrom_id(&record.chrom).ok_or_else(|| {
            Error::Data(format!(
                "{source}, line {line}: {}",
                bins.missing_chrom(&record.chrom)
            ))
        })?;
        let span = bins.span(chrom);
        if record.end <= record.start || record.start < span.start || record.end > span.end {
            return Err(Error::Data(format!(
                "{source}, line {line}: region {}:{}-{} is not within {} (0-{})",
                record.chrom, record.start, record.end, record.chrom, span.end
            )));
        }
        Ok((chrom, record.start, record.end))
    };
    records
        .iter()
        .enumerate()
        .map(|(k, record)| {
            let strand = |i: usize| record.rest.get(i).map_or("+", String::as_str);
            Ok(RegionPair {
                id: record
                    .rest
                    .first()
                    .cloned()
                    .unwrap_or_else(|| k.to_string()),
                reference: locate(reference, &record.first, record.line)?,
                query: locate(query, &record.second, record.line)?,
                reversed: strand(2) != strand(3),
            })
        })
        .collect()
}

/// CHESS's `chess pairs`: windows of `window_bp` every `step_bp` along each chromosome (those
/// shorter than the window have none), the same region in both maps, IDs from 0.
pub fn sliding_pairs(
    bins: &crate::genome::BinTable,
    window_bp: u64,
    step_bp: u64,
) -> Vec<RegionPair> {
    let mut pairs = Vec::new();
    for chrom in 0..bins.n_chroms() {
        let size = bins.span(chrom).end;
        let mut start = 0;
        while start + window_bp <= size {
            let region = (chrom, start, start + window_bp);
            pairs.push(RegionPair {
                id: pairs.len().to_string(),
                reference: region,
                query: region,
                reversed: false,
            });
            start += step_bp;
        }
    }
    pairs
}

/// The comparison as CHESS writes it, `ID SN ssim z_ssim` (numbers as Python's `repr`
/// writes them: shortest round trip, `nan`, `inf`), then the regions `chrom1 start1 end1 chrom2
/// start2 end2`; tab-separated with a header line.
pub fn regions_tsv(
    bins: &crate::genome::BinTable,
    pairs: &[RegionPair],
    similarity: &RegionSimilarity,
) -> String {
    let repr = |v: f64| {
        if v.is_nan() {
            "nan".to_string()
        } else if v.is_infinite() {
            if v > 0.0 { "inf" } else { "-inf" }.to_string()
        } else {
            format!("{v:?}")
        }
    };
    let region = |(chrom, start, end): (usize, u64, u64)| {
        format!("{}\t{start}\t{end}", bins.chroms()[chrom].name)
    };
    let mut out =
        String::from("ID\tSN\tssim\tz_ssim\tchrom1\tstart1\tend1\tchrom2\tstart2\tend2\n");
    for (p, pair) in pairs.iter().enumerate() {
        out.push_str(&format!(
            "{}\t{}\t{}\t{}\t{}\t{}\n",
            pair.id,
            repr(similarity.signal_to_noise[p]),
            repr(similarity.ssim[p]),
            repr(similarity.z_ssim[p]),
            region(pair.reference),
            region(pair.query)
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::bed::read_bedpe;
    use crate::io::{InMemory, OpenOptions, open_matrix, open_text};
    use crate::matrix::{CountType, MatrixBuilder};
    use std::io::Read;

    /// The query of a case: the reference's pixels changed by the case's rules (chess.json:
    /// multiply, ceil_div, drop_bins, nan_weight), as scripts/chess_references.py made it.
    fn query_of(
        reference: &dyn MatrixReader,
        weights: Option<&[f64]>,
        rules: &[serde_json::Value],
    ) -> (InMemory, Option<Vec<f64>>) {
        let range = |v: &serde_json::Value| {
            let r: Vec<usize> = serde_json::from_value(v.clone()).unwrap();
            r[0]..r[1]
        };
        let n = reference.bins().n_bins();
        let mut pixels = Vec::new();
        reference
            .read_pixels(0..n, 0..n, &mut |block| {
                for k in 0..block.len() {
                    pixels.push((
                        block.bin1[k] as usize,
                        block.bin2[k] as usize,
                        block.count[k],
                    ));
                }
                Ok(())
            })
            .unwrap();
        let mut weights = weights.map(<[f64]>::to_vec);
        for rule in rules {
            let op = rule["op"].as_str().unwrap();
            match op {
                "multiply" | "ceil_div" => {
                    let (rows, cols) = (range(&rule["bin1"]), range(&rule["bin2"]));
                    for (i, j, count) in &mut pixels {
                        if rows.contains(i) && cols.contains(j) {
                            *count = if op == "multiply" {
                                *count * rule["factor"].as_f64().unwrap()
                            } else {
                                let q = rule["divisor"].as_f64().unwrap();
                                ((*count + q - 1.0) / q).floor()
                            };
                        }
                    }
                }
                "drop_bins" | "nan_weight" => {
                    let dropped: Vec<usize> = serde_json::from_value(rule["bins"].clone()).unwrap();
                    if op == "drop_bins" {
                        pixels.retain(|(i, j, _)| !dropped.contains(i) && !dropped.contains(j));
                    } else if let Some(w) = &mut weights {
                        for &b in &dropped {
                            w[b] = f64::NAN;
                        }
                    }
                }
                other => panic!("rule {other}"),
            }
        }
        let mut builder = MatrixBuilder::new(reference.bins().clone(), CountType::Integer);
        for (i, j, count) in pixels {
            builder.push(i as u64, j as u64, count).unwrap();
        }
        (InMemory::new("query".into(), builder.build()), weights)
    }

    fn close(ours: f64, theirs: f64) -> bool {
        (ours.is_nan() && theirs.is_nan())
            || ours == theirs
            || (ours - theirs).abs() <= 1e-9 * theirs.abs().max(1e-300)
    }

    /// A gzipped table's rows after its header, split at tabs.
    fn table(path: &str) -> Vec<Vec<String>> {
        let mut text = String::new();
        open_text(std::path::Path::new(path))
            .unwrap()
            .read_to_string(&mut text)
            .unwrap();
        text.lines()
            .skip(1)
            .map(|l| l.split('\t').map(str::to_string).collect())
            .collect()
    }

    /// The rows of one case (the first column), without it.
    fn of_case(rows: &[Vec<String>], name: &str) -> Vec<Vec<String>> {
        rows.iter()
            .filter(|r| r[0] == name)
            .map(|r| r[1..].to_vec())
            .collect()
    }

    /// `chess sim` 0.3.8 on four cases (data/diff/chess/, scripts/chess_references.py): every
    /// SN, ssim and z_ssim to 1e-9 relative, NaN where chess gives NaN; the pairs are those
    /// `chess pairs` made.
    #[test]
    fn regions_equal_chess() {
        let mut text = String::new();
        open_text(std::path::Path::new("data/diff/chess/chess.json"))
            .unwrap()
            .read_to_string(&mut text)
            .unwrap();
        let cases: serde_json::Value = serde_json::from_str(&text).unwrap();
        let pairs_table = table("data/diff/chess/pairs.tsv.gz");
        let chess_table = table("data/diff/chess/sim.tsv.gz");
        for case in cases["cases"].as_array().unwrap() {
            let name = case["name"].as_str().unwrap();
            let reference =
                open_matrix(case["reference"].as_str().unwrap(), &OpenOptions::default()).unwrap();
            let weights = reference
                .weight_names()
                .iter()
                .any(|n| n == "weight")
                .then(|| reference.weights("weight").unwrap().values);
            let (query, query_weights) = query_of(
                reference.as_ref(),
                weights.as_deref(),
                case["query_rules"].as_array().unwrap(),
            );
            let dir = std::env::temp_dir().join(format!("chess-{}-{name}", std::process::id()));
            std::fs::create_dir_all(&dir).unwrap();
            let pairs_path = dir.join("pairs.bedpe");
            let lines: String = of_case(&pairs_table, name)
                .iter()
                .map(|fields| fields.join("\t") + "\n")
                .collect();
            std::fs::write(&pairs_path, lines).unwrap();
            let records = read_bedpe(&pairs_path).unwrap();
            let source = pairs_path.display().to_string();
            let pairs = pairs_of(reference.as_ref(), &query, &records, &source).unwrap();
            std::fs::remove_dir_all(&dir).unwrap();

            let mut sliding = sliding_pairs(
                reference.bins(),
                case["window"].as_u64().unwrap(),
                case["step"].as_u64().unwrap(),
            );
            if let Some(chrom) = case["chromosome"].as_str() {
                let id = reference.bins().chrom_id(chrom).unwrap();
                sliding.retain(|p| p.reference.0 == id);
                for (k, pair) in sliding.iter_mut().enumerate() {
                    pair.id = k.to_string();
                }
            }
            assert_eq!(sliding, pairs, "{name}: chess pairs");

            let similarity = compare_regions(
                reference.as_ref(),
                weights.as_deref(),
                &query,
                query_weights.as_deref(),
                &pairs,
                &RegionParams::default(),
            )
            .unwrap();
            let rows: Vec<Vec<f64>> = of_case(&chess_table, name)
                .iter()
                .map(|fields| fields[1..].iter().map(|v| v.parse().unwrap()).collect())
                .collect();
            assert_eq!(rows.len(), pairs.len(), "{name}");
            for (p, row) in rows.iter().enumerate() {
                let ours = [
                    similarity.signal_to_noise[p],
                    similarity.ssim[p],
                    similarity.z_ssim[p],
                ];
                for (column, (a, b)) in ours.iter().zip(row).enumerate() {
                    assert!(close(*a, *b), "{name} pair {p} column {column}: {a} vs {b}");
                }
            }
        }
    }

    #[test]
    fn identical_matrices_are_similar_and_noiseless() {
        let m: Vec<Vec<f64>> = (0..21usize)
            .map(|i| {
                (0..21)
                    .map(|j| 1.0 / (1.0 + i.abs_diff(j) as f64))
                    .collect()
            })
            .collect();
        let (s, sn) = compare_matrices(m.clone(), m, false, &RegionParams::default()).unwrap();
        assert_eq!(s, 1.0);
        assert!(
            sn.is_nan(),
            "every block's variance is 0: no signal to noise"
        );
    }
}
