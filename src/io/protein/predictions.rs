//! Predicted residue contacts: CASP RR, CCMpred / PSICOV matrices, `i j score` tables,
//! trRosetta `.npz` distograms and `.npy` predicted distance maps.
//!
//! Every reader returns a [`Prediction`]: scored residue pairs `(i, j, score)` with 1-based
//! residue numbers in the prediction's own numbering (that of its sequence), where **a higher
//! score means a more confident contact**, and the sequence when the file gives one. Pairs are
//! returned as written (RR, tables) or as the upper triangle `i < j` (matrices, where row `i`
//! and column `j`, 0-based, become residues `i + 1` and `j + 1`); making pairs `i < j`,
//! removing duplicates and ranking is the scorer's job ([`crate::score::contacts`]).
//!
//! | format | [`PredictionFormat`] | rules |
//! |---|---|---|
//! | CASP RR (CASP assessment format; ConEVA, DISTEVAL, PSICOV output) | `Rr` | optional `PFRMAT` / `TARGET` / `AUTHOR` / `REMARK` / `METHOD` / `MODEL` header lines, optional sequence lines (letters only) before the first row, rows `i j score` or `i j d1 d2 score`, `END` or a second `MODEL` stops; residues beyond the sequence are errors |
//! | CCMpred / PSICOV / plain matrix | `Matrix` | whitespace-separated square matrix, `#` lines skipped (ccmpred-py's `#>META>` line), upper triangle |
//! | CASP RR mode 2 (CASP14 distance bins) | `Rr` | as RR, with rows `i j p b1 .. b10`: `p` = P(d < 8 A) is the score, `b1..b10` the probabilities of the bins 0-4, 4-6, ..., 18-20, > 20 A (checked to be numbers); an `RMODE` line is allowed in the header |
//! | table (plmDCA, PSICOV-style lists) | `Table` | rows `i j score`, separated by whitespace or commas (plmDCA writes `i,j,score`), `#` lines skipped |
//! | EVfold / EVcouplings | `Evfold` | rows `i A_i j A_j x score` (`x` is ignored) |
//! | GREMLIN | `Gremlin` | a header `i j i_id j_id r_sco s_sco prob` (or with `gene` after `j`, inter-chain), rows whose `i_id` is `12_M`; the score is `r_sco` |
//!
//! EVfold and GREMLIN name the amino acid of each residue: a residue named twice with different
//! letters is an error, and when every position from 1 to the largest is named the letters give
//! the prediction's sequence (so no FASTA is needed).
//! | trRosetta `.npz` | `Npz` | array `dist` of shape `(L, L, 37)`: bin 0 is `d > 20` A, bins 1..36 cover 2-20 A in 0.5 A steps; the score is `P(d < 8) = sum of bins 1..=12` ([`TRROSETTA_CONTACT_BINS`]), upper triangle |
//! | `.npy` distance map | `Npy` | `(L, L)` or `(L, L, 1)` predicted distances; the score is **minus** the distance (the smallest distance ranks first, as DISTEVAL), upper triangle |
//!
//! [`detect_format`] recognises the format from the content (zip and NumPy magic bytes, then the
//! shape of the first data lines of a text file); an explicit [`PredictionFormat`] overrides it.
//! [`read_prediction`] reads files plain or gzip-compressed (`x.mat.gz`; gzip is recognised from
//! its magic bytes, whatever the name), and detects the format on the decompressed bytes.
//! An `.npz` is a zip of `.npy` files: it is opened with the `zip` crate (deflate through
//! `flate2`, already a dependency); `.npy` headers are parsed here (little-endian `f2`, `f4`,
//! `f8`, C order), which avoids a dependency for a twenty-line format.

use std::io::Read;
use std::path::Path;

use crate::error::{Error, Result};

/// Bins of a trRosetta `dist` array whose sum is `P(d < 8 A)`: bins 1..=12 span 2-8 A.
pub const TRROSETTA_CONTACT_BINS: std::ops::RangeInclusive<usize> = 1..=12;

