//! Parallel reading of chunked, deflate-compressed HDF5 columns.
//!
//! libhdf5 serialises every call behind one global lock, so reading a cooler pixel column through
//! it uses one core. cooler writes its pixel columns as many small chunks filtered by
//! shuffle + deflate. We ask libhdf5 once for the chunk index (file address and size of every
//! chunk, via `H5Dchunk_iter`), then read the raw chunks with positioned reads and undo the filters
//! ourselves, one chunk per rayon task. Columns with any other layout, filter or byte order fall back
//! to libhdf5's own reader.

use std::fs::File;
use std::os::unix::fs::FileExt;
use std::path::Path;

use flate2::{Decompress, FlushDecompress, Status};
use hdf5::filters::Filter;
use hdf5::types::{FloatSize, IntSize, TypeDescriptor};
use rayon::prelude::*;

use super::hdf5_file::file_len;
use crate::error::{Error, Result};

/// Element type of a column, as stored (little-endian).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Element {
    I8,
    I16,
    I32,
    I64,
    U8,
    U16,
    U32,
    U64,
    F32,
    F64,
}

impl Element {
    fn from_descriptor(descriptor: &TypeDescriptor) -> Option<Element> {
        Some(match descriptor {
            TypeDescriptor::Integer(size) => match size {
                IntSize::U1 => Element::I8,
                IntSize::U2 => Element::I16,
                IntSize::U4 => Element::I32,
                IntSize::U8 => Element::I64,
            },
            TypeDescriptor::Unsigned(size) => match size {
                IntSize::U1 => Element::U8,
                IntSize::U2 => Element::U16,
                IntSize::U4 => Element::U32,
                IntSize::U8 => Element::U64,
            },
            TypeDescriptor::Float(FloatSize::U4) => Element::F32,
            TypeDescriptor::Float(FloatSize::U8) => Element::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Element::I8 | Element::U8 => 1,
            Element::I16 | Element::U16 => 2,
            Element::I32 | Element::U32 | Element::F32 => 4,
            Element::I64 | Element::U64 | Element::F64 => 8,
        }
    }

    fn is_float(self) -> bool {
        matches!(self, Element::F32 | Element::F64)
    }
}

/// Values that a column can be decoded into.
pub trait ColumnValue: Copy + Default + Send + Sync + hdf5::H5Type {
    /// From a stored integer.
    fn from_int(v: i64) -> Self;
    /// From a stored float.
    fn from_float(v: f64) -> Self;
}

impl ColumnValue for i64 {
    #[inline]
    fn from_int(v: i64) -> Self {
        v
    }
    #[inline]
    fn from_float(v: f64) -> Self {
        v as i64
    }
}

/// Bin ids read as `u64`, the pixel block's type: a negative stored id wraps to a huge one, which
/// the range checks refuse.
impl ColumnValue for u64 {
    #[inline]
    fn from_int(v: i64) -> Self {
        v as u64
    }
    #[inline]
    fn from_float(v: f64) -> Self {
        v as i64 as u64
    }
}

impl ColumnValue for f64 {
    #[inline]
    fn from_int(v: i64) -> Self {
        v as f64
    }
    #[inline]
    fn from_float(v: f64) -> Self {
        v
    }
}

#[derive(Clone, Copy, Debug)]
struct RawChunk {
    /// Index of the chunk's first element.
    first: u64,
    /// File address of the stored (filtered) bytes.
    address: u64,
    /// Stored size in bytes.
    size: u64,
    /// Bit k set: filter k of the pipeline was skipped for this chunk.
    filter_mask: u32,
}

/// How a column is read.
#[derive(Debug)]
enum Plan {
    /// Our own parallel chunk reader.
    Direct {
        element: Element,
        chunk_len: usize,
        shuffle_position: Option<u32>,
        deflate_position: Option<u32>,
        chunks: Vec<RawChunk>,
    },
    /// Our own parallel reader of a 2-D dataset chunked in tiles of `rows x columns` (h5py's
    /// automatic chunks of polychrom's positions split the three coordinates).
    Tiles {
        decoder: ChunkDecoder,
        rows: usize,
        columns: usize,
        width: usize,
        /// Each stored tile with its first row and first column.
        tiles: Vec<(usize, usize, RawChunk)>,
    },
    /// libhdf5's reader.
    Library,
}

/// A 1-D numeric column of an HDF5 file.
#[derive(Debug)]
pub struct Column {
    dataset: hdf5::Dataset,
    name: String,
    path: String,
    len: usize,
    is_float: bool,
    plan: Plan,
}

impl Column {
    /// Open the 1-D numeric dataset `name` (a path inside `group`) of the file at `path`.
    pub fn open(group: &hdf5::Group, name: &str, path: &str) -> Result<Column> {
        let dataset = group
            .dataset(name)
            .map_err(|e| Error::hdf5(path, format!("opening dataset {name}"), e))?;
        Column::from_dataset(dataset, name, path, None)
    }

