//! One alignment as pairtools sees it: its side's 5' position, strand, uniqueness, and the
//! read geometry its CIGAR gives (clipping, spans), from an [`AlignmentRecord`].
//!
//! The CIGAR is read as pairtools reads it: `M` counts as matched, aligned on the read and the
//! reference; `I` on the read; `D` on the reference; `S` and `H` as clipping (at the 5' end of
//! the record until the first `M`, at its 3' end after); `N`, `P`, `=` and `X` are not counted
//! (bwa writes none of them).

use crate::io::pairs::AlignmentRecord;

/// The type letter of a side: `U` unique, `M` multi-mapping (MAPQ under the threshold), `N`
/// unmapped (null), `R` the linear side of a rescued walk, `X` no alignment at all, `W` a
/// masked walk.
pub type SideType = u8;

/// What `--min-mapq` and the other per-alignment settings decide.
#[derive(Clone, Copy, Debug)]
pub struct AlignmentSettings {
    /// The smallest MAPQ of a unique alignment.
    pub min_mapq: u8,
    /// Whether the `mismatches` column is written (it needs `MD` and the bases).
    pub mismatches: bool,
    /// Whether the `seq` column is written.
    pub sequence: bool,
    /// Whether the `cigar` column is written (the CIGAR's text is made only then).
    pub cigar: bool,
}

/// What the CIGAR says about an alignment (pairtools' `cigar_dict`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CigarGeometry {
    /// Bases clipped before the first `M` (in the record's orientation).
    pub clip5_ref: i64,
    /// Bases clipped after an `M`.
    pub clip3_ref: i64,
    /// Bases in `M` operations.
    pub matched_bp: i64,
    /// Reference bases covered (`M`, `D`).
    pub algn_ref_span: i64,
    /// Read bases covered (`M`, `I`).
    pub algn_read_span: i64,
    /// The read's length (`M`, `I`, `S`, `H`).
    pub read_len: i64,
}

impl CigarGeometry {
    /// Measure a CIGAR (BAM operation codes).
    pub fn of(cigar: &[(u8, u32)]) -> CigarGeometry {
        let mut g = CigarGeometry::default();
        for &(op, len) in cigar {
            let len = i64::from(len);
            match op {
                0 => {
                    g.matched_bp += len;
                    g.algn_ref_span += len;
                    g.algn_read_span += len;
                    g.read_len += len;
                }
                1 => {
                    g.algn_read_span += len;
                    g.read_len += len;
                }
                2 => g.algn_ref_span += len,
                4 | 5 => {
                    g.read_len += len;
                    if g.matched_bp == 0 {
                        g.clip5_ref = len;
                    } else {
                        g.clip3_ref = len;
                    }
                }
                _ => {}
            }
        }
        g
    }
}

/// How the `cigar` column shows an alignment's CIGAR.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CigarText {
    /// The record's CIGAR (its text in [`AlignmentText::cigar`], when asked for).
    Text,
    /// A record without CIGAR (`*` in SAM): pysam's `None`.
    Absent,
    /// No record at all (a gap or a missing side): `*`.
    Star,
}

/// One alignment (pairtools' alignment dictionary).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Alignment {
    /// The chromosome (index into the input's `@SQ` lines); `None` is `!` (unmapped, or not
    /// unique).
    pub chrom: Option<usize>,
    /// The 5' end on the reference (1-based; 0 when not reported).
    pub pos5: i64,
    /// The 3' end on the reference.
    pub pos3: i64,
    /// The position written (`pos5`, or `pos3` with `--report-alignment-end 3`).
    pub pos: i64,
    /// `+` or `-`.
    pub strand: u8,
    /// MAPQ.
    pub mapq: u8,
    /// Mapped (flag 0x4 clear).
    pub is_mapped: bool,
    /// MAPQ at least `--min-mapq`.
    pub is_unique: bool,
    /// No `SA` tag.
    pub is_linear: bool,
    /// Read bases before the alignment, from the read's 5' end.
    pub dist_to_5: i64,
    /// Read bases after it, to the read's 3' end.
    pub dist_to_3: i64,
    /// The CIGAR's measures.
    pub geometry: CigarGeometry,
    /// The CIGAR as the `cigar` column shows it.
    pub cigar: CigarText,
    /// The type letter.
    pub kind: SideType,
    /// 1 or 2, set once the side's list is made.
    pub read_side: Option<u8>,
    /// Its index among its side's alignments.
    pub algn_idx: Option<u32>,
    /// The number of alignments on its side.
    pub same_side_algn_count: Option<u32>,
    /// The columns' text, made only when `--add-columns` asks for `cigar`, `mismatches` or
    /// `seq`: an alignment is moved several times while its read is classified, and without
    /// the text it is 144 bytes instead of 232 (moving them was 6% of `pairs parse`'s time).
    pub text: Option<Box<AlignmentText>>,
}

