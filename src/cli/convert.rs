//! `contactmap convert`: any supported input to .cool, .mcool, .hic or a text table.

use std::path::PathBuf;

use clap::Args;

use crate::cli::args::InputArgs;
use crate::cli::matrix_output::{OutputFormat, parse_normalizations, write_matrix};
use crate::cli::output::{refuse_overwrites, uri_file};
use crate::cli::progress::Progress;
use contactmap::error::{Error, Result};
use contactmap::export::{MatrixFormat, MatrixOutput};
use contactmap::io::cool::resolutions::mcool_resolutions;
use contactmap::io::{self, FileKind, MatrixReader};

/// Arguments of `contactmap convert`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
The output format follows the extension of OUT (.cool, .mcool, .hic, .bg2, .coo, .dense, each
text one optionally .gz) or --to. Files are written under a temporary name and renamed when
complete.

Resolutions for .mcool and .hic: a list (10000,50000,100000) or a progression from a base: 10000N for
10000, 20000, 50000, 100000, 200000, ... (steps 1-2-5) and 10000B for 10000, 20000, 40000, ...
(steps of 2), up to the length of the longest chromosome. Each must be a multiple of the input's
bin size. Default: the input's bin size followed by its N progression. Coarser levels are summed
from the input in a single pass, as `cooler zoomify` would make them.

A .hic is Juicer's version 9, as Juicebox, straw and hictk read it: every resolution, the `All`
whole-genome view, and per resolution and chromosome the normalisation vectors of
--normalizations (default VC, VC_SQRT, KR, SCALE, computed as `balance --method M --cis-only`
computes them, Juicer's way) with Juicer's expected values, raw and normalised. Chromosomes where
KR or SCALE does not converge keep their vector and are listed on standard error. Memory: the
open blocks while streaming, then one chromosome's intra-chromosomal pixels at a time.

Examples:
  contactmap convert data/hic_test_file.hic out.cool
  contactmap convert in.cool out.mcool \\
      --resolutions 100000,200000,500000,1000000
  contactmap convert in.mcool::/resolutions/5000 out.hic --resolutions 5000N \\
      --genome hg38
  contactmap convert pairs.txt.gz out.cool --bin-size 2000000 \\
      --chrom-sizes hg19.sizes
  contactmap convert in.mcool::/resolutions/100000 - \\
      --to bg2 | gzip > out.bg2.gz")]
pub struct ConvertArgs {
    /// Input URI (file.cool, file.mcool::/resolutions/N, file.hic[::/resolutions/N], text, pairs).
    pub input: String,
    /// Output path (`-` for standard output, text formats only).
    pub output: PathBuf,
    /// Output format (default: from the extension of OUTPUT).
    #[arg(long, value_enum)]
    pub to: Option<OutputFormat>,
    /// Resolutions of an .mcool output: a comma-separated list, or BASE N / BASE B progressions.
    #[arg(long, value_delimiter = ',', value_name = "LIST")]
    pub resolutions: Vec<String>,
    /// genome-assembly attribute written into .cool / .mcool outputs (the genome id of a .hic).
    #[arg(long, visible_alias = "genome")]
    pub assembly: Option<String>,
    /// Normalisations stored in a .hic, per resolution and chromosome: VC, VC_SQRT, KR, SCALE,
    /// ICE, or none.
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "LIST",
        default_value = "VC,VC_SQRT,KR,SCALE"
    )]
    pub normalizations: Vec<String>,
    /// zlib level of .hic blocks (0-9).
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u32).range(0..=9))]
    pub compression_level: u32,
    /// Options for text inputs (--bin-size bins pairs).
    #[command(flatten)]
    pub input_args: InputArgs,
}

/// Run `contactmap convert`.
pub fn run(args: &ConvertArgs) -> Result<()> {
    let mut inputs = vec![uri_file(&args.input)];
    inputs.extend(args.input_args.files());
    refuse_overwrites(&inputs, &[Some(&args.output)])?;
    let format = match args.to {
        Some(format) => format.into(),
        None => MatrixFormat::from_extension(&args.output)?,
    };
    let (input_path, _) = io::split_uri(&args.input);
    if args.input_args.bin_size.is_some() && io::detect_kind(input_path)? != FileKind::Text {
        return Err(Error::Argument(
            "--bin-size bins text and pairs inputs; to coarsen a .cool or .hic matrix, write an .mcool with --resolutions".into(),
        ));
    }
    if !args.resolutions.is_empty() && !format.has_resolutions() {
        return Err(Error::Argument(
            "--resolutions applies to .mcool and .hic outputs only".into(),
        ));
    }
    if args.output.as_os_str() == "-" && format.needs_a_file() {
        return Err(Error::Argument(
            ".cool, .mcool and .hic outputs need a file path, not '-'".into(),
        ));
    }
    let methods = parse_normalizations(&args.normalizations)?;
    let opened = io::open_matrix(&args.input, &args.input_args.to_options()?)?;
    let bar = Progress::new(opened.as_ref(), "converting")?;
    let reader = bar.reader();
    let output = MatrixOutput {
        resolutions: match format.has_resolutions() {
            true => mcool_resolutions(reader.bins(), &args.input, &args.resolutions)?,
            false => Vec::new(),
        },
        assembly: args.assembly.clone().or_else(|| reader.info().assembly()),
        normalizations: methods,
        compression_level: args.compression_level,
        ..MatrixOutput::default()
    };
    let written = write_matrix(&reader, &args.output, format, &output);
    written?;
    super::warnings::print_reader_warnings(reader.warnings());
    Ok(())
}
