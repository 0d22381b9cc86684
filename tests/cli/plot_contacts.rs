//! `contactmap plot contacts`: the SVG parsed element by element and the PNG decoded pixel by
//! pixel, against `contactmap contacts` (the true contacts), `contactmap score contacts` (the
//! counts and the curve) and published reference counts (`data/protein/README.md`).

use std::collections::BTreeSet;

use crate::plot::{Image, decode_png, plot_fails, plot_svg};
use crate::{data, run, run_ok};

fn protein(name: &str) -> String {
    data(&format!("protein/{name}"))
}

/// ConKit's colours (`conkit.plot.tools.ColorDefinitions` 0.13.3): MATCH, MISMATCH, STRUCTURAL.
const TP: (u8, u8, u8) = (0x0f, 0x0b, 0x2c);
const FP: (u8, u8, u8) = (0xdc, 0x48, 0x69);
const GREY: (u8, u8, u8) = (0xd8, 0xd6, 0xd6);

/// The toxd arguments with `extra` options (CCMpred matrix, FASTA, the PDB).
fn toxd_args(extra: &[&'static str]) -> Vec<String> {
    let mut args: Vec<String> = [
        "plot".to_string(),
        "contacts".into(),
        "--structure".into(),
        protein("toxd/toxd.pdb.gz"),
        "--fasta".into(),
        protein("toxd/toxd.fasta"),
        protein("toxd/toxd.mat.gz"),
    ]
    .to_vec();
    args.extend(extra.iter().map(|s| s.to_string()));
    args
}

fn strs(args: &[String]) -> Vec<&str> {
    args.iter().map(String::as_str).collect()
}

/// A parsed figure: the map frame, cell size, and the marks by residue pair.
struct Figure {
    /// Left, top and side of the map in pixels.
    map: (f64, f64, f64),
    /// First residue of the axes.
    first: i32,
    /// Pixels per residue.
    cell: f64,
    /// Grey cells `(row, col)`.
    grey: Vec<(i32, i32)>,
    /// Markers `(triangle, class, row, col, cx, cy)`.
    markers: Vec<(String, String, i32, i32, f64, f64)>,
    /// The curve panel's frame `(x, y, width, height)`.
    curve_frame: (f64, f64, f64, f64),
    /// The points of each curve's polyline.
    curves: Vec<Vec<(f64, f64)>>,
}

fn number(node: &roxmltree::Node, attribute: &str) -> f64 {
    node.attribute(attribute)
        .unwrap_or_else(|| panic!("<{}> without {attribute}", node.tag_name().name()))
        .parse()
        .unwrap()
}

fn class_of<'a>(node: &roxmltree::Node<'a, 'a>) -> Option<&'a str> {
    node.attribute("class")
}

/// The frame rectangle among the children of `group` (no fill, a stroke).
fn frame_in(group: roxmltree::Node) -> (f64, f64, f64, f64) {
    let frame = group
        .children()
        .find(|n| n.has_tag_name("rect") && n.attribute("fill") == Some("none"))
        .expect("a frame");
    (
        number(&frame, "x"),
        number(&frame, "y"),
        number(&frame, "width"),
        number(&frame, "height"),
    )
}

/// Parse the SVG of a toxd-like figure whose axes start at residue `first`.
fn parse(svg: &str, first: i32, last: i32) -> Figure {
    let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
    let root = doc.root_element();
    // The map frame: the square frame drawn at the top level.
    let map_frame = root
        .children()
        .filter(|n| n.has_tag_name("rect") && n.attribute("fill") == Some("none"))
        .map(|n| {
            (
                number(&n, "x"),
                number(&n, "y"),
                number(&n, "width"),
                number(&n, "height"),
            )
        })
        .find(|r| (r.2 - r.3).abs() < 0.01)
        .expect("the square map frame");
    let cell = map_frame.2 / f64::from(last - first + 1);
    let residue = |offset: f64| -> i32 {
        let at = offset / cell;
        let index = at.floor();
        assert!(
            at - index > 0.05 && at - index < 0.95,
            "{at} not inside a cell"
        );
        first + index as i32
    };
    let group = |class: &str| {
        doc.descendants()
            .find(|n| class_of(n) == Some(class))
            .unwrap_or_else(|| panic!("no group {class}"))
    };
    let grey = group("true-contacts")
        .children()
        .filter(|n| n.has_tag_name("rect"))
        .map(|n| {
            let (x, y) = (number(&n, "x"), number(&n, "y"));
            let (w, h) = (number(&n, "width"), number(&n, "height"));
            // Edges on whole pixels: within a pixel of the exact cell size.
            assert!(
                (w - cell).abs() < 1.0 && (h - cell).abs() < 1.0,
                "{w} x {h}"
            );
            assert!(x.fract() == 0.0 && y.fract() == 0.0, "({x}, {y})");
            (
                residue(y + h / 2.0 - map_frame.1),
                residue(x + w / 2.0 - map_frame.0),
            )
        })
        .collect();
    let mut markers = Vec::new();
    for triangle in ["upper", "lower"] {
        let Some(layer) = doc.descendants().find(|n| class_of(n) == Some(triangle)) else {
            continue;
        };
        for marks in layer.children().filter(|n| n.is_element()) {
            let class = class_of(&marks).unwrap_or_default().to_string();
            for circle in marks.children().filter(|n| n.has_tag_name("circle")) {
                let (cx, cy) = (number(&circle, "cx"), number(&circle, "cy"));
                markers.push((
                    triangle.to_string(),
                    class.clone(),
                    residue(cy - map_frame.1),
                    residue(cx - map_frame.0),
                    cx,
                    cy,
                ));
            }
        }
    }
    let curve_group = group("precision-curve");
    let curves = (1..=2)
        .filter_map(|index| {
            let class = format!("curve-{index}");
            let g = curve_group
                .descendants()
                .find(|n| class_of(n) == Some(class.as_str()))?;
            let line = g.children().find(|n| n.has_tag_name("polyline"))?;
            Some(
                line.attribute("points")
                    .unwrap()
                    .split_whitespace()
                    .map(|p| {
                        let (x, y) = p.split_once(',').unwrap();
                        (x.parse().unwrap(), y.parse().unwrap())
                    })
                    .collect(),
            )
        })
        .collect();
    Figure {
        map: (map_frame.0, map_frame.1, map_frame.2),
        first,
        cell,
        grey,
        markers,
        curve_frame: frame_in(curve_group),
        curves,
    }
}

/// The rows `i j` of `contactmap contacts ARGS`.
fn true_contacts(args: &[&str]) -> BTreeSet<(i32, i32)> {
    run_ok(&[&["contacts"][..], args].concat())
        .lines()
        .filter(|line| line.starts_with(|c: char| c.is_ascii_digit()))
        .map(|line| {
            let mut fields = line.split_whitespace();
            let i = fields.next().unwrap().parse().unwrap();
            let j = fields.next().unwrap().parse().unwrap();
            (i, j)
        })
        .collect()
}

/// `(tp, n_scored)` of the one row of `score contacts ... --tsv`.
fn score_row(args: &[&str]) -> (usize, usize) {
    let text = run_ok(&[&["score", "contacts"][..], args, &["--tsv"]].concat());
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2, "{text}");
    let header: Vec<&str> = lines[0].split('\t').collect();
    let row: Vec<&str> = lines[1].split('\t').collect();
    let column = |name: &str| -> usize {
        row[header.iter().position(|h| *h == name).unwrap()]
            .parse()
            .unwrap()
    };
    (column("tp"), column("n_scored"))
}

