//! What `contactmap info` reports about a matrix file: its attributes as `cooler info` shows
//! them, and the figures computed from its data.

use serde_json::{Map, Value, json};

use crate::error::Result;
use crate::io::matrices::cool::{self, HdfContent};
use crate::io::matrices::hic::HicReader;
use crate::io::matrices::kind::{FileKind, detect_kind};
use crate::io::matrices::open::open_matrix;
use crate::io::matrices::reader::MatrixReader;
use crate::io::matrices::text::options::OpenOptions;
use crate::io::matrices::uri::split_uri;

/// The report of the file or matrix at `uri`, as `cooler info` prints it (the attributes under
/// cooler's names, then `nbins`, `nchroms`, `nnz` and `sum` computed from the data); for a
/// multi-resolution file without a resolution, each level's bins, nnz, sum and weights.
///
/// # Examples
///
/// ```
/// use contactmap::io::info::describe;
///
/// let report = describe("data/CN.mm9.10000kb.cool", &Default::default())?;
/// assert_eq!(report["bin-size"], 10_000_000);
/// let levels = describe("data/cooler_test_file.mcool", &Default::default())?;
/// assert!(levels["levels"].as_array().unwrap().len() > 1);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn describe(uri: &str, options: &OpenOptions) -> Result<Value> {
    let (path, group) = split_uri(uri);
    Ok(match (detect_kind(path)?, group) {
        (FileKind::Hdf5, None) => match cool::inspect(path)? {
            HdfContent::Multires(resolutions) => multires_report(path, &resolutions, "mcool")?,
            HdfContent::Cooler => matrix_report(open_matrix(uri, options)?.as_ref())?,
        },
        (FileKind::Hic, None) => {
            let resolutions = HicReader::list_resolutions(std::path::Path::new(path))?;
            if resolutions.len() == 1 {
                matrix_report(open_matrix(uri, options)?.as_ref())?
            } else {
                multires_report(path, &resolutions, "hic")?
            }
        }
        _ => matrix_report(open_matrix(uri, options)?.as_ref())?,
    })
}

/// Summary of a multi-resolution file: each resolution's bins, nnz and sum.
fn multires_report(path: &str, resolutions: &[u64], kind: &str) -> Result<Value> {
    let mut levels = Vec::new();
    for &r in resolutions {
        let uri = format!("{path}::/resolutions/{r}");
        let reader = open_matrix(&uri, &OpenOptions::default())?;
        let (nnz, sum) = reader.totals()?;
        levels.push(json!({
            "uri": uri,
            "bin-size": r,
            "nbins": reader.bins().n_bins(),
            "nnz": nnz,
            "sum": number(sum),
            "weights": reader.weight_names(),
        }));
    }
    Ok(json!({
        "uri": path,
        "file-format": if kind == "mcool" { "mcool (multi-resolution cooler)" } else { "hic (multi-resolution)" },
        "resolutions": resolutions,
        "levels": levels,
    }))
}

/// Report of one matrix: its attributes, then the figures computed from the data.
fn matrix_report(reader: &dyn MatrixReader) -> Result<Value> {
    let info = reader.info();
    let bins = reader.bins();
    let (nnz, sum) = reader.totals()?;
    let mut map = Map::new();
    map.insert("uri".into(), Value::from(reader.source()));
    map.insert("file-format".into(), Value::from(info.format.clone()));
    let cooler = info.format.starts_with("cool");
    for (key, value) in &info.attributes {
        map.insert(key.clone(), attribute_json(value, cooler));
    }
    match bins.resolution() {
        Some(size) => {
            map.insert("bin-type".into(), Value::from("fixed"));
            map.insert("bin-size".into(), Value::from(size));
        }
        None => {
            map.insert("bin-type".into(), Value::from("variable"));
        }
    }
    map.insert("nbins".into(), Value::from(bins.n_bins()));
    map.insert("nchroms".into(), Value::from(bins.n_chroms()));
    map.insert("nnz".into(), Value::from(nnz));
    map.insert("sum".into(), number(sum));
    map.insert(
        "count-type".into(),
        Value::from(match reader.count_type() {
            crate::matrix::CountType::Integer => "integer",
            crate::matrix::CountType::Float => "float",
        }),
    );
    map.insert("weights".into(), Value::from(reader.weight_names()));
    if !info.resolutions.is_empty() {
        map.insert("resolutions".into(), Value::from(info.resolutions.clone()));
    }
    map.insert(
        "chromosomes".into(),
        Value::Array(
            bins.chroms()
                .iter()
                .map(|c| json!({"name": c.name, "length": c.length_bp}))
                .collect(),
        ),
    );
    if !info.notes.is_empty() {
        map.insert("notes".into(), Value::from(info.notes.clone()));
    }
    Ok(Value::Object(map))
}

