//! The files `serve` was given, opened once at start: each with a readable, stable UID made
//! from its file name. Nothing a request says reaches the filesystem: a request names a UID,
//! and only UIDs listed here answer.

use std::path::{Path, PathBuf};

use serde_json::Value;

use contactmap::error::{Error, Result};
use contactmap::genome::Chrom;
use contactmap::io::bed::read_bed_table;
use contactmap::io::{FileKind, detect_kind, open_levels};
use contactmap::tiles::{Intervals, Norms, Tileset};

/// One file served.
pub struct Entry {
    /// The UID the API names it by (from the file name).
    pub uid: String,
    /// The file's name, shown in the viewer.
    pub name: String,
    /// The path given at start.
    pub path: PathBuf,
    /// higlass-server's `filetype` (`cooler`, `hic`, `bedfile`).
    pub filetype: &'static str,
    /// higlass-server's `datatype` (`matrix`, `bedlike`).
    pub datatype: &'static str,
    /// The assembly the file names, else the UID (HiGlass pairs tracks by coordinate system); a
    /// track takes its map's.
    pub coord_system: String,
    /// What is cut into tiles.
    pub data: Data,
}

/// A served file's content.
pub enum Data {
    /// A contact map: 2D tiles.
    Map(Tileset),
    /// A BED file's intervals: 1D interval tiles.
    Intervals(Intervals),
}

impl Entry {
    /// clodius' tileset_info of the file.
    pub fn info(&self) -> Value {
        match &self.data {
            Data::Map(tileset) => tileset.info(),
            Data::Intervals(intervals) => intervals.info(),
        }
    }

    /// What the server prints of it at start.
    pub fn describe(&self) -> String {
        match &self.data {
            Data::Map(tileset) => format!(
                "{}, {} resolution(s)",
                self.filetype,
                tileset.resolutions().len()
            ),
            Data::Intervals(_) => "BED intervals".into(),
        }
    }
}

/// The files served, in the order given.
pub struct Registry {
    pub entries: Vec<Entry>,
}

impl Registry {
    /// Open `paths`: maps (.mcool, .cool, .hic) and BED files (.bed, .bed.gz), each BED on the
    /// genome of the first map that has all its chromosomes. Every file must open: a file that
    /// does not is an error naming it, and the server does not start.
    pub fn open(paths: &[PathBuf]) -> Result<Registry> {
        let mut entries: Vec<Entry> = Vec::with_capacity(paths.len());
        let (beds, maps): (Vec<&PathBuf>, Vec<&PathBuf>) = paths.iter().partition(|p| is_bed(p));
        for path in maps {
            let entry = open_map(path)?;
            let uid = unique(&entry.uid, &entries);
            entries.push(Entry { uid, ..entry });
        }
        for path in beds {
            let entry = open_bed(path, &entries)?;
            let uid = unique(&entry.uid, &entries);
            entries.push(Entry { uid, ..entry });
        }
        Ok(Registry { entries })
    }

    /// The entry named `uid`.
    pub fn get(&self, uid: &str) -> Option<&Entry> {
        self.entries.iter().find(|e| e.uid == uid)
    }
}

/// The UID of a file: its name up to the first dot, every character but letters, digits, `-`
/// and `_` made `_` (`GM12878.hg19.mcool` -> `GM12878`).
pub fn uid_of(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = name.split('.').next().unwrap_or_default();
    let uid: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if uid.is_empty() { "map".into() } else { uid }
}

/// `uid`, or `uid-2`, `uid-3` ... when an earlier file took it.
fn unique(uid: &str, entries: &[Entry]) -> String {
    let taken = |candidate: &str| entries.iter().any(|e| e.uid == candidate);
    if !taken(uid) {
        return uid.to_string();
    }
    (2..)
        .map(|k| format!("{uid}-{k}"))
        .find(|c| !taken(c))
        .expect("an unused suffix")
}

/// A BED file, by its name (`.bed`, `.bed.gz`).
fn is_bed(path: &Path) -> bool {
    let name = path.to_string_lossy().to_ascii_lowercase();
    name.ends_with(".bed") || name.ends_with(".bed.gz")
}

/// A BED file on the genome of the first map served that has every chromosome it names.
fn open_bed(path: &Path, maps: &[Entry]) -> Result<Entry> {
    let text = path.to_string_lossy().into_owned();
    let table = read_bed_table(path)?;
    let genome = maps.iter().find_map(|entry| {
        let Data::Map(tileset) = &entry.data else {
            return None;
        };
        let chroms: Vec<Chrom> = tileset.reader(0)?.bins().chroms().to_vec();
        let all = table
            .records
            .iter()
            .all(|r| chroms.iter().any(|c| c.name == r.chrom));
        all.then_some((chroms, entry.coord_system.clone()))
    });
    let Some((chroms, coord_system)) = genome else {
        return Err(Error::Argument(format!(
            "{text}: no map served has all its chromosomes (serve a BED file with its map: \
             contactmap serve map.mcool domains.bed)"
        )));
    };
    Ok(Entry {
        uid: uid_of(path),
        name: file_name(path),
        path: path.to_path_buf(),
        filetype: "bedfile",
        datatype: "bedlike",
        coord_system,
        data: Data::Intervals(Intervals::new(&chroms, &table.fields, &text)?),
    })
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.to_string_lossy().into_owned())
}

fn open_map(path: &Path) -> Result<Entry> {
    let text = path.to_string_lossy().into_owned();
    if text.contains("::") {
        return Err(Error::Argument(format!(
            "{text}: serve takes whole files (an .mcool or .hic serves all its resolutions)"
        )));
    }
    let filetype = match detect_kind(&text)? {
        FileKind::Hdf5 => "cooler",
        FileKind::Hic => "hic",
        FileKind::Text => {
            return Err(Error::Argument(format!(
                "{text}: not a .cool, .mcool, .hic or .bed file (serve shows contact maps and \
                 BED tracks; convert a text table with `contactmap convert` first)"
            )));
        }
    };
    let (kind, levels) = open_levels(&text)?;
    let norms = Norms::of(kind);
    let uid = uid_of(path);
    let coord_system = levels[0].1.info().assembly().unwrap_or_else(|| uid.clone());
    Ok(Entry {
        uid,
        name: file_name(path),
        path: path.to_path_buf(),
        filetype,
        datatype: "matrix",
        coord_system,
        data: Data::Map(Tileset::new(levels, norms)?),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uids_are_the_file_names_first_word() {
        assert_eq!(uid_of(Path::new("/data/GM12878.hg19.mcool")), "GM12878");
        assert_eq!(uid_of(Path::new("a b+c.cool")), "a_b_c");
        assert_eq!(uid_of(Path::new(".hidden.cool")), "map");
    }
}
