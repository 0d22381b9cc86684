//! `contactmap merge`: the sum of several maps on the same bins (replicates, simulation replicas)
//! as a .cool, .mcool or .hic, streamed.

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::args::InputArgs;
use crate::cli::matrix_output::write_matrix;
use crate::cli::output::{refuse_overwrites, uri_file};
use contactmap::error::{Error, Result};
use contactmap::export::{MatrixFormat, MatrixOutput};
use contactmap::io::cool::resolutions::{fixed_resolution, mcool_resolutions};
use contactmap::io::merged::MergedReader;
use contactmap::io::{self, MatrixReader};

/// Arguments of `contactmap merge`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Every input must have the same chromosomes (names and lengths, in the same order) and the same
bins; a pixel of the output is the sum of that pixel over the inputs (as `cooler merge`). Inputs
are any matrix contactmap reads (.cool, .mcool::/resolutions/N, .hic, text tables); the output is
a .cool, an .mcool with --resolutions (as `convert`), or a Juicer .hic (its resolutions too, with
Juicer's VC, VC_SQRT, KR and SCALE vectors computed on the merged map, as `convert` writes it).
Counts stay integers when every input's are. Weight columns are not carried over: balance the
merged file (`contactmap balance OUT --store`).

The pixels are streamed in bands of rows from every input at once, so memory follows the band
(a few million pixels), not the files. The output is written under a temporary name and renamed
when complete.

Examples:
  contactmap merge rep1.cool rep2.cool rep3.cool -o merged.cool
  contactmap merge a.mcool::/resolutions/10000 b.mcool::/resolutions/10000 \\
      -o ab.mcool --resolutions 10000N
  contactmap merge replica_*.cool -o ensemble.cool")]
pub struct MergeArgs {
    /// The maps to sum (at least one).
    #[arg(value_name = "URI", required = true)]
    pub inputs: Vec<String>,
    /// Output: FILE.cool, FILE.mcool (with --resolutions) or FILE.hic.
    #[arg(short, long, value_name = "FILE")]
    pub out: PathBuf,
    /// Resolutions of an .mcool output (a list, or BASE N / BASE B progressions, as `convert`).
    #[arg(long, value_delimiter = ',', value_name = "LIST")]
    pub resolutions: Vec<String>,
    /// `genome-assembly` attribute of the output (default: the first input's).
    #[arg(long)]
    pub assembly: Option<String>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input_args: InputArgs,
}

/// Run `contactmap merge`.
pub fn run(args: &MergeArgs) -> Result<()> {
    let inputs: Vec<&Path> = args
        .inputs
        .iter()
        .map(|uri| uri_file(uri))
        .chain(args.input_args.files())
        .collect();
    refuse_overwrites(&inputs, &[Some(&args.out)])?;
    let gzip = args
        .out
        .to_string_lossy()
        .to_ascii_lowercase()
        .ends_with(".gz");
    let format = match MatrixFormat::from_extension(&args.out) {
        Ok(format) if format.needs_a_file() && !gzip => format,
        _ => {
            return Err(Error::Argument(format!(
                "--out {}: merge writes .cool, .mcool or .hic (give one of those extensions)",
                args.out.display()
            )));
        }
    };
    if format == MatrixFormat::Cool && !args.resolutions.is_empty() {
        return Err(Error::Argument(
            "--resolutions needs an .mcool or .hic output".into(),
        ));
    }
    let options = args.input_args.to_options()?;
    let opened: Vec<Box<dyn MatrixReader>> = args
        .inputs
        .iter()
        .map(|uri| io::open_matrix(uri, &options))
        .collect::<Result<_>>()?;
    let reader = MergedReader::new(opened.iter().map(|r| r.as_ref()).collect())?;
    let output = MatrixOutput {
        resolutions: match (format.has_resolutions(), args.resolutions.is_empty()) {
            (false, _) => Vec::new(),
            (true, true) => vec![fixed_resolution(reader.bins(), reader.source())?],
            (true, false) => mcool_resolutions(reader.bins(), reader.source(), &args.resolutions)?,
        },
        assembly: args
            .assembly
            .clone()
            .or_else(|| opened[0].info().assembly()),
        weight_columns: Some(Vec::new()),
        ..MatrixOutput::default()
    };
    write_matrix(&reader, &args.out, format, &output)?;
    for reader in &opened {
        super::warnings::print_reader_warnings(reader.warnings());
    }
    Ok(())
}
