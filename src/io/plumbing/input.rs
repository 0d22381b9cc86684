//! Text inputs read line by line: standard input, or a file plain, gzip- or BGZF-compressed.

use std::io::{BufRead, BufReader, Read};
use std::num::NonZero;
use std::path::Path;

use noodles::bgzf;

use crate::error::{Error, Result};

const BUFFER_BYTES: usize = 1 << 20;

/// The number of threads for inflating and deflating BGZF: the machine's cores.
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

/// Open a text file for reading line by line: `-` is standard input; compression is detected
/// from the content (the magic bytes), whatever the extension: BGZF (block gzip, as bgzip,
/// pairtools and `contactmap pairs` write it) is inflated on worker threads, other gzip on this
/// thread.
pub fn open_text(path: &Path) -> Result<Box<dyn BufRead + Send>> {
    let input: Box<dyn Read + Send> = if path == Path::new("-") {
        Box::new(std::io::stdin())
    } else {
        Box::new(std::fs::File::open(path).map_err(|e| Error::io(path, e))?)
    };
    let mut reader = BufReader::with_capacity(BUFFER_BYTES, input);
    let start = reader.fill_buf().map_err(|e| Error::io(path, e))?;
    Ok(if is_bgzf(start) {
        Box::new(bgzf::io::MultithreadedReader::with_worker_count(
            worker_count(),
            reader,
        ))
    } else if start.starts_with(&[0x1f, 0x8b]) {
        Box::new(BufReader::new(flate2::read::MultiGzDecoder::new(reader)))
    } else {
        Box::new(reader)
    })
}
