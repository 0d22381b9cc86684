//! polychrom's HDF5 trajectories, read by the layout `polychrom/hdf5_format.py` writes: a
//! trajectory folder holds files `blocks_X-Y.h5`, each with blocks X to Y (inclusive) as groups
//! `/X` .. `/Y`; a block's conformation is its dataset `pos` (`N x 3`, any float type). polychrom
//! names a block by the URI `path/blocks_X-Y.h5::K`.
//!
//! Inputs: a folder (its `blocks_*-*.h5` files in block order; a block listed by two files is an
//! error, as in polychrom's `list_URIs`), one blocks file (its numbered groups, in number order),
//! or one URI. A block the file's name promises but the file lacks, a `pos` that is not `N x 3`,
//! an empty block or a non-finite coordinate is an error naming `file::block`.
//!
//! [`write_blocks`] writes conformations in this layout (what `simulate polymer
//! --conformations-format polychrom` writes), so that polychrom's own loader opens them.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::buffers::positions_buffer;
use super::frame::{Conformation, LengthUnit, checked};
use crate::error::{Error, Result};
use crate::io::matrices::cool::chunks::Column;
use crate::io::plumbing::hdf5_guard::guarded;

/// Blocks per file of polychrom's `HDF5Reporter` (`max_data_length`).
pub const BLOCKS_PER_FILE: usize = 50;

/// The block range `X..=Y` of a file named `blocks_X-Y.h5`.
pub fn block_range(path: &Path) -> Option<(u64, u64)> {
    let name = path.file_name()?.to_str()?;
    let range = name.strip_prefix("blocks_")?.strip_suffix(".h5")?;
    let (first, last) = range.split_once('-')?;
    Some((first.parse().ok()?, last.parse().ok()?))
}

/// The blocks files of a trajectory folder, in block order, with their ranges.
fn folder_files(folder: &Path) -> Result<Vec<(PathBuf, (u64, u64))>> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(folder).map_err(|e| Error::io(folder, e))? {
        let path = entry.map_err(|e| Error::io(folder, e))?.path();
        if let Some(range) = block_range(&path) {
            files.push((path, range));
        }
    }
    if files.is_empty() {
        return Err(Error::format(
            folder,
            "no polychrom blocks file (blocks_X-Y.h5) in this folder",
        ));
    }
    files.sort_by_key(|(_, (first, _))| *first);
    for pair in files.windows(2) {
        let ((a, (_, a_last)), (b, (b_first, _))) = (&pair[0], &pair[1]);
        if b_first <= a_last {
            return Err(Error::format(
                folder,
                format!(
                    "block {b_first} is in two files, {} and {}",
                    a.display(),
                    b.display()
                ),
            ));
        }
    }
    Ok(files)
}

/// What is still to read: files, each with the blocks to read from it (`None`: its numbered
/// groups).
type Plan = Vec<(PathBuf, Option<Vec<u64>>)>;

/// The conformations of a polychrom input, read a file at a time: the blocks' `pos` chunks
/// are inflated in parallel (libhdf5 would inflate them one at a time, behind its lock), so the
/// memory held is one file's blocks (polychrom writes 50 per file), and the next file is opened
/// (its chunk indexes read) meanwhile.
pub struct PolychromBlocks {
    plan: std::vec::IntoIter<(PathBuf, Option<Vec<u64>>)>,
    read: std::collections::VecDeque<Result<Conformation>>,
    /// The next file, opened while the last one was inflated.
    ahead: Option<Result<OpenedFile>>,
}

impl PolychromBlocks {
    /// Open a folder, a blocks file or a `file::block` URI (see the module docs).
    pub fn open(input: &str) -> Result<PolychromBlocks> {
        let plan: Plan = match input.split_once("::") {
            Some((file, block)) => {
                let block: u64 = block.trim_start_matches('/').parse().map_err(|_| {
                    Error::Argument(format!(
                        "{input}: a polychrom URI ends with a block number (blocks_1-50.h5::42)"
                    ))
                })?;
                if Path::new(file).is_dir() {
                    return Err(Error::Argument(format!(
                        "{input}: {file} is a folder; a polychrom URI names a blocks file and \
                         a block (blocks_1-50.h5::42)"
                    )));
                }
                vec![(PathBuf::from(file), Some(vec![block]))]
            }
            None => {
                let path = Path::new(input);
                if path.is_dir() {
                    folder_files(path)?
                        .into_iter()
                        .map(|(file, (first, last))| (file, Some((first..=last).collect())))
                        .collect()
                } else {
                    let blocks = block_range(path).map(|(first, last)| (first..=last).collect());
                    vec![(path.to_path_buf(), blocks)]
                }
            }
        };
        Ok(PolychromBlocks {
            plan: plan.into_iter(),
            read: std::collections::VecDeque::new(),
            ahead: None,
        })
    }