/// Number of distance bins in a trRosetta `dist` array.
pub const TRROSETTA_N_BINS: usize = 37;

/// Scored residue pairs from a contact predictor.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Prediction {
    /// `(i, j, score)`: 1-based residue numbers in the prediction's numbering; a higher score is
    /// a more confident contact.
    pub pairs: Vec<(i32, i32, f64)>,
    /// The target sequence, when the file gives one (RR sequence lines).
    pub sequence: Option<String>,
    /// The number of residues the file covers, when its shape says it (the size of a matrix,
    /// a distogram or a distance map).
    pub length: Option<usize>,
}

impl Prediction {
    /// Attach `sequence` (for example from a FASTA file) and check that every residue number
    /// lies in `1..=sequence.len()`; a sequence already in the file must be the same, or its
    /// beginning.
    pub fn with_sequence(mut self, sequence: &str) -> Result<Self> {
        if let Some(own) = &self.sequence {
            // A list format's letters may stop before the end of the target: a prefix agrees.
            let agrees = sequence
                .get(..own.len())
                .is_some_and(|start| own.eq_ignore_ascii_case(start));
            if !agrees {
                return Err(Error::Data(format!(
                    "the prediction's sequence ({} residues) differs from the one given ({} residues)",
                    own.len(),
                    sequence.len()
                )));
            }
        }
        let length = sequence.chars().count();
        if let Some(covered) = self.length.filter(|&covered| covered != length) {
            return Err(Error::Data(format!(
                "the prediction covers {covered} residues but the sequence has {length}"
            )));
        }
        if let Some(&(i, j, _)) = self
            .pairs
            .iter()
            .find(|(i, j, _)| !in_sequence(*i, length) || !in_sequence(*j, length))
        {
            return Err(Error::Data(format!(
                "predicted pair {i}-{j} refers to a residue beyond the sequence (length {length})"
            )));
        }
        self.sequence = Some(sequence.to_string());
        Ok(self)
    }
}

fn in_sequence(residue: i32, length: usize) -> bool {
    residue >= 1 && (residue as usize) <= length
}

/// A prediction file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PredictionFormat {
    /// CASP RR.
    Rr,
    /// Square matrix (CCMpred, PSICOV matrix output, plain).
    Matrix,
    /// `i j score` rows.
    Table,
    /// trRosetta `.npz` distogram.
    Npz,
    /// `.npy` predicted distance map.
    Npy,
    /// EVfold `i A j B x score` rows.
    Evfold,
    /// GREMLIN table with its header.
    Gremlin,
}

const RR_KEYWORDS: &[&str] = &[
    "PFRMAT", "TARGET", "AUTHOR", "REMARK", "METHOD", "MODEL", "PARENT", "RMODE",
];

/// Number of fields of a CASP RR mode 2 row: `i j p` and ten bin probabilities.
const RR_MODE2_FIELDS: usize = 13;

fn is_gremlin_header(line: &str) -> bool {
    let words: Vec<&str> = line.split_whitespace().collect();
    words.len() >= 7 && words[0] == "i" && words[1] == "j" && words.contains(&"r_sco")
}

fn is_residue_letter(field: &str) -> bool {
    field.len() == 1 && field.as_bytes()[0].is_ascii_alphabetic()
}

fn is_sequence_line(line: &str) -> bool {
    !line.is_empty() && line.chars().all(|c| c.is_ascii_alphabetic() || c == '-')
}

/// The lines of `text` with their 1-based numbers, trimmed, without blank and `#` lines.
fn data_lines(text: &str) -> impl Iterator<Item = (u64, &str)> {
    text.lines()
        .enumerate()
        .map(|(index, line)| (index as u64 + 1, line.trim()))
        .filter(|(_, line)| !line.is_empty() && !line.starts_with('#'))
}

/// The fields of a list row, which must be `expected` many (`layout` names them).
fn list_fields<'a>(
    line: &'a str,
    expected: usize,
    layout: &str,
    path: &Path,
    line_number: u64,
) -> Result<Vec<&'a str>> {
    let fields = split_fields(line);
    if fields.len() == expected {
        Ok(fields)
    } else {
        Err(Error::parse(
            path,
            line_number,
            format!("{} fields, expected `{layout}`", fields.len()),
        ))
    }
}