    /// The 2-D numeric dataset `dataset` (called `name` in messages) of `rows x width` values,
    /// read as one column of its values in row order: parallel when its chunks span whole rows.
    pub fn rows(dataset: hdf5::Dataset, name: &str, path: &str, width: usize) -> Result<Column> {
        Column::from_dataset(dataset, name, path, Some(width))
    }

    fn from_dataset(
        dataset: hdf5::Dataset,
        name: &str,
        path: &str,
        width: Option<usize>,
    ) -> Result<Column> {
        crate::io::plumbing::hdf5_guard::checked_len(path, &dataset, name, file_len(path))?;
        let shape = dataset.shape();
        let len = match (width, shape.as_slice()) {
            (None, &[n]) => n,
            (Some(width), &[n, w]) if w == width => n * width,
            (None, _) => {
                return Err(Error::format(
                    path,
                    format!("dataset {name} has shape {shape:?}; expected one dimension"),
                ));
            }
            (Some(width), _) => {
                return Err(Error::format(
                    path,
                    format!("dataset {name} has shape {shape:?}; expected N x {width}"),
                ));
            }
        };
        let descriptor = dataset
            .dtype()
            .and_then(|t| t.to_descriptor())
            .map_err(|e| Error::hdf5(path, format!("reading the type of {name}"), e))?;
        let element = match &descriptor {
            TypeDescriptor::Enum(e) => Element::from_descriptor(&if e.signed {
                TypeDescriptor::Integer(e.size)
            } else {
                TypeDescriptor::Unsigned(e.size)
            }),
            other => Element::from_descriptor(other),
        }
        .ok_or_else(|| {
            Error::format(
                path,
                format!("dataset {name} has type {descriptor:?}; expected numbers"),
            )
        })?;
        let plan = direct_plan(&dataset, element, width).unwrap_or(Plan::Library);
        Ok(Column {
            name: name.to_string(),
            path: path.to_string(),
            len,
            is_float: element.is_float(),
            plan,
            dataset,
        })
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when the column is empty.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// True when the stored type is floating point.
    pub fn is_float(&self) -> bool {
        self.is_float
    }

    /// True when the column is read by the parallel chunk reader rather than by libhdf5.
    pub fn is_direct(&self) -> bool {
        matches!(self.plan, Plan::Direct { .. })
    }

    /// Read elements `lo..hi` (in parallel when the layout allows it).
    pub fn read<T: ColumnValue>(&self, file: &File, lo: usize, hi: usize) -> Result<Vec<T>> {
        let mut out = Vec::new();
        self.read_into(file, lo, hi, &mut out)?;
        Ok(out)
    }

    /// Read elements `lo..hi` into `out`, reusing its allocation: `out` ends `hi - lo` long, each
    /// element written (a buffer handed back by a reader is not zeroed again first).
    pub fn read_into<T: ColumnValue>(
        &self,
        file: &File,
        lo: usize,
        hi: usize,
        out: &mut Vec<T>,
    ) -> Result<()> {
        if lo > hi || hi > self.len {
            return Err(Error::format(
                &self.path,
                format!(
                    "dataset {}: requested elements {lo}..{hi} of {}",
                    self.name, self.len
                ),
            ));
        }
        match &self.plan {
            Plan::Library if self.dataset.ndim() != 1 => {
                // a 2-D dataset read whole (polychrom's positions: one conformation)
                let values = self
                    .dataset
                    .read_raw::<T>()
                    .map_err(|e| Error::hdf5(&self.path, format!("reading {}", self.name), e))?;
                out.clear();
                out.extend_from_slice(values.get(lo..hi).unwrap_or_default());
                Ok(())
            }
            Plan::Library => {
                let values = self
                    .dataset
                    .read_slice_1d::<T, _>(lo..hi)
                    .map_err(|e| Error::hdf5(&self.path, format!("reading {}", self.name), e))?;
                out.clear();
                out.extend(values.iter());
                Ok(())
            }
            Plan::Direct {
                element,
                chunk_len,
                shuffle_position,
                deflate_position,
                chunks,
            } => {
                // every element is written below: only growth is zeroed
                if out.len() < hi - lo {
                    out.resize(hi - lo, T::default());
                }
                out.truncate(hi - lo);
                if lo == hi {
                    return Ok(());
                }
                // Split the output into one slice per chunk overlapping lo..hi.
                let first_chunk = lo / chunk_len;
                let mut tasks = Vec::new();
                let mut rest: &mut [T] = out;
                let mut position = lo;
                let mut chunk_index =
                    chunks.partition_point(|c| (c.first as usize) < first_chunk * chunk_len);
                while position < hi {
                    let chunk_start = position / chunk_len * chunk_len;
                    let chunk_end = (chunk_start + chunk_len).min(hi);
                    let (head, tail) = rest.split_at_mut(chunk_end - position);
                    let raw = match chunks.get(chunk_index) {
                        Some(c) if c.first as usize == chunk_start => {
                            chunk_index += 1;
                            Some(*c)
                        }
                        _ => None, // never written: fill value (0)
                    };
                    tasks.push((raw, position - chunk_start, head));
                    rest = tail;
                    position = chunk_end;
                }
                let decoder = ChunkDecoder {
                    element: *element,
                    chunk_len: *chunk_len,
                    shuffle_position: *shuffle_position,
                    deflate_position: *deflate_position,
                };
                tasks
                    .into_par_iter()
                    .map_init(Scratch::new, |scratch, (raw, skip, target)| match raw {
                        None => {
                            target.fill(T::default());
                            Ok(())
                        }
                        Some(raw) => decoder
                            .decode(file, &raw, scratch, skip, target)
                            .map_err(|message| {
                                Error::format(
                                    &self.path,
                                    format!(
                                        "dataset {}: chunk at element {} (file offset {}): {message}",
                                        self.name, raw.first, raw.address
                                    ),
                                )
                            }),
                    })
                    .collect::<Result<()>>()
            }
            Plan::Tiles {
                decoder,
                rows,
                columns,
                width,
                tiles,
            } => {
                let decoded: Vec<Vec<T>> = tiles
                    .par_iter()
                    .map_init(Scratch::new, |scratch, (row, column, raw)| {
                        let mut tile = vec![T::default(); rows * columns];
                        decoder
                            .decode(file, raw, scratch, 0, &mut tile)
                            .map_err(|message| {
                                Error::format(
                                    &self.path,
                                    format!(
                                        "dataset {}: chunk at row {row}, column {column} (file \
                                         offset {}): {message}",
                                        self.name, raw.address
                                    ),
                                )
                            })?;
                        Ok(tile)
                    })
                    .collect::<Result<_>>()?;
                // tiles never written hold the fill value (0)
                out.clear();
                out.resize(self.len, T::default());
                let n_rows = self.len / width;
                for ((row, column, _), tile) in tiles.iter().zip(&decoded) {
                    for r in 0..*rows {
                        let target_row = row + r;
                        if target_row >= n_rows {
                            break;
                        }
                        let used = (*columns).min(width.saturating_sub(*column));
                        let start = target_row * width + column;
                        out[start..start + used]
                            .copy_from_slice(&tile[r * columns..r * columns + used]);
                    }
                }
                out.truncate(hi);
                out.drain(..lo);
                Ok(())
            }
        }
    }
}

/// Build the direct plan when the column is chunked, little-endian, and filtered by at most
/// shuffle then deflate.
fn direct_plan(dataset: &hdf5::Dataset, element: Element, width: Option<usize>) -> Option<Plan> {
    let mut chunk = dataset.chunk()?;
    // a 2-D dataset whose chunks span whole rows is a 1-D column of its values in row order;
    // one chunked in narrower tiles is read tile by tile
    let mut tiles = None;
    let width = match width {
        None => 1,
        Some(width) if chunk.len() == 2 && chunk[1] == width => {
            chunk = vec![chunk[0] * width];
            width
        }
        Some(width) if chunk.len() == 2 && chunk[0] > 0 && chunk[1] > 0 => {
            tiles = Some((chunk[0], chunk[1]));
            chunk = vec![chunk[0] * chunk[1]];
            width
        }
        Some(_) => return None,
    };
    let chunk_len = *chunk.first()?;
    // Each task inflates one chunk into a buffer of its size: a chunk size from a corrupt
    // layout (cooler writes chunks of about 1 MB) goes through the library instead.
    const MAX_DIRECT_CHUNK_BYTES: usize = 64 << 20;
    if chunk.len() != 1
        || chunk_len == 0
        || chunk_len.saturating_mul(element.size()) > MAX_DIRECT_CHUNK_BYTES
    {
        return None;
    }
    let dtype = dataset.dtype().ok()?;
    if element.size() > 1 && dtype.byte_order() != hdf5::datatype::ByteOrder::LittleEndian {
        return None;
    }
    let mut shuffle_position = None;
    let mut deflate_position = None;
    for (k, filter) in dataset.filters().iter().enumerate() {
        match filter {
            Filter::Shuffle if deflate_position.is_none() && shuffle_position.is_none() => {
                shuffle_position = Some(k as u32)
            }
            Filter::Deflate(_) if deflate_position.is_none() => deflate_position = Some(k as u32),
            _ => return None,
        }
    }
    if let Some((rows, columns)) = tiles {
        let mut found = Vec::new();
        dataset
            .chunks_visit(|info| {
                found.push((
                    info.offset[0] as usize,
                    info.offset[1] as usize,
                    RawChunk {
                        first: 0,
                        address: info.addr,
                        size: info.size,
                        filter_mask: info.filter_mask,
                    },
                ));
                0
            })
            .ok()?;
        return Some(Plan::Tiles {
            decoder: ChunkDecoder {
                element,
                chunk_len,
                shuffle_position,
                deflate_position,
            },
            rows,
            columns,
            width,
            tiles: found,
        });
    }
    let mut chunks = Vec::new();
    dataset
        .chunks_visit(|info| {
            chunks.push(RawChunk {
                first: info.offset[0] * width as u64,
                address: info.addr,
                size: info.size,
                filter_mask: info.filter_mask,
            });
            0
        })
        .ok()?;
    chunks.sort_unstable_by_key(|c| c.first);
    Some(Plan::Direct {
        element,
        chunk_len,
        shuffle_position,
        deflate_position,
        chunks,
    })
}

#[derive(Clone, Copy, Debug)]
struct ChunkDecoder {
    element: Element,
    chunk_len: usize,
    shuffle_position: Option<u32>,
    deflate_position: Option<u32>,
}

impl ChunkDecoder {
    /// Read, inflate and unshuffle one chunk, then decode `target.len()` elements starting at
    /// element `skip` of the chunk into `target`.
    fn decode<T: ColumnValue>(
        &self,
        file: &File,
        raw: &RawChunk,
        scratch: &mut Scratch,
        skip: usize,
        target: &mut [T],
    ) -> std::result::Result<(), String> {
        let element_size = self.element.size();
        let chunk_bytes = self.chunk_len * element_size;
        let stored_size =
            usize::try_from(raw.size).map_err(|_| "chunk size too large".to_string())?;
        if stored_size > chunk_bytes + chunk_bytes / 2 + 1024 {
            return Err(format!(
                "stored size {stored_size} is implausible for a {chunk_bytes}-byte chunk"
            ));
        }
        let stored = scratch.stored(stored_size);
        file.read_exact_at(stored, raw.address).map_err(|e| {
            format!("cannot read {stored_size} bytes: {e} (is the file truncated?)")
        })?;
        let applied =
            |position: Option<u32>| position.is_some_and(|k| raw.filter_mask & (1 << k) == 0);
        let plain: &[u8] = if applied(self.deflate_position) {
            let Scratch {
                stored,
                plain,
                inflater,
            } = scratch;
            if plain.len() < chunk_bytes {
                plain.resize(chunk_bytes, 0);
            }
            inflater.reset(true);
            let status = inflater
                .decompress(&stored[..stored_size], plain, FlushDecompress::Finish)
                .map_err(|e| format!("corrupt deflate data ({e})"))?;
            if status != Status::StreamEnd {
                return Err(if inflater.total_out() as usize >= plain.len() {
                    format!("the chunk inflates to more than {chunk_bytes} bytes")
                } else {
                    "deflate stream does not end where the chunk ends".into()
                });
            }
            &plain[..inflater.total_out() as usize]
        } else {
            &scratch.stored[..stored_size]
        };
        if plain.len() < (skip + target.len()) * element_size {
            return Err(format!(
                "chunk holds {} bytes; expected {chunk_bytes}",
                plain.len()
            ));
        }
        let shuffled = applied(self.shuffle_position);
        let element = self.element;
        match element_size {
            1 => decode_elements::<1, T>(plain, false, element, skip, target),
            2 => decode_elements::<2, T>(plain, shuffled, element, skip, target),
            4 => decode_elements::<4, T>(plain, shuffled, element, skip, target),
            _ => decode_elements::<8, T>(plain, shuffled, element, skip, target),
        }
        Ok(())
    }
}

/// What one task reuses from chunk to chunk: the stored bytes, the inflated bytes and the
/// inflater (set up once, not per chunk).
struct Scratch {
    stored: Vec<u8>,
    plain: Vec<u8>,
    inflater: Decompress,
}

impl Scratch {
    fn new() -> Scratch {
        Scratch {
            stored: Vec::new(),
            plain: Vec::new(),
            inflater: Decompress::new(true),
        }
    }

