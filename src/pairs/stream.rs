//! `pairs parse` over a whole input: batches of read groups read by one thread (BAM inflated on
//! worker threads of its own), classified by workers that each take the next batch as soon as
//! they are free, the pairs written in input order and counted for the statistics.
//!
//! The workers are threads of their own, waiting on a channel, rather than a rayon loop per
//! batch: between rayon loops the pool's idle threads yield the CPU over and over
//! (`sched_yield`, 200,000 calls for 10 M read pairs on two cores, a tenth of `pairs parse`'s
//! time in the kernel), while a thread blocked on a channel sleeps until it is woken once.

use std::collections::BTreeMap;
use std::sync::Mutex;
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};

use super::parse::{
    ChromOrder, ParseParams, ParseScratch, ParsedPair, parse_read_into, write_pair,
};
use super::stats::PairCounter;
use crate::error::{Error, Result};
use crate::io::pairs::alignments::RawBatch;
use crate::io::pairs::{AlignmentReader, ReadGroup, RecordNeeds};

/// Read groups per batch. A batch is small (about 300 kB of records) so that its records are
/// still in the cache when they are classified: batches of 16,384 groups made `pairs parse` a
/// third slower on two cores, the records read from memory. Halving it to 256 costs 3% more
/// CPU in hand-offs.
const GROUPS_PER_BATCH: usize = 512;

/// Threads classifying batches, at least (else one per core). They wait on channels, for
/// the reader and for the writer, and with more threads than cores a core always has one to
/// run: on two cores `pairs parse | pairs sort | pairs dedup` of the 10 M-pair BAM took 14.2 s
/// with two classifying threads (and one inflating) and 12.5 s with eight (and four).
const MIN_CLASSIFIERS: usize = 8;

/// Batches in flight per worker (being read, waiting, classified, or written).
const BATCHES_PER_WORKER: usize = 3;

/// A batch of read groups and its pairs: it goes from the reader to a worker to the writer, and
/// back to the reader, its buffers kept.
struct Slot {
    batch: RawBatch,
    parsed: Parsed,
}

/// A slot on its way, numbered in input order; `Err` when reading or classifying it failed.
type Numbered = (u64, Result<Slot>);

/// One batch's pairs: their lines, and what the statistics count of each (kept only when they
/// are counted).
#[derive(Default)]
struct Parsed {
    text: Vec<u8>,
    counted: Vec<Counted>,
}

/// A pair's fields as [`PairCounter::add_pair`] reads them.
struct Counted {
    sides: [(Option<usize>, i64, u8); 2],
    pair_type: [u8; 2],
}

impl Counted {
    fn of(pair: &ParsedPair) -> Counted {
        let side = |a: &super::alignment::Alignment| (a.chrom, a.pos, a.strand);
        Counted {
            sides: [side(&pair.side1), side(&pair.side2)],
            pair_type: pair.pair_type(),
        }
    }
}

/// Parse every read group of `reader`, writing the pairs' lines through `write` in input order;
/// each pair is counted in `counter` (as `pairtools parse --output-stats` counts it) when given;
/// `progress` is told the number of read groups done after each batch. Batches are classified
/// on as many threads as rayon's pool has (the cores, or `RAYON_NUM_THREADS`), at least
/// eight.
pub fn parse_alignments(
    reader: AlignmentReader,
    order: &ChromOrder,
    params: &ParseParams,
    counter: Option<&mut PairCounter>,
    write: &mut dyn FnMut(&[u8]) -> Result<()>,
    progress: &mut dyn FnMut(u64),
) -> Result<()> {
    parse_in_batches(
        reader,
        order,
        params,
        counter,
        write,
        progress,
        GROUPS_PER_BATCH,
    )
}

