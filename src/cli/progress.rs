//! Progress on long work: a bar on standard error, only when it is a terminal (so logs of batch
//! jobs stay clean).

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};

use contactmap::error::Result;
use contactmap::io::{Inspect, MatrixReader};
use contactmap::matrix::PixelBlock;

/// A progress bar on standard error counting the stored pixels of a reader; hidden when
/// standard error is not a terminal. Read through [`Progress::reader`].
pub struct Progress<'a> {
    inner: &'a dyn MatrixReader,
    bar: ProgressBar,
}

impl<'a> Progress<'a> {
    /// A bar for the pixels of `inner`, saying `what` is being done.
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
        Ok(Progress { inner, bar })
    }

    /// The reader whose pixels advance the bar.
    pub fn reader(&self) -> Inspect<'a, impl Fn(&PixelBlock) -> Result<()> + use<>> {
        let bar = self.bar.clone();
        Inspect::new(self.inner, move |block: &PixelBlock| {
            bar.inc(block.len() as u64);
            Ok(())
        })
    }
}

impl Drop for Progress<'_> {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

/// A counter on standard error while work of unknown length runs (`what`: the things counted,
/// e.g. "frames"); hidden when standard error is not a terminal (logs, pipelines).
pub fn spinner(what: &str) -> ProgressBar {
    if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new_spinner();
        bar.set_message(what.to_string());
        bar
    } else {
        ProgressBar::hidden()
    }
}
