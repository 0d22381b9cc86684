//! Opening the input matrix of the analyses (balance, expected, normalize, tads), and the inputs
//! several of them share: a weight column, a BED view.
//!
//! The analyses read through [`CheckedCounts`], so that a file with a negative, NaN or infinite
//! count is refused (exit 2, naming the file and the first such pixel) instead of being computed
//! on; `dump`, `info` and `convert` open files as they are.

use std::path::Path;

use crate::cli::args::InputArgs;
use contactmap::error::{Error, Result};
use contactmap::expected::expected_to_divide_by;
use contactmap::genome::BinTable;
use contactmap::genome::View;
use contactmap::io::tables::Table;
use contactmap::io::{self, CheckedCounts, MatrixReader};

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
        Some(path) => contactmap::io::bed::read_view(path, reader.bins())?,
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

/// The phasing track of `--phasing-track FILE:COLUMN` or `--fasta` (the bins' GC content), on
/// `bins`, NaN where `weights` are; `None` when neither is given.
pub fn phasing_track(
    track: Option<&str>,
    fasta: Option<&Path>,
    bins: &BinTable,
    weights: &[f64],
) -> Result<Option<Vec<f64>>> {
    Ok(match (track, fasta) {
        (Some(track), _) => Some(track_argument(track, "--phasing-track", bins, weights)?.0),
        (None, Some(fasta)) => Some(mask_unweighted(
            contactmap::io::fasta::gc_content(fasta, bins)?,
            weights,
        )),
        (None, None) => None,
    })
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
        _ => Err(Error::Argument(format!(
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
        Some(path) => contactmap::io::bed::read_view(path, reader.bins())?,
        None => View::chromosomes(reader.bins()),
    };
    Ok((weights, view))
}

/// The column of an expected table that observed / expected divides by: `column` when given,
/// else `balanced.avg`, or `count.avg` for raw counts.
pub fn expected_column(column: Option<&str>, raw: bool) -> &str {
    column.unwrap_or(if raw { "count.avg" } else { "balanced.avg" })
}

/// The expected that dots and pileups divide by ([`expected_to_divide_by`]): cis per region
/// and diagonal, or with `trans` per two regions; from `table` (an `--expected`) or computed
/// from `reader`'s pixels.
pub fn expected_to_divide(
    reader: &dyn MatrixReader,
    weights: Option<&[f64]>,
    view: &View,
    table: Option<&Table>,
    column: &str,
    trans: bool,
) -> Result<Vec<Vec<f64>>> {
    let pixels = io::LoadedPixels::Streamed(io::StreamedPixels::new(reader));
    expected_to_divide_by(&pixels, weights, view, table, column, trans)
}

/// A table (an `--expected`) read on another thread while the map is opened: the two are
/// independent, and a genome's expected table is tens of megabytes of text.
pub struct TableReading(Option<std::thread::JoinHandle<Result<Table>>>);

impl TableReading {
    /// Start reading `path` (nothing to read without one).
    pub fn start(path: Option<&str>) -> TableReading {
        TableReading(path.map(|path| {
            let path = path.to_string();
            std::thread::spawn(move || Table::read(&path))
        }))
    }

    /// The table, once read (none without a path).
    pub fn finish(self) -> Result<Option<Table>> {
        self.0
            .map(|reading| {
                reading.join().unwrap_or_else(|_| {
                    Err(Error::Invalid("the thread reading a table panicked".into()))
                })
            })
            .transpose()
    }
}

/// The distance given to `option` (`20k`, `1.5M`, `5000`) in bp; the error names the option.
pub fn bp_option(option: &str, text: &str) -> Result<u64> {
    contactmap::genome::parse_bp(text).map_err(|e| Error::Argument(format!("{option}: {e}")))
}
