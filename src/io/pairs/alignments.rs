//! The aligner's output that `contactmap pairs parse` reads: SAM or BAM (noodles), its records
//! grouped by read name, as `bwa mem -SP5M` writes them.
//!
//! BAM is inflated on worker threads in pieces of whole blocks
//! ([`crate::io::plumbing::bgzf_blocks`]) and its records stay where they were inflated (a
//! record across two pieces is copied); the header and each record's fields are read through
//! noodles. The records of a batch of read groups are decoded into plain [`AlignmentRecord`]s
//! on every core ([`RawBatch::decode`]). The input must be grouped by read name: a header that says
//! `SO:coordinate` is refused, and so is a read name met again after its group ended (the mates
//! of a coordinate-sorted or merged file arrive apart), with the command that groups it.

use std::collections::{HashMap, VecDeque};
use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::sync::Arc;

use noodles::sam::alignment::record::cigar::op::Kind;
use noodles::sam::alignment::record::data::field::Tag;
use noodles::{bam, sam};

use super::header::read_marked_lines;
use crate::error::{Error, Result};
use crate::io::plumbing::bgzf_blocks::{BlockStream, PieceReader};
use crate::io::plumbing::input::{is_bgzf, worker_count};

/// What the decoded records must carry beyond flags, position, MAPQ and CIGAR (the rest costs
/// time and is only decoded when an output column needs it).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RecordNeeds {
    /// The read's bases and qualities (the `seq` and `mismatches` columns).
    pub sequence: bool,
    /// The `MD` tag (the `mismatches` column).
    pub md: bool,
    /// The record as a SAM line (the `sam1` / `sam2` columns).
    pub sam_text: bool,
}

/// One CIGAR operation: its kind as BAM numbers it (`MIDNSHP=X` = 0..8) and its length.
pub type CigarOp = (u8, u32);

/// An alignment record as plain data.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct AlignmentRecord {
    /// The SAM flags.
    pub flags: u16,
    /// The reference sequence (index into the header's `@SQ` lines).
    pub reference_id: Option<usize>,
    /// The 1-based leftmost position; 0 when there is none.
    pub start: u64,
    /// MAPQ; 255 when not available.
    pub mapq: u8,
    /// The CIGAR operations (empty for `*`).
    pub cigar: Vec<CigarOp>,
    /// Whether the record has an `SA` tag (other parts of a chimeric alignment).
    pub has_supplementary_tag: bool,
    /// The `MD` tag, when asked for and present.
    pub md: Option<String>,
    /// The bases as letters (when asked for).
    pub sequence: Vec<u8>,
    /// The base qualities, Phred (when asked for).
    pub qualities: Vec<u8>,
    /// The record as a SAM line (when asked for).
    pub sam_text: Option<String>,
}

impl AlignmentRecord {
    /// The CIGAR as text (`None` for `*`, as pysam's `cigarstring` gives it).
    pub fn cigar_text(&self) -> Option<String> {
        if self.cigar.is_empty() {
            return None;
        }
        let mut text = String::new();
        for &(op, len) in &self.cigar {
            text.push_str(&len.to_string());
            text.push(b"MIDNSHP=X"[op as usize] as char);
        }
        Some(text)
    }

    /// Whether it is the first read of its pair (flag 0x40).
    pub fn is_read1(&self) -> bool {
        self.flags & 0x40 != 0
    }

    /// The query position of its first aligned base (soft clips at the start skipped, hard clips
    /// not counted), as pysam's `query_alignment_start`.
    pub fn query_alignment_start(&self) -> u64 {
        let mut start = 0u64;
        for &(op, len) in &self.cigar {
            match op {
                4 => start += u64::from(len),
                5 => {}
                _ => break,
            }
        }
        start
    }
}

/// The records of one read name, in file order.
#[derive(Clone, Debug, Default)]
pub struct ReadGroup {
    /// The read name.
    pub name: Vec<u8>,
    /// Its records.
    pub records: Vec<AlignmentRecord>,
}

/// A SAM record read (BAM records stay where they were inflated: [`Span`]).
type Raw = sam::Record;

/// Where a BAM record's bytes are: a piece of inflated blocks held by the batch, or the batch's
/// own buffer (a record across two pieces, or carried from the previous batch).
#[derive(Clone, Copy, Debug)]
struct Span {
    buffer: u32,
    start: u32,
    end: u32,
}

/// [`Span::buffer`] of the batch's own buffer.
const OWN: u32 = u32::MAX;

/// Threads inflating BAM, at least (else half the cores): as with `pairs parse`'s classifying
/// threads, on few cores more threads than cores keep the cores busy (on two, parse alone of
/// the 10 M-pair BAM took 6.9 s with one inflating thread and two classifying, 6.2 s with four
/// and eight).
const MIN_INFLATERS: usize = 4;

/// A BAM record's name (without its NUL) and flags, from its bytes (checked by
/// [`check_bam_record`]).
fn bam_name(record: &[u8]) -> &[u8] {
    let len = usize::from(record[8]);
    let name = &record[32..32 + len];
    name.strip_suffix(b"\0").unwrap_or(name)
}

fn bam_flags(record: &[u8]) -> u16 {
    u16::from_le_bytes([record[14], record[15]])
}

