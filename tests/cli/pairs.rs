//! `contactmap pairs`: every subcommand's output compared with pairtools 1.1.2's on the same
//! simulated BAM (`data/pairs/`, made by `scripts/pairs_fixture.py`; the references by
//! `scripts/pairs_references.sh`), and bad inputs refused with one line and no output.

use std::io::Read;

use super::*;

/// The records of a pairs file (plain or gzip): its lines after the header.
fn body(path: &str) -> Vec<String> {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut text = String::new();
    if bytes.starts_with(&[0x1f, 0x8b]) {
        flate2::read::MultiGzDecoder::new(&bytes[..])
            .read_to_string(&mut text)
            .unwrap();
    } else {
        text = String::from_utf8(bytes).unwrap();
    }
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .map(str::to_string)
        .collect()
}

/// The header lines of a pairs file, those that name a program left out.
fn header(path: &str) -> Vec<String> {
    let bytes = std::fs::read(path).unwrap();
    let mut text = String::new();
    flate2::read::MultiGzDecoder::new(&bytes[..])
        .read_to_string(&mut text)
        .unwrap_or_else(|_| {
            text = String::from_utf8(bytes.clone()).unwrap();
            0
        });
    text.lines()
        .filter(|l| l.starts_with('#') && !l.starts_with("#samheader: @PG"))
        .map(str::to_string)
        .collect()
}

fn reference(name: &str) -> String {
    data(&format!("pairs/reference/{name}"))
}

fn same_rows(ours: &str, theirs: &str) {
    let (a, b) = (body(ours), body(&reference(theirs)));
    assert_eq!(a.len(), b.len(), "{theirs}: row counts");
    for (i, (x, y)) in a.iter().zip(&b).enumerate() {
        assert_eq!(x, y, "{theirs}: row {}", i + 1);
    }
}

fn parse_args<'a>(out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "pairs",
        "parse",
        Box::leak(data("pairs/sim.bam").into_boxed_str()),
        "-c",
        Box::leak(data("pairs/sim.chrom.sizes").into_boxed_str()),
        "--assembly",
        "sim",
        "-o",
        out,
    ];
    args.extend_from_slice(extra);
    args
}

#[test]
fn parse_equals_pairtools_for_every_walks_policy() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let five_unique = path("5unique.pairs.gz");
    run_ok(&parse_args(&five_unique, &[]));
    same_rows(&five_unique, "sim.5unique.pairs.gz");
    // The header is pairtools' but for the @PG line of the program.
    assert_eq!(
        header(&five_unique),
        header(&reference("sim.5unique.pairs.gz"))
    );
    for policy in ["5any", "3unique", "3any", "mask"] {
        let out = path(&format!("{policy}.pairs"));
        run_ok(&parse_args(
            &out,
            &["--walks-policy", policy, "--drop-readid"],
        ));
        same_rows(&out, &format!("sim.{policy}.pairs.gz"));
    }
    let all = path("all.pairs");
    run_ok(&parse_args(
        &all,
        &["--walks-policy", "all", "--add-pair-index", "--drop-readid"],
    ));
    same_rows(&all, "sim.all.pairs.gz");
    let no_flip = path("noflip.pairs");
    run_ok(&parse_args(&no_flip, &["--no-flip", "--drop-readid"]));
    same_rows(&no_flip, "sim.5unique.noflip.pairs.gz");
}

#[test]
fn parse_extra_columns_and_statistics_equal_pairtools() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("full.pairs").to_string_lossy().into_owned();
    let stats = dir.path().join("full.stats").to_string_lossy().into_owned();
    run_ok(&parse_args(
        &out,
        &[
            "--add-columns",
            "mapq,pos5,pos3,cigar,read_len,matched_bp,algn_ref_span,algn_read_span,dist_to_5,\
             dist_to_3,mismatches",
            "--output-stats",
            &stats,
        ],
    ));
    same_rows(&out, "sim.5unique.full.pairs.gz");
    assert_eq!(
        std::fs::read_to_string(&stats)
            .unwrap()
            .lines()
            .collect::<Vec<_>>(),
        body(&reference("sim.5unique.full.stats.gz"))
    );
}

