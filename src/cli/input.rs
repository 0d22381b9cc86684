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
use contactmap::error::{Error, Result};
use contactmap::expected::view::{RegionSpec, View};
use contactmap::expected::CisExpected;
use contactmap::genome::BinTable;
use contactmap::io::tables::Table;
use contactmap::io::{self, CheckedCounts, MatrixReader};
use contactmap::normalize::DiagonalCurve;

/// Open the matrix at `uri` (with the text-input options `input`) for an analysis: its counts are
/// checked as they stream.
pub fn open_for_analysis(uri: &str, input: &InputArgs) -> Result<Box<dyn MatrixReader>> {
    let reader = io::open_matrix(uri, &input.to_options()?)?;
    Ok(Box::new(CheckedCounts::new(reader)))
}

/// The weight column `name`, or [`missing_weights`]' error: `option` is the command's option
/// that names a column (`--weight-name`, `--balanced`), `raw_option` whether it has `--raw`.
pub fn read_weights(
    reader: &dyn MatrixReader,
    name: &str,
    option: &str,
    raw_option: bool,
) -> Result<Vec<f64>> {
    if !reader.weight_names().iter().any(|n| n == name) {
        return Err(missing_weights(reader, name, option, raw_option));
    }
    Ok(reader.weights(name)?.values)
}

/// The one wording of "this map has no weights" (or not the column asked for), with the command
/// that makes them for this kind of file: `balance --store` for a cooler, a .cool copy for a
/// .hic or a text table; the columns it has, for `option`; `--raw` where the command has it.
pub fn missing_weights(
    reader: &dyn MatrixReader,
    name: &str,
    option: &str,
    raw_option: bool,
) -> Error {
    let uri = reader.source();
    let names = reader.weight_names();
    let kind = io::detect_kind(io::split_uri(uri).0).unwrap_or(io::FileKind::Text);
    let store = if name == "weight" {
        String::new()
    } else {
        format!(" --name {name}")
    };
    let make = match kind {
        io::FileKind::Hdf5 if reader.info().format.starts_with("cool") => {
            format!("balance it first: `contactmap balance {uri} --store{store}`")
        }
        _ => format!(
            "balance a .cool copy: `contactmap convert {uri} copy.cool`, then `contactmap balance \
             copy.cool --store{store}`"
        ),
    };
    let raw = if raw_option {
        "; or pass --raw for raw counts"
    } else {
        ""
    };
    let message = if names.is_empty() {
        format!("this map has no weights (no balancing weight column '{name}'): {make}{raw}")
    } else {
        format!(
            "this map has no weight column '{name}' (it has {}): choose one with {option} NAME, \
             or {make}{raw}",
            names.join(", ")
        )
    };
    Error::format(uri, message)
}

/// Open `uri` for an analysis of balanced values: the reader, the weight column `weight_name`
/// (an error naming the available ones when it is missing) and the view (`view`, or whole
/// chromosomes).
pub fn open_balanced(
    uri: &str,
    input: &InputArgs,
    weight_name: &str,
    view: Option<&Path>,
) -> Result<(Box<dyn MatrixReader>, Vec<f64>, View)> {
    let reader = open_for_analysis(uri, input)?;
    let weights = read_weights(reader.as_ref(), weight_name, "--weight-name", false)?;
    let view = match view {
        Some(path) => read_view(path, reader.as_ref())?,
        None => View::chromosomes(reader.bins()),
    };
    Ok((reader, weights, view))
}

/// A per-bin track given as `FILE:COLUMN` to the option `option` (a header name, or a 1-based
/// column number for a bedGraph), on `bins`, NaN at bins without a weight (cooltools'
/// `align_track_with_cooler(mask_clr_bad_bins=True)`); also the column's name.
pub fn track_argument(
    argument: &str,
    option: &str,
    bins: &BinTable,
    weights: &[f64],
) -> Result<(Vec<f64>, String)> {
    let (path, column) = file_column(argument, option, None)?;
    let track = contactmap::io::tables::track_on_bins(Path::new(path), column, bins)?;
    Ok((mask_unweighted(track, weights), column.to_string()))
}

