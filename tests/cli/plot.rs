//! `contactmap plot map`: figures decoded and checked pixel by pixel (PNG) and element by element
//! (SVG). The helpers here serve the other `plot` test modules too.

use super::*;

/// A decoded RGB image.
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<u8>,
}

impl Image {
    /// Pixel `(x, y)`.
    pub fn at(&self, x: usize, y: usize) -> (u8, u8, u8) {
        let i = 3 * (y * self.width + x);
        (self.rgb[i], self.rgb[i + 1], self.rgb[i + 2])
    }
}

/// Decode a PNG (8-bit RGB, as contactmap writes).
pub fn decode_png(bytes: &[u8]) -> Image {
    let decoder = png::Decoder::new(bytes);
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buffer = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buffer).expect("a PNG frame");
    assert_eq!(info.color_type, png::ColorType::Rgb, "RGB PNG");
    buffer.truncate(info.buffer_size());
    Image {
        width: info.width as usize,
        height: info.height as usize,
        rgb: buffer,
    }
}

/// Run `contactmap plot ...` writing the PNG to stdout (`-o -`), and decode it.
pub fn plot_png(args: &[&str]) -> Image {
    let mut all = args.to_vec();
    all.extend(["-o", "-", "--to", "png"]);
    let out = run(&all);
    assert!(
        out.status.success(),
        "contactmap {all:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    decode_png(&out.stdout)
}

/// Run `contactmap plot ...` writing SVG to stdout; return the document text.
pub fn plot_svg(args: &[&str]) -> String {
    let mut all = args.to_vec();
    all.extend(["-o", "-", "--to", "svg"]);
    run_ok(&all)
}

/// The `(x, y, width, height)` of every element `name` of an SVG document with attribute
/// `key = value` (any when `key` is empty).
pub fn svg_rects(svg: &str, name: &str, key: &str, value: &str) -> Vec<(f64, f64, f64, f64)> {
    let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
    let number = |node: &roxmltree::Node, attribute: &str| -> f64 {
        node.attribute(attribute)
            .unwrap_or_else(|| panic!("<{name}> without {attribute}"))
            .parse()
            .unwrap()
    };
    doc.descendants()
        .filter(|n| n.has_tag_name(name))
        .filter(|n| key.is_empty() || n.attribute(key) == Some(value))
        .map(|n| {
            (
                number(&n, "x"),
                number(&n, "y"),
                number(&n, "width"),
                number(&n, "height"),
            )
        })
        .collect()
}

#[test]
fn a_map_is_a_png_of_the_asked_size() {
    let image = plot_png(&[
        "plot",
        "map",
        &data("yeast.10kb.cool"),
        "-r",
        "chrIV:200k-800k",
        "--width",
        "5",
        "--dpi",
        "80",
    ]);
    assert_eq!(image.width, 400);
    assert!(image.height > 200 && image.height < 600, "{}", image.height);
}

/// A 4-bin chromosome `c1` (10 bp bins) with known contacts, as a BG2 table and its sizes.
/// Upper triangle: the diagonal 10, first off-diagonal 5 except (1, 2) = 0 (unstored), second
/// off-diagonal 2.5, (0, 3) unstored.
fn known_map(dir: &std::path::Path) -> (String, String) {
    let sizes = dir.join("c1.sizes");
    std::fs::write(&sizes, "c1\t40\n").unwrap();
    let table = dir.join("known.bg2");
    let mut text = String::new();
    for (i, j, value) in [
        (0, 0, 10.0),
        (1, 1, 10.0),
        (2, 2, 10.0),
        (3, 3, 10.0),
        (0, 1, 5.0),
        (2, 3, 5.0),
        (0, 2, 2.5),
        (1, 3, 2.5),
    ] {
        text.push_str(&format!(
            "c1\t{}\t{}\tc1\t{}\t{}\t{value}\n",
            10 * i,
            10 * i + 10,
            10 * j,
            10 * j + 10
        ));
    }
    std::fs::write(&table, text).unwrap();
    (
        table.to_string_lossy().into_owned(),
        sizes.to_string_lossy().into_owned(),
    )
}

fn known_value(i: usize, j: usize) -> f64 {
    let (i, j) = (i.min(j), i.max(j));
    match (i, j) {
        _ if i == j => 10.0,
        (1, 2) | (0, 3) => 0.0,
        _ if j - i == 1 => 5.0,
        _ => 2.5,
    }
}

/// matplotlib 3.11.2 `Greys(k / 255, bytes=True)` grey level at the lookup entries a value in
/// [0, 10] takes on a linear 0..10 scale: 0 -> entry 0, 2.5 -> 64, 5 -> 128, 10 -> 255.
pub fn greys_linear(value: f64) -> u8 {
    if value == 0.0 {
        255
    } else if value == 2.5 {
        216
    } else if value == 5.0 {
        149
    } else if value == 10.0 {
        0
    } else {
        panic!("no reference colour for {value}")
    }
}

pub fn known_args<'a>(table: &'a str, sizes: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "plot",
        "map",
        table,
        "--format",
        "bg2",
        "--chrom-sizes",
        sizes,
        "--bin-size",
        "10",
        "-r",
        "c1",
        "--raw",
        "--cmap",
        "Greys",
    ];
    args.extend_from_slice(extra);
    args
}