fn count(figure: &Figure, triangle: &str, class: &str) -> usize {
    figure
        .markers
        .iter()
        .filter(|m| m.0 == triangle && m.1 == class)
        .count()
}

#[test]
fn markers_count_the_true_and_false_positives_of_score_contacts() {
    let pdb = protein("toxd/toxd.pdb.gz");
    let fasta = protein("toxd/toxd.fasta");
    let mat = protein("toxd/toxd.mat.gz");
    let truth = true_contacts(&[&pdb, "--fasta", &fasta]);
    for (min_sep, top, reference) in [
        // Long range, top L: "method P" of data/protein/README.md, 22 / 59.
        ("24", "L", Some((22, 59))),
        // All ranges, top L: ConKit 0.13.3 (scripts/figures/conkit_cmap.py) draws 34 / 59.
        ("6", "L", Some((34, 59))),
        ("6", "L/5", None),
        ("12", "0.5L", None),
        ("6", "30", None),
        // NC: k = the 115 true contacts; 5000: more than the 1378 available pairs, all drawn.
        ("6", "NC", None),
        ("6", "5000", Some((115, 1378))),
    ] {
        let args = toxd_args(&["--min-sep", min_sep, "--top", top]);
        let svg = plot_svg(&strs(&args));
        let figure = parse(&svg, 1, 59);
        let (tp, n_scored) = score_row(&[
            "--structure",
            &pdb,
            &mat,
            "--fasta",
            &fasta,
            "--min-sep",
            min_sep,
            "--top",
            top,
        ]);
        let (n_tp, n_fp) = (count(&figure, "upper", "tp"), count(&figure, "upper", "fp"));
        assert_eq!(
            (n_tp, n_tp + n_fp),
            (tp, n_scored),
            "--min-sep {min_sep} --top {top}"
        );
        if let Some(reference) = reference {
            assert_eq!(
                (n_tp, n_tp + n_fp),
                reference,
                "--min-sep {min_sep} --top {top}"
            );
        }
        assert_eq!(
            count(&figure, "lower", "tp") + count(&figure, "lower", "fp"),
            0
        );
        // Every marker sits on its pair: TP on a true contact, FP off one, in the upper
        // triangle, at least --min-sep apart.
        let min_sep: i32 = min_sep.parse().unwrap();
        for (_, class, row, col, _, _) in &figure.markers {
            assert!(col - row >= min_sep, "({row}, {col})");
            assert_eq!(
                truth.contains(&(*row, *col)),
                class == "tp",
                "({row}, {col}) is {class}"
            );
        }
        let legend = format!("TP {n_tp}</text>");
        assert!(svg.contains(&legend), "no '{legend}' in the legend");
        let precision = format!("precision {:.3}", n_tp as f64 / (n_tp + n_fp) as f64);
        assert!(svg.contains(&precision), "no '{precision}' in the legend");
    }
}

