//! The kind of a matrix file, recognised by its first bytes.

use std::io::Read;

use crate::error::{Error, Result};

/// The on-disk kind of a matrix file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// HDF5: .cool / .mcool.
    Hdf5,
    /// Juicer .hic.
    Hic,
    /// Anything else: a text table, maybe gzip-compressed.
    Text,
}

/// Recognise a file by its first bytes (`-`, stdin, is always text).
pub fn detect_kind(path: &str) -> Result<FileKind> {
    if path == "-" {
        return Ok(FileKind::Text);
    }
    let mut file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut magic = [0u8; 8];
    let mut n = 0;
    while n < magic.len() {
        match file.read(&mut magic[n..]).map_err(|e| Error::io(path, e))? {
            0 => break,
            k => n += k,
        }
    }
    Ok(if n >= 8 && &magic == b"\x89HDF\r\n\x1a\n" {
        FileKind::Hdf5
    } else if n >= 4 && &magic[..4] == b"HIC\0" {
        FileKind::Hic
    } else {
        FileKind::Text
    })
}
