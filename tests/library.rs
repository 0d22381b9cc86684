//! The library called directly (not the binary), one job after another, each compared with an
//! independent reference: the outputs of cooler, cooltools and hictk in `data/reference/`
//! (`data/README.md` says how they were made), published numbers (`data/protein/README.md`), a
//! closed form, or a naive computation written here.
//!
//! Tolerances: the references keep 10 significant digits (`%.10g`), so reals are compared to
//! `1e-8` relative unless said; `cooler dump` prints 6 significant digits.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::io::BufRead;
use std::path::{Path, PathBuf};

use contactmap::balance::{BalanceParams, Method, Scope, balance};
use contactmap::compartments::cis::CisEigParams;
use contactmap::compartments::eigs::{Phasing, eigs_cis, eigs_trans};
use contactmap::compartments::saddle::{
    Binning, SaddleParams, digitize, saddle_cis, saddle_strength, saddle_trans,
};
use contactmap::compartments::trans::TransEigParams;
use contactmap::expected::logbin::{LogBinParams, logbin_expected};
use contactmap::expected::{CisParams, Column, cis_curves, expected_cis, expected_trans};
use contactmap::genome::View;
use contactmap::io::cool::{CoolWriteOptions, write_cool, write_mcool};
use contactmap::io::hic::{HicReader, HicWriteOptions};
use contactmap::io::predictions::{read_fasta, read_prediction};
use contactmap::io::structure::read_structure;
use contactmap::io::text::{TextFormat, write_text};
use contactmap::io::{
    MatrixReader, OpenOptions, load_matrix, load_pixels, load_pixels_for_balancing, open_matrix,
    open_text,
};
use contactmap::matrix::ContactMatrix;
use contactmap::normalize::{Method as NormMethod, NormalizedReader, Normalizer};
use contactmap::plot::heatmap::{AxisCells, CellGrid};
use contactmap::plot::map::{
    GenomicSpan, MapFigure, MapLayout, MapStyle, MapView, Overlays, draw_map,
};
use contactmap::plot::{ColorMap, ColorScale, ImageFormat, Rgb, ScaleKind, figure_bytes};
use contactmap::score::boundaries::score_boundaries;
use contactmap::score::compartments::score_compartments;
use contactmap::score::contacts::{
    ContactDefinition, ListSize, Prediction, ScoreParams, SeparationRange, TrueContacts,
    score_contacts,
};
use contactmap::score::overlap::{overlap, ranked_pairs};
use contactmap::sim::ensemble::{EnsembleParams, run_ensemble};
use contactmap::sim::polymer::{Confinement, PolymerParams};
use contactmap::sim::{BlockMapParams, block_map};
use contactmap::tads::armatus::ArmatusParams;
use contactmap::tads::call::{Caller, call};
use contactmap::tads::directionality::{DirectionalityParams, directionality};
use contactmap::tads::hmm::HmmParams;
use contactmap::tads::insulation::{InsulationParams, insulation};
use contactmap::tads::threshold::Threshold;
use contactmap::tads::topdom::TopDomParams;

const DM6: &str = "cooler_test_file.mcool::/resolutions/100000";
const MM9: &str = "CN.mm9.10000kb.cool";
const GM12878: &str = "hg19.GM12878-MboI.matrix.2000kb.cool";
const YEAST: &str = "yeast.10kb.cool";

/// Path (or URI) of a fixture under `data/`.
fn data(name: &str) -> String {
    format!("{}/data/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn open(name: &str) -> Box<dyn MatrixReader> {
    open_matrix(&data(name), &OpenOptions::default()).expect("the fixture opens")
}

fn weights(reader: &dyn MatrixReader, name: &str) -> Vec<f64> {
    reader.weights(name).expect("the weight column").values
}

/// A tab-separated table under `data/` (gzip or plain), with or without a header.
struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

fn read_table(name: &str, has_header: bool) -> Table {
    let path = PathBuf::from(data(name));
    let mut lines = open_text(&path)
        .expect("the reference opens")
        .lines()
        .map(|line| line.expect("a text line"))
        .filter(|line| !line.is_empty());
    let header = if has_header {
        lines
            .next()
            .expect("a header")
            .split('\t')
            .map(String::from)
            .collect()
    } else {
        Vec::new()
    };
    let rows = lines
        .map(|line| line.split('\t').map(String::from).collect())
        .collect();
    Table { header, rows }
}

impl Table {
    fn index(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.header))
    }

    /// A column as numbers: `nan`, `NA` or an empty field is NaN, `True` / `False` 1 / 0.
    fn numbers(&self, name: &str) -> Vec<f64> {
        let k = self.index(name);
        self.rows.iter().map(|row| number(&row[k])).collect()
    }

    fn texts(&self, name: &str) -> Vec<&str> {
        let k = self.index(name);
        self.rows.iter().map(|row| row[k].as_str()).collect()
    }
}

fn number(field: &str) -> f64 {
    match field {
        "" | "nan" | "NaN" | "NA" => f64::NAN,
        "True" => 1.0,
        "False" => 0.0,
        _ => field
            .parse()
            .unwrap_or_else(|_| panic!("'{field}' is not a number")),
    }
}

/// `ours` equals `theirs` to `relative` (NaN where they have NaN); `what` names the values.
fn assert_close(ours: &[f64], theirs: &[f64], relative: f64, what: &str) {
    assert_eq!(ours.len(), theirs.len(), "{what}: lengths");
    for (k, (a, b)) in ours.iter().zip(theirs).enumerate() {
        if b.is_nan() {
            assert!(a.is_nan(), "{what}[{k}]: {a} where the reference has NaN");
        } else {
            assert!(
                (a - b).abs() <= relative * b.abs(),
                "{what}[{k}]: {a} vs reference {b}"
            );
        }
    }
}

/// Every stored pixel of a matrix, `(bin1, bin2, count)`.
fn pixels_of(matrix: &ContactMatrix) -> Vec<(u64, u64, f64)> {
    let block = matrix.all_pixels();
    (0..block.len())
        .map(|k| (block.bin1[k], block.bin2[k], block.count[k]))
        .collect()
}

