//! The room against pydeseq2 0.5.4 run to convergence on the same count matrices
//! (`scripts/diff_references.py`, data/diff/), and against closed forms.

use std::io::Read;

use ndarray::Array2;

use super::*;

/// A case's counts and pydeseq2's columns.
struct Case {
    counts: Array2<f64>,
    design: Design,
    columns: Vec<(String, Vec<f64>)>,
    summary: serde_json::Value,
}

fn case(name: &str) -> Case {
    let path = format!("data/diff/{name}.tsv.gz");
    let mut text = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(&path).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split('\t').collect();
    let n_samples = header
        .iter()
        .take_while(|h| h.starts_with(['A', 'B']))
        .count();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split('\t').map(|v| v.parse::<f64>().unwrap()).collect())
        .collect();
    let counts = Array2::from_shape_fn((rows.len(), n_samples), |(g, j)| rows[g][j]);
    let conditions: Vec<usize> = header[..n_samples]
        .iter()
        .map(|h| usize::from(h.starts_with('B')))
        .collect();
    let columns = header[n_samples..]
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let values = rows.iter().map(|r| r[n_samples + k]).collect();
            (name.to_string(), values)
        })
        .collect();
    let summary =
        serde_json::from_str(&std::fs::read_to_string(format!("data/diff/{name}.json")).unwrap())
            .unwrap();
    Case {
        counts,
        design: Design::conditions(&conditions, &["A", "B"]).unwrap(),
        columns,
        summary,
    }
}

impl Case {
    fn column(&self, name: &str) -> &[f64] {
        &self.columns.iter().find(|(n, _)| n == name).unwrap().1
    }
}

/// Largest relative difference over the features where both are finite, and the number of
/// features where only one is.
fn worst(ours: &[f64], theirs: &[f64]) -> (f64, usize, usize) {
    worst_above(ours, theirs, 0.0)
}

/// [`worst`] over the features where either value is at least `floor` (dispersions both under
/// 100·min_disp are pydeseq2's "at the minimum": the likelihood cannot tell them apart, and the
/// trend and the prior leave them out).
fn worst_above(ours: &[f64], theirs: &[f64], floor: f64) -> (f64, usize, usize) {
    let mut worst = (0.0, 0, 0);
    for (g, (a, b)) in ours.iter().zip(theirs).enumerate() {
        if a.max(*b) < floor {
            continue;
        }
        if a.is_nan() != b.is_nan() {
            worst.2 += 1;
            continue;
        }
        if a.is_nan() {
            continue;
        }
        let relative = (a - b).abs() / b.abs().max(1e-300);
        if relative > worst.0 {
            worst = (relative, g, worst.2);
        }
    }
    worst
}

