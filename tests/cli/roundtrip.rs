//! Property tests: random matrices round-trip through every writer / reader pair, and region
//! queries equal a dense reference built naively from the triplets.

use std::collections::BTreeMap;

use proptest::prelude::*;

use contactmap::genome::{BinTable, Chrom};
use contactmap::io::cool::{CoolReader, CoolWriteOptions, write_cool, write_mcool};
use contactmap::io::hic::{HicReader, HicWriteOptions, HicWriter};
use contactmap::io::text::{TextFormat, read_matrix, write_text};
use contactmap::io::{InMemory, MatrixReader, OpenOptions, load_matrix};
use contactmap::matrix::{ContactMatrix, CountType, MatrixBuilder, Weights};

/// A random matrix: 1-3 chromosomes, a bin size, triplets in either triangle, optional weights.
fn matrices() -> impl Strategy<Value = (ContactMatrix, Vec<(u64, u64, f64)>)> {
    (
        prop::collection::vec(1u64..400, 1..4),
        5u64..40,
        any::<bool>(),
        any::<u64>(),
    )
        .prop_flat_map(|(lengths, bin_size, integer, seed)| {
            let chroms: Vec<Chrom> = lengths
                .iter()
                .enumerate()
                .map(|(i, &l)| Chrom::new(format!("chr{}", i + 1), l))
                .collect();
            let bins = BinTable::fixed(chroms, bin_size).unwrap();
            let n = bins.n_bins() as u64;
            let triplets = prop::collection::vec((0..n, 0..n, 1u32..1000), 0..200);
            (Just(bins), Just(integer), Just(seed), triplets)
        })
        .prop_map(|(bins, integer, seed, raw)| {
            let count_type = if integer {
                CountType::Integer
            } else {
                CountType::Float
            };
            let triplets: Vec<(u64, u64, f64)> = raw
                .into_iter()
                .map(|(i, j, c)| (i, j, if integer { c as f64 } else { c as f64 / 7.0 }))
                .collect();
            let mut builder = MatrixBuilder::new(bins.clone(), count_type);
            for &(i, j, c) in &triplets {
                builder.push(i, j, c).unwrap();
            }
            let n = bins.n_bins();
            let weight: Vec<f64> = (0..n)
                .map(|k| {
                    if (seed >> (k % 64)) & 1 == 1 {
                        f64::NAN
                    } else {
                        0.5 + k as f64 / 3.0
                    }
                })
                .collect();
            let kr: Vec<f64> = (0..n).map(|k| 1.0 / (1.0 + k as f64)).collect();
            builder
                .add_weights(Weights {
                    name: "weight".into(),
                    values: weight,
                    provenance: None,
                })
                .unwrap();
            builder
                .add_weights(Weights {
                    name: "KR".into(),
                    values: kr,
                    provenance: None,
                })
                .unwrap();
            (builder.build(), triplets)
        })
}

fn same_weights(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            (x.is_nan() && y.is_nan()) || (x - y).abs() <= 1e-15 * x.abs().max(y.abs())
        })
}

