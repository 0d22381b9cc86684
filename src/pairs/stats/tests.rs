use std::collections::BTreeMap;

use super::*;
use crate::io::pairs::PairsReader;
use crate::io::pairs::{PairColumns, PairRecord, parse_position};

use crate::pairs::tests::reference;

/// What `pairtools dedup --mark-dups` counted for `sim.dedup.stats`: its nodups, dups (pair
/// type `DD`) and unmapped outputs one after the other, under the nodups header. `pairtools
/// stats` of this text writes `sim.dedup.stats` plus the `chromsizes/` lines (which dedup does
/// not write).
fn marked_pairs() -> String {
    let mut text = reference("sim.nodups.pairs.gz");
    for name in ["sim.dups.pairs.gz", "sim.unmapped.pairs.gz"] {
        for line in reference(name).lines().filter(|l| !l.starts_with('#')) {
            text.push_str(line);
            text.push('\n');
        }
    }
    text
}

fn reader(text: &str, name: &str) -> PairsReader {
    let input = std::io::Cursor::new(text.as_bytes().to_vec());
    PairsReader::new(Box::new(input), name).unwrap()
}

/// `pairtools stats` on pairs text: records in chunks, chromosome sizes from the header when
/// `with_sizes`.
fn stats_of(text: &str, name: &str, with_sizes: bool) -> PairCounter {
    let mut reader = reader(text, name);
    let columns = PairColumns::of(reader.header(), name).unwrap();
    let mut counter = PairCounter::new();
    if with_sizes {
        counter.set_chromsizes(reader.header().chromsizes(name).unwrap());
    }
    let mut record = PairRecord::default();
    while reader.read_record(&mut record).unwrap() {
        counter.add_record(&record, &columns, None).unwrap();
        if counter.n_chunk_records() == STATS_CHUNK_RECORDS {
            counter.end_chunk();
        }
    }
    counter
}

/// The same text counted pair by pair, as `pairtools parse` counts (its statistics have no
/// chromosome sizes).
fn parse_stats_of(text: &str, name: &str, with_sizes: bool) -> PairCounter {
    let mut reader = reader(text, name);
    let c = PairColumns::of(reader.header(), name).unwrap();
    let mut counter = PairCounter::new();
    if with_sizes {
        counter.set_chromsizes(reader.header().chromsizes(name).unwrap());
    }
    let mut record = PairRecord::default();
    while reader.read_record(&mut record).unwrap() {
        let position = |i| parse_position(record.field(i)).unwrap();
        counter
            .add_pair(
                record.field(c.chrom1),
                position(c.pos1),
                record.field(c.strand1),
                record.field(c.chrom2),
                position(c.pos2),
                record.field(c.strand2),
                record.field(c.pair_type.unwrap()),
            )
            .unwrap();
    }
    counter
}

fn parse_lines(text: &str) -> Vec<(String, String)> {
    text.lines()
        .map(|line| {
            let (key, value) = line.split_once('\t').expect("key<TAB>value");
            (key.to_string(), value.to_string())
        })
        .collect()
}