/// An attribute as `cooler info` shows it: cooler stores `metadata` (and `id`) as JSON text and
/// decodes every string attribute that parses as JSON (`"null"` is null, `"{}"` an object, `"2"`
/// a number); other strings stay strings. Other formats' attributes are shown as stored.
fn attribute_json(value: &Value, cooler: bool) -> Value {
    match value {
        Value::String(text) if cooler => {
            serde_json::from_str(text).unwrap_or_else(|_| value.clone())
        }
        other => other.clone(),
    }
}

/// An integer-valued sum as a JSON integer, otherwise a float.
fn number(value: f64) -> Value {
    if value.fract() == 0.0 && value.abs() < 9.0e15 {
        Value::from(value as i64)
    } else {
        serde_json::Number::from_f64(value).map_or(Value::Null, Value::Number)
    }
}

/// The report of [`describe`] as the text `contactmap info` prints: one labelled line per
/// attribute (labels in a column of 15), a table of levels for a multi-resolution file, at most
/// 12 chromosomes listed.
///
/// ```
/// use contactmap::io::info::{describe, describe_text};
/// use contactmap::io::OpenOptions;
/// let report = describe("data/cooler_test_file.mcool::/resolutions/100000", &OpenOptions::default())?;
/// let text = describe_text(&report);
/// assert!(text.starts_with("uri "));
/// assert!(text.contains("\nbin-size        100000\n"));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn describe_text(report: &Value) -> String {
    let mut lines = Vec::new();
    let get = |key: &str| report.get(key).cloned().unwrap_or(Value::Null);
    let plain = |v: &Value| match v {
        Value::String(s) => s.clone(),
        Value::Null => "-".into(),
        other => other.to_string(),
    };
    // Labels in one column as wide as the longest, `genome-assembly`.
    let row = |label: &str, value: String| format!("{label:<15} {value}");
    lines.push(row("uri", plain(&get("uri"))));
    lines.push(row("format", plain(&get("file-format"))));
    if let Some(levels) = report.get("levels").and_then(|l| l.as_array()) {
        lines.push(row("resolutions", levels.len().to_string()));
        lines.push("  bin-size        nbins            nnz                sum  weights".into());
        for level in levels {
            lines.push(format!(
                "  {:>8} {:>12} {:>14} {:>18}  {}",
                plain(&level["bin-size"]),
                plain(&level["nbins"]),
                plain(&level["nnz"]),
                plain(&level["sum"]),
                level["weights"]
                    .as_array()
                    .map(|w| w.iter().map(&plain).collect::<Vec<_>>().join(","))
                    .unwrap_or_default()
            ));
        }
        return lines.join("\n") + "\n";
    }
    for key in [
        "genome-assembly",
        "bin-type",
        "bin-size",
        "nbins",
        "nchroms",
        "nnz",
        "sum",
        "count-type",
    ] {
        if let Some(v) = report.get(key) {
            lines.push(row(key, plain(v)));
        }
    }
    if let Some(weights) = report.get("weights").and_then(|w| w.as_array()) {
        let names: Vec<String> = weights.iter().map(&plain).collect();
        lines.push(row(
            "weights",
            if names.is_empty() {
                "none".to_string()
            } else {
                names.join(", ")
            },
        ));
    }
    if let Some(resolutions) = report.get("resolutions").and_then(|r| r.as_array()) {
        let list: Vec<String> = resolutions.iter().map(&plain).collect();
        lines.push(row("resolutions", list.join(", ")));
    }
    if let Some(chroms) = report.get("chromosomes").and_then(|c| c.as_array()) {
        let shown: Vec<String> = chroms
            .iter()
            .take(12)
            .map(|c| format!("{}:{}", plain(&c["name"]), plain(&c["length"])))
            .collect();
        let more = if chroms.len() > 12 {
            format!(" ... ({} more)", chroms.len() - 12)
        } else {
            String::new()
        };
        lines.push(row("chromosomes", format!("{}{more}", shown.join(" "))));
    }
    if let Some(notes) = report.get("notes").and_then(|n| n.as_array()) {
        for note in notes {
            lines.push(row("note", plain(note)));
        }
    }
    lines.join("\n") + "\n"
}