/// The record's fixed fields and lengths are consistent with its size (what noodles' reader
/// checks before it hands a record out).
fn check_bam_record(record: &[u8]) -> std::io::Result<()> {
    let cut = || {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "the record is shorter than its fields' lengths",
        )
    };
    if record.len() < 32 {
        return Err(cut());
    }
    let name = usize::from(record[8]);
    let cigar = usize::from(u16::from_le_bytes([record[12], record[13]]));
    let bases = u32::from_le_bytes([record[16], record[17], record[18], record[19]]) as usize;
    let end = 32 + name + 4 * cigar + bases.div_ceil(2) + bases;
    if record.len() < end {
        Err(cut())
    } else {
        Ok(())
    }
}

/// Records read from the input, grouped by name, not yet decoded.
pub struct RawBatch {
    /// SAM records.
    records: Vec<Raw>,
    /// BAM records, in the pieces below or in `own`.
    spans: Vec<Span>,
    pieces: Vec<Arc<Vec<u8>>>,
    own: Vec<u8>,
    /// For each group: its records' range and the 1-based number of its first record.
    groups: Vec<(usize, usize, u64)>,
    header: Arc<sam::Header>,
    path: Arc<str>,
    /// Lines before the first record (SAM), so that record numbers become line numbers.
    header_lines: u64,
    is_sam: bool,
}

impl RawBatch {
    /// The number of read groups.
    pub fn len(&self) -> usize {
        self.groups.len()
    }

    /// Whether the batch has no group (the input has ended).
    pub fn is_empty(&self) -> bool {
        self.groups.is_empty()
    }

    /// Decode group `i` into plain records.
    pub fn decode(&self, i: usize, needs: &RecordNeeds) -> Result<ReadGroup> {
        let mut group = ReadGroup::default();
        self.decode_into(i, needs, &mut group)?;
        Ok(group)
    }

    /// Decode group `i` into `group`, reusing its buffers (a task decodes many groups).
    pub fn decode_into(&self, i: usize, needs: &RecordNeeds, group: &mut ReadGroup) -> Result<()> {
        let (start, end, first) = self.groups[i];
        group.name.clear();
        if self.is_sam {
            group.name.extend_from_slice(sam_name(&self.records[start]));
        } else {
            group
                .name
                .extend_from_slice(bam_name(self.bytes(self.spans[start])));
        }
        let n = end - start;
        group.records.truncate(n);
        group.records.resize_with(n, AlignmentRecord::default);
        for (k, (index, record)) in (start..end).zip(group.records.iter_mut()).enumerate() {
            if self.is_sam {
                decode(&self.records[index], &self.header, needs, record)
            } else {
                // Checked when read: at least 32 bytes, its fields within it.
                let raw = bam::RecordRef::new(self.bytes(self.spans[index]))
                    .expect("records are checked as they are read");
                decode_bam(&raw, &self.header, needs, record)
            }
            .map_err(|e| self.record_error(first + k as u64, &e.to_string()))?;
        }
        Ok(())
    }

    /// A BAM record's bytes.
    fn bytes(&self, span: Span) -> &[u8] {
        let buffer = match span.buffer {
            OWN => &self.own[..],
            i => &self.pieces[i as usize][..],
        };
        &buffer[span.start as usize..span.end as usize]
    }

    fn record_error(&self, number: u64, message: &str) -> Error {
        if self.is_sam {
            Error::Parse {
                path: (*self.path).into(),
                line: self.header_lines + number,
                message: format!("not a valid SAM record: {message}"),
            }
        } else {
            Error::Format {
                path: (*self.path).into(),
                message: format!("BAM record {number}: {message}"),
            }
        }
    }
}

/// A BAM record's fields through noodles' BAM types (no boxed trait objects: this runs for
/// every record); what only some columns need goes through [`decode_extras`].
fn decode_bam(
    record: &bam::RecordRef<'_>,
    header: &sam::Header,
    needs: &RecordNeeds,
    out: &mut AlignmentRecord,
) -> std::io::Result<()> {
    out.flags = u16::from(record.flags());
    out.reference_id = record.reference_sequence_id().transpose()?;
    let n_references = header.reference_sequences().len();
    if let Some(id) = out.reference_id
        && id >= n_references
    {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("reference sequence {id}, but the header has {n_references} @SQ lines"),
        ));
    }
    out.start = record
        .alignment_start()
        .transpose()?
        .map_or(0, |p| usize::from(p) as u64);
    out.mapq = record.mapping_quality().map_or(255, u8::from);
    set_cigar(record.cigar().iter(), &mut out.cigar)?;
    out.has_supplementary_tag =
        has_bam_tag(record.data().as_bytes(), Tag::OTHER_ALIGNMENTS.into())?;
    decode_extras(record, header, needs, out)
}

