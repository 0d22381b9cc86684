//! `contactmap plot expected`: the P(s) figure read back from its SVG (points mapped to data
//! units through the tick labels) against closed-form power laws, `contactmap expected --fit`,
//! and cooltools' expected table.

use super::plot::{plot_fails, plot_svg};
use super::*;

/// The text of an SVG `<text>` element, its superscript (`<tspan>`) included.
fn full_text(node: &roxmltree::Node) -> String {
    node.descendants()
        .filter(|n| n.is_text())
        .filter_map(|n| n.text())
        .collect()
}

/// Every `<text>` of the document: `(x, y, text)`.
fn texts(svg: &str) -> Vec<(f64, f64, String)> {
    let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| {
            let number = |a: &str| n.attribute(a).unwrap().parse::<f64>().unwrap();
            (number("x"), number("y"), full_text(&n))
        })
        .collect()
}

/// Pixel or data coordinates `(x, y)`.
type Points = Vec<(f64, f64)>;

/// Every `<polyline>`: its points in pixels and its stroke colour and dashes.
fn polylines(svg: &str) -> Vec<(Points, String, bool)> {
    let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
    doc.descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .map(|n| {
            let points = n
                .attribute("points")
                .unwrap()
                .split_whitespace()
                .map(|p| {
                    let (x, y) = p.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect();
            (
                points,
                n.attribute("stroke").unwrap().to_string(),
                n.attribute("stroke-dasharray").is_some(),
            )
        })
        .collect()
}

/// A cis expected table (cooltools' columns) of one region of `n` bins of `bin` bp whose raw
/// average on diagonal `d >= 2` is `1000 * d^alpha` exactly; diagonals 0 and 1 are NaN.
fn power_law_table(path: &std::path::Path, region: &str, n: u64, bin: u64, alpha: f64) {
    let mut text = String::from(
        "region1\tregion2\tdist\tdist_bp\tcontact_frequency\tn_total\tn_valid\tcount.sum\tcount.avg\n",
    );
    for d in 0..n {
        let n_pixels = n - d;
        let (sum, avg) = if d < 2 {
            (f64::NAN, f64::NAN)
        } else {
            let avg = 1000.0 * (d as f64).powf(alpha);
            (avg * n_pixels as f64, avg)
        };
        text.push_str(&format!(
            "{region}\t{region}\t{d}\t{}\t{avg}\t{n_pixels}\t{n_pixels}\t{sum}\t{avg}\n",
            d * bin
        ));
    }
    std::fs::write(path, text).unwrap();
}

/// The decade ticks of the shared axis (`10 kb` ...) and the P(s) axis (`10^-3` ...) as
/// `(log10 value, pixel)`.
fn decade_ticks(svg: &str) -> (Points, Points) {
    let mut x = Vec::new();
    let mut y = Vec::new();
    for (px, py, text) in texts(svg) {
        let bp = match text.split_once(' ') {
            Some((number, "bp")) => number.parse::<f64>().ok(),
            Some((number, "kb")) => number.parse::<f64>().ok().map(|v| v * 1e3),
            Some((number, "Mb")) => number.parse::<f64>().ok().map(|v| v * 1e6),
            _ => None,
        };
        if let Some(bp) = bp {
            x.push((bp.log10(), px));
        } else if let Some(exponent) = text.strip_prefix("10") {
            if let Ok(k) = exponent.parse::<f64>() {
                y.push((k, py));
            }
        }
    }
    (x, y)
}

/// The linear map `value -> pixel` through two ticks.
fn through(ticks: &[(f64, f64)]) -> impl Fn(f64) -> f64 + use<> {
    assert!(ticks.len() >= 2, "two ticks needed: {ticks:?}");
    let (a, b) = (ticks[0], ticks[ticks.len() - 1]);
    let slope = (b.0 - a.0) / (b.1 - a.1);
    move |pixel| a.0 + (pixel - a.1) * slope
}

#[test]
fn a_power_law_is_drawn_as_one_with_its_slope() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("ps.tsv");
    power_law_table(&table, "r1", 40_000, 100, -1.0);
    let table = table.to_string_lossy().into_owned();
    let svg = plot_svg(&["plot", "expected", &table]);
    let (x_ticks, y_ticks) = decade_ticks(&svg);
    let log_s = through(&x_ticks);
    // Tick labels sit 0.36 em below their tick (middle baseline): use their spacing only,
    // shifted onto the tick line by that offset (9 pt font at 100 dpi).
    let shift = 0.36 * 9.0 * 100.0 / 72.0;
    let y_lines: Vec<(f64, f64)> = y_ticks.iter().map(|&(k, y)| (k, y - shift)).collect();
    let log_p = through(&y_lines);
    let lines = polylines(&svg);
    assert_eq!(lines.len(), 2, "the P(s) curve and its slope");
    let (ps, _, _) = &lines[0];
    assert!(ps.len() >= 25, "log bins from 200 bp to 1 Mb: {}", ps.len());
    for &(x, y) in ps {
        // log P = 3 - log(s / 100 bp): within 0.01 decade (pixel rounding of the SVG numbers).
        let (s, p) = (log_s(x), log_p(y));
        assert!((p - (3.0 - (s - 2.0))).abs() < 0.01, "point ({s}, {p})");
    }
    // The slope panel: -1 everywhere, read through its (linear, decimal) tick labels.
    let slope_ticks: Vec<(f64, f64)> = texts(&svg)
        .into_iter()
        .filter(|(_, _, t)| t.contains('.'))
        .filter_map(|(_, y, t)| t.parse::<f64>().ok().map(|v| (v, y - shift)))
        .collect();
    let slope_at = through(&slope_ticks);
    let (slope, _, _) = &lines[1];
    assert!(slope.len() >= 20);
    for &(_, y) in slope {
        assert!((slope_at(y) + 1.0).abs() < 0.01, "slope {}", slope_at(y));
    }
}

#[test]
fn samples_overlay_with_a_legend_and_fits() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.tsv"), dir.path().join("b.tsv"));
    power_law_table(&a, "chrA", 20_000, 1000, -1.0);
    power_law_table(&b, "chrB", 20_000, 1000, -0.5);
    let (a, b) = (a.to_string_lossy(), b.to_string_lossy());
    let svg = plot_svg(&[
        "plot",
        "expected",
        &a,
        &b,
        "--labels",
        "one,two",
        "--fit",
        "--fit-range",
        "10k-1M",
    ]);
    let labels: Vec<String> = texts(&svg).into_iter().map(|t| t.2).collect();
    assert!(labels.contains(&"one".to_string()) && labels.contains(&"two".to_string()));
    // Fitted from the first log bin in 10 kb - 1 Mb to the last one.
    assert!(
        labels.contains(&"fit 10.9 kb-892 kb: s-1.00".to_string()),
        "{labels:?}"
    );
    assert!(labels.contains(&"fit 11 kb-893 kb: s-0.50".to_string()));
    let lines = polylines(&svg);
    // Per sample: curve and dashed fit (P(s)), slope and dashed level; two colours.
    assert_eq!(lines.iter().filter(|l| l.2).count(), 4);
    let colours: std::collections::BTreeSet<&str> = lines.iter().map(|l| l.1.as_str()).collect();
    assert_eq!(colours.len(), 2, "{colours:?}");
}

