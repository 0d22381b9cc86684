//! The residue contact frequency table of `contactmap contacts --trajectory`
//! ([`crate::score::frequency::frequency_table`] writes it), read back as the truth of
//! `score contacts --frequencies`.
//!
//! One row per residue pair, tab-separated, with the header [`FREQUENCY_HEADER`]: the chain id
//! (blank for a blank chain), the residues' author numbers with their insertion codes (`52A`),
//! their names as the topology writes them, their 0-based indices in the topology, the frames
//! in contact and the fraction of frames. gzip is detected from the content.

use std::path::Path;

use crate::error::{Error, Result};
use crate::io::plumbing::tables::Table;

/// The header of a contact frequency table.
pub const FREQUENCY_HEADER: &str =
    "chain\tresidue1\tresidue2\tname1\tname2\tindex1\tindex2\tcontact_frames\tfrequency";

/// A residue of a frequency table row: its author number, insertion code and name.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct FrequencyResidue {
    /// Author residue number.
    pub number: i32,
    /// Insertion code, if any.
    pub insertion: Option<char>,
    /// The residue name as the topology writes it (`HSD`, `MSE` ...).
    pub name: String,
}

/// One residue pair of a frequency table.
#[derive(Clone, Debug, PartialEq)]
pub struct FrequencyRow {
    /// The line of the row in its file (1-based), for messages.
    pub line: u64,
    /// The chain id (empty for a blank chain).
    pub chain: String,
    /// The first residue.
    pub residue1: FrequencyResidue,
    /// The second residue.
    pub residue2: FrequencyResidue,
    /// Frames in contact.
    pub contact_frames: u64,
    /// The fraction of frames in contact, in `[0, 1]`.
    pub frequency: f64,
}

/// A residue number with an optional insertion code (`52`, `52A`, `-3`).
fn residue_number(text: &str) -> Option<(i32, Option<char>)> {
    let text = text.trim();
    let last = text.chars().last()?;
    if last.is_ascii_alphabetic() {
        let number = text[..text.len() - 1].parse().ok()?;
        Some((number, Some(last)))
    } else {
        Some((text.parse().ok()?, None))
    }
}

/// Read a contact frequency table (`-` for standard input); every row checked: residue numbers,
/// a frame count and a frequency in `[0, 1]`, two different residues.
///
/// ```
/// use contactmap::io::frequencies::{read_frequency_table, FREQUENCY_HEADER};
/// let path = std::env::temp_dir().join("contactmap-doc-frequencies.tsv");
/// let rows = "A\t1\t4\tMET\tILE\t0\t3\t9\t0.9\nA\t52A\t60\tHSD\tGLY\t51\t59\t0\t0\n";
/// std::fs::write(&path, format!("{FREQUENCY_HEADER}\n{rows}")).unwrap();
/// let rows = read_frequency_table(&path)?;
/// assert_eq!((rows[1].residue1.number, rows[1].residue1.insertion), (52, Some('A')));
/// assert_eq!((rows[0].contact_frames, rows[0].frequency), (9, 0.9));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn read_frequency_table(path: impl AsRef<Path>) -> Result<Vec<FrequencyRow>> {
    let path = path.as_ref();
    let table = Table::read(&path.to_string_lossy())?;
    let columns: Vec<usize> = FREQUENCY_HEADER
        .split('\t')
        .map(|name| table.column(name))
        .collect::<Result<_>>()
        .map_err(|_| {
            Error::format(
                path,
                format!(
                    "not a contact frequency table (`contactmap contacts --trajectory` writes \
                     one): the header must name the columns {}",
                    FREQUENCY_HEADER.replace('\t', " ")
                ),
            )
        })?;
    let &[
        chain,
        residue1,
        residue2,
        name1,
        name2,
        _,
        _,
        frames,
        frequency,
    ] = &columns[..]
    else {
        unreachable!("nine columns in the header")
    };
    let mut rows = Vec::with_capacity(table.len());
    for row in 0..table.len() {
        // 1-based, after the header line
        let line = row as u64 + 2;
        let bad = |what: String| Error::parse(path, line, what);
        let residue = |number: usize, name: usize| {
            let text = table.text(row, number);
            let (number, insertion) = residue_number(text).ok_or_else(|| {
                bad(format!(
                    "'{text}' is not a residue number (a number, optionally with an insertion \
                     code: 52, 52A)"
                ))
            })?;
            Ok::<_, Error>(FrequencyResidue {
                number,
                insertion,
                name: table.text(row, name).trim().to_string(),
            })
        };
        let (first, second) = (residue(residue1, name1)?, residue(residue2, name2)?);
        if first == second {
            return Err(bad(format!(
                "a pair of residue {} with itself",
                table.text(row, residue1)
            )));
        }
        let count_text = table.text(row, frames).trim();
        let contact_frames = count_text.parse().map_err(|_| {
            bad(format!(
                "'{count_text}' in column 'contact_frames' is not a number of frames"
            ))
        })?;
        let value = table.number(row, frequency)?;
        if !(0.0..=1.0).contains(&value) {
            return Err(bad(format!(
                "frequency {} is not a fraction of frames (0 to 1)",
                table.text(row, frequency).trim()
            )));
        }
        rows.push(FrequencyRow {
            line,
            chain: table.text(row, chain).trim().to_string(),
            residue1: first,
            residue2: second,
            contact_frames,
            frequency: value,
        });
    }
    if rows.is_empty() {
        return Err(Error::format(
            path,
            "the frequency table has no residue pair",
        ));
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn residue_numbers_with_insertion_codes() {
        assert_eq!(residue_number("52"), Some((52, None)));
        assert_eq!(residue_number("52A"), Some((52, Some('A'))));
        assert_eq!(residue_number("-3"), Some((-3, None)));
        assert_eq!(residue_number("A"), None);
        assert_eq!(residue_number("5x2"), None);
        assert_eq!(residue_number(""), None);
    }
}