/// Whether two written values agree: the same text, or two floats (written with a '.', an
/// exponent, or nan / inf) within 1e-9 relative.
fn same_value(ours: &str, theirs: &str) -> bool {
    if ours == theirs {
        return true;
    }
    let is_float = |s: &str| s.contains(['.', 'e', 'n']);
    match (ours.parse::<f64>(), theirs.parse::<f64>()) {
        (Ok(a), Ok(b)) if is_float(ours) && is_float(theirs) => {
            (a.is_nan() && b.is_nan()) || (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
        }
        _ => false,
    }
}

/// Compare every line, in order; the lines whose key starts with `unordered` are compared as
/// a set within their block.
fn assert_same_stats(ours: &[(String, String)], expected: &str, unordered: Option<&str>) {
    let mut theirs = parse_lines(expected);
    let mut ours = ours.to_vec();
    if let Some(prefix) = unordered {
        for lines in [&mut ours, &mut theirs] {
            let start = lines.iter().position(|(k, _)| k.starts_with(prefix));
            if let Some(start) = start {
                let end = start
                    + lines[start..]
                        .iter()
                        .take_while(|(k, _)| k.starts_with(prefix))
                        .count();
                lines[start..end].sort();
            }
        }
    }
    assert_eq!(ours.len(), theirs.len(), "number of lines");
    for (i, ((key, value), (their_key, their_value))) in ours.iter().zip(&theirs).enumerate() {
        assert_eq!(key, their_key, "line {}", i + 1);
        assert!(
            same_value(value, their_value),
            "line {} {key}: ours {value}, pairtools {their_value}",
            i + 1
        );
    }
}

#[test]
fn stats_match_pairtools_with_duplicates() {
    // pairtools dedup's statistics of the pairs it marked: no chromosome sizes.
    let counter = stats_of(&marked_pairs(), "marked.pairs", false);
    assert!(counter.n_duplicates() > 0);
    assert_same_stats(&counter.lines(), &reference("sim.dedup.stats.gz"), None);
}

#[test]
fn stats_match_pairtools_without_duplicates() {
    // No duplicates: pairtools' complexity is nan.
    let counter = stats_of(&reference("sim.5unique.pairs.gz"), "5unique.pairs", true);
    assert_eq!(counter.n_duplicates(), 0);
    let expected = reference("sim.5unique.stats.gz");
    assert!(expected.contains("summary/complexity_naive\tnan\n"));
    assert_same_stats(&counter.lines(), &expected, None);
}

/// Five pairs, every mapped one a `DD` duplicate, and what `pairtools stats` (1.1.2) writes
/// for them but the `dist_freq/` lines (all 0): fractions of nothing, complexity 0.
const ONLY_DUPLICATES: &str = "## pairs format v1.0.0
#chromsize: chr1 60000000
#chromsize: chr2 40000000
#chromsize: chr3 12000000
#chromsize: chrX 5000000
#columns: readID chrom1 pos1 chrom2 pos2 strand1 strand2 pair_type
c1\tchr1\t100\tchr1\t5000\t+\t-\tDD
c2\tchr2\t7\tchr3\t9\t-\t-\tDD
c3\t!\t0\t!\t0\t-\t-\tNN
c4\tchrX\t10\t!\t0\t+\t-\tUN
c5\tchr1\t100\tchr1\t5000\t+\t-\tDD
";

const ONLY_DUPLICATES_STATS: &str = "total\t5
total_unmapped\t1
total_single_sided_mapped\t1
total_mapped\t3
total_dups\t3
total_nodups\t0
cis\t0
trans\t0
pair_types/DD\t3
pair_types/NN\t1
pair_types/UN\t1
cis_1kb+\t0
cis_2kb+\t0
cis_4kb+\t0
cis_10kb+\t0
cis_20kb+\t0
cis_40kb+\t0
summary/frac_cis\t0
summary/frac_cis_1kb+\t0
summary/frac_cis_2kb+\t0
summary/frac_cis_4kb+\t0
summary/frac_cis_10kb+\t0
summary/frac_cis_20kb+\t0
summary/frac_cis_40kb+\t0
summary/frac_dups\t1.0
summary/complexity_naive\t0
summary/dist_freq_convergence/convergence_dist\t0
summary/dist_freq_convergence/strands_w_max_convergence_dist\t??
summary/dist_freq_convergence/convergence_rel_diff_threshold\t0.05
summary/dist_freq_convergence/n_cis_pairs_below_convergence_dist/++\t0
summary/dist_freq_convergence/n_cis_pairs_below_convergence_dist/--\t0
summary/dist_freq_convergence/n_cis_pairs_below_convergence_dist/-+\t0
summary/dist_freq_convergence/n_cis_pairs_below_convergence_dist/+-\t0
summary/dist_freq_convergence/n_cis_pairs_below_convergence_dist_all_strands\t0
summary/dist_freq_convergence/n_cis_pairs_above_convergence_dist_all_strands\t0
summary/dist_freq_convergence/frac_cis_in_cis_below_convergence_dist/++\tnan
summary/dist_freq_convergence/frac_cis_in_cis_below_convergence_dist/--\tnan
summary/dist_freq_convergence/frac_cis_in_cis_below_convergence_dist/-+\tnan
summary/dist_freq_convergence/frac_cis_in_cis_below_convergence_dist/+-\tnan
summary/dist_freq_convergence/frac_cis_in_cis_below_convergence_dist_all_strands\tnan
summary/dist_freq_convergence/frac_cis_in_cis_above_convergence_dist_all_strands\tnan
summary/dist_freq_convergence/frac_total_mapped_in_cis_below_convergence_dist/++\t0.0
summary/dist_freq_convergence/frac_total_mapped_in_cis_below_convergence_dist/--\t0.0
summary/dist_freq_convergence/frac_total_mapped_in_cis_below_convergence_dist/-+\t0.0
summary/dist_freq_convergence/frac_total_mapped_in_cis_below_convergence_dist/+-\t0.0
summary/dist_freq_convergence/frac_total_mapped_in_cis_below_convergence_dist_all_strands\t0.0
summary/dist_freq_convergence/frac_total_mapped_in_cis_above_convergence_dist_all_strands\t0.0
summary/dist_freq_convergence/frac_total_nodups_in_cis_below_convergence_dist/++\tnan
summary/dist_freq_convergence/frac_total_nodups_in_cis_below_convergence_dist/--\tnan
summary/dist_freq_convergence/frac_total_nodups_in_cis_below_convergence_dist/-+\tnan
summary/dist_freq_convergence/frac_total_nodups_in_cis_below_convergence_dist/+-\tnan
summary/dist_freq_convergence/frac_total_nodups_in_cis_below_convergence_dist_all_strands\tnan
summary/dist_freq_convergence/frac_total_nodups_in_cis_above_convergence_dist_all_strands\tnan
chromsizes/chr1\t60000000
chromsizes/chr2\t40000000
chromsizes/chr3\t12000000
chromsizes/chrX\t5000000
";

#[test]
fn stats_match_pairtools_with_only_duplicates_mapped() {
    let counter = stats_of(ONLY_DUPLICATES, "c.pairs", true);
    assert_eq!(counter.n_duplicates(), counter.n_mapped());
    let (dist_freq, others): (Vec<_>, Vec<_>) = counter
        .lines()
        .into_iter()
        .partition(|(k, _)| k.starts_with("dist_freq/"));
    assert_same_stats(&others, ONLY_DUPLICATES_STATS, None);
    // The distance bins are pairtools' (those of a stats file it wrote), every count 0.
    let pairtools_bins: Vec<String> = parse_lines(&reference("sim.5unique.stats.gz"))
        .into_iter()
        .filter(|(k, _)| k.starts_with("dist_freq/"))
        .map(|(k, _)| k)
        .collect();
    assert_eq!(
        dist_freq.iter().map(|(k, _)| k.clone()).collect::<Vec<_>>(),
        pairtools_bins
    );
    assert!(dist_freq.iter().all(|(_, v)| v == "0"));
}

#[test]
fn the_text_is_the_lines() {
    let counter = stats_of(&marked_pairs(), "marked.pairs", true);
    assert_eq!(parse_lines(&counter.to_text()), counter.lines());
}

#[test]
fn parse_counting_matches_pairtools_parse() {
    // add_pair lists pair types and chromosome pairs as they first appear in the file, as
    // `pairtools parse --output-stats` does for the pairs it writes.
    let counter = parse_stats_of(&reference("sim.5unique.full.pairs.gz"), "full.pairs", false);
    assert_same_stats(
        &counter.lines(),
        &reference("sim.5unique.full.stats.gz"),
        None,
    );
}

#[test]
fn parse_counting_differs_only_in_the_order_of_keys() {
    let text = marked_pairs();
    let by_pair = parse_stats_of(&text, "marked.pairs", true);
    let by_record = stats_of(&text, "marked.pairs", true);
    let sorted = |lines: Vec<(String, String)>| {
        let mut lines = lines;
        lines.sort();
        lines
    };
    assert_eq!(sorted(by_pair.lines()), sorted(by_record.lines()));
    let mut reader = reader(&text, "marked.pairs");
    let c = PairColumns::of(reader.header(), "marked.pairs").unwrap();
    let mut first_seen: Vec<Vec<u8>> = Vec::new();
    let mut record = PairRecord::default();
    while reader.read_record(&mut record).unwrap() {
        let pair_type = record.field(c.pair_type.unwrap()).to_vec();
        if !first_seen.contains(&pair_type) {
            first_seen.push(pair_type);
        }
    }
    assert!(first_seen.contains(&b"DD".to_vec()));
    assert_eq!(by_pair.pair_types.keys, first_seen);
    // By record they come by decreasing count: another order.
    assert_ne!(by_record.finished().pair_types.keys, first_seen);
}

#[test]
fn merged_stats_match_pairtools() {
    let parsed = reference("sim.5unique.stats.gz");
    let deduplicated = reference("sim.dedup.stats.gz");
    let mut merged = PairCounter::from_text(&parsed, "sim.5unique.stats").unwrap();
    merged
        .merge(&PairCounter::from_text(&deduplicated, "sim.dedup.stats").unwrap())
        .unwrap();
    // pairtools lists merged pair types in Python's string-hash order (a set union).
    assert_same_stats(
        &merged.lines(),
        &reference("sim.merged.stats.gz"),
        Some("pair_types/"),
    );
}

#[test]
fn a_stats_file_read_back_matches_pairtools_merge_of_one_file() {
    // `pairtools stats --merge` of one file writes it back but for chrom_freq, grouped by
    // first chromosome as its reading nests them; a merged file comes back unchanged (checked
    // with pairtools 1.1.2 on sim.merged.stats).
    let merged = reference("sim.merged.stats.gz");
    let counter = PairCounter::from_text(&merged, "sim.merged.stats").unwrap();
    assert_same_stats(&counter.lines(), &merged, None);
    // sim.5unique.stats lists cis chromosome pairs first; read back, chrom_freq comes in the
    // order of pairtools' merge (sim.merged.stats: the same chromosome pairs, grouped).
    let parsed = reference("sim.5unique.stats.gz");
    let merged_order: Vec<String> = parse_lines(&merged)
        .into_iter()
        .filter(|(k, _)| k.starts_with("chrom_freq/"))
        .map(|(k, _)| k)
        .collect();
    let mut expected = parse_lines(&parsed);
    let start = expected
        .iter()
        .position(|(k, _)| k.starts_with("chrom_freq/"))
        .unwrap();
    let end = start
        + expected[start..]
            .iter()
            .take_while(|(k, _)| k.starts_with("chrom_freq/"))
            .count();
    let original: Vec<_> = expected[start..end].to_vec();
    expected[start..end].sort_by_key(|(k, _)| merged_order.iter().position(|m| m == k).unwrap());
    assert_ne!(expected[start..end], original[..], "already grouped");
    let expected: String = expected
        .iter()
        .map(|(k, v)| format!("{k}\t{v}\n"))
        .collect();
    let counter = PairCounter::from_text(&parsed, "sim.5unique.stats").unwrap();
    assert_same_stats(&counter.lines(), &expected, None);
}

#[test]
fn merging_counters_adds_their_counts() {
    let a = stats_of(&reference("sim.5unique.pairs.gz"), "5unique.pairs", true);
    let b = stats_of(&marked_pairs(), "marked.pairs", true);
    let mut merged = a.clone();
    merged.merge(&b).unwrap();
    assert_eq!(merged.n_total(), a.n_total() + b.n_total());
    assert_eq!(merged.n_duplicates(), b.n_duplicates());
    assert_eq!(
        merged.n_pair_type("UU"),
        a.n_pair_type("UU") + b.n_pair_type("UU")
    );
    for s in 0..4 {
        for bin in 0..merged.dist_bins.len() {
            assert_eq!(
                merged.dist_freq[s][bin],
                a.dist_freq[s][bin] + b.dist_freq[s][bin]
            );
        }
    }
    let mut other_sizes = PairCounter::new();
    other_sizes.set_chromsizes(vec![("chr1".into(), 5)]);
    let error = merged.merge(&other_sizes).unwrap_err().to_string();
    assert!(error.contains("different chromosome sizes"), "{error}");
    let mut no_sizes = PairCounter::new();
    no_sizes.merge(&a).unwrap();
    assert_eq!(no_sizes.chromsizes, a.chromsizes);
    let mut other_bins = PairCounter::with_dist_bins_per_decade(4).unwrap();
    assert!(other_bins.merge(&a).is_err());
}

/// A small deterministic generator (an LCG) for the naive recount.
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: u64) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) % n
    }
}

