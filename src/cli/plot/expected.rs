//! `contactmap plot expected`: P(s) curves of several samples on log-log axes with their local
//! slopes, and the fitted power laws.

use std::path::{Path, PathBuf};

use clap::Args;

use super::figure::{FigureArgs, write_figure};
use crate::cli::args::InputArgs;
use crate::cli::input::{open_for_analysis, weights_and_view};
use crate::cli::output::{refuse_overwrites, uri_file};
use contactmap::error::{Error, Result};
use contactmap::expected::powerlaw::{FitRange, PowerLaw, power_law, power_law_of_table};
use contactmap::expected::{CisExpected, CisParams};
use contactmap::genome::format_bp;
use contactmap::io::tables::Table;
use contactmap::io::{LoadedPixels, StreamedPixels};
use contactmap::plot::curves::{PsFigure, PsSample, draw_curves, ps_figure};

/// Arguments of `contactmap plot expected`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Each input is a contact matrix (file.cool, file.mcool::/resolutions/N, file.hic, a text table)
or a cis expected table (the output of `contactmap expected` or `cooltools expected-cis`,
recognised by its header `region1 region2 dist ...`). From a matrix, the cis expected is
computed over whole chromosomes (or --view), balanced unless --raw, leaving out the
--ignore-diags first diagonals, exactly as `contactmap expected` does.