fn bins_bed(bins: &BinTable, path: &std::path::Path) {
    let text: String = bins
        .iter()
        .map(|b| {
            format!(
                "{}\t{}\t{}\n",
                bins.chroms()[b.chrom_id].name,
                b.start,
                b.end
            )
        })
        .collect();
    std::fs::write(path, text).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn cool_and_mcool_round_trip((matrix, _) in matrices()) {
        let dir = tempfile::tempdir().unwrap();
        let source = InMemory::new("random".into(), matrix.clone());
        let cool = dir.path().join("m.cool");
        write_cool(&source, &cool, &CoolWriteOptions::default()).unwrap();
        let back = load_matrix(&CoolReader::open(cool.to_str().unwrap()).unwrap()).unwrap();
        prop_assert_eq!(back.all_pixels(), matrix.all_pixels());
        prop_assert_eq!(back.bins(), matrix.bins());
        prop_assert_eq!(back.count_type(), matrix.count_type());
        for name in ["weight", "KR"] {
            prop_assert!(same_weights(&back.weight(name).unwrap().values, &matrix.weight(name).unwrap().values));
        }
        let mcool = dir.path().join("m.mcool");
        let base = matrix.bins().resolution().unwrap();
        write_mcool(&source, &mcool, &[base, 3 * base], &CoolWriteOptions::default()).unwrap();
        let uri = format!("{}::/resolutions/{base}", mcool.display());
        let level = load_matrix(&CoolReader::open(&uri).unwrap()).unwrap();
        prop_assert_eq!(level.all_pixels(), matrix.all_pixels());
        // The coarse level equals a naive coarsening of the dense matrix.
        let coarse_uri = format!("{}::/resolutions/{}", mcool.display(), 3 * base);
        let coarse = load_matrix(&CoolReader::open(&coarse_uri).unwrap()).unwrap();
        let n = matrix.bins().n_bins();
        let dense = matrix.dense(0..n, 0..n);
        let mut expected: BTreeMap<(usize, usize), f64> = BTreeMap::new();
        for i in 0..n {
            for j in i..n {
                if dense[[i, j]] != 0.0 {
                    let bi = matrix.bins().bin(i);
                    let bj = matrix.bins().bin(j);
                    let ci = coarse.bins().bin_at(bi.chrom_id, bi.start);
                    let cj = coarse.bins().bin_at(bj.chrom_id, bj.start);
                    *expected.entry((ci, cj)).or_default() += dense[[i, j]];
                }
            }
        }
        let got = coarse.all_pixels();
        prop_assert_eq!(got.len(), expected.len());
        for (k, ((ci, cj), value)) in expected.iter().enumerate() {
            prop_assert_eq!((got.bin1[k] as usize, got.bin2[k] as usize), (*ci, *cj));
            prop_assert!((got.count[k] - value).abs() <= 1e-9 * value.abs());
        }
    }

    /// The .hic writer at every resolution, with blocks of 1 to 6 bins (many blocks, depths along
    /// the diagonal, dense and list-of-rows blocks, short and float values), read back by our
    /// reader: the pixels of a naive coarsening of the triplets, counts rounded to float32.
    #[test]
    fn hic_round_trips_every_resolution((matrix, triplets) in matrices(), block in 1u64..7, factor in 2u64..4, whole_genome in any::<bool>()) {
        let dir = tempfile::tempdir().unwrap();
        let source = InMemory::new("random".into(), matrix.clone());
        let path = dir.path().join("m.hic");
        let base = matrix.bins().resolution().unwrap();
        let options = HicWriteOptions { block_bin_count: block, whole_genome, ..HicWriteOptions::default() };
        let mut writer = HicWriter::create(&path, matrix.bins(), &[base, factor * base], &options).unwrap();
        writer.write_matrices(&source).unwrap();
        writer.write_footer(&[], &[], &[]).unwrap();
        drop(writer);
        for resolution in [base, factor * base] {
            let reader = HicReader::open(&path, Some(resolution)).unwrap();
            let coarse = BinTable::fixed(matrix.bins().chroms().to_vec(), resolution).unwrap();
            prop_assert_eq!(reader.bins(), &coarse);
            let mut expected: BTreeMap<(usize, usize), f64> = BTreeMap::new();
            for &(i, j, v) in &triplets {
                let (bi, bj) = (matrix.bins().bin(i as usize), matrix.bins().bin(j as usize));
                let (ci, cj) = (coarse.bin_at(bi.chrom_id, bi.start), coarse.bin_at(bj.chrom_id, bj.start));
                *expected.entry((ci.min(cj), ci.max(cj))).or_default() += v;
            }
            let got = load_matrix(&reader).unwrap().all_pixels();
            prop_assert_eq!(got.len(), expected.len());
            for (k, ((ci, cj), value)) in expected.iter().enumerate() {
                prop_assert_eq!((got.bin1[k] as usize, got.bin2[k] as usize), (*ci, *cj));
                // float32 storage (sums of reals may round either way of a float32 tie)
                prop_assert!((got.count[k] - value).abs() <= 2e-7 * value.abs(), "{} {}", got.count[k], value);
            }
        }
    }

    #[test]
    fn text_formats_round_trip((matrix, _) in matrices()) {
        let dir = tempfile::tempdir().unwrap();
        let source = InMemory::new("random".into(), matrix.clone());
        let bed = dir.path().join("bins.bed");
        bins_bed(matrix.bins(), &bed);
        for (format, name) in [(TextFormat::Bg2, "m.bg2"), (TextFormat::Coo, "m.coo.gz"), (TextFormat::Dense, "m.dense")] {
            let path = dir.path().join(name);
            write_text(&source, path.to_str().unwrap(), format).unwrap();
            let options = OpenOptions { text_format: Some(format), bins_bed: Some(bed.clone()), ..OpenOptions::default() };
            let back = read_matrix(path.to_str().unwrap(), &options).unwrap();
            prop_assert_eq!(back.all_pixels(), matrix.all_pixels(), "{:?}", format);
        }
    }

    #[test]
    fn region_queries_equal_a_dense_reference((matrix, triplets) in matrices(), a in 0usize..1000, b in 0usize..1000, c in 0usize..1000, d in 0usize..1000) {
        let n = matrix.bins().n_bins();
        let (r0, r1) = (a.min(b) % (n + 1), a.max(b) % (n + 1));
        let (rows, cols) = (r0.min(r1)..r0.max(r1), (c.min(d) % (n + 1)).min(c.max(d) % (n + 1))..(c.min(d) % (n + 1)).max(c.max(d) % (n + 1)));
        // naive symmetric dense matrix from the raw triplets
        let mut naive = vec![vec![0.0f64; n]; n];
        for &(i, j, v) in &triplets {
            let (i, j) = (i as usize, j as usize);
            naive[i][j] += v;
            if i != j {
                naive[j][i] += v;
            }
        }
        let dense = matrix.dense(rows.clone(), cols.clone());
        for (ri, i) in rows.clone().enumerate() {
            for (ci, j) in cols.clone().enumerate() {
                prop_assert!((dense[[ri, ci]] - naive[i][j]).abs() <= 1e-9 * naive[i][j].abs());
            }
        }
        // streamed upper-triangle query through a written cooler equals filtering the naive matrix
        let dir = tempfile::tempdir().unwrap();
        let cool = dir.path().join("q.cool");
        write_cool(&InMemory::new("q".into(), matrix.clone()), &cool, &CoolWriteOptions::default()).unwrap();
        let reader = CoolReader::open(cool.to_str().unwrap()).unwrap();
        let mut got = Vec::new();
        reader.read_pixels(rows.clone(), cols.clone(), &mut |block| {
            for k in 0..block.len() {
                got.push((block.bin1[k] as usize, block.bin2[k] as usize, block.count[k]));
            }
            Ok(())
        }).unwrap();
        let mut expected = Vec::new();
        for i in rows.clone() {
            for j in cols.clone() {
                if i <= j && naive[i][j] != 0.0 {
                    expected.push((i, j, naive[i][j]));
                }
            }
        }
        prop_assert_eq!(got.len(), expected.len());
        for (g, e) in got.iter().zip(&expected) {
            prop_assert_eq!((g.0, g.1), (e.0, e.1));
            prop_assert!((g.2 - e.2).abs() <= 1e-9 * e.2.abs());
        }
    }
}

