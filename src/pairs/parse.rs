//! From a read's alignments to pairs, as `pairtools parse` (1.1.2) classifies them.
//!
//! Each side's alignments (read 1's records, read 2's) are sorted from the read's 5' end; a
//! stretch of a read longer than `--max-inter-align-gap` that no alignment covers becomes an
//! unmapped ("null") alignment. A read pair with one alignment per side is one pair. With more
//! (chimeric reads), a single ligation read through on one side is rescued (the linear side
//! typed `R`: pair types `UR`, `RU`, `MR`, `NR`); other walks follow `--walks-policy`:
//!
//! | policy | reports |
//! |---|---|
//! | `5unique` (default) | the 5'-most unique alignment of each side (the 5'-most when none is) |
//! | `5any` | the 5'-most alignment of each side |
//! | `3unique`, `3any` | the same from the 3' end |
//! | `mask` | one pair `!`/`0`/`-` typed `WW` |
//! | `all` | every ligation of the walk (see [`super::walks`]) |
//!
//! A side without records is `X` (`XX`). Side types: `U` unique (MAPQ >= `--min-mapq`), `M`
//! multi-mapping, `N` unmapped; pairs are flipped so that side 1 comes first in the
//! chromosomes' order (then position), or, with a side not unique, so that the less mapped side
//! comes first (`NU`, `MU`, `NM`).

use super::alignment::{Alignment, AlignmentSettings, CigarText};
use super::walks::complex_walk;
use crate::error::{Error, Result};
use crate::io::pairs::ReadGroup;

/// How walks that no single ligation explains are reported (`--walks-policy`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WalksPolicy {
    /// The 5'-most unique alignment of each side.
    FiveUnique,
    /// The 5'-most alignment of each side.
    FiveAny,
    /// The 3'-most unique alignment of each side.
    ThreeUnique,
    /// The 3'-most alignment of each side.
    ThreeAny,
    /// One masked pair, typed `WW`.
    Mask,
    /// Every ligation of the walk.
    All,
}

impl WalksPolicy {
    /// The policy named as pairtools names it.
    pub fn from_name(name: &str) -> Option<WalksPolicy> {
        Some(match name {
            "5unique" => WalksPolicy::FiveUnique,
            "5any" => WalksPolicy::FiveAny,
            "3unique" => WalksPolicy::ThreeUnique,
            "3any" => WalksPolicy::ThreeAny,
            "mask" => WalksPolicy::Mask,
            "all" => WalksPolicy::All,
            _ => return None,
        })
    }
}

/// The extra columns `--add-columns` may ask for (pairtools' names); each is written twice,
/// `NAME1` and `NAME2`.
pub const EXTRA_COLUMNS: [&str; 15] = [
    "mapq",
    "pos5",
    "pos3",
    "cigar",
    "read_len",
    "matched_bp",
    "algn_ref_span",
    "algn_read_span",
    "dist_to_5",
    "dist_to_3",
    "seq",
    "mismatches",
    "read_side",
    "algn_idx",
    "same_side_algn_count",
];

/// The settings of [`ParseParams`], with pairtools' defaults.
#[derive(Clone, Debug)]
pub struct ParseParams {
    /// `--min-mapq` (1): the smallest MAPQ of a unique alignment.
    pub min_mapq: u8,
    /// `--max-molecule-size` (750): the largest molecule a rescued walk may imply (and, with
    /// `all`, the largest insert of a partial overlap).
    pub max_molecule_size: i64,
    /// `--max-inter-align-gap` (20): longer uncovered stretches become null alignments.
    pub max_inter_align_gap: i64,
    /// `--walks-policy` (`5unique`).
    pub walks_policy: WalksPolicy,
    /// `--report-alignment-end` 3 instead of 5.
    pub report_3_end: bool,
    /// `--no-flip`: keep read 1's side first.
    pub no_flip: bool,
    /// `--drop-readid`: `.` instead of the read name.
    pub drop_readid: bool,
    /// `--keep-sam`: the `sam1`, `sam2` columns.
    pub keep_sam: bool,
    /// `--drop-seq`: no bases and qualities in those SAM columns.
    pub drop_seq: bool,
    /// `--add-pair-index`: `walk_pair_index`, `walk_pair_type`.
    pub add_pair_index: bool,
    /// `--add-columns`, in the order given (names of [`EXTRA_COLUMNS`]).
    pub add_columns: Vec<String>,
}