/// Whether BAM data fields (`tag`, type, value, ...) hold `tag`: the fields are stepped over by
/// their types' sizes without decoding the values (noodles' `Data::get` decodes each field it
/// passes, a tenth of `pairs parse`'s time for the one tag it looks up on every record).
fn has_bam_tag(mut data: &[u8], tag: [u8; 2]) -> std::io::Result<bool> {
    let invalid = |what: &str| std::io::Error::new(std::io::ErrorKind::InvalidData, what);
    let size = |ty: u8| match ty {
        b'A' | b'c' | b'C' => Some(1),
        b's' | b'S' => Some(2),
        b'i' | b'I' | b'f' => Some(4),
        _ => None,
    };
    while !data.is_empty() {
        let [t0, t1, ty, rest @ ..] = data else {
            return Err(invalid("a data field cut short"));
        };
        if [*t0, *t1] == tag {
            return Ok(true);
        }
        let skip = match ty {
            b'Z' | b'H' => rest
                .iter()
                .position(|&b| b == 0)
                .map(|end| end + 1)
                .ok_or_else(|| invalid("a string data field without its NUL"))?,
            b'B' => {
                let [sub, n0, n1, n2, n3, ..] = rest else {
                    return Err(invalid("an array data field cut short"));
                };
                let element = size(*sub).ok_or_else(|| invalid("an array of an unknown type"))?;
                let count = u32::from_le_bytes([*n0, *n1, *n2, *n3]) as usize;
                count
                    .checked_mul(element)
                    .and_then(|n| n.checked_add(5))
                    .ok_or_else(|| invalid("an array data field too long"))?
            }
            other => size(*other).ok_or_else(|| invalid("a data field of an unknown type"))?,
        };
        data = rest
            .get(skip..)
            .ok_or_else(|| invalid("a data field cut short"))?;
    }
    Ok(false)
}

/// A record's fields through noodles' generic record (SAM).
fn decode<R: sam::alignment::Record>(
    record: &R,
    header: &sam::Header,
    needs: &RecordNeeds,
    out: &mut AlignmentRecord,
) -> std::io::Result<()> {
    out.flags = u16::from(record.flags()?);
    out.reference_id = record.reference_sequence_id(header).transpose()?;
    out.start = record
        .alignment_start()
        .transpose()?
        .map_or(0, |p| usize::from(p) as u64);
    out.mapq = record.mapping_quality().transpose()?.map_or(255, u8::from);
    set_cigar(record.cigar().iter(), &mut out.cigar)?;
    let data = record.data();
    out.has_supplementary_tag = data.get(&Tag::OTHER_ALIGNMENTS).transpose()?.is_some();
    decode_extras(record, header, needs, out)
}

/// The CIGAR operations as BAM numbers them (`MIDNSHP=X` = 0..8).
fn set_cigar(
    ops: impl Iterator<Item = std::io::Result<noodles::sam::alignment::record::cigar::Op>>,
    out: &mut Vec<CigarOp>,
) -> std::io::Result<()> {
    out.clear();
    for op in ops {
        let op = op?;
        out.push((kind_code(op.kind()), op.len() as u32));
    }
    Ok(())
}

/// BAM's number for a CIGAR operation (`MIDNSHP=X` = 0..8).
fn kind_code(kind: Kind) -> u8 {
    match kind {
        Kind::Match => 0,
        Kind::Insertion => 1,
        Kind::Deletion => 2,
        Kind::Skip => 3,
        Kind::SoftClip => 4,
        Kind::HardClip => 5,
        Kind::Pad => 6,
        Kind::SequenceMatch => 7,
        Kind::SequenceMismatch => 8,
    }
}

/// The fields that only some output columns need: the MD tag, the bases and qualities, the
/// record as SAM text (cleared when not needed).
fn decode_extras<R: sam::alignment::Record>(
    record: &R,
    header: &sam::Header,
    needs: &RecordNeeds,
    out: &mut AlignmentRecord,
) -> std::io::Result<()> {
    out.md = None;
    if needs.md
        && let Some(sam::alignment::record::data::field::Value::String(s)) =
            record.data().get(&Tag::MISMATCHED_POSITIONS).transpose()?
    {
        out.md = Some(String::from_utf8_lossy(s).into_owned());
    }
    out.sequence.clear();
    out.qualities.clear();
    if needs.sequence {
        out.sequence.extend(record.sequence().iter());
        for q in record.quality_scores().iter() {
            out.qualities.push(q?);
        }
    }
    out.sam_text = None;
    if needs.sam_text {
        use noodles::sam::alignment::io::Write as _;
        let mut writer = sam::io::Writer::new(Vec::new());
        writer.write_alignment_record(header, record)?;
        let mut text = String::from_utf8_lossy(&writer.into_inner()).into_owned();
        while text.ends_with('\n') {
            text.pop();
        }
        out.sam_text = Some(text);
    }
    Ok(())
}

/// A SAM record's name.
fn sam_name(record: &sam::Record) -> &[u8] {
    record.name().map_or(&b"*"[..], |n| n)
}

fn sam_flags(record: &sam::Record) -> u16 {
    record.flags().map(u16::from).unwrap_or(0)
}

/// BAM's records as they come out of the inflated pieces.
struct BamInput {
    stream: BlockStream,
    /// The piece being read, and where.
    piece: Arc<Vec<u8>>,
    at: usize,
    /// The first record of the next group (read at the end of a batch).
    pending: Vec<u8>,
}