fn temp_dir(what: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("contactmap-library-{what}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

// ---------------------------------------------------------------------------------------------
// Open and read

#[test]
fn open_matrix_gives_the_totals_of_cooler_and_hictkpy() {
    let totals = read_table("reference/totals.tsv", true);
    for row in &totals.rows {
        let uri = format!("{}/{}", env!("CARGO_MANIFEST_DIR"), row[0]);
        let reader = open_matrix(&uri, &OpenOptions::default()).expect(&uri);
        assert_eq!(
            reader.bins().n_bins(),
            row[1].parse::<usize>().unwrap(),
            "{uri}"
        );
        let (nnz, sum) = reader.totals().unwrap();
        assert_eq!(nnz, row[2].parse::<u64>().unwrap(), "{uri}");
        assert_eq!(sum, number(&row[3]), "{uri}");
    }
}

#[test]
fn read_pixels_and_weights_equal_cooler_dump() {
    // cooler dump --join --balanced -r chr2L:1,000,000-3,000,000 -r2 chr2L:2,000,000-5,000,000
    let reader = open(DM6);
    let bins = reader.bins();
    let rows = bins.parse_region_bins("chr2L:1,000,000-3,000,000").unwrap();
    let cols = bins.parse_region_bins("chr2L:2,000,000-5,000,000").unwrap();
    let w = weights(reader.as_ref(), "weight");
    let mut ours = Vec::new();
    reader
        .read_pixels(rows, cols, &mut |block| {
            for k in 0..block.len() {
                ours.push((
                    block.bin1[k] as usize,
                    block.bin2[k] as usize,
                    block.count[k],
                ));
            }
            Ok(())
        })
        .unwrap();
    let reference = read_table("reference/dm6_100kb.chr2L_box.balanced.join.tsv", true);
    assert_eq!(ours.len(), reference.rows.len());
    let balanced = reference.numbers("balanced");
    for ((i, j, count), (row, expected)) in ours.iter().zip(reference.rows.iter().zip(&balanced)) {
        let (a, b) = (bins.bin(*i), bins.bin(*j));
        assert_eq!(
            [a.start, a.end, b.start, b.end],
            [1, 2, 4, 5].map(|k| row[k].parse::<u64>().unwrap())
        );
        assert_eq!(*count, number(&row[6]));
        let value = count * w[*i] * w[*j];
        assert!(
            (value - expected).abs() <= 1e-5 * expected.abs(),
            "{row:?}: {value}"
        );
    }

    // cooler dump -r chrX --range2 chrY: bin ids and counts
    let x = bins.parse_region_bins("chrX").unwrap();
    let y = bins.parse_region_bins("chrY").unwrap();
    let mut trans = Vec::new();
    reader
        .read_pixels(x, y, &mut |block| {
            for k in 0..block.len() {
                trans.push(vec![
                    block.bin1[k].to_string(),
                    block.bin2[k].to_string(),
                    block.count[k].to_string(),
                ]);
            }
            Ok(())
        })
        .unwrap();
    assert_eq!(
        trans,
        read_table("reference/dm6_100kb.chrX_chrY.tsv", false).rows
    );

    // cooler dump -t bins: the stored ICE weights of mm9
    let mm9 = open(MM9);
    let reference = read_table("reference/CN.mm9.10000kb.bins.tsv", true);
    assert_close(
        &weights(mm9.as_ref(), "weight"),
        &reference.numbers("weight"),
        1e-5,
        "mm9 weight",
    );
}

// ---------------------------------------------------------------------------------------------
// Balance

#[test]
fn ice_equals_cooler_balance() {
    for (key, name) in [("mm9_CN_10Mb", MM9), ("gm12878_2Mb", GM12878)] {
        let reader = open(name);
        let pixels = load_pixels_for_balancing(reader.as_ref(), u64::MAX).unwrap();
        for (mode, scope) in [("gw", Scope::GenomeWide), ("cis", Scope::Cis)] {
            let params = BalanceParams {
                scope,
                ..BalanceParams::default()
            };
            let ours = balance(&pixels, &params).unwrap();
            let reference = read_table(
                &format!("reference/numerics/{key}.ice_{mode}.weights.tsv.gz"),
                true,
            );
            // 1e-6: cooler's own tolerance leaves the last digits to the iteration order
            assert_close(
                &ours.weights,
                &reference.numbers("weight"),
                1e-6,
                &format!("{key} ICE {mode}"),
            );
        }
    }
}

#[test]
fn juicer_methods_equal_the_vectors_hic2cool_stored() {
    let reader = open(DM6);
    let pixels = load_pixels_for_balancing(reader.as_ref(), u64::MAX).unwrap();
    for method in [Method::Vc, Method::VcSqrt, Method::Kr, Method::Scale] {
        let params = BalanceParams {
            scope: Scope::Cis,
            ..BalanceParams::juicer(method)
        };
        let ours = balance(&pixels, &params).unwrap();
        let juicer = weights(reader.as_ref(), method.juicer_name());
        assert_close(&ours.weights, &juicer, 1e-9, method.juicer_name());
    }
}

// ---------------------------------------------------------------------------------------------
// Expected

/// Compare every column of `ours` (`CisExpected::columns`) with cooltools' table `name`.
fn assert_expected_equals(ours: &contactmap::expected::CisExpected, name: &str) {
    let reference = read_table(name, true);
    assert_eq!(ours.n_rows(), reference.rows.len(), "{name}");
    let regions: Vec<&str> = (0..ours.n_rows()).map(|r| ours.region_name(r)).collect();
    assert_eq!(regions, reference.texts("region1"), "{name}");
    for (column, values) in ours.columns() {
        let theirs = reference.numbers(&column);
        match values {
            Column::Integer(v) => {
                let v: Vec<f64> = v.iter().map(|&x| x as f64).collect();
                assert_eq!(v, theirs, "{name} {column}");
            }
            Column::Real(v) => assert_close(v, &theirs, 1e-8, &format!("{name} {column}")),
        }
    }
}

#[test]
fn expected_cis_equals_cooltools() {
    for (key, name) in [("mm9_CN_10Mb", MM9), ("dm6_100kb", DM6)] {
        let reader = open(name);
        let pixels = load_pixels(reader.as_ref(), u64::MAX).unwrap();
        let view = View::chromosomes(reader.bins());
        let params = CisParams::default();
        let raw = expected_cis(&pixels, None, &view, &params).unwrap();
        assert_expected_equals(
            &raw,
            &format!("reference/numerics/{key}.expected_cis.raw.tsv.gz"),
        );
        let w = weights(reader.as_ref(), "weight");
        let balanced = expected_cis(&pixels, Some(&w), &view, &params).unwrap();
        assert_expected_equals(
            &balanced,
            &format!("reference/numerics/{key}.expected_cis.balanced_storedweight.tsv.gz"),
        );
    }
}

#[test]
fn expected_trans_and_log_bins_equal_naive_sums() {
    let reader = open(MM9);
    let w = weights(reader.as_ref(), "weight");
    let matrix = load_matrix(reader.as_ref()).unwrap();
    let bins = matrix.bins();
    let pixels = load_pixels(reader.as_ref(), u64::MAX).unwrap();
    let view = View::chromosomes(bins);
    let table = expected_trans(&pixels, Some(&w), &view).unwrap();

    // naive: every trans pixel of two good bins, by pair of chromosomes
    let mut sums: HashMap<(usize, usize), (f64, f64)> = HashMap::new();
    for (i, j, count) in pixels_of(&matrix) {
        let (i, j) = (i as usize, j as usize);
        let (a, b) = (bins.chrom_of(i), bins.chrom_of(j));
        if a != b && w[i].is_finite() && w[j].is_finite() {
            let entry = sums.entry((a, b)).or_default();
            entry.0 += count;
            entry.1 += count * w[i] * w[j];
        }
    }
    let good = |chrom: usize| bins.chrom_bins(chrom).filter(|&b| w[b].is_finite()).count();
    let n_chroms = bins.n_chroms();
    assert_eq!(table.n_rows(), n_chroms * (n_chroms - 1) / 2);
    let balanced_sum = table.balanced_sum.as_ref().unwrap();
    for (row, ours) in balanced_sum.iter().enumerate() {
        let a = bins.chrom_id(&table.region1[row]).unwrap();
        let b = bins.chrom_id(&table.region2[row]).unwrap();
        assert_eq!(table.n_valid[row], (good(a) * good(b)) as u64);
        let (count, balanced) = sums.get(&(a, b)).copied().unwrap_or_default();
        assert_eq!(table.count_sum[row], count, "{a} {b}");
        assert!((ours - balanced).abs() <= 1e-12 * balanced.abs());
    }

    // log bins: per bin, the summed summary over the summed valid pixels of its diagonals
    let params = CisParams {
        smooth: false,
        aggregate_smoothed: false,
        ..CisParams::default()
    };
    let cis = expected_cis(&pixels, Some(&w), &view, &params).unwrap();
    let binned = logbin_expected(&cis, &LogBinParams::default()).unwrap();
    for bin in &binned.by_region {
        let rows: Vec<usize> = (0..cis.n_rows())
            .filter(|&r| {
                cis.region[r] == bin.region
                    && (bin.dist_bin_start..=bin.dist_bin_end).contains(&cis.dist[r])
                    && !cis.summary()[r].is_nan()
            })
            .collect();
        let n_valid: u64 = rows.iter().map(|&r| cis.n_valid[r]).sum();
        let summary: f64 = rows.iter().map(|&r| cis.summary()[r]).sum();
        assert_eq!(bin.n_valid, n_valid);
        assert!((bin.average - summary / n_valid as f64).abs() <= 1e-12 * bin.average);
    }
}

// ---------------------------------------------------------------------------------------------
// Observed / expected

#[test]
fn observed_over_expected_equals_cooltools() {
    let reader = open(MM9);
    let w = weights(reader.as_ref(), "weight");
    let pixels = load_pixels(reader.as_ref(), u64::MAX).unwrap();
    let curves = cis_curves(&pixels, Some(&w), 2).unwrap();
    let n = reader.bins().n_bins();
    let mut values: BTreeMap<(u64, u64), [f64; 2]> = BTreeMap::new();
    for (slot, method) in [(0, NormMethod::Oe), (1, NormMethod::Log2Oe)] {
        let normalizer = Normalizer::new(method, n, Some(w.clone()), curves.clone()).unwrap();
        let normalized = NormalizedReader::new(reader.as_ref(), &normalizer, "oe".into());
        normalized
            .read_pixels(0..n, 0..n, &mut |block| {
                for k in 0..block.len() {
                    values.entry((block.bin1[k], block.bin2[k])).or_default()[slot] =
                        block.count[k];
                }
                Ok(())
            })
            .unwrap();
    }
    let reference = read_table("reference/CN.mm9.10000kb.cis_oe.tsv", false);
    assert_eq!(values.len(), reference.rows.len());
    for row in &reference.rows {
        let key = (row[0].parse().unwrap(), row[1].parse().unwrap());
        let [oe, log2] = values[&key];
        let expected = number(&row[2]);
        assert!(
            (oe - expected).abs() <= 1e-10 * expected,
            "{key:?}: {oe} vs {expected}"
        );
        assert!((log2 - oe.log2()).abs() < 1e-12);
    }
}

// ---------------------------------------------------------------------------------------------
// TADs

#[test]
fn insulation_and_directionality_equal_cooltools() {
    let reader = open(YEAST);
    let w = weights(reader.as_ref(), "weight");
    let pixels = load_pixels(reader.as_ref(), u64::MAX).unwrap();
    let view = View::chromosomes(reader.bins());

    let windows = [30_000, 50_000, 100_000];
    let table = insulation(
        &pixels,
        Some(&w),
        &view,
        &InsulationParams::new(windows.to_vec()),
    )
    .unwrap();
    let reference = read_table("reference/tads/yeast_10kb.insulation.Li.tsv.gz", true);
    assert_eq!(table.n_rows(), reference.rows.len());
    let bad: Vec<f64> = table
        .is_bad_bin
        .iter()
        .map(|&b| f64::from(u8::from(b)))
        .collect();
    assert_eq!(bad, reference.numbers("is_bad_bin"));
    for (track, window) in table.tracks.iter().zip(windows) {
        let column = |name: &str| reference.numbers(&format!("{name}_{window}"));
        assert_close(
            &track.log2_insulation_score,
            &column("log2_insulation_score"),
            1e-8,
            "log2_insulation_score",
        );
        assert_eq!(track.n_valid_pixels, column("n_valid_pixels"));
        assert_close(
            &track.boundary_strength,
            &column("boundary_strength"),
            1e-8,
            "boundary_strength",
        );
        let called: Vec<f64> = track
            .is_boundary
            .iter()
            .map(|&b| f64::from(u8::from(b)))
            .collect();
        assert_eq!(called, column("is_boundary"), "window {window}");
    }

    let table =
        directionality(&pixels, Some(&w), &view, &DirectionalityParams::new(50_000)).unwrap();
    let reference = read_table(
        "reference/tads/yeast_10kb.directionality_50000.tsv.gz",
        true,
    );
    let masked: Vec<f64> = table
        .bad_bin_masked
        .iter()
        .map(|&b| f64::from(u8::from(b)))
        .collect();
    assert_eq!(masked, reference.numbers("bad_bin_masked"));
    assert_close(
        &table.ratio,
        &reference.numbers("directionality_ratio_50000"),
        1e-8,
        "directionality ratio",
    );
    assert_close(
        &table.index,
        &reference.numbers("directionality_index_50000"),
        1e-8,
        "directionality index",
    );
}

#[test]
fn every_caller_finds_the_boundaries_of_a_simulated_map() {
    let params = BlockMapParams {
        n_bins: 600,
        depth: 2e7,
        seed: 11,
        ..BlockMapParams::default()
    };
    let map = block_map(&params).unwrap();
    let bins = map.matrix.bins().clone();
    let position = |bin: usize| ("chr1".to_string(), bins.bin(bin).start);
    let truth: Vec<(String, u64)> = map.boundaries.iter().map(|&b| position(b)).collect();
    let matrix = contactmap::io::InMemory::new("blocks".into(), map.matrix.clone());
    let pixels = load_pixels(&matrix, u64::MAX).unwrap();
    let view = View::chromosomes(&bins);
    let bin_bp = params.resolution;
    let callers = [
        (
            Caller::Insulation {
                params: InsulationParams {
                    threshold: Threshold::Li,
                    ..InsulationParams::new(vec![5 * bin_bp])
                },
                calls_window: 0,
            },
            0.9,
        ),
        (
            Caller::Directionality {
                params: DirectionalityParams::new(10 * bin_bp),
                hmm: HmmParams::default(),
            },
            0.9,
        ),
        (Caller::TopDom(TopDomParams::default()), 0.9),
        (
            Caller::Armatus {
                params: ArmatusParams::default(),
                ignore_diags: 2,
                boundary_level: 0,
            },
            0.9,
        ),
    ];
    for (caller, least_f1) in callers {
        let calls = call(&pixels, None, &view, &caller).unwrap();
        let called: Vec<(String, u64)> = calls.boundaries.iter().map(|b| position(b.bin)).collect();
        let score = score_boundaries(&truth, &called, bin_bp);
        eprintln!("{}: {score:?}", calls.label);
        assert!(score.f1 >= least_f1, "{}: {score:?}", calls.label);
    }
}

// ---------------------------------------------------------------------------------------------
// Compartments

/// `ours` equals `theirs` to `tolerance` times the largest magnitude of `theirs`, each
/// chromosome's vector possibly negated when `up_to_sign`.
fn assert_vector(ours: &[f64], theirs: &[f64], tolerance: f64, up_to_sign: bool, what: &str) {
    assert_eq!(ours.len(), theirs.len(), "{what}");
    let scale = theirs
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let difference = |sign: f64| {
        ours.iter().zip(theirs).fold(0.0f64, |m, (a, b)| {
            assert_eq!(a.is_nan(), b.is_nan(), "{what}: NaN pattern");
            if a.is_nan() {
                m
            } else {
                m.max((a - sign * b).abs())
            }
        })
    };
    let d = if up_to_sign {
        difference(1.0).min(difference(-1.0))
    } else {
        difference(1.0)
    };
    assert!(d <= tolerance * scale, "{what}: max difference {d}");
}

fn masked(mut track: Vec<f64>, weights: &[f64]) -> Vec<f64> {
    for (t, w) in track.iter_mut().zip(weights) {
        if !w.is_finite() {
            *t = f64::NAN;
        }
    }
    track
}

#[test]
fn eigenvectors_equal_cooltools_cis_and_trans() {
    let reference = Path::new("reference/compartments");
    let reader = open(DM6);
    let w = weights(reader.as_ref(), "weight");
    let bins = reader.bins();
    let phasing = contactmap::io::tables::track_on_bins(
        Path::new(&data("reference/compartments/dm6_100kb.phasing.tsv.gz")),
        "track",
        bins,
    )
    .unwrap();
    let phasing = masked(phasing, &w);
    let view = View::chromosomes(bins);
    let eigs = eigs_cis(
        reader.as_ref(),
        &w,
        &view,
        Phasing {
            track: Some(&phasing),
            sort: None,
        },
        &CisEigParams::default(),
    )
    .unwrap();
    let name = |file: &str| reference.join(file).to_string_lossy().into_owned();
    let vecs = read_table(&name("dm6_100kb.eigs_cis_phased.vecs.tsv.gz"), true);
    let vals = read_table(&name("dm6_100kb.eigs_cis_phased.vals.tsv.gz"), true);
    assert_eq!(eigs.eigs.len(), vals.rows.len());
    for (k, column) in ["E1", "E2", "E3"].iter().enumerate() {
        let theirs = vecs.numbers(column);
        let values = vals.numbers(&format!("eigval{}", k + 1));
        for (r, (region, ours)) in view.regions().iter().zip(&eigs.eigs).enumerate() {
            let what = format!("{} {column}", region.name);
            assert_vector(
                &ours.vectors[k],
                &theirs[region.bins.clone()],
                1e-8,
                false,
                &what,
            );
            assert_close(&[ours.values[k]], &[values[r]], 1e-8, &what);
        }
    }

    let reader = open(MM9);
    let w = weights(reader.as_ref(), "weight");
    let trans = eigs_trans(
        reader.as_ref(),
        &w,
        Phasing::default(),
        &TransEigParams::default(),
    )
    .unwrap();
    let vecs = read_table(&name("mm9_10Mb.eigs_trans.vecs.tsv.gz"), true);
    let vals = read_table(&name("mm9_10Mb.eigs_trans.vals.tsv.gz"), true);
    for (k, column) in ["E1", "E2", "E3"].iter().enumerate() {
        // without a phasing track the signs are arbitrary, in cooltools too
        assert_vector(
            &trans.eigs.vectors[k],
            &vecs.numbers(column),
            1e-8,
            true,
            column,
        );
        let value = vals.numbers(&format!("eigval{}", k + 1));
        assert_close(&[trans.eigs.values[k]], &value, 1e-8, column);
    }
}

#[test]
fn saddles_equal_cooltools() {
    // cis: dm6 with cooltools' own phased E1 as the track
    let reader = open(DM6);
    let w = weights(reader.as_ref(), "weight");
    let e1 = read_table(
        "reference/compartments/dm6_100kb.eigs_cis_phased.vecs.tsv.gz",
        true,
    )
    .numbers("E1");
    let track = masked(e1, &w);
    let pixels = load_pixels(reader.as_ref(), u64::MAX).unwrap();
    let view = View::chromosomes(reader.bins());
    let params = SaddleParams {
        n_bins: 10,
        binning: Binning::Quantiles(0.025, 0.975),
        min_diag: 3,
        max_diag: None,
    };
    let digitized = digitize(&track, params.n_bins, params.binning).unwrap();
    let edges = read_table("reference/compartments/dm6_100kb.saddle_edges.tsv.gz", true);
    for (ours, theirs) in digitized.edges.iter().zip(edges.numbers("edge")) {
        assert!((ours - theirs).abs() <= 1e-9, "edge {ours} vs {theirs}");
    }
    let expected = expected_cis(&pixels, Some(&w), &view, &CisParams::default())
        .unwrap()
        .average_by_region();
    let saddle = saddle_cis(&pixels, &w, &digitized, &view, &expected, &params).unwrap();
    let assert_saddle = |saddle: &contactmap::compartments::saddle::Saddle, name: &str| {
        let reference = read_table(name, true);
        let n = saddle.n_classes;
        assert_eq!(reference.rows.len(), n * n, "{name}");
        let (i, j) = (reference.numbers("i"), reference.numbers("j"));
        let (sum, count) = (reference.numbers("sum"), reference.numbers("count"));
        for r in 0..n * n {
            let at = i[r] as usize * n + j[r] as usize;
            assert_eq!(
                saddle.count[at], count[r],
                "{name} count ({}, {})",
                i[r], j[r]
            );
            assert_close(&[saddle.sum[at]], &[sum[r]], 1e-8, name);
        }
    };
    assert_saddle(&saddle, "reference/compartments/dm6_100kb.saddle.tsv.gz");
    let strength = read_table(
        "reference/compartments/dm6_100kb.saddle_strength.tsv.gz",
        true,
    );
    // cooltools' entry k = 0 is a placeholder 0
    assert_close(
        &saddle_strength(&saddle)[1..],
        &strength.numbers("strength")[1..],
        1e-8,
        "saddle strength",
    );

    // trans: mm9 with cooltools' trans E1
    let reader = open(MM9);
    let w = weights(reader.as_ref(), "weight");
    let e1 = read_table(
        "reference/compartments/mm9_10Mb.eigs_trans.vecs.tsv.gz",
        true,
    )
    .numbers("E1");
    let track = masked(e1, &w);
    let pixels = load_pixels(reader.as_ref(), u64::MAX).unwrap();
    let view = View::chromosomes(reader.bins());
    let digitized = digitize(&track, 10, Binning::Quantiles(0.025, 0.975)).unwrap();
    let expected = expected_trans(&pixels, Some(&w), &view)
        .unwrap()
        .average_by_pair(&view);
    let saddle = saddle_trans(&pixels, &w, &digitized, &view, &expected).unwrap();
    assert_saddle(
        &saddle,
        "reference/compartments/mm9_10Mb.saddle_trans.tsv.gz",
    );
}

// ---------------------------------------------------------------------------------------------
// Write

#[test]
fn written_coolers_read_back_and_coarsen_as_hictk() {
    let dir = temp_dir("write");
    let input = open(MM9);
    let original = load_matrix(input.as_ref()).unwrap();

    let cool = dir.join("mm9.cool");
    write_cool(input.as_ref(), &cool, &CoolWriteOptions::default()).unwrap();
    let copy = load_matrix(
        open_matrix(cool.to_str().unwrap(), &OpenOptions::default())
            .unwrap()
            .as_ref(),
    )
    .unwrap();
    assert_eq!(copy.bins(), original.bins());
    assert_eq!(pixels_of(&copy), pixels_of(&original));
    let bits = |m: &ContactMatrix| -> Vec<u64> {
        m.weight("weight")
            .unwrap()
            .values
            .iter()
            .map(|v| v.to_bits())
            .collect()
    };
    assert_eq!(bits(&copy), bits(&original));

    // every level of the .mcool holds the pixels of hictk's .hic of the same map
    let mcool = dir.join("mm9.mcool");
    let resolutions = [10_000_000, 20_000_000, 50_000_000];
    write_mcool(
        input.as_ref(),
        &mcool,
        &resolutions,
        &CoolWriteOptions::default(),
    )
    .unwrap();
    for resolution in resolutions {
        let ours = open_matrix(
            &format!("{}::/resolutions/{resolution}", mcool.display()),
            &OpenOptions::default(),
        )
        .unwrap();
        let hictk = open(&format!("CN.mm9.multires.hic::/resolutions/{resolution}"));
        assert_eq!(ours.bins().n_bins(), hictk.bins().n_bins());
        assert_eq!(
            pixels_of(&load_matrix(ours.as_ref()).unwrap()),
            pixels_of(&load_matrix(hictk.as_ref()).unwrap()),
            "{resolution}"
        );
    }

    // a .hic with Juicer's VC: the pixels of the input and our per-chromosome VC
    let hic = dir.join("mm9.hic");
    let unconverged = contactmap::export::write_hic(
        input.as_ref(),
        &hic,
        &[10_000_000, 20_000_000],
        &[Method::Vc],
        &HicWriteOptions::default(),
    )
    .unwrap();
    assert!(unconverged.is_empty());
    let level = HicReader::open(&hic, Some(10_000_000)).unwrap();
    assert_eq!(
        pixels_of(&load_matrix(&level).unwrap()),
        pixels_of(&original)
    );
    let pixels = load_pixels(input.as_ref(), u64::MAX).unwrap();
    let vc = balance(
        &pixels,
        &BalanceParams {
            scope: Scope::Cis,
            ..BalanceParams::juicer(Method::Vc)
        },
    )
    .unwrap();
    assert_close(
        &weights(&level, "VC"),
        &vc.weights,
        1e-6,
        "VC stored in the .hic",
    );

    // BG2 text as cooler dump --join prints it
    let toy = open("toy.symm.upper.2.mcool::/resolutions/4");
    let bg2 = dir.join("toy.bg2");
    write_text(toy.as_ref(), bg2.to_str().unwrap(), TextFormat::Bg2).unwrap();
    assert_eq!(
        std::fs::read_to_string(&bg2).unwrap(),
        std::fs::read_to_string(data("reference/toy_4.join.tsv")).unwrap()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

// ---------------------------------------------------------------------------------------------
// Simulate

#[test]
fn block_map_counts_are_poisson_around_the_model() {
    let params = BlockMapParams {
        n_bins: 300,
        depth: 1e6,
        seed: 5,
        ..BlockMapParams::default()
    };
    let map = block_map(&params).unwrap();
    // the model written out: (d + 1)^-alpha, times 1 + enrichment inside a domain, scaled to
    // the depth (no bias, no dead bin)
    let domain = |bin: usize| {
        map.domains
            .iter()
            .position(|d| d.level == 0 && (d.start_bin..d.end_bin).contains(&bin))
    };
    let n = params.n_bins;
    let mut model = vec![0.0; n * n];
    for i in 0..n {
        for j in i..n {
            let inside = if domain(i) == domain(j) {
                1.0 + params.domain_enrichment
            } else {
                1.0
            };
            model[i * n + j] = ((j - i + 1) as f64).powf(-params.decay_exponent) * inside;
        }
    }
    let scale = params.depth / model.iter().sum::<f64>();
    // chi-square over all pixels: its mean is the number of pixels, its sd sqrt(2 n)
    let mut chi2 = 0.0;
    let mut n_pixels = 0.0;
    for i in 0..n {
        for j in i..n {
            let expected = model[i * n + j] * scale;
            chi2 += (map.matrix.get(i, j) - expected).powi(2) / expected;
            n_pixels += 1.0;
        }
    }
    assert!(
        (chi2 - n_pixels).abs() < 5.0 * (2.0 * n_pixels).sqrt(),
        "chi2 {chi2} over {n_pixels} pixels"
    );
    assert!(map.biases.iter().all(|&b| b == 1.0));
}

#[test]
fn ensemble_contacts_are_the_naive_count_of_close_pairs() {
    let radius = 1.5;
    let params = EnsembleParams {
        polymer: PolymerParams {
            chains: vec![24, 16],
            confinement: Confinement::Sphere {
                radius: 4.0,
                stiffness: 10.0,
            },
            ..PolymerParams::default()
        },
        replicas: 3,
        equilibration_steps: 300,
        sample_every: 100,
        samples: 4,
        contact_radius: radius,
        monomers_per_bin: 4,
        seed: 9,
        extrusion: None,
        keep_conformations: true,
    };
    let ensemble = run_ensemble(&params, &|_| {}).unwrap();
    assert_eq!(ensemble.bins_per_chain, [6, 4]);
    assert_eq!(ensemble.conformations.len(), 12);
    // beads 0..24 are chain 1 (bins 0..6), 24..40 chain 2 (bins 6..10)
    let bin = |bead: usize| {
        if bead < 24 {
            bead / 4
        } else {
            6 + (bead - 24) / 4
        }
    };
    let mut naive: BTreeMap<(u32, u32), u64> = BTreeMap::new();
    for positions in &ensemble.conformations {
        for i in 0..40 {
            for j in i + 1..40 {
                let d2: f64 = (0..3)
                    .map(|k| (positions[i][k] - positions[j][k]).powi(2))
                    .sum();
                if d2 < radius * radius {
                    *naive.entry((bin(i) as u32, bin(j) as u32)).or_default() += 1;
                }
            }
        }
    }
    let naive: Vec<(u32, u32, u64)> = naive.into_iter().map(|((a, b), c)| (a, b, c)).collect();
    assert_eq!(ensemble.pixels, naive);
    // the sphere holds the chains
    assert!(
        ensemble
            .conformations
            .iter()
            .flatten()
            .all(|p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() < 6.0)
    );
}

// ---------------------------------------------------------------------------------------------
// Score

fn truth(structure: &str) -> TrueContacts {
    let structure = read_structure(data(&format!("protein/{structure}"))).unwrap();
    TrueContacts::from_chain(structure.chain(None).unwrap(), ContactDefinition::default()).unwrap()
}

fn prediction(file: &str, fasta: &str) -> Prediction {
    let sequence = read_fasta(data(&format!("protein/{fasta}"))).unwrap();
    read_prediction(data(&format!("protein/{file}")), None)
        .unwrap()
        .with_sequence(&sequence)
        .unwrap()
}

#[test]
fn contact_scores_equal_the_published_numbers() {
    // data/protein/README.md: true contacts per range (short, medium, long, all)
    for (structure, counts) in [
        ("toxd/toxd.pdb.gz", [15, 43, 57, 115]),
        ("1atzA/1atzA.pdb.gz", [24, 27, 69, 120]),
        ("1aapA/1aapA.pdb.gz", [13, 44, 57, 114]),
        ("1guuA/1guuA.pdb.gz", [15, 17, 13, 45]),
        ("1a8o/1A8O.cif.gz", [16, 26, 35, 77]),
    ] {
        let truth = truth(structure);
        let ranges = [
            SeparationRange::SHORT,
            SeparationRange::MEDIUM,
            SeparationRange::LONG,
            SeparationRange::ALL,
        ];
        assert_eq!(ranges.map(|r| truth.n_contacts(r)), counts, "{structure}");
    }
    // "Method P": long range, top L/10, L/5, L/2, L as (true positives, pairs scored)
    for (structure, file, fasta, expected) in [
        (
            "toxd/toxd.pdb.gz",
            "toxd/toxd.mat.gz",
            "toxd/toxd.fasta",
            [(5, 5), (9, 11), (17, 29), (22, 59)],
        ),
        (
            "1atzA/1atzA.pdb.gz",
            "1atzA/1atzA.apc.mat.gz",
            "1atzA/1atzA.fasta",
            [(6, 7), (12, 15), (21, 37), (30, 75)],
        ),
        (
            "1atzA/1atzA.pdb.gz",
            "1atzA/1atzA.noapc.mat.gz",
            "1atzA/1atzA.fasta",
            [(4, 7), (5, 15), (9, 37), (11, 75)],
        ),
        (
            "1aapA/1aapA.pdb.gz",
            "1aapA/1aapA.rr.gz",
            "1aapA/1aapA.fasta",
            [(4, 5), (9, 11), (13, 28), (17, 56)],
        ),
        (
            "1guuA/1guuA.pdb.gz",
            "1guuA/1guuA.contact.rr",
            "1guuA/1guuA.fasta",
            [(1, 1); 4],
        ),
        (
            "1guuA/1guuA.pdb.gz",
            "1guuA/1guuA.npz",
            "1guuA/1guuA.fasta",
            [(5, 5), (10, 10), (13, 25), (13, 50)],
        ),
    ] {
        let score = score_contacts(
            &truth(structure),
            &prediction(file, fasta),
            &ScoreParams::default(),
        )
        .unwrap();
        let found: Vec<(usize, usize)> = score
            .lists
            .iter()
            .map(|list| (list.true_positives, list.n_scored))
            .collect();
        assert_eq!(found, expected, "{file}");
    }
    // ConKit's documentation: toxd, separation >= 5, top 29, 59, 88
    let params = ScoreParams {
        range: SeparationRange::new(5, None),
        list_sizes: [29, 59, 88].map(ListSize::Count).to_vec(),
        ..ScoreParams::default()
    };
    let score = score_contacts(
        &truth("toxd/toxd.pdb.gz"),
        &prediction("toxd/toxd.mat.gz", "toxd/toxd.fasta"),
        &params,
    )
    .unwrap();
    let found: Vec<usize> = score.lists.iter().map(|l| l.true_positives).collect();
    assert_eq!(found, [24, 35, 38]);
}

/// The largest number of one-to-one pairs within `tolerance`, by trying every assignment.
fn brute_force_matching(truth: &[u64], calls: &[u64], tolerance: u64) -> usize {
    fn best(truth: &[u64], calls: &[u64], used: &mut Vec<bool>, tolerance: u64) -> usize {
        let Some((&t, rest)) = truth.split_first() else {
            return 0;
        };
        let mut most = best(rest, calls, used, tolerance);
        for k in 0..calls.len() {
            if !used[k] && calls[k].abs_diff(t) <= tolerance {
                used[k] = true;
                most = most.max(1 + best(rest, calls, used, tolerance));
                used[k] = false;
            }
        }
        most
    }
    best(truth, calls, &mut vec![false; calls.len()], tolerance)
}

#[test]
fn boundary_overlap_and_compartment_scores_equal_naive_ones() {
    // boundaries: a small linear congruential sequence of positions, matched by brute force
    let mut state = 12345u64;
    let mut next = |modulo: u64| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) % modulo
    };
    for _ in 0..50 {
        let truth: Vec<u64> = (0..1 + next(6)).map(|_| next(50) * 1_000).collect();
        let calls: Vec<u64> = (0..1 + next(6)).map(|_| next(50) * 1_000).collect();
        let tolerance = next(4) * 1_000;
        let on = |v: &[u64]| -> Vec<(String, u64)> {
            v.iter().map(|&p| ("chr1".to_string(), p)).collect()
        };
        let score = score_boundaries(&on(&truth), &on(&calls), tolerance);
        let matched = brute_force_matching(&truth, &calls, tolerance);
        assert_eq!(
            score.true_positives, matched,
            "{truth:?} {calls:?} {tolerance}"
        );
        assert_eq!(
            score.f1,
            2.0 * matched as f64 / (truth.len() + calls.len()) as f64
        );
    }

    // overlap of two predictions' top lists, the lists ranked naively
    let first = prediction("1atzA/1atzA.apc.mat.gz", "1atzA/1atzA.fasta");
    let second = prediction("1atzA/1atzA.noapc.mat.gz", "1atzA/1atzA.fasta");
    let naive_ranked = |p: &Prediction| -> Vec<(i32, i32)> {
        let mut best: Vec<((i32, i32), f64)> = Vec::new();
        for &(i, j, score) in &p.pairs {
            let key = (i.min(j), i.max(j));
            if i == j || score.is_nan() || key.1 - key.0 < 24 {
                continue;
            }
            match best.iter_mut().find(|(k, _)| *k == key) {
                Some(entry) => entry.1 = entry.1.max(score),
                None => best.push((key, score)),
            }
        }
        best.sort_by(|a, b| b.1.partial_cmp(&a.1).unwrap());
        best.into_iter().map(|(k, _)| k).collect()
    };
    let (a, b) = (naive_ranked(&first), naive_ranked(&second));
    assert_eq!(ranked_pairs(&first, SeparationRange::LONG), a);
    assert_eq!(ranked_pairs(&second, SeparationRange::LONG), b);
    for k in [7, 15, 37, 75] {
        let got = overlap(&a, &b, k);
        let top_a: HashSet<&(i32, i32)> = a.iter().take(k).collect();
        let shared = b.iter().take(k).filter(|p| top_a.contains(p)).count();
        assert_eq!(got.shared, shared, "top {k}");
        let union = top_a.len() + b.len().min(k) - shared;
        assert_eq!(got.jaccard, shared as f64 / union as f64);
    }

    // compartments: signs counted bin by bin
    let values: Vec<f64> = (0..200)
        .map(|k| ((k * 37 % 101) as f64 - 50.0) / 10.0)
        .collect();
    let truth: Vec<f64> = (0..200)
        .map(|k| match k % 7 {
            0 => f64::NAN,
            1..=3 => 1.0,
            _ => -1.0,
        })
        .collect();
    let score = score_compartments(&values, &truth);
    let kept: Vec<(f64, f64)> = values
        .iter()
        .zip(&truth)
        .filter(|(v, t)| v.is_finite() && t.is_finite())
        .map(|(&v, &t)| (v, t))
        .collect();
    let right = kept.iter().filter(|(v, t)| v * t > 0.0).count();
    assert_eq!(score.n_bins, kept.len());
    assert_eq!(score.sign_accuracy, right as f64 / kept.len() as f64);
}

// ---------------------------------------------------------------------------------------------
// Plot

#[test]
fn heatmap_pixels_have_the_colour_of_their_balanced_value() {
    let reader = open(DM6);
    let w = weights(reader.as_ref(), "weight");
    let bins = reader.bins();
    let region = bins
        .parse_region_bins("chr2L:5,000,000-10,000,000")
        .unwrap();
    let span = GenomicSpan {
        chrom: "chr2L".into(),
        start_bp: 5_000_000,
        end_bp: 10_000_000,
    };
    let layout = MapLayout::new(600, None, 100.0, MapView::Square, &span, &span, 0);
    let rows = AxisCells::new(region.clone(), layout.map_height_px());
    let cols = AxisCells::new(region.clone(), layout.map_width_px());
    assert_eq!(rows.n_cells, 50);
    let mut grid = CellGrid::new(rows, cols, &|b| w[b].is_finite(), 0, true);
    let mut balanced = HashMap::new();
    reader
        .read_pixels(region.clone(), region.clone(), &mut |block| {
            for k in 0..block.len() {
                let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                let value = block.count[k] * w[i] * w[j];
                grid.add(i, j, value);
                if i != j {
                    grid.add(j, i, value);
                }
                balanced.insert((i, j), value);
            }
            Ok(())
        })
        .unwrap();
    let colour_map = ColorMap::by_name("fall").unwrap();
    let scale = ColorScale::new(ScaleKind::Log, 1e-4, 1e-1).unwrap();
    let style = MapStyle {
        colour_map: colour_map.clone(),
        scale,
        nan: Rgb(128, 128, 128),
        colour_label: "balanced".into(),
        title: String::new(),
    };
    let figure = MapFigure {
        layout: &layout,
        view: MapView::Square,
        grid: &grid,
        rows: &span,
        cols: &span,
        style: &style,
        overlays: &Overlays::default(),
        tracks: &[],
    };
    let svg = draw_map(&figure).unwrap();
    let png = figure_bytes(&svg, ImageFormat::Png, 100.0).unwrap();
    let mut decoder = png::Decoder::new(png.as_slice()).read_info().unwrap();
    let mut image = vec![0; decoder.output_buffer_size()];
    let frame = decoder.next_frame(&mut image).unwrap();
    assert_eq!(
        (frame.width as usize, frame.height as usize),
        (layout.width_px, layout.height_px)
    );
    let map = &layout.map;
    let (cell_w, cell_h) = (map.width / 50.0, map.height / 50.0);
    let mut checked = 0;
    for (r, c) in [
        (0, 0),
        (3, 10),
        (10, 3),
        (20, 21),
        (25, 40),
        (49, 49),
        (7, 30),
    ] {
        let (i, j) = (region.start + r, region.start + c);
        // the naive value of the pair: one bin per cell, the stored pixel or 0
        let value = if w[i].is_finite() && w[j].is_finite() {
            balanced.get(&(i.min(j), i.max(j))).copied().unwrap_or(0.0)
        } else {
            f64::NAN
        };
        let want = match scale.position(value) {
            Some(t) => colour_map.colour(t),
            None => style.nan,
        };
        let x = (map.x + (c as f64 + 0.5) * cell_w) as usize;
        let y = (map.y + (r as f64 + 0.5) * cell_h) as usize;
        let at = 3 * (y * frame.width as usize + x);
        let got = [image[at], image[at + 1], image[at + 2]];
        let want = [want.0, want.1, want.2];
        assert!(
            got.iter().zip(want).all(|(g, w)| g.abs_diff(w) <= 2),
            "cell ({r}, {c}), value {value}: {got:?} vs {want:?}"
        );
        checked += 1;
    }
    assert_eq!(checked, 7);
    // the SVG is well-formed XML with the raster embedded
    let text = String::from_utf8(figure_bytes(&svg, ImageFormat::Svg, 100.0).unwrap()).unwrap();
    let document = roxmltree::Document::parse(&text).unwrap();
    assert!(
        document
            .descendants()
            .any(|node| node.has_tag_name("image"))
    );
}
