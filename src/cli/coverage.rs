//! `contactmap coverage`: cis and total coverage per bin, as `cooltools coverage`.

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::args::InputArgs;
use crate::cli::input::{open_for_analysis, read_weights};
use crate::cli::output::{Output, refuse_overwrites, store_lock, uri_file};
use contactmap::compare::coverage::{balanced_coverage, coverage};
use contactmap::error::{Error, Result};
use contactmap::export::cooler::store_coverage;
use contactmap::io::output::python_float;

/// Arguments of `contactmap coverage`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
The sums of each bin's row and column of the symmetric map (cooltools 0.7.1 `coverage`): every
pixel (i, j) counts for bin i and for bin j (a diagonal pixel twice), pixels on the first
--ignore-diags diagonals left out; cis counts pixels within a chromosome only, total all of
them. The sum of the total coverage is twice the number of contacts.

Output (tab-separated, header): chrom start end cov_cis_raw cov_tot_raw (integers), or with
--weight-name W the balanced coverage (count x w_i x w_j) chrom start end cov_cis_W cov_tot_W,
nan at bins without a weight. --ignore-diags defaults, as cooltools, to the ignore_diags the
map's `weight` column was balanced with.

--store also writes the two columns into the cooler's bins (replacing columns of those names, as
cooltools does), and for raw coverage the cooler attribute `cis` (the number of cis contacts);
the file is locked while it is written.

Examples:
  contactmap coverage data/CN.mm9.10000kb.cool
  contactmap coverage data/yeast.10kb.cool --ignore-diags 0 -o yeast.cov.tsv
  contactmap coverage data/CN.mm9.10000kb.cool --weight-name weight
  contactmap coverage copy.cool --store -o copy.cov.tsv")]
pub struct CoverageArgs {
    /// Matrix URI: file.cool, file.mcool::/resolutions/N, file.hic[::/resolutions/N], text table.
    pub uri: String,
    /// Leave out pixels with |j - i| < N (default: the weight column's ignore_diags).
    #[arg(long, value_name = "N")]
    pub ignore_diags: Option<usize>,
    /// Balanced coverage with this weight column (default: raw counts).
    #[arg(long, value_name = "COLUMN")]
    pub weight_name: Option<String>,
    /// Also store the columns in the cooler (.cool, or an .mcool resolution).
    #[arg(long)]
    pub store: bool,
    /// Write to FILE (gzip if it ends in .gz) instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `contactmap coverage`.
pub fn run(args: &CoverageArgs) -> Result<()> {
    let inputs: Vec<&Path> = std::iter::once(uri_file(&args.uri))
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let _lock = args.store.then(|| store_lock(&args.uri, "")).transpose()?;
    let reader = open_for_analysis(&args.uri, &args.input)?;
    let ignore_diags = match args.ignore_diags {
        Some(n) => n,
        None => reader.stored_ignore_diags("weight").ok_or_else(|| {
            Error::Argument(format!(
                "--ignore-diags: give it: {} has no `weight` column with an ignore_diags \
                     attribute saying how many diagonals its balancing left out (cooltools \
                     stops here too)",
                reader.source()
            ))
        })?,
    };
    let (cov, suffix) = match &args.weight_name {
        None => (coverage(reader.as_ref(), ignore_diags)?, "raw".to_string()),
        Some(name) => {
            let weights = read_weights(reader.as_ref(), name, "--weight-name", false)?;
            (
                balanced_coverage(reader.as_ref(), ignore_diags, &weights)?,
                name.clone(),
            )
        }
    };
    let bins = reader.bins();
    let mut text = format!("chrom\tstart\tend\tcov_cis_{suffix}\tcov_tot_{suffix}\n");
    let value = |v: f64| {
        if args.weight_name.is_none() {
            format!("{}", v as i64)
        } else {
            python_float(v)
        }
    };
    for (k, bin) in bins.iter().enumerate() {
        text.push_str(&format!(
            "{}\t{}\t{}\t{}\t{}\n",
            bins.chroms()[bin.chrom_id].name,
            bin.start,
            bin.end,
            value(cov.cis[k]),
            value(cov.total[k])
        ));
    }
    let warnings = reader.warnings();
    drop(reader);
    if args.store {
        store_coverage(&args.uri, &cov, args.weight_name.as_deref())?;
    }
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(text.as_bytes())?;
    out.finish()?;
    crate::cli::warnings::print_reader_warnings(warnings);
    Ok(())
}