impl BamInput {
    /// Whether bytes are left (the next piece taken when this one is read).
    fn fill(&mut self) -> std::io::Result<bool> {
        while self.at == self.piece.len() {
            match self.stream.next_piece() {
                None => return Ok(false),
                Some(piece) => {
                    let read = std::mem::replace(&mut self.piece, Arc::new(piece?.data));
                    if let Ok(buffer) = Arc::try_unwrap(read) {
                        self.stream.give_back(buffer);
                    }
                    self.at = 0;
                }
            }
        }
        Ok(true)
    }

    /// Append the next `n` bytes (across pieces) to `out`: `false` when the input ends first.
    fn copy_into(&mut self, mut n: usize, out: &mut Vec<u8>) -> std::io::Result<bool> {
        while n > 0 {
            if !self.fill()? {
                return Ok(false);
            }
            let take = n.min(self.piece.len() - self.at);
            out.extend_from_slice(&self.piece[self.at..self.at + take]);
            self.at += take;
            n -= take;
        }
        Ok(true)
    }

    /// The next record, where it lies for `batch`; `None` at the end of the input.
    fn next_record(&mut self, batch: &mut RawBatch) -> std::io::Result<Option<Span>> {
        let ends_inside = || {
            std::io::Error::new(
                std::io::ErrorKind::UnexpectedEof,
                "the file ends inside the record",
            )
        };
        if !self.fill()? {
            return Ok(None);
        }
        let size = if let Some(bytes) = self.piece.get(self.at..self.at + 4) {
            self.at += 4;
            u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as usize
        } else {
            let mut bytes = Vec::with_capacity(4);
            if !self.copy_into(4, &mut bytes)? {
                return Err(ends_inside());
            }
            u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as usize
        };
        let span = if self.at + size <= self.piece.len() {
            if batch
                .pieces
                .last()
                .is_none_or(|p| !Arc::ptr_eq(p, &self.piece))
            {
                batch.pieces.push(Arc::clone(&self.piece));
            }
            let span = Span {
                buffer: (batch.pieces.len() - 1) as u32,
                start: self.at as u32,
                end: (self.at + size) as u32,
            };
            self.at += size;
            span
        } else {
            let start = batch.own.len();
            if !self.copy_into(size, &mut batch.own)? {
                return Err(ends_inside());
            }
            own_span(start, batch.own.len())
        };
        check_bam_record(batch.bytes(span))?;
        Ok(Some(span))
    }
}

fn own_span(start: usize, end: usize) -> Span {
    Span {
        buffer: OWN,
        start: start as u32,
        end: end as u32,
    }
}

enum Input {
    Bam(Box<BamInput>),
    Sam(sam::io::Reader<Box<dyn BufRead + Send>>),
}

/// How many incomplete read names (a group with one read's records only) are remembered to
/// catch mates that arrive apart.
const REMEMBERED_INCOMPLETE: usize = 100_000;

/// Reads SAM or BAM, a batch of read groups at a time.
pub struct AlignmentReader {
    input: Input,
    header: Arc<sam::Header>,
    header_text: String,
    path: Arc<str>,
    header_lines: u64,
    n_records: u64,
    /// A SAM record read that starts the next group (valid when `has_pending`; BAM keeps its
    /// own).
    pending: Raw,
    has_pending: bool,
    pending_number: u64,
    incomplete: HashMap<Vec<u8>, u64>,
    incomplete_order: VecDeque<Vec<u8>>,
}

impl AlignmentReader {
    /// Open SAM or BAM (told apart by the first bytes; `-` for standard input) and read its
    /// header. A coordinate-sorted input (`@HD ... SO:coordinate`) is refused.
    pub fn open(path: &Path) -> Result<AlignmentReader> {
        let name: Arc<str> = if path == Path::new("-") {
            "<stdin>".into()
        } else {
            path.display().to_string().into()
        };
        let raw: Box<dyn Read + Send> = if path == Path::new("-") {
            Box::new(std::io::stdin())
        } else {
            Box::new(std::fs::File::open(path).map_err(|e| Error::io(path, e))?)
        };
        let mut reader = BufReader::with_capacity(1 << 20, raw);
        let start = reader.fill_buf().map_err(|e| Error::io(path, e))?.to_vec();
        let format_error = |message: String| Error::Format {
            path: (*name).into(),
            message,
        };
        let (input, header, header_text, header_lines) = if is_bgzf(&start) {
            // Inflating is about half of parse's work: half the cores inflate, at least
            // MIN_INFLATERS threads (one inflater on two cores was the critical path).
            let workers = (worker_count().get() / 2).max(MIN_INFLATERS);
            let stream = BlockStream::new(Box::new(reader), workers);
            let mut bam = bam::io::Reader::from(PieceReader::new(stream));
            let header = bam.read_header().map_err(|e| {
                format_error(format!("not a readable BAM header: {e} (is it BAM?)"))
            })?;
            let text = header_as_text(&header);
            let (stream, rest) = bam.into_inner().into_parts();
            let input = BamInput {
                stream,
                piece: Arc::new(rest),
                at: 0,
                pending: Vec::new(),
            };
            (Input::Bam(Box::new(input)), header, text, 0)
        } else if start.starts_with(b"CRAM") {
            return Err(format_error(
                "CRAM is not read here: convert it to BAM first (samtools view -b -T REF.fa)"
                    .into(),
            ));
        } else if start.starts_with(&[0x1f, 0x8b]) {
            return Err(format_error(
                "gzip that is not BGZF: give SAM as plain text, or BAM".into(),
            ));
        } else {
            let mut input: Box<dyn BufRead + Send> = Box::new(reader);
            let lines = read_marked_lines(&mut input, b'@', &name)?;
            let n_lines = lines.len() as u64;
            let text: String = lines.iter().map(|l| format!("{l}\n")).collect();
            let header: sam::Header = text
                .parse()
                .map_err(|e| format_error(format!("not a valid SAM header: {e}")))?;
            (
                Input::Sam(sam::io::Reader::new(input)),
                header,
                text,
                n_lines,
            )
        };
        if header.reference_sequences().is_empty() {
            return Err(format_error(
                "the header has no @SQ lines: pairs need the reference's chromosomes (with \
                 samtools view, pass -h to keep the header)"
                    .into(),
            ));
        }
        let coordinate_sorted = header_text
            .lines()
            .find(|l| l.starts_with("@HD"))
            .is_some_and(|l| l.split('\t').any(|f| f == "SO:coordinate"));
        if coordinate_sorted {
            return Err(format_error(
                "sorted by coordinate (@HD SO:coordinate): the records of each read must come \
                 together; group them by name first (samtools collate -o grouped.bam IN.bam, or \
                 samtools sort -n)"
                    .into(),
            ));
        }
        Ok(AlignmentReader {
            input,
            header: Arc::new(header),
            header_text,
            path: name,
            header_lines,
            n_records: 0,
            pending: Raw::default(),
            has_pending: false,
            pending_number: 0,
            incomplete: HashMap::new(),
            incomplete_order: VecDeque::new(),
        })
    }