#[test]
fn counts_match_a_naive_recount() {
    let chroms = ["!", "chr1", "chr2", "chr3"];
    let types = ["UU", "RU", "DD", "NN", "MM"];
    let strands = ["+", "-"];
    let mut rng = Lcg(7);
    let mut pairs = Vec::new();
    for _ in 0..3000 {
        let c1 = chroms[rng.below(4) as usize];
        let c2 = if rng.below(2) == 0 {
            c1
        } else {
            chroms[rng.below(4) as usize]
        };
        let bits1 = rng.below(31);
        let pos1 = rng.below(1 << bits1);
        let bits2 = rng.below(31);
        let pos2 = rng.below(1 << bits2);
        let s1 = strands[rng.below(2) as usize];
        let s2 = strands[rng.below(2) as usize];
        let t = types[rng.below(5) as usize];
        pairs.push((c1, pos1, s1, c2, pos2, s2, t));
    }
    let mut by_pair = PairCounter::new();
    let columns = PairColumns {
        read_id: Some(0),
        chrom1: 1,
        pos1: 2,
        chrom2: 3,
        pos2: 4,
        strand1: 5,
        strand2: 6,
        pair_type: Some(7),
        n_columns: 8,
    };
    let mut by_record = PairCounter::new();
    for (i, &(c1, p1, s1, c2, p2, s2, t)) in pairs.iter().enumerate() {
        by_pair
            .add_pair(
                c1.as_bytes(),
                p1,
                s1.as_bytes(),
                c2.as_bytes(),
                p2,
                s2.as_bytes(),
                t.as_bytes(),
            )
            .unwrap();
        let line = format!(".\t{c1}\t{p1}\t{c2}\t{p2}\t{s1}\t{s2}\t{t}");
        by_record
            .add_record(
                &PairRecord::from_line(line.as_bytes(), i as u64 + 1),
                &columns,
                None,
            )
            .unwrap();
        if by_record.n_chunk_records() == 700 {
            by_record.end_chunk();
        }
    }
    by_record.end_chunk();

    let mapped: Vec<_> = pairs.iter().filter(|p| p.0 != "!" && p.3 != "!").collect();
    let nodups: Vec<_> = mapped.iter().filter(|p| p.6 != "DD").collect();
    let cis: Vec<_> = nodups.iter().filter(|p| p.0 == p.3).collect();
    let edges = dist_bin_edges(8);
    let mut dist_freq = vec![[0u64; 4]; edges.len()];
    for p in &cis {
        let separation = p.1.abs_diff(p.4);
        let bin = edges.iter().rposition(|&e| e <= separation).unwrap();
        let s = STRAND_PAIRS
            .iter()
            .position(|&s| s == format!("{}{}", p.2, p.5))
            .unwrap();
        dist_freq[bin][s] += 1;
    }
    let mut chrom_freq = BTreeMap::new();
    for p in &nodups {
        *chrom_freq
            .entry(format!("{}\t{}", p.0, p.3))
            .or_insert(0u64) += 1;
    }
    let mut pair_types = BTreeMap::new();
    for p in &pairs {
        *pair_types.entry(p.6.as_bytes().to_vec()).or_insert(0u64) += 1;
    }
    let unmapped = pairs.iter().filter(|p| p.0 == "!" && p.3 == "!").count() as u64;
    for counter in [&by_pair, &by_record] {
        assert_eq!(counter.total, pairs.len() as u64);
        assert_eq!(counter.total_unmapped, unmapped);
        assert_eq!(counter.total_mapped, mapped.len() as u64);
        assert_eq!(
            counter.total_single_sided_mapped,
            pairs.len() as u64 - unmapped - mapped.len() as u64
        );
        assert_eq!(counter.total_nodups, nodups.len() as u64);
        assert_eq!(counter.total_dups, (mapped.len() - nodups.len()) as u64);
        assert_eq!(counter.cis, cis.len() as u64);
        assert_eq!(counter.trans, (nodups.len() - cis.len()) as u64);
        for (k, cutoff) in CIS_CUTOFFS_BP.iter().enumerate() {
            let n = cis.iter().filter(|p| p.1.abs_diff(p.4) >= *cutoff).count() as u64;
            assert_eq!(counter.cis_beyond[k], n);
        }
        for (bin, counts) in dist_freq.iter().enumerate() {
            for (s, count) in counts.iter().enumerate() {
                assert_eq!(counter.dist_freq[s][bin], *count, "bin {bin} strands {s}");
            }
        }
        let ours: BTreeMap<_, _> = counter
            .chrom_freq
            .iter()
            .map(|(k, n)| (String::from_utf8(k.to_vec()).unwrap(), n))
            .collect();
        assert_eq!(ours, chrom_freq);
        let ours: BTreeMap<_, _> = counter
            .pair_types
            .iter()
            .map(|(k, n)| (k.to_vec(), n))
            .collect();
        assert_eq!(ours, pair_types);
    }
    // The summary fractions are the counts' ratios.
    let lines: BTreeMap<_, _> = by_record.lines().into_iter().collect();
    let frac_cis: f64 = lines["summary/frac_cis"].parse().unwrap();
    assert_eq!(frac_cis, cis.len() as f64 / nodups.len() as f64);
    let below: u64 =
        lines["summary/dist_freq_convergence/n_cis_pairs_below_convergence_dist_all_strands"]
            .parse()
            .unwrap();
    let above: u64 =
        lines["summary/dist_freq_convergence/n_cis_pairs_above_convergence_dist_all_strands"]
            .parse()
            .unwrap();
    assert_eq!(below + above, cis.len() as u64);
}

