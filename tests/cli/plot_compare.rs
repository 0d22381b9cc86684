//! `contactmap plot map --compare` (two maps split along the diagonal, or their log2 ratio) and
//! `contactmap plot hicrep` (the SCC table as a clustered heatmap), checked cell by cell against
//! values computed by hand and the order scipy's clustering gives.

#![allow(clippy::needless_range_loop)] // cells are indexed (i, j) as the maps are

use super::plot::{greys_linear, heatmap_rect, known_args, plot_png, plot_svg};
use super::*;

/// A 4-bin chromosome `c1` (10 bp bins) from upper-triangle pixels, as a BG2 table; the sizes
/// file beside it.
fn bg2(dir: &std::path::Path, name: &str, pixels: &[(usize, usize, f64)]) -> (String, String) {
    let sizes = write(dir, "c1.sizes", "c1\t40\n");
    let text: String = pixels
        .iter()
        .map(|(i, j, v)| {
            format!(
                "c1\t{}\t{}\tc1\t{}\t{}\t{v}\n",
                10 * i,
                10 * i + 10,
                10 * j,
                10 * j + 10
            )
        })
        .collect();
    (write(dir, name, &text), sizes)
}

/// The first map (total 55) and a second one (total 110, so --compare-mode total halves it).
fn two_maps(dir: &std::path::Path) -> (String, String, String) {
    let diagonal = |v: f64| (0..4).map(move |i| (i, i, v));
    let first: Vec<_> = diagonal(10.0)
        .chain([(0, 1, 5.0), (2, 3, 5.0), (0, 2, 2.5), (1, 3, 2.5)])
        .collect();
    let second: Vec<_> = diagonal(20.0)
        .chain([(0, 1, 5.0), (2, 3, 10.0), (0, 2, 10.0), (1, 3, 5.0)])
        .collect();
    let (a, sizes) = bg2(dir, "a.bg2", &first);
    let (b, _) = bg2(dir, "b.bg2", &second);
    (a, b, sizes)
}

/// The colour at the centre of cell `(i, j)` of a 4 x 4 map.
fn cell_colours(args: &[&str]) -> Vec<Vec<(u8, u8, u8)>> {
    let (x0, y0, width, height) = heatmap_rect(args);
    let image = plot_png(args);
    (0..4)
        .map(|i| {
            (0..4)
                .map(|j| {
                    let x = (x0 + (j as f64 + 0.5) * width / 4.0) as usize;
                    let y = (y0 + (i as f64 + 0.5) * height / 4.0) as usize;
                    image.at(x, y)
                })
                .collect()
        })
        .collect()
}

#[test]
fn split_map_shows_the_second_map_below_the_diagonal_at_the_first_ones_depth() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b, sizes) = two_maps(dir.path());
    let mut args = known_args(&a, &sizes, &["--linear", "--vmin", "0", "--vmax", "10"]);
    args.extend(["--compare", &b]);
    // upper and diagonal: the first map; lower: the second times 55 / 110
    let expected = |i: usize, j: usize| -> f64 {
        let first = [
            [10.0, 5.0, 2.5, 0.0],
            [5.0, 10.0, 0.0, 2.5],
            [2.5, 0.0, 10.0, 5.0],
            [0.0, 2.5, 5.0, 10.0],
        ];
        let second_halved = [
            [10.0, 2.5, 5.0, 0.0],
            [2.5, 10.0, 0.0, 2.5],
            [5.0, 0.0, 10.0, 5.0],
            [0.0, 2.5, 5.0, 10.0],
        ];
        if j >= i {
            first[i][j]
        } else {
            second_halved[i][j]
        }
    };
    let colours = cell_colours(&args);
    for i in 0..4 {
        for j in 0..4 {
            let grey = greys_linear(expected(i, j));
            assert_eq!(colours[i][j], (grey, grey, grey), "cell ({i}, {j})");
        }
    }
    let svg = plot_svg(&args);
    assert!(svg.contains("a (upper) vs b (lower)"), "default title");
}

#[test]
fn log2_ratio_is_centred_at_zero() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b, sizes) = two_maps(dir.path());
    let mut args = known_args(&a, &sizes, &["--compare", &b, "--ratio"]);
    let colours = cell_colours(&args);
    // log2(first / (second / 2)): (0, 1) 1, (0, 2) -1, (1, 3) and (2, 3) 0, the diagonal 0;
    // (1, 2) and (0, 3) have no contacts: NaN (lightgrey). Default limits: +-1 (symmetric).
    let grey = |v: f64| greys_linear(5.0 * (v + 1.0)); // -1..1 onto the 0..10 references
    let lightgrey = (211, 211, 211);
    let expected = [
        [Some(0.0), Some(1.0), Some(-1.0), None],
        [Some(1.0), Some(0.0), None, Some(0.0)],
        [Some(-1.0), None, Some(0.0), Some(0.0)],
        [None, Some(0.0), Some(0.0), Some(0.0)],
    ];
    for i in 0..4 {
        for j in 0..4 {
            let want = expected[i][j].map_or(lightgrey, |v| (grey(v), grey(v), grey(v)));
            assert_eq!(colours[i][j], want, "cell ({i}, {j})");
        }
    }
    let svg = plot_svg(&args);
    assert!(svg.contains("log2(a / b)"), "colour bar label");
    // Each map over its own expected (--ignore-diags 0): per diagonal, first 10, 10/3, 2.5, 0;
    // second 20, 5, 7.5, 0. So (0, 1) and (1, 3) are log2(1.5) = 0.585, (2, 3) and (0, 2)
    // log2(0.75) = -0.415, the diagonal 0, (1, 2) and (0, 3) NaN (0 / 0). Limits just inside
    // +-0.415 / 0.585 put them on the ends of the scale.
    args.extend([
        "--compare-mode",
        "expected",
        "--ignore-diags",
        "0",
        "--vmin=-0.41",
        "--vmax=0.58",
    ]);
    let colours = cell_colours(&args);
    let (black, white) = ((0, 0, 0), (255, 255, 255));
    for (i, j, want) in [
        (0, 1, black),
        (1, 3, black),
        (2, 3, white),
        (0, 2, white),
        (1, 2, lightgrey),
        (0, 3, lightgrey),
    ] {
        assert_eq!(colours[i][j], want, "cell ({i}, {j})");
        assert_eq!(colours[j][i], want, "cell ({j}, {i})");
    }
}