#[test]
fn grey_cells_are_the_true_contacts_in_both_triangles() {
    let pdb = protein("toxd/toxd.pdb.gz");
    for (min_sep, expected) in [("6", 115), ("24", 57)] {
        let truth = true_contacts(&[&pdb, "--min-sep", min_sep]);
        // data/protein/README.md: 115 contacts at >= 6, 57 at >= 24.
        assert_eq!(truth.len(), expected);
        let svg = plot_svg(&strs(&toxd_args(&["--min-sep", min_sep])));
        let figure = parse(&svg, 1, 59);
        assert_eq!(figure.grey.len(), 2 * truth.len());
        let cells: BTreeSet<(i32, i32)> = figure.grey.iter().copied().collect();
        let both: BTreeSet<(i32, i32)> =
            truth.iter().flat_map(|&(i, j)| [(i, j), (j, i)]).collect();
        assert_eq!(cells, both);
    }
}

#[test]
fn png_pixels_show_the_marker_and_contact_colours() {
    let args = toxd_args(&["--dpi", "100"]);
    let figure = parse(&plot_svg(&strs(&args)), 1, 59);
    let png = run(&[strs(&args), vec!["-o", "-", "--to", "png"]].concat());
    assert!(png.status.success());
    let image: Image = decode_png(&png.stdout);
    let at = |x: f64, y: f64| image.at(x.floor() as usize, y.floor() as usize);
    let centre = |row: i32, col: i32| {
        (
            figure.map.0 + (f64::from(col - figure.first) + 0.5) * figure.cell,
            figure.map.1 + (f64::from(row - figure.first) + 0.5) * figure.cell,
        )
    };
    let (mut n_tp, mut n_fp) = (0, 0);
    for (_, class, row, col, cx, cy) in &figure.markers {
        let (x, y) = centre(*row, *col);
        assert!((x - cx).abs() < 0.02 && (y - cy).abs() < 0.02);
        match class.as_str() {
            "tp" => {
                assert_eq!(at(x, y), TP, "TP ({row}, {col})");
                n_tp += 1;
            }
            "fp" => {
                assert_eq!(at(x, y), FP, "FP ({row}, {col})");
                n_fp += 1;
            }
            other => panic!("unexpected marker class {other}"),
        }
    }
    assert!(n_tp > 0 && n_fp > 0);
    // A true contact not predicted: with one prediction, the lower triangle shows the grey
    // cells alone; a pair neither true nor predicted is white.
    let pdb = protein("toxd/toxd.pdb.gz");
    let truth = true_contacts(&[&pdb]);
    let &(i, j) = truth.iter().next().unwrap();
    let (x, y) = centre(j, i);
    assert_eq!(at(x, y), GREY, "true contact ({i}, {j}) below the diagonal");
    let predicted: BTreeSet<(i32, i32)> = figure.markers.iter().map(|m| (m.2, m.3)).collect();
    let empty = (1..=59)
        .flat_map(|i| (i + 6..=59).map(move |j| (i, j)))
        .find(|pair| !truth.contains(pair) && !predicted.contains(pair))
        .unwrap();
    let (x, y) = centre(empty.0, empty.1);
    assert_eq!(at(x, y), (255, 255, 255), "empty cell {empty:?}");
}

