//! The pixels of a cooler: in range, upper triangle when stored so, sorted, unique, finite.

use super::check::CoolerCheck;
use super::coarsening::PixelSummary;
use super::columns::PixelColumns;
use crate::error::Result;
use crate::io::cool::BLOCK_PIXELS;
use crate::validate::report::{Class, Collector};

impl CoolerCheck<'_> {
    pub(crate) fn check_pixels(
        &self,
        out: &mut Collector,
        pixels: &PixelColumns,
        n_bins: usize,
        bin1_offsets: Option<&[i64]>,
        symmetric_upper: bool,
    ) -> Result<PixelSummary> {
        let nnz = pixels.len();
        let n = n_bins as i64;
        let mut summary = PixelSummary {
            sum: 0.0,
            clean: true,
        };
        let mut last: Option<(i64, i64)> = None;
        // Row of the pixel according to bin1_offset.
        let mut row = 0usize;
        let mut lo = 0;
        while lo < nnz {
            let hi = (lo + BLOCK_PIXELS).min(nnz);
            let (bin1, bin2, count) = pixels.read(self.raw, lo, hi)?;
            for k in 0..bin1.len() {
                let index = lo + k;
                let (i, j, c) = (bin1[k], bin2[k], count[k]);
                let at = || format!("pixels row {index}");
                if !c.is_finite() || c < 0.0 {
                    out.add(self.name, Class::Count, || {
                        (
                            at(),
                            format!("pixel ({i}, {j}) has count {c}; expected finite and >= 0"),
                        )
                    });
                } else {
                    summary.sum += c;
                }
                if i < 0 || j < 0 || i >= n || j >= n {
                    summary.clean = false;
                    out.add(self.name, Class::BinId, || {
                        (
                            at(),
                            format!("pixel ({i}, {j}) is out of range for {n_bins} bins"),
                        )
                    });
                    continue;
                }
                if symmetric_upper && i > j {
                    summary.clean = false;
                    out.add(self.name, Class::LowerTriangle, || {
                        (
                            at(),
                            format!(
                                "pixel ({i}, {j}) is below the diagonal in symmetric-upper storage"
                            ),
                        )
                    });
                }
                if let Some(previous) = last {
                    if (i, j) < previous {
                        summary.clean = false;
                        out.add(self.name, Class::Unsorted, || {
                            (at(), format!("pixel ({i}, {j}) follows ({}, {}): pixels must be sorted by (bin1_id, bin2_id)", previous.0, previous.1))
                        });
                    } else if (i, j) == previous {
                        summary.clean = false;
                        out.add(self.name, Class::Duplicate, || {
                            (
                                at(),
                                format!(
                                    "pixel ({i}, {j}) is stored twice (rows {} and {index})",
                                    index - 1
                                ),
                            )
                        });
                    }
                }
                last = Some((i, j));
                if let Some(offsets) = bin1_offsets {
                    while row < n_bins && offsets[row + 1] as usize <= index {
                        row += 1;
                    }
                    if i as usize != row {
                        out.add(self.name, Class::Bin1Offset, || {
                            (at(), format!("pixel ({i}, {j}) is in the rows of bin {row} according to indexes/bin1_offset"))
                        });
                    }
                }
            }
            lo = hi;
        }
        Ok(summary)
    }
}
