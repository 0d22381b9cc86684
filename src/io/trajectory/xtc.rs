//! GROMACS XTC trajectories, decoded by the `molly` crate (pure Rust, the XTC reader that
//! GROMACS users benchmark against xdrfile; see DESIGN notes). Positions are in nanometres,
//! as written; each frame's box vectors become the conformation's cell.
//!
//! molly trusts its input (it asserts on impossible values and stops quietly at a run of atoms
//! past the frame's end), so each frame's header and the start of its compressed block are
//! checked here first (magic number, the atom count against the first frame's and the bytes
//! left, the precision, the integer ranges, the size index, the block's byte count against the
//! bytes left), a decoding that fails is reported as a corrupt frame, naming it, instead of
//! stopping the program, and a decoding must use exactly the block's bytes: the check that
//! catches a corrupt block which MDTraj's "Buffer overrun during decompression" catches, and
//! more (a run cut short leaves bytes unread; a corrupt byte count leaves too few or too many).

use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use molly::selection::AtomSelection;

use super::buffers::positions_buffer;
use super::frame::{Conformation, LengthUnit, checked};
use crate::error::{Error, Result};

/// The frames of an XTC file.
pub struct XtcFrames {
    path: PathBuf,
    reader: molly::XTCReader<std::io::BufReader<std::fs::File>>,
    length: u64,
    natoms: Option<usize>,
    frame: usize,
    decoded: molly::Frame,
    scratch: Vec<u8>,
}

/// The magic number of XTC frames (the 2023 variant, for more than 298 million atoms, too).
const MAGIC: [i32; 2] = [1995, 2023];

impl XtcFrames {
    /// Open the XTC file at `path`.
    pub fn open(path: &Path) -> Result<XtcFrames> {
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
        let length = file.metadata().map_err(|e| Error::io(path, e))?.len();
        let mut frames = XtcFrames {
            path: path.to_path_buf(),
            reader: molly::XTCReader::new(std::io::BufReader::new(file)),
            length,
            natoms: None,
            frame: 0,
            decoded: molly::Frame::default(),
            scratch: Vec::new(),
        };
        let magic = frames.peek(4)?.get(..4).map(be);
        if !magic.is_some_and(|m| MAGIC.contains(&m)) {
            return Err(Error::format(
                path,
                "not an XTC file (no magic number 1995)",
            ));
        }
        Ok(frames)
    }

    /// The next `n` bytes (fewer at the end of the file), the position left where it was.
    fn peek(&mut self, n: usize) -> Result<Vec<u8>> {
        let file = &mut self.reader.file;
        let start = file
            .stream_position()
            .map_err(|e| Error::io(&self.path, e))?;
        let mut bytes = Vec::with_capacity(n);
        file.by_ref()
            .take(n as u64)
            .read_to_end(&mut bytes)
            .map_err(|e| Error::io(&self.path, e))?;
        file.seek(SeekFrom::Start(start))
            .map_err(|e| Error::io(&self.path, e))?;
        Ok(bytes)
    }