#[test]
fn the_curve_is_the_score_contacts_curve() {
    let dir = tempfile::tempdir().unwrap();
    let curve = dir.path().join("curve.tsv");
    let curve_text = curve.to_string_lossy().into_owned();
    for curve_max in ["2L", "L/2"] {
        run_ok(&[
            "score",
            "contacts",
            "--structure",
            &protein("toxd/toxd.pdb.gz"),
            &protein("toxd/toxd.mat.gz"),
            "--fasta",
            &protein("toxd/toxd.fasta"),
            "--min-sep",
            "6",
            "--curve",
            &curve_text,
            "--curve-max",
            curve_max,
        ]);
        let rows: Vec<(f64, f64)> = std::fs::read_to_string(&curve)
            .unwrap()
            .lines()
            .skip(1)
            .map(|line| {
                let fields: Vec<&str> = line.split('\t').collect();
                (fields[3].parse().unwrap(), fields[5].parse().unwrap())
            })
            .collect();
        // 2L = 118 and L/2 = 29 (floor) rows.
        assert_eq!(rows.len(), if curve_max == "2L" { 118 } else { 29 });
        let svg = plot_svg(&strs(&toxd_args(&["--curve-max", curve_max])));
        let figure = parse(&svg, 1, 59);
        assert_eq!(figure.curves.len(), 1);
        let points = &figure.curves[0];
        assert_eq!(points.len(), rows.len());
        let (fx, fy, fw, fh) = figure.curve_frame;
        let x_max = rows.len() as f64 / 59.0;
        for ((x, y), (k_over_l, precision)) in points.iter().zip(&rows) {
            // The precision axis runs from 0 to 1.05 (PRECISION_AXIS_MAX).
            let drawn_precision = (fy + fh - y) / fh * 1.05;
            let drawn_fraction = (x - fx) / fw * x_max;
            assert!(
                (drawn_precision - precision).abs() < 1e-3,
                "{drawn_precision} vs {precision}"
            );
            assert!((drawn_fraction - k_over_l).abs() < 1e-3);
        }
    }
}

#[test]
fn a_second_prediction_goes_to_the_lower_triangle() {
    let dir = tempfile::tempdir().unwrap();
    let rr = dir.path().join("true.rr");
    let rr_text = rr.to_string_lossy().into_owned();
    let pdb = protein("toxd/toxd.pdb.gz");
    let fasta = protein("toxd/toxd.fasta");
    // The structure's own contacts as the second prediction: all true.
    run_ok(&["contacts", &pdb, "--fasta", &fasta, "-o", &rr_text]);
    let mut args = toxd_args(&[]);
    args.push(rr_text.clone());
    let svg = plot_svg(&strs(&args));
    let figure = parse(&svg, 1, 59);
    // Top L = 59 of its 115 true contacts, all true positives, mirrored below the diagonal.
    assert_eq!(count(&figure, "lower", "tp"), 59);
    assert_eq!(count(&figure, "lower", "fp"), 0);
    assert!(
        figure
            .markers
            .iter()
            .filter(|m| m.0 == "lower")
            .all(|m| m.2 > m.3)
    );
    assert_eq!(count(&figure, "upper", "tp"), 34);
    assert_eq!(figure.curves.len(), 2);
    // Precision 1 at every k; the curve stops at the 115 listed pairs, short of 2L = 118, as
    // score contacts' curve.
    let (_, fy, _, fh) = figure.curve_frame;
    let one = fy + fh * (1.0 - 1.0 / 1.05);
    assert_eq!(figure.curves[1].len(), 115);
    assert!(
        figure.curves[1]
            .iter()
            .all(|&(_, y)| (y - one).abs() < 0.02)
    );
    assert!(svg.contains("lower: true.rr, top L (k = 59):"), "legend");
}