#[test]
fn sort_equals_pairtools_in_memory_and_through_runs_on_disk() {
    let dir = tempfile::tempdir().unwrap();
    let input = reference("sim.5unique.pairs.gz");
    let sorted = dir.path().join("s.pairs.gz").to_string_lossy().into_owned();
    run_ok(&["pairs", "sort", &input, "-o", &sorted]);
    same_rows(&sorted, "sim.5unique.sorted.pairs.gz");
    assert!(header(&sorted).contains(&"#sorted: chr1-chr2-pos1-pos2".to_string()));
    // BGZF: block gzip with its end-of-file block.
    let bytes = std::fs::read(&sorted).unwrap();
    assert_eq!(&bytes[12..14], b"BC");
    // A 64 KiB cap writes many runs; the temporary folder is left empty.
    let tmp = tempfile::tempdir().unwrap();
    let spilled = dir.path().join("s2.pairs").to_string_lossy().into_owned();
    let tmp_path = tmp.path().to_string_lossy().into_owned();
    run_ok(&[
        "pairs", "sort", &input, "-o", &spilled, "--memory", "64K", "--tmpdir", &tmp_path,
    ]);
    same_rows(&spilled, "sim.5unique.sorted.pairs.gz");
    assert_eq!(std::fs::read_dir(tmp.path()).unwrap().count(), 0);
}

#[test]
fn dedup_equals_pairtools_outputs_and_statistics() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let sorted = reference("sim.5unique.sorted.pairs.gz");
    let (nodups, dups, unmapped, stats) = (
        path("nodups.pairs.gz"),
        path("dups.pairs.gz"),
        path("unmapped.pairs.gz"),
        path("dedup.stats"),
    );
    run_ok(&[
        "pairs",
        "dedup",
        &sorted,
        "-o",
        &nodups,
        "--output-dups",
        &dups,
        "--output-unmapped",
        &unmapped,
        "--output-stats",
        &stats,
    ]);
    same_rows(&nodups, "sim.nodups.pairs.gz");
    same_rows(&dups, "sim.dups.pairs.gz");
    same_rows(&unmapped, "sim.unmapped.pairs.gz");
    assert_eq!(body(&stats), body(&reference("sim.dedup.stats.gz")));
    let (sum_dups, sum_stats) = (path("sum.dups.pairs"), path("sum.stats"));
    run_ok(&[
        "pairs",
        "dedup",
        &sorted,
        "--method",
        "sum",
        "-o",
        &path("sum.nodups.pairs"),
        "--output-dups",
        &sum_dups,
        "--output-stats",
        &sum_stats,
    ]);
    same_rows(&sum_dups, "sim.sum.dups.pairs.gz");
    assert_eq!(body(&sum_stats), body(&reference("sim.sum.dedup.stats.gz")));
    // The compression level changes the bytes, never the rows; libdeflate's levels are 0-12.
    let sizes: Vec<u64> = ["1", "12"]
        .iter()
        .map(|level| {
            let out = path(&format!("level{level}.pairs.gz"));
            run_ok(&[
                "pairs",
                "dedup",
                &sorted,
                "--compress-level",
                level,
                "-o",
                &out,
            ]);
            same_rows(&out, "sim.nodups.pairs.gz");
            std::fs::metadata(&out).unwrap().len()
        })
        .collect();
    assert!(
        sizes[0] > sizes[1],
        "level 1 {} B, level 12 {} B",
        sizes[0],
        sizes[1]
    );
    let out = dir.path().join("level13.pairs.gz");
    let line = refused(
        &[
            "pairs",
            "dedup",
            &sorted,
            "--compress-level",
            "13",
            "-o",
            &out.to_string_lossy(),
        ],
        &out,
    );
    assert!(line.contains("--compress-level"), "{line}");
}