impl Default for ParseParams {
    fn default() -> Self {
        ParseParams {
            min_mapq: 1,
            max_molecule_size: 750,
            max_inter_align_gap: 20,
            walks_policy: WalksPolicy::FiveUnique,
            report_3_end: false,
            no_flip: false,
            drop_readid: false,
            keep_sam: false,
            drop_seq: false,
            add_pair_index: false,
            add_columns: Vec::new(),
        }
    }
}

impl ParseParams {
    /// Check the extra columns' names.
    pub fn check(&self) -> Result<()> {
        for column in &self.add_columns {
            if !EXTRA_COLUMNS.contains(&column.as_str()) {
                return Err(Error::Parameter {
                    name: "add_columns",
                    value: column.clone(),
                    expected: format!("one of {}", EXTRA_COLUMNS.join(", ")),
                });
            }
        }
        Ok(())
    }

    /// The columns of the output, in pairtools' order.
    pub fn columns(&self) -> Vec<String> {
        let mut columns: Vec<String> = crate::io::pairs::STANDARD_COLUMNS
            .iter()
            .map(|c| c.to_string())
            .collect();
        if self.keep_sam {
            columns.push("sam1".into());
            columns.push("sam2".into());
        }
        if self.add_pair_index {
            columns.push("walk_pair_index".into());
            columns.push("walk_pair_type".into());
        }
        for column in &self.add_columns {
            columns.push(format!("{column}1"));
            columns.push(format!("{column}2"));
        }
        columns
    }

    /// What the records must carry for these columns.
    pub fn needs(&self) -> crate::io::pairs::RecordNeeds {
        let has = |name: &str| self.add_columns.iter().any(|c| c == name);
        crate::io::pairs::RecordNeeds {
            sequence: has("mismatches") || has("seq"),
            md: has("mismatches"),
            sam_text: self.keep_sam,
        }
    }

    fn alignment_settings(&self) -> AlignmentSettings {
        let has = |name: &str| self.add_columns.iter().any(|c| c == name);
        AlignmentSettings {
            min_mapq: self.min_mapq,
            mismatches: has("mismatches"),
            sequence: has("seq"),
            cigar: has("cigar"),
        }
    }
}

/// The chromosomes as the output names and orders them.
#[derive(Clone, Debug)]
pub struct ChromOrder {
    /// The name of each `@SQ` chromosome.
    pub names: Vec<String>,
    /// The length of each `@SQ` chromosome.
    pub lengths: Vec<u64>,
    /// The rank of each `@SQ` chromosome in the order pairs are flipped to (1-based; `!` is 0).
    pub ranks: Vec<usize>,
}

impl ChromOrder {
    /// The order of `--chrom-sizes` (`sizes`: name, length) over the input's `@SQ`
    /// chromosomes (`sam`), as pairtools orders them: the sizes file's order, chromosomes it
    /// lists that the input lacks skipped. A chromosome of the input that the sizes file does
    /// not list is an error unless `add_missing` (then, as pairtools does, they follow in name
    /// order); so is a length that differs (another assembly). `sizes_path` names the sizes
    /// file in errors.
    pub fn new(
        sam: &[(String, u64)],
        sizes: &[(String, u64)],
        add_missing: bool,
        sizes_path: &str,
    ) -> Result<ChromOrder> {
        let index: std::collections::HashMap<&str, usize> = sam
            .iter()
            .enumerate()
            .map(|(i, (name, _))| (name.as_str(), i))
            .collect();
        let mut ranks = vec![0usize; sam.len()];
        let mut next = 1;
        for (name, length) in sizes {
            let Some(&i) = index.get(name.as_str()) else {
                continue;
            };
            if ranks[i] != 0 {
                continue;
            }
            if sam[i].1 != *length {
                return Err(Error::Argument(format!(
                    "{sizes_path}: {name} is {length} bp there but {} bp in the input's header: \
                     the two are of different assemblies",
                    sam[i].1
                )));
            }
            ranks[i] = next;
            next += 1;
        }
        let mut missing: Vec<usize> = (0..sam.len()).filter(|&i| ranks[i] == 0).collect();
        if !missing.is_empty() && !add_missing {
            let names: Vec<&str> = missing.iter().take(5).map(|&i| sam[i].0.as_str()).collect();
            return Err(Error::Argument(format!(
                "{sizes_path}: {} chromosome(s) of the input's header are not listed ({}{}): \
                 give sizes for every @SQ chromosome, or pass --add-missing-chroms to order them \
                 after the listed ones by name, as pairtools does",
                missing.len(),
                names.join(", "),
                if missing.len() > 5 { ", ..." } else { "" }
            )));
        }
        missing.sort_by(|&a, &b| sam[a].0.cmp(&sam[b].0));
        for i in missing {
            ranks[i] = next;
            next += 1;
        }
        Ok(ChromOrder {
            names: sam.iter().map(|(n, _)| n.clone()).collect(),
            lengths: sam.iter().map(|&(_, l)| l).collect(),
            ranks,
        })
    }

