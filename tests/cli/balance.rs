//! `contactmap balance` against the peer tools' reference outputs: cooler 0.11 `balance_cooler`
//! weights (`data/reference/numerics/*.ice_{gw,cis}.weights.tsv.gz`, written with `%.10g`), the ICE
//! `weight` columns stored in the fixtures by cooler, and Juicer's KR / VC / VC_SQRT vectors stored
//! by hic2cool in the dm6 .mcool.

use std::io::Read;

use crate::{data, run, run_err, run_ok};

const DM6: &str = "cooler_test_file.mcool::/resolutions/100000";
const MM9: &str = "CN.mm9.10000kb.cool";
const GM12878: &str = "hg19.GM12878-MboI.matrix.2000kb.cool";

/// Relative tolerance against cooler's weights (the references keep 10 significant digits).
const COOLER_TOLERANCE: f64 = 1e-6;

/// Parse a table with a header and `chrom start end` first; return the column `name` (`nan` or an
/// empty field as NaN) with the bin coordinates.
fn column(text: &str, name: &str) -> (Vec<String>, Vec<f64>) {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header line").split('\t').collect();
    let index = header
        .iter()
        .position(|h| *h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    let mut bins = Vec::new();
    let mut values = Vec::new();
    for line in lines {
        let fields: Vec<&str> = line.split('\t').collect();
        bins.push(fields[..3].join("\t"));
        let field = fields[index];
        values.push(if field.is_empty() || field == "nan" {
            f64::NAN
        } else {
            field.parse().expect("a number")
        });
    }
    (bins, values)
}

fn gunzip(path: &str) -> String {
    let mut text = String::new();
    flate2::read::MultiGzDecoder::new(std::fs::File::open(path).expect("reference file"))
        .read_to_string(&mut text)
        .expect("gzip text");
    text
}

/// Same bins, same NaN masks, and a relative difference below `tolerance` everywhere; returns
/// the largest relative difference.
fn assert_weights_match(ours: &str, reference: &str, name: &str, tolerance: f64) -> f64 {
    let (our_bins, our_values) = column(ours, "weight");
    let (ref_bins, ref_values) = column(reference, name);
    assert_eq!(our_bins, ref_bins, "bin tables differ");
    let mut worst: f64 = 0.0;
    for (k, (a, b)) in our_values.iter().zip(&ref_values).enumerate() {
        assert_eq!(
            a.is_nan(),
            b.is_nan(),
            "bin {k} ({}): ours {a}, reference {b}",
            our_bins[k]
        );
        if !a.is_nan() {
            let relative = (a - b).abs() / b.abs();
            assert!(
                relative < tolerance,
                "bin {k} ({}): ours {a}, reference {b}, relative difference {relative:e}",
                our_bins[k]
            );
            worst = worst.max(relative);
        }
    }
    assert!(ref_values.iter().any(|v| !v.is_nan()));
    worst
}

fn check_against_cooler(key: &str, input: &str) {
    for (mode, flags) in [("gw", vec![]), ("cis", vec!["--cis-only"])] {
        let uri = data(input);
        let mut args = vec!["balance", uri.as_str()];
        args.extend(flags);
        let ours = run_ok(&args);
        let reference = gunzip(&data(&format!(
            "reference/numerics/{key}.ice_{mode}.weights.tsv.gz"
        )));
        assert_weights_match(&ours, &reference, "weight", COOLER_TOLERANCE);
    }
}

#[test]
fn ice_equals_cooler_on_dm6_100kb() {
    check_against_cooler("dm6_100kb", DM6);
}

#[test]
fn ice_equals_cooler_on_mm9_10mb() {
    check_against_cooler("mm9_CN_10Mb", MM9);
}

#[test]
fn ice_equals_cooler_on_gm12878_2mb() {
    check_against_cooler("gm12878_2Mb", GM12878);
}

#[test]
fn ice_reproduces_the_weight_columns_cooler_stored() {
    for input in [MM9, DM6] {
        let ours = run_ok(&["balance", &data(input)]);
        let stored = run_ok(&[
            "dump",
            "-t",
            "bins",
            "-H",
            "--float-format",
            ".17g",
            &data(input),
        ]);
        assert_weights_match(&ours, &stored, "weight", COOLER_TOLERANCE);
    }
}

#[test]
fn vc_vc_sqrt_kr_and_scale_per_chromosome_equal_juicers_vectors() {
    // hic2cool stored Juicer's divisive vectors, which `dump -t bins` prints as stored: inverted
    // here to multiplicative weights (0 marks a masked bin).
    let stored = run_ok(&[
        "dump",
        "-t",
        "bins",
        "-H",
        "--float-format",
        ".17g",
        &data(DM6),
    ]);
    let stored: String = stored
        .lines()
        .enumerate()
        .map(|(row, line)| {
            let fields: Vec<String> = line
                .split('\t')
                .enumerate()
                .map(|(k, field)| match field.parse::<f64>() {
                    Ok(v) if row > 0 && k >= 3 && v > 0.0 => format!("{:e}", 1.0 / v),
                    Ok(_) if row > 0 && k >= 3 => "nan".to_string(),
                    _ => field.to_string(),
                })
                .collect();
            fields.join("\t") + "\n"
        })
        .collect();
    for (method, column_name) in [
        ("vc", "VC"),
        ("vc-sqrt", "VC_SQRT"),
        ("kr", "KR"),
        ("scale", "SCALE"),
    ] {
        let ours = run_ok(&["balance", &data(DM6), "--method", method, "--cis-only"]);
        assert_weights_match(&ours, &stored, column_name, 1e-9);
    }
}

#[test]
fn the_summary_reports_convergence_on_stderr() {
    let out = run(&["balance", &data(MM9)]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.starts_with("# method=ice scope=genome-wide converged=true"),
        "{stderr}"
    );
    assert!(
        stderr.contains("scale=") && stderr.contains("var="),
        "{stderr}"
    );
    let out = run(&["balance", &data(DM6), "--cis-only"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    // dm6 chrM has no contact left after filtering: NaN weights, converged, scale NaN (as cooler).
    assert!(
        stderr.contains("# chrM converged=true n_iterations=1 scale=NaN var=0e0"),
        "{stderr}"
    );
    let (bins, weights) = column(&String::from_utf8_lossy(&out.stdout), "weight");
    for (bin, w) in bins.iter().zip(&weights) {
        if bin.starts_with("chrM\t") {
            assert!(w.is_nan(), "{bin}: {w}");
        }
    }
}

#[test]
fn streamed_pixels_give_the_same_weights_as_in_memory() {
    let uri = data(DM6);
    for flags in [
        vec!["--cis-only"],
        vec!["--method", "kr"],
        vec!["--method", "vc"],
        vec!["--method", "scale", "--cis-only"],
    ] {
        let mut args = vec!["balance", uri.as_str()];
        args.extend(&flags);
        let memory = run_ok(&args);
        args.extend(["--max-memory", "0"]);
        let streamed = run_ok(&args);
        assert_weights_match(&streamed, &memory, "weight", 1e-12);
    }
}

#[test]
fn store_with_the_resolution_option_writes_into_that_level() {
    let dir = tempfile::tempdir().unwrap();
    let copy = dir.path().join("copy.mcool");
    std::fs::copy(data("cooler_test_file.mcool"), &copy).unwrap();
    let file = copy.to_string_lossy().into_owned();
    let level = format!("{file}::/resolutions/100000");
    let table = run_ok(&["balance", &level]);
    run_ok(&[
        "balance",
        &file,
        "--resolution",
        "100000",
        "--store",
        "--name",
        "ice2",
    ]);
    let bins = run_ok(&["dump", "-t", "bins", "-H", "--float-format", ".17g", &level]);
    assert_eq!(assert_weights_match(&table, &bins, "ice2", 1e-15), 0.0);
    let other = format!("{file}::/resolutions/1000000");
    let bins = run_ok(&["dump", "-t", "bins", "-H", &other]);
    assert!(!bins.lines().next().unwrap().contains("ice2"), "{bins}");
}

#[test]
fn store_writes_a_column_that_dump_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let copy = dir.path().join("copy.mcool");
    std::fs::copy(data("cooler_test_file.mcool"), &copy).unwrap();
    let uri = format!("{}::/resolutions/100000", copy.display());
    let table = run_ok(&["balance", &uri]);
    let out = run(&["balance", &uri, "--store", "--name", "ice2"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty());
    let bins = run_ok(&["dump", "-t", "bins", "-H", "--float-format", ".17g", &uri]);
    let worst = assert_weights_match(&table, &bins, "ice2", 1e-15);
    assert_eq!(worst, 0.0);
    // cooler's attributes are on the column.
    let file = hdf5::File::open(&copy).unwrap();
    let dataset = file.dataset("resolutions/100000/bins/ice2").unwrap();
    let attr_bool = |name: &str| dataset.attr(name).unwrap().read_scalar::<bool>().unwrap();
    let attr_i64 = |name: &str| dataset.attr(name).unwrap().read_scalar::<i64>().unwrap();
    assert!(attr_bool("converged"));
    assert!(!attr_bool("cis_only"));
    assert!(!attr_bool("divisive_weights"));
    assert_eq!(attr_i64("ignore_diags"), 2);
    assert_eq!(attr_i64("min_nnz"), 10);
    assert_eq!(attr_i64("mad_max"), 5);
    let scale = dataset.attr("scale").unwrap().read_scalar::<f64>().unwrap();
    // cooler stored the same scale with its own weight column.
    let cooler_scale = file
        .dataset("resolutions/100000/bins/weight")
        .unwrap()
        .attr("scale")
        .unwrap()
        .read_scalar::<f64>()
        .unwrap();
    assert!((scale - cooler_scale).abs() < 1e-9 * cooler_scale);
}

#[test]
fn store_refuses_an_existing_column_without_force_and_leaves_the_file_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let copy = dir.path().join("copy.cool");
    std::fs::copy(data(MM9), &copy).unwrap();
    let path = copy.to_str().unwrap();
    let before = std::fs::read(&copy).unwrap();
    let error = run_err(&["balance", path, "--store", "--cis-only"]);
    assert!(
        error.contains("bins/weight already exists") && error.contains("--force"),
        "{error}"
    );
    assert_eq!(std::fs::read(&copy).unwrap(), before);
    // With --force the column is replaced: now the cis-only weights, with per-chromosome attributes.
    run_ok(&["balance", path, "--store", "--cis-only", "--force"]);
    let cis = run_ok(&["balance", path, "--cis-only"]);
    let stored = run_ok(&["dump", "-t", "bins", "-H", "--float-format", ".17g", path]);
    assert_weights_match(&cis, &stored, "weight", 1e-15);
    let file = hdf5::File::open(&copy).unwrap();
    let dataset = file.dataset("bins/weight").unwrap();
    let n_chroms = file.dataset("chroms/length").unwrap().size();
    let scales = dataset.attr("scale").unwrap().read_raw::<f64>().unwrap();
    assert_eq!(scales.len(), n_chroms);
    assert!(
        dataset
            .attr("cis_only")
            .unwrap()
            .read_scalar::<bool>()
            .unwrap()
    );
}

#[test]
fn bad_inputs_fail_with_one_clear_line() {
    let error = run_err(&["balance", "no/such/file.cool"]);
    assert!(error.contains("no/such/file.cool"), "{error}");
    let dir = tempfile::tempdir().unwrap();
    let bed = dir.path().join("blacklist.bed");
    std::fs::write(&bed, "chr1\t0\t20000000\nchrNope\t0\t100\n").unwrap();
    let error = run_err(&["balance", &data(MM9), "--blacklist", bed.to_str().unwrap()]);
    assert!(
        error.contains("blacklist.bed:2") && error.contains("chrNope"),
        "{error}"
    );
    let error = run_err(&["balance", &data("hic_test_file.hic"), "--store"]);
    assert!(error.contains("--store"), "{error}");
    let error = run_err(&["balance", &data(MM9), "--tol", "0"]);
    assert!(error.contains("--tol"), "{error}");
}

#[test]
fn a_blacklist_masks_the_bins_it_overlaps() {
    let dir = tempfile::tempdir().unwrap();
    let bed = dir.path().join("blacklist.bed");
    std::fs::write(&bed, "track name=gaps\nchr2\t5000000\t25000000\n").unwrap();
    let ours = run_ok(&["balance", &data(MM9), "--blacklist", bed.to_str().unwrap()]);
    let (bins, weights) = column(&ours, "weight");
    for (bin, w) in bins.iter().zip(&weights) {
        let masked = [
            "chr2\t0\t10000000",
            "chr2\t10000000\t20000000",
            "chr2\t20000000\t30000000",
        ]
        .contains(&bin.as_str());
        if masked {
            assert!(w.is_nan(), "{bin}");
        }
    }
    assert!(weights.iter().filter(|w| !w.is_nan()).count() > 200);
}

#[test]
fn unconverged_weights_are_written_with_a_warning_but_not_stored_unless_asked() {
    let out = run(&["balance", &data(DM6), "--max-iters", "3"]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("WARNING") && stderr.contains("did not converge"),
        "{stderr}"
    );
    assert!(stderr.contains("converged=false"), "{stderr}");
    let (_, weights) = column(&String::from_utf8_lossy(&out.stdout), "weight");
    assert_eq!(weights.len(), 1380);

    let dir = tempfile::tempdir().unwrap();
    let copy = dir.path().join("copy.cool");
    std::fs::copy(data(MM9), &copy).unwrap();
    let path = copy.to_str().unwrap();
    let before = std::fs::read(&copy).unwrap();
    let error = run_err(&["balance", path, "--store", "--force", "--max-iters", "2"]);
    assert!(
        error.contains("did not converge") && error.contains("--store-unconverged"),
        "{error}"
    );
    assert_eq!(std::fs::read(&copy).unwrap(), before);
    run_ok(&[
        "balance",
        path,
        "--store",
        "--force",
        "--max-iters",
        "2",
        "--store-unconverged",
    ]);
    let file = hdf5::File::open(&copy).unwrap();
    let converged = file
        .dataset("bins/weight")
        .unwrap()
        .attr("converged")
        .unwrap()
        .read_scalar::<bool>()
        .unwrap();
    assert!(!converged);
}

#[test]
fn an_all_zero_chromosome_gives_nan_weights_and_nan_expected_without_failing() {
    // chrB has bins but no contact at all: cooler masks its bins (NaN weights); its expected is
    // NaN (0 / 0 valid pixels), and normalize writes nothing for it.
    let dir = tempfile::tempdir().unwrap();
    let bed = dir.path().join("bins.bed");
    let mut bins = String::new();
    for (chrom, n) in [("chrA", 30), ("chrB", 10)] {
        for k in 0..n {
            bins.push_str(&format!("{chrom}\t{}\t{}\n", k * 100, (k + 1) * 100));
        }
    }
    std::fs::write(&bed, bins).unwrap();
    let mut pixels = String::new();
    for i in 0..30u64 {
        for j in i..(i + 6).min(30) {
            pixels.push_str(&format!("{i}\t{j}\t{}\n", 50 / (j - i + 1) + (i * j) % 3));
        }
    }
    let coo = dir.path().join("m.coo");
    std::fs::write(&coo, pixels).unwrap();
    let cool = dir.path().join("m.cool");
    let (coo, bed, cool) = (
        coo.to_str().unwrap(),
        bed.to_str().unwrap(),
        cool.to_str().unwrap(),
    );
    run_ok(&["convert", coo, cool, "--format", "coo", "--bins", bed]);
    run_ok(&["balance", cool, "--store", "--min-nnz", "1"]);
    let table = run_ok(&["dump", "-t", "bins", "-H", cool]);
    let (_, weights) = column(&table, "weight");
    assert!(
        weights[30..].iter().all(|w| w.is_nan()),
        "chrB must be masked"
    );
    assert!(weights[..30].iter().filter(|w| !w.is_nan()).count() > 20);
    let expected = run_ok(&["expected", cool]);
    let chr_b: Vec<&str> = expected
        .lines()
        .filter(|l| l.starts_with("chrB\t"))
        .collect();
    assert_eq!(chr_b.len(), 10);
    assert!(
        chr_b.iter().all(|l| l.split('\t').nth(6) == Some("0")),
        "n_valid 0 on chrB"
    );
    let oe = run_ok(&["normalize", cool, "-", "--to", "coo"]);
    assert!(
        oe.lines()
            .all(|l| l.split('\t').next().unwrap().parse::<usize>().unwrap() < 30)
    );
}