/// [`parse_alignments`] with batches of `batch_groups` read groups.
fn parse_in_batches(
    mut reader: AlignmentReader,
    order: &ChromOrder,
    params: &ParseParams,
    mut counter: Option<&mut PairCounter>,
    write: &mut dyn FnMut(&[u8]) -> Result<()>,
    progress: &mut dyn FnMut(u64),
    batch_groups: usize,
) -> Result<()> {
    let workers = rayon::current_num_threads().max(MIN_CLASSIFIERS);
    let in_flight = BATCHES_PER_WORKER * workers + 1;
    let (empty_tx, empty_rx) = sync_channel::<Slot>(in_flight);
    let (full_tx, full_rx) = sync_channel::<Numbered>(in_flight);
    let (done_tx, done_rx) = sync_channel::<Numbered>(in_flight);
    for _ in 0..in_flight {
        let slot = Slot {
            batch: reader.new_batch(),
            parsed: Parsed::default(),
        };
        empty_tx
            .send(slot)
            .expect("the channel has room for every batch");
    }
    let full_rx = Mutex::new(full_rx);
    let needs = params.needs();
    let count = counter.is_some();
    std::thread::scope(|scope| {
        scope.spawn(move || read_batches(&mut reader, batch_groups, &empty_rx, &full_tx));
        for _ in 0..workers {
            let (full, done) = (&full_rx, done_tx.clone());
            let needs = &needs;
            scope.spawn(move || classify_batches(full, &done, order, params, needs, count));
        }
        drop(done_tx);
        // Returning drops the writer's channel ends, which stops the reader and the workers.
        let (done, empty) = (done_rx, empty_tx);
        let mut waiting = BTreeMap::new();
        let (mut next, mut n_groups) = (0u64, 0u64);
        loop {
            let slot = match waiting.remove(&next) {
                Some(slot) => slot,
                None => match done.recv() {
                    Ok((number, slot)) if number != next => {
                        waiting.insert(number, slot);
                        continue;
                    }
                    Ok((_, slot)) => slot,
                    Err(_) => {
                        return Err(Error::Invalid(
                            "pairs parse: a reading or classifying thread stopped".into(),
                        ));
                    }
                },
            };
            let slot = slot?;
            if slot.batch.is_empty() {
                return Ok(());
            }
            if let Some(counter) = counter.as_deref_mut() {
                count_pairs(counter, order, &slot.parsed.counted);
            }
            write(&slot.parsed.text)?;
            n_groups += slot.batch.len() as u64;
            progress(n_groups);
            crate::interrupt::check()?;
            next += 1;
            // The reader stops at the input's end (or an error it has sent) and no longer takes
            // slots back; what it sent is still to be received, so the loop goes on.
            let _ = empty.send(slot);
        }
    })
}

/// The reading thread: fill each slot given back with the next batch, numbered, until the
/// input ends (an empty batch is sent last) or fails.
fn read_batches(
    reader: &mut AlignmentReader,
    batch_groups: usize,
    empty: &Receiver<Slot>,
    full: &SyncSender<Numbered>,
) {
    let mut number = 0u64;
    while let Ok(mut slot) = empty.recv() {
        let result = reader.read_batch(&mut slot.batch, batch_groups);
        let stop = result.is_err() || slot.batch.is_empty();
        if full.send((number, result.map(|()| slot))).is_err() || stop {
            return;
        }
        number += 1;
    }
}

/// A worker: classify batches as they come, until the reader or the writer stops.
fn classify_batches(
    full: &Mutex<Receiver<Numbered>>,
    done: &SyncSender<Numbered>,
    order: &ChromOrder,
    params: &ParseParams,
    needs: &RecordNeeds,
    count: bool,
) {
    let mut group = ReadGroup::default();
    let mut scratch = ParseScratch::default();
    let mut pairs = Vec::new();
    loop {
        // The lock is held only to take a batch.
        let next = match full.lock() {
            Ok(full) => full.recv(),
            Err(_) => return,
        };
        let Ok((number, slot)) = next else { return };
        let result = slot.and_then(|mut slot| {
            let Parsed { text, counted } = &mut slot.parsed;
            text.clear();
            counted.clear();
            for i in 0..slot.batch.len() {
                slot.batch.decode_into(i, needs, &mut group)?;
                parse_read_into(&group, order, params, &mut scratch, &mut pairs);
                for pair in &pairs {
                    write_pair(pair, &group, order, params, text);
                    if count {
                        counted.push(Counted::of(pair));
                    }
                }
            }
            Ok(slot)
        });
        if done.send((number, result)).is_err() {
            return;
        }
    }
}

