//! Juicer `.hic` reader (versions 8 and 9). Being written.

use std::ops::Range;
use std::path::Path;

use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::io::{MatrixInfo, MatrixReader};
use crate::matrix::{CountType, PixelBlock, Weights};

/// An open `.hic` file at one resolution.
#[derive(Debug)]
pub struct HicReader {
    source: String,
    bins: BinTable,
}

impl HicReader {
    /// Open `path` at `resolution` (the only one if `None` and the file has one).
    pub fn open(path: &Path, _resolution: Option<u64>) -> Result<Self> {
        Err(Error::format(path, ".hic reading is not available yet"))
    }
}

impl HicReader {
    /// The base-pair resolutions of the file at `path`.
    pub fn list_resolutions(path: &Path) -> Result<Vec<u64>> {
        Err(Error::format(path, ".hic reading is not available yet"))
    }
}

impl MatrixReader for HicReader {
    fn source(&self) -> &str {
        &self.source
    }
    fn bins(&self) -> &BinTable {
        &self.bins
    }
    fn count_type(&self) -> CountType {
        CountType::Float
    }
    fn weight_names(&self) -> Vec<String> {
        Vec::new()
    }
    fn weights(&self, name: &str) -> Result<Weights> {
        Err(Error::format(
            &self.source,
            format!("no weight column '{name}'"),
        ))
    }
    fn info(&self) -> MatrixInfo {
        MatrixInfo::default()
    }
    fn read_pixels(
        &self,
        _rows: Range<usize>,
        _cols: Range<usize>,
        _sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        Ok(())
    }
}
