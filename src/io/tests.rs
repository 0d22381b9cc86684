use super::*;
use std::ops::Range;

use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::genome::Chrom;
use crate::matrix::MatrixBuilder;
use crate::matrix::pixels::PixelSource;
use crate::matrix::{CountType, PixelBlock, Weights};

#[test]
fn streamed_and_in_memory_passes_agree() {
    let bins = BinTable::fixed(vec![Chrom::new("a", 3000), Chrom::new("b", 2000)], 10).unwrap();
    let mut builder = MatrixBuilder::new(bins, CountType::Integer);
    for i in 0..500u64 {
        for j in (i..500).step_by(3) {
            builder.push(i, j, ((i * 7 + j) % 11) as f64).unwrap();
        }
    }
    let reader = InMemory::new("test".into(), builder.build());
    let pass = |p: &LoadedPixels| {
        p.pass(
            || vec![0.0; 500],
            |mut acc, s| {
                for (i, j, c) in s.iter() {
                    acc[i] += c;
                    if i != j {
                        acc[j] += c;
                    }
                }
                acc
            },
            |mut a, b| {
                a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
                a
            },
        )
    };
    let memory = load_pixels(&reader, u64::MAX).unwrap();
    let streamed = load_pixels(&reader, 0).unwrap();
    assert!(matches!(memory, LoadedPixels::Memory(_)));
    assert!(matches!(streamed, LoadedPixels::Streamed(_)));
    let a = pass(&memory).unwrap();
    let b = pass(&streamed).unwrap();
    assert_eq!(a, b);
    assert_eq!(
        a.iter().sum::<f64>(),
        2.0 * reader.matrix().sum() - (0..500).map(|i| reader.matrix().get(i, i)).sum::<f64>()
    );
}

/// A reader that hands out one fixed block.
struct OneBlock {
    bins: BinTable,
    block: PixelBlock,
}

impl MatrixReader for OneBlock {
    fn source(&self) -> &str {
        "one.cool"
    }
    fn bins(&self) -> &BinTable {
        &self.bins
    }
    fn count_type(&self) -> CountType {
        CountType::Float
    }
    fn weight_names(&self) -> Vec<String> {
        Vec::new()
    }
    fn weights(&self, name: &str) -> Result<Weights> {
        Err(Error::Argument(name.into()))
    }
    fn info(&self) -> MatrixInfo {
        MatrixInfo::default()
    }
    fn read_pixels(
        &self,
        _rows: Range<usize>,
        _cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        sink(&self.block)
    }
    fn warnings(&self) -> Vec<String> {
        vec![format!("{} pixels", self.block.len())]
    }
}

#[test]
fn checked_counts_name_the_first_bad_pixel() {
    let bins = BinTable::fixed(vec![Chrom::new("a", 30), Chrom::new("b", 25)], 10).unwrap();
    for (bad, what) in [
        (-2.0, "negative count (-2)"),
        (f64::NAN, "NaN count (NaN)"),
        (f64::INFINITY, "infinite count (inf)"),
        (f64::NEG_INFINITY, "infinite count (-inf)"),
    ] {
        let mut block = PixelBlock::with_capacity(4);
        block.push(0, 0, 1.0);
        block.push(1, 4, bad);
        block.push(3, 4, -1.0);
        let reader = CheckedCounts::new(Box::new(OneBlock {
            bins: bins.clone(),
            block,
        }));
        let mut seen = 0;
        let error = reader
            .read_pixels(0..5, 0..5, &mut |b| {
                seen += b.len();
                Ok(())
            })
            .unwrap_err()
            .to_string();
        assert_eq!(seen, 0, "a bad block never reaches the sink");
        assert_eq!(reader.warnings(), vec!["3 pixels".to_string()]);
        assert!(
            error.starts_with(&format!(
                "one.cool: pixel bin1_id=1 bin2_id=4 (a:10-20 x b:10-20) has a {what}"
            )),
            "{error}"
        );
    }
    let mut block = PixelBlock::with_capacity(2);
    block.push(0, 0, 0.0);
    block.push(0, 1, f64::MAX);
    let reader = CheckedCounts::new(Box::new(OneBlock { bins, block }));
    let mut seen = 0;
    reader
        .read_pixels(0..5, 0..5, &mut |b| {
            seen += b.len();
            Ok(())
        })
        .unwrap();
    assert_eq!(seen, 2);
}