    /// The chromosomes and their lengths in rank order (the header's `#chromsize:` lines).
    pub fn chromsizes(&self) -> Vec<(String, u64)> {
        let mut order: Vec<usize> = (0..self.names.len()).collect();
        order.sort_by_key(|&i| self.ranks[i]);
        order
            .into_iter()
            .map(|i| (self.names[i].clone(), self.lengths[i]))
            .collect()
    }
}

/// One pair to write: its two sides, its index along the walk, and the sides' SAM records.
#[derive(Clone, Debug)]
pub struct ParsedPair {
    /// Side 1 (after flipping).
    pub side1: Alignment,
    /// Side 2.
    pub side2: Alignment,
    /// The pair's index and type along the walk.
    pub index: (usize, &'static str),
    /// Whether the SAM records of the two reads are swapped for this pair (pairtools swaps
    /// them with each flipped pair of a read, the swaps adding up over a walk).
    pub sams_swapped: bool,
}

impl ParsedPair {
    /// The pair type (`UU`, `NU`, `WW` ...).
    pub fn pair_type(&self) -> [u8; 2] {
        [self.side1.kind, self.side2.kind]
    }
}

/// Sort a side's alignments from the read's 5' end and fill uncovered stretches longer than
/// `max_gap` with null alignments (pairtools' `normalize_alignment_list`, including its
/// iteration over the list's first length while inserting).
fn normalize(algns: &mut Vec<Alignment>, side: u8, max_gap: i64) {
    if algns.is_empty() {
        algns.push(Alignment::empty());
    }
    algns.sort_by_key(|a| a.dist_to_5);
    if algns.len() != 1 || algns[0].is_mapped {
        let mut last_5_pos = 0i64;
        let n = algns.len();
        for i in 0..n {
            let (dist_to_5, span, read_len) = {
                let a = &algns[i];
                (a.dist_to_5, a.geometry.algn_read_span, a.geometry.read_len)
            };
            if dist_to_5 - last_5_pos > max_gap {
                let mut gap = Alignment::empty();
                gap.dist_to_5 = last_5_pos;
                gap.geometry.algn_read_span = dist_to_5 - last_5_pos;
                gap.geometry.read_len = read_len;
                gap.dist_to_3 = read_len - dist_to_5;
                last_5_pos = dist_to_5 + span;
                algns.insert(i, gap);
            } else {
                last_5_pos = last_5_pos.max(dist_to_5 + span);
            }
        }
    }
    // A read's alignments number far fewer than 2^32 (each takes memory).
    let count = u32::try_from(algns.len()).unwrap_or(u32::MAX);
    for (i, a) in algns.iter_mut().enumerate() {
        a.read_side = Some(side);
        a.algn_idx = Some(u32::try_from(i).unwrap_or(u32::MAX));
        a.same_side_algn_count = Some(count);
    }
}

/// Rescue a walk that is one ligation read through on one side (pairtools' `rescue_walk`):
/// returns the side with the linear alignment, having typed it `R`.
fn rescue_walk(
    algns1: &mut [Alignment],
    algns2: &mut [Alignment],
    max_molecule_size: i64,
) -> Option<u8> {
    let (n1, n2) = (algns1.len(), algns2.len());
    if n1 <= 1 && n2 <= 1 {
        return None;
    }
    if !((n1 == 1 && n2 == 2) || (n1 == 2 && n2 == 1)) {
        return None;
    }
    let first_is_chimeric = n1 > 1;
    let (chim5, chim3, linear) = if first_is_chimeric {
        (&algns1[0], &algns1[1], &algns2[0])
    } else {
        (&algns2[0], &algns2[1], &algns1[0])
    };
    if !linear.is_mapped_unique() {
        return None;
    }
    let mut can_rescue = true;
    if chim3.is_mapped && chim5.is_unique {
        can_rescue &= chim3.chrom == linear.chrom;
        can_rescue &= chim3.strand != linear.strand;
        if linear.strand == b'+' {
            can_rescue &= linear.pos5 < chim3.pos5;
        } else {
            can_rescue &= linear.pos5 > chim3.pos5;
        }
        let molecule_size = if linear.strand == b'+' {
            chim3.pos5 - linear.pos5 + chim3.dist_to_5 + linear.dist_to_5
        } else {
            linear.pos5 - chim3.pos5 + chim3.dist_to_5 + linear.dist_to_5
        };
        can_rescue &= molecule_size <= max_molecule_size;
    }
    if !can_rescue {
        return None;
    }
    if first_is_chimeric {
        algns1[1].kind = b'X';
        algns2[0].kind = b'R';
        Some(1)
    } else {
        algns1[0].kind = b'R';
        algns2[1].kind = b'X';
        Some(2)
    }
}

/// Buffers reused from one read group to the next (a task parses many groups).
#[derive(Default)]
pub struct ParseScratch {
    order: Vec<(bool, u64, usize)>,
    algns1: Vec<Alignment>,
    algns2: Vec<Alignment>,
    raw: Vec<RawPair>,
}

/// A pair before flipping: its sides and its index along the walk.
type RawPair = (Alignment, Alignment, (usize, &'static str));

/// The pairs of one read group (pairtools' `parse_read`, then the flip of
/// `streaming_classify`).
pub fn parse_read(group: &ReadGroup, order: &ChromOrder, params: &ParseParams) -> Vec<ParsedPair> {
    let mut pairs = Vec::new();
    parse_read_into(
        group,
        order,
        params,
        &mut ParseScratch::default(),
        &mut pairs,
    );
    pairs
}

/// [`parse_read`] into `pairs` (cleared first), with buffers reused through `scratch`.
pub fn parse_read_into(
    group: &ReadGroup,
    order: &ChromOrder,
    params: &ParseParams,
    scratch: &mut ParseScratch,
    pairs: &mut Vec<ParsedPair>,
) {
    pairs.clear();
    let settings = params.alignment_settings();
    // pairtools sorts the records by (is read 2, query alignment start), then each side by
    // distance to the 5' end (stable).
    let records = &group.records;
    scratch.order.clear();
    scratch.order.extend(
        records
            .iter()
            .enumerate()
            .map(|(i, r)| (!r.is_read1(), r.query_alignment_start(), i)),
    );
    scratch
        .order
        .sort_by_key(|&(is_read2, start, _)| (is_read2, start));
    scratch.algns1.clear();
    scratch.algns2.clear();
    for &(is_read2, _, i) in &scratch.order {
        let side = if is_read2 {
            &mut scratch.algns2
        } else {
            &mut scratch.algns1
        };
        side.push(Alignment::of(&records[i], &settings));
    }
    classify(
        &mut scratch.algns1,
        &mut scratch.algns2,
        params,
        &mut scratch.raw,
    );
    let mut sams_swapped = false;
    for (mut a, mut b, index) in scratch.raw.drain(..) {
        let pick = |x: &Alignment| if params.report_3_end { x.pos3 } else { x.pos5 };
        a.pos = pick(&a);
        b.pos = pick(&b);
        if !params.no_flip && !in_pair_order(&a, &b, order) {
            std::mem::swap(&mut a, &mut b);
            sams_swapped = !sams_swapped;
        }
        pairs.push(ParsedPair {
            side1: a,
            side2: b,
            index,
            sams_swapped,
        });
    }
}

/// The pairs of a read's two sides' alignments (each in pairtools' order) into `out`.
fn classify(
    algns1: &mut Vec<Alignment>,
    algns2: &mut Vec<Alignment>,
    params: &ParseParams,
    out: &mut Vec<RawPair>,
) {
    out.clear();
    let is_empty = if params.walks_policy == WalksPolicy::All {
        (algns1.is_empty() && algns2.len() < 2) || (algns2.is_empty() && algns1.len() < 2)
    } else {
        algns1.is_empty() || algns2.is_empty()
    };
    if is_empty {
        let mut a = Alignment::empty();
        a.kind = b'X';
        let b = a.clone();
        out.push((a, b, (1, "R1-2")));
        return;
    }
    let gap = params.max_inter_align_gap;
    normalize(algns1, 1, gap);
    normalize(algns2, 2, gap);
    let is_chimeric1 = algns1.len() > 1;
    let is_chimeric2 = algns2.len() > 1;
    if !is_chimeric1 && !is_chimeric2 {
        out.push((algns1[0].clone(), algns2[0].clone(), (1, "R1-2")));
        return;
    }
    if params.walks_policy == WalksPolicy::All {
        out.extend(complex_walk(algns1, algns2, params.max_molecule_size, 3));
        return;
    }
    if let Some(linear_side) = rescue_walk(algns1, algns2, params.max_molecule_size) {
        let index = (1, if linear_side == 1 { "R1" } else { "R2" });
        out.push((algns1[0].clone(), algns2[0].clone(), index));
        return;
    }
    let first_unique = |algns: &[Alignment]| {
        algns
            .iter()
            .find(|a| a.is_mapped_unique())
            .unwrap_or(&algns[0])
            .clone()
    };
    let last_unique = |algns: &[Alignment]| {
        algns
            .iter()
            .rev()
            .find(|a| a.is_mapped_unique())
            .unwrap_or(&algns[algns.len() - 1])
            .clone()
    };
    let (a, b) = match params.walks_policy {
        WalksPolicy::Mask => {
            let mut a = algns1[0].clone().masked();
            let mut b = algns2[0].clone().masked();
            a.kind = b'W';
            b.kind = b'W';
            (a, b)
        }
        WalksPolicy::FiveAny => (algns1[0].clone(), algns2[0].clone()),
        WalksPolicy::FiveUnique => (first_unique(algns1), first_unique(algns2)),
        WalksPolicy::ThreeAny => (
            algns1[algns1.len() - 1].clone(),
            algns2[algns2.len() - 1].clone(),
        ),
        WalksPolicy::ThreeUnique => (last_unique(algns1), last_unique(algns2)),
        WalksPolicy::All => unreachable!("handled above"),
    };
    out.push((a, b, (1, "R1-2")));
}

/// pairtools' `check_pair_order`: by mapping first, then, with both sides on a chromosome, by
/// chromosome rank and position.
fn in_pair_order(a: &Alignment, b: &Alignment, order: &ChromOrder) -> bool {
    match (a.chrom, b.chrom) {
        (Some(ca), Some(cb)) => (order.ranks[ca], a.pos) <= (order.ranks[cb], b.pos),
        _ => (a.is_mapped, a.is_unique) <= (b.is_mapped, b.is_unique),
    }
}

/// Write a pair as a line of the output's columns (pairtools' `write_pairsam`).
pub fn write_pair(
    pair: &ParsedPair,
    group: &ReadGroup,
    order: &ChromOrder,
    params: &ParseParams,
    out: &mut Vec<u8>,
) {
    let chrom = |a: &Alignment| a.chrom.map_or("!", |c| order.names[c].as_str());
    if params.drop_readid {
        out.push(b'.');
    } else {
        out.extend_from_slice(&group.name);
    }
    for side in [&pair.side1, &pair.side2] {
        out.push(b'\t');
        out.extend_from_slice(chrom(side).as_bytes());
        out.push(b'\t');
        push_integer(out, side.pos);
    }
    out.extend_from_slice(&[b'\t', pair.side1.strand, b'\t', pair.side2.strand, b'\t']);
    out.extend_from_slice(&pair.pair_type());
    if params.keep_sam {
        let (first, second) = sam_sides(group);
        let (first, second) = if pair.sams_swapped {
            (second, first)
        } else {
            (first, second)
        };
        for side in [first, second] {
            out.push(b'\t');
            write_sams(group, &side, pair, params.drop_seq, out);
        }
    }
    if params.add_pair_index {
        out.push(b'\t');
        out.extend_from_slice(pair.index.0.to_string().as_bytes());
        out.push(b'\t');
        out.extend_from_slice(pair.index.1.as_bytes());
    }
    for column in &params.add_columns {
        for side in [&pair.side1, &pair.side2] {
            out.push(b'\t');
            out.extend_from_slice(extra_column(side, column).as_bytes());
        }
    }
    out.push(b'\n');
}

/// Write an integer in decimal.
fn push_integer(out: &mut Vec<u8>, value: i64) {
    if value < 0 {
        out.push(b'-');
    }
    let mut digits = [0u8; 20];
    let mut rest = value.unsigned_abs();
    let mut at = digits.len();
    loop {
        at -= 1;
        digits[at] = b'0' + (rest % 10) as u8;
        rest /= 10;
        if rest == 0 {
            break;
        }
    }
    out.extend_from_slice(&digits[at..]);
}

/// The group's records of read 1 and of read 2, each in pairtools' order.
fn sam_sides(group: &ReadGroup) -> (Vec<usize>, Vec<usize>) {
    let records = &group.records;
    let mut indices: Vec<usize> = (0..records.len()).collect();
    indices.sort_by_key(|&i| (!records[i].is_read1(), records[i].query_alignment_start()));
    indices.into_iter().partition(|&i| records[i].is_read1())
}

fn write_sams(
    group: &ReadGroup,
    side: &[usize],
    pair: &ParsedPair,
    drop_seq: bool,
    out: &mut Vec<u8>,
) {
    for (k, &i) in side.iter().enumerate() {
        if k > 0 {
            out.extend_from_slice(b"\x19NEXT_SAM\x19");
        }
        let text = group.records[i].sam_text.as_deref().unwrap_or("");
        for (f, field) in text.split('\t').enumerate() {
            if f > 0 {
                out.push(0x19);
            }
            if drop_seq && (f == 9 || f == 10) {
                out.push(b'*');
            } else {
                out.extend_from_slice(field.as_bytes());
            }
        }
        out.extend_from_slice(b"\x19Yt:Z:");
        out.extend_from_slice(&pair.pair_type());
    }
}

/// An extra column's value for one side, as pairtools writes it (`str()` of the value; empty
/// where the alignment has none).
fn extra_column(a: &Alignment, column: &str) -> String {
    let optional = |value: Option<u32>| value.map_or(String::new(), |v| v.to_string());
    match column {
        "mapq" => a.mapq.to_string(),
        "pos5" => a.pos5.to_string(),
        "pos3" => a.pos3.to_string(),
        "cigar" => match a.cigar {
            CigarText::Text => a.cigar_text().to_string(),
            CigarText::Absent => "None".into(),
            CigarText::Star => "*".into(),
        },
        "read_len" => a.geometry.read_len.to_string(),
        "matched_bp" => a.geometry.matched_bp.to_string(),
        "algn_ref_span" => a.geometry.algn_ref_span.to_string(),
        "algn_read_span" => a.geometry.algn_read_span.to_string(),
        "dist_to_5" => a.dist_to_5.to_string(),
        "dist_to_3" => a.dist_to_3.to_string(),
        "seq" => match a.sequence() {
            Some(Some(seq)) => seq.to_string(),
            Some(None) => "None".into(),
            None => String::new(),
        },
        "mismatches" => a.mismatches().to_string(),
        "read_side" => optional(a.read_side.map(u32::from)),
        "algn_idx" => optional(a.algn_idx),
        "same_side_algn_count" => optional(a.same_side_algn_count),
        _ => String::new(),
    }
}
