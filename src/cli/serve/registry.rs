//! The files `serve` was given, opened once at start: each with a readable, stable UID made
//! from its file name. Nothing a request says reaches the filesystem: a request names a UID,
//! and only UIDs listed here answer.

use std::path::{Path, PathBuf};

use serde_json::Value;

use contactmap::error::{Error, Result};
use contactmap::genome::Chrom;
use contactmap::io::bed::{read_bed_table, read_bedpe_table};
use contactmap::io::{FileKind, detect_kind, open_levels};
use contactmap::tiles::{Intervals, Norms, Rectangles, Tileset, Vector};

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
    /// A bedGraph or a table's column: 1D vector tiles.
    Vector(Vector),
    /// A BEDPE file's anchor pairs: 2D (and 1D) rectangle tiles.
    Rectangles(Rectangles),
}

impl Entry {
    /// clodius' tileset_info of the file.
    pub fn info(&self) -> Value {
        match &self.data {
            Data::Map(tileset) => tileset.info(),
            Data::Intervals(intervals) => intervals.info(),
            Data::Vector(vector) => vector.info(),
            Data::Rectangles(rectangles) => rectangles.info(),
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
            Data::Vector(_) => "a 1D track".into(),
            Data::Rectangles(_) => "BEDPE rectangles".into(),
        }
    }
}

/// The files served, in the order given.
pub struct Registry {
    pub entries: Vec<Entry>,
}