/// The heatmap's place in the figure: the first `<image>` of the SVG.
pub fn heatmap_rect(args: &[&str]) -> (f64, f64, f64, f64) {
    svg_rects(&plot_svg(args), "image", "", "")[0]
}

#[test]
fn known_values_land_on_their_cells_with_their_colours() {
    let dir = tempfile::tempdir().unwrap();
    let (table, sizes) = known_map(dir.path());
    let args = known_args(&table, &sizes, &["--linear", "--vmin", "0", "--vmax", "10"]);
    let (x0, y0, width, height) = heatmap_rect(&args);
    assert_eq!(width, height, "one region: a square map");
    let image = plot_png(&args);
    for i in 0..4 {
        for j in 0..4 {
            let x = (x0 + (j as f64 + 0.5) * width / 4.0) as usize;
            let y = (y0 + (i as f64 + 0.5) * height / 4.0) as usize;
            let grey = greys_linear(known_value(i, j));
            assert_eq!(image.at(x, y), (grey, grey, grey), "cell ({i}, {j})");
        }
    }
}

#[test]
fn log_scale_maps_decades_to_the_colour_bar() {
    // On a log scale from 2.5 to 10, 5 sits half way: Greys entry 127 or 128, 2.5 at the
    // bottom (255, white), 10 at the top (0); unstored zeros take the lowest colour.
    let dir = tempfile::tempdir().unwrap();
    let (table, sizes) = known_map(dir.path());
    let args = known_args(&table, &sizes, &[]);
    let (x0, y0, width, height) = heatmap_rect(&args);
    let image = plot_png(&args);
    let at = |i: usize, j: usize| {
        image.at(
            (x0 + (j as f64 + 0.5) * width / 4.0) as usize,
            (y0 + (i as f64 + 0.5) * height / 4.0) as usize,
        )
    };
    assert_eq!(at(0, 0), (0, 0, 0));
    // ln 2 / ln 4 rounds to either side of 1/2: entry 127 (150) or 128 (149).
    let half = at(0, 1);
    assert!(
        half == (149, 149, 149) || half == (150, 150, 150),
        "{half:?}"
    );
    assert_eq!(at(0, 2), (255, 255, 255));
    assert_eq!(at(0, 3), (255, 255, 255));
    // The colour bar (second image): black at the top, white at the bottom.
    let svg = plot_svg(&args);
    let (bx, by, bw, bh) = svg_rects(&svg, "image", "", "")[1];
    let centre = (bx + bw / 2.0) as usize;
    // (rows are sampled at their centres: Greys entries 254-255 at the top, 0-1 at the bottom)
    assert!(image.at(centre, by as usize + 1).0 <= 1);
    assert!(image.at(centre, (by + bh) as usize - 2).0 >= 254);
    // Its middle (log scale: the value 5) is the middle grey.
    let middle = image.at(centre, (by + bh / 2.0) as usize);
    assert!((i32::from(middle.0) - 149).abs() <= 2, "{middle:?}");
}

