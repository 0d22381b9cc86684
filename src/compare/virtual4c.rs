//! A viewpoint's contacts with the rest of the genome (virtual 4C), as cooltools 0.7.1
//! `virtual4c` computes them: for every bin `b`, the mean over the viewpoint's bins `v` of the
//! stored pixels `(b, v)` of the symmetric map (balanced `count * w_b * w_v`, or raw counts),
//! pixels absent from the file left out of the mean and NaN values skipped; NaN where no such
//! pixel exists, and NaN for the bins lying wholly inside the viewpoint.

use std::ops::Range;

use crate::error::Result;
use crate::genome::{BinTable, Region};
use crate::io::MatrixReader;

/// The virtual 4C profile of `reader`'s map at the viewpoint `viewpoint` (bins), balanced by
/// `weights` when given; one value per bin of the map. `inside` are the bins wholly inside the
/// viewpoint region (NaN in the profile).
///
/// # Examples
///
/// ```
/// use contactmap::compare::virtual4c::virtual4c;
/// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
///
/// let reader = open_matrix("data/CN.mm9.10000kb.cool", &OpenOptions::default())?;
/// let viewpoint = reader.bins().parse_region_bins("chr1:50,000,000-60,000,000")?;
/// let profile = virtual4c(reader.as_ref(), viewpoint.clone(), viewpoint.clone(), None)?;
/// assert_eq!(profile.len(), reader.bins().n_bins());
/// assert!(profile[viewpoint.start].is_nan());
/// assert!(profile[viewpoint.start + 1] > profile[viewpoint.start + 5]);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn virtual4c(
    reader: &dyn MatrixReader,
    viewpoint: Range<usize>,
    inside: Range<usize>,
    weights: Option<&[f64]>,
) -> Result<Vec<f64>> {
    let n = reader.bins().n_bins();
    let (mut sum, mut count) = (vec![0.0f64; n], vec![0u64; n]);
    let mut add = |b: usize, v: usize, c: f64| {
        let value = match weights {
            Some(w) => c * w[b] * w[v],
            None => c,
        };
        if !value.is_nan() {
            sum[b] += value;
            count[b] += 1;
        }
    };
    // Pixels (b, v) of the upper triangle (b <= v), then the lower triangle's (v, b), b > v,
    // read as the upper triangle's (v, b).
    reader.read_pixels(0..n, viewpoint.clone(), &mut |block| {
        for k in 0..block.len() {
            add(
                block.bin1[k] as usize,
                block.bin2[k] as usize,
                block.count[k],
            );
        }
        Ok(())
    })?;
    reader.read_pixels(viewpoint.clone(), 0..n, &mut |block| {
        for k in 0..block.len() {
            let (v, b) = (block.bin1[k] as usize, block.bin2[k] as usize);
            if b > v {
                add(b, v, block.count[k]);
            }
        }
        Ok(())
    })?;
    Ok((0..n)
        .map(|b| {
            if count[b] == 0 || inside.contains(&b) {
                f64::NAN
            } else {
                sum[b] / count[b] as f64
            }
        })
        .collect())
}

/// The bins of a viewpoint `region`: those it overlaps (cooler's fetch), and among them those
/// lying wholly inside it (cooltools sets these to NaN); a region naming a whole chromosome
/// covers it whole. An error for a region outside the bin table.
pub fn viewpoint_bins(bins: &BinTable, region: &Region) -> Result<(Range<usize>, Range<usize>)> {
    let viewpoint = bins.region_bins(region)?;
    if viewpoint.is_empty() {
        return Ok((viewpoint.clone(), viewpoint));
    }
    let start = region.start.unwrap_or(bins.bin(viewpoint.start).start);
    let end = region.end.unwrap_or(bins.bin(viewpoint.end - 1).end);
    let inside = |k: &usize| {
        let bin = bins.bin(*k);
        bin.start >= start && bin.end <= end
    };
    let first = viewpoint.clone().find(inside);
    let last = viewpoint.clone().rev().find(inside);
    let inside = match (first, last) {
        (Some(a), Some(b)) => a..b + 1,
        _ => 0..0,
    };
    Ok((viewpoint, inside))
}