impl Registry {
    /// Open `paths`: maps (.mcool, .cool, .hic), BED files (.bed) and 1D tracks (.bedgraph, or
    /// a table's column, `table.tsv::COLUMN`; each may be gzip'd), each track on the genome of the
    /// first map that has all its chromosomes. Every file must open: a file that
    /// does not is an error naming it, and the server does not start.
    pub fn open(paths: &[PathBuf]) -> Result<Registry> {
        let mut entries: Vec<Entry> = Vec::with_capacity(paths.len());
        let (tracks, maps): (Vec<&PathBuf>, Vec<&PathBuf>) = paths
            .iter()
            .partition(|p| is_bed(p) || is_bedpe(p) || vector_column(p).is_some());
        for path in maps {
            let entry = open_map(path)?;
            let uid = unique(&entry.uid, &entries);
            entries.push(Entry { uid, ..entry });
        }
        for path in tracks {
            let entry = match vector_column(path) {
                Some(column) => open_vector(path, column, &entries)?,
                None if is_bedpe(path) => open_bedpe(path, &entries)?,
                None => open_bed(path, &entries)?,
            };
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

/// The genome (chromosomes, coordinate system) of the first map served that has every chromosome
/// in `names`.
fn genome_for<'a>(
    names: impl Iterator<Item = &'a str> + Clone,
    maps: &[Entry],
    text: &str,
) -> Result<(Vec<Chrom>, String)> {
    let genome = maps.iter().find_map(|entry| {
        let Data::Map(tileset) = &entry.data else {
            return None;
        };
        let chroms: Vec<Chrom> = tileset.reader(0)?.bins().chroms().to_vec();
        let all = names
            .clone()
            .all(|name| chroms.iter().any(|c| c.name == name));
        all.then_some((chroms, entry.coord_system.clone()))
    });
    genome.ok_or_else(|| {
        Error::Argument(format!(
            "{text}: no map served has all its chromosomes (serve a track with its map: \
             contactmap serve map.mcool domains.bed)"
        ))
    })
}

/// A BEDPE file, by its name (`.bedpe`, `.bedpe.gz`).
fn is_bedpe(path: &Path) -> bool {
    let name = path.to_string_lossy().to_ascii_lowercase();
    name.ends_with(".bedpe") || name.ends_with(".bedpe.gz")
}

/// A BEDPE file on the genome of the first map served that has every chromosome it names.
fn open_bedpe(path: &Path, maps: &[Entry]) -> Result<Entry> {
    let text = path.to_string_lossy().into_owned();
    let table = read_bedpe_table(path)?;
    let names = table
        .records
        .iter()
        .flat_map(|r| [r.first.chrom.as_str(), r.second.chrom.as_str()]);
    let (chroms, coord_system) = genome_for(names, maps, &text)?;
    let fields: Vec<Vec<String>> = table.records.iter().map(|r| r.fields()).collect();
    let data = Rectangles::new(&chroms, &fields, table.header.as_deref(), &text)?;
    Ok(Entry {
        uid: uid_of(path),
        name: file_name(path),
        path: path.to_path_buf(),
        filetype: "bedpe",
        datatype: "2d-rectangle-domains",
        coord_system,
        data: Data::Rectangles(data),
    })
}

/// A BED file on the genome of the first map served that has every chromosome it names.
fn open_bed(path: &Path, maps: &[Entry]) -> Result<Entry> {
    let text = path.to_string_lossy().into_owned();
    let table = read_bed_table(path)?;
    let (chroms, coord_system) =
        genome_for(table.records.iter().map(|r| r.chrom.as_str()), maps, &text)?;
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

/// Where a 1D track's values are: `Some(None)` for a bedGraph (the 4th column), `Some(Some(name))`
/// for a table's column (`table.tsv::name`, or the first of the columns contactmap's tables lead
/// with), `None` for anything else.
fn vector_column(path: &Path) -> Option<Option<String>> {
    let text = path.to_string_lossy();
    let (file, column) = match text.rsplit_once("::") {
        Some((file, column)) => (file.to_ascii_lowercase(), Some(column.to_string())),
        None => (text.to_ascii_lowercase(), None),
    };
    let file = file.strip_suffix(".gz").unwrap_or(&file);
    if [".bedgraph", ".bg"].iter().any(|e| file.ends_with(e)) && column.is_none() {
        return Some(None);
    }
    if file.ends_with(".tsv") {
        return Some(Some(column.unwrap_or_default()));
    }
    None
}

/// The columns a table's track defaults to, by prefix: insulation, eigenvectors, coverage.
const DEFAULT_COLUMNS: [&str; 3] = ["log2_insulation_score_", "E1", "cov_cis_raw"];

/// A bedGraph, or a table's column, on the genome of the first map served that has all its
/// chromosomes.
fn open_vector(path: &Path, column: Option<String>, maps: &[Entry]) -> Result<Entry> {
    let spec = path.to_string_lossy().into_owned();
    let file = PathBuf::from(spec.rsplit_once("::").map_or(spec.as_str(), |(f, _)| f));
    let table = read_bed_table(&file)?;
    let index = match &column {
        None => 3,
        Some(name) => {
            let header = table.header.as_ref().ok_or_else(|| {
                Error::Argument(format!("{}: a table needs a header line", file.display()))
            })?;
            let found = if name.is_empty() {
                header
                    .iter()
                    .position(|h| DEFAULT_COLUMNS.iter().any(|p| h.starts_with(p)))
            } else {
                header.iter().position(|h| h == name)
            };
            found.ok_or_else(|| {
                Error::Argument(format!(
                    "{}: no column {} (the table has: {}); name one as {}::COLUMN",
                    file.display(),
                    if name.is_empty() {
                        "to show by default".to_string()
                    } else {
                        format!("'{name}'")
                    },
                    header.join(", "),
                    file.display()
                ))
            })?
        }
    };
    let mut records = Vec::with_capacity(table.records.len());
    for (k, (record, fields)) in table.records.iter().zip(&table.fields).enumerate() {
        let text = fields.get(index).map(String::as_str).unwrap_or("");
        let value = match text {
            "" | "nan" | "NaN" | "NA" | "." => f64::NAN,
            _ => text.parse::<f64>().map_err(|_| {
                Error::Data(format!(
                    "{}: record {}: '{text}' is not a number",
                    file.display(),
                    k + 1
                ))
            })?,
        };
        records.push((record.chrom.clone(), record.start, record.end, value));
    }
    let (chroms, coord_system) =
        genome_for(table.records.iter().map(|r| r.chrom.as_str()), maps, &spec)?;
    let name = match &column {
        Some(c) if !c.is_empty() => format!("{} {c}", file_name(&file)),
        Some(_) => format!(
            "{} {}",
            file_name(&file),
            table.header.as_ref().map_or("", |h| h[index].as_str())
        ),
        None => file_name(&file),
    };
    Ok(Entry {
        uid: uid_of(&file),
        name,
        path: file.clone(),
        filetype: "bigwig",
        datatype: "vector",
        coord_system,
        data: Data::Vector(Vector::new(&chroms, &records, &spec)?),
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
                "{text}: not a .cool, .mcool, .hic, .bed, .bedpe or .bedgraph file (serve shows contact maps and their \
                 tracks; convert a text table with `contactmap convert` first)"
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
