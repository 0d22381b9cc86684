//! Protein structures from PDB and mmCIF files: chains of residues with atom coordinates.
//!
//! [`read_structure`] reads a `.pdb` / `.ent` or `.cif` / `.mmcif` file (optionally gzipped,
//! `.gz`); the format is taken from the content (an mmCIF file starts with `data_`), so the
//! extension does not matter. The parser is hand-written (fixed PDB columns, and the
//! `_atom_site` loop of mmCIF) because the few rules below are the whole point of the reader
//! and must be exactly those of the contact-scoring references (see `data/protein/README.md`).
//!
//! Conventions:
//!
//! - **First model only**: PDB records after the first `ENDMDL`, and mmCIF rows whose
//!   `pdbx_PDB_model_num` differs from the first row's, are ignored.
//! - **First alternate location only**: an atom whose name already occurs in its residue is
//!   ignored, so the first altloc written (blank or `A` in practice) wins.
//! - **Author numbering**: residue numbers are the author numbers (PDB columns 23-26, mmCIF
//!   `auth_seq_id`), with the insertion code (PDB column 27, `pdbx_PDB_ins_code`) kept apart;
//!   chains are the author chain ids (PDB column 22, `auth_asym_id`).
//! - **Which residues are kept**: the 20 standard amino acids (and `UNK`, one-letter `X`),
//!   whether written as `ATOM` or `HETATM`, and the modified amino acids of
//!   [`MODIFIED_RESIDUES`] (for example `MSE`, selenomethionine, kept as `MET`), which are
//!   renamed to their parent. Everything else is ignored: waters, ligands, ions, nucleotides,
//!   and modified residues that are not in the table. In particular `PCA` (pyroglutamic acid,
//!   the first residue of 1DTX / toxd) is **dropped**, as the CASP-style reference computation
//!   (method P of the test data) does: it is a cyclised glutamate without a free backbone amine
//!   and is absent from the ATOM records.
//! - Elements come from PDB columns 77-78 (mmCIF `type_symbol`), or from the atom name when
//!   those are blank.
//!
//! Parsing errors name the file and the 1-based line.

use std::collections::HashSet;
use std::io::Read;
use std::path::Path;

use crate::error::{Error, Result};

/// A residue number: an integer of at most [`MAX_RESIDUE_NUMBER`] in magnitude.
fn residue_number(text: &str) -> Option<i32> {
    text.parse::<i32>()
        .ok()
        .filter(|n| n.unsigned_abs() <= MAX_RESIDUE_NUMBER)
}

/// The message for a bad residue number (`place`: where it was read, for PDB's columns).
fn bad_number(text: &str, place: &str) -> String {
    format!(
        "residue number '{text}'{place} is not an integer of at most {MAX_RESIDUE_NUMBER} in \
         magnitude"
    )
}

/// The largest residue number accepted, in magnitude (titin, the longest protein, has about
/// 35,000 residues): larger numbers are corrupt fields, and numbering spans are allocated.
pub const MAX_RESIDUE_NUMBER: u32 = 1_000_000;

/// Modified amino acids kept as their parent residue: `(name in the file, parent name)`.
///
/// Residues not in this table and not standard are ignored. `PCA` is deliberately absent (see
/// the module docs).
pub const MODIFIED_RESIDUES: &[(&str, &str)] = &[
    ("MSE", "MET"), // selenomethionine
    ("SEP", "SER"), // phosphoserine
    ("TPO", "THR"), // phosphothreonine
    ("PTR", "TYR"), // phosphotyrosine
    ("CSO", "CYS"), // S-hydroxycysteine
    ("CME", "CYS"), // S,S-(2-hydroxyethyl)thiocysteine
    ("MLY", "LYS"), // N-dimethyl-lysine
    ("M3L", "LYS"), // N-trimethyl-lysine
    ("HYP", "PRO"), // 4-hydroxyproline
    ("KCX", "LYS"), // lysine NZ-carboxylic acid
    // protonation states named by MD force fields (CHARMM, AMBER), as MDTraj reads them
    ("HSD", "HIS"),
    ("HSE", "HIS"),
    ("HSP", "HIS"),
    ("HID", "HIS"),
    ("HIE", "HIS"),
    ("HIP", "HIS"),
    ("CYX", "CYS"),
];

