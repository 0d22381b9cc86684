//! `contactmap dump`: print pixels, bins or chromosomes as tab-separated text, as `cooler dump`.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};

use crate::cli::args::InputArgs;
use crate::cli::output::{FloatFormat, Output};
use crate::cli::output::{refuse_overwrites, uri_file};
use contactmap::error::Result;
use contactmap::io;
use contactmap::io::text::dump::{DumpOptions, dump_bins, dump_chroms, dump_pixels};

/// Which table to print.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Table {
    /// bin1_id bin2_id count (as stored: upper triangle, both for storage-mode square)
    Pixels,
    /// chrom start end [weight columns]
    Bins,
    /// name length
    Chroms,
}

/// Arguments of `contactmap dump`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Output follows `cooler dump`: no header unless -H, tab-separated, counts as integers when they
are integers, other numbers with the printf format of --float-format (default %g, 6 significant
digits; use --float-format .17g to print every digit), missing values (masked bins) as --na-rep.
Pixels are printed as stored, as cooler dump prints them: the upper triangle (bin1 <= bin2) of
symmetric matrices, both triangles of coolers with storage-mode square. With --region R and
--region2 R2, the stored pixels with bin1 in R and bin2 in R2.

-t bins prints the weight columns as stored in the file, as cooler dump does: Juicer's divisive
columns (KR, VC, VC_SQRT written by hic2cool or contactmap, columns marked divisive_weights, and
a .hic file's normalisation vectors) hold the values counts are divided by. Wherever weights are applied (--balanced, balance, expected, tads,
normalize) such columns are inverted first, so balanced = count * w1 * w2 always holds for the
weights in use.

Examples:
  contactmap dump data/cooler_test_file.mcool::/resolutions/100000 | head
  contactmap dump data/hic_test_file.hic -r chr2L:1,000,000-2,000,000 \\
      --join --balanced=KR
  contactmap dump data/yeast.10kb.cool -t bins -H")]
pub struct DumpArgs {
    /// Matrix URI: file.cool, file.mcool::/resolutions/N, file.hic[::/resolutions/N], text table.
    pub uri: String,
    /// Table to print.
    #[arg(short, long, value_enum, default_value_t = Table::Pixels)]
    pub table: Table,
    /// Rows: a region such as chr2L or chr2L:1,000,000-2,000,000 (0-based, half-open).
    #[arg(short, long, visible_alias = "range", value_name = "REGION")]
    pub region: Option<String>,
    /// Columns: a second region (default: the same as --region).
    #[arg(long, visible_alias = "range2", value_name = "REGION")]
    pub region2: Option<String>,
    /// Add a `balanced` column = count * w1 * w2 from weight column COLUMN (default `weight`).
    #[arg(short, long, value_name = "COLUMN", num_args = 0..=1, require_equals = true, default_missing_value = "weight")]
    pub balanced: Option<String>,
    /// Print chrom, start, end for each bin instead of bin ids.
    #[arg(long)]
    pub join: bool,
    /// Print a header line with column names.
    #[arg(short = 'H', long)]
    pub header: bool,
    /// Text for missing values (NaN weights, masked bins).
    #[arg(long, default_value = "", value_name = "TEXT")]
    pub na_rep: String,
    /// printf format for real numbers: g, .12g, .3f, .4e ...
    #[arg(long, default_value = "g", value_name = "FORMAT")]
    pub float_format: FloatFormat,
    /// Write to FILE (gzip if it ends in .gz) instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `contactmap dump`.
pub fn run(args: &DumpArgs) -> Result<()> {
    let inputs: Vec<&Path> = std::iter::once(uri_file(&args.uri))
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let reader = io::open_matrix(&args.uri, &args.input.to_options()?)?;
    let bins = reader.bins();
    let rows = || match &args.region {
        Some(region) => bins.parse_region_bins(region),
        None => Ok(0..bins.n_bins()),
    };
    let weights = match (&args.balanced, args.table) {
        (Some(name), Table::Pixels) => Some(crate::cli::input::read_weights(
            reader.as_ref(),
            name,
            "--balanced",
            false,
        )?),
        _ => None,
    };
    let options = DumpOptions {
        header: args.header,
        join: args.join,
        float_format: args.float_format,
        na_rep: args.na_rep.clone(),
    };
    let mut out = Output::open(args.out.as_deref())?;
    let write = |bytes: &[u8]| out.write_all(bytes);
    match args.table {
        Table::Chroms => dump_chroms(bins, &options, write)?,
        Table::Bins => dump_bins(reader.as_ref(), rows()?, &options, write)?,
        Table::Pixels => {
            let rows = rows()?;
            let cols = match &args.region2 {
                Some(region2) => bins.parse_region_bins(region2)?,
                None => rows.clone(),
            };
            dump_pixels(
                reader.as_ref(),
                rows,
                cols,
                weights.as_deref(),
                &options,
                write,
            )?
        }
    }
    out.finish()?;
    super::warnings::print_reader_warnings(reader.warnings());
    Ok(())
}
