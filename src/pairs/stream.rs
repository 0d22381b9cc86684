//! `pairs parse` over a whole input: batches of read groups read by one thread (BAM inflated on
//! worker threads of its own) while the previous batch is classified on every core, the pairs
//! written in input order and counted for the statistics.

use rayon::prelude::*;

use super::parse::{
    ChromOrder, ParseParams, ParseScratch, ParsedPair, parse_read_into, write_pair,
};
use super::stats::PairCounter;
use crate::error::Result;
use crate::io::pairs::alignments::RawBatch;
use crate::io::pairs::{AlignmentReader, ReadGroup};

/// Read groups classified by one task of a batch.
const GROUPS_PER_TASK: usize = 128;

/// Tasks per batch and thread. A batch is small (a few hundred kilobytes of records per
/// thread) so that its records are still in the cache when they are classified: batches of
/// 16,384 groups made `pairs parse` a third slower on two cores, the records read from memory.
const TASKS_PER_THREAD: usize = 2;

/// Batches being read or classified at once.
const BATCHES_IN_FLIGHT: usize = 3;

/// One task's pairs: their lines, and what the statistics count of each (kept only when they
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
/// `progress` is told the number of read groups done after each batch.
pub fn parse_alignments(
    mut reader: AlignmentReader,
    order: &ChromOrder,
    params: &ParseParams,
    mut counter: Option<&mut PairCounter>,
    write: &mut dyn FnMut(&[u8]) -> Result<()>,
    progress: &mut dyn FnMut(u64),
) -> Result<()> {
    let (full_tx, full_rx) = std::sync::mpsc::sync_channel::<Result<RawBatch>>(1);
    let (empty_tx, empty_rx) = std::sync::mpsc::sync_channel::<RawBatch>(BATCHES_IN_FLIGHT);
    for _ in 0..BATCHES_IN_FLIGHT {
        empty_tx
            .send(reader.new_batch())
            .expect("the channel has room for every batch");
    }
    let batch_groups = GROUPS_PER_TASK * TASKS_PER_THREAD * rayon::current_num_threads();
    std::thread::scope(|scope| {
        scope.spawn(move || {
            while let Ok(mut batch) = empty_rx.recv() {
                let result = reader.read_batch(&mut batch, batch_groups);
                let stop = result.is_err() || batch.is_empty();
                if full_tx.send(result.map(|()| batch)).is_err() || stop {
                    break;
                }
            }
        });
        // Returning drops both channel ends, which stops the reader.
        let (full, empty) = (full_rx, empty_tx);
        let needs = params.needs();
        let count = counter.is_some();
        let mut n_groups = 0u64;
        while let Ok(batch) = full.recv() {
            let batch = batch?;
            if batch.is_empty() {
                break;
            }
            let n_tasks = batch.len().div_ceil(GROUPS_PER_TASK);
            let chunks: Vec<Result<Parsed>> = (0..n_tasks)
                .into_par_iter()
                .map(|task| {
                    let mut parsed = Parsed::default();
                    let mut group = ReadGroup::default();
                    let mut scratch = ParseScratch::default();
                    let mut pairs = Vec::new();
                    let end = ((task + 1) * GROUPS_PER_TASK).min(batch.len());
                    for i in task * GROUPS_PER_TASK..end {
                        batch.decode_into(i, &needs, &mut group)?;
                        parse_read_into(&group, order, params, &mut scratch, &mut pairs);
                        for pair in &pairs {
                            write_pair(pair, &group, order, params, &mut parsed.text);
                            if count {
                                parsed.counted.push(Counted::of(pair));
                            }
                        }
                    }
                    Ok(parsed)
                })
                .collect();
            for chunk in chunks {
                let chunk = chunk?;
                if let Some(counter) = counter.as_deref_mut() {
                    for pair in &chunk.counted {
                        let name =
                            |c: Option<usize>| c.map_or(&b"!"[..], |c| order.names[c].as_bytes());
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
                write(&chunk.text)?;
            }
            n_groups += batch.len() as u64;
            progress(n_groups);
            crate::interrupt::check()?;
            // The reader may have stopped already (at the end, or on an error it has sent):
            // what it sent is still to be received, so the loop goes on to the channel's end.
            let _ = empty.send(batch);
        }
        Ok(())
    })
}