/// The text of an alignment's `cigar`, `mismatches` and `seq` columns.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct AlignmentText {
    /// The CIGAR, when `cigar` is asked for.
    pub cigar: String,
    /// `ref:read:phred:ref_pos:read_pos` for each mismatch, comma-separated.
    pub mismatches: String,
    /// The read's bases (pysam's `seq`; `None` when the record has none), when asked for.
    pub sequence: Option<Option<String>>,
}

impl Alignment {
    /// An empty alignment: no record, a gap in the read or a side without records.
    pub fn empty() -> Alignment {
        Alignment {
            chrom: None,
            pos5: 0,
            pos3: 0,
            pos: 0,
            strand: b'-',
            mapq: 0,
            is_mapped: false,
            is_unique: false,
            is_linear: true,
            dist_to_5: 0,
            dist_to_3: 0,
            geometry: CigarGeometry::default(),
            cigar: CigarText::Star,
            kind: b'N',
            read_side: None,
            algn_idx: None,
            same_side_algn_count: None,
            text: None,
        }
    }

    /// The alignment of a record (pairtools' `parse_pysam_entry`).
    pub fn of(record: &AlignmentRecord, settings: &AlignmentSettings) -> Alignment {
        let is_mapped = record.flags & 0x4 == 0;
        let is_unique = record.mapq >= settings.min_mapq;
        let geometry = CigarGeometry::of(&record.cigar);
        let reverse = record.flags & 0x10 != 0;
        let (mut chrom, mut pos5, mut pos3, mut strand) = (None, 0, 0, b'-');
        let (mut dist_to_5, mut dist_to_3) = (0, 0);
        let mut mismatches = String::new();
        if is_mapped {
            strand = if reverse { b'-' } else { b'+' };
            (dist_to_5, dist_to_3) = if reverse {
                (geometry.clip3_ref, geometry.clip5_ref)
            } else {
                (geometry.clip5_ref, geometry.clip3_ref)
            };
            if is_unique {
                chrom = record.reference_id;
                let reference_start = record.start as i64 - 1;
                if reverse {
                    pos5 = reference_start + geometry.algn_ref_span;
                    pos3 = reference_start + 1;
                } else {
                    pos5 = reference_start + 1;
                    pos3 = reference_start + geometry.algn_ref_span;
                }
                if settings.mismatches
                    && let Some(md) = &record.md
                {
                    mismatches = mismatch_list(record, md);
                }
            } else {
                strand = b'-';
            }
        }
        let sequence = settings.sequence.then(|| {
            (!record.sequence.is_empty())
                .then(|| String::from_utf8_lossy(&record.sequence).into_owned())
        });
        let text = (settings.cigar || settings.mismatches || settings.sequence).then(|| {
            Box::new(AlignmentText {
                cigar: if settings.cigar {
                    record.cigar_text().unwrap_or_default()
                } else {
                    String::new()
                },
                mismatches,
                sequence,
            })
        });
        Alignment {
            chrom,
            pos5,
            pos3,
            pos: pos5,
            strand,
            mapq: record.mapq,
            is_mapped,
            is_unique,
            is_linear: !record.has_supplementary_tag,
            dist_to_5,
            dist_to_3,
            geometry,
            cigar: if record.cigar.is_empty() {
                CigarText::Absent
            } else {
                CigarText::Text
            },
            kind: if !is_mapped {
                b'N'
            } else if !is_unique {
                b'M'
            } else {
                b'U'
            },
            read_side: None,
            algn_idx: None,
            same_side_algn_count: None,
            text,
        }
    }

