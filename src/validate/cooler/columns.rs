//! The columns of a cooler's tables as stored: the bin table's and the pixels'.

use std::fs::File;

use crate::error::Result;
use crate::io::cool::chunks::Column;

/// The columns `bins/chrom`, `bins/start`, `bins/end` as stored.
pub(in crate::validate) type BinColumns = (Vec<i64>, Vec<i64>, Vec<i64>);

pub(in crate::validate) struct PixelColumns {
    pub(in crate::validate) bin1: Column,
    pub(in crate::validate) bin2: Column,
    pub(in crate::validate) count: Column,
}

impl PixelColumns {
    pub(in crate::validate) fn len(&self) -> usize {
        self.count.len()
    }

    pub(in crate::validate) fn read(
        &self,
        raw: &File,
        lo: usize,
        hi: usize,
    ) -> Result<(Vec<i64>, Vec<i64>, Vec<f64>)> {
        let ((bin1, bin2), count) = rayon::join(
            || {
                rayon::join(
                    || self.bin1.read::<i64>(raw, lo, hi),
                    || self.bin2.read::<i64>(raw, lo, hi),
                )
            },
            || self.count.read::<f64>(raw, lo, hi),
        );
        Ok((bin1?, bin2?, count?))
    }
}