    /// The chromosomes of the `@SQ` lines, with their lengths, in order.
    pub fn chromosomes(&self) -> Vec<(String, u64)> {
        self.header
            .reference_sequences()
            .iter()
            .map(|(name, map)| (name.to_string(), usize::from(map.length()) as u64))
            .collect()
    }

    /// The header as SAM text lines (without line ends).
    pub fn header_lines(&self) -> Vec<String> {
        self.header_text.lines().map(str::to_string).collect()
    }

    /// The input's name, as errors give it.
    pub fn path(&self) -> &str {
        &self.path
    }

    /// The number of records read so far.
    pub fn n_records(&self) -> u64 {
        self.n_records
    }

    /// The error for a record that cannot be read.
    fn read_error(&self, number: u64, e: &dyn std::fmt::Display) -> Error {
        match &self.input {
            Input::Sam(_) => Error::Parse {
                path: (*self.path).into(),
                line: self.header_lines + number,
                message: format!("not a valid SAM record: {e}"),
            },
            Input::Bam(_) => Error::Format {
                path: (*self.path).into(),
                message: format!("BAM record {number}: {e} (a truncated or corrupt file?)"),
            },
        }
    }

    /// Read the next SAM record into `slot` (its buffers reused); `false` at the end of the
    /// input.
    fn read_sam(&mut self, slot: &mut Raw) -> Result<bool> {
        let number = self.n_records + 1;
        let Input::Sam(reader) = &mut self.input else {
            unreachable!("SAM records are read from SAM")
        };
        let n = reader
            .read_record(slot)
            .map_err(|e| self.read_error(number, &e))?;
        if n > 0 {
            self.n_records = number;
        }
        Ok(n > 0)
    }

    /// Read the next BAM record for `batch`; `None` at the end of the input.
    fn read_bam(&mut self, batch: &mut RawBatch) -> Result<Option<Span>> {
        let number = self.n_records + 1;
        let Input::Bam(input) = &mut self.input else {
            unreachable!("BAM records are read from BAM")
        };
        let span = input
            .next_record(batch)
            .map_err(|e| self.read_error(number, &e))?;
        if span.is_some() {
            self.n_records = number;
        }
        Ok(span)
    }

    /// An empty batch for [`AlignmentReader::read_batch`] (batches are reused: their records'
    /// buffers are kept from one batch to the next).
    pub fn new_batch(&self) -> RawBatch {
        RawBatch {
            records: Vec::new(),
            spans: Vec::new(),
            pieces: Vec::new(),
            own: Vec::new(),
            groups: Vec::new(),
            header: self.header.clone(),
            path: self.path.clone(),
            header_lines: self.header_lines,
            is_sam: matches!(self.input, Input::Sam(_)),
        }
    }

    /// Read up to `max_groups` read groups into `batch` (fewer at the end; none once the input
    /// has ended).
    pub fn read_batch(&mut self, batch: &mut RawBatch, max_groups: usize) -> Result<()> {
        batch.groups.clear();
        batch.spans.clear();
        for piece in batch.pieces.drain(..) {
            if let (Ok(buffer), Input::Bam(input)) = (Arc::try_unwrap(piece), &self.input) {
                input.stream.give_back(buffer);
            }
        }
        batch.own.clear();
        match self.input {
            Input::Bam(_) => self.read_bam_batch(batch, max_groups),
            Input::Sam(_) => self.read_sam_batch(batch, max_groups),
        }
    }