#[test]
fn the_fit_is_the_one_of_expected_fit_on_matrices_and_tables() {
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    let json = run_ok(&["expected", &uri, "--json", "--fit-range", "200k-5M"]);
    let report: serde_json::Value = serde_json::from_str(&json).unwrap();
    let alpha = report["power_law"]["alpha"].as_f64().unwrap();
    // The legend names the distances of the points fitted (the effective distances of the
    // first and last log bins in the range), as the headline does.
    let legend = format!(
        "fit {}-{}: s{alpha:.2}",
        contactmap::genome::format_distance(report["power_law"]["first_bp"].as_f64().unwrap()),
        contactmap::genome::format_distance(report["power_law"]["last_bp"].as_f64().unwrap())
    );
    let out = run(&[
        "plot",
        "expected",
        &uri,
        "--fit",
        "--fit-range",
        "200k-5M",
        "-o",
        "-",
        "--to",
        "svg",
    ]);
    assert!(out.status.success());
    let svg = String::from_utf8(out.stdout).unwrap();
    assert!(texts(&svg).iter().any(|t| t.2 == legend), "{legend}");
    let headline = String::from_utf8(out.stderr).unwrap();
    assert!(
        headline.contains(&format!("P(s) ~ s^{alpha:.2}")),
        "{headline}"
    );
    // cooltools' expected_cis table of the same map (balanced with the stored weights) gives
    // the same fit.
    let table = data("reference/numerics/dm6_100kb.expected_cis.balanced_storedweight.tsv.gz");
    let out = run(&[
        "plot",
        "expected",
        &table,
        "--fit",
        "--fit-range",
        "200k-5M",
        "-o",
        "-",
        "--to",
        "svg",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let from_table = String::from_utf8(out.stderr).unwrap();
    let tail = |text: &str| text.split_once(": ").map(|p| p.1.to_string()).unwrap();
    assert_eq!(tail(&from_table), tail(&headline));
}

#[test]
fn per_region_draws_each_chromosome() {
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    let svg = plot_svg(&["plot", "expected", &uri, "--per-region", "--no-slope"]);
    let labels: Vec<String> = texts(&svg).into_iter().map(|t| t.2).collect();
    for chrom in ["chr2L", "chr2R", "chr3L", "chr3R", "chrX"] {
        assert!(labels.contains(&chrom.to_string()), "{chrom}: {labels:?}");
    }
    assert!(!labels.contains(&"slope".to_string()));
    // A .cool file (binary, no `::`) is a matrix, not a table.
    let svg = plot_svg(&["plot", "expected", &data("yeast.10kb.cool"), "--per-region"]);
    assert!(texts(&svg).iter().any(|t| t.2 == "chrIV"));
}

#[test]
fn bad_inputs_fail_with_one_line_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    let message = plot_fails(&["plot", "expected", &uri, "--labels", "a,b"], dir.path());
    assert!(
        message.contains("--labels gives 2 name(s) for 1 input(s)"),
        "{message}"
    );
    let message = plot_fails(
        &["plot", "expected", &uri, "--fit", "--fit-range", "5M-1M"],
        dir.path(),
    );
    assert!(message.contains("--fit-range '5M-1M'"), "{message}");
    let missing = dir.path().join("missing.cool");
    let missing = missing.to_string_lossy().into_owned();
    let message = plot_fails(&["plot", "expected", &missing], dir.path());
    assert!(message.contains("missing.cool"), "{message}");
    // A trans table is not a P(s).
    let trans = dir.path().join("trans.tsv");
    std::fs::write(
        &trans,
        "region1\tregion2\tdist\tdist_bp\tn_total\tn_valid\tcount.sum\tcount.avg\nchr1\tchr2\t0\t0\t4\t4\t1\t0.25\n",
    )
    .unwrap();
    let trans = trans.to_string_lossy().into_owned();
    let message = plot_fails(&["plot", "expected", &trans], dir.path());
    assert!(message.contains("a trans table"), "{message}");
    // Too few pixels for a single log bin (cooltools' thresholds).
    let tiny = dir.path().join("tiny.tsv");
    power_law_table(&tiny, "r1", 30, 100, -1.0);
    let tiny = tiny.to_string_lossy().into_owned();
    let message = plot_fails(&["plot", "expected", &tiny], dir.path());
    assert!(
        message.contains("no distance has enough valid pixels"),
        "{message}"
    );
}