    fn open_file(path: &Path, blocks: Option<Vec<u64>>) -> Result<(hdf5::File, Vec<u64>)> {
        let text = path.to_string_lossy().into_owned();
        let file = guarded(&text, "the file", || {
            crate::io::matrices::cool::file_builder().open(path)
        })
        .map_err(|e| Error::hdf5(path, "opening the polychrom blocks file", e))?;
        let blocks = match blocks {
            Some(blocks) => blocks,
            None => {
                let names = guarded(&text, "the group names", || file.member_names())
                    .map_err(|e| Error::hdf5(path, "listing the blocks", e))?;
                let mut blocks: Vec<u64> = names.iter().filter_map(|n| n.parse().ok()).collect();
                blocks.sort_unstable();
                if blocks.is_empty() {
                    return Err(Error::format(
                        path,
                        "no block in this file (polychrom stores blocks as groups /1, /2 ... with \
                         a dataset pos)",
                    ));
                }
                blocks
            }
        };
        Ok((file, blocks))
    }

    /// The `pos` column of `block`, its shape checked.
    fn block_column(path: &Path, file: &hdf5::File, block: u64) -> Result<Column> {
        let label = format!("{}::{block}", path.display());
        let text = path.to_string_lossy().into_owned();
        if !guarded(&text, "a block", || file.link_exists(&block.to_string())) {
            return Err(Error::Data(format!(
                "{label}: no block {block} in this file (polychrom's blocks are groups /0, /1 \
                 ... each with a dataset pos)"
            )));
        }
        let dataset =
            guarded(&text, "a block", || file.dataset(&format!("{block}/pos"))).map_err(|_| {
                Error::Data(format!(
                    "{label}: no dataset pos in block {block} (polychrom's blocks are groups \
                     with a dataset pos of N x 3 positions)"
                ))
            })?;
        let shape = dataset.shape();
        if shape.len() != 2 || shape[1] != 3 {
            return Err(Error::Data(format!(
                "{label}: pos has shape {shape:?}; expected N x 3 positions"
            )));
        }
        if shape[0] == 0 {
            return Err(Error::Data(format!(
                "{label}: an empty block (pos has no position)"
            )));
        }
        Column::rows(dataset, &format!("{block}/pos"), &text, 3)
    }

    /// Open the blocks of one file (libhdf5's part: the file, each block's `pos`, its chunk
    /// index), stopping at the first bad block.
    fn open_blocks(path: PathBuf, blocks: Option<Vec<u64>>) -> Result<OpenedFile> {
        let (file, blocks) = Self::open_file(&path, blocks)?;
        let raw = crate::io::matrices::cool::chunks::open_raw(&path)?;
        let mut columns = Vec::with_capacity(blocks.len());
        let mut failure = None;
        for &block in &blocks {
            match Self::block_column(&path, &file, block) {
                Ok(column) => columns.push((block, column)),
                Err(error) => {
                    failure = Some(error);
                    break;
                }
            }
        }
        Ok(OpenedFile {
            path,
            _file: file,
            raw,
            columns,
            failure,
        })
    }

    /// The conformations of an opened file, their chunks inflated in parallel.
    fn inflate(opened: Result<OpenedFile>) -> Vec<Result<Conformation>> {
        let opened = match opened {
            Ok(opened) => opened,
            Err(error) => return vec![Err(error)],
        };
        let mut read: Vec<Result<Conformation>> = opened
            .columns
            .par_iter()
            .map(|(block, column)| {
                let label = format!("{}::{block}", opened.path.display());
                let values: Vec<f64> = column.read(&opened.raw, 0, column.len())?;
                let mut positions = positions_buffer(values.len() / 3);
                positions.extend(values.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
                checked(label, positions, None, LengthUnit::Model)
            })
            .collect();
        if let Some(error) = opened.failure {
            read.push(Err(error));
        }
        read
    }
}

/// One blocks file opened: its blocks' `pos` columns ready to inflate.
struct OpenedFile {
    path: PathBuf,
    /// The libhdf5 file, open while its columns are.
    _file: hdf5::File,
    /// The file for the raw chunk reads.
    raw: std::fs::File,
    columns: Vec<(u64, Column)>,
    /// The bad block that ended the opening, after the good ones.
    failure: Option<Error>,
}

impl Iterator for PolychromBlocks {
    type Item = Result<Conformation>;