    fn read_bam_batch(&mut self, batch: &mut RawBatch, max_groups: usize) -> Result<()> {
        let mut ended = false;
        while batch.groups.len() < max_groups && !ended {
            let (first, first_number) = if self.has_pending {
                self.has_pending = false;
                let Input::Bam(input) = &self.input else {
                    unreachable!("BAM records are read from BAM")
                };
                let start = batch.own.len();
                batch.own.extend_from_slice(&input.pending);
                (own_span(start, batch.own.len()), self.pending_number)
            } else if let Some(span) = self.read_bam(batch)? {
                (span, self.n_records)
            } else {
                break;
            };
            let start = batch.spans.len();
            batch.spans.push(first);
            let flags = bam_flags(batch.bytes(first));
            let (mut has1, mut has2) = (flags & 0x40 != 0, flags & 0x40 == 0);
            loop {
                let Some(span) = self.read_bam(batch)? else {
                    ended = true;
                    break;
                };
                let record = batch.bytes(span);
                if bam_name(record) == bam_name(batch.bytes(first)) {
                    if bam_flags(record) & 0x40 != 0 {
                        has1 = true;
                    } else {
                        has2 = true;
                    }
                    batch.spans.push(span);
                } else {
                    if let Input::Bam(input) = &mut self.input {
                        input.pending.clear();
                        input.pending.extend_from_slice(record);
                    }
                    self.has_pending = true;
                    self.pending_number = self.n_records;
                    break;
                }
            }
            let name = bam_name(batch.bytes(first));
            self.check_grouped(name, has1 && has2, first_number)?;
            batch.groups.push((start, batch.spans.len(), first_number));
        }
        Ok(())
    }

    fn read_sam_batch(&mut self, batch: &mut RawBatch, max_groups: usize) -> Result<()> {
        let mut n = 0usize;
        let mut ended = false;
        while batch.groups.len() < max_groups && !ended {
            if batch.records.len() <= n {
                batch.records.push(Raw::default());
            }
            let first_number = if self.has_pending {
                std::mem::swap(&mut batch.records[n], &mut self.pending);
                self.has_pending = false;
                self.pending_number
            } else if self.read_sam(&mut batch.records[n])? {
                self.n_records
            } else {
                break;
            };
            let start = n;
            n += 1;
            let flags = sam_flags(&batch.records[start]);
            let (mut has1, mut has2) = (flags & 0x40 != 0, flags & 0x40 == 0);
            loop {
                if batch.records.len() <= n {
                    batch.records.push(Raw::default());
                }
                let (head, tail) = batch.records.split_at_mut(n);
                let slot = &mut tail[0];
                if !self.read_sam(slot)? {
                    ended = true;
                    break;
                }
                if sam_name(slot) == sam_name(&head[start]) {
                    if sam_flags(slot) & 0x40 != 0 {
                        has1 = true;
                    } else {
                        has2 = true;
                    }
                    n += 1;
                } else {
                    std::mem::swap(slot, &mut self.pending);
                    self.has_pending = true;
                    self.pending_number = self.n_records;
                    break;
                }
            }
            let name = sam_name(&batch.records[start]);
            self.check_grouped(name, has1 && has2, first_number)?;
            batch.groups.push((start, n, first_number));
        }
        Ok(())
    }

    /// A read name met again after its group ended is refused; names of groups with only one
    /// read's records are remembered (the most recent ones) to catch it.
    fn check_grouped(&mut self, name: &[u8], complete: bool, number: u64) -> Result<()> {
        if let Some(&earlier) = self.incomplete.get(name) {
            let place = match self.pending_place(number) {
                Some(line) => format!("line {line}"),
                None => format!("record {number}"),
            };
            return Err(Error::Format {
                path: (*self.path).into(),
                message: format!(
                    "read '{}' at {place} was met before (record {earlier}) with other records \
                     between: the input is not grouped by read name (mates arrive apart). Group \
                     it first: samtools collate -o grouped.bam IN.bam (or samtools sort -n)",
                    String::from_utf8_lossy(name)
                ),
            });
        }
        if !complete {
            if self.incomplete_order.len() == REMEMBERED_INCOMPLETE
                && let Some(oldest) = self.incomplete_order.pop_front()
            {
                self.incomplete.remove(&oldest);
            }
            self.incomplete.insert(name.to_vec(), number);
            self.incomplete_order.push_back(name.to_vec());
        }
        Ok(())
    }

    fn pending_place(&self, number: u64) -> Option<u64> {
        matches!(self.input, Input::Sam(_)).then_some(self.header_lines + number)
    }
}