fn split_fields(line: &str) -> Vec<&str> {
    line.split(|c: char| c.is_ascii_whitespace() || c == ',')
        .filter(|field| !field.is_empty())
        .collect()
}

/// The format of `bytes` (the start of a file is enough), or an error naming `path`.
pub fn detect_format(bytes: &[u8], path: &Path) -> Result<PredictionFormat> {
    if bytes.starts_with(b"PK\x03\x04") {
        return Ok(PredictionFormat::Npz);
    }
    if bytes.starts_with(b"\x93NUMPY") {
        return Ok(PredictionFormat::Npy);
    }
    let unknown = || {
        Error::format(
            path,
            "unknown prediction format (expected CASP RR, a CCMpred/PSICOV matrix, an `i j score` \
             table, a trRosetta .npz or a .npy distance map); give the format explicitly",
        )
    };
    let text = std::str::from_utf8(bytes).map_err(|_| unknown())?;
    let first = text
        .lines()
        .map(str::trim)
        .find(|line| !line.is_empty() && !line.starts_with('#'))
        .ok_or_else(unknown)?;
    let first_word = first.split_whitespace().next().unwrap_or("");
    if RR_KEYWORDS.contains(&first_word) || is_sequence_line(first) {
        return Ok(PredictionFormat::Rr);
    }
    if is_gremlin_header(first) {
        return Ok(PredictionFormat::Gremlin);
    }
    let fields = split_fields(first);
    if fields.len() == 6
        && is_residue_letter(fields[1])
        && is_residue_letter(fields[3])
        && [0, 2, 4, 5]
            .iter()
            .all(|&k| fields[k].parse::<f64>().is_ok())
    {
        return Ok(PredictionFormat::Evfold);
    }
    let integer = |field: &str| field.parse::<i64>().is_ok();
    let number = |field: &&str| field.parse::<f64>().is_ok();
    if !fields.iter().all(number) {
        return Err(unknown());
    }
    match fields.len() {
        5 | RR_MODE2_FIELDS if integer(fields[0]) && integer(fields[1]) => Ok(PredictionFormat::Rr),
        3 if integer(fields[0]) && integer(fields[1]) => Ok(PredictionFormat::Table),
        n if n > 3 => Ok(PredictionFormat::Matrix),
        _ => Err(unknown()),
    }
}

/// [`read_prediction`], then, with `fasta`, that sequence attached and the residue numbers
/// checked against it ([`Prediction::with_sequence`]; errors name the file). The sequence is made
/// upper case.
///
/// ```
/// use contactmap::io::predictions::load_prediction;
/// let prediction = load_prediction("data/protein/1aapA/1aapA.rr.gz", None, None)?;
/// assert!(prediction.sequence.is_some_and(|s| s.starts_with("VREVCSEQ")));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn load_prediction(
    path: impl AsRef<Path>,
    format: Option<PredictionFormat>,
    fasta: Option<&str>,
) -> Result<Prediction> {
    let path = path.as_ref();
    let mut prediction = read_prediction(path, format)?;
    if let Some(sequence) = fasta {
        prediction = prediction
            .with_sequence(sequence)
            .map_err(|err| err.in_file(path))?;
    }
    if let Some(sequence) = &mut prediction.sequence {
        sequence.make_ascii_uppercase();
    }
    Ok(prediction)
}

