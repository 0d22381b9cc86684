//! `contactmap virtual4c`: a viewpoint's contacts with the whole genome, as `cooltools
//! virtual4c`.

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::args::InputArgs;
use crate::cli::input::{open_for_analysis, read_weights};
use crate::cli::output::{Output, refuse_overwrites, uri_file};
use contactmap::compare::virtual4c::{viewpoint_bins, virtual4c};
use contactmap::error::{Error, Result};
use contactmap::genome::Region;
use contactmap::io::output::python_float;

/// Arguments of `contactmap virtual4c`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
The viewpoint's row of the symmetric map, as cooltools 0.7.1 `virtual4c`: for every bin, the
mean over the viewpoint's bins of the stored pixels between them (balanced by --weight-name,
or raw counts with --raw); nan where no pixel is stored and for the bins wholly inside the
viewpoint.

Output (tab-separated, header): chrom start end balanced (or count with --raw), one row per bin
of the map.

Examples:
  contactmap virtual4c data/CN.mm9.10000kb.cool --viewpoint chr1:50M-60M
  contactmap virtual4c rep1.mcool::/resolutions/10000 \\
      --viewpoint chr2:1,200,000-1,210,000 --raw -o myc.v4c.tsv")]
pub struct Virtual4cArgs {
    /// Matrix URI: file.cool, file.mcool::/resolutions/N, file.hic[::/resolutions/N], text table.
    pub uri: String,
    /// The viewpoint: chrom:start-end (bp; 20k, 1.5M and commas allowed), or a whole chrom.
    #[arg(long, value_name = "REGION")]
    pub viewpoint: String,
    /// Weight column for balanced values.
    #[arg(long, default_value = "weight", value_name = "COLUMN")]
    pub weight_name: String,
    /// Raw counts (cooltools' --clr-weight-name '').
    #[arg(long)]
    pub raw: bool,
    /// Write to FILE (gzip if it ends in .gz) instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `contactmap virtual4c`.
pub fn run(args: &Virtual4cArgs) -> Result<()> {
    let inputs: Vec<&Path> = std::iter::once(uri_file(&args.uri))
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let reader = open_for_analysis(&args.uri, &args.input)?;
    let bins = reader.bins();
    let (viewpoint, inside) = Region::parse(&args.viewpoint)
        .and_then(|region| viewpoint_bins(bins, &region))
        .map_err(|e| Error::parameter("viewpoint", &args.viewpoint, e.to_string()))?;
    if viewpoint.is_empty() {
        return Err(Error::parameter(
            "viewpoint",
            &args.viewpoint,
            format!("a region that covers a bin of {}", reader.source()),
        ));
    }
    let weights = if args.raw {
        None
    } else {
        Some(read_weights(
            reader.as_ref(),
            &args.weight_name,
            "--weight-name",
            true,
        )?)
    };
    let profile = virtual4c(reader.as_ref(), viewpoint, inside, weights.as_deref())?;
    let column = if args.raw { "count" } else { "balanced" };
    let mut text = format!("chrom\tstart\tend\t{column}\n");
    for (k, bin) in bins.iter().enumerate() {
        text.push_str(&format!(
            "{}\t{}\t{}\t{}\n",
            bins.chroms()[bin.chrom_id].name,
            bin.start,
            bin.end,
            python_float(profile[k])
        ));
    }
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(text.as_bytes())?;
    out.finish()?;
    crate::cli::warnings::print_reader_warnings(reader.warnings());
    Ok(())
}
