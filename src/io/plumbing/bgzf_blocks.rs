//! BGZF (block gzip) inflated in pieces of whole blocks on worker threads and handed out in
//! order, each piece one contiguous buffer that its reader may keep (shared) while it reads
//! the next: a record that lies inside a piece is read where it was inflated, never copied.
//!
//! noodles' multithreaded reader hands out one block at a time through a channel per block and
//! copies each record out of it; reading BAM that way, the hand-offs and the copies cost a
//! quarter of `pairs parse`'s time on two cores. Blocks are framed as the SAM/BAM
//! specification's BGZF section says (a gzip member with the `BC` extra field giving its size),
//! inflated with libdeflate and checked against their CRC32 and length.

use std::io::{self, Read};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::sync::{Arc, Mutex};

use super::input::is_bgzf;

/// Blocks inflated per piece (about a megabyte of BAM records).
const BLOCKS_PER_PIECE: usize = 4;

/// The largest block BGZF allows (BSIZE is 16 bits).
const MAX_BLOCK: usize = 1 << 16;

/// A piece of the inflated input.
pub struct Piece {
    /// The inflated bytes of the piece's blocks, one after another.
    pub data: Vec<u8>,
}

/// One block of a job.
struct Block {
    /// Its deflate data's range in the job's `compressed`.
    deflated: std::ops::Range<usize>,
    crc: u32,
    inflated_len: u32,
    /// Where the block starts in the input (for errors).
    offset: u64,
}

/// A job: the compressed blocks of one piece and where to send the inflated piece.
struct Job {
    compressed: Vec<u8>,
    blocks: Vec<Block>,
    done: SyncSender<io::Result<Piece>>,
}

/// The pieces of a BGZF input, inflated ahead on `workers` threads (and one thread reading the
/// input); dropping it stops them.
pub struct BlockStream {
    pieces: Receiver<Receiver<io::Result<Piece>>>,
    ended: bool,
    spare: Spare,
}

/// Piece buffers given back, for the workers to inflate into again (a fresh megabyte for
/// each piece, and its release, cost page faults and the other core's TLB).
type Spare = Arc<Mutex<Vec<Vec<u8>>>>;

/// Buffers kept for reuse, at most.
const SPARE_BUFFERS: usize = 32;

impl BlockStream {
    /// Start inflating `input` on `workers` threads.
    pub fn new(input: Box<dyn Read + Send>, workers: usize) -> BlockStream {
        let workers = workers.max(1);
        let (order_tx, order_rx) = sync_channel(2 * workers + 2);
        let (job_tx, job_rx) = sync_channel::<Job>(workers);
        let job_rx = Arc::new(Mutex::new(job_rx));
        let spare: Spare = Arc::default();
        for _ in 0..workers {
            let jobs = Arc::clone(&job_rx);
            let spare = Arc::clone(&spare);
            std::thread::spawn(move || inflate_jobs(&jobs, &spare));
        }
        std::thread::spawn(move || split_blocks(input, &job_tx, &order_tx));
        BlockStream {
            pieces: order_rx,
            ended: false,
            spare,
        }
    }

    /// Give a piece's buffer back once read, to be inflated into again.
    pub fn give_back(&self, buffer: Vec<u8>) {
        if let Ok(mut spare) = self.spare.lock()
            && spare.len() < SPARE_BUFFERS
        {
            spare.push(buffer);
        }
    }

    /// The next piece; `None` at the end of the input (an error ends the stream).
    pub fn next_piece(&mut self) -> Option<io::Result<Piece>> {
        if self.ended {
            return None;
        }
        let piece = self.pieces.recv().ok().map(|done| {
            done.recv()
                .unwrap_or_else(|_| Err(io::Error::other("a BGZF worker stopped")))
        });
        if !matches!(piece, Some(Ok(_))) {
            self.ended = true;
        }
        piece
    }
}

fn inflate_jobs(jobs: &Mutex<Receiver<Job>>, spare: &Mutex<Vec<Vec<u8>>>) {
    let mut inflater = libdeflater::Decompressor::new();
    loop {
        // The lock is held only to take a job.
        let job = match jobs.lock() {
            Ok(jobs) => jobs.recv(),
            Err(_) => return,
        };
        let Ok(job) = job else { return };
        let buffer = spare
            .lock()
            .ok()
            .and_then(|mut s| s.pop())
            .unwrap_or_default();
        let result = inflate(&mut inflater, &job, buffer);
        let _ = job.done.send(result);
    }
}

