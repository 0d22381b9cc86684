//! Writing a chunked, shuffle + deflate compressed HDF5 column on every core: full chunks are
//! shuffled and deflated in parallel (rayon) by our code, then handed to libhdf5 as they are with
//! direct chunk writes (`H5Dwrite_chunk`), so that libhdf5's lock only covers the copy into the
//! file. The last, partial chunk goes through libhdf5's own filter pipeline. The file is the one
//! libhdf5 would write (same chunking and filters; deflate streams are zlib streams, as the HDF5
//! deflate filter writes them), and it reads back through any HDF5 reader.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::chunks::{transpose_bytes, transpose_bytes_4};
use crate::error::{Error, Result};

/// Full chunks gathered before they are compressed together (keeps every core busy).
const CHUNKS_PER_FLUSH: usize = 64;

/// An element of a column: its little-endian bytes.
pub trait ChunkValue: Copy + Send + Sync + hdf5::H5Type {
    /// Bytes per element (4 or 8).
    const SIZE: usize;
    /// The element's bytes as the low `SIZE` bytes of a word (little endian).
    fn bits(self) -> u64;
}

impl ChunkValue for i64 {
    const SIZE: usize = 8;
    fn bits(self) -> u64 {
        self as u64
    }
}

impl ChunkValue for i32 {
    const SIZE: usize = 4;
    fn bits(self) -> u64 {
        u64::from(self as u32)
    }
}

impl ChunkValue for f64 {
    const SIZE: usize = 8;
    fn bits(self) -> u64 {
        self.to_bits()
    }
}

/// HDF5's shuffle filter: byte `b` of element `e` goes to position `b * n + e`. Eight elements
/// at a time as a byte matrix transposed in registers (the reader's transposes: a transpose is
/// its own inverse), the rest one by one.
pub fn shuffle<T: ChunkValue>(values: &[T]) -> Vec<u8> {
    let n = values.len();
    let size = T::SIZE;
    let mut out = vec![0u8; n * size];
    let mut start = 0;
    let put_words = |out: &mut [u8], start: usize, words: &[u64]| {
        for (b, word) in words.iter().enumerate() {
            out[b * n + start..b * n + start + 8].copy_from_slice(&word.to_le_bytes());
        }
    };
    if size == 8 {
        while start + 8 <= n {
            let mut words: [u64; 8] = std::array::from_fn(|k| values[start + k].bits());
            transpose_bytes(&mut words);
            put_words(&mut out, start, &words);
            start += 8;
        }
    } else if size == 4 {
        while start + 8 <= n {
            // elements 0-3 in the low halves, 4-7 in the high halves
            let mut words: [u64; 4] = std::array::from_fn(|k| {
                values[start + k].bits() | (values[start + 4 + k].bits() << 32)
            });
            transpose_bytes_4(&mut words);
            put_words(&mut out, start, &words);
            start += 8;
        }
    }
    for (e, value) in values.iter().enumerate().skip(start) {
        let bytes = value.bits().to_le_bytes();
        for (b, &byte) in bytes[..size].iter().enumerate() {
            out[b * n + e] = byte;
        }
    }
    out
}

/// A zlib compressor at `level` (what HDF5's deflate filter writes), to be used by [`deflate`].
pub fn compressor(level: u8) -> flate2::Compress {
    flate2::Compress::new(flate2::Compression::new(u32::from(level)), true)
}

/// `bytes` as one zlib stream, by `compressor` (reset first: one compressor serves many chunks
/// without setting up its tables again).
pub fn deflate(compressor: &mut flate2::Compress, bytes: &[u8]) -> Vec<u8> {
    compressor.reset();
    let mut out = Vec::with_capacity(bytes.len() / 2 + 64);
    loop {
        let input = &bytes[compressor.total_in() as usize..];
        let status = compressor
            .compress_vec(input, &mut out, flate2::FlushCompress::Finish)
            .expect("deflating into memory does not fail");
        if status == flate2::Status::StreamEnd {
            return out;
        }
        // the output is full: room for as much again
        out.reserve(out.capacity().max(64));
    }
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

    fn hdf5_err(&self, what: &str) -> impl FnOnce(hdf5::Error) -> Error + '_ + use<'_, T> {
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
            .map_init(
                || compressor(level),
                |compressor, values| deflate(compressor, &shuffle(values)),
            )
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

    /// The shuffle filter's definition, byte by byte.
    fn naive_shuffle(bytes: &[u8], size: usize) -> Vec<u8> {
        let n = bytes.len() / size;
        let mut out = vec![0u8; bytes.len()];
        for e in 0..n {
            for b in 0..size {
                out[b * n + e] = bytes[e * size + b];
            }
        }
        out
    }

    #[test]
    fn shuffle_equals_the_definition_at_every_length() {
        // lengths around the blocks of eight; values with every byte different
        for n in 0..40usize {
            let wide: Vec<i64> = (0..n as i64)
                .map(|k| (k * 0x0102_0304_0506_0709) ^ -0x7766_5544_3322_1100)
                .collect();
            let bytes: Vec<u8> = wide.iter().flat_map(|v| v.to_le_bytes()).collect();
            assert_eq!(shuffle(&wide), naive_shuffle(&bytes, 8), "i64, {n}");
            let floats: Vec<f64> = wide.iter().map(|&v| v as f64 / 7.0).collect();
            let bytes: Vec<u8> = floats.iter().flat_map(|v| v.to_le_bytes()).collect();
            assert_eq!(shuffle(&floats), naive_shuffle(&bytes, 8), "f64, {n}");
            let narrow: Vec<i32> = wide.iter().map(|&v| (v >> 16) as i32).collect();
            let bytes: Vec<u8> = narrow.iter().flat_map(|v| v.to_le_bytes()).collect();
            assert_eq!(shuffle(&narrow), naive_shuffle(&bytes, 4), "i32, {n}");
        }
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