#[test]
fn masked_bins_are_drawn_in_the_nan_colour() {
    // chrIV:510,000-520,000 has no ICE weight in yeast.10kb.cool: bin 31 of the 60 drawn.
    let args = [
        "plot",
        "map",
        &data("yeast.10kb.cool"),
        "-r",
        "chrIV:200k-800k",
        "--nan-color",
        "#00ff00",
    ];
    let (x0, y0, width, height) = heatmap_rect(&args);
    let image = plot_png(&args);
    let y = (y0 + 31.5 * height / 60.0) as usize;
    for j in [0.5, 10.5, 45.5, 59.5] {
        let x = (x0 + j * width / 60.0) as usize;
        assert_eq!(
            image.at(x, y),
            (0, 255, 0),
            "row of the masked bin, column {j}"
        );
    }
    let x = (x0 + 31.5 * width / 60.0) as usize;
    assert_eq!(
        image.at(x, (y0 + 5.5 * height / 60.0) as usize),
        (0, 255, 0)
    );
    // A valid pair is not.
    let x = (x0 + 20.5 * width / 60.0) as usize;
    assert_ne!(
        image.at(x, (y0 + 21.5 * height / 60.0) as usize),
        (0, 255, 0)
    );
}

#[test]
fn triangle_pixels_show_the_pair_below_them() {
    let dir = tempfile::tempdir().unwrap();
    let (table, sizes) = known_map(dir.path());
    let args = known_args(
        &table,
        &sizes,
        &[
            "--linear",
            "--vmin",
            "0",
            "--vmax",
            "10",
            "--triangle",
            "--depth",
            "40",
        ],
    );
    let (x0, y0, width, height) = heatmap_rect(&args);
    // The whole depth of a 4-bin region: half as high as wide (45 degrees).
    assert!((height - width / 2.0).abs() <= 1.0, "{width} x {height}");
    let image = plot_png(&args);
    // Position p and distance d in bins -> pixel; the pair is (p - d/2, p + d/2).
    let pixel = |p: f64, d: f64| {
        let x = x0 + p / 4.0 * width;
        let y = y0 + height - d / 4.0 * height;
        image.at(x as usize, y as usize)
    };
    let grey = |i, j| {
        let g = greys_linear(known_value(i, j));
        (g, g, g)
    };
    assert_eq!(pixel(1.5, 2.0), grey(0, 2));
    assert_eq!(pixel(2.5, 2.0), grey(1, 3));
    assert_eq!(pixel(2.0, 1.0), grey(1, 2));
    assert_eq!(pixel(1.0, 1.0), grey(0, 1));
    assert_eq!(pixel(0.5, 0.2), grey(0, 0));
    // Outside the matrix: the white background, not a colour of the map.
    assert_eq!(pixel(0.25, 3.0), (255, 255, 255));
}

#[test]
fn domains_are_outlined_on_their_bins() {
    let dir = tempfile::tempdir().unwrap();
    let (table, sizes) = known_map(dir.path());
    let domains = dir.path().join("domains.bed");
    std::fs::write(&domains, "c1\t10\t30\tdomain1\nc2\t0\t10\telsewhere\n").unwrap();
    let domains = domains.to_string_lossy().into_owned();
    let args = known_args(&table, &sizes, &["--domains", &domains]);
    let svg = plot_svg(&args);
    let (x0, y0, width, _) = svg_rects(&svg, "image", "", "")[0];
    let outlines = svg_rects(&svg, "rect", "stroke", "#0072b2");
    assert_eq!(outlines.len(), 1, "one domain on c1: {outlines:?}");
    let (x, y, w, h) = outlines[0];
    let bin = width / 4.0;
    assert!((x - (x0 + bin)).abs() < 0.02 && (y - (y0 + bin)).abs() < 0.02);
    assert!((w - 2.0 * bin).abs() < 0.02 && (h - 2.0 * bin).abs() < 0.02);
    // In the PNG the outline is blue where the map is grey.
    let image = plot_png(&args);
    let (r, _, b) = image.at(x.round() as usize, (y + h / 2.0) as usize);
    assert!(
        i32::from(b) > i32::from(r) + 60,
        "outline pixel ({r}, _, {b})"
    );
}