fn inflate(
    inflater: &mut libdeflater::Decompressor,
    job: &Job,
    mut data: Vec<u8>,
) -> io::Result<Piece> {
    let total: usize = job.blocks.iter().map(|b| b.inflated_len as usize).sum();
    // Only bytes beyond the buffer's length are zeroed; the rest is overwritten.
    data.resize(total, 0);
    let mut at = 0;
    for block in &job.blocks {
        let len = block.inflated_len as usize;
        let out = &mut data[at..at + len];
        let corrupt = |what: &str| {
            io::Error::new(
                io::ErrorKind::InvalidData,
                format!(
                    "the BGZF block at byte {} is corrupt ({what})",
                    block.offset
                ),
            )
        };
        match inflater.deflate_decompress(&job.compressed[block.deflated.clone()], out) {
            Ok(n) if n == len => {}
            Ok(_) => return Err(corrupt("its length is not the one its trailer gives")),
            Err(_) => return Err(corrupt("its deflate data do not inflate")),
        }
        if libdeflater::crc32(out) != block.crc {
            return Err(corrupt("its CRC32 does not match"));
        }
        at += len;
    }
    Ok(Piece { data })
}

/// Read `input` block by block, sending each piece's blocks to the workers and the place its
/// result will come from to the reader, in order.
fn split_blocks(
    mut input: Box<dyn Read + Send>,
    jobs: &SyncSender<Job>,
    order: &SyncSender<Receiver<io::Result<Piece>>>,
) {
    let mut offset = 0u64;
    loop {
        let (done, piece) = sync_channel(1);
        let mut job = Job {
            compressed: Vec::with_capacity(BLOCKS_PER_PIECE * MAX_BLOCK / 2),
            blocks: Vec::with_capacity(BLOCKS_PER_PIECE),
            done,
        };
        // The input's end, or the error that ends it.
        let mut end = None;
        while job.blocks.len() < BLOCKS_PER_PIECE && end.is_none() {
            match read_block(&mut input, &mut job, offset) {
                Ok(Some(size)) => offset += size as u64,
                Ok(None) => end = Some(Ok(())),
                Err(e) => end = Some(Err(e)),
            }
        }
        // The blocks before a bad one are inflated first, so that their records are read.
        if !job.blocks.is_empty() && (order.send(piece).is_err() || jobs.send(job).is_err()) {
            return;
        }
        match end {
            None => {}
            Some(Ok(())) => return,
            Some(Err(e)) => {
                let (done, piece) = sync_channel(1);
                let _ = done.send(Err(e));
                let _ = order.send(piece);
                return;
            }
        }
    }
}

/// Read one block into `job`: its size in the input, `None` at the end of the input.
fn read_block(input: &mut dyn Read, job: &mut Job, offset: u64) -> io::Result<Option<usize>> {
    let mut header = [0u8; 18];
    let n = read_full(input, &mut header)?;
    if n == 0 {
        return Ok(None);
    }
    let bad = |what: String| io::Error::new(io::ErrorKind::InvalidData, what);
    if n < header.len() {
        return Err(bad(format!("the BGZF block at byte {offset} is cut short")));
    }
    if !is_bgzf(&header) {
        return Err(bad(format!(
            "the data at byte {offset} is not a BGZF block header"
        )));
    }
    let extra_len = u16::from_le_bytes([header[10], header[11]]) as usize;
    if extra_len != 6 {
        return Err(bad(format!(
            "the BGZF block at byte {offset} has extra fields BGZF readers do not expect"
        )));
    }
    let size = u16::from_le_bytes([header[16], header[17]]) as usize + 1;
    if size < header.len() + 8 {
        return Err(bad(format!(
            "the BGZF block at byte {offset} gives an impossible size ({size} bytes)"
        )));
    }
    let start = job.compressed.len();
    job.compressed.resize(start + size - header.len(), 0);
    let rest = &mut job.compressed[start..];
    if read_full(input, rest)? < rest.len() {
        return Err(bad(format!("the BGZF block at byte {offset} is cut short")));
    }
    let trailer = &rest[rest.len() - 8..];
    let crc = u32::from_le_bytes([trailer[0], trailer[1], trailer[2], trailer[3]]);
    let isize = u32::from_le_bytes([trailer[4], trailer[5], trailer[6], trailer[7]]);
    if isize as usize > MAX_BLOCK {
        return Err(bad(format!(
            "the BGZF block at byte {offset} claims {isize} inflated bytes, over BGZF's 65,536"
        )));
    }
    job.blocks.push(Block {
        deflated: start..job.compressed.len() - 8,
        crc,
        inflated_len: isize,
        offset,
    });
    Ok(Some(size))
}

