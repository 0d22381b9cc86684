//! Writing a chunked, shuffle + deflate compressed HDF5 column on every core: full chunks are
//! shuffled and deflated in parallel (rayon) by our code, then handed to libhdf5 as they are with
//! direct chunk writes (`H5Dwrite_chunk`), so that libhdf5's lock only covers the copy into the
//! file. The last, partial chunk goes through libhdf5's own filter pipeline. The file is the one
//! libhdf5 would write (same chunking and filters; deflate streams are zlib streams, as the HDF5
//! deflate filter writes them), and it reads back through any HDF5 reader.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::error::{Error, Result};

/// Full chunks gathered before they are compressed together (keeps every core busy).
const CHUNKS_PER_FLUSH: usize = 64;

/// An element of a column: its little-endian bytes.
pub trait ChunkValue: Copy + Send + Sync + hdf5::H5Type {
    /// Bytes per element.
    const SIZE: usize;
    /// Append the little-endian bytes of `self`.
    fn put(self, out: &mut Vec<u8>);
}

impl ChunkValue for i64 {
    const SIZE: usize = 8;
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl ChunkValue for i32 {
    const SIZE: usize = 4;
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl ChunkValue for f64 {
    const SIZE: usize = 8;
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

/// HDF5's shuffle filter: byte `b` of element `e` goes to position `b * n + e`.
pub fn shuffle<T: ChunkValue>(values: &[T]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(values.len() * T::SIZE);
    for &v in values {
        v.put(&mut bytes);
    }
    let n = values.len();
    let mut out = vec![0u8; bytes.len()];
    for (e, element) in bytes.chunks_exact(T::SIZE).enumerate() {
        for (b, &byte) in element.iter().enumerate() {
            out[b * n + e] = byte;
        }
    }
    out
}

/// A zlib stream of `bytes` at `level` (what HDF5's deflate filter stores).
pub fn deflate(bytes: &[u8], level: u8) -> Vec<u8> {
    let mut encoder = flate2::write::ZlibEncoder::new(
        Vec::with_capacity(bytes.len() / 2),
        flate2::Compression::new(u32::from(level)),
    );
    encoder
        .write_all(bytes)
        .expect("writing into a Vec does not fail");
    encoder.finish().expect("writing into a Vec does not fail")
}

/// `H5Dwrite_chunk` of the already filtered `bytes` at element `offset` of the one-dimensional
/// dataset `id`, under the library lock; negative on failure.
#[allow(unsafe_code)]
fn write_chunk(id: hdf5_sys::h5i::hid_t, offset: u64, bytes: &[u8]) -> hdf5_sys::h5::herr_t {
    let offset: [hdf5_sys::h5::hsize_t; 1] = [offset];
    hdf5::sync::sync(|| {
        // SAFETY: `id` is an open dataset (borrowed from a live `hdf5::Dataset`), `offset` points
        // to one coordinate (the dataset's rank), and `bytes` is a live buffer of `bytes.len()`
        // bytes that libhdf5 only reads during the call. The call is made under hdf5-metno's
        // library lock, as every other libhdf5 call.
        unsafe {
            hdf5_sys::h5d::H5Dwrite_chunk(
                id,
                hdf5_sys::h5p::H5P_DEFAULT,
                0,
                offset.as_ptr(),
                bytes.len(),
                bytes.as_ptr().cast(),
            )
        }
    })
}

/// A one-dimensional resizable dataset with chunks of `chunk` elements, filters shuffle then
/// deflate at `level`, written in order.
pub struct ChunkedColumn<T: ChunkValue> {
    path: PathBuf,
    name: String,
    dataset: hdf5::Dataset,
    chunk: usize,
    level: u8,
    pending: Vec<T>,
    /// Elements already in the file (whole chunks).
    written: usize,
}

impl<T: ChunkValue> ChunkedColumn<T> {
    /// Write into `dataset` (created empty with `chunk`-element chunks, shuffle and deflate at
    /// `level`), named `name` in `path` for errors.
    pub fn new(path: &Path, name: &str, dataset: hdf5::Dataset, chunk: usize, level: u8) -> Self {
        ChunkedColumn {
            path: path.to_path_buf(),
            name: name.to_string(),
            dataset,
            chunk,
            level,
            pending: Vec::with_capacity(chunk * CHUNKS_PER_FLUSH * 2),
            written: 0,
        }
    }

    /// Append `values`; full chunks are compressed and written once enough have gathered.
    pub fn extend(&mut self, values: impl IntoIterator<Item = T>) -> Result<()> {
        self.pending.extend(values);
        if self.pending.len() >= self.chunk * CHUNKS_PER_FLUSH {
            self.flush_full_chunks()?;
        }
        Ok(())
    }

    fn hdf5_err(&self, what: &str) -> impl FnOnce(hdf5::Error) -> Error + '_ {
        let what = format!("{what} {}", self.name);
        move |e| Error::hdf5(&self.path, what, e)
    }

    /// Compress the full chunks of `pending` in parallel and write them directly.
    fn flush_full_chunks(&mut self) -> Result<()> {
        let n_full = self.pending.len() / self.chunk;
        if n_full == 0 {
            return Ok(());
        }
        let level = self.level;
        let compressed: Vec<Vec<u8>> = self.pending[..n_full * self.chunk]
            .par_chunks(self.chunk)
            .map(|values| deflate(&shuffle(values), level))
            .collect();
        let end = self.written + n_full * self.chunk;
        self.dataset
            .resize(end)
            .map_err(self.hdf5_err("resizing"))?;
        let id = self.dataset.id();
        for (k, bytes) in compressed.iter().enumerate() {
            let offset = (self.written + k * self.chunk) as u64;
            if write_chunk(id, offset, bytes) < 0 {
                return Err(Error::Invalid(format!(
                    "{}: writing a chunk of {} failed (H5Dwrite_chunk)",
                    self.path.display(),
                    self.name
                )));
            }
        }
        self.pending.drain(..n_full * self.chunk);
        self.written = end;
        Ok(())
    }

    /// Write what is left (the last chunk through libhdf5's filters) and return the length.
    pub fn finish(&mut self) -> Result<usize> {
        self.flush_full_chunks()?;
        let end = self.written + self.pending.len();
        if !self.pending.is_empty() {
            self.dataset
                .resize(end)
                .map_err(self.hdf5_err("resizing"))?;
            self.dataset
                .write_slice(&self.pending, self.written..end)
                .map_err(self.hdf5_err("writing"))?;
            self.pending.clear();
            self.written = end;
        }
        Ok(end)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shuffle_groups_bytes_by_significance() {
        let out = shuffle(&[0x0102_i32, 0x0304_0506]);
        // Element bytes (LE): [02 01 00 00], [06 05 04 03].
        assert_eq!(out, vec![0x02, 0x06, 0x01, 0x05, 0x00, 0x04, 0x00, 0x03]);
    }

    #[test]
    fn direct_chunks_read_back_through_libhdf5() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.h5");
        let file = hdf5::File::create(&path).unwrap();
        let values: Vec<i64> = (0..10_000).map(|k| k * k % 977 - 300).collect();
        let floats: Vec<f64> = values.iter().map(|&v| v as f64 / 3.0).collect();
        for (name, chunk) in [("a", 100usize), ("b", 7)] {
            let dataset = file
                .new_dataset::<i64>()
                .shape(0..)
                .chunk(chunk)
                .shuffle()
                .deflate(6)
                .create(name)
                .unwrap();
            let mut column = ChunkedColumn::new(&path, name, dataset, chunk, 6);
            for part in values.chunks(333) {
                column.extend(part.iter().copied()).unwrap();
            }
            assert_eq!(column.finish().unwrap(), values.len());
        }
        let dataset = file
            .new_dataset::<f64>()
            .shape(0..)
            .chunk(64)
            .shuffle()
            .deflate(6)
            .create("f")
            .unwrap();
        let mut column = ChunkedColumn::new(&path, "f", dataset, 64, 6);
        column.extend(floats.iter().copied()).unwrap();
        column.finish().unwrap();
        file.close().unwrap();
        let file = hdf5::File::open(&path).unwrap();
        for name in ["a", "b"] {
            let back: Vec<i64> = file.dataset(name).unwrap().read_raw().unwrap();
            assert_eq!(back, values, "{name}");
        }
        let back: Vec<f64> = file.dataset("f").unwrap().read_raw().unwrap();
        assert_eq!(back, floats);
    }
}
