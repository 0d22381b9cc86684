//! `contactmap normalize`: observed / expected maps (o/e, log2 o/e, z-score) as a .cool or a text
//! table.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};

use crate::cli::args::InputArgs;
use crate::cli::input::expected_column;
use crate::cli::matrix_output::{OutputFormat, write_matrix};
use crate::cli::output::{refuse_overwrites, uri_file};
use crate::cli::progress::Progress;
use contactmap::error::{Error, Result};
use contactmap::export::{MatrixFormat, MatrixOutput};
use contactmap::io;
use contactmap::normalize::{Method, NormalizedReader, Normalizer};

/// Normalisation methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// observed / expected
    Oe,
    /// log2(observed / expected)
    Log2oe,
    /// (observed - expected) / standard deviation of the diagonal
    Zscore,
}

/// Arguments of `contactmap normalize`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Observed values are balanced (count * w1 * w2 with --weight-name, default `weight`) unless --raw.
The expected of each diagonal is cooltools' expected-cis average (balanced.avg, or count.avg with
--raw), computed on the fly or read from --expected (a cooltools expected-cis table; regions named
by chromosome). Only stored cis pixels are written; pixels of masked bins, of diagonals without an
expected value (the --ignore-diags first ones) and trans pixels are dropped. The output's count
column holds the normalised values (float).

Examples:
  contactmap normalize data/CN.mm9.10000kb.cool oe.cool
  contactmap normalize in.mcool::/resolutions/10000 - --method log2oe \\
      --to bg2 | head
  contactmap expected in.cool -o exp.tsv && \\
      contactmap normalize in.cool z.cool --method zscore --expected exp.tsv")]
pub struct NormalizeArgs {
    /// Input matrix URI.
    pub uri: String,
    /// Output: .cool, or a text table (.bg2, .coo, optionally .gz; `-` with --to for stdout).
    pub output: PathBuf,
    /// What to compute.
    #[arg(long, value_enum, default_value_t = MethodArg::Oe)]
    pub method: MethodArg,
    /// Use raw counts instead of balanced ones.
    #[arg(long)]
    pub raw: bool,
    /// Weight column for balancing.
    #[arg(long, default_value = "weight", value_name = "COLUMN")]
    pub weight_name: String,
    /// Read the expected from this table (cooltools expected-cis layout) instead of computing it.
    #[arg(long, value_name = "TSV")]
    pub expected: Option<String>,
    /// Column of --expected to use (default: balanced.avg, or count.avg with --raw).
    #[arg(long, value_name = "NAME")]
    pub expected_column: Option<String>,
    /// Diagonals ignored when computing the expected (2, as cooltools expected-cis, which does
    /// not read the number stored with the weights).
    #[arg(long, default_value_t = 2)]
    pub ignore_diags: usize,
    /// Output format (default: from the extension of OUTPUT).
    #[arg(long, value_enum)]
    pub to: Option<OutputFormat>,
    /// Memory budget for the in-memory pixel copy (e.g. 8G); larger matrices are streamed.
    #[arg(long, value_name = "SIZE")]
    pub max_memory: Option<String>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `contactmap normalize`.
pub fn run(args: &NormalizeArgs) -> Result<()> {
    let inputs: Vec<&Path> = std::iter::once(uri_file(&args.uri))
        .chain(args.expected.as_deref().map(Path::new))
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[Some(&args.output)])?;
    let format = match args.to {
        Some(format) => format.into(),
        None => MatrixFormat::from_extension(&args.output)?,
    };
    if format.has_resolutions() || format == MatrixFormat::Dense {
        return Err(Error::Argument(
            "normalize writes .cool, .bg2 or .coo outputs".into(),
        ));
    }
    let reader = crate::cli::input::open_for_analysis(&args.uri, &args.input)?;
    let bins = reader.bins().clone();
    let weights = if args.raw {
        None
    } else {
        Some(crate::cli::input::read_weights(
            reader.as_ref(),
            &args.weight_name,
            "--weight-name",
            true,
        )?)
    };
    let method = match args.method {
        MethodArg::Oe => Method::Oe,
        MethodArg::Log2oe => Method::Log2Oe,
        MethodArg::Zscore => Method::Zscore,
    };
    let budget = match &args.max_memory {
        Some(text) => io::parse_memory_size(text)?,
        None => io::default_memory_budget(),
    };
    let needs_pass = method == Method::Zscore || args.expected.is_none();
    let pixels = if needs_pass {
        Some(io::load_pixels(reader.as_ref(), budget)?)
    } else {
        None
    };
    let curves = match &args.expected {
        Some(path) => contactmap::expected::table::curves(
            &contactmap::io::tables::Table::read(path)?,
            &bins,
            expected_column(args.expected_column.as_deref(), args.raw),
        )?,
        None => {
            let pixels = pixels.as_ref().expect("loaded when no --expected");
            contactmap::expected::cis_curves(pixels, weights.as_deref(), args.ignore_diags)?
        }
    };
    let mut normalizer = Normalizer::new(method, bins.n_bins(), weights, curves)?;
    if normalizer.needs_deviations() {
        let pixels = pixels.as_ref().expect("loaded for zscore");
        normalizer.compute_deviations(pixels)?;
    }
    drop(pixels);
    let normalized = NormalizedReader::new(
        reader.as_ref(),
        &normalizer,
        format!("{} ({:?})", reader.source(), args.method),
    );
    let bar = Progress::new(&normalized, "normalizing")?;
    let progress = bar.reader();
    let output = MatrixOutput {
        weight_columns: Some(Vec::new()),
        ..MatrixOutput::default()
    };
    write_matrix(&progress, &args.output, format, &output)
}