/// Split a `FILE:COLUMN` option value (`option` names it in the error); without a `:COLUMN`,
/// `default` when given (a `:` inside the file's path, as in `dir:x/file`, is not a column).
pub fn file_column<'a>(
    argument: &'a str,
    option: &str,
    default: Option<&'a str>,
) -> Result<(&'a str, &'a str)> {
    match (argument.rsplit_once(':'), default) {
        (Some((path, column)), _) if !column.is_empty() && !column.contains('/') => {
            Ok((path, column))
        }
        (_, Some(column)) => Ok((argument, column)),
        _ => Err(Error::Invalid(format!(
            "{option} '{argument}': expected FILE:COLUMN (a header name or a 1-based column number)"
        ))),
    }
}

/// `track` with NaN at the bins whose weight is not finite (cooltools masks a track on the
/// map's bad bins).
pub fn mask_unweighted(mut track: Vec<f64>, weights: &[f64]) -> Vec<f64> {
    for (value, w) in track.iter_mut().zip(weights) {
        if !w.is_finite() {
            *value = f64::NAN;
        }
    }
    track
}

/// The inputs of an analysis besides the pixels: the weight column `weight_name` (none for raw
/// counts) and the view (the BED file `view`, or whole chromosomes).
pub fn weights_and_view(
    reader: &dyn MatrixReader,
    raw: bool,
    weight_name: &str,
    view: Option<&Path>,
) -> Result<(Option<Vec<f64>>, View)> {
    let weights = if raw {
        None
    } else {
        Some(read_weights(reader, weight_name, "--weight-name", true)?)
    };
    let view = match view {
        Some(path) => read_view(path, reader)?,
        None => View::chromosomes(reader.bins()),
    };
    Ok((weights, view))
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
/// `path` (regions named by chromosome); the default column is `balanced.avg`, or `count.avg`
/// for raw counts.
pub fn read_expected_curves(
    path: &str,
    bins: &BinTable,
    column: Option<&str>,
    raw: bool,
) -> Result<Vec<DiagonalCurve>> {
    let column = column.unwrap_or(if raw { "count.avg" } else { "balanced.avg" });
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

/// A cooltools `expected-cis` table (as `cooltools expected-cis` or `contactmap expected` write
/// it) read back for the P(s) analyses, and the median length of its regions in bp (each region
/// has one row per diagonal, so its length is its number of rows times the bin size). The
/// smoothed columns are not read; the averages are the table's own.
pub fn read_cis_expected(path: &str) -> Result<(CisExpected, f64)> {
    let table = Table::read(path)?;
    let (c1, c2) = (table.column("region1")?, table.column("region2")?);
    let dist_column = table.column("dist")?;
    let dist_bp_column = table.column("dist_bp")?;
    let (n_total_column, n_valid_column) = (table.column("n_total")?, table.column("n_valid")?);
    let count_sum_column = table.column("count.sum")?;
    let balanced_sum_column = table.column("balanced.sum").ok();
    let count_avg_column = table.column("count.avg")?;
    let balanced_avg_column = match balanced_sum_column {
        Some(_) => Some(table.column("balanced.avg")?),
        None => None,
    };
    if table.is_empty() {
        return Err(Error::format(path, "the expected table has no rows"));
    }
    let bad_row = |row: usize, message: String| Error::parse(path, row as u64 + 2, message);
    let whole = |row: usize, column: usize| -> Result<u64> {
        let value = table.number(row, column)?;
        if value >= 0.0 && value.fract() == 0.0 && value < 2f64.powi(53) {
            Ok(value as u64)
        } else {
            Err(bad_row(
                row,
                format!(
                    "'{}' in column '{}' is not a non-negative integer",
                    table.text(row, column),
                    table.header()[column]
                ),
            ))
        }
    };
    let mut out = CisExpected {
        bin_size_bp: 0,
        region_names: Vec::new(),
        region: Vec::with_capacity(table.len()),
        dist: Vec::with_capacity(table.len()),
        dist_bp: Vec::with_capacity(table.len()),
        n_total: Vec::with_capacity(table.len()),
        n_valid: Vec::with_capacity(table.len()),
        count_sum: Vec::with_capacity(table.len()),
        balanced_sum: balanced_sum_column.map(|_| Vec::with_capacity(table.len())),
        count_avg: Vec::with_capacity(table.len()),
        balanced_avg: balanced_avg_column.map(|_| Vec::with_capacity(table.len())),
        avg_smoothed: None,
        avg_smoothed_agg: None,
    };
    let mut rows_per_region: Vec<u64> = Vec::new();
    for row in 0..table.len() {
        let (r1, r2) = (table.text(row, c1), table.text(row, c2));
        if r1 != r2 {
            return Err(bad_row(
                row,
                format!("region1 '{r1}' differs from region2 '{r2}': a trans table, not the cis expected (contactmap expected, cooltools expected-cis)"),
            ));
        }
        if out.region_names.last().map(String::as_str) != Some(r1) {
            if out.region_names.iter().any(|name| name == r1) {
                return Err(bad_row(
                    row,
                    format!("the rows of region '{r1}' are not together"),
                ));
            }
            out.region_names.push(r1.to_string());
            rows_per_region.push(0);
        }
        let region = out.region_names.len() - 1;
        rows_per_region[region] += 1;
        let (dist, dist_bp) = (whole(row, dist_column)?, whole(row, dist_bp_column)?);
        let expected_dist = rows_per_region[region] - 1;
        if dist != expected_dist {
            return Err(bad_row(
                row,
                format!("dist {dist} where {expected_dist} was expected (one row per diagonal of each region, in order)"),
            ));
        }
        if let Some(size) = dist_bp.checked_div(dist) {
            if out.bin_size_bp == 0 {
                out.bin_size_bp = size;
            }
            if dist.checked_mul(out.bin_size_bp) != Some(dist_bp) || out.bin_size_bp == 0 {
                return Err(bad_row(
                    row,
                    format!(
                        "dist_bp {dist_bp} is not dist {dist} times the bin size {} of the rows above",
                        out.bin_size_bp
                    ),
                ));
            }
        }
        out.region.push(region as u32);
        out.dist.push(dist);
        out.dist_bp.push(dist_bp);
        out.n_total.push(whole(row, n_total_column)?);
        out.n_valid.push(whole(row, n_valid_column)?);
        out.count_sum.push(table.number(row, count_sum_column)?);
        out.count_avg.push(table.number(row, count_avg_column)?);
        if let (Some(sums), Some(column)) = (out.balanced_sum.as_mut(), balanced_sum_column) {
            sums.push(table.number(row, column)?);
        }
        if let (Some(avgs), Some(column)) = (out.balanced_avg.as_mut(), balanced_avg_column) {
            avgs.push(table.number(row, column)?);
        }
    }
    if out.bin_size_bp == 0 {
        return Err(Error::format(
            path,
            "every region has a single diagonal: no distances to plot",
        ));
    }
    let mut lengths: Vec<u64> = rows_per_region
        .iter()
        .map(|n| n * out.bin_size_bp)
        .collect();
    lengths.sort_unstable();
    let n = lengths.len();
    let median = if n % 2 == 1 {
        lengths[n / 2] as f64
    } else {
        (lengths[n / 2 - 1] + lengths[n / 2]) as f64 / 2.0
    };
    Ok((out, median))
}

/// The genome assembly an input names (`genome-assembly` of a cooler, the genome id of a .hic),
/// for the outputs made from it; `None` when unknown or when the id is a chrom.sizes path.
pub fn input_assembly(reader: &dyn MatrixReader) -> Option<String> {
    reader
        .info()
        .attributes
        .iter()
        .find(|(k, _)| k == "genome-assembly" || k == "genome_id")
        .and_then(|(_, v)| v.as_str())
        .filter(|id| !id.is_empty() && *id != "unknown" && !id.contains('/'))
        .map(str::to_string)
}