#[test]
fn stats_and_merge_equal_pairtools() {
    let dir = tempfile::tempdir().unwrap();
    let stats = run_ok(&["pairs", "stats", &reference("sim.5unique.pairs.gz")]);
    assert_eq!(
        stats.lines().collect::<Vec<_>>(),
        body(&reference("sim.5unique.stats.gz"))
    );
    // stats --merge: pairtools lists the merged pair types in Python's string-hash order (a set
    // union; PYTHONHASHSEED=0 for the reference), so that block is compared as a set.
    let merged_stats = run_ok(&[
        "pairs",
        "stats",
        "--merge",
        &reference("sim.5unique.stats.gz"),
        &reference("sim.dedup.stats.gz"),
    ]);
    let pair_types_as_a_set = |lines: Vec<String>| {
        let (mut types, mut others): (Vec<_>, Vec<_>) = lines
            .into_iter()
            .enumerate()
            .partition(|(_, l)| l.starts_with("pair_types/"));
        let first = types[0].0;
        assert!(types.iter().enumerate().all(|(i, (j, _))| *j == first + i));
        types.sort_by(|a, b| a.1.cmp(&b.1));
        others.splice(first..first, types);
        others.into_iter().map(|(_, l)| l).collect::<Vec<_>>()
    };
    let expected = body(&reference("sim.merged.stats.gz"));
    assert!(expected.iter().any(|l| l.starts_with("pair_types/DD\t")));
    assert_eq!(
        pair_types_as_a_set(merged_stats.lines().map(str::to_string).collect()),
        pair_types_as_a_set(expected)
    );
    let merged = dir.path().join("m.pairs").to_string_lossy().into_owned();
    run_ok(&[
        "pairs",
        "merge",
        &reference("sim.half1.sorted.pairs.gz"),
        &reference("sim.half2.sorted.pairs.gz"),
        "-o",
        &merged,
    ]);
    same_rows(&merged, "sim.merged.pairs.gz");
}

#[test]
fn select_equals_pairtools() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("uu.pairs").to_string_lossy().into_owned();
    run_ok(&[
        "pairs",
        "select",
        r#"(pair_type=="UU") or (pair_type=="UR") or (pair_type=="RU")"#,
        &reference("sim.5any.pairs.gz"),
        "-o",
        &out,
    ]);
    same_rows(&out, "sim.select_uu_ur_ru.pairs.gz");
    let trans = run_ok(&[
        "pairs",
        "select",
        "(chrom1!=chrom2) and (mapq1>=30) and (mapq2>=30)",
        &reference("sim.5unique.full.pairs.gz"),
    ]);
    let rows: Vec<String> = trans
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(str::to_string)
        .collect();
    assert_eq!(rows, body(&reference("sim.select_trans_mapq30.pairs.gz")));
}

#[test]
fn a_bam_piped_to_a_cooler_equals_pairtools_and_cooler_cload() {
    // parse | sort | dedup | convert, each reading standard input.
    let dir = tempfile::tempdir().unwrap();
    let cool = dir
        .path()
        .join("sim.1000.cool")
        .to_string_lossy()
        .into_owned();
    let binary = env!("CARGO_BIN_EXE_contactmap");
    let script = format!(
        "set -o pipefail; '{binary}' pairs parse '{bam}' -c '{sizes}' | '{binary}' pairs sort \
         | '{binary}' pairs dedup | '{binary}' convert - '{cool}' --bin-size 1000 --format pairs",
        bam = data("pairs/sim.bam"),
        sizes = data("pairs/sim.chrom.sizes"),
    );
    let status = Command::new("bash").args(["-c", &script]).status().unwrap();
    assert!(status.success());
    let pixels = run_ok(&["dump", &cool]);
    assert_eq!(
        pixels.lines().collect::<Vec<_>>(),
        body(&reference("sim.1000.pixels.tsv.gz"))
    );
}

/// Run a failing command: exit 2, one line, and no file at `out`.
fn refused(args: &[&str], out: &std::path::Path) -> String {
    let line = run_err(args);
    assert!(!out.exists(), "{} was left behind", out.display());
    line
}

