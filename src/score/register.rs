//! The register of a prediction on a structure: which residue of the chain each position of the
//! prediction's sequence is.
//!
//! A prediction numbers residues by their position in its target sequence (1-based). A
//! structure numbers them as its authors chose: it may start later (1A8O is numbered 151-220),
//! skip residues that were not resolved, carry insertion codes (`52A`), or cover one domain of a
//! longer target. [`register`] finds the mapping, in this order ([`RegisterMode::Auto`]):
//!
//! 1. **Numbering, offset 0**: when every residue number of the chain lies in the sequence and
//!    at least 90 % of the residues are the amino acid the sequence has at that position (`X`
//!    compares as equal to anything), the numbers are the positions. This keeps what CASP,
//!    ConKit's documented example and ConEVA do on renumbered chains, and it is exact where an
//!    alignment could only guess (a missing residue inside a run of equal residues).
//! 2. **Numbering with an offset**: the chain is aligned to the sequence (below); if the most
//!    common difference `number - position` among the aligned residues passes the same test,
//!    `position = number - offset` for every residue.
//! 3. **Alignment**: otherwise each aligned residue takes the position the alignment gives it,
//!    and residues aligned to a gap are left out. Insertion codes are handled here: every
//!    residue gets its own position.
//!
//! The alignment is a semi-global Needleman-Wunsch with affine gaps (Gotoh): end gaps on both
//! sides are free (the structure may cover part of the sequence, and may carry tags the
//! sequence lacks), identical residues score [`MATCH`], different ones [`MISMATCH`], `X`
//! scores 0, a gap costs [`GAP_OPEN`] for its first residue and [`GAP_EXTEND`] for each further
//! one. Identity scoring is enough here: the two sequences are the same protein, and only the
//! gaps (unresolved residues) and the ends must be placed. Memory is one byte per cell of the
//! `sequence x chain` table (a million for a 1,000-residue target).
//!
//! A register with fewer identical residues than half the chain is refused: the chain is
//! likely the wrong one (`--chain`) or the sequence another protein's.

use crate::error::{Error, Result};
use crate::io::structure::{Chain, Residue};

/// Score of two identical residues.
pub const MATCH: i32 = 5;
/// Score of two different residues.
pub const MISMATCH: i32 = -4;
/// Cost of the first residue of a gap.
pub const GAP_OPEN: i32 = 10;
/// Cost of each further residue of a gap.
pub const GAP_EXTEND: i32 = 1;

/// Fraction of identical residues for the numbering to be trusted (steps 1-2).
pub const NUMBERING_IDENTITY: f64 = 0.9;

/// How the register is found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RegisterMode {
    /// Numbering if consistent with the sequence, else alignment (see the module docs).
    #[default]
    Auto,
    /// Always align.
    Alignment,
}

/// How a register was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RegisterMethod {
    /// `position = residue number - offset`.
    Numbering {
        /// `residue number - position`.
        offset: i32,
    },
    /// By sequence alignment.
    Alignment,
}

/// Sequence positions of the residues of a chain.
#[derive(Clone, Debug, PartialEq)]
pub struct Register {
    /// How it was found.
    pub method: RegisterMethod,
    /// `(position, residue index)`: 1-based sequence position and index into
    /// [`Chain::residues`], increasing in both.
    pub pairs: Vec<(usize, usize)>,
    /// Residues of the chain.
    pub n_residues: usize,
    /// Length of the sequence.
    pub sequence_length: usize,
    /// Aligned residues identical to the sequence.
    pub identical: usize,
}

fn same(a: u8, b: u8) -> bool {
    a == b || a == b'X' || b == b'X'
}

fn substitution(a: u8, b: u8) -> i32 {
    if a == b'X' || b == b'X' {
        0
    } else if a == b {
        MATCH
    } else {
        MISMATCH
    }
}

const NONE: i32 = i32::MIN / 4;