#[test]
fn bad_comparisons_are_refused_in_one_line_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b, sizes) = two_maps(dir.path());
    let out = dir.path().join("x.png");
    let out = out.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--compare", &b, "--triangle"], "--ratio"),
        (vec!["--compare", &b, "--region2", "c1:0-20"], "--region2"),
        (vec!["--ratio"], "--compare"),
        (vec!["--compare", &b, "--oe"], "--oe"),
    ];
    for (extra, needle) in cases {
        let mut args = known_args(&a, &sizes, &extra);
        args.extend(["-o", out]);
        let message = run_err(&args);
        assert!(message.contains(needle), "{extra:?}: {message}");
        assert!(!std::path::Path::new(out).exists());
    }
    // a second map on other bins
    let yeast = data("yeast.10kb.cool");
    let mut args = known_args(&a, &sizes, &["--compare", &yeast]);
    args.extend(["-o", out]);
    let message = run_err(&args);
    assert!(message.contains("bins differ"), "{message}");
    assert!(!std::path::Path::new(out).exists());
}

/// Six samples at distances `1 - SCC` whose average-linkage tree scipy 1.x gives with the leaves
/// in the order 5, 0, 2, 1, 3, 4 (`src/compare/cluster.rs` holds the same case against
/// `linkage` itself).
const DISTANCES: [[f64; 6]; 6] = [
    [0.0, 0.794599, 0.196499, 0.400881, 0.660508, 0.414414],
    [0.794599, 0.0, 0.72268, 0.53129, 0.473214, 0.415232],
    [0.196499, 0.72268, 0.0, 0.47213, 0.715699, 0.308641],
    [0.400881, 0.53129, 0.47213, 0.0, 0.259645, 0.367645],
    [0.660508, 0.473214, 0.715699, 0.259645, 0.0, 0.529483],
    [0.414414, 0.415232, 0.308641, 0.367645, 0.529483, 0.0],
];

fn scc_table(dir: &std::path::Path, skip: Option<(usize, usize)>) -> String {
    let mut text = String::from("sample1\tsample2\tchrom\tlength\tscc\n");
    for a in 0..6 {
        for b in a + 1..6 {
            if skip == Some((a, b)) {
                continue;
            }
            let scc = 1.0 - DISTANCES[a][b];
            text.push_str(&format!("s{a}\ts{b}\tchrX\t100\t{}\n", scc - 0.01));
            text.push_str(&format!("s{a}\ts{b}\tgenome\t200\t{scc}\n"));
        }
    }
    write(dir, "scc.tsv", &text)
}

#[test]
fn hicrep_heatmap_orders_samples_as_scipys_average_linkage() {
    let dir = tempfile::tempdir().unwrap();
    let table = scc_table(dir.path(), None);
    let svg = plot_svg(&["plot", "hicrep", &table]);
    let position = |k: usize| svg.find(&format!(">s{k}<")).unwrap();
    let order = [5, 0, 2, 1, 3, 4];
    assert!(
        order.windows(2).all(|w| position(w[0]) < position(w[1])),
        "rows in scipy's leaf order"
    );
    // the SCCs in the cells (s0, s2: 1 - 0.196499), the tree, the colour bar's label
    assert!(svg.contains(">0.804<") && svg.contains("<polyline"));
    assert!(svg.contains("SCC (genome-wide)"));
    // --no-cluster keeps the table's order; --chrom draws that chromosome's rows
    let plain = plot_svg(&["plot", "hicrep", &table, "--no-cluster", "--chrom", "chrX"]);
    let at = |k: usize| plain.find(&format!(">s{k}<")).unwrap();
    assert!((0..5).all(|k| at(k) < at(k + 1)));
    assert!(!plain.contains("<polyline") && plain.contains(">0.794<"));
    let image = plot_png(&["plot", "hicrep", &table, "--width", "4"]);
    assert_eq!(image.width, 400);
}

#[test]
fn incomplete_scc_tables_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("h.png");
    let out = out.to_str().unwrap();
    let table = scc_table(dir.path(), Some((1, 4)));
    let message = run_err(&["plot", "hicrep", &table, "-o", out]);
    assert!(message.contains("no SCC for s1 and s4"), "{message}");
    let full = scc_table(dir.path(), None);
    let message = run_err(&["plot", "hicrep", &full, "--chrom", "chrY", "-o", out]);
    assert!(
        message.contains("no row of chromosome 'chrY' (the table has chrX, genome)"),
        "{message}"
    );
    let other = write(dir.path(), "other.tsv", "a\tb\n1\t2\n");
    let message = run_err(&["plot", "hicrep", &other, "-o", out]);
    assert!(message.contains("sample1"), "{message}");
    assert!(!std::path::Path::new(out).exists());
}
