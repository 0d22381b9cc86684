//! Several matrices on the same bins read as one: their pixels summed (replicates, simulation
//! replicas), streamed in bands of rows so that memory follows the band, not the files.

use std::ops::Range;

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

/// Sum two pixel lists sorted by `(bin1, bin2)` into one sorted list (a linear merge).
fn merge_two(a: &PixelBlock, b: &PixelBlock) -> PixelBlock {
    let mut out = PixelBlock::with_capacity(a.len() + b.len());
    let (mut x, mut y) = (0, 0);
    while x < a.len() && y < b.len() {
        let (ka, kb) = ((a.bin1[x], a.bin2[x]), (b.bin1[y], b.bin2[y]));
        if ka < kb {
            out.push(ka.0, ka.1, a.count[x]);
            x += 1;
        } else if kb < ka {
            out.push(kb.0, kb.1, b.count[y]);
            y += 1;
        } else {
            out.push(ka.0, ka.1, a.count[x] + b.count[y]);
            x += 1;
            y += 1;
        }
    }
    for k in x..a.len() {
        out.push(a.bin1[k], a.bin2[k], a.count[k]);
    }
    for k in y..b.len() {
        out.push(b.bin1[k], b.bin2[k], b.count[k]);
    }
    out
}

/// Sum the pixels of `parts` (each sorted by `(bin1, bin2)`) into one sorted list, the parts
/// added in their order (so that float sums do not depend on the threads).
fn sum_sorted(parts: Vec<PixelBlock>) -> PixelBlock {
    let mut parts = parts.into_iter();
    let first = parts.next().unwrap_or_default();
    parts.fold(first, |sum, part| merge_two(&sum, &part))
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
            // the inputs read side by side, each on its own thread (not rayon's: a reader may
            // hold a lock while it waits on rayon's pool)
            let read = |reader: &&dyn MatrixReader| -> Result<PixelBlock> {
                let mut part = PixelBlock::default();
                reader.read_pixels(start..end, cols.clone(), &mut |block| {
                    part.bin1.extend_from_slice(&block.bin1);
                    part.bin2.extend_from_slice(&block.bin2);
                    part.count.extend_from_slice(&block.count);
                    Ok(())
                })?;
                Ok(part)
            };
            let parts: Vec<PixelBlock> = std::thread::scope(|scope| {
                let handles: Vec<_> = self
                    .readers
                    .iter()
                    .map(|reader| scope.spawn(move || read(reader)))
                    .collect();
                handles
                    .into_iter()
                    .map(|handle| handle.join().expect("a reading thread panicked"))
                    .collect::<Result<_>>()
            })?;
            let gathered: usize = parts.iter().map(PixelBlock::len).sum();
            let summed = sum_sorted(parts);
            if summed.len() <= BLOCK_PIXELS {
                sink(&summed)?;
            } else {
                for first in (0..summed.len()).step_by(BLOCK_PIXELS) {
                    let last = (first + BLOCK_PIXELS).min(summed.len());
                    let block = PixelBlock {
                        bin1: summed.bin1[first..last].to_vec(),
                        bin2: summed.bin2[first..last].to_vec(),
                        count: summed.count[first..last].to_vec(),
                    };
                    sink(&block)?;
                }
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
        let block = |pixels: &[(u64, u64, f64)]| {
            let mut block = PixelBlock::default();
            for &(i, j, c) in pixels {
                block.push(i, j, c);
            }
            block
        };
        let a = block(&[(0, 0, 1.0), (0, 3, 2.0), (2, 2, 5.0)]);
        let b = block(&[(0, 1, 1.0), (0, 3, 4.0), (1, 1, 1.0)]);
        let c = block(&[(1, 1, 2.0), (3, 4, 1.0)]);
        assert_eq!(
            sum_sorted(vec![a, b, c]),
            block(&[
                (0, 0, 1.0),
                (0, 1, 1.0),
                (0, 3, 6.0),
                (1, 1, 3.0),
                (2, 2, 5.0),
                (3, 4, 1.0)
            ])
        );
    }
}