    /// The `mismatches` column's text (empty unless asked for).
    pub fn mismatches(&self) -> &str {
        self.text.as_ref().map_or("", |t| &t.mismatches)
    }

    /// The `seq` column's value (`None` unless asked for).
    pub fn sequence(&self) -> Option<Option<&str>> {
        self.text
            .as_ref()
            .and_then(|t| t.sequence.as_ref())
            .map(|s| s.as_deref())
    }

    /// The CIGAR's text (empty unless asked for).
    pub fn cigar_text(&self) -> &str {
        self.text.as_ref().map_or("", |t| &t.cigar)
    }

    /// Mapped and unique.
    pub fn is_mapped_unique(&self) -> bool {
        self.is_mapped && self.is_unique
    }

    /// The type letter from mapping alone (`N`, `M` or `U`), as pairtools' `format_pair` resets
    /// it.
    pub fn mapping_kind(&self) -> SideType {
        if !self.is_mapped {
            b'N'
        } else if !self.is_unique {
            b'M'
        } else {
            b'U'
        }
    }

    /// Reset the coordinates (a masked walk).
    pub fn masked(mut self) -> Alignment {
        self.chrom = None;
        self.pos5 = 0;
        self.pos3 = 0;
        self.pos = 0;
        self.strand = b'-';
        self
    }

    /// The other strand.
    pub fn flip_orientation(&mut self) {
        self.strand = if self.strand == b'-' { b'+' } else { b'-' };
    }

    /// Swap the 5' and 3' ends.
    pub fn flip_position(&mut self) {
        std::mem::swap(&mut self.pos5, &mut self.pos3);
    }
}

/// pairtools' `mismatches` column: every aligned base (`M`, `=`, `X`) where the read differs
/// from the reference the `MD` tag gives, as `REF:READ:PHRED:REF_POS:READ_POS` (0-based
/// positions on the reference and on the stored read), comma-separated.
fn mismatch_list(record: &AlignmentRecord, md: &str) -> String {
    let reference = md_reference_bases(md);
    let mut out = Vec::new();
    let mut read_pos = 0usize;
    let mut ref_pos = record.start as i64 - 1;
    let mut aligned = 0usize;
    for &(op, len) in &record.cigar {
        let len = len as usize;
        match op {
            0 | 7 | 8 => {
                for k in 0..len {
                    let ref_base = reference.get(aligned + k).copied().flatten();
                    let read_base = record
                        .sequence
                        .get(read_pos + k)
                        .map(|b| b.to_ascii_uppercase());
                    if let (Some(ref_base), Some(read_base)) = (ref_base, read_base)
                        && ref_base.to_ascii_uppercase() != read_base
                    {
                        let phred = record.qualities.get(read_pos + k).copied().unwrap_or(0);
                        out.push(format!(
                            "{}:{}:{}:{}:{}",
                            ref_base.to_ascii_uppercase() as char,
                            read_base as char,
                            phred,
                            ref_pos + k as i64,
                            read_pos + k
                        ));
                    }
                }
                aligned += len;
                read_pos += len;
                ref_pos += len as i64;
            }
            1 | 4 => read_pos += len,
            2 | 3 => ref_pos += len as i64,
            _ => {}
        }
    }
    out.join(",")
}