const STANDARD_RESIDUES: &[(&str, char)] = &[
    ("ALA", 'A'),
    ("ARG", 'R'),
    ("ASN", 'N'),
    ("ASP", 'D'),
    ("CYS", 'C'),
    ("GLN", 'Q'),
    ("GLU", 'E'),
    ("GLY", 'G'),
    ("HIS", 'H'),
    ("ILE", 'I'),
    ("LEU", 'L'),
    ("LYS", 'K'),
    ("MET", 'M'),
    ("PHE", 'F'),
    ("PRO", 'P'),
    ("SER", 'S'),
    ("THR", 'T'),
    ("TRP", 'W'),
    ("TYR", 'Y'),
    ("VAL", 'V'),
    ("UNK", 'X'),
];

/// A chain id as messages and reports show it: `(blank)` for the blank id.
pub fn chain_label(id: &str) -> &str {
    if id.is_empty() { "(blank)" } else { id }
}

/// The parent residue name and its one-letter code for a residue name found in a file, or
/// `None` when the residue is not an amino acid this reader keeps.
pub fn amino_acid(name: &str) -> Option<(&'static str, char)> {
    let parent = MODIFIED_RESIDUES
        .iter()
        .find(|(modified, _)| *modified == name)
        .map_or(name, |(_, parent)| parent);
    STANDARD_RESIDUES
        .iter()
        .find(|(standard, _)| *standard == parent)
        .map(|(standard, code)| (*standard, *code))
}

/// One atom.
#[derive(Clone, Debug, PartialEq)]
pub struct Atom {
    /// Atom name, e.g. `CA`, `CB`, `OG1` (PDB columns 13-16, trimmed).
    pub name: String,
    /// Element symbol, upper case, e.g. `C`, `SE`.
    pub element: String,
    /// Cartesian coordinates in Angstrom.
    pub xyz: [f64; 3],
}

impl Atom {
    /// True for hydrogen and deuterium.
    pub fn is_hydrogen(&self) -> bool {
        self.element == "H" || self.element == "D"
    }
}

/// One amino-acid residue.
#[derive(Clone, Debug, PartialEq)]
pub struct Residue {
    /// Author residue number.
    pub number: i32,
    /// Insertion code, if any.
    pub insertion: Option<char>,
    /// Three-letter name of the (parent) amino acid: `MSE` is stored as `MET`.
    pub name: String,
    /// One-letter code of the parent amino acid (`X` for `UNK`).
    pub one_letter: char,
    /// Atoms, first alternate location only, in file order.
    pub atoms: Vec<Atom>,
}

impl Residue {
    /// The atom called `name`, if present.
    pub fn atom(&self, name: &str) -> Option<&Atom> {
        self.atoms.iter().find(|atom| atom.name == name)
    }
}

/// One chain of amino-acid residues, in file order.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// Author chain id.
    pub id: String,
    /// Observed residues.
    pub residues: Vec<Residue>,
}

impl Chain {
    /// One-letter sequence of the observed residues.
    pub fn sequence(&self) -> String {
        self.residues
            .iter()
            .map(|residue| residue.one_letter)
            .collect()
    }
}

/// The protein chains of the first model of a structure.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Structure {
    /// Chains with at least one amino-acid residue, in file order.
    pub chains: Vec<Chain>,
}

impl Structure {
    /// The chain `id`, or the first protein chain when `id` is `None`.
    pub fn chain(&self, id: Option<&str>) -> Result<&Chain> {
        match id {
            None => self
                .chains
                .first()
                .ok_or_else(|| Error::Data("the structure has no protein chain".into())),
            Some(id) => self
                .chains
                .iter()
                .find(|chain| chain.id == id)
                .ok_or_else(|| {
                    let ids: Vec<&str> =
                        self.chains.iter().map(|chain| chain.id.as_str()).collect();
                    Error::Data(format!(
                        "the structure has no protein chain '{id}' (chains: {})",
                        ids.join(", ")
                    ))
                }),
        }
    }
}