#[test]
fn chunks_list_new_keys_by_decreasing_count() {
    let columns = PairColumns {
        read_id: Some(0),
        chrom1: 1,
        pos1: 2,
        chrom2: 3,
        pos2: 4,
        strand1: 5,
        strand2: 6,
        pair_type: Some(7),
        n_columns: 8,
    };
    let mut counter = PairCounter::new();
    for (i, t) in ["RU", "UU", "UR", "UU", "UR", "", "NA"].iter().enumerate() {
        let line = format!(".\t!\t0\t!\t0\t-\t-\t{t}");
        counter
            .add_record(
                &PairRecord::from_line(line.as_bytes(), i as u64),
                &columns,
                None,
            )
            .unwrap();
    }
    counter.end_chunk();
    counter
        .add_record(
            &PairRecord::from_line(b".\t!\t0\t!\t0\t-\t-\tRU", 9),
            &columns,
            None,
        )
        .unwrap();
    // pandas reads '' and 'NA' as missing: not counted as pair types.
    let keys: Vec<_> = counter
        .finished()
        .pair_types
        .iter()
        .map(|(k, n)| (k.to_vec(), n))
        .collect();
    assert_eq!(
        keys,
        vec![
            (b"UU".to_vec(), 2),
            (b"UR".to_vec(), 2),
            (b"RU".to_vec(), 2)
        ]
    );
    assert_eq!(counter.n_total(), 8);
}