/// For each aligned base, in order, the reference base the `MD` tag names where it differs
/// (`Some(base)`), or `None` where it matches the read.
fn md_reference_bases(md: &str) -> Vec<Option<u8>> {
    let mut bases = Vec::new();
    let mut number = 0usize;
    let mut deletion = false;
    for &byte in md.as_bytes() {
        if byte.is_ascii_digit() {
            number = number * 10 + usize::from(byte - b'0');
            deletion = false;
        } else {
            bases.extend(std::iter::repeat_n(None, number));
            number = 0;
            if byte == b'^' {
                deletion = true;
            } else if !deletion {
                bases.push(Some(byte));
            }
        }
    }
    bases.extend(std::iter::repeat_n(None, number));
    bases
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(flags: u16, start: u64, mapq: u8, cigar: &[(u8, u32)]) -> AlignmentRecord {
        AlignmentRecord {
            flags,
            reference_id: Some(1),
            start,
            mapq,
            cigar: cigar.to_vec(),
            ..AlignmentRecord::default()
        }
    }

    const SETTINGS: AlignmentSettings = AlignmentSettings {
        min_mapq: 1,
        mismatches: true,
        sequence: false,
        cigar: true,
    };

    #[test]
    fn the_cigar_is_measured_as_pairtools_measures_it() {
        // 5S 10M 2I 3M 4D 6M 7H
        let g = CigarGeometry::of(&[(4, 5), (0, 10), (1, 2), (0, 3), (2, 4), (0, 6), (5, 7)]);
        assert_eq!(
            g,
            CigarGeometry {
                clip5_ref: 5,
                clip3_ref: 7,
                matched_bp: 19,
                algn_ref_span: 23,
                algn_read_span: 21,
                read_len: 33,
            }
        );
        // '=' and 'X' are not counted, as pairtools does not count them.
        assert_eq!(
            CigarGeometry::of(&[(7, 10), (8, 1)]),
            CigarGeometry::default()
        );
    }

    #[test]
    fn forward_and_reverse_alignments_report_their_5_prime_ends() {
        let forward = Alignment::of(&record(0x41, 100, 60, &[(4, 10), (0, 40)]), &SETTINGS);
        assert_eq!(
            (forward.pos5, forward.pos3, forward.strand),
            (100, 139, b'+')
        );
        assert_eq!((forward.dist_to_5, forward.dist_to_3), (10, 0));
        let reverse = Alignment::of(&record(0x51, 100, 60, &[(4, 10), (0, 40)]), &SETTINGS);
        assert_eq!(
            (reverse.pos5, reverse.pos3, reverse.strand),
            (139, 100, b'-')
        );
        assert_eq!((reverse.dist_to_5, reverse.dist_to_3), (0, 10));
        assert_eq!(reverse.kind, b'U');
    }

    #[test]
    fn multimappers_lose_their_coordinates_but_keep_their_clipping() {
        let multi = Alignment::of(&record(0x51, 100, 0, &[(4, 10), (0, 40)]), &SETTINGS);
        assert_eq!(
            (multi.chrom, multi.pos5, multi.strand, multi.kind),
            (None, 0, b'-', b'M')
        );
        assert_eq!(multi.dist_to_5, 0);
        assert_eq!(multi.dist_to_3, 10);
        let unmapped = Alignment::of(&record(0x45, 0, 0, &[]), &SETTINGS);
        assert_eq!((unmapped.kind, unmapped.cigar), (b'N', CigarText::Absent));
    }

    #[test]
    fn mismatches_come_from_md_against_the_read() {
        let mut r = record(0x41, 11, 60, &[(4, 2), (0, 5), (2, 2), (0, 3)]);
        r.sequence = b"NNACGTAGGT".to_vec();
        r.qualities = vec![30, 31, 32, 33, 34, 35, 36, 37, 38, 39];
        // Reference ACCTA ^TT GGT: base 2 of the first block is C where the read has G.
        r.md = Some("2C2^TT3".into());
        let a = Alignment::of(&r, &SETTINGS);
        // Read position 4 (after 2 clipped), reference position 10 + 2 = 12 (0-based).
        assert_eq!(a.mismatches(), "C:G:34:12:4");
        assert_eq!(
            md_reference_bases("2C0^A1"),
            vec![None, None, Some(b'C'), None]
        );
    }
}