/// Count a batch's pairs.
fn count_pairs(counter: &mut PairCounter, order: &ChromOrder, counted: &[Counted]) {
    let name = |c: Option<usize>| c.map_or(&b"!"[..], |c| order.names[c].as_bytes());
    for pair in counted {
        let [(c1, p1, s1), (c2, p2, s2)] = pair.sides;
        // Strands come from the classification: always + or -, never refused.
        let _ = counter.add_pair(
            name(c1),
            p1 as u64,
            &[s1],
            name(c2),
            p2 as u64,
            &[s2],
            &pair.pair_type,
        );
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::io::text::read_chrom_sizes;
    use crate::pairs::tests::reference;

    const BAM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/pairs/sim.bam");
    const SIZES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/pairs/sim.chrom.sizes");

    /// Parse `bam` with the defaults on `threads` workers in batches of `batch_groups`, the
    /// lines handed to `write`.
    fn parse_with(
        bam: &Path,
        threads: usize,
        batch_groups: usize,
        write: &mut (dyn FnMut(&[u8]) -> Result<()> + Send),
    ) -> Result<()> {
        let reader = AlignmentReader::open(bam).unwrap();
        let sizes: Vec<(String, u64)> = read_chrom_sizes(Path::new(SIZES))
            .unwrap()
            .into_iter()
            .map(|c| (c.name, c.length_bp))
            .collect();
        let order = ChromOrder::new(&reader.chromosomes(), &sizes, false, SIZES).unwrap();
        let params = ParseParams::default();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            parse_in_batches(
                reader,
                &order,
                &params,
                None,
                write,
                &mut |_| {},
                batch_groups,
            )
        })
    }

    /// [`parse_with`] into a string: the lines written, and the result.
    fn parse(bam: &Path, threads: usize, batch_groups: usize) -> (String, Result<()>) {
        let mut text = Vec::new();
        let result = parse_with(bam, threads, batch_groups, &mut |bytes| {
            text.extend_from_slice(bytes);
            Ok(())
        });
        (String::from_utf8(text).unwrap(), result)
    }

    #[test]
    fn pairs_come_out_in_input_order_whichever_worker_classifies_them() {
        let expected: String = reference("sim.5unique.pairs.gz")
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| format!("{l}\n"))
            .collect();
        for threads in [1, 3, 7] {
            for batch_groups in [1, 7, GROUPS_PER_BATCH] {
                let (text, result) = parse(Path::new(BAM), threads, batch_groups);
                result.unwrap();
                assert!(
                    text == expected,
                    "{threads} workers, batches of {batch_groups}"
                );
            }
        }
    }

    #[test]
    fn a_failing_writer_stops_the_reader_and_the_workers() {
        // As `pairs parse | head` does: the writer fails after a few batches, and every thread
        // must stop (the scope joins them) with the writer's error.
        let mut calls = 0;
        let result = parse_with(Path::new(BAM), 3, 1, &mut |_| {
            calls += 1;
            if calls == 3 {
                Err(Error::Invalid("the reader went away".into()))
            } else {
                Ok(())
            }
        });
        assert!(matches!(result, Err(Error::Invalid(m)) if m == "the reader went away"));
        assert_eq!(calls, 3);
    }

    #[test]
    fn a_cut_input_is_an_error_after_the_pairs_before_the_cut() {
        let bytes = std::fs::read(BAM).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let cut = dir.path().join("cut.bam");
        std::fs::write(&cut, &bytes[..bytes.len() * 2 / 3]).unwrap();
        let (full, _) = parse(Path::new(BAM), 1, 7);
        for threads in [1, 3] {
            let (text, result) = parse(&cut, threads, 7);
            assert!(result.is_err(), "{threads} workers");
            assert!(full.starts_with(&text) && text.len() > full.len() / 3);
        }
    }
}