/// Read a prediction file, plain or gzip-compressed (detected from the content); `format`
/// overrides [`detect_format`], which looks at the decompressed bytes.
///
/// # Examples
///
/// A CASP RR file carries its sequence; its pairs keep the file's order.
///
/// ```
/// use contactmap::io::predictions::read_prediction;
/// let prediction = read_prediction("data/protein/1aapA/1aapA.rr.gz", None)?;
/// assert!(prediction.sequence.as_deref().unwrap().starts_with("VREVCSEQ"));
/// assert_eq!(prediction.pairs[0], (14, 38, 41.427055));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn read_prediction(
    path: impl AsRef<Path>,
    format: Option<PredictionFormat>,
) -> Result<Prediction> {
    let path = path.as_ref();
    let bytes = read_bytes(path)?;
    let format = match format {
        Some(format) => format,
        None => detect_format(&bytes, path)?,
    };
    let text =
        || std::str::from_utf8(&bytes).map_err(|_| Error::format(path, "not a UTF-8 text file"));
    match format {
        PredictionFormat::Rr => parse_rr(text()?, path),
        PredictionFormat::Matrix => parse_matrix(text()?, path),
        PredictionFormat::Table => parse_table(text()?, path),
        PredictionFormat::Npz => parse_npz(&bytes, path),
        PredictionFormat::Npy => parse_distance_npy(&bytes, path),
        PredictionFormat::Evfold => parse_evfold(text()?, path),
        PredictionFormat::Gremlin => parse_gremlin(text()?, path),
    }
}

/// The bytes of `path`, decompressed when they are gzip (detected from the magic bytes, whatever
/// the name: `x.mat.gz` reads as `x.mat` would).
fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    let bytes = std::fs::read(path).map_err(|err| Error::io(path, err))?;
    if !bytes.starts_with(&[0x1f, 0x8b]) {
        return Ok(bytes);
    }
    let mut text = Vec::new();
    flate2::read::MultiGzDecoder::new(bytes.as_slice())
        .read_to_end(&mut text)
        .map_err(|err| Error::io(path, err))?;
    Ok(text)
}

fn parse_residue(field: &str, path: &Path, line: u64) -> Result<i32> {
    use crate::io::protein::structure::MAX_RESIDUE_NUMBER;
    match field.parse::<i32>() {
        Ok(residue) if residue >= 1 && residue.unsigned_abs() <= MAX_RESIDUE_NUMBER => Ok(residue),
        _ => Err(Error::parse(
            path,
            line,
            format!("residue number '{field}' is not an integer from 1 to {MAX_RESIDUE_NUMBER}"),
        )),
    }
}

fn parse_score(field: &str, path: &Path, line: u64) -> Result<f64> {
    field
        .parse::<f64>()
        .map_err(|_| Error::parse(path, line, format!("score '{field}' is not a number")))
}

/// Parse a CASP RR file (see the module docs).
pub fn parse_rr(text: &str, path: &Path) -> Result<Prediction> {
    let mut sequence = String::new();
    let mut pairs = Vec::new();
    let mut n_models = 0;
    for (line_number, line) in data_lines(text) {
        let first_word = line.split_whitespace().next().unwrap_or("");
        if first_word == "END" {
            break;
        }
        if first_word == "MODEL" {
            n_models += 1;
            if n_models > 1 {
                break; // first model only
            }
            continue;
        }
        if RR_KEYWORDS.contains(&first_word) {
            continue;
        }
        if is_sequence_line(line) {
            if !pairs.is_empty() {
                return Err(Error::parse(
                    path,
                    line_number,
                    "sequence line after the first contact row",
                ));
            }
            sequence.push_str(line);
            continue;
        }
        let fields: Vec<&str> = line.split_whitespace().collect();
        let score_field = match fields.len() {
            3 => fields[2],
            5 => fields[4],
            RR_MODE2_FIELDS => {
                for field in &fields[3..] {
                    parse_score(field, path, line_number)?;
                }
                fields[2]
            }
            n => {
                return Err(Error::parse(
                    path,
                    line_number,
                    format!(
                        "RR row with {n} fields, expected `i j score`, `i j d1 d2 score` or \
                         `i j p` and 10 bin probabilities (mode 2)"
                    ),
                ));
            }
        };
        let i = parse_residue(fields[0], path, line_number)?;
        let j = parse_residue(fields[1], path, line_number)?;
        if !sequence.is_empty() {
            let length = sequence.len();
            for residue in [i, j] {
                if !in_sequence(residue, length) {
                    return Err(Error::parse(
                        path,
                        line_number,
                        format!("residue {residue} is beyond the sequence (length {length})"),
                    ));
                }
            }
        }
        pairs.push((i, j, parse_score(score_field, path, line_number)?));
    }
    Ok(Prediction {
        pairs,
        sequence: (!sequence.is_empty()).then_some(sequence),
        length: None,
    })
}