#[test]
fn bad_records_are_reported_and_not_counted() {
    let mut columns = PairColumns {
        read_id: Some(0),
        chrom1: 1,
        pos1: 2,
        chrom2: 3,
        pos2: 4,
        strand1: 5,
        strand2: 6,
        pair_type: Some(7),
        n_columns: 8,
    };
    let mut counter = PairCounter::new();
    let record = |line: &str| PairRecord::from_line(line.as_bytes(), 1);
    let error = counter
        .add_record(&record(".\tc\t1\tc\t5\t+\t.\tUU"), &columns, None)
        .unwrap_err();
    assert!(error.contains("strands '+' and '.'"), "{error}");
    let error = counter
        .add_record(&record(".\tc\tx\tc\t5\t+\t-\tUU"), &columns, None)
        .unwrap_err();
    assert!(error.contains("position 'x'"), "{error}");
    assert!(
        counter
            .add_pair(b"c", 1, b"+", b"c", 2, b"*", b"UU")
            .is_err()
    );
    // A trans or duplicate pair's strands are not read.
    counter
        .add_record(&record(".\tc\t1\td\t5\t+\t.\tUU"), &columns, None)
        .unwrap();
    counter
        .add_record(&record(".\tc\t1\tc\t5\t+\t.\tUU"), &columns, Some(true))
        .unwrap();
    assert_eq!(counter.n_total(), 2);
    assert_eq!(counter.n_duplicates(), 1);
    columns.pair_type = None;
    assert!(
        counter
            .add_record(&record(".\tc\t1\td\t5\t+\t-\tUU"), &columns, None)
            .is_err()
    );
}