#[test]
fn unobserved_pairs_are_dropped_or_drawn_open() {
    // toxd's residue 1 (PCA) is not read: pairs with it are dropped by default (as score
    // contacts), and drawn as open circles with --keep-unobserved.
    let dir = tempfile::tempdir().unwrap();
    let rr = dir.path().join("one.rr");
    std::fs::write(&rr, "1 30 0 8 0.9\n2 40 0 8 0.5\n").unwrap();
    let rr_text = rr.to_string_lossy().into_owned();
    let base = [
        "plot",
        "contacts",
        "--structure",
        &protein("toxd/toxd.pdb.gz"),
        "--fasta",
        &protein("toxd/toxd.fasta"),
        &rr_text,
    ];
    let svg = plot_svg(&base);
    assert!(!svg.contains(
        r#"<g class="unobserved">
<circle"#
    ));
    let figure = parse(&svg, 1, 59);
    assert_eq!(figure.markers.len(), 1);
    let kept = plot_svg(&[&base[..], &["--keep-unobserved"]].concat());
    assert!(kept.contains("unobserved 1"), "legend");
    let doc = roxmltree::Document::parse(&kept).unwrap();
    let open = doc
        .descendants()
        .filter(|n| class_of(n) == Some("unobserved"))
        .flat_map(|g| g.children().filter(|c| c.has_tag_name("circle")))
        .collect::<Vec<_>>();
    assert_eq!(open.len(), 1);
    assert_eq!(open[0].attribute("fill"), Some("none"));
}

#[test]
fn bad_inputs_fail_with_one_line_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let pdb = protein("toxd/toxd.pdb.gz");
    let fasta = protein("toxd/toxd.fasta");
    let mat = protein("toxd/toxd.mat.gz");
    let outside = dir.path().join("outside.rr");
    std::fs::write(&outside, "5 80 0 8 0.9\n").unwrap();
    let outside = outside.to_string_lossy().into_owned();
    let missing = dir.path().join("missing.pdb");
    let missing = missing.to_string_lossy().into_owned();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["--structure", &missing, "--fasta", &fasta, &mat],
            "missing.pdb",
        ),
        (
            vec!["--structure", &pdb, "--chain", "Z", "--fasta", &fasta, &mat],
            "no protein chain 'Z'",
        ),
        (
            vec!["--structure", &pdb, "--fasta", &fasta, &outside],
            "outside.rr: predicted pair 5-80 refers to a residue beyond the sequence",
        ),
        (
            vec!["--structure", &pdb, "--fasta", &fasta, &mat, "--top", "L/0"],
            "--top",
        ),
        (
            vec![
                "--structure",
                &pdb,
                "--fasta",
                &fasta,
                &mat,
                "--top",
                "lots",
            ],
            "bad list size 'lots'",
        ),
        (
            vec![
                "--structure",
                &pdb,
                "--fasta",
                &fasta,
                &mat,
                "--curve-max=-3",
            ],
            "--curve-max",
        ),
    ];
    for (args, expected) in cases {
        let all = [&["plot", "contacts"][..], &args].concat();
        let message = plot_fails(&all, dir.path());
        assert!(message.contains(expected), "{all:?}: {message}");
    }
}

#[test]
fn help_shows_examples() {
    let help = run_ok(&["plot", "contacts", "--help"]);
    assert!(help.contains("Examples:"), "{help}");
    assert!(help.contains("--structure"));
    assert!(help.contains("--curve-max"));
}