/// Semi-global affine alignment of `a` (rows) and `b` (columns): the aligned index pairs
/// `(index in a, index in b)`, 0-based and increasing.
pub fn align(a: &[u8], b: &[u8]) -> Vec<(usize, usize)> {
    let (n, m) = (a.len(), b.len());
    if n == 0 || m == 0 {
        return Vec::new();
    }
    let width = m + 1;
    // States: 0 = pair a[i-1] with b[j-1]; 1 = a[i-1] against a gap; 2 = b[j-1] against a gap.
    // Per cell, 2 bits per state: the state the best path into it came from.
    let mut from = vec![0u8; (n + 1) * width];
    let mut previous = vec![[NONE; 3]; width];
    let mut current = vec![[NONE; 3]; width];
    // Free leading gaps: the empty prefix of a against any prefix of b (and vice versa) is 0.
    for cell in previous.iter_mut() {
        *cell = [NONE, NONE, 0];
    }
    previous[0] = [0, NONE, NONE];
    let mut best = (NONE, 0usize, 0usize, 0usize); // score, i, j, state
    let best_of = |cell: &[i32; 3]| -> (i32, usize) {
        (0..3).fold((NONE, 0), |acc, state| {
            if cell[state] > acc.0 {
                (cell[state], state)
            } else {
                acc
            }
        })
    };
    let open_or_extend = |cell: &[i32; 3], gap_state: usize| -> (i32, u8) {
        let mut choice = (NONE, 0u8);
        for (state, &score) in cell.iter().enumerate() {
            let cost = if state == gap_state {
                GAP_EXTEND
            } else {
                GAP_OPEN
            };
            let value = score.saturating_sub(cost);
            if value > choice.0 {
                choice = (value, state as u8);
            }
        }
        choice
    };
    for i in 1..=n {
        current[0] = [NONE, 0, NONE];
        for j in 1..=m {
            let (diagonal, diagonal_from) = best_of(&previous[j - 1]);
            let pair = diagonal.saturating_add(substitution(a[i - 1], b[j - 1]));
            let (gap_b, gap_b_from) = open_or_extend(&previous[j], 1);
            let (gap_a, gap_a_from) = open_or_extend(&current[j - 1], 2);
            current[j] = [pair, gap_b, gap_a];
            from[i * width + j] = diagonal_from as u8 | (gap_b_from << 2) | (gap_a_from << 4);
            if i == n || j == m {
                let (score, state) = best_of(&current[j]);
                if score > best.0 {
                    best = (score, i, j, state);
                }
            }
        }
        std::mem::swap(&mut previous, &mut current);
    }
    let (_, mut i, mut j, mut state) = best;
    let mut pairs = Vec::new();
    while i > 0 && j > 0 {
        let bits = from[i * width + j];
        let came_from = ((bits >> (2 * state)) & 3) as usize;
        match state {
            0 => {
                pairs.push((i - 1, j - 1));
                i -= 1;
                j -= 1;
            }
            1 => i -= 1,
            _ => j -= 1,
        }
        state = came_from;
    }
    pairs.reverse();
    pairs
}

/// The register of `chain` on `sequence` (one-letter codes); see the module docs.
pub fn register(chain: &Chain, sequence: &str, mode: RegisterMode) -> Result<Register> {
    let sequence: Vec<u8> = sequence.bytes().map(|c| c.to_ascii_uppercase()).collect();
    let residues: Vec<u8> = chain
        .residues
        .iter()
        .map(|residue| residue.one_letter as u8)
        .collect();
    let mut found = None;
    if mode == RegisterMode::Auto {
        found = by_numbering(chain, &sequence, &residues, 0);
    }
    if found.is_none() {
        let aligned: Vec<(usize, usize)> = align(&sequence, &residues)
            .into_iter()
            .map(|(position, residue)| (position + 1, residue))
            .collect();
        if mode == RegisterMode::Auto {
            found = dominant_offset(chain, &aligned)
                .and_then(|offset| by_numbering(chain, &sequence, &residues, offset));
        }
        if found.is_none() {
            let identical = aligned
                .iter()
                .filter(|&&(position, residue)| same(sequence[position - 1], residues[residue]))
                .count();
            found = Some(Register {
                method: RegisterMethod::Alignment,
                pairs: aligned,
                n_residues: residues.len(),
                sequence_length: sequence.len(),
                identical,
            });
        }
    }
    let register = found.expect("a register was found");
    if 2 * register.identical < register.n_residues {
        return Err(Error::Invalid(format!(
            "chain {} ({} residues) does not match the prediction's sequence ({} residues): the \
             best register has {} identical residues; check --chain and the sequence",
            chain.id, register.n_residues, register.sequence_length, register.identical
        )));
    }
    Ok(register)
}

/// The most common `number - position` among aligned residues without insertion codes.
fn dominant_offset(chain: &Chain, aligned: &[(usize, usize)]) -> Option<i32> {
    let mut offsets: Vec<i32> = aligned
        .iter()
        .map(|&(position, residue)| chain.residues[residue].number - position as i32)
        .collect();
    offsets.sort_unstable();
    offsets
        .chunk_by(|a, b| a == b)
        .max_by_key(|run| run.len())
        .map(|run| run[0])
}