/// Parse a table of `i j score` rows (whitespace or commas; `#` lines skipped).
pub fn parse_table(text: &str, path: &Path) -> Result<Prediction> {
    let mut pairs = Vec::new();
    for (line_number, line) in data_lines(text) {
        let fields = list_fields(line, 3, "i j score", path, line_number)?;
        let i = parse_residue(fields[0], path, line_number)?;
        let j = parse_residue(fields[1], path, line_number)?;
        pairs.push((i, j, parse_score(fields[2], path, line_number)?));
    }
    Ok(Prediction {
        pairs,
        sequence: None,
        length: None,
    })
}

/// Residue letters named by a list format, checked for consistency; the sequence they spell
/// when every position from 1 to the largest is named.
#[derive(Default)]
struct NamedResidues {
    letters: Vec<Option<char>>,
}

impl NamedResidues {
    fn name(&mut self, residue: i32, letter: char, path: &Path, line: u64) -> Result<()> {
        let index = residue as usize - 1;
        if self.letters.len() <= index {
            self.letters.resize(index + 1, None);
        }
        let letter = letter.to_ascii_uppercase();
        match self.letters[index] {
            Some(known) if known != letter => Err(Error::parse(
                path,
                line,
                format!("residue {residue} is {letter} here but {known} on an earlier line"),
            )),
            _ => {
                self.letters[index] = Some(letter);
                Ok(())
            }
        }
    }

    fn sequence(&self) -> Option<String> {
        self.letters.iter().copied().collect()
    }
}

fn residue_letter(field: &str, path: &Path, line: u64) -> Result<char> {
    if is_residue_letter(field) {
        Ok(field.as_bytes()[0] as char)
    } else {
        Err(Error::parse(
            path,
            line,
            format!("'{field}' is not a one-letter amino-acid code"),
        ))
    }
}

/// Parse an EVfold / EVcouplings list: rows `i A_i j A_j x score`.
pub fn parse_evfold(text: &str, path: &Path) -> Result<Prediction> {
    let mut pairs = Vec::new();
    let mut named = NamedResidues::default();
    for (line_number, line) in data_lines(text) {
        let fields = list_fields(line, 6, "i A_i j A_j x score", path, line_number)?;
        let i = parse_residue(fields[0], path, line_number)?;
        let j = parse_residue(fields[2], path, line_number)?;
        named.name(
            i,
            residue_letter(fields[1], path, line_number)?,
            path,
            line_number,
        )?;
        named.name(
            j,
            residue_letter(fields[3], path, line_number)?,
            path,
            line_number,
        )?;
        pairs.push((i, j, parse_score(fields[5], path, line_number)?));
    }
    Ok(Prediction {
        pairs,
        sequence: named.sequence(),
        length: None,
    })
}