/// Read a PDB or mmCIF file (optionally gzipped); see the module docs.
///
/// # Examples
///
/// ```
/// let structure = contactmap::io::structure::read_structure("data/protein/1aapA/1aapA.pdb.gz")?;
/// let chain = structure.chain(None)?; // the only chain (its id is blank in this file)
/// assert!(chain.sequence().starts_with("VREVCSEQ"));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn read_structure(path: impl AsRef<Path>) -> Result<Structure> {
    let path = path.as_ref();
    parse_structure(&structure_text(path)?, path)
}

/// Read the structure at `path` and select one chain, as [`Structure::chain`] selects it (errors
/// name the file).
///
/// ```
/// let chain = contactmap::io::structure::read_chain("data/protein/1aapA/1aapA.pdb.gz", None)?;
/// assert!(chain.sequence().starts_with("VREVCSEQ"));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn read_chain(path: impl AsRef<Path>, chain: Option<&str>) -> Result<Chain> {
    let path = path.as_ref();
    Ok(read_structure(path)?
        .chain(chain)
        .map_err(|err| err.in_file(path))?
        .clone())
}

/// The text of a PDB or mmCIF file (gzip detected from its content; bytes that are not UTF-8
/// replaced, as old PDB files hold a few).
pub fn structure_text(path: &Path) -> Result<String> {
    let mut bytes = Vec::new();
    crate::io::plumbing::input::open_text(path)?
        .read_to_end(&mut bytes)
        .map_err(|err| Error::io(path, err))?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// Parse the text of a PDB or mmCIF file; `path` is used in messages only.
pub fn parse_structure(text: &str, path: &Path) -> Result<Structure> {
    first_model(text, path, for_each_atom_site)
}

/// Accumulates atoms into residues and chains.
#[derive(Default)]
struct Builder {
    chains: Vec<Chain>,
    /// (chain, number, insertion, file residue name) of the residue being filled.
    current: Option<(String, i32, Option<char>, String)>,
}

struct AtomRecord<'a> {
    chain: &'a str,
    number: i32,
    insertion: Option<char>,
    residue_name: &'a str,
    atom: Atom,
}

impl Builder {
    fn push(&mut self, record: AtomRecord<'_>) {
        let Some((parent, one_letter)) = amino_acid(record.residue_name) else {
            return;
        };
        let same = self
            .current
            .as_ref()
            .is_some_and(|(chain, number, insertion, name)| {
                chain == record.chain
                    && *number == record.number
                    && *insertion == record.insertion
                    && name == record.residue_name
            });
        if !same {
            self.current = Some((
                record.chain.to_string(),
                record.number,
                record.insertion,
                record.residue_name.to_string(),
            ));
            if self
                .chains
                .last()
                .is_none_or(|chain| chain.id != record.chain)
            {
                self.chains.push(Chain {
                    id: record.chain.to_string(),
                    residues: Vec::new(),
                });
            }
            let chain = self.chains.last_mut().expect("pushed above");
            chain.residues.push(Residue {
                number: record.number,
                insertion: record.insertion,
                name: parent.to_string(),
                one_letter,
                atoms: Vec::new(),
            });
        }
        let chain = self.chains.last_mut().expect("a residue was started");
        let residue = chain.residues.last_mut().expect("a residue was started");
        residue.atoms.push(record.atom);
    }

    fn finish(self) -> Structure {
        // A chain id may reappear after other chains (rare, e.g. after TER and ligands of
        // another chain): merge such pieces so that a chain id names one chain.
        let mut chains: Vec<Chain> = Vec::new();
        for chain in self.chains {
            match chains.iter_mut().find(|known| known.id == chain.id) {
                Some(known) => known.residues.extend(chain.residues),
                None => chains.push(chain),
            }
        }
        Structure { chains }
    }
}

fn element_from_name(name: &str) -> String {
    // PDB atom names of the standard residues start with the element (one letter for
    // protein atoms); selenium in MSE is "SE".
    if name == "SE" {
        return "SE".into();
    }
    name.chars()
        .find(|c| c.is_ascii_alphabetic())
        .map(|c| c.to_ascii_uppercase().to_string())
        .unwrap_or_default()
}