/// Step 1-2 of the module docs: `position = number - offset` if that is consistent.
fn by_numbering(chain: &Chain, sequence: &[u8], residues: &[u8], offset: i32) -> Option<Register> {
    if chain.residues.is_empty()
        || chain
            .residues
            .iter()
            .any(|residue| residue.insertion.is_some())
    {
        return None;
    }
    let mut pairs = Vec::with_capacity(residues.len());
    for (index, residue) in chain.residues.iter().enumerate() {
        let position = i64::from(residue.number) - i64::from(offset);
        if position < 1 || position > sequence.len() as i64 {
            return None;
        }
        pairs.push((position as usize, index));
    }
    if pairs.windows(2).any(|pair| pair[0].0 >= pair[1].0) {
        return None; // not increasing: numbers out of order or repeated
    }
    let identical = pairs
        .iter()
        .filter(|&&(position, residue)| same(sequence[position - 1], residues[residue]))
        .count();
    let consistent = identical as f64 >= NUMBERING_IDENTITY * pairs.len() as f64;
    consistent.then_some(Register {
        method: RegisterMethod::Numbering { offset },
        pairs,
        n_residues: residues.len(),
        sequence_length: sequence.len(),
        identical,
    })
}

fn label(residue: &Residue) -> String {
    match residue.insertion {
        Some(code) => format!("{}{code}", residue.number),
        None => residue.number.to_string(),
    }
}

impl Register {
    /// A copy of `chain` whose residues are numbered by their sequence position, without the
    /// residues that have none.
    pub fn renumber(&self, chain: &Chain) -> Chain {
        Chain {
            id: chain.id.clone(),
            residues: self
                .pairs
                .iter()
                .map(|&(position, index)| Residue {
                    number: position as i32,
                    insertion: None,
                    ..chain.residues[index].clone()
                })
                .collect(),
        }
    }

    /// Runs of residues placed consecutively: `(first residue index, first position, length)`,
    /// where both the positions and the residue numbers advance by one.
    pub fn segments(&self, chain: &Chain) -> Vec<(usize, usize, usize)> {
        let mut segments: Vec<(usize, usize, usize)> = Vec::new();
        for &(position, index) in &self.pairs {
            if let Some(last) = segments.last_mut() {
                let (first_index, first_position, length) = *last;
                let previous = &chain.residues[first_index + length - 1];
                let residue = &chain.residues[index];
                if index == first_index + length
                    && position == first_position + length
                    && residue.insertion.is_none()
                    && previous.insertion.is_none()
                    && residue.number == previous.number + 1
                {
                    last.2 += 1;
                    continue;
                }
            }
            segments.push((index, position, 1));
        }
        segments
    }