    fn next_frame(&mut self) -> Result<Option<Conformation>> {
        let start = self
            .reader
            .file
            .stream_position()
            .map_err(|e| Error::io(&self.path, e))?;
        if start >= self.length {
            return Ok(None);
        }
        self.frame += 1;
        let label = format!("{}:frame {}", self.path.display(), self.frame);
        let corrupt = |why: String| Error::Data(format!("{label}: {why}"));
        // header: magic, natoms, step, time, box (9), natoms again; then for more than 9
        // atoms: precision, minint (3), maxint (3), smallidx
        let head = self.peek(88)?;
        let word = |k: usize| head.get(4 * k..4 * k + 4).map(be);
        let (Some(magic), Some(natoms), Some(again)) = (word(0), word(1), word(13)) else {
            return Err(corrupt(format!(
                "truncated frame (its header cut short at {} bytes)",
                self.length - start
            )));
        };
        if !MAGIC.contains(&magic) {
            return Err(corrupt(format!("bad magic number {magic} (expected 1995)")));
        }
        let expected = *self.natoms.get_or_insert(natoms.max(0) as usize);
        if natoms <= 0 || natoms != again || natoms as usize != expected {
            return Err(corrupt(format!(
                "atom count {natoms} / {again} (the first frame has {expected})"
            )));
        }
        // no encoding spends less than a bit per atom: a larger count is a corrupt header
        if natoms as u64 > 8 * (self.length - start) {
            return Err(corrupt(format!(
                "truncated frame ({natoms} atoms in the {} bytes left)",
                self.length - start
            )));
        }
        let left = self.length - start;
        // the compressed block's byte count: after precision, minint, maxint and smallidx
        // (word 22); a u64 in the 2023 variant
        let count_bytes = if magic == MAGIC[1] { 8 } else { 4 };
        let block_start = 92 + count_bytes - 4;
        let mut count = None;
        if natoms > 9 {
            let head = self.peek(block_start as usize)?;
            if head.len() < block_start as usize {
                return Err(corrupt(format!(
                    "truncated frame (its header cut short at {left} bytes)"
                )));
            }
            let word = |k: usize| be(&head[4 * k..4 * k + 4]);
            let small = word(21);
            let precision = f32::from_bits(word(14) as u32);
            if !(precision.is_finite() && precision > 0.0) {
                return Err(corrupt(format!(
                    "corrupt compressed coordinates (precision {precision})"
                )));
            }
            for axis in 0..3 {
                let (low, high) = (word(15 + axis), word(18 + axis));
                // GROMACS' encoder keeps each range within 31 bits
                if low > high || i64::from(high) - i64::from(low) >= i64::from(i32::MAX) {
                    return Err(corrupt(format!(
                        "corrupt compressed coordinates (integer range {low}..{high} on axis {})",
                        axis + 1
                    )));
                }
            }
            // the size indexes an encoder writes: FIRSTIDX (9) to the last magic integer (72)
            if !(9..73).contains(&small) {
                return Err(corrupt(format!(
                    "corrupt compressed coordinates (size index {small}, expected 9 to 72)"
                )));
            }
            let stated = match count_bytes {
                8 => u64::from_be_bytes(head[88..96].try_into().expect("eight bytes")),
                _ => u64::from(word(22) as u32),
            };
            let padded = stated + (4 - stated % 4) % 4;
            if padded > left - block_start {
                return Err(corrupt(format!(
                    "truncated frame (a compressed block of {stated} bytes, {} left in the file)",
                    left - block_start
                )));
            }
            count = Some(stated as usize);
        }
        let (reader, decoded, scratch) = (&mut self.reader, &mut self.decoded, &mut self.scratch);
        let result = quietly(|| -> std::io::Result<usize> {
            let header = reader.read_header()?;
            decoded.step = header.step;
            decoded.time = header.time;
            decoded.boxvec = header.boxvec;
            if header.natoms <= 9 {
                reader.read_smol_positions(header.natoms, decoded, &AtomSelection::All)
            } else {
                molly::read_positions::<molly::buffer::UnBuffered, _>(
                    &mut reader.file,
                    header.natoms,
                    scratch,
                    decoded,
                    &AtomSelection::All,
                    header.magic,
                )
            }
        });
        let used = match result {
            Some(Ok(used)) => used,
            Some(Err(e)) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
                return Err(corrupt("truncated frame (the file ends inside it)".into()));
            }
            Some(Err(e)) => return Err(corrupt(format!("unreadable frame ({e})"))),
            None => return Err(corrupt("corrupt compressed coordinates".into())),
        };
        // as the reference decoder reads them: the block is consumed exactly, and no run of
        // atoms goes past the frame's atom count (MDTraj: "Buffer overrun during decompression")
        if let Some(count) = count {
            if used != count {
                return Err(corrupt(format!(
                    "corrupt compressed coordinates (decoding used {used} of the block's {count} \
                     bytes)"
                )));
            }
        }
        let mut positions = positions_buffer(expected);
        positions.extend(
            self.decoded
                .positions
                .chunks_exact(3)
                .map(|p| [f64::from(p[0]), f64::from(p[1]), f64::from(p[2])]),
        );
        if positions.len() != expected {
            return Err(corrupt(format!(
                "{} positions decoded, expected {expected}",
                positions.len()
            )));
        }
        // molly's box is column-major: column k is box vector k (GROMACS' rows)
        let b = self.decoded.boxvec;
        let cell = [
            [b[0], b[1], b[2]].map(f64::from),
            [b[3], b[4], b[5]].map(f64::from),
            [b[6], b[7], b[8]].map(f64::from),
        ];
        let cell = cell.iter().flatten().any(|&x| x != 0.0).then_some(cell);
        checked(label, positions, cell, LengthUnit::Nanometre).map(Some)
    }
}

fn be(bytes: &[u8]) -> i32 {
    i32::from_be_bytes(bytes.try_into().expect("four bytes"))
}

thread_local! {
    static QUIET: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Run `f`, turning a panic inside it into `None` without the panic message (molly asserts on
/// corrupt data; the caller reports the frame instead).
fn quietly<T>(f: impl FnOnce() -> T) -> Option<T> {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(std::cell::Cell::get) {
                previous(info);
            }
        }));
    });
    QUIET.with(|quiet| quiet.set(true));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    QUIET.with(|quiet| quiet.set(false));
    result.ok()
}

impl super::frame::ReadFrame for XtcFrames {
    fn read_frame(&mut self) -> Result<Option<Conformation>> {
        self.next_frame()
    }
}
