//! Several matrices on the same bins read as one: their pixels summed (replicates, simulation
//! replicas), streamed in bands of rows so that memory follows the band, not the files.

use std::ops::Range;

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::io::matrices::reader::{MatrixInfo, MatrixReader};
use crate::matrix::{CountType, PixelBlock, Weights};

/// Pixels gathered from all inputs per band, aimed at (the band grows or shrinks to it).
const BAND_PIXELS: usize = 1 << 21;
/// Pixels per block handed to the sink.
const BLOCK_PIXELS: usize = 1 << 20;

/// The sum of several matrices on identical bins.
pub struct MergedReader<'a> {
    readers: Vec<&'a dyn MatrixReader>,
    source: String,
}

impl<'a> MergedReader<'a> {
    /// Merge `readers`; fails when one has other chromosomes or other bins than the first.
    pub fn new(readers: Vec<&'a dyn MatrixReader>) -> Result<Self> {
        let Some(first) = readers.first() else {
            return Err(Error::Argument("nothing to merge: no input".into()));
        };
        for other in &readers[1..] {
            if let Some(why) = first.bins().difference(other.bins()) {
                return Err(Error::format(
                    other.source(),
                    format!(
                        "its bins differ from those of {} ({why}): merged maps must have the same chromosomes and bins",
                        first.source()
                    ),
                ));
            }
        }
        let source = format!(
            "the sum of {}",
            readers
                .iter()
                .map(|r| r.source())
                .collect::<Vec<_>>()
                .join(", ")
        );
        Ok(MergedReader { readers, source })
    }
}

/// Sum the pixels of `parts` (each sorted by `(bin1, bin2)`) into one sorted list.
fn sum_sorted(parts: Vec<Vec<(u64, u64, f64)>>) -> Vec<(u64, u64, f64)> {
    let mut all: Vec<(u64, u64, f64)> = parts.into_iter().flatten().collect();
    all.par_sort_by_key(|&(i, j, _)| (i, j));
    let mut out: Vec<(u64, u64, f64)> = Vec::with_capacity(all.len());
    for (i, j, c) in all {
        match out.last_mut() {
            Some(last) if last.0 == i && last.1 == j => last.2 += c,
            _ => out.push((i, j, c)),
        }
    }
    out
}

impl MatrixReader for MergedReader<'_> {
    fn source(&self) -> &str {
        &self.source
    }

    fn bins(&self) -> &BinTable {
        self.readers[0].bins()
    }

    fn count_type(&self) -> CountType {
        if self
            .readers
            .iter()
            .all(|r| r.count_type() == CountType::Integer)
        {
            CountType::Integer
        } else {
            CountType::Float
        }
    }

    fn weight_names(&self) -> Vec<String> {
        Vec::new()
    }

    fn weights(&self, name: &str) -> Result<Weights> {
        Err(Error::Argument(format!(
            "{}: a merged map has no weight column '{name}' (balance the merged file)",
            self.source
        )))
    }

    fn info(&self) -> MatrixInfo {
        MatrixInfo {
            format: "merged".into(),
            attributes: Vec::new(),
            resolutions: self.bins().resolution().into_iter().collect(),
            notes: Vec::new(),
        }
    }

    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        let mut band = 1024usize.min(rows.len().max(1));
        let mut start = rows.start;
        while start < rows.end {
            let end = (start + band).min(rows.end);
            let mut parts = Vec::with_capacity(self.readers.len());
            for reader in &self.readers {
                let mut part = Vec::new();
                reader.read_pixels(start..end, cols.clone(), &mut |block| {
                    part.extend(
                        block
                            .bin1
                            .iter()
                            .zip(&block.bin2)
                            .zip(&block.count)
                            .map(|((&i, &j), &c)| (i, j, c)),
                    );
                    Ok(())
                })?;
                parts.push(part);
            }
            let gathered: usize = parts.iter().map(Vec::len).sum();
            let summed = sum_sorted(parts);
            for chunk in summed.chunks(BLOCK_PIXELS) {
                let mut block = PixelBlock::with_capacity(chunk.len());
                for &(i, j, c) in chunk {
                    block.bin1.push(i);
                    block.bin2.push(j);
                    block.count.push(c);
                }
                sink(&block)?;
            }
            // Aim the next band at BAND_PIXELS gathered pixels.
            let per_row = gathered as f64 / (end - start) as f64;
            band = if per_row > 0.0 {
                ((BAND_PIXELS as f64 / per_row) as usize).clamp(1, 1 << 20)
            } else {
                band.saturating_mul(4).min(1 << 20)
            };
            start = end;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_pixels_are_summed_in_order() {
        let a = vec![(0, 0, 1.0), (0, 3, 2.0), (2, 2, 5.0)];
        let b = vec![(0, 1, 1.0), (0, 3, 4.0), (1, 1, 1.0)];
        assert_eq!(
            sum_sorted(vec![a, b]),
            vec![
                (0, 0, 1.0),
                (0, 1, 1.0),
                (0, 3, 6.0),
                (1, 1, 1.0),
                (2, 2, 5.0)
            ]
        );
    }
}
