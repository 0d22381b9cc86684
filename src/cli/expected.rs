//! `contactmap expected`: cis expected as `cooltools expected-cis`, trans expected as
//! `cooltools expected-trans`, log-binned P(s) with slopes, and power-law exponents.

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::args::InputArgs;
use crate::cli::input::weights_and_view;
use crate::cli::output::write_whole;
use crate::cli::output::{refuse_overwrites, uri_file};
use contactmap::error::{Error, Result};
use contactmap::expected::powerlaw::{FitRange, PowerLaw, power_law};
use contactmap::expected::{CisParams, expected_cis, expected_trans};
use contactmap::io::{self, LoadedPixels, StreamedPixels};

/// Arguments of `contactmap expected`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Output (tab-separated, header line, NaN as `nan`, numbers with every digit):

  default    the cis expected table of `cooltools expected-cis` with smoothing on (the Python
             API's defaults: smooth=True, aggregate_smoothed=True, smooth_sigma=0.1; the
             cooltools command line needs --smooth --aggregate-smoothed for the same table):
             region1 region2 dist dist_bp contact_frequency n_total n_valid count.sum
             [balanced.sum] count.avg [balanced.avg] X.avg.smoothed X.avg.smoothed.agg
  --trans    the trans table of `cooltools expected-trans`:
             region1 region2 n_valid count.sum [balanced.sum] count.avg [balanced.avg]
  --logbin   log-binned P(s) combined over regions (cooltools logbin_expected +
             combine_binned_expected: 10 bins per decade, distances in bins; per region, bins
             with n_valid <= 200 or count.sum <= 50 are dropped, as cooltools does), with the
             local slope d ln P / d ln s from each bin to the next:
             dist_bin_id X.avg n_valid dist.avg dist_bin_start dist_bin_end low_err high_err
             dist_bp.avg slope slope.low_err slope.high_err slope.dist.avg slope.n_valid
             The power-law exponent goes to standard error.
  --fit      power-law exponent of P(s) over --fit-range (least squares on the log-binned
             P(s) in log-log space, at each bin's effective distance), with its 95% CI
             (Student's t) and R^2, and piecewise exponents between 0-3 breakpoints chosen
             by BIC (--json for everything, with the points fitted)

Balanced values use the weight column --weight-name (default `weight`, cooler's ICE weights);
--raw uses raw counts with no masked bins, as cooltools with clr_weight_name=None.
The view (--view) is a BED file `chrom start end [name]` of sorted, non-overlapping regions
(names default to chrom:start-end); without it, whole chromosomes.
The default fit range is max(ignore-diags, 2) bins to a quarter of the median region length.

Examples:
  contactmap expected data/cooler_test_file.mcool::/resolutions/100000 \\
      -o exp.tsv
  contactmap expected data/hg19.GM12878-MboI.matrix.2000kb.cool --raw --trans
  contactmap expected data/cooler_test_file.mcool::/resolutions/100000 \\
      --fit --fit-range 200k-5M
  contactmap expected big.cool --raw --logbin --view arms.bed")]
pub struct ExpectedArgs {
    /// Matrix URI: file.cool, file.mcool::/resolutions/N, file.hic[::/resolutions/N], text table.
    pub uri: String,
    /// Write to FILE (gzip if it ends in .gz) instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Weight column for balanced values.
    #[arg(long, default_value = "weight", value_name = "COLUMN")]
    pub weight_name: String,
    /// Raw counts: no weights, no masked bins (cooltools' clr_weight_name=None).
    #[arg(long, visible_alias = "no-balance")]
    pub raw: bool,
    /// BED file of regions (`chrom start end [name]`), sorted and non-overlapping.
    #[arg(long, value_name = "BED")]
    pub view: Option<PathBuf>,
    /// Diagonals 0..N get NaN sums (2, as cooltools expected-cis: the number stored with the
    /// weights is not read).
    #[arg(long, default_value_t = 2, value_name = "N")]
    pub ignore_diags: usize,
    /// Standard deviation of the smoothing kernel, in log10(distance).
    #[arg(long, default_value_t = 0.1, value_name = "SIGMA")]
    pub smooth_sigma: f64,
    /// Leave out the smoothed columns.
    #[arg(long)]
    pub no_smooth: bool,
    /// Leave out the smoothed-over-all-regions column (*.avg.smoothed.agg).
    #[arg(long)]
    pub no_aggregate: bool,
    /// Print the trans expected (pairs of regions on different chromosomes) instead.
    #[arg(long, conflicts_with_all = ["logbin", "fit", "json"])]
    pub trans: bool,
    /// Print the log-binned P(s) with its slopes instead.
    #[arg(long, conflicts_with_all = ["fit", "json"])]
    pub logbin: bool,
    /// Print power-law exponents of P(s) instead.
    #[arg(long)]
    pub fit: bool,
    /// Distance range of the fits in bp, e.g. 100k-10M (default: see below).
    #[arg(long, value_name = "MIN-MAX")]
    pub fit_range: Option<String>,
    /// Power-law report as JSON (implies --fit).
    #[arg(long)]
    pub json: bool,
    /// Copy the pixels into memory first when they fit SIZE (e.g. 8G; 0 never copies). By
    /// default they are streamed from the file: expected makes a single pass over them, so a
    /// copy only costs time and memory.
    #[arg(long, value_name = "SIZE")]
    pub max_memory: Option<String>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// What to print.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Report {
    Cis,
    Trans,
    LogBin,
    Fit { json: bool },
}

/// Checked parameters.
struct Checked {
    report: Report,
    params: CisParams,
    fit_range: Option<FitRange>,
    /// `None`: stream the pixels.
    max_memory: Option<u64>,
}

fn check(args: &ExpectedArgs) -> Result<Checked> {
    let report = if args.trans {
        Report::Trans
    } else if args.logbin {
        Report::LogBin
    } else if args.fit || args.json {
        Report::Fit { json: args.json }
    } else {
        Report::Cis
    };
    if !(args.smooth_sigma > 0.0 && args.smooth_sigma.is_finite()) {
        return Err(Error::Argument(format!(
            "--smooth-sigma must be a positive number (got {})",
            args.smooth_sigma
        )));
    }
    if args.fit_range.is_some() && !matches!(report, Report::Fit { .. }) {
        return Err(Error::Argument(
            "--fit-range sets the distances of the power-law fit: add --fit (or --json)".into(),
        ));
    }
    let fit_range = args
        .fit_range
        .as_deref()
        .map(str::parse::<FitRange>)
        .transpose()?;
    let max_memory = args
        .max_memory
        .as_deref()
        .map(io::parse_memory_size)
        .transpose()?;
    Ok(Checked {
        report,
        params: CisParams {
            ignore_diags: args.ignore_diags,
            smooth: !args.no_smooth,
            aggregate_smoothed: !args.no_smooth && !args.no_aggregate,
            smooth_sigma_log10: args.smooth_sigma,
        },
        fit_range,
        max_memory,
    })
}

/// Run `contactmap expected`.
pub fn run(args: &ExpectedArgs) -> Result<()> {
    let inputs: Vec<&Path> = std::iter::once(uri_file(&args.uri))
        .chain(args.view.as_deref())
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let checked = check(args)?;
    let reader = crate::cli::input::open_for_analysis(&args.uri, &args.input)?;
    let (weights, view) = weights_and_view(
        reader.as_ref(),
        args.raw,
        &args.weight_name,
        args.view.as_deref(),
    )?;
    if reader.bins().resolution().is_none() {
        return Err(Error::format(
            reader.source(),
            "expected needs fixed-size bins (distances are diagonals times the bin size)",
        ));
    }
    let pixels = match checked.max_memory {
        Some(budget) => io::load_pixels(reader.as_ref(), budget)?,
        None => LoadedPixels::Streamed(StreamedPixels::new(reader.as_ref())),
    };
    let weights = weights.as_deref();
    let written = match checked.report {
        Report::Trans => {
            let table = expected_trans(&pixels, weights, &view)?;
            write_whole(args.out.as_deref(), &table.to_tsv())
        }
        Report::Cis => {
            let table = expected_cis(&pixels, weights, &view, &checked.params)?;
            write_whole(args.out.as_deref(), &table.to_tsv())
        }
        Report::LogBin => {
            let PowerLaw { binned, fit, .. } =
                power_law(&pixels, weights, &view, &checked.params, checked.fit_range)?;
            write_whole(args.out.as_deref(), &binned.to_tsv())?;
            match fit {
                Ok(report) => eprintln!("{}", report.headline()),
                Err(e) => eprintln!("contactmap: no power-law fit: {e}"),
            }
            Ok(())
        }
        Report::Fit { json } => {
            let PowerLaw { table, binned, fit } =
                power_law(&pixels, weights, &view, &checked.params, checked.fit_range)?;
            let report = fit?;
            let text = if json {
                let mut text = serde_json::to_string_pretty(&report.to_json(
                    &args.uri,
                    &args.weight_name,
                    &table,
                    &binned,
                ))
                .map_err(|e| Error::Invalid(format!("JSON output: {e}")))?;
                text.push('\n');
                text
            } else {
                report.summary_text()
            };
            write_whole(args.out.as_deref(), text.as_bytes())
        }
    };
    written?;
    super::warnings::print_reader_warnings(reader.warnings());
    Ok(())
}