/// Read until `buf` is full or the input ends: the number of bytes read.
fn read_full(input: &mut dyn Read, buf: &mut [u8]) -> io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match input.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(n)
}

/// The stream's bytes through [`Read`] (for a header read before the records).
pub struct PieceReader {
    stream: BlockStream,
    piece: Vec<u8>,
    at: usize,
}

impl PieceReader {
    /// Read `stream` from its start.
    pub fn new(stream: BlockStream) -> PieceReader {
        PieceReader {
            stream,
            piece: Vec::new(),
            at: 0,
        }
    }

    /// The stream, and the bytes of the current piece not yet read.
    pub fn into_parts(self) -> (BlockStream, Vec<u8>) {
        (self.stream, self.piece[self.at..].to_vec())
    }
}

impl Read for PieceReader {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        while self.at == self.piece.len() {
            match self.stream.next_piece() {
                None => return Ok(0),
                Some(piece) => {
                    self.piece = piece?.data;
                    self.at = 0;
                }
            }
        }
        let n = buf.len().min(self.piece.len() - self.at);
        buf[..n].copy_from_slice(&self.piece[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bgzf(text: &[u8], block: usize) -> Vec<u8> {
        let mut writer = noodles::bgzf::io::Writer::new(Vec::new());
        for part in text.chunks(block) {
            std::io::Write::write_all(&mut writer, part).unwrap();
            // Each part its own block.
            std::io::Write::flush(&mut writer).unwrap();
        }
        writer.finish().unwrap()
    }

    fn all(data: Vec<u8>, workers: usize) -> io::Result<Vec<u8>> {
        let mut stream = BlockStream::new(Box::new(std::io::Cursor::new(data)), workers);
        let mut out = Vec::new();
        while let Some(piece) = stream.next_piece() {
            out.extend_from_slice(&piece?.data);
        }
        Ok(out)
    }

    fn text(n: usize) -> Vec<u8> {
        (0..n)
            .map(|i| format!("line {i}\n"))
            .collect::<String>()
            .into_bytes()
    }

    #[test]
    fn the_pieces_are_what_gzip_inflates_in_order() {
        let text = text(60_000);
        // Blocks of many sizes: many pieces of many blocks.
        let data = bgzf(&text, 3_001);
        let mut reference = Vec::new();
        flate2::read::MultiGzDecoder::new(&data[..])
            .read_to_end(&mut reference)
            .unwrap();
        assert_eq!(reference, text);
        for workers in [1, 2, 5] {
            assert_eq!(all(data.clone(), workers).unwrap(), text);
        }
        assert!(all(Vec::new(), 2).unwrap().is_empty());
    }

    #[test]
    fn cut_or_corrupt_blocks_are_errors_after_the_good_ones() {
        let text = text(20_000);
        let data = bgzf(&text, 1_000);
        let cut = data[..data.len() / 2].to_vec();
        let error = all(cut, 2).unwrap_err().to_string();
        assert!(error.contains("cut short"), "{error}");
        // A flipped byte inside the deflate data of the second block.
        let mut corrupt = data.clone();
        let second = 18 + u16::from_le_bytes([data[16], data[17]]) as usize + 1 - 18;
        corrupt[second + 18 + 30] ^= 0x55;
        let error = all(corrupt, 2).unwrap_err().to_string();
        assert!(error.contains("corrupt"), "{error}");
        // Named by where the second block starts, inside the first piece.
        assert!(error.contains(&format!("at byte {second} ")), "{error}");
        let mut not_bgzf = data;
        not_bgzf[0] = b'x';
        let error = all(not_bgzf, 1).unwrap_err().to_string();
        assert!(error.contains("not a BGZF block header"), "{error}");
    }

    #[test]
    fn the_piece_reader_reads_across_pieces() {
        let text = text(30_000);
        let data = bgzf(&text, 777);
        let stream = BlockStream::new(Box::new(std::io::Cursor::new(data)), 2);
        let mut reader = PieceReader::new(stream);
        let mut head = vec![0u8; 100_000];
        reader.read_exact(&mut head).unwrap();
        assert_eq!(head, text[..100_000]);
        let (mut stream, rest) = reader.into_parts();
        let mut tail = rest;
        while let Some(piece) = stream.next_piece() {
            tail.extend_from_slice(&piece.unwrap().data);
        }
        assert_eq!(tail, text[100_000..]);
    }
}
