//! Frames read a chunk at a time, each chunk worked on by another thread while the next is read.

use super::buffers::recycle;
use super::frame::Conformation;
use crate::error::Result;

/// Read `frames` a chunk of `size` frames at a time and give each chunk to `work` on another
/// thread while this one reads the next, so that reading overlaps the work. `keep(index, frame)`
/// sees every frame as it is read (`index` counts from 0): an error stops everything, `false`
/// leaves the frame out of the chunks (a stride). Returns the number of frames worked on.
pub fn for_each_chunk(
    frames: &mut dyn Iterator<Item = Result<Conformation>>,
    size: usize,
    mut keep: impl FnMut(usize, &Conformation) -> Result<bool>,
    mut work: impl FnMut(&[Conformation]) + Send,
) -> Result<usize> {
    let mut index = 0;
    let mut read = || -> Result<Vec<Conformation>> {
        let mut chunk = Vec::with_capacity(size);
        while chunk.len() < size.max(1) {
            let Some(frame) = frames.next() else { break };
            let frame = frame?;
            index += 1;
            if keep(index - 1, &frame)? {
                chunk.push(frame);
            }
        }
        Ok(chunk)
    };
    let mut total = 0;
    let mut chunk = read()?;
    while !chunk.is_empty() {
        let next = std::thread::scope(|scope| {
            let working = scope.spawn(|| work(&chunk));
            let next = read();
            working.join().expect("the work on a chunk does not panic");
            next
        })?;
        total += chunk.len();
        recycle(std::mem::replace(&mut chunk, next));
    }
    Ok(total)
}