#[test]
fn stats_file_errors_name_the_line() {
    let error = |text: &str| {
        PairCounter::from_text(text, "x.stats")
            .unwrap_err()
            .to_string()
    };
    assert!(error("total\t3\ncis\t1\t2\n").starts_with("x.stats:2: 3 tab-separated fields"));
    assert!(error("total\t-3\n").starts_with("x.stats:1: '-3' for 'total'"));
    assert!(
        error("\ntotal\t3\ndist_freq/5-7/++\t1\n").starts_with("x.stats:3: 'dist_freq/5-7/++'")
    );
    assert!(error("dist_freq/0-1/+x\t1\n").starts_with("x.stats:1:"));
    assert!(error("chrom_freq/chr1\t1\n").starts_with("x.stats:1: 'chrom_freq/chr1'"));
    let counter =
        PairCounter::from_text("total\t3\nsummary/frac_cis\tnan\nother\tx\n", "x").unwrap();
    assert_eq!(counter.n_total(), 3);
}

#[test]
fn distance_bins_are_pairtools_log_bins() {
    let edges = dist_bin_edges(8);
    assert_eq!(edges.len(), 72);
    assert_eq!(edges[..12], [0, 1, 2, 3, 4, 6, 7, 10, 13, 18, 24, 32]);
    assert_eq!(*edges.last().unwrap(), 1_000_000_000);
    assert!(edges.windows(2).all(|w| w[0] < w[1]));
    // Every decade's edges are there.
    for k in 0..=9 {
        assert!(edges.contains(&10u64.pow(k)));
    }
    assert_eq!(
        dist_bin_edges(1),
        vec![
            0,
            1,
            10,
            100,
            1_000,
            10_000,
            100_000,
            1_000_000,
            10_000_000,
            100_000_000,
            1_000_000_000
        ]
    );
    assert!(PairCounter::with_dist_bins_per_decade(0).is_err());
}

