//! GROMACS XTC trajectories, decoded by the `molly` crate (pure Rust, the XTC reader that
//! GROMACS users benchmark against xdrfile; see DESIGN notes). Positions are in nanometres,
//! as written; each frame's box vectors become the conformation's cell.
//!
//! molly trusts its input (it asserts on impossible values), so each frame's header and the
//! start of its compressed block are checked here first (magic number, the atom count against
//! the first frame's and the bytes left, the size index), and a decoding that still fails is
//! reported as a corrupt frame, naming it, instead of stopping the program.

use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use super::{checked, positions_buffer, Conformation, LengthUnit};
use crate::error::{Error, Result};

/// The frames of an XTC file.
pub struct XtcFrames {
    path: PathBuf,
    reader: molly::XTCReader<std::io::BufReader<std::fs::File>>,
    length: u64,
    natoms: Option<usize>,
    frame: usize,
    decoded: molly::Frame,
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
        let corrupt = |why: String| Error::Invalid(format!("{label}: {why}"));
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
        if natoms > 9 {
            match word(21) {
                None => return Err(corrupt("truncated frame".into())),
                Some(small) if !(0..73).contains(&small) => {
                    return Err(corrupt(format!(
                        "corrupt compressed coordinates (size index {small})"
                    )))
                }
                Some(_) => {}
            }
        }
        let result = quietly(|| self.reader.read_frame(&mut self.decoded));
        match result {
            Some(Ok(())) => {}
            Some(Err(e)) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
                return Err(corrupt("truncated frame (the file ends inside it)".into()))
            }
            Some(Err(e)) => return Err(corrupt(format!("unreadable frame ({e})"))),
            None => return Err(corrupt("corrupt compressed coordinates".into())),
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

impl super::ReadFrame for XtcFrames {
    fn read_frame(&mut self) -> Result<Option<Conformation>> {
        self.next_frame()
    }
}