/// Run a plot that must fail: exit 2, one error line, and no output file.
pub fn plot_fails(args: &[&str], dir: &std::path::Path) -> String {
    let out = dir.join("figure.png");
    let mut all = args.to_vec();
    let out_text = out.to_string_lossy().into_owned();
    all.extend(["-o", &out_text]);
    let message = run_err(&all);
    assert!(!out.exists(), "a failed plot wrote {out_text}");
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains("figure"))
        .collect();
    assert!(leftovers.is_empty(), "partial files: {leftovers:?}");
    message
}

#[test]
fn bad_inputs_fail_with_one_line_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let yeast = data("yeast.10kb.cool");
    let base = ["plot", "map", yeast.as_str()];
    let with = |extra: &[&'static str]| {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        args
    };
    let message = plot_fails(&with(&["-r", "chrXXX:1-100"]), dir.path());
    assert!(message.contains("no chromosome 'chrXXX'"), "{message}");
    let message = plot_fails(&with(&["-r", "chrIV:300k-300k"]), dir.path());
    assert!(message.contains("chrIV:300k-300k"), "{message}");
    let message = plot_fails(&with(&["-r", "chrIV", "--cmap", "jet"]), dir.path());
    assert!(message.contains("unknown colour map 'jet'"), "{message}");
    // A track at another resolution (20 kb rows for a 10 kb map).
    let track = dir.path().join("track.tsv");
    let mut text = String::from("chrom\tstart\tend\tscore\n");
    for k in 0..100 {
        text.push_str(&format!(
            "chrIV\t{}\t{}\t{k}\n",
            20_000 * k,
            20_000 * (k + 1)
        ));
    }
    std::fs::write(&track, text).unwrap();
    let spec = format!("{}:score", track.display());
    let mut args = with(&["-r", "chrIV:200k-800k", "--track"]);
    args.push(&spec);
    let message = plot_fails(&args, dir.path());
    assert!(
        message.contains("has 30 rows in chrIV:200000-800000, where the map has 60 bins"),
        "{message}"
    );
    // An empty region: no contacts at all to scale the colours by.
    let (table, sizes) = known_map(dir.path());
    let empty = dir.path().join("empty.bg2");
    std::fs::write(&empty, "").unwrap();
    let empty = empty.to_string_lossy().into_owned();
    let mut args = known_args(&empty, &sizes, &[]);
    args.retain(|a| *a != table);
    let message = plot_fails(&args, dir.path());
    assert!(message.contains("no positive values to draw"), "{message}");
}

/// Issue 26: on a whole chromosome with its boundaries (4,800 bins of 10 kb and about 140
/// boundaries, the workflow's map.png of a human chromosome), the boundary marks stop short of
/// the diagonal, which stays in view, and are thinner than the space between them; on a few
/// large bins they still cross it.
#[test]
fn boundary_marks_scale_with_the_bins_on_screen() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("big.cool");
    let map = map.to_str().unwrap();
    run_ok(&[
        "simulate", "blocks", "-o", map, "--bins", "4800", "--seed", "2",
    ]);
    let boundaries = dir.path().join("b.bed");
    run_ok(&[
        "tads",
        map,
        "--raw",
        "--window",
        "100k",
        "-o",
        dir.path().join("i.tsv").to_str().unwrap(),
        "--boundaries",
        boundaries.to_str().unwrap(),
    ]);
    let n_boundaries = std::fs::read_to_string(&boundaries)
        .unwrap()
        .lines()
        .count();
    assert!(n_boundaries > 100, "{n_boundaries}");
    let marks = |region: &str| -> (Vec<[f64; 5]>, [f64; 3]) {
        let svg = run_ok(&[
            "plot",
            "map",
            map,
            "--raw",
            "-r",
            region,
            "--boundaries",
            boundaries.to_str().unwrap(),
            "-o",
            "-",
            "--to",
            "svg",
        ]);
        let attr = |element: &str, name: &str| -> f64 {
            let start = element.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
            element[start..].split('"').next().unwrap().parse().unwrap()
        };
        let image = svg.split("<image").nth(1).unwrap();
        let frame = [attr(image, "x"), attr(image, "y"), attr(image, "width")];
        let lines = svg
            .split("<line")
            .skip(1)
            .filter(|l| l.contains("stroke=\"#009e73\""))
            .map(|l| {
                let l = l.split('>').next().unwrap();
                [
                    attr(l, "x1"),
                    attr(l, "y1"),
                    attr(l, "x2"),
                    attr(l, "y2"),
                    attr(l, "stroke-width"),
                ]
            })
            .collect();
        (lines, frame)
    };
    // Signed distance (px) of a point from the diagonal of the map's frame.
    let off = |frame: [f64; 3], x: f64, y: f64| ((x - frame[0]) - (y - frame[1])) / 2f64.sqrt();
    let (lines, frame) = marks("chr1");
    assert!(lines.len() >= 2 * n_boundaries - 4, "{} marks", lines.len());
    let spacing = frame[2] / n_boundaries as f64;
    for [x1, y1, x2, y2, width] in &lines {
        let (a, b) = (off(frame, *x1, *y1), off(frame, *x2, *y2));
        assert!(a * b > 0.0, "a mark crosses the diagonal: {a} {b}");
        assert!(
            a.abs().min(b.abs()) >= 1.0,
            "a mark touches the diagonal: {a} {b}"
        );
        assert!(
            *width <= spacing,
            "marks {width} px wide, {spacing} px apart"
        );
    }
    // 40 bins on screen around a boundary: each mark crosses the diagonal cell.
    let text = std::fs::read_to_string(&boundaries).unwrap();
    let middle: u64 = text
        .lines()
        .map(|l| l.split('\t').nth(1).unwrap().parse::<u64>().unwrap())
        .find(|&start| start >= 300_000)
        .unwrap();
    let (lines, frame) = marks(&format!("chr1:{}-{}", middle - 200_000, middle + 200_000));
    assert!(!lines.is_empty());
    for [x1, y1, x2, y2, _] in &lines {
        assert!(off(frame, *x1, *y1) * off(frame, *x2, *y2) < 0.0);
    }
}