#[test]
fn bad_alignments_are_refused_with_one_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.pairs.gz");
    let out_text = out.to_string_lossy().into_owned();
    let sizes = data("pairs/sim.chrom.sizes");
    let bam = std::fs::read(data("pairs/sim.bam")).unwrap();
    // A BAM cut inside a block, and one cut at a block's end (records cut short).
    let cut = dir.path().join("cut.bam");
    std::fs::write(&cut, &bam[..bam.len() / 2]).unwrap();
    let line = refused(
        &[
            "pairs",
            "parse",
            &cut.to_string_lossy(),
            "-c",
            &sizes,
            "-o",
            &out_text,
        ],
        &out,
    );
    assert!(line.contains("cut.bam"), "{line}");
    // SAM with a record of too few fields.
    let sam = write(
        dir.path(),
        "short.sam",
        "@SQ\tSN:chr1\tLN:300000\nr1\t65\tchr1\t100\n",
    );
    let sizes_chr1 = write(dir.path(), "chr1.sizes", "chr1\t300000\n");
    let line = refused(
        &["pairs", "parse", &sam, "-c", &sizes_chr1, "-o", &out_text],
        &out,
    );
    assert!(line.contains("short.sam:2:"), "{line}");
    // A chromosome of the BAM missing from the sizes, and a length that differs.
    let line = refused(
        &[
            "pairs",
            "parse",
            &data("pairs/sim.bam"),
            "-c",
            &sizes_chr1,
            "-o",
            &out_text,
        ],
        &out,
    );
    assert!(
        line.contains("not listed") && line.contains("chr2"),
        "{line}"
    );
    let other = write(
        dir.path(),
        "other.sizes",
        "chr1\t300001\nchr2\t1\nchr3\t1\nchrX\t1\n",
    );
    let line = refused(
        &[
            "pairs",
            "parse",
            &data("pairs/sim.bam"),
            "-c",
            &other,
            "-o",
            &out_text,
        ],
        &out,
    );
    assert!(line.contains("different assemblies"), "{line}");
    // Coordinate-sorted input.
    let sorted = write(
        dir.path(),
        "sorted.sam",
        "@HD\tVN:1.6\tSO:coordinate\n@SQ\tSN:chr1\tLN:300000\n",
    );
    let line = refused(
        &[
            "pairs",
            "parse",
            &sorted,
            "-c",
            &sizes_chr1,
            "-o",
            &out_text,
        ],
        &out,
    );
    assert!(line.contains("samtools collate"), "{line}");
}

#[test]
fn bad_pairs_are_refused_with_their_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.pairs.gz");
    let out_text = out.to_string_lossy().into_owned();
    let mut rows = body(&reference("sim.5unique.sorted.pairs.gz"));
    let head = "## pairs format v1.0.0\n#sorted: chr1-chr2-pos1-pos2\n#chromsize: chr1 300000\n\
                #columns: readID chrom1 pos1 chrom2 pos2 strand1 strand2 pair_type\n";
    // Two records swapped: row 250 (line 255) now holds a later record, so line 256 is the
    // first that comes before the one above it.
    assert!(rows.len() > 1000);
    rows.swap(250, 1000);
    let unsorted = write(
        dir.path(),
        "unsorted.pairs",
        &format!("{head}{}\n", rows.join("\n")),
    );
    let line = refused(&["pairs", "dedup", &unsorted, "-o", &out_text], &out);
    assert!(
        line.contains("unsorted.pairs:256:") && line.contains("not sorted"),
        "{line}"
    );
    // A line with too few fields.
    let short = write(
        dir.path(),
        "short.pairs",
        &format!("{head}.\tchr1\t5\tchr1\n"),
    );
    for command in ["sort", "dedup", "stats"] {
        let line = refused(&["pairs", command, &short, "-o", &out_text], &out);
        assert!(line.contains("short.pairs:5:"), "{command}: {line}");
    }
    // Files of different chromosomes are not merged.
    let other = write(
        dir.path(),
        "other.pairs",
        "## pairs format v1.0.0\n#chromsize: chr9 10\n#columns: readID chrom1 pos1 chrom2 pos2 \
         strand1 strand2 pair_type\n",
    );
    let sorted = reference("sim.5unique.sorted.pairs.gz");
    let line = refused(&["pairs", "merge", &sorted, &other, "-o", &out_text], &out);
    assert!(line.contains("different chromosomes"), "{line}");
}