/// 2-4 random matrices on the same random bins.
fn same_bins_matrices() -> impl Strategy<Value = Vec<ContactMatrix>> {
    (
        prop::collection::vec(1u64..300, 1..4),
        5u64..40,
        any::<bool>(),
    )
        .prop_flat_map(|(lengths, bin_size, integer)| {
            let chroms: Vec<Chrom> = lengths
                .iter()
                .enumerate()
                .map(|(i, &l)| Chrom::new(format!("chr{}", i + 1), l))
                .collect();
            let bins = BinTable::fixed(chroms, bin_size).unwrap();
            let n = bins.n_bins() as u64;
            let lists = prop::collection::vec(
                prop::collection::vec((0..n, 0..n, 1u32..1000), 0..150),
                2..5,
            );
            (Just(bins), Just(integer), lists)
        })
        .prop_map(|(bins, integer, lists)| {
            let count_type = if integer {
                CountType::Integer
            } else {
                CountType::Float
            };
            lists
                .into_iter()
                .map(|triplets| {
                    let mut builder = MatrixBuilder::new(bins.clone(), count_type);
                    for (i, j, c) in triplets {
                        let c = if integer { c as f64 } else { c as f64 / 7.0 };
                        builder.push(i, j, c).unwrap();
                    }
                    builder.build()
                })
                .collect()
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// `merge` writes the sum of its inputs: the merged .cool read back equals the sum of the
    /// inputs' dense matrices, pixel by pixel.
    #[test]
    fn merged_maps_are_the_sum(maps in same_bins_matrices()) {
        let dir = tempfile::tempdir().unwrap();
        let readers: Vec<InMemory> = maps
            .iter()
            .enumerate()
            .map(|(k, m)| InMemory::new(format!("m{k}"), m.clone()))
            .collect();
        let merged = contactmap::io::merged::MergedReader::new(
            readers.iter().map(|r| r as &dyn MatrixReader).collect(),
        )
        .unwrap();
        let cool = dir.path().join("merged.cool");
        write_cool(&merged, &cool, &CoolWriteOptions::default()).unwrap();
        let back = load_matrix(&CoolReader::open(cool.to_str().unwrap()).unwrap()).unwrap();
        prop_assert_eq!(back.count_type(), maps[0].count_type());
        let n = maps[0].bins().n_bins();
        let mut expected = maps[0].dense(0..n, 0..n);
        for m in &maps[1..] {
            expected = expected + m.dense(0..n, 0..n);
        }
        let got = back.dense(0..n, 0..n);
        for i in 0..n {
            for j in 0..n {
                prop_assert!((got[[i, j]] - expected[[i, j]]).abs() <= 1e-9 * expected[[i, j]].abs());
            }
        }
    }
}