/// Parse a GREMLIN table: a header `i j [gene] i_id j_id r_sco s_sco prob ...` and rows whose
/// `i_id` / `j_id` are `12_M`; the score is `r_sco`.
pub fn parse_gremlin(text: &str, path: &Path) -> Result<Prediction> {
    let mut pairs = Vec::new();
    let mut named = NamedResidues::default();
    let mut columns: Option<(usize, usize, usize, usize)> = None; // i_id, j_id, r_sco, width
    for (line_number, line) in data_lines(text) {
        if is_gremlin_header(line) {
            let words: Vec<&str> = line.split_whitespace().collect();
            let find = |name: &str| words.iter().position(|word| *word == name);
            match (find("i_id"), find("j_id"), find("r_sco")) {
                (Some(i_id), Some(j_id), Some(r_sco)) => {
                    columns = Some((i_id, j_id, r_sco, words.len()))
                }
                _ => {
                    return Err(Error::parse(
                        path,
                        line_number,
                        "GREMLIN header without i_id, j_id and r_sco columns",
                    ));
                }
            }
            continue;
        }
        let Some((i_id, j_id, r_sco, width)) = columns else {
            return Err(Error::parse(
                path,
                line_number,
                "GREMLIN row before the header `i j i_id j_id r_sco s_sco prob`",
            ));
        };
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.len() != width {
            return Err(Error::parse(
                path,
                line_number,
                format!("{} fields, the header has {width}", fields.len()),
            ));
        }
        let i = parse_residue(fields[0], path, line_number)?;
        let j = parse_residue(fields[1], path, line_number)?;
        for (residue, id) in [(i, fields[i_id]), (j, fields[j_id])] {
            let letter = match id.split_once('_') {
                Some((number, letter)) if number.parse::<i32>() == Ok(residue) => {
                    residue_letter(letter, path, line_number)?
                }
                _ => {
                    return Err(Error::parse(
                        path,
                        line_number,
                        format!("residue id '{id}' is not `{residue}_X`"),
                    ));
                }
            };
            named.name(residue, letter, path, line_number)?;
        }
        pairs.push((i, j, parse_score(fields[r_sco], path, line_number)?));
    }
    Ok(Prediction {
        pairs,
        sequence: named.sequence(),
        length: None,
    })
}

/// Parse a whitespace-separated square matrix (CCMpred, PSICOV, plain); `#` lines are skipped.
/// Returns the upper triangle, 0-based row / column `i < j` as residues `i + 1`, `j + 1`.
pub fn parse_matrix(text: &str, path: &Path) -> Result<Prediction> {
    let mut rows: Vec<Vec<f64>> = Vec::new();
    for (line_number, line) in data_lines(text) {
        let row = line
            .split_whitespace()
            .map(|field| parse_score(field, path, line_number))
            .collect::<Result<Vec<f64>>>()?;
        if let Some(first) = rows.first() {
            if row.len() != first.len() {
                return Err(Error::parse(
                    path,
                    line_number,
                    format!(
                        "matrix row with {} values, the first row has {}",
                        row.len(),
                        first.len()
                    ),
                ));
            }
        }
        rows.push(row);
    }
    let n = rows.len();
    if n == 0 {
        return Err(Error::format(path, "empty matrix"));
    }
    if rows[0].len() != n {
        return Err(Error::format(
            path,
            format!("matrix is not square: {n} rows of {} values", rows[0].len()),
        ));
    }
    Ok(Prediction {
        pairs: upper_triangle(n, |i, j| rows[i][j]),
        sequence: None,
        length: Some(n),
    })
}

fn upper_triangle(n: usize, value: impl Fn(usize, usize) -> f64) -> Vec<(i32, i32, f64)> {
    let mut pairs = Vec::with_capacity(n * n.saturating_sub(1) / 2);
    for i in 0..n {
        for j in i + 1..n {
            pairs.push((i as i32 + 1, j as i32 + 1, value(i, j)));
        }
    }
    pairs
}

/// A decoded `.npy` array: its shape and its values in C order.
#[derive(Clone, Debug, PartialEq)]
pub struct NpyArray {
    /// Dimensions.
    pub shape: Vec<usize>,
    /// Values, row-major.
    pub values: Vec<f64>,
}

fn header_value<'a>(header: &'a str, key: &str) -> Option<&'a str> {
    let start = header.find(&format!("'{key}'"))? + key.len() + 2;
    let rest = header[start..].trim_start().strip_prefix(':')?.trim_start();
    if let Some(tuple) = rest.strip_prefix('(') {
        return tuple.find(')').map(|end| &tuple[..end]);
    }
    if let Some(quoted) = rest.strip_prefix('\'') {
        return quoted.find('\'').map(|end| &quoted[..end]);
    }
    rest.find([',', '}']).map(|end| rest[..end].trim())
}

fn f16_to_f64(bits: u16) -> f64 {
    let sign = if bits & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exponent = i32::from((bits >> 10) & 0x1f);
    let fraction = f64::from(bits & 0x3ff);
    match exponent {
        0 => sign * fraction * 2f64.powi(-24),
        31 if fraction == 0.0 => sign * f64::INFINITY,
        31 => f64::NAN,
        _ => sign * (1.0 + fraction / 1024.0) * 2f64.powi(exponent - 15),
    }
}

