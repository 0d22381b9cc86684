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

use super::{checked, positions_buffer, Conformation, LengthUnit};
use crate::error::{Error, Result};
use crate::io::cool::chunks::Column;
use crate::io::hdf5_guard::guarded;

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
/// memory held is one file's blocks (polychrom writes 50 per file).
pub struct PolychromBlocks {
    plan: std::vec::IntoIter<(PathBuf, Option<Vec<u64>>)>,
    read: std::collections::VecDeque<Result<Conformation>>,
}

impl PolychromBlocks {
    /// Open a folder, a blocks file or a `file::block` URI (see the module docs).
    pub fn open(input: &str) -> Result<PolychromBlocks> {
        let plan: Plan = match input.split_once("::") {
            Some((file, block)) => {
                let block: u64 = block.trim_start_matches('/').parse().map_err(|_| {
                    Error::Invalid(format!(
                        "{input}: a polychrom URI ends with a block number (blocks_1-50.h5::42)"
                    ))
                })?;
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
        })
    }

    fn open_file(path: &Path, blocks: Option<Vec<u64>>) -> Result<(hdf5::File, Vec<u64>)> {
        let text = path.to_string_lossy().into_owned();
        let file = guarded(&text, "the file", || {
            crate::io::cool::file_builder().open(path)
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
        let dataset =
            guarded(&text, "a block", || file.dataset(&format!("{block}/pos"))).map_err(|_| {
                Error::Invalid(format!(
                    "{label}: no dataset pos in block {block} (polychrom's blocks are groups \
                     with a dataset pos of N x 3 positions)"
                ))
            })?;
        let shape = dataset.shape();
        if shape.len() != 2 || shape[1] != 3 {
            return Err(Error::Invalid(format!(
                "{label}: pos has shape {shape:?}; expected N x 3 positions"
            )));
        }
        if shape[0] == 0 {
            return Err(Error::Invalid(format!(
                "{label}: an empty block (pos has no position)"
            )));
        }
        Column::rows(dataset, &format!("{block}/pos"), &text, 3)
    }

    /// Read the blocks of one file, their chunks inflated in parallel.
    fn read_file(path: &Path, blocks: Option<Vec<u64>>) -> Vec<Result<Conformation>> {
        let (file, blocks) = match Self::open_file(path, blocks) {
            Ok(opened) => opened,
            Err(error) => return vec![Err(error)],
        };
        let raw = match crate::io::cool::chunks::open_raw(path) {
            Ok(raw) => raw,
            Err(error) => return vec![Err(error)],
        };
        // the columns opened in order (libhdf5 calls), stopping at the first bad block
        let mut columns = Vec::with_capacity(blocks.len());
        let mut failure = None;
        for &block in &blocks {
            match Self::block_column(path, &file, block) {
                Ok(column) => columns.push((block, column)),
                Err(error) => {
                    failure = Some(error);
                    break;
                }
            }
        }
        let mut read: Vec<Result<Conformation>> = columns
            .par_iter()
            .map(|(block, column)| {
                let label = format!("{}::{block}", path.display());
                let values: Vec<f64> = column.read(&raw, 0, column.len())?;
                let mut positions = positions_buffer(values.len() / 3);
                positions.extend(values.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
                checked(label, positions, None, LengthUnit::Model)
            })
            .collect();
        if let Some(error) = failure {
            read.push(Err(error));
        }
        read
    }
}

impl Iterator for PolychromBlocks {
    type Item = Result<Conformation>;

    fn next(&mut self) -> Option<Result<Conformation>> {
        loop {
            if let Some(next) = self.read.pop_front() {
                return Some(next);
            }
            let (path, blocks) = self.plan.next()?;
            self.read = Self::read_file(&path, blocks).into();
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
        crate::io::atomic::with_temporary(&path, crate::io::cool::create_excl, |tmp, file| {
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
        })?;
        written.push(path);
    }
    Ok(written)
}
