//! Readers that wrap another: [`Inspect`] shows every block streamed (progress, taps), and
//! [`CheckedCounts`] refuses a pixel whose count is negative, NaN or infinite.

use std::ops::Range;

use crate::error::{Error, Result};
use crate::matrix::PixelBlock;

use super::reader::MatrixReader;

/// A reader that shows every block of pixels it streams to a callback, then passes it on
/// unchanged: progress bars, running sums beside another job, checks (an error from the callback
/// ends the stream).
///
/// # Examples
///
/// ```
/// use std::sync::atomic::{AtomicUsize, Ordering};
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{InMemory, Inspect, MatrixReader};
/// use contactmap::matrix::{CountType, MatrixBuilder};
///
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 1_000)], 100)?;
/// let mut builder = MatrixBuilder::new(bins, CountType::Integer);
/// builder.push(0, 3, 2.0)?;
/// builder.push(1, 1, 5.0)?;
/// let matrix = InMemory::new("example".into(), builder.build());
/// let seen = AtomicUsize::new(0);
/// let inspected = Inspect::new(&matrix, |block| {
///     seen.fetch_add(block.len(), Ordering::Relaxed);
///     Ok(())
/// });
/// let n = inspected.bins().n_bins();
/// inspected.read_pixels(0..n, 0..n, &mut |_| Ok(()))?;
/// assert_eq!(seen.load(Ordering::Relaxed), 2);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub struct Inspect<'a, F> {
    inner: &'a dyn MatrixReader,
    on_block: F,
}

impl<'a, F: Fn(&PixelBlock) -> Result<()> + Send + Sync> Inspect<'a, F> {
    /// Show the blocks `inner` streams to `on_block`.
    pub fn new(inner: &'a dyn MatrixReader, on_block: F) -> Self {
        Inspect { inner, on_block }
    }
}

impl<F: Fn(&PixelBlock) -> Result<()> + Send + Sync> MatrixReader for Inspect<'_, F> {
    forward_reader_metadata!(inner);

    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.inner.read_pixels(rows, cols, &mut |block| {
            (self.on_block)(block)?;
            sink(block)
        })
    }

    fn read_stored_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.inner.read_stored_pixels(rows, cols, &mut |block| {
            (self.on_block)(block)?;
            sink(block)
        })
    }

    fn read_rows_owned(
        &self,
        rows: Range<usize>,
        sink: &mut dyn FnMut(PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.inner.read_rows_owned(rows, &mut |block| {
            (self.on_block)(&block)?;
            sink(block)
        })
    }

    fn read_pixels_owned(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.inner.read_pixels_owned(rows, cols, &mut |block| {
            (self.on_block)(&block)?;
            sink(block)
        })
    }
}

/// A reader whose counts are checked as they stream: the first pixel whose count is negative, NaN
/// or infinite ends the stream with an error naming the file, the pixel's bin ids and
/// coordinates, and its value.
///
/// The analyses (balance, expected, normalize, tads) read through it, so that they never compute
/// on such counts; `dump` and `info` read the file as it is, so that users can look at them. Text
/// tables refuse such counts when they are parsed; this adapter does the same for the binary
/// formats (.cool / .mcool / .hic), one pass over each block's counts as it goes by.
pub struct CheckedCounts {
    inner: Box<dyn MatrixReader>,
}

impl CheckedCounts {
    /// Check the counts of `inner`.
    pub fn new(inner: Box<dyn MatrixReader>) -> Self {
        CheckedCounts { inner }
    }

    /// The reader whose counts are checked, unchecked (to show a file as it is).
    pub fn inner(&self) -> &dyn MatrixReader {
        self.inner.as_ref()
    }

    /// Fail on the first count of `block` that is not finite and `>= 0`.
    fn check(&self, block: &PixelBlock) -> Result<()> {
        // A branch-free pass over the block; the position is looked for only on failure.
        let valid = block
            .count
            .iter()
            .fold(true, |ok, c| ok & (0.0..=f64::MAX).contains(c));
        if valid {
            return Ok(());
        }
        let k = block
            .count
            .iter()
            .position(|c| !(0.0..=f64::MAX).contains(c))
            .unwrap_or(0);
        Err(self.bad_count(block.bin1[k], block.bin2[k], block.count[k]))
    }

    fn bad_count(&self, bin1: u64, bin2: u64, count: f64) -> Error {
        let bins = self.inner.bins();
        let place = |bin: u64| match usize::try_from(bin) {
            Ok(id) if id < bins.n_bins() => {
                let bin = bins.bin(id);
                format!(
                    "{}:{}-{}",
                    bins.chroms()[bin.chrom_id].name,
                    bin.start,
                    bin.end
                )
            }
            _ => "outside the bin table".to_string(),
        };
        let problem = if count.is_nan() {
            "NaN"
        } else if count.is_infinite() {
            "infinite"
        } else {
            "negative"
        };
        Error::format(
            self.inner.source(),
            format!(
                "pixel bin1_id={bin1} bin2_id={bin2} ({} x {}) has a {problem} count ({count}): \
                 counts must be finite and >= 0 to be analysed (dump shows the pixels as stored)",
                place(bin1),
                place(bin2)
            ),
        )
    }
}

impl MatrixReader for CheckedCounts {
    forward_reader_metadata!(inner);

    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        Inspect::new(self.inner.as_ref(), |block| self.check(block)).read_pixels(rows, cols, sink)
    }

    fn read_stored_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        Inspect::new(self.inner.as_ref(), |block| self.check(block))
            .read_stored_pixels(rows, cols, sink)
    }

    fn read_rows_owned(
        &self,
        rows: Range<usize>,
        sink: &mut dyn FnMut(PixelBlock) -> Result<()>,
    ) -> Result<()> {
        Inspect::new(self.inner.as_ref(), |block| self.check(block)).read_rows_owned(rows, sink)
    }

    fn read_pixels_owned(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(PixelBlock) -> Result<()>,
    ) -> Result<()> {
        Inspect::new(self.inner.as_ref(), |block| self.check(block))
            .read_pixels_owned(rows, cols, sink)
    }
}