    /// What was done, in a few lines, e.g. for the log of `score contacts`.
    pub fn describe(&self, chain: &Chain) -> String {
        let placed = self.pairs.len();
        let identity = if placed == 0 {
            0.0
        } else {
            100.0 * self.identical as f64 / placed as f64
        };
        let head = match self.method {
            RegisterMethod::Numbering { offset: 0 } => {
                "the structure's residue numbers are the sequence positions".to_string()
            }
            RegisterMethod::Numbering { offset } => format!(
                "the structure's residue numbers are the sequence positions {} {}",
                if offset > 0 { "+" } else { "-" },
                offset.unsigned_abs()
            ),
            RegisterMethod::Alignment => "aligned the structure's chain to the sequence".into(),
        };
        let mut text = format!(
            "register: {head}: {placed} of {} residues of chain {} on {} sequence positions, {} \
             identical ({identity:.1}%)",
            self.n_residues,
            crate::io::structure::chain_label(&chain.id),
            self.sequence_length,
            self.identical
        );
        if placed < self.n_residues {
            text.push_str(&format!(
                "; {} residues without a position left out",
                self.n_residues - placed
            ));
        }
        let segments = self.segments(chain);
        let shown: Vec<String> = segments
            .iter()
            .take(12)
            .map(|&(index, position, length)| {
                let first = &chain.residues[index];
                let last = &chain.residues[index + length - 1];
                if length == 1 {
                    format!("{}->{position}", label(first))
                } else {
                    format!(
                        "{}-{}->{position}-{}",
                        label(first),
                        label(last),
                        position + length - 1
                    )
                }
            })
            .collect();
        text.push_str(&format!(
            "\n  residues -> positions: {}{}",
            shown.join(", "),
            if segments.len() > shown.len() {
                format!(", ... ({} segments)", segments.len())
            } else {
                String::new()
            }
        ));
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::structure::Atom;
    use proptest::prelude::*;

    fn chain(residues: &[(i32, Option<char>, char)]) -> Chain {
        Chain {
            id: "A".into(),
            residues: residues
                .iter()
                .map(|&(number, insertion, one_letter)| Residue {
                    number,
                    insertion,
                    name: "ALA".into(),
                    one_letter,
                    atoms: vec![Atom {
                        name: "CA".into(),
                        element: "C".into(),
                        xyz: [0.0; 3],
                    }],
                })
                .collect(),
        }
    }

    fn numbered(start: i32, letters: &str) -> Chain {
        let residues: Vec<(i32, Option<char>, char)> = letters
            .chars()
            .enumerate()
            .map(|(k, c)| (start + k as i32, None, c))
            .collect();
        chain(&residues)
    }

    const TARGET: &str = "MKTAYIAKQRQISFVKSHFSRQLEERLGLIEVQAPILSRVGDGTQDNLSGAEKAVQVKVKALPDAQ";

    #[test]
    fn consistent_numbering_is_kept() {
        let chain = numbered(5, &TARGET[4..40]);
        let register = register(&chain, TARGET, RegisterMode::Auto).unwrap();
        assert_eq!(register.method, RegisterMethod::Numbering { offset: 0 });
        assert_eq!(register.pairs.first(), Some(&(5, 0)));
        assert_eq!(register.identical, 36);
    }

    #[test]
    fn offset_numbering_is_found() {
        // 1A8O-like: numbered from 151, sequence from 1, with two unresolved residues.
        let letters = &TARGET[..30];
        let mut residues: Vec<(i32, Option<char>, char)> = letters
            .chars()
            .enumerate()
            .map(|(k, c)| (151 + k as i32, None, c))
            .collect();
        residues.remove(12);
        residues.remove(12);
        let chain = chain(&residues);
        let register = register(&chain, TARGET, RegisterMode::Auto).unwrap();
        assert_eq!(register.method, RegisterMethod::Numbering { offset: 150 });
        assert_eq!(register.pairs.len(), 28);
        assert_eq!(register.pairs[12], (15, 12));
        assert_eq!(register.identical, 28);
        let renumbered = register.renumber(&chain);
        assert_eq!(renumbered.residues[12].number, 15);
        assert_eq!(register.segments(&chain), vec![(0, 1, 12), (12, 15, 16)]);
    }

    #[test]
    fn insertion_codes_are_aligned() {
        // Residues 10, 10A, 10B, 11...: the numbers cannot be positions.
        let letters: Vec<char> = TARGET[20..45].chars().collect();
        let mut residues = vec![(9, None, letters[0])];
        residues.push((10, None, letters[1]));
        residues.push((10, Some('A'), letters[2]));
        residues.push((10, Some('B'), letters[3]));
        for (k, &c) in letters[4..].iter().enumerate() {
            residues.push((11 + k as i32, None, c));
        }
        let chain = chain(&residues);
        let register = register(&chain, TARGET, RegisterMode::Auto).unwrap();
        assert_eq!(register.method, RegisterMethod::Alignment);
        let positions: Vec<usize> = register.pairs.iter().map(|p| p.0).collect();
        assert_eq!(positions, (21..46).collect::<Vec<_>>());
        assert!(register.describe(&chain).contains("10A"));
    }

    #[test]
    fn wrong_chain_is_refused() {
        let chain = numbered(1, "WWWWWWWWWWWWWWWWWWWWHHHHHHHHHH");
        let err = register(&chain, TARGET, RegisterMode::Auto).unwrap_err();
        assert!(err.to_string().contains("does not match"), "{err}");
    }

    #[test]
    fn alignment_places_an_internal_gap_and_free_ends() {
        let a = b"AAAACDEFGHIKLMNPQRSTVWYAAAA";
        let b = b"CDEFGHIKQRSTVWY"; // LMNP missing
        let pairs = align(a, b);
        assert_eq!(pairs.len(), b.len());
        assert_eq!(pairs[0], (4, 0));
        assert_eq!(pairs[8], (16, 8)); // Q after the gap
        assert_eq!(pairs.last(), Some(&(22, 14)));
    }

    proptest! {
        /// A chain cut out of the sequence, with unresolved stretches removed and renumbered
        /// arbitrarily, is placed back exactly where it came from.
        #[test]
        fn alignment_recovers_deleted_stretches(
            sequence in "[ACDEFGHIKLMNPQRSTVWY]{70,120}",
            start in 0usize..10,
            cuts in proptest::collection::vec(0usize..6, 3),
            shift in -200i32..200,
        ) {
            let bytes = sequence.as_bytes();
            // Unresolved stretches of 0-5 residues, 15 residues apart.
            let mut keep: Vec<usize> = (start..bytes.len()).collect();
            for (k, &length) in cuts.iter().enumerate().rev() {
                let at = 15 * (k + 1);
                keep.drain(at..at + length);
            }
            let residues: Vec<(i32, Option<char>, char)> = keep
                .iter()
                .enumerate()
                .map(|(k, &p)| (shift + k as i32, None, bytes[p] as char))
                .collect();
            let chain = chain(&residues);
            let register = register(&chain, &sequence, RegisterMode::Alignment).unwrap();
            // Every residue is placed on its own letter (an ambiguous gap placement can only
            // trade equal letters).
            prop_assert_eq!(register.pairs.len(), keep.len());
            prop_assert_eq!(register.identical, keep.len());
            for &(position, index) in &register.pairs {
                prop_assert_eq!(bytes[position - 1], residues[index].2 as u8);
            }
        }
    }
}