/// A header as SAM text (noodles' writer), for the `#samheader:` lines.
fn header_as_text(header: &sam::Header) -> String {
    let mut writer = sam::io::Writer::new(Vec::new());
    // Writing to memory cannot fail.
    let _ = writer.write_header(header);
    String::from_utf8_lossy(&writer.into_inner()).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tags_are_found_as_noodles_finds_them() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/pairs/sim.bam");
        let mut reader = bam::io::reader::Builder.build_from_path(&path).unwrap();
        reader.read_header().unwrap();
        let (mut n, mut with_sa) = (0, 0);
        for record in reader.records() {
            let record = record.unwrap();
            let data = record.data();
            for tag in [
                Tag::OTHER_ALIGNMENTS,
                Tag::MISMATCHED_POSITIONS,
                Tag::ALIGNMENT_HIT_COUNT,
            ] {
                let expected = data.get(&tag).transpose().unwrap().is_some();
                assert_eq!(has_bam_tag(data.as_bytes(), tag.into()).unwrap(), expected);
                with_sa += usize::from(expected && tag == Tag::OTHER_ALIGNMENTS);
            }
            n += 1;
        }
        assert!(n > 3000 && with_sa > 100, "{n} records, {with_sa} with SA");
        // Every value type, and fields cut short.
        let mut data = Vec::new();
        for (tag, ty, value) in [
            (*b"XA", b'A', &b"x"[..]),
            (*b"Xc", b'c', &[1][..]),
            (*b"Xs", b's', &[1, 0][..]),
            (*b"Xi", b'i', &[1, 0, 0, 0][..]),
            (*b"Xf", b'f', &[0, 0, 128, 63][..]),
            (*b"XZ", b'Z', &b"text\0"[..]),
            (*b"XH", b'H', &b"1AE3\0"[..]),
            (*b"XB", b'B', &[b's', 2, 0, 0, 0, 1, 0, 2, 0][..]),
            (*b"SA", b'Z', &b"chr1,5,+,3M,60,0;\0"[..]),
        ] {
            data.extend_from_slice(&tag);
            data.push(ty);
            data.extend_from_slice(value);
        }
        assert!(has_bam_tag(&data, *b"SA").unwrap());
        assert!(has_bam_tag(&data, *b"XB").unwrap());
        assert!(!has_bam_tag(&data, *b"NM").unwrap());
        for cut in [1, 5, 21, data.len() - 1] {
            assert!(has_bam_tag(&data[..cut], *b"NM").is_err(), "cut at {cut}");
        }
        let unknown = [b'X', b'Y', b'q', 0];
        assert!(has_bam_tag(&unknown, *b"NM").is_err());
    }

    /// A record's name, flags, chromosome, start, MAPQ, CIGAR and whether it has an SA tag.
    type Fields = (Vec<u8>, u16, Option<usize>, u64, u8, Vec<CigarOp>, bool);

    /// Every record of `path` through the reader's groups.
    fn records_of(path: &std::path::Path) -> Vec<Fields> {
        let mut reader = AlignmentReader::open(path).unwrap();
        let mut batch = reader.new_batch();
        let mut out = Vec::new();
        loop {
            reader.read_batch(&mut batch, 7).unwrap();
            if batch.is_empty() {
                return out;
            }
            for i in 0..batch.len() {
                let group = batch.decode(i, &RecordNeeds::default()).unwrap();
                for r in group.records {
                    let fields = (r.flags, r.reference_id, r.start, r.mapq, r.cigar);
                    out.push((
                        group.name.clone(),
                        fields.0,
                        fields.1,
                        fields.2,
                        fields.3,
                        fields.4,
                        r.has_supplementary_tag,
                    ));
                }
            }
        }
    }

    #[test]
    fn records_across_blocks_and_pieces_are_read_as_noodles_reads_them() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/pairs/sim.bam");
        // The reference: noodles' own reader, record by record.
        let mut reader = bam::io::reader::Builder.build_from_path(&path).unwrap();
        let header = reader.read_header().unwrap();
        let mut expected = Vec::new();
        for record in reader.records() {
            let record = record.unwrap();
            let mut cigar = Vec::new();
            set_cigar(record.cigar().iter(), &mut cigar).unwrap();
            expected.push((
                record.name().map(|n| n.to_vec()).unwrap(),
                u16::from(record.flags()),
                record.reference_sequence_id().transpose().unwrap(),
                record
                    .alignment_start()
                    .transpose()
                    .unwrap()
                    .map_or(0, |p| usize::from(p) as u64),
                record.mapping_quality().map_or(255, u8::from),
                cigar,
                record.data().get(&Tag::OTHER_ALIGNMENTS).is_some(),
            ));
        }
        assert!(!header.reference_sequences().is_empty() && expected.len() > 3000);
        assert_eq!(records_of(&path), expected);
        // The same BAM in blocks of 997 bytes: records (and the header) cut across blocks and
        // across the pieces they are inflated in.
        let mut bytes = Vec::new();
        flate2::read::MultiGzDecoder::new(std::fs::File::open(&path).unwrap())
            .read_to_end(&mut bytes)
            .unwrap();
        let mut writer = noodles::bgzf::io::Writer::new(Vec::new());
        for part in bytes.chunks(997) {
            std::io::Write::write_all(&mut writer, part).unwrap();
            std::io::Write::flush(&mut writer).unwrap();
        }
        let folder = tempfile::tempdir().unwrap();
        let rechunked = folder.path().join("rechunked.bam");
        std::fs::write(&rechunked, writer.finish().unwrap()).unwrap();
        assert_eq!(records_of(&rechunked), expected);
    }

    const HEADER: &str = "@HD\tVN:1.6\tSO:unsorted\n@SQ\tSN:chr1\tLN:1000\n@SQ\tSN:chr2\tLN:800\n";

    fn sam_file(body: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("in.sam");
        std::fs::write(&path, format!("{HEADER}{body}")).unwrap();
        (folder, path)
    }

    #[test]
    fn records_are_grouped_by_name_and_decoded() {
        let body = "r1\t65\tchr1\t100\t60\t10S40M\tchr2\t200\t0\t*\t*\tSA:Z:chr2,5,+,10M40S,60,0;\n\
                    r1\t129\tchr2\t200\t3\t50M\tchr1\t100\t0\t*\t*\n\
                    r2\t77\t*\t0\t0\t*\t*\t0\t0\t*\t*\n\
                    r2\t141\t*\t0\t0\t*\t*\t0\t0\t*\t*\n";
        let (_folder, path) = sam_file(body);
        let mut reader = AlignmentReader::open(&path).unwrap();
        assert_eq!(
            reader.chromosomes(),
            vec![("chr1".to_string(), 1000), ("chr2".to_string(), 800)]
        );
        let mut batch = reader.new_batch();
        reader.read_batch(&mut batch, 10).unwrap();
        assert_eq!(batch.len(), 2);
        let group = batch.decode(0, &RecordNeeds::default()).unwrap();
        assert_eq!(group.name, b"r1");
        let first = &group.records[0];
        assert_eq!(
            (first.flags, first.reference_id, first.start, first.mapq),
            (65, Some(0), 100, 60)
        );
        assert_eq!(first.cigar, vec![(4, 10), (0, 40)]);
        assert_eq!(first.cigar_text().as_deref(), Some("10S40M"));
        assert_eq!(first.query_alignment_start(), 10);
        assert!(first.has_supplementary_tag);
        assert!(!group.records[1].has_supplementary_tag);
        let unmapped = batch.decode(1, &RecordNeeds::default()).unwrap();
        assert_eq!(unmapped.records[0].cigar_text(), None);
        assert_eq!(unmapped.records[0].reference_id, None);
        reader.read_batch(&mut batch, 10).unwrap();
        assert!(batch.is_empty());
    }

    #[test]
    fn coordinate_sorted_input_is_refused_with_the_fix() {
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("sorted.sam");
        std::fs::write(&path, "@HD\tVN:1.6\tSO:coordinate\n@SQ\tSN:chr1\tLN:10\n").unwrap();
        let error = AlignmentReader::open(&path).err().unwrap().to_string();
        assert!(
            error.contains("SO:coordinate") && error.contains("samtools collate"),
            "{error}"
        );
    }

    #[test]
    fn mates_arriving_apart_are_refused() {
        let body = "r1\t65\tchr1\t100\t60\t50M\tchr2\t200\t0\t*\t*\n\
                    r2\t65\tchr1\t150\t60\t50M\tchr2\t200\t0\t*\t*\n\
                    r1\t129\tchr2\t200\t60\t50M\tchr1\t100\t0\t*\t*\n";
        let (_folder, path) = sam_file(body);
        let mut reader = AlignmentReader::open(&path).unwrap();
        let mut batch = reader.new_batch();
        let error = reader.read_batch(&mut batch, 10).err().unwrap().to_string();
        assert!(
            error.contains("read 'r1' at line 6") && error.contains("not grouped"),
            "{error}"
        );
    }

    #[test]
    fn a_bam_record_on_a_chromosome_the_header_lacks_is_an_error() {
        use noodles::sam::alignment::RecordBuf;
        use noodles::sam::alignment::io::Write as _;
        use noodles::sam::alignment::record::Flags;
        let header: sam::Header = HEADER.parse().unwrap();
        let record = |reference: usize| {
            RecordBuf::builder()
                .set_name("r1")
                .set_flags(Flags::SEGMENTED | Flags::FIRST_SEGMENT)
                .set_reference_sequence_id(reference)
                .build()
        };
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("in.bam");
        let mut writer = bam::io::Writer::new(std::fs::File::create(&path).unwrap());
        writer.write_header(&header).unwrap();
        // The file's header has two @SQ lines: 0 and 1 are fine, 2 is not (a damaged record,
        // written here against a header with a third line).
        let wider: sam::Header = format!("{HEADER}@SQ\tSN:chr3\tLN:500\n").parse().unwrap();
        for reference in [1, 2] {
            writer
                .write_alignment_record(&wider, &record(reference))
                .unwrap();
        }
        writer.try_finish().unwrap();
        drop(writer);
        let mut reader = AlignmentReader::open(&path).unwrap();
        let mut batch = reader.new_batch();
        reader.read_batch(&mut batch, 10).unwrap();
        assert_eq!(batch.len(), 1, "both records are named r1");
        let error = batch
            .decode(0, &RecordNeeds::default())
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("BAM record 2") && error.contains("2 @SQ lines"),
            "{error}"
        );
    }

    #[test]
    fn a_sam_line_with_too_few_fields_is_named_by_line() {
        let (_folder, path) = sam_file("r1\t65\tchr1\n");
        let mut reader = AlignmentReader::open(&path).unwrap();
        let mut batch = reader.new_batch();
        let result = reader
            .read_batch(&mut batch, 10)
            .and_then(|()| batch.decode(0, &RecordNeeds::default()).map(|_| ()));
        let error = result.unwrap_err().to_string();
        assert!(error.contains("in.sam:4:"), "{error}");
    }
}