#[test]
fn lambert_w_inverts_w_exp_w() {
    for i in 1..=1000 {
        let x = -1.0 + i as f64 / 1000.0 * 1.5;
        let w = lambert_w0(x * x.exp());
        // Next to the branch point (-1) W is ill-conditioned: sqrt of the rounding of z.
        let tolerance = if x < -0.99 { 1e-6 } else { 1e-12 };
        assert!(
            (w - x).abs() <= tolerance * x.abs().max(1.0),
            "x {x}: W {w}"
        );
    }
    assert_eq!(lambert_w0(0.0), 0.0);
    // At the f64 nearest -1/e scipy's iteration divides 0 by 0.
    assert!(lambert_w0(-(-1f64).exp()).is_nan());
}

#[test]
fn complexity_solves_the_duplication_equation() {
    for (n, d) in [
        (1000u64, 1u64),
        (1000, 100),
        (1000, 999),
        (168, 18),
        (10_000_000, 12_345),
        (50, 25),
    ] {
        let c = estimate_library_complexity(n, d).unwrap();
        let unique = c * (1.0 - (-(n as f64) / c).exp());
        assert!(
            ((unique - (n - d) as f64) / (n - d) as f64).abs() < 1e-8,
            "{n} {d}: {c}"
        );
    }
    assert_eq!(estimate_library_complexity(0, 0), None);
    assert_eq!(estimate_library_complexity(10, 10), None);
    assert!(estimate_library_complexity(10, 0).unwrap().is_nan());
}
