//! Opening pairs files and outputs.
//!
//! Inputs may be plain text, gzip or BGZF (told apart by their first bytes, whatever the name);
//! BGZF, which every pairs file from pairtools or from here is, is inflated on worker threads.
//! Outputs ending in `.gz` are written as BGZF (block gzip: any gzip reader reads it, and
//! tabix / pairix can index it), deflated on worker threads; other names are plain text; `-`
//! is standard output, uncompressed, for the next command of a pipe. Files are written under a
//! temporary name and renamed when complete, so a failed command leaves no output behind.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Read, Write};
use std::num::NonZero;
use std::path::Path;

use noodles::bgzf;

use super::records::PairsReader;
use crate::error::{Error, Result};
use crate::io::plumbing::atomic::{Temporary, is_special_file};
use crate::io::plumbing::output::is_stdout;

const BUFFER_BYTES: usize = 1 << 20;

/// The number of threads for inflating and deflating: the machine's cores.
pub fn worker_count() -> NonZero<usize> {
    std::thread::available_parallelism().unwrap_or(NonZero::<usize>::MIN)
}

/// Whether `bytes` start a BGZF block (gzip with the `BC` extra subfield).
pub fn is_bgzf(bytes: &[u8]) -> bool {
    bytes.len() >= 18
        && bytes[..4] == [0x1f, 0x8b, 0x08, 0x04]
        && bytes[12..14] == *b"BC"
        && bytes[14..16] == [2, 0]
}

/// Open a compressed or plain input, `-` for standard input: BGZF on worker threads, other
/// gzip on this thread, text as it is.
pub fn open_input(path: &Path) -> Result<Box<dyn BufRead + Send>> {
    let raw: Box<dyn Read + Send> = if path == Path::new("-") {
        Box::new(std::io::stdin())
    } else {
        Box::new(File::open(path).map_err(|e| Error::io(path, e))?)
    };
    let mut reader = BufReader::with_capacity(BUFFER_BYTES, raw);
    let start = reader.fill_buf().map_err(|e| Error::io(path, e))?;
    Ok(if is_bgzf(start) {
        Box::new(bgzf::io::MultithreadedReader::with_worker_count(
            worker_count(),
            reader,
        ))
    } else if start.starts_with(&[0x1f, 0x8b]) {
        Box::new(BufReader::with_capacity(
            BUFFER_BYTES,
            flate2::read::MultiGzDecoder::new(reader),
        ))
    } else {
        Box::new(reader)
    })
}

/// Open a pairs file (or `-`) and read its header.
pub fn open_pairs(path: &Path) -> Result<PairsReader> {
    let input = open_input(path)?;
    let name = if path == Path::new("-") {
        "<stdin>".to_string()
    } else {
        path.display().to_string()
    };
    PairsReader::new(input, &name)
}

/// Where pairs (or any text a pairs command writes) go: standard output, a plain file, or a
/// BGZF file for a `.gz` name; committed by [`PairsOutput::finish`], removed if dropped before.
pub struct PairsOutput {
    sink: Option<Sink>,
    temporary: Option<Temporary>,
    label: String,
}

enum Sink {
    Stdout(BufWriter<std::io::Stdout>),
    Plain(BufWriter<File>),
    Bgzf(Box<bgzf::io::MultithreadedWriter<File>>),
}

impl PairsOutput {
    /// Open `path`: `None` or `-` for standard output.
    pub fn open(path: Option<&Path>) -> Result<PairsOutput> {
        let Some(path) = path.filter(|p| !is_stdout(Some(p))) else {
            return Ok(PairsOutput {
                sink: Some(Sink::Stdout(BufWriter::with_capacity(
                    BUFFER_BYTES,
                    std::io::stdout(),
                ))),
                temporary: None,
                label: "<stdout>".into(),
            });
        };
        let (file, temporary) = if is_special_file(path) {
            let file = File::options()
                .write(true)
                .open(path)
                .map_err(|e| Error::io(path, e))?;
            (file, None)
        } else {
            let (temporary, file) = Temporary::create(path)?;
            (file, Some(temporary))
        };
        let sink = if path.extension().is_some_and(|e| e == "gz") {
            Sink::Bgzf(Box::new(bgzf::io::MultithreadedWriter::with_worker_count(
                worker_count(),
                file,
            )))
        } else {
            Sink::Plain(BufWriter::with_capacity(BUFFER_BYTES, file))
        };
        Ok(PairsOutput {
            sink: Some(sink),
            temporary,
            label: path.display().to_string(),
        })
    }

    /// The output's name, as errors give it.
    pub fn label(&self) -> &str {
        &self.label
    }

    /// Write bytes.
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<()> {
        let result = match &mut self.sink {
            Some(Sink::Stdout(w)) => w.write_all(bytes),
            Some(Sink::Plain(w)) => w.write_all(bytes),
            Some(Sink::Bgzf(w)) => w.write_all(bytes),
            None => Ok(()),
        };
        result.map_err(|e| Error::io(&self.label, e))
    }

    /// Flush, end the BGZF stream (its empty end-of-file block) and rename the file into place.
    pub fn finish(mut self) -> Result<()> {
        let label = self.label.clone();
        let io = |e| Error::io(&label, e);
        match self.sink.take() {
            Some(Sink::Stdout(mut w)) => w.flush().map_err(io)?,
            Some(Sink::Plain(w)) => {
                let file = w.into_inner().map_err(|e| io(e.into_error()))?;
                if self.temporary.is_some() {
                    file.sync_all().map_err(io)?;
                }
            }
            Some(Sink::Bgzf(mut w)) => {
                let file = w.finish().map_err(io)?;
                if self.temporary.is_some() {
                    file.sync_all().map_err(io)?;
                }
            }
            None => {}
        }
        match self.temporary.take() {
            Some(temporary) => temporary.persist(),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gz_outputs_are_bgzf_that_gzip_and_we_read_back() {
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("out.pairs.gz");
        let mut output = PairsOutput::open(Some(&path)).unwrap();
        output.write_all(b"#columns: a b\nx\ty\n").unwrap();
        output.finish().unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert!(is_bgzf(&bytes));
        // The BGZF end-of-file block: an empty block of 28 bytes.
        assert_eq!(
            &bytes[bytes.len() - 28..bytes.len() - 24],
            &[0x1f, 0x8b, 8, 4]
        );
        let mut text = String::new();
        flate2::read::MultiGzDecoder::new(&bytes[..])
            .read_to_string(&mut text)
            .unwrap();
        assert_eq!(text, "#columns: a b\nx\ty\n");
        let mut reader = open_pairs(&path).unwrap();
        assert_eq!(reader.header().columns(), ["a", "b"]);
        let mut record = crate::io::pairs::PairRecord::default();
        assert!(reader.read_record(&mut record).unwrap());
        assert_eq!(record.line(), b"x\ty");
    }

    #[test]
    fn an_output_dropped_before_finish_leaves_nothing() {
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("out.pairs");
        let mut output = PairsOutput::open(Some(&path)).unwrap();
        output.write_all(b"half").unwrap();
        drop(output);
        assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 0);
    }
}
