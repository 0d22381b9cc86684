//! `contactmap sample`: a map downsampled to fewer contacts, as `cooltools random-sample`.

use std::path::{Path, PathBuf};

use clap::{ArgGroup, Args};

use crate::cli::args::InputArgs;
use crate::cli::input::open_for_analysis;
use crate::cli::output::{refuse_overwrites, uri_file};
use contactmap::compare::sample::{SampleParams, Sampled, Target};
use contactmap::error::{Error, Result};
use contactmap::export::MatrixFormat;
use contactmap::io::cool::{CoolWriteOptions, write_cool};

/// Arguments of `contactmap sample`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Contacts are drawn as cooltools 0.7.1 `random-sample` draws them:
  --fraction F   each contact kept with probability F (binomial thinning of every pixel's
                 count), so the total is F times the input's on average (cooltools' default)
  --count N      exactly N distinct contacts drawn without replacement (cooltools --exact);
                 --fraction F --exact keeps exactly round(F x total)
Pixels left without contacts are dropped; counts must be whole numbers (raw counts). The
output is a .cool on the input's bins, without weight columns (balance the sample itself).

The draws are made per block of 256 rows, each block with its own random stream from --seed,
so a seed gives the same file whatever the number of threads. cooltools draws from numpy's
unseeded generator: its samples differ from run to run, ours do not (same distribution).

Examples:
  contactmap sample deep.cool --count 50000000 --seed 1 -o deep.50M.cool
  contactmap sample rep1.mcool::/resolutions/10000 --fraction 0.25 \\
      -o rep1.quarter.cool
  # two replicates at the same depth before comparing them
  depth=$(contactmap info rep1.cool --json | jq .sum)
  contactmap sample rep2.cool --count \"$depth\" -o rep2.eq.cool")]
#[command(group(ArgGroup::new("amount").required(true).args(["count", "fraction"])))]
pub struct SampleArgs {
    /// Matrix URI: file.cool, file.mcool::/resolutions/N, file.hic[::/resolutions/N], text table.
    pub uri: String,
    /// Keep exactly this many contacts.
    #[arg(long, value_name = "N")]
    pub count: Option<u64>,
    /// Keep each contact with this probability, in (0, 1].
    #[arg(long, value_name = "F")]
    pub fraction: Option<f64>,
    /// With --fraction: keep exactly round(F x total) contacts.
    #[arg(long)]
    pub exact: bool,
    /// Seed of the random draws.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Output .cool file.
    #[arg(short, long, value_name = "FILE.cool")]
    pub out: PathBuf,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `contactmap sample`.
pub fn run(args: &SampleArgs) -> Result<()> {
    let inputs: Vec<&Path> = std::iter::once(uri_file(&args.uri))
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[Some(&args.out)])?;
    if !matches!(
        MatrixFormat::from_extension(&args.out),
        Ok(MatrixFormat::Cool)
    ) {
        return Err(Error::Argument(format!(
            "--out {}: sample writes a .cool (give the .cool extension)",
            args.out.display()
        )));
    }
    let target = match (args.count, args.fraction) {
        (Some(n), _) => Target::Count(n),
        (None, Some(f)) => Target::Fraction(f),
        (None, None) => unreachable!("clap requires one"),
    };
    let reader = open_for_analysis(&args.uri, &args.input)?;
    let params = SampleParams {
        target,
        exact: args.exact,
        seed: args.seed,
    };
    let sampled = Sampled::new(reader.as_ref(), params)?;
    let options = CoolWriteOptions {
        assembly: reader.info().assembly(),
        weight_columns: Some(Vec::new()),
    };
    write_cool(&sampled, &args.out, &options)?;
    crate::cli::warnings::print_reader_warnings(reader.warnings());
    Ok(())
}