/// `text` from a file, fit for a one-line message: control and non-ASCII characters escaped,
/// cut after [`QUOTE_CHARS`] characters (with `...`).
fn quote(text: &str) -> String {
    let mut escaped: String = text.escape_default().take(QUOTE_CHARS + 1).collect();
    if escaped.chars().count() > QUOTE_CHARS {
        escaped = escaped.chars().take(QUOTE_CHARS).collect();
        escaped.push_str("...");
    }
    format!("'{escaped}'")
}

/// The most characters of file content that [`quote`] keeps.
const QUOTE_CHARS: usize = 40;

/// Decode a `.npy` array of little-endian `f2`, `f4` or `f8` values in C order.
///
/// The header is checked before anything is allocated from it: the shape's product must fit a
/// `usize` and the data after the header must hold that many values. Messages never quote the
/// header as it is: what they cite from it is escaped and cut short.
pub fn parse_npy(bytes: &[u8], path: &Path) -> Result<NpyArray> {
    let bad = |message: String| Error::format(path, message);
    if !bytes.starts_with(b"\x93NUMPY") || bytes.len() < 10 {
        return Err(bad("not a .npy array (no \\x93NUMPY magic)".into()));
    }
    let (header_length, header_start) = match bytes[6] {
        1 => (usize::from(u16::from_le_bytes([bytes[8], bytes[9]])), 10),
        2 | 3 if bytes.len() >= 12 => (
            u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize,
            12,
        ),
        version => return Err(bad(format!("unsupported .npy version {version}"))),
    };
    let data_start = header_start + header_length;
    let header = bytes.get(header_start..data_start).ok_or_else(|| {
        bad(format!(
            "truncated .npy header: it claims {header_length} bytes, the file has {} after the \
             preamble",
            bytes.len() - header_start.min(bytes.len())
        ))
    })?;
    let header = std::str::from_utf8(header).map_err(|e| {
        bad(format!(
            "the .npy header is not text (byte {})",
            e.valid_up_to()
        ))
    })?;
    let descr = header_value(header, "descr").unwrap_or("");
    match header_value(header, "fortran_order") {
        Some("False") => {}
        Some("True") => return Err(bad(".npy array in Fortran order is not supported".into())),
        Some(other) => {
            return Err(bad(format!(
                "the .npy header's 'fortran_order' is {}, expected True or False",
                quote(other)
            )));
        }
        None => return Err(bad("the .npy header has no 'fortran_order' entry".into())),
    }
    let shape = header_value(header, "shape")
        .ok_or_else(|| bad("the .npy header has no 'shape' entry".into()))?
        .split(',')
        .map(str::trim)
        .filter(|dim| !dim.is_empty())
        .map(|dim| {
            dim.parse::<usize>()
                .map_err(|_| bad(format!("bad .npy shape dimension {}", quote(dim))))
        })
        .collect::<Result<Vec<usize>>>()?;
    let width = match descr {
        "<f2" => 2,
        "<f4" => 4,
        "<f8" => 8,
        other => {
            return Err(bad(format!(
                ".npy dtype {} is not supported (expected <f2, <f4 or <f8)",
                quote(other)
            )));
        }
    };
    let data = &bytes[data_start..];
    // An empty dimension makes an empty array, whatever the others say.
    let n_bytes = if shape.contains(&0) {
        Some(0)
    } else {
        shape
            .iter()
            .try_fold(width, |product: usize, &dim| product.checked_mul(dim))
    };
    let n_bytes = match n_bytes {
        Some(n) if n <= data.len() => n,
        Some(n) => {
            return Err(bad(format!(
                "truncated .npy data: shape {shape:?} needs {n} bytes, found {}",
                data.len()
            )));
        }
        None => {
            return Err(bad(format!(
                ".npy shape {shape:?} is too large: its size overflows (the file holds {} bytes \
                 of data)",
                data.len()
            )));
        }
    };
    let values = data[..n_bytes]
        .chunks_exact(width)
        .map(|chunk| match width {
            2 => f16_to_f64(u16::from_le_bytes([chunk[0], chunk[1]])),
            4 => f64::from(f32::from_le_bytes([chunk[0], chunk[1], chunk[2], chunk[3]])),
            _ => f64::from_le_bytes(chunk.try_into().expect("8-byte chunk")),
        })
        .collect();
    Ok(NpyArray { shape, values })
}

