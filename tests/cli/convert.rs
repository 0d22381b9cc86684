//! `contactmap convert`: round trips and coarsening against independent references.

use crate::{data, run_err, run_ok};

#[test]
fn cool_to_cool_round_trips_pixels_bins_and_weights() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("copy.cool");
    let out = out.to_str().unwrap();
    let uri = data("cooler_test_file.mcool::/resolutions/100000");
    run_ok(&["convert", &uri, out]);
    assert_eq!(run_ok(&["dump", out]), run_ok(&["dump", &uri]));
    // Weight columns as stored: the same, except hic2cool's SCALE, divisive in the source (by
    // its generated-by) and written multiplicative (divisive_weights = false) in the copy, as
    // cooler multiplies by columns not named KR / VC / VC_SQRT.
    let bins = |u: &str| run_ok(&["dump", "-t", "bins", "-H", "--float-format", ".17g", u]);
    let (copy, source) = (bins(out), bins(&uri));
    let header: Vec<&str> = source.lines().next().unwrap().split('\t').collect();
    assert_eq!(
        copy.lines().next().unwrap().split('\t').collect::<Vec<_>>(),
        header
    );
    let scale = header.iter().position(|&h| h == "SCALE").unwrap();
    for (a, b) in copy.lines().zip(source.lines()).skip(1) {
        let (a, b): (Vec<&str>, Vec<&str>) = (a.split('\t').collect(), b.split('\t').collect());
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            // Divisive columns go through 1 / (1 / w): equal within an ulp or two.
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(x), Ok(y)) if k == scale => {
                    assert!((x * y - 1.0).abs() < 1e-15, "SCALE {x} vs divisive {y}")
                }
                (Ok(x), Ok(y)) if k >= 3 => {
                    assert!(
                        (x - y).abs() <= 1e-15 * y.abs(),
                        "{}: {x} vs {y}",
                        header[k]
                    )
                }
                // A masked bin: 0 in the source's divisive columns, NaN (empty) in the copy.
                (Err(_), Ok(y)) if k >= 3 && x.is_empty() => assert_eq!(y, 0.0, "{}", header[k]),
                _ => assert_eq!(x, y, "column {}", header[k]),
            }
        }
    }
    assert_eq!(
        run_ok(&["dump", "-t", "chroms", out]),
        run_ok(&["dump", "-t", "chroms", &uri])
    );
}

#[test]
fn coarsened_level_equals_juicers_own_1mb_level() {
    // hic2cool copied Juicer's 1 Mb matrix, binned from the raw contacts: summing our 100 kb pixels
    // into 1 Mb bins must give exactly the same pixels.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("zoom.mcool");
    let out = out.to_str().unwrap();
    let base = data("cooler_test_file.mcool::/resolutions/100000");
    run_ok(&["convert", &base, out, "--resolutions", "100000,1000000"]);
    assert_eq!(
        run_ok(&["dump", &format!("{out}::/resolutions/1000000")]),
        run_ok(&[
            "dump",
            &data("cooler_test_file.mcool::/resolutions/1000000")
        ])
    );
    assert_eq!(
        run_ok(&["dump", &format!("{out}::/resolutions/100000")]),
        run_ok(&["dump", &base])
    );
}

#[test]
fn zoomified_levels_equal_cooler_zoomify() {
    // toy.symm.upper.2.mcool was made by cooler zoomify from its 2 bp level.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("toy.mcool");
    let out = out.to_str().unwrap();
    let toy = data("toy.symm.upper.2.mcool");
    run_ok(&[
        "convert",
        &format!("{toy}::/resolutions/2"),
        out,
        "--resolutions",
        "2B",
    ]);
    for r in [2, 4, 8, 16, 32] {
        assert_eq!(
            run_ok(&["dump", "--join", &format!("{out}::/resolutions/{r}")]),
            run_ok(&["dump", "--join", &format!("{toy}::/resolutions/{r}")]),
            "resolution {r}"
        );
    }
}

#[test]
fn variable_bins_round_trip_through_cool() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("variable.cool");
    let out = out.to_str().unwrap();
    let src = data("cooler_variable_bins_test_file.cool");
    run_ok(&["convert", &src, out]);
    assert_eq!(
        run_ok(&["dump", "--join", out]),
        run_ok(&["dump", "--join", &src])
    );
    let info: serde_json::Value = serde_json::from_str(&run_ok(&["info", "--json", out])).unwrap();
    assert_eq!(info["bin-type"], "variable");
    assert_eq!(info["format-version"], 3);
}

#[test]
fn errors_in_the_input_pixels_name_the_input_and_the_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let write = |name: &str, text: &str| {
        std::fs::write(path(name), text).unwrap();
        path(name)
    };
    let sizes = write("small.sizes", "chr1\t100\nchr2\t50\n");
    // A whole count past i32::MAX: the matrix has integer counts, which cooler stores as int32.
    let big = write("big.bg2", "chr1\t0\t10\tchr2\t10\t20\t3000000000\n");
    let out = path("out.cool");
    let line = run_err(&[
        "convert",
        &big,
        &out,
        "--chrom-sizes",
        &sizes,
        "--bin-size",
        "10",
    ]);
    assert_eq!(
        line,
        format!(
            "contactmap: error: {big}: pixel (0, 11) chr1:0-10 x chr2:10-20: count 3000000000 \
             does not fit cooler's int32 count column (whole numbers from -2147483648 to \
             2147483647)"
        )
    );
    // A chromosome name cooler cannot store, refused before anything is written.
    let sizes = write("utf8.sizes", "chr1\t100\nchr\u{e9}\t50\n");
    let bg2 = write("utf8.bg2", "chr1\t0\t10\tchr1\t0\t10\t1\n");
    let line = run_err(&[
        "convert",
        &bg2,
        &out,
        "--chrom-sizes",
        &sizes,
        "--bin-size",
        "10",
    ]);
    assert_eq!(
        line,
        format!(
            "contactmap: error: {bg2}: chromosome 2 'chr\\u{{e9}}' cannot be written to a .cool: \
             cooler's chromosome names must be ASCII and at most 255 bytes long"
        )
    );
    // A chromosome past cooler's int32 lengths (fuzz finding F-HIC-1, there from a .hic header).
    let sizes = write("long.sizes", "chr1\t100\nchr17\t3000000000\n");
    let bg2 = write("long.bg2", "chr1\t0\t100\tchr1\t0\t100\t1\n");
    let line = run_err(&[
        "convert",
        &bg2,
        &out,
        "--chrom-sizes",
        &sizes,
        "--bin-size",
        "1000000000",
    ]);
    assert_eq!(
        line,
        format!(
            "contactmap: error: {bg2}: chromosome chr17 (3000000000 bp) is too long for cooler's \
             int32 lengths (at most 2147483647 bp)"
        )
    );
    assert!(
        std::fs::read_dir(dir.path()).unwrap().all(|e| !e
            .unwrap()
            .file_name()
            .to_string_lossy()
            .starts_with("out"))
    );
}