    fn next(&mut self) -> Option<Result<Conformation>> {
        loop {
            if let Some(next) = self.read.pop_front() {
                return Some(next);
            }
            let current = match self.ahead.take() {
                Some(opened) => opened,
                None => {
                    let (path, blocks) = self.plan.next()?;
                    Self::open_blocks(path, blocks)
                }
            };
            // the next file is opened (libhdf5, one thread) while this one is inflated (the
            // pool): the opening is off the critical path on many cores
            let following = self.plan.next();
            let (read, ahead) = std::thread::scope(|scope| {
                let inflating = scope.spawn(|| Self::inflate(current));
                let ahead = following.map(|(path, blocks)| Self::open_blocks(path, blocks));
                let read = inflating.join().expect("inflating a file does not panic");
                (read, ahead)
            });
            self.read = read.into();
            self.ahead = ahead;
        }
    }
}

/// Write `conformations` (all with the same number of beads) into the folder `folder` as
/// polychrom's `HDF5Reporter` does: `blocks_X-Y.h5` files of [`BLOCKS_PER_FILE`] blocks, block
/// `K` (from 0, as polychrom counts them) the group `/K` with its dataset `pos` (`N x 3`, float64, gzip) and the attribute
/// `block`. Each file is written under a temporary name and renamed when complete. Returns the
/// files written.
pub fn write_blocks(folder: &Path, conformations: &[Vec<[f64; 3]>]) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(folder).map_err(|e| Error::io(folder, e))?;
    let mut written = Vec::new();
    for (index, chunk) in conformations.chunks(BLOCKS_PER_FILE).enumerate() {
        let first = index * BLOCKS_PER_FILE;
        let last = first + chunk.len() - 1;
        let path = folder.join(format!("blocks_{first}-{last}.h5"));
        crate::io::plumbing::atomic::with_temporary(
            &path,
            crate::io::matrices::cool::create_excl,
            |tmp, file| {
                for (k, positions) in chunk.iter().enumerate() {
                    let block = first + k;
                    let group = file
                        .create_group(&block.to_string())
                        .map_err(|e| Error::hdf5(tmp, "writing a block", e))?;
                    let flat: Vec<f64> = positions.iter().flatten().copied().collect();
                    group
                        .new_dataset::<f64>()
                        .shape((positions.len(), 3))
                        .deflate(9)
                        .create("pos")
                        .and_then(|pos| pos.write_raw(&flat))
                        .map_err(|e| Error::hdf5(tmp, "writing pos", e))?;
                    group
                        .new_attr::<u64>()
                        .create("block")
                        .and_then(|a| a.write_scalar(&(block as u64)))
                        .map_err(|e| Error::hdf5(tmp, "writing the block attribute", e))?;
                }
                Ok(())
            },
        )?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 120 conformations in three files (50, 50, 20): read in order, each file opened while
    /// the last is inflated; a bad block or an unreadable file in the middle ends the stream
    /// after every conformation before it, in order.
    #[test]
    fn files_are_read_in_order_and_errors_come_in_place() {
        let dir = tempfile::tempdir().unwrap();
        let conformations: Vec<Vec<[f64; 3]>> = (0..120)
            .map(|k| (0..4).map(|b| [k as f64, b as f64, 0.5]).collect())
            .collect();
        let folder = dir.path().join("run");
        assert_eq!(write_blocks(&folder, &conformations).unwrap().len(), 3);
        let labels = |input: &Path| -> Vec<std::result::Result<f64, String>> {
            PolychromBlocks::open(&input.to_string_lossy())
                .unwrap()
                .map(|c| c.map(|c| c.positions[0][0]).map_err(|e| e.to_string()))
                .collect()
        };
        let all = labels(&folder);
        let want: Vec<std::result::Result<f64, String>> = (0..120).map(|k| Ok(k as f64)).collect();
        assert_eq!(all, want);
        // block 60 loses its positions: 0..=59, then the error naming it
        {
            let file = hdf5::File::open_rw(folder.join("blocks_50-99.h5")).unwrap();
            file.unlink("60/pos").unwrap();
        }
        let read = labels(&folder);
        assert_eq!(&read[..60], &want[..60]);
        let error = read[60].as_ref().unwrap_err();
        assert!(
            error.contains("blocks_50-99.h5::60: no dataset pos"),
            "{error}"
        );
        // the second file is not HDF5: the first file's 50, then the error naming the file
        std::fs::write(folder.join("blocks_50-99.h5"), b"not hdf5").unwrap();
        let read = labels(&folder);
        assert_eq!(&read[..50], &want[..50]);
        let error = read[50].as_ref().unwrap_err();
        assert!(error.contains("blocks_50-99.h5"), "{error}");
    }
}