/// A coordinate of `atom` (described on error only): a finite number. `NaN` and `inf` parse as
/// floats but would silently drop the atom's contacts (every distance comparison fails), so they
/// are refused, naming the atom.
fn parse_coordinate(
    text: &str,
    path: &Path,
    line: u64,
    what: &str,
    atom: impl Fn() -> String,
) -> Result<f64> {
    let text = text.trim();
    match text.parse::<f64>() {
        Ok(value) if value.is_finite() => Ok(value),
        Ok(_) => Err(Error::parse(
            path,
            line,
            format!(
                "{what} of {} is '{}': coordinates must be finite numbers",
                atom(),
                text.escape_default()
            ),
        )),
        Err(_) => Err(Error::parse(
            path,
            line,
            format!("{what} '{}' is not a number", text.escape_default()),
        )),
    }
}

/// One atom record as read, of any model: a PDB `ATOM` / `HETATM` record or an mmCIF
/// `_atom_site` row, with the residue name as written (`MSE`, `HSD`, `HOH` ...).
#[derive(Clone, Debug, PartialEq)]
pub struct AtomSite<'a> {
    /// The model, counted from 0 (PDB: the `ENDMDL` records before it; mmCIF: the changes of
    /// `pdbx_PDB_model_num` before it).
    pub model: usize,
    /// Author chain id.
    pub chain: &'a str,
    /// Author residue number.
    pub number: i32,
    /// Insertion code, if any.
    pub insertion: Option<char>,
    /// The residue name as written.
    pub residue_name: &'a str,
    /// The atom (its element from the file, else from its name).
    pub atom: Atom,
    /// The 1-based line of the record (of the row's first line in mmCIF).
    pub line: u64,
    /// PDB: a `TER` record since the previous atom of the model (a chain ends there).
    pub after_ter: bool,
}

