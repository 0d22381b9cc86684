//! The indexes of a cooler: `indexes/chrom_offset` and `indexes/bin1_offset` against the bins
//! and the pixels.

use super::check::CoolerCheck;
use super::columns::PixelColumns;
use super::stored::Kind;
use crate::error::Result;
use crate::io::cool::chunks::Column;
use crate::validate::report::{Class, Collector};

impl CoolerCheck<'_> {
    pub(crate) fn check_chrom_offset(
        &self,
        out: &mut Collector,
        n_chroms: usize,
        chrom_ids: &[i64],
    ) -> Result<()> {
        let Some(offsets) = self.ints(out, "indexes/chrom_offset")? else {
            return Ok(());
        };
        if offsets.len() != n_chroms + 1 {
            self.add(
                out,
                Class::ChromOffset,
                "indexes/chrom_offset",
                format!(
                    "{} entries; expected {} (number of chromosomes + 1)",
                    offsets.len(),
                    n_chroms + 1
                ),
            );
            return Ok(());
        }
        for (c, &offset) in offsets.iter().enumerate() {
            // First bin of chromosome c: the number of bins of the chromosomes before it.
            let expected = chrom_ids.partition_point(|&id| id < c as i64) as i64;
            if offset != expected {
                self.add(
                    out,
                    Class::ChromOffset,
                    &format!("indexes/chrom_offset[{c}]"),
                    format!("{offset}; the bin table's chromosome {c} starts at bin {expected}"),
                );
            }
        }
        Ok(())
    }

    /// Check `indexes/bin1_offset` alone (length, monotone, ends); return it (with `nnz` appended
    /// to a legacy `nbins`-entry index) when it can be used to locate the pixels' rows.
    pub(crate) fn check_bin1_offset(
        &self,
        out: &mut Collector,
        n_bins: usize,
        nnz: usize,
    ) -> Result<Option<Vec<i64>>> {
        let Some(mut offsets) = self.ints(out, "indexes/bin1_offset")? else {
            return Ok(None);
        };
        if offsets.len() == n_bins && n_bins > 0 {
            self.add(
                out,
                Class::LegacyIndex,
                "indexes/bin1_offset",
                format!(
                    "{n_bins} entries, one per bin (hic2cool 0.3 - 0.4); the format says {} (number of bins + 1). cooler reads it; --repair writes the full index",
                    n_bins + 1
                ),
            );
            offsets.push(nnz as i64);
        } else if offsets.len() != n_bins + 1 {
            self.add(
                out,
                Class::Bin1Offset,
                "indexes/bin1_offset",
                format!(
                    "{} entries; expected {} (number of bins + 1)",
                    offsets.len(),
                    n_bins + 1
                ),
            );
            return Ok(None);
        }
        let mut usable = true;
        if offsets[0] != 0 {
            usable = false;
            self.add(
                out,
                Class::Bin1Offset,
                "indexes/bin1_offset[0]",
                format!("{}; expected 0", offsets[0]),
            );
        }
        if offsets[n_bins] != nnz as i64 {
            usable = false;
            self.add(
                out,
                Class::Bin1Offset,
                &format!("indexes/bin1_offset[{n_bins}]"),
                format!("{}; expected {nnz} (the number of pixels)", offsets[n_bins]),
            );
        }
        for k in 1..offsets.len() {
            if offsets[k] < offsets[k - 1] {
                usable = false;
                self.add(
                    out,
                    Class::Bin1Offset,
                    &format!("indexes/bin1_offset[{k}]"),
                    format!(
                        "{} is below the previous entry {}: the index must be non-decreasing",
                        offsets[k],
                        offsets[k - 1]
                    ),
                );
            }
        }
        Ok(usable.then_some(offsets))
    }

    pub(crate) fn open_pixels(&self, out: &mut Collector) -> Option<PixelColumns> {
        let bin1 = self.dataset(out, "pixels/bin1_id", &[Kind::Integer]);
        let bin2 = self.dataset(out, "pixels/bin2_id", &[Kind::Integer]);
        let count = self.dataset(out, "pixels/count", &[Kind::Integer, Kind::Float]);
        let (Some(_), Some(_), Some(_)) = (bin1, bin2, count) else {
            return None;
        };
        let open = |name: &str| Column::open(self.group, name, self.path);
        let columns = match (
            open("pixels/bin1_id"),
            open("pixels/bin2_id"),
            open("pixels/count"),
        ) {
            (Ok(bin1), Ok(bin2), Ok(count)) => PixelColumns { bin1, bin2, count },
            (a, b, c) => {
                let message = [a.err(), b.err(), c.err()]
                    .into_iter()
                    .flatten()
                    .map(|e| e.to_string())
                    .collect::<Vec<_>>()
                    .join("; ");
                self.add(out, Class::Schema, "pixels", message);
                return None;
            }
        };
        if columns.bin1.len() != columns.len() || columns.bin2.len() != columns.len() {
            self.add(
                out,
                Class::Schema,
                "pixels",
                format!(
                    "pixels/bin1_id, pixels/bin2_id and pixels/count have {}, {} and {} rows",
                    columns.bin1.len(),
                    columns.bin2.len(),
                    columns.len()
                ),
            );
            return None;
        }
        Some(columns)
    }
}