/// Issue 51: 10 kb loops in a 7 Mb view were hairlines (outlines thinned as the bins shrank on
/// screen, as domain outlines are): loops keep a full-width outline and a visible size.
#[test]
fn loops_stay_visible_when_their_bins_are_small() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("big.cool");
    let map = map.to_str().unwrap();
    run_ok(&[
        "simulate", "blocks", "-o", map, "--bins", "1000", "--seed", "3",
    ]);
    let loops = dir.path().join("loops.bedpe");
    std::fs::write(
        &loops,
        "chr1\t2000000\t2010000\tchr1\t2300000\t2310000\nchr1\t5000000\t5010000\tchr1\t5500000\t5510000\n",
    )
    .unwrap();
    let domains = dir.path().join("domains.bed");
    std::fs::write(&domains, "chr1\t1000000\t3000000\n").unwrap();
    let svg = run_ok(&[
        "plot",
        "map",
        map,
        "--raw",
        "-r",
        "chr1:0-7,000,000",
        "--loops",
        loops.to_str().unwrap(),
        "--domains",
        domains.to_str().unwrap(),
        "-o",
        "-",
        "--to",
        "svg",
    ]);
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let outlines: Vec<(f64, f64)> = doc
        .descendants()
        .filter(|n| n.has_tag_name("rect") && n.attribute("stroke") == Some("#0072b2"))
        .map(|n| {
            let number = |a: &str| n.attribute(a).unwrap().parse::<f64>().unwrap();
            (number("width"), number("stroke-width"))
        })
        .collect();
    let (image_width, bins) = (svg_rects(&svg, "image", "", "")[0].2, 700.0);
    assert!(
        image_width / bins < 2.0,
        "bins of {} px",
        image_width / bins
    );
    // the domain (2 Mb wide), then each loop drawn on both sides of the diagonal
    let domain = outlines
        .iter()
        .find(|(w, _)| *w > image_width / 5.0)
        .expect("the domain's outline");
    let marks: Vec<&(f64, f64)> = outlines
        .iter()
        .filter(|(w, _)| *w < image_width / 5.0)
        .collect();
    assert_eq!(marks.len(), 4, "{outlines:?}");
    for (width, stroke) in marks {
        assert!(
            *stroke >= 3.0 * domain.1,
            "loop outline {stroke} against the domain's {}",
            domain.1
        );
        assert!(*width >= 5.0 * stroke, "a loop mark {width} px wide");
    }
}
