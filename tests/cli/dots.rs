//! `contactmap dots`: cooltools 0.7.1's dot caller on the yeast 10 kb map
//! (data/reference/dots, scripts/dots_reference.py), and the refusals of bad inputs.

use super::*;

/// Same rows and columns; numbers to 1e-9 relative.
fn assert_close_tables(ours: &Table, reference: &Table) {
    assert_eq!(ours.header, reference.header);
    assert_eq!(ours.rows.len(), reference.rows.len());
    for (a, b) in ours.rows.iter().zip(&reference.rows) {
        for (c, (x, y)) in a.iter().zip(b).enumerate() {
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(u), Ok(v)) => assert!(
                    u == v || (u - v).abs() <= 1e-9 * u.abs().max(v.abs()),
                    "{}: {x} vs {y}",
                    ours.header[c]
                ),
                _ => assert_eq!(x, y, "{}", ours.header[c]),
            }
        }
    }
}

#[test]
fn dots_equal_cooltools_on_yeast() {
    let dir = tempfile::tempdir().unwrap();
    let enriched = dir.path().join("enriched.tsv");
    let dots = run_ok(&[
        "dots",
        &data("yeast.10kb.cool"),
        "--enriched",
        &enriched.to_string_lossy(),
    ]);
    assert_close_tables(
        &parse_table(&dots),
        &reference_table("reference/dots/yeast_10kb.dots.tsv.gz"),
    );
    let enriched = std::fs::read_to_string(&enriched).unwrap();
    let reference = reference_table("reference/dots/yeast_10kb.enriched.tsv.gz");
    assert_close_tables(&parse_table(&enriched), &reference);
    // --no-cluster: the enriched pixels on the output
    let no_cluster = run_ok(&["dots", &data("yeast.10kb.cool"), "--no-cluster"]);
    assert_close_tables(&parse_table(&no_cluster), &reference);
    assert_eq!(reference.header.len(), 15);
}

#[test]
fn dots_refuse_bad_inputs_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("dots.tsv");
    let out_s = out.to_string_lossy().into_owned();
    // an unbalanced map
    let line = run_err(&[
        "dots",
        &data("hg19.GM12878-MboI.matrix.2000kb.cool"),
        "-o",
        &out_s,
    ]);
    assert!(line.contains("weight"), "{line}");
    // a bin size cooltools has no kernels for (10 Mb)
    let line = run_err(&["dots", &data("CN.mm9.10000kb.cool"), "-o", &out_s]);
    assert!(line.contains("--w and --p"), "{line}");
    // an expected of another resolution (its dist_bp are for 20 kb bins)
    let expected = run_ok(&["expected", &data("yeast.10kb.cool")]);
    let mut table = parse_table(&expected);
    let dist_bp = table.header.iter().position(|h| h == "dist_bp").unwrap();
    let mut text = table.header.join("\t") + "\n";
    for row in &mut table.rows {
        row[dist_bp] = (row[dist_bp].parse::<u64>().unwrap() * 2).to_string();
        text.push_str(&(row.join("\t") + "\n"));
    }
    let other = dir.path().join("exp20kb.tsv");
    std::fs::write(&other, text).unwrap();
    let line = run_err(&[
        "dots",
        &data("yeast.10kb.cool"),
        "--expected",
        &other.to_string_lossy(),
        "-o",
        &out_s,
    ]);
    assert!(line.contains("another resolution"), "{line}");
    // an expected without the view's regions
    let view = dir.path().join("arms.bed");
    std::fs::write(
        &view,
        "chrI\t0\t100000\tleft\nchrI\t100000\t230218\tright\n",
    )
    .unwrap();
    let line = run_err(&[
        "dots",
        &data("yeast.10kb.cool"),
        "--view",
        &view.to_string_lossy(),
        "--expected",
        &data("reference/numerics/dm6_100kb.expected_cis.raw.tsv.gz"),
        "--expected-column",
        "count.avg",
        "-o",
        &out_s,
    ]);
    assert!(line.contains("region 'left'"), "{line}");
    // a view outside its chromosome
    std::fs::write(&view, "chrI\t0\t900000000\n").unwrap();
    let line = run_err(&[
        "dots",
        &data("yeast.10kb.cool"),
        "--view",
        &view.to_string_lossy(),
        "-o",
        &out_s,
    ]);
    assert!(line.contains("arms.bed"), "{line}");
    // --w without --p, a bad FDR
    run_err(&["dots", &data("yeast.10kb.cool"), "--w", "5", "-o", &out_s]);
    let line = run_err(&["dots", &data("yeast.10kb.cool"), "--fdr", "2", "-o", &out_s]);
    assert!(line.contains("--fdr 2"), "{line}");
    assert!(!out.exists(), "no output after an error");
}

/// A view of whole chromosomes under other names: the same dots, named by the view.
#[test]
fn dots_on_a_named_view_name_their_regions() {
    let dir = tempfile::tempdir().unwrap();
    let chroms = run_ok(&["dump", "-t", "chroms", &data("yeast.10kb.cool")]);
    let bed: String = chroms
        .lines()
        .map(|l| {
            let (name, length) = l.split_once('\t').unwrap();
            format!("{name}\t0\t{length}\tv_{name}\n")
        })
        .collect();
    let view = dir.path().join("view.bed");
    std::fs::write(&view, bed).unwrap();
    let dots = parse_table(&run_ok(&[
        "dots",
        &data("yeast.10kb.cool"),
        "--view",
        &view.to_string_lossy(),
    ]));
    let mut reference = reference_table("reference/dots/yeast_10kb.dots.tsv.gz");
    for column in ["region", "region1", "region2"] {
        let c = reference.header.iter().position(|h| h == column).unwrap();
        for row in &mut reference.rows {
            row[c] = format!("v_{}", row[c]);
        }
    }
    assert_close_tables(&dots, &reference);
}

/// Nothing enriched (an FDR no pixel can meet): the header alone, in the column order of
/// cooltools' empty result.
#[test]
fn no_enriched_pixel_gives_cooltools_empty_table() {
    let out = run_ok(&["dots", &data("yeast.10kb.cool"), "--fdr", "1e-300"]);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 1, "{out}");
    assert!(
        lines[0].ends_with(
            "la_exp.lowleft.qval\tregion\tregion1\tregion2\tc_label\tc_size\tcstart1\tcstart2"
        ),
        "{out}"
    );
}
