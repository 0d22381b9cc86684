//! Progress on long work: a bar on standard error, only when it is a terminal (so logs of batch
//! jobs stay clean).

use std::io::IsTerminal;
use std::ops::Range;

use indicatif::{ProgressBar, ProgressStyle};

use crate::error::Result;
use crate::io::{forward_reader_metadata, MatrixReader};
use crate::matrix::PixelBlock;

/// A [`MatrixReader`] that advances a progress bar as pixels stream through it.
pub struct WithProgress<'a> {
    inner: &'a dyn MatrixReader,
    bar: ProgressBar,
}

impl<'a> WithProgress<'a> {
    /// Wrap `inner`; the bar counts its stored pixels and says `what` is being done. Hidden when
    /// standard error is not a terminal.
    pub fn new(inner: &'a dyn MatrixReader, what: &str) -> Result<Self> {
        let bar = if std::io::stderr().is_terminal() {
            let (nnz, _) = inner.totals()?;
            let bar = ProgressBar::new(nnz);
            bar.set_style(
                ProgressStyle::with_template(
                    "{msg} [{bar:40}] {human_pos}/{human_len} pixels, {elapsed} (eta {eta})",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
            );
            bar.set_message(what.to_string());
            bar
        } else {
            ProgressBar::hidden()
        };
        Ok(WithProgress { inner, bar })
    }
}

impl Drop for WithProgress<'_> {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

impl MatrixReader for WithProgress<'_> {
    forward_reader_metadata!(inner);

    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        self.inner.read_pixels(rows, cols, &mut |block| {
            self.bar.inc(block.len() as u64);
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
            self.bar.inc(block.len() as u64);
            sink(block)
        })
    }
}