/// Read a trRosetta `.npz` and score each pair `i < j` by `P(d < 8 A)`, the sum of the `dist`
/// bins [`TRROSETTA_CONTACT_BINS`].
pub fn parse_npz(bytes: &[u8], path: &Path) -> Result<Prediction> {
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes))
        .map_err(|err| Error::format(path, format!("not a readable .npz (zip) archive: {err}")))?;
    let names: Vec<String> = archive.file_names().map(str::to_string).collect();
    let Some(name) = names
        .iter()
        .find(|name| *name == "dist.npy" || *name == "dist")
    else {
        return Err(Error::format(
            path,
            format!(
                "no 'dist' array (trRosetta distogram) in the .npz; it holds: {}",
                names
                    .iter()
                    .map(|name| quote(name))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    };
    let mut entry = archive
        .by_name(name)
        .map_err(|err| Error::format(path, format!("cannot open {name} in the .npz: {err}")))?;
    let mut npy = Vec::new();
    entry
        .read_to_end(&mut npy)
        .map_err(|err| Error::format(path, format!("cannot inflate {name} in the .npz: {err}")))?;
    let array = parse_npy(&npy, path)?;
    let n = match array.shape[..] {
        [rows, cols, TRROSETTA_N_BINS] if rows == cols => rows,
        _ => {
            return Err(Error::format(
                path,
                format!(
                    "'dist' has shape {:?}, expected (L, L, {TRROSETTA_N_BINS}) (trRosetta bins)",
                    array.shape
                ),
            ));
        }
    };
    let at = |i: usize, j: usize| {
        let start = (i * n + j) * TRROSETTA_N_BINS;
        TRROSETTA_CONTACT_BINS
            .map(|bin| array.values[start + bin])
            .sum::<f64>()
    };
    Ok(Prediction {
        pairs: upper_triangle(n, at),
        sequence: None,
        length: Some(n),
    })
}

/// Read a `.npy` predicted distance map of shape `(L, L)` or `(L, L, 1)`; each pair `i < j` is
/// scored by minus its distance.
pub fn parse_distance_npy(bytes: &[u8], path: &Path) -> Result<Prediction> {
    let array = parse_npy(bytes, path)?;
    let n = match array.shape[..] {
        [rows, cols] | [rows, cols, 1] if rows == cols => rows,
        _ => {
            return Err(Error::format(
                path,
                format!(
                    "distance map has shape {:?}, expected a square (L, L) or (L, L, 1)",
                    array.shape
                ),
            ));
        }
    };
    Ok(Prediction {
        pairs: upper_triangle(n, |i, j| -array.values[i * n + j]),
        sequence: None,
        length: Some(n),
    })
}

/// The sequence of the first record of a FASTA file (letters only, upper case).
pub fn read_fasta(path: impl AsRef<Path>) -> Result<String> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|err| Error::io(path, err))?;
    let mut lines = text.lines().filter(|line| !line.trim().is_empty());
    match lines.next() {
        Some(header) if header.starts_with('>') => {}
        _ => {
            return Err(Error::parse(
                path,
                1,
                "FASTA file without a '>' header line",
            ));
        }
    }
    let sequence: String = lines
        .take_while(|line| !line.starts_with('>'))
        .flat_map(|line| line.trim().chars())
        .map(|c| c.to_ascii_uppercase())
        .collect();
    if sequence.is_empty() {
        return Err(Error::format(path, "empty FASTA sequence"));
    }
    Ok(sequence)
}

#[cfg(test)]
mod tests;