Upper panel: the log-binned P(s) combined over regions (10 bins per decade, as `contactmap
expected --logbin` and cooltools' logbin_expected + combine_binned_expected) against the mean
separation of each bin, on log-log axes. Lower panel (unless --no-slope): its local slope
d ln P / d ln s (cooltools' smoothed derivative, the slope column of `expected --logbin`).
--per-region draws every region (chromosome) of each input as its own curve instead of the
combined one (HiCExplorer hicPlotDistVsCounts draws chromosomes that way).

--fit adds the power law fitted over --fit-range (default: max(ignore-diags, 2) bins to a
quarter of the median region; the same fit and numbers as `contactmap expected --fit`) as a
dashed line over the points fitted, with the exponent in the legend, and the exponent as a
dashed level in the slope panel; the fits are also printed on standard error.

Examples:
  contactmap plot expected data/cooler_test_file.mcool::/resolutions/100000 \\
      --fit -o ps.png
  contactmap plot expected wt.mcool::/resolutions/10000 \\
      ko.mcool::/resolutions/10000 --labels WT,KO --fit --fit-range 50k-5M \\
      -o ps.svg
  contactmap expected in.cool -o exp.tsv && \\
      contactmap plot expected exp.tsv -o ps.png
  contactmap plot expected in.cool --per-region --no-slope -o chroms.png")]
pub struct ExpectedPlotArgs {
    /// Contact matrices or cis expected tables, one curve each.
    #[arg(value_name = "URI|TABLE", required = true)]
    pub inputs: Vec<String>,
    /// Legend names of the inputs, comma separated (default: the file names).
    #[arg(long, value_delimiter = ',', value_name = "NAMES")]
    pub labels: Option<Vec<String>>,
    /// Draw the fitted power law of each curve, exponent in the legend.
    #[arg(long)]
    pub fit: bool,
    /// Distance range of the fits in bp, e.g. 100k-10M (default: see below).
    #[arg(long, value_name = "MIN-MAX", requires = "fit")]
    pub fit_range: Option<String>,
    /// One curve per region (chromosome) instead of the combined P(s).
    #[arg(long, conflicts_with = "fit")]
    pub per_region: bool,
    /// Leave out the local-slope panel.
    #[arg(long)]
    pub no_slope: bool,
    /// Raw counts for matrix inputs (default: balanced with --weight-name).
    #[arg(long)]
    pub raw: bool,
    /// Weight column for balanced values of matrix inputs.
    #[arg(long, default_value = "weight", value_name = "COLUMN")]
    pub weight_name: String,
    /// BED file of regions for matrix inputs (`chrom start end [name]`).
    #[arg(long, value_name = "BED")]
    pub view: Option<PathBuf>,
    /// Diagonals 0..N left out of the expected of matrix inputs.
    #[arg(long, default_value_t = 2, value_name = "N")]
    pub ignore_diags: usize,
    /// Output, size, dpi, title.
    #[command(flatten)]
    pub figure: FigureArgs,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// Default figure width in inches.
const DEFAULT_WIDTH_IN: f64 = 6.0;

/// The legend name of an input: the file name without its extensions, and the resolution of
/// an `::/resolutions/N` URI.
fn default_label(uri: &str) -> String {
    let (file, inner) = uri.split_once("::").unwrap_or((uri, ""));
    let name = Path::new(file)
        .file_name()
        .map_or_else(|| file.to_string(), |n| n.to_string_lossy().into_owned());
    let mut stem = name.as_str();
    for extension in [".gz", ".tsv", ".txt", ".cool", ".mcool", ".hic", ".h5"] {
        stem = stem.strip_suffix(extension).unwrap_or(stem);
    }
    match inner.rsplit('/').next().and_then(|n| n.parse::<u64>().ok()) {
        Some(resolution) => format!("{stem} {}", format_bp(resolution as f64)),
        None => stem.to_string(),
    }
}

fn load(uri: &str, args: &ExpectedPlotArgs, fit_range: Option<FitRange>) -> Result<PowerLaw> {
    if Table::starts_with_column(uri, "region1")? {
        let table = CisExpected::from_table(&Table::read(uri)?)?;
        let median_bp = table.median_region_length_bp();
        return power_law_of_table(table, args.ignore_diags, median_bp, fit_range);
    }
    let reader = open_for_analysis(uri, &args.input)?;
    if reader.bins().resolution().is_none() {
        return Err(Error::format(
            reader.source(),
            "P(s) needs fixed-size bins (distances are diagonals times the bin size)",
        ));
    }
    let (weights, view) = weights_and_view(
        reader.as_ref(),
        args.raw,
        &args.weight_name,
        args.view.as_deref(),
    )?;
    let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader.as_ref()));
    let params = CisParams {
        ignore_diags: args.ignore_diags,
        smooth: false,
        aggregate_smoothed: false,
        smooth_sigma_log10: 0.1,
    };
    let result = power_law(&pixels, weights.as_deref(), &view, &params, fit_range)?;
    super::super::warnings::print_reader_warnings(reader.warnings());
    Ok(result)
}

/// Run `contactmap plot expected`.
pub fn run(args: &ExpectedPlotArgs) -> Result<()> {
    let inputs: Vec<&Path> = args
        .inputs
        .iter()
        .map(|input| uri_file(input))
        .chain(args.view.as_deref())
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[Some(&args.figure.out)])?;
    let figure = args.figure.check(DEFAULT_WIDTH_IN)?;
    let labels = super::figure::legend_labels(args.labels.as_ref(), &args.inputs, default_label)?;
    let fit_range = args
        .fit_range
        .as_deref()
        .map(str::parse::<FitRange>)
        .transpose()?;
    let mut samples = Vec::with_capacity(args.inputs.len());
    for (uri, label) in args.inputs.iter().zip(labels) {
        let power_law = load(uri, args, fit_range)?;
        if power_law.binned.combined.is_empty() {
            return Err(Error::Data(format!(
                "{uri}: no distance has enough valid pixels for a P(s) point (cooltools' thresholds: more than 200 valid pixels and a sum above 50 per log bin and region)"
            )));
        }
        if args.fit {
            match &power_law.fit {
                Ok(report) => eprintln!("{label}: {}", report.headline()),
                Err(e) => return Err(Error::Data(format!("{uri}: no power-law fit: {e}"))),
            }
        }
        samples.push(PsSample { label, power_law });
    }
    let options = PsFigure {
        per_region: args.per_region,
        fit: args.fit,
        slope_panel: !args.no_slope,
        title: args.figure.title.clone().unwrap_or_default(),
        width_px: figure.width_px,
        height_px: figure.height_px,
        dpi: figure.dpi,
    };
    let svg = draw_curves(&ps_figure(&samples, &options))?;
    write_figure(&svg, &figure, &args.figure)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_come_from_file_names() {
        assert_eq!(
            default_label("data/cooler_test_file.mcool::/resolutions/100000"),
            "cooler_test_file 100 kb"
        );
        assert_eq!(default_label("out/exp.tsv.gz"), "exp");
        assert_eq!(default_label("yeast.10kb.cool"), "yeast.10kb");
    }
}
