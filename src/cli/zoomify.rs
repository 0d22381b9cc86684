//! `contactmap zoomify`: a multi-resolution .mcool (or .hic) from a cooler (or any matrix), as
//! `cooler zoomify` / `hictk zoomify`, with every level optionally balanced.

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::args::InputArgs;
use crate::cli::matrix_output::write_matrix;
use crate::cli::output::{refuse_overwrites, uri_file};
use contactmap::balance::{BalanceParams, Method};
use contactmap::error::{Error, Result};
use contactmap::export::cooler::balance_and_store;
use contactmap::export::{DEFAULT_HIC_NORMALIZATIONS, MatrixFormat, MatrixOutput};
use contactmap::io::cool::resolutions::mcool_resolutions;
use contactmap::io::{self, default_memory_budget};

/// Arguments of `contactmap zoomify`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Each level sums the input's pixels into coarser bins (the same pixels as `cooler zoomify`), all
levels in one pass over the input; the pixel columns are compressed on every core. Resolutions
(-r), as cooler zoomify: a comma-separated list of bin sizes, or progressions: B (the default:
the input's bin size, doubled up to the longest chromosome), N (steps 1-2-5), 5000B, 5000N (from
5000), 4DN (1000,2000,5000N); each must be a multiple of the input's bin size.

--balance balances every level with ICE exactly as `cooler balance` does with its defaults
(ignore 2 diagonals, MAD-max 5, min-nnz 10, tol 1e-5, 200 iterations) and stores the column
`weight` with cooler's attributes, as `cooler zoomify --balance` (the input's resolution keeps the
input's own `weight` column when it has one, as cooler does); a level that does not converge
is stored with converged=false and a warning, as cooler's default does. Use `contactmap balance
OUT::/resolutions/N --store --force` for other balancing of a level.

With -o FILE.hic the levels are written as a Juicer .hic (as `hictk zoomify` can), each with
Juicer's VC, VC_SQRT, KR and SCALE vectors and expected values (see `convert`); --balance adds
an ICE vector (cooler's defaults, per chromosome). The output (default: the input's name with
.mcool) is written under a temporary name and renamed when complete.

Examples:
  contactmap zoomify in.cool                       # in.mcool, B progression
  contactmap zoomify in.cool -r 10000,20000,50000,100000 --balance \\
      -o out.mcool
  contactmap zoomify in.cool -r 10000N -o out.mcool
  contactmap zoomify in.cool -r 5000N -o out.hic   # Juicer .hic for Juicebox")]
pub struct ZoomifyArgs {
    /// The input: file.cool, file.mcool::/resolutions/N, .hic, text tables.
    pub input: String,
    /// Output .mcool or .hic (default: the input's name with .mcool).
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Resolutions: a list, or B / N progressions (see below).
    #[arg(
        short,
        long,
        value_delimiter = ',',
        value_name = "LIST",
        default_value = "B"
    )]
    pub resolutions: Vec<String>,
    /// Balance every level (ICE, cooler's defaults) and store it as `weight`.
    #[arg(long)]
    pub balance: bool,
    /// Copy the pixels of a level into memory for balancing when they fit SIZE (e.g. 4G).
    #[arg(long, value_name = "SIZE")]
    pub max_memory: Option<String>,
    /// `genome-assembly` attribute (default: the input's).
    #[arg(long)]
    pub assembly: Option<String>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input_args: InputArgs,
}

/// The default output: the input's file name with `.mcool`.
fn default_output(input: &str) -> PathBuf {
    let (path, _) = io::split_uri(input);
    let path = Path::new(path);
    let stem = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = stem
        .strip_suffix(".gz")
        .unwrap_or(&stem)
        .rsplit_once('.')
        .map_or(stem.as_str(), |(s, _)| s)
        .to_string();
    path.with_file_name(format!("{stem}.mcool"))
}

/// Run `contactmap zoomify`.
pub fn run(args: &ZoomifyArgs) -> Result<()> {
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| default_output(&args.input));
    let inputs: Vec<&Path> = std::iter::once(uri_file(&args.input))
        .chain(args.input_args.files())
        .collect();
    refuse_overwrites(&inputs, &[Some(&out)])?;
    let name = out.to_string_lossy().to_ascii_lowercase();
    let hic = name.ends_with(".hic");
    if !hic && !name.ends_with(".mcool") {
        return Err(Error::Argument(format!(
            "--out {}: zoomify writes an .mcool or a .hic",
            out.display()
        )));
    }
    let budget = match &args.max_memory {
        Some(text) => io::parse_memory_size(text)?,
        None => default_memory_budget(),
    };
    let resolutions = {
        let reader = io::open_matrix(&args.input, &args.input_args.to_options()?)?;
        let resolutions = mcool_resolutions(reader.bins(), reader.source(), &args.resolutions)?;
        let mut normalizations = DEFAULT_HIC_NORMALIZATIONS.to_vec();
        if args.balance {
            normalizations.push(Method::Ice);
        }
        let output = MatrixOutput {
            resolutions: resolutions.clone(),
            assembly: args.assembly.clone().or_else(|| reader.info().assembly()),
            normalizations,
            ..MatrixOutput::default()
        };
        let format = match hic {
            true => MatrixFormat::Hic,
            false => MatrixFormat::Mcool,
        };
        write_matrix(reader.as_ref(), &out, format, &output)?;
        super::warnings::print_reader_warnings(reader.warnings());
        if hic {
            return Ok(());
        }
        resolutions
    };
    if args.balance {
        for &resolution in &resolutions {
            balance_level(&out, resolution, budget)?;
        }
    }
    Ok(())
}

/// ICE with cooler's defaults on one level, stored as `weight` (a copied one is kept).
fn balance_level(out: &Path, resolution: u64, budget: u64) -> Result<()> {
    let uri = format!("{}::/resolutions/{resolution}", out.display());
    if let Some(result) = balance_and_store(&uri, budget)? {
        if !result.converged {
            eprintln!(
                "contactmap: WARNING: {uri}: ICE did not converge within {} iterations (var={:e}); storing the weights with converged=false",
                BalanceParams::default().max_iters,
                result.var
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_output_is_the_input_named_mcool() {
        assert_eq!(default_output("dir/a.cool"), PathBuf::from("dir/a.mcool"));
        assert_eq!(
            default_output("x.mcool::/resolutions/1000"),
            PathBuf::from("x.mcool")
        );
    }
}