#[test]
fn memory_sizes_parse() {
    assert_eq!(parse_memory_size("8G").unwrap(), 8 << 30);
    assert_eq!(parse_memory_size("512m").unwrap(), 512 << 20);
    assert_eq!(parse_memory_size("1.5GiB").unwrap(), 3 << 29);
    assert!(parse_memory_size("lots").is_err());
}

#[test]
fn blocks_handed_back_are_read_into_without_changing_what_is_read() {
    // A reader that reads into recycled blocks (longer and shorter than the next read, holding
    // other rows' pixels) gives exactly what a fresh reader gives.
    let uri = concat!(env!("CARGO_MANIFEST_DIR"), "/data/yeast.10kb.cool");
    let collect = |reader: &dyn MatrixReader, rows: Range<usize>, recycle: bool| {
        let mut pixels = Vec::new();
        let mut blocks = Vec::new();
        reader
            .read_rows_owned(rows, &mut |block| {
                pixels.extend(
                    (0..block.len()).map(|k| (block.bin1[k], block.bin2[k], block.count[k])),
                );
                blocks.push(block);
                Ok(())
            })
            .unwrap();
        if recycle {
            for block in blocks {
                reader.recycle(block);
            }
        }
        pixels
    };
    let recycling = open_matrix(uri, &OpenOptions::default()).unwrap();
    let n = recycling.bins().n_bins();
    assert!(n > 1000);
    let reads = [0..n, 100..130, 0..n, 500..900, 7..8, 300..n];
    for (k, rows) in reads.iter().enumerate() {
        let fresh = open_matrix(uri, &OpenOptions::default()).unwrap();
        let want = collect(fresh.as_ref(), rows.clone(), false);
        assert!(!want.is_empty());
        let got = collect(recycling.as_ref(), rows.clone(), true);
        assert_eq!(got, want, "read {k}: rows {rows:?}");
    }
    // the streamed reads recycle their blocks themselves
    let mut streamed = Vec::new();
    recycling
        .read_pixels(200..260, 0..n, &mut |block| {
            streamed.extend((0..block.len()).map(|k| (block.bin1[k], block.bin2[k])));
            Ok(())
        })
        .unwrap();
    let fresh = open_matrix(uri, &OpenOptions::default()).unwrap();
    let want: Vec<(u64, u64)> = collect(fresh.as_ref(), 200..260, false)
        .into_iter()
        .map(|(i, j, _)| (i, j))
        .collect();
    assert_eq!(streamed, want);
}

#[test]
fn reading_ahead_at_any_depth_keeps_the_order_and_stops_at_the_first_error() {
    for depth in [0, 1, 2, 5] {
        let mut seen = Vec::new();
        read_ahead_by(
            0..20u32,
            depth,
            |&k| Ok(k * k),
            |k, data| {
                seen.push((k, data));
                Ok(())
            },
        )
        .unwrap();
        let want: Vec<(u32, u32)> = (0..20).map(|k| (k, k * k)).collect();
        assert_eq!(seen, want, "depth {depth}");
        // a failed read: the items before it processed, none after
        let mut processed = Vec::new();
        let err = read_ahead_by(
            0..20u32,
            depth,
            |&k| {
                if k == 7 {
                    Err(Error::Data(format!("item {k}")))
                } else {
                    Ok(k)
                }
            },
            |k, _| {
                processed.push(k);
                Ok(())
            },
        )
        .unwrap_err();
        assert!(err.to_string().contains("item 7"), "{err}");
        assert_eq!(processed, (0..7).collect::<Vec<_>>(), "depth {depth}");
        // a failed processing stops the loop
        let mut processed = 0;
        let err = read_ahead_by(
            0..20u32,
            depth,
            |&k| Ok(k),
            |k, _| {
                processed += 1;
                if k == 3 {
                    Err(Error::Data("stop".into()))
                } else {
                    Ok(())
                }
            },
        )
        .unwrap_err();
        assert!(err.to_string().contains("stop"));
        assert_eq!(processed, 4, "depth {depth}");
    }
}
