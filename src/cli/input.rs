//! Opening the input matrix of the analyses (balance, expected, normalize, tads), and the inputs
//! several of them share: a weight column, a BED view.
//!
//! The analyses read through [`CheckedCounts`], so that a file with a negative, NaN or infinite
//! count is refused (exit 2, naming the file and the first such pixel) instead of being computed
//! on; `dump`, `info` and `convert` open files as they are.

use std::collections::HashMap;
use std::io::Read;
use std::ops::Range;
use std::path::Path;

use crate::cli::InputArgs;
use crate::error::{Error, Result};
use crate::expected::view::{RegionSpec, View};
use crate::genome::BinTable;
use crate::io::tables::Table;
use crate::io::{self, CheckedCounts, MatrixReader};
use crate::normalize::DiagonalCurve;

/// Open the matrix at `uri` (with the text-input options `input`) for an analysis: its counts are
/// checked as they stream.
pub fn open_for_analysis(uri: &str, input: &InputArgs) -> Result<Box<dyn MatrixReader>> {
    let reader = io::open_matrix(uri, &input.to_options()?)?;
    Ok(Box::new(CheckedCounts::new(reader)))
}

/// The weight column `name`, or an error listing the available ones.
pub fn read_weights(reader: &dyn MatrixReader, name: &str) -> Result<Vec<f64>> {
    let names = reader.weight_names();
    if !names.iter().any(|n| n == name) {
        let available = if names.is_empty() {
            "it has none".to_string()
        } else {
            format!("it has {}", names.join(", "))
        };
        return Err(Error::format(
            reader.source(),
            format!(
                "no weight column '{name}' ({available}); use --weight-name NAME, or --raw for raw counts"
            ),
        ));
    }
    Ok(reader.weights(name)?.values)
}

/// Read a BED view (`chrom start end [name]`, gzip allowed) and check it against the matrix.
pub fn read_view(path: &Path, reader: &dyn MatrixReader) -> Result<View> {
    let mut bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    if bytes.starts_with(&[0x1f, 0x8b]) {
        let mut text = Vec::new();
        flate2::read::MultiGzDecoder::new(bytes.as_slice())
            .read_to_end(&mut text)
            .map_err(|e| Error::io(path, e))?;
        bytes = text;
    }
    let text =
        String::from_utf8(bytes).map_err(|_| Error::format(path, "not a text (UTF-8) BED file"))?;
    let mut specs = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let line_number = index as u64 + 1;
        let trimmed = line.trim_end_matches('\r');
        if trimmed.trim().is_empty()
            || trimmed.starts_with('#')
            || trimmed.starts_with("track")
            || trimmed.starts_with("browser")
        {
            continue;
        }
        let fields: Vec<&str> = if trimmed.contains('\t') {
            trimmed.split('\t').collect()
        } else {
            trimmed.split_whitespace().collect()
        };
        if !(3..=4).contains(&fields.len()) {
            return Err(Error::parse(
                path,
                line_number,
                format!(
                    "expected 3 or 4 columns (chrom start end [name]), found {}",
                    fields.len()
                ),
            ));
        }
        let number = |text: &str, what: &str| {
            text.trim().parse::<u64>().map_err(|_| {
                Error::parse(
                    path,
                    line_number,
                    format!("{what} '{text}' is not a non-negative integer"),
                )
            })
        };
        specs.push(RegionSpec {
            chrom: fields[0].trim().to_string(),
            start_bp: number(fields[1], "start")?,
            end_bp: number(fields[2], "end")?,
            name: fields.get(3).map(|n| n.trim().to_string()),
        });
    }
    View::new(reader.bins(), &specs).map_err(|e| Error::format(path, e.to_string()))
}

/// Per-chromosome curves (for o/e) from column `column` of the cooltools expected-cis table at
/// `path` (regions named by chromosome).
pub fn read_expected_curves(
    path: &str,
    bins: &BinTable,
    column: &str,
) -> Result<Vec<DiagonalCurve>> {
    let table = &Table::read(path)?;
    let (c1, c2) = (table.column("region1")?, table.column("region2")?);
    let (dist, n_valid, value) = (
        table.column("dist")?,
        table.column("n_valid")?,
        table.column(column)?,
    );
    let mut curves: HashMap<usize, DiagonalCurve> = HashMap::new();
    for row in 0..table.len() {
        let (r1, r2) = (table.text(row, c1), table.text(row, c2));
        if r1 != r2 {
            continue;
        }
        let chrom = bins.chrom_id(r1).ok_or_else(|| {
            Error::format(
                table.path(),
                format!("region '{r1}' is not a chromosome of the matrix (regions must be whole chromosomes)"),
            )
        })?;
        let range: Range<usize> = bins.chrom_bins(chrom);
        let curve = curves.entry(chrom).or_insert_with(|| DiagonalCurve {
            expected: vec![f64::NAN; range.len()],
            n_valid: vec![0.0; range.len()],
            bins: range.clone(),
        });
        let d = table.number(row, dist)?;
        if !(d >= 0.0 && d.fract() == 0.0 && (d as usize) < range.len()) {
            return Err(Error::format(
                table.path(),
                format!(
                    "row {}: dist {d} is not a diagonal of {r1} ({} bins)",
                    row + 1,
                    range.len()
                ),
            ));
        }
        curve.expected[d as usize] = table.number(row, value)?;
        curve.n_valid[d as usize] = table.number(row, n_valid)?;
    }
    let mut curves: Vec<DiagonalCurve> = curves.into_values().collect();
    curves.sort_by_key(|c| c.bins.start);
    Ok(curves)
}