    /// Room for `size` stored bytes.
    fn stored(&mut self, size: usize) -> &mut [u8] {
        if self.stored.len() < size {
            self.stored.resize(size, 0);
        }
        &mut self.stored[..size]
    }
}

/// Decode elements `skip..skip + target.len()` of a chunk's `N`-byte elements, undoing HDF5's
/// shuffle filter on the way when `shuffled` (byte `b` of element `i` was stored at `b * n + i`,
/// `n` the number of whole elements; trailing bytes are stored as they are). The element type is
/// matched once per chunk, not per element.
fn decode_elements<const N: usize, T: ColumnValue>(
    plain: &[u8],
    shuffled: bool,
    element: Element,
    skip: usize,
    target: &mut [T],
) {
    match element {
        Element::I8 => fill::<N, T, _>(plain, shuffled, skip, target, |v| {
            T::from_int(v as u8 as i8 as i64)
        }),
        Element::U8 => fill::<N, T, _>(plain, shuffled, skip, target, |v| T::from_int(v as i64)),
        Element::I16 => fill::<N, T, _>(plain, shuffled, skip, target, |v| {
            T::from_int(v as u16 as i16 as i64)
        }),
        Element::U16 => fill::<N, T, _>(plain, shuffled, skip, target, |v| T::from_int(v as i64)),
        Element::I32 => fill::<N, T, _>(plain, shuffled, skip, target, |v| {
            T::from_int(v as u32 as i32 as i64)
        }),
        Element::U32 => fill::<N, T, _>(plain, shuffled, skip, target, |v| T::from_int(v as i64)),
        Element::I64 | Element::U64 => {
            fill::<N, T, _>(plain, shuffled, skip, target, |v| T::from_int(v as i64))
        }
        Element::F32 => fill::<N, T, _>(plain, shuffled, skip, target, |v| {
            T::from_float(f32::from_bits(v as u32) as f64)
        }),
        Element::F64 => fill::<N, T, _>(plain, shuffled, skip, target, |v| {
            T::from_float(f64::from_bits(v))
        }),
    }
}

/// The loop of [`decode_elements`]: each element's `N` little-endian bytes as a `u64`, converted.
#[inline(always)]
fn fill<const N: usize, T, F: Fn(u64) -> T>(
    plain: &[u8],
    shuffled: bool,
    skip: usize,
    target: &mut [T],
    convert: F,
) {
    let len = target.len();
    if shuffled {
        let n = plain.len() / N;
        let planes: [&[u8]; N] = std::array::from_fn(|b| &plain[b * n + skip..b * n + skip + len]);
        let mut start = 0;
        if N == 8 {
            // Eight 8-byte elements at a time: eight words, one per plane, transposed as an
            // 8 x 8 byte matrix.
            while start + 8 <= len {
                let mut words = plane_words(&planes, start);
                let words: &mut [u64; 8] = (&mut words[..]).try_into().expect("eight planes");
                transpose_bytes(words);
                for (value, &word) in target[start..start + 8].iter_mut().zip(words.iter()) {
                    *value = convert(word);
                }
                start += 8;
            }
        }
        if N == 4 {
            // Eight 4-byte elements at a time: a word of eight bytes per plane, transposed as two
            // 4 x 4 byte matrices side by side (elements 0-3 in the low halves, 4-7 in the high).
            while start + 8 <= len {
                let mut words = plane_words(&planes, start);
                let words: &mut [u64; 4] = (&mut words[..]).try_into().expect("four planes");
                transpose_bytes_4(words);
                for (c, &word) in words.iter().enumerate() {
                    target[start + c] = convert(word & 0xFFFF_FFFF);
                    target[start + 4 + c] = convert(word >> 32);
                }
                start += 8;
            }
        }
        for (k, value) in target.iter_mut().enumerate().skip(start) {
            let mut v = 0u64;
            for (b, plane) in planes.iter().enumerate() {
                v |= (plane[k] as u64) << (8 * b);
            }
            *value = convert(v);
        }
    } else {
        let elements = plain[skip * N..(skip + len) * N].chunks_exact(N);
        for (value, bytes) in target.iter_mut().zip(elements) {
            let mut v = 0u64;
            for (b, &byte) in bytes.iter().enumerate() {
                v |= (byte as u64) << (8 * b);
            }
            *value = convert(v);
        }
    }
}

/// Bytes `start..start + 8` of each plane as a little-endian word.
#[inline(always)]
fn plane_words<const N: usize>(planes: &[&[u8]; N], start: usize) -> [u64; N] {
    std::array::from_fn(|b| {
        let bytes: [u8; 8] = planes[b][start..start + 8].try_into().expect("8 bytes");
        u64::from_le_bytes(bytes)
    })
}

/// Transpose the two 4 x 4 byte matrices held side by side in `words` (row `r` is `words[r]`'s
/// low four bytes for the first, its high four for the second): afterwards byte `r` of each half
/// of `words[c]` is what byte `c` of that half of `words[r]` was.
#[inline(always)]
pub(crate) fn transpose_bytes_4(words: &mut [u64; 4]) {
    for r in [0, 1] {
        let (a, b) = (words[r], words[r + 2]);
        words[r] = (a & 0x0000_FFFF_0000_FFFF) | ((b & 0x0000_FFFF_0000_FFFF) << 16);
        words[r + 2] = (b & 0xFFFF_0000_FFFF_0000) | ((a & 0xFFFF_0000_FFFF_0000) >> 16);
    }
    for r in [0, 2] {
        let (a, b) = (words[r], words[r + 1]);
        words[r] = (a & 0x00FF_00FF_00FF_00FF) | ((b & 0x00FF_00FF_00FF_00FF) << 8);
        words[r + 1] = (b & 0xFF00_FF00_FF00_FF00) | ((a & 0xFF00_FF00_FF00_FF00) >> 8);
    }
}

/// Transpose the 8 x 8 byte matrix whose row `r` is `words[r]` (byte `c` its column `c`, little
/// endian): afterwards byte `r` of `words[c]` is what byte `c` of `words[r]` was. Off-diagonal
/// blocks of 4, then 2, then 1 bytes are swapped.
#[inline(always)]
pub(crate) fn transpose_bytes(words: &mut [u64; 8]) {
    for r in 0..4 {
        let (a, b) = (words[r], words[r + 4]);
        words[r] = (a & 0x0000_0000_FFFF_FFFF) | (b << 32);
        words[r + 4] = (b & 0xFFFF_FFFF_0000_0000) | (a >> 32);
    }
    for r in [0, 1, 4, 5] {
        let (a, b) = (words[r], words[r + 2]);
        words[r] = (a & 0x0000_FFFF_0000_FFFF) | ((b & 0x0000_FFFF_0000_FFFF) << 16);
        words[r + 2] = (b & 0xFFFF_0000_FFFF_0000) | ((a & 0xFFFF_0000_FFFF_0000) >> 16);
    }
    for r in [0, 2, 4, 6] {
        let (a, b) = (words[r], words[r + 1]);
        words[r] = (a & 0x00FF_00FF_00FF_00FF) | ((b & 0x00FF_00FF_00FF_00FF) << 8);
        words[r + 1] = (b & 0xFF00_FF00_FF00_FF00) | ((a & 0xFF00_FF00_FF00_FF00) >> 8);
    }
}

/// Open the file at `path` for positioned reads.
pub fn open_raw(path: &Path) -> Result<File> {
    File::open(path).map_err(|e| Error::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wide_elements_are_unshuffled_eight_at_a_time_and_one_by_one() {
        // shuffled by the writer's filter (its own implementation), decoded at every offset
        // and length: the transposed blocks of eight and the element-by-element tail agree
        let values: Vec<i64> = (0..53i64)
            .map(|k| (k * 0x0123_4567_89ab_cdef_i64).wrapping_mul(k + 1) ^ (k << 40))
            .collect();
        let shuffled = crate::io::matrices::cool::chunk_writer::shuffle(&values);
        for skip in [0, 1, 7, 8, 13] {
            for len in [0, 1, 8, 9, 16, 40 - skip.min(8)] {
                let mut target = vec![0i64; len];
                decode_elements::<8, i64>(&shuffled, true, Element::I64, skip, &mut target);
                assert_eq!(target, values[skip..skip + len], "skip {skip} len {len}");
            }
        }
        // 4-byte elements (cooler's int32 counts), signed and float
        let ints: Vec<i32> = values.iter().map(|&v| (v >> 13) as i32).collect();
        let shuffled_ints = crate::io::matrices::cool::chunk_writer::shuffle(&ints);
        for skip in [0, 1, 7, 8, 13] {
            for len in [0, 1, 8, 9, 16, 40 - skip.min(8)] {
                let mut target = vec![0i64; len];
                decode_elements::<4, i64>(&shuffled_ints, true, Element::I32, skip, &mut target);
                let want: Vec<i64> = ints[skip..skip + len].iter().map(|&v| v as i64).collect();
                assert_eq!(target, want, "int32 skip {skip} len {len}");
            }
        }
        let floats: Vec<f64> = values.iter().map(|&v| v as f64 / 7.0).collect();
        let shuffled = crate::io::matrices::cool::chunk_writer::shuffle(&floats);
        let mut target = vec![0.0f64; 50];
        decode_elements::<8, f64>(&shuffled, true, Element::F64, 3, &mut target);
        assert_eq!(target, floats[3..53]);
    }

    #[test]
    fn shuffled_elements_are_decoded_from_the_byte_planes() {
        // Elements 0x0102, 0x0304, 0x0506 (little-endian) shuffled: low bytes then high bytes,
        // then a trailing byte.
        let shuffled = [0x02, 0x04, 0x06, 0x01, 0x03, 0x05, 0xff];
        let mut target = [0i64; 2];
        decode_elements::<2, i64>(&shuffled, true, Element::U16, 1, &mut target);
        assert_eq!(target, [0x0304, 0x0506]);
        let plain = [0x02, 0x01, 0x04, 0x03, 0x06, 0x05];
        let mut target = [0i64; 3];
        decode_elements::<2, i64>(&plain, false, Element::I16, 0, &mut target);
        assert_eq!(target, [0x0102, 0x0304, 0x0506]);
    }
}