/// Call `site` with every atom record of a PDB or mmCIF text, in file order, whose residue name
/// passes `keep` (records of other residues are skipped unparsed, so a malformed water does not
/// stop a protein reader), first alternate location only; `site` returns `false` to stop.
/// Errors name `path` and the line.
pub fn for_each_atom_site(
    text: &str,
    path: &Path,
    keep: &dyn Fn(&str) -> bool,
    site: &mut dyn FnMut(AtomSite<'_>) -> Result<bool>,
) -> Result<()> {
    let first = text.lines().find(|line| !line.trim().is_empty());
    if first.is_some_and(|line| line.trim_start().starts_with("data_")) {
        mmcif_sites(text, path, keep, site)
    } else {
        pdb_sites(text, path, keep, site)
    }
}

/// The first alternate location rule of the module docs, applied to the sites as they are read:
/// an atom whose name already occurs in its residue (same model, chain, number, insertion code
/// and residue name, no `TER` between) is a later alternate location and is not passed on.
#[derive(Default)]
struct FirstLocation {
    residue: Option<(usize, String, i32, Option<char>, String)>,
    names: HashSet<String>,
}

impl FirstLocation {
    /// True when `site` is the first location of its atom.
    fn first(&mut self, site: &AtomSite<'_>) -> bool {
        let same = !site.after_ter
            && self
                .residue
                .as_ref()
                .is_some_and(|(model, chain, number, insertion, name)| {
                    *model == site.model
                        && chain == site.chain
                        && *number == site.number
                        && *insertion == site.insertion
                        && name == site.residue_name
                });
        if !same {
            self.residue = Some((
                site.model,
                site.chain.to_string(),
                site.number,
                site.insertion,
                site.residue_name.to_string(),
            ));
            self.names.clear();
        }
        self.names.insert(site.atom.name.clone())
    }
}

/// The PDB records of [`for_each_atom_site`] (fixed columns).
fn pdb_sites(
    text: &str,
    path: &Path,
    keep: &dyn Fn(&str) -> bool,
    site: &mut dyn FnMut(AtomSite<'_>) -> Result<bool>,
) -> Result<()> {
    let mut model = 0;
    let mut atoms_in_model = false;
    let mut after_ter = false;
    let mut locations = FirstLocation::default();
    for (index, line) in text.lines().enumerate() {
        let line_number = index as u64 + 1;
        if line.starts_with("ENDMDL") {
            if atoms_in_model {
                model += 1;
            }
            atoms_in_model = false;
            after_ter = false;
            continue;
        }
        if line.starts_with("TER") {
            after_ter = true;
            continue;
        }
        if !(line.starts_with("ATOM  ") || line.starts_with("HETATM")) {
            continue;
        }
        let field = |start: usize, end: usize| line.get(start..end.min(line.len())).unwrap_or("");
        if line.len() < 54 || !line.is_char_boundary(54) {
            return Err(Error::parse(
                path,
                line_number,
                "ATOM/HETATM record shorter than 54 columns (coordinates end at column 54)",
            ));
        }
        atoms_in_model = true;
        let residue_name = field(17, 20).trim();
        if !keep(residue_name) {
            continue;
        }
        let name = field(12, 16).trim().to_string();
        let number_text = field(22, 26).trim();
        let number = residue_number(number_text).ok_or_else(|| {
            Error::parse(
                path,
                line_number,
                bad_number(number_text, " (columns 23-26)"),
            )
        })?;
        let insertion = field(26, 27).chars().next().filter(|c| *c != ' ');
        let atom = || {
            format!(
                "atom {name} of {residue_name} {number_text}{} chain '{}'",
                insertion.map(String::from).unwrap_or_default(),
                field(21, 22).trim()
            )
        };
        let xyz = [
            parse_coordinate(field(30, 38), path, line_number, "x (columns 31-38)", atom)?,
            parse_coordinate(field(38, 46), path, line_number, "y (columns 39-46)", atom)?,
            parse_coordinate(field(46, 54), path, line_number, "z (columns 47-54)", atom)?,
        ];
        let element = match field(76, 78).trim() {
            "" => element_from_name(&name),
            symbol => symbol.to_ascii_uppercase(),
        };
        let record = AtomSite {
            model,
            chain: field(21, 22).trim(),
            number,
            insertion,
            residue_name,
            atom: Atom { name, element, xyz },
            line: line_number,
            after_ter,
        };
        after_ter = false;
        if locations.first(&record) && !site(record)? {
            break;
        }
    }
    Ok(())
}

/// A reader of atom sites: [`for_each_atom_site`], [`pdb_sites`] or [`mmcif_sites`].
type SiteReader = fn(
    &str,
    &Path,
    &dyn Fn(&str) -> bool,
    &mut dyn FnMut(AtomSite<'_>) -> Result<bool>,
) -> Result<()>;

/// The amino-acid residues of the first model of `sites`' text (see the module docs).
fn first_model(text: &str, path: &Path, sites: SiteReader) -> Result<Structure> {
    let mut builder = Builder::default();
    let keep = |name: &str| amino_acid(name).is_some();
    sites(text, path, &keep, &mut |site| {
        if site.model > 0 {
            return Ok(false);
        }
        builder.push(AtomRecord {
            chain: site.chain,
            number: site.number,
            insertion: site.insertion,
            residue_name: site.residue_name,
            atom: site.atom,
        });
        Ok(true)
    })?;
    Ok(builder.finish())
}

/// Parse PDB `ATOM` / `HETATM` records (fixed columns) of the first model.
pub fn parse_pdb(text: &str, path: &Path) -> Result<Structure> {
    first_model(text, path, pdb_sites)
}

/// Split one line of a CIF loop into tokens (whitespace separated; `'...'` and `"..."` quoted
/// values end at a matching quote followed by whitespace or the end of the line).
fn cif_tokens(line: &str) -> Vec<&str> {
    let bytes = line.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i].is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let quote = bytes[i];
        if quote == b'\'' || quote == b'"' {
            let start = i + 1;
            let mut end = start;
            while end < bytes.len()
                && !(bytes[end] == quote
                    && (end + 1 == bytes.len() || bytes[end + 1].is_ascii_whitespace()))
            {
                end += 1;
            }
            tokens.push(&line[start..end.min(bytes.len())]);
            i = end + 1;
        } else {
            let start = i;
            while i < bytes.len() && !bytes[i].is_ascii_whitespace() {
                i += 1;
            }
            tokens.push(&line[start..i]);
        }
    }
    tokens
}

/// Parse the `_atom_site` loop of an mmCIF file (first model).
pub fn parse_mmcif(text: &str, path: &Path) -> Result<Structure> {
    first_model(text, path, mmcif_sites)
}

/// The `_atom_site` rows of [`for_each_atom_site`].
fn mmcif_sites(
    text: &str,
    path: &Path,
    keep: &dyn Fn(&str) -> bool,
    site: &mut dyn FnMut(AtomSite<'_>) -> Result<bool>,
) -> Result<()> {
    let lines: Vec<&str> = text.lines().collect();
    // Find the `_atom_site.` header of a loop, skipping semicolon text fields.
    let mut in_text_field = false;
    let mut header_start = None;
    for (index, line) in lines.iter().enumerate() {
        if line.starts_with(';') {
            in_text_field = !in_text_field;
            continue;
        }
        if !in_text_field && line.trim_start().starts_with("_atom_site.") {
            header_start = Some(index);
            break;
        }
    }
    let Some(header_start) = header_start else {
        return Err(Error::format(path, "mmCIF file without an _atom_site loop"));
    };
    if header_start == 0 || lines[header_start - 1].trim() != "loop_" {
        return Err(Error::parse(
            path,
            header_start as u64 + 1,
            "_atom_site is not a loop_ (single-atom mmCIF files are not supported)",
        ));
    }
    let mut columns = Vec::new();
    let mut index = header_start;
    while index < lines.len() && lines[index].trim_start().starts_with("_atom_site.") {
        let name = lines[index].trim().trim_start_matches("_atom_site.");
        columns.push(name.split_whitespace().next().unwrap_or("").to_string());
        index += 1;
    }
    let column = |names: &[&str]| {
        names
            .iter()
            .find_map(|n| columns.iter().position(|c| c == n))
    };
    let require = |names: &[&str]| {
        column(names).ok_or_else(|| {
            Error::parse(
                path,
                header_start as u64 + 1,
                format!("_atom_site loop without a {} column", names.join(" or ")),
            )
        })
    };
    let group = require(&["group_PDB"])?;
    let x = require(&["Cartn_x"])?;
    let y = require(&["Cartn_y"])?;
    let z = require(&["Cartn_z"])?;
    let atom_name = require(&["auth_atom_id", "label_atom_id"])?;
    let residue_name = require(&["auth_comp_id", "label_comp_id"])?;
    let chain = require(&["auth_asym_id", "label_asym_id"])?;
    let number = require(&["auth_seq_id", "label_seq_id"])?;
    let insertion = column(&["pdbx_PDB_ins_code"]);
    let element = column(&["type_symbol"]);
    let model = column(&["pdbx_PDB_model_num"]);

    let mut model_index = 0;
    let mut current_model: Option<String> = None;
    let mut locations = FirstLocation::default();
    let mut row: Vec<&str> = Vec::with_capacity(columns.len());
    let mut row_line = index as u64 + 1;
    while index < lines.len() {
        let line = lines[index];
        let line_number = index as u64 + 1;
        index += 1;
        let trimmed = line.trim_start();
        if row.is_empty()
            && (trimmed.starts_with('_')
                || trimmed.starts_with("loop_")
                || trimmed.starts_with('#')
                || trimmed.starts_with("data_"))
        {
            break;
        }
        if trimmed.is_empty() {
            continue;
        }
        if row.is_empty() {
            row_line = line_number;
        }
        row.extend(cif_tokens(line));
        if row.len() < columns.len() {
            continue;
        }
        if row.len() > columns.len() {
            return Err(Error::parse(
                path,
                row_line,
                format!(
                    "_atom_site row with {} values, expected {}",
                    row.len(),
                    columns.len()
                ),
            ));
        }
        if let Some(model) = model {
            match &current_model {
                None => current_model = Some(row[model].to_string()),
                Some(current) if current != row[model] => {
                    model_index += 1;
                    current_model = Some(row[model].to_string());
                }
                Some(_) => {}
            }
        }
        let group_name = row[group];
        if (group_name == "ATOM" || group_name == "HETATM") && keep(row[residue_name]) {
            let number_text = row[number];
            let residue_number = residue_number(number_text)
                .ok_or_else(|| Error::parse(path, row_line, bad_number(number_text, "")))?;
            let insertion_code = insertion
                .map(|column| row[column])
                .filter(|code| *code != "?" && *code != ".")
                .and_then(|code| code.chars().next());
            let name = row[atom_name].to_string();
            let element_symbol = element
                .map(|column| row[column])
                .filter(|symbol| *symbol != "?" && *symbol != ".")
                .map_or_else(|| element_from_name(&name), str::to_ascii_uppercase);
            let atom = || {
                format!(
                    "atom {name} of {} {residue_number}{} chain '{}'",
                    row[residue_name],
                    insertion_code.map(String::from).unwrap_or_default(),
                    row[chain]
                )
            };
            let xyz = [
                parse_coordinate(row[x], path, row_line, "Cartn_x", atom)?,
                parse_coordinate(row[y], path, row_line, "Cartn_y", atom)?,
                parse_coordinate(row[z], path, row_line, "Cartn_z", atom)?,
            ];
            let record = AtomSite {
                model: model_index,
                chain: row[chain],
                number: residue_number,
                insertion: insertion_code,
                residue_name: row[residue_name],
                atom: Atom {
                    name,
                    element: element_symbol,
                    xyz,
                },
                line: row_line,
                after_ter: false,
            };
            if locations.first(&record) && !site(record)? {
                return Ok(());
            }
        }
        row.clear();
    }
    if !row.is_empty() {
        return Err(Error::parse(
            path,
            row_line,
            format!(
                "incomplete _atom_site row: {} values, expected {}",
                row.len(),
                columns.len()
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/protein");

    #[test]
    fn pdb_and_mmcif_of_1a8o_agree() {
        let pdb = read_structure(format!("{DATA}/1a8o/1A8O.pdb.gz")).unwrap();
        let cif = read_structure(format!("{DATA}/1a8o/1A8O.cif.gz")).unwrap();
        assert_eq!(pdb.chains.len(), 1);
        assert_eq!(pdb, cif);
        let chain = pdb.chain(None).unwrap();
        assert_eq!(chain.id, "A");
        assert_eq!(chain.residues.len(), 70);
        assert_eq!(chain.residues[0].number, 151);
        assert_eq!(chain.residues[69].number, 220);
        let fasta = std::fs::read_to_string(format!("{DATA}/1a8o/1A8O.fasta")).unwrap();
        assert_eq!(chain.sequence(), fasta.lines().nth(1).unwrap().trim());
        // The four selenomethionines are kept as MET, with their selenium atom.
        let mse: Vec<i32> = chain
            .residues
            .iter()
            .filter(|residue| residue.atom("SE").is_some())
            .map(|residue| residue.number)
            .collect();
        assert_eq!(mse.len(), 4);
        for number in mse {
            let residue = chain.residues.iter().find(|r| r.number == number).unwrap();
            assert_eq!((residue.name.as_str(), residue.one_letter), ("MET", 'M'));
            assert_eq!(residue.atom("SE").unwrap().element, "SE");
        }
    }

    #[test]
    fn toxd_drops_pca_waters_and_sulfate() {
        let structure = read_structure(format!("{DATA}/toxd/toxd.pdb.gz")).unwrap();
        assert_eq!(structure.chains.len(), 1);
        let chain = structure.chain(Some("A")).unwrap();
        let numbers: Vec<i32> = chain
            .residues
            .iter()
            .map(|residue| residue.number)
            .collect();
        assert_eq!(numbers, (2..=59).collect::<Vec<_>>());
        let fasta = std::fs::read_to_string(format!("{DATA}/toxd/toxd.fasta")).unwrap();
        assert_eq!(chain.sequence(), &fasta.lines().nth(1).unwrap().trim()[1..]);
        assert!(structure.chain(Some("B")).is_err());
    }

    #[test]
    fn first_model_first_altloc_and_insertion_codes() {
        let text = "\
MODEL        1
ATOM      1  N   ALA A  10       1.000   2.000   3.000  1.00  0.00           N
ATOM      2  CA AALA A  10       1.000   2.000   4.000  0.50  0.00           C
ATOM      3  CA BALA A  10       9.000   9.000   9.000  0.50  0.00           C
ATOM      4  CA  GLY A  10A      5.000   5.000   5.000  1.00  0.00           C
HETATM    5  O   HOH A 100       0.000   0.000   0.000  1.00  0.00           O
HETATM    6  CA  PCA A   9       0.000   0.000   0.000  1.00  0.00           C
ENDMDL
MODEL        2
ATOM      7  CA  SER A  11       0.000   0.000   0.000  1.00  0.00           C
ENDMDL
";
        let structure = parse_pdb(text, Path::new("test.pdb")).unwrap();
        let residues = &structure.chains[0].residues;
        assert_eq!(residues.len(), 2);
        assert_eq!(residues[0].atoms.len(), 2);
        assert_eq!(residues[0].atom("CA").unwrap().xyz, [1.0, 2.0, 4.0]);
        assert_eq!((residues[1].number, residues[1].insertion), (10, Some('A')));
    }

    #[test]
    fn errors_name_file_and_line() {
        let text = "HEADER\nATOM      1  CA  ALA A  1x      1.000   2.000   3.000\n";
        let err = parse_pdb(text, Path::new("bad.pdb")).unwrap_err();
        assert!(matches!(err, Error::Parse { line: 2, .. }), "{err}");
        assert!(err.to_string().starts_with("bad.pdb:2:"), "{err}");
        let text = "data_x\nloop_\n_atom_site.group_PDB\n_atom_site.Cartn_x\n";
        let err = parse_mmcif(text, Path::new("bad.cif")).unwrap_err();
        assert!(err.to_string().contains("Cartn_y"), "{err}");
    }

    #[test]
    fn non_finite_coordinates_are_errors_naming_the_atom() {
        // Rust parses "nan" and "inf" as floats; every distance to such an atom compares false,
        // which would silently drop its contacts.
        let text = "\
ATOM      1  N   ALA A  10       1.000   2.000   3.000  1.00  0.00           N
ATOM      2  CA  GLY A  10A      5.000     NaN   5.000  1.00  0.00           C
";
        let err = parse_pdb(text, Path::new("nan.pdb")).unwrap_err();
        assert_eq!(
            err.to_string(),
            "nan.pdb:2: y (columns 39-46) of atom CA of GLY 10A chain 'A' is 'NaN': coordinates \
             must be finite numbers"
        );
        let text = "\
ATOM      1  N   ALA A  10      -inf     2.000   3.000  1.00  0.00           N
";
        let err = parse_pdb(text, Path::new("inf.pdb")).unwrap_err();
        assert!(
            err.to_string().starts_with(
                "inf.pdb:1: x (columns 31-38) of atom N of ALA 10 chain 'A' is '-inf'"
            ),
            "{err}"
        );
        let cif = |z: &str| {
            format!(
                "data_x\nloop_\n_atom_site.group_PDB\n_atom_site.auth_atom_id\n\
                 _atom_site.auth_comp_id\n_atom_site.auth_asym_id\n_atom_site.auth_seq_id\n\
                 _atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n\
                 ATOM CA ALA B 7 1.0 2.0 3.0\nATOM CB ALA B 7 1.0 2.0 {z}\n"
            )
        };
        let structure = parse_mmcif(&cif("4.5"), Path::new("ok.cif")).unwrap();
        assert_eq!(
            structure.chain(Some("B")).unwrap().residues[0]
                .atom("CB")
                .unwrap()
                .xyz,
            [1.0, 2.0, 4.5]
        );
        let err = parse_mmcif(&cif("infinity"), Path::new("inf.cif")).unwrap_err();
        assert_eq!(
            err.to_string(),
            "inf.cif:12: Cartn_z of atom CB of ALA 7 chain 'B' is 'infinity': coordinates must \
             be finite numbers"
        );
    }

    #[test]
    fn cif_tokens_handle_quotes() {
        assert_eq!(
            cif_tokens("ATOM 1 O \"O5'\" 'a b' x"),
            vec!["ATOM", "1", "O", "O5'", "a b", "x"]
        );
    }
}
