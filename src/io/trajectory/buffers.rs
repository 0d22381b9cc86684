//! Position buffers used again: a trajectory's frames all have the same size, so the buffers of
//! the conformations worked on are kept for the next frames read.

use super::frame::Conformation;

/// Position buffers of conformations worked on, for the next frames read: a trajectory's frames
/// all have the same size, and a buffer used again costs no page faults (80 kB a frame of an
/// all-atom protein; fresh memory made page faults half the time of a `ca` measure).
static SPARE_POSITIONS: std::sync::Mutex<Vec<Vec<[f64; 3]>>> = std::sync::Mutex::new(Vec::new());

/// At most this many positions are kept in [`SPARE_POSITIONS`] (32 MB).
const SPARE_COORDINATES: usize = (32 << 20) / std::mem::size_of::<[f64; 3]>();

/// Whether a reader took a buffer from [`SPARE_POSITIONS`] (the text readers do not: nothing
/// is kept for them).
static SPARE_DRAWN: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Keep the position buffers of `chunk` for [`positions_buffer`], up to [`SPARE_COORDINATES`],
/// once a reader draws from them.
pub(super) fn recycle(chunk: Vec<Conformation>) {
    if !SPARE_DRAWN.load(std::sync::atomic::Ordering::Relaxed) {
        return;
    }
    let Ok(mut spare) = SPARE_POSITIONS.lock() else {
        return;
    };
    let mut held: usize = spare.iter().map(Vec::capacity).sum();
    for conformation in chunk {
        let mut positions = conformation.positions;
        if held + positions.capacity() > SPARE_COORDINATES {
            break;
        }
        held += positions.capacity();
        positions.clear();
        spare.push(positions);
    }
}

/// An empty position buffer with room for `n` beads: a recycled one when there is one.
pub(crate) fn positions_buffer(n: usize) -> Vec<[f64; 3]> {
    SPARE_DRAWN.store(true, std::sync::atomic::Ordering::Relaxed);
    let recycled = SPARE_POSITIONS
        .lock()
        .ok()
        .and_then(|mut spare| spare.pop());
    let mut positions = recycled.unwrap_or_default();
    positions.reserve(n);
    positions
}