#[test]
fn statistics_equal_pydeseq2_run_to_convergence() {
    for name in ["two_by_two", "three_by_three"] {
        let case = case(name);
        let fit = fit(case.counts.view(), &case.design, &Params::default()).unwrap();
        let results = results(
            case.counts.view(),
            &fit,
            &case.design,
            &case.design.contrast(1),
            true,
        );
        let summary = &case.summary;
        let factors: Vec<f64> = summary["size_factors"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let (size_error, _, _) = worst(&fit.size_factors, &factors);
        assert!(size_error < 1e-12, "{name}: size factors {size_error:e}");
        let Trend::Parametric { a0, a1 } = fit.trend else {
            panic!("{name}: a parametric trend")
        };
        let trend = &summary["trend"];
        let (want0, want1) = (trend["a0"].as_f64().unwrap(), trend["a1"].as_f64().unwrap());
        assert!((a0 / want0 - 1.0).abs() < 1e-6, "{name}: a0 {a0} {want0}");
        assert!((a1 / want1 - 1.0).abs() < 1e-6, "{name}: a1 {a1} {want1}");
        let prior = summary["prior_variance"].as_f64().unwrap();
        assert!(
            (fit.prior_variance / prior - 1.0).abs() < 1e-6,
            "{name}: prior"
        );
        let outliers: Vec<f64> = fit
            .dispersion_outlier
            .iter()
            .map(|&o| f64::from(u8::from(o)))
            .collect();
        assert_eq!(
            outliers,
            case.column("outlier"),
            "{name}: dispersion outliers"
        );
        for (ours, theirs) in [
            (&fit.genewise_dispersions, "genewise"),
            (&fit.map_dispersions, "map"),
            (&results.log2_fold_change, "log2FoldChange"),
            (&results.lfc_se, "lfcSE"),
            (&results.p_value, "pvalue"),
            (&results.q_value, "padj"),
        ] {
            let floor = if theirs == "genewise" { 1e-6 } else { 0.0 };
            let (error, at, only_one) = worst_above(ours, case.column(theirs), floor);
            eprintln!("{name} {theirs}: largest relative difference {error:.2e} (feature {at})");
            assert_eq!(only_one, 0, "{name} {theirs}: NaN in one only");
            assert!(error < 1e-6, "{name} {theirs}: {error:e} at feature {at}");
        }
    }
}

#[test]
fn bad_designs_are_refused_with_the_reason() {
    let no_b = Design::conditions(&[0, 0, 0], &["A", "B"]).unwrap_err();
    assert_eq!(no_b.to_string(), "condition B has no sample");
    let no_replicate = Design::conditions(&[0, 1], &["A", "B"]).unwrap_err();
    assert!(
        no_replicate
            .to_string()
            .contains("no condition has a replicate")
    );
    let design = Design::conditions(&[0, 0, 1, 1], &["A", "B"]).unwrap();
    let fractional = ndarray::array![[1.0, 2.0, 3.5, 4.0]];
    let error = fit(fractional.view(), &design, &Params::default()).unwrap_err();
    assert_eq!(
        error.to_string(),
        "feature 1, sample 3: count 3.5 is not a non-negative integer"
    );
}

#[test]
fn normalisation_factors_equal_to_the_size_factors_change_nothing() {
    let case = case("three_by_three");
    let by_size = fit(case.counts.view(), &case.design, &Params::default()).unwrap();
    let factors = by_size.factors.clone();
    let given = fit_normalized(
        case.counts.view(),
        &case.design,
        &Params::default(),
        Normalization::Factors(factors.view()),
    )
    .unwrap();
    assert_eq!(given.dispersions, by_size.dispersions);
    assert_eq!(given.coefficients, by_size.coefficients);
    assert!(given.size_factors.iter().all(|s| s.is_nan()));
    let mut wrong = factors.clone();
    wrong[[4, 2]] = 0.0;
    let error = fit_normalized(
        case.counts.view(),
        &case.design,
        &Params::default(),
        Normalization::Factors(wrong.view()),
    )
    .unwrap_err();
    assert_eq!(
        error.to_string(),
        "feature 5, sample 3: normalisation factor 0 is not positive"
    );
}

/// A feature whose expected count doubles in condition B (its offsets there twice as large)
/// has the same fit less ln 2 on the condition's coefficient: the offset absorbs it.
#[test]
fn an_offset_moves_the_fold_change_by_its_log() {
    let counts = [31.0, 40.0, 22.0, 90.0, 71.0, 84.0];
    let design = Design::conditions(&[0, 0, 0, 1, 1, 1], &["A", "B"]).unwrap();
    let offsets = [0.9, 1.2, 0.8, 1.1, 0.95, 1.05];
    let doubled: Vec<f64> = offsets
        .iter()
        .enumerate()
        .map(|(j, s)| if j >= 3 { 2.0 * s } else { *s })
        .collect();
    let fit_with = |o: &[f64]| glm::irls(&counts, o, &design.matrix, 2, 0.05, 0.5, 1e-14);
    let (plain, shifted) = (fit_with(&offsets), fit_with(&doubled));
    assert!((plain.beta[0] - shifted.beta[0]).abs() < 1e-7);
    assert!((plain.beta[1] - shifted.beta[1] - std::f64::consts::LN_2).abs() < 1e-7);
}
