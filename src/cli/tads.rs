//! `contactmap tads`: TAD boundaries and domains along the chromosomes: diamond insulation (as
//! `cooltools insulation`), directionality index (as cooltools) with Dixon's HMM, TopDom, Armatus.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};

use crate::cli::args::InputArgs;
use crate::cli::input::{bp_option, weights_and_view};
use crate::cli::output::{is_stdout, print_json, write_whole};
use crate::cli::output::{refuse_overwrites, uri_file};
use crate::cli::warnings::Warnings;
use contactmap::error::{Error, Result};
use contactmap::genome::BinTable;
use contactmap::io::{LoadedPixels, MatrixReader, StreamedPixels};
use contactmap::tads::armatus::ArmatusParams;
use contactmap::tads::call::{Caller, call};
use contactmap::tads::directionality::DirectionalityParams;
use contactmap::tads::hmm::HmmParams;
use contactmap::tads::insulation::{
    DEFAULT_WINDOW_BINS, InsulationParams, check_window_fits, window_bins,
};
use contactmap::tads::threshold::Threshold;
use contactmap::tads::topdom::TopDomParams;

/// TAD callers, for `--method`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// diamond insulation score and prominent minima (Crane 2015), as cooltools insulation
    Insulation,
    /// directionality index (Dixon 2012) as cooltools, domains from a 3-state HMM
    Directionality,
    /// TopDom (Shin 2016): binSignal minima filtered by a Wilcoxon test
    Topdom,
    /// Armatus (Filippova 2014): nested domains by dynamic programming over several scales
    Armatus,
}

/// Arguments of `contactmap tads`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Methods and their outputs (-o: per-bin track, tab-separated with a header, `nan` for NaN):

  insulation      cooltools insulation's table, same columns and values:
                  chrom start end region is_bad_bin [dist_bad_bin]
                  log2_insulation_score_W n_valid_pixels_W [sum_counts_W sum_balanced_W] ...
                  boundary_strength_W ... is_boundary_W ...
                  Diamond of W/binsize bins without the --ignore-diags diagonals (default: the
                  number the weights were balanced with), score over its median, log2;
                  boundary strength = prominence of the minima over bins with at least
                  --min-frac-valid-pixels of the fullest diamond; boundaries are strengths >= the
                  --threshold cutoff (li, otsu or a number; cooltools' default is li). Unlike
                  cooltools 0.7.1, otsu works when some strengths are NaN (they are left out).
  directionality  cooltools directionality's table: chrom start end bad_bin_masked
                  directionality_ratio_W directionality_index_W, plus di_state (upstream, neutral,
                  downstream) from a 3-state Gaussian HMM fitted genome-wide to the index's
                  signed normal scores (Dixon 2012); domains run from a downstream-biased run to the end of the following
                  upstream-biased run.
  topdom          chrom start end bin_signal local_min pvalue segment (domain, gap, boundary):
                  TopDom's binSignal over --window (default 5 bins), local minima, and its
                  Wilcoxon filter (p < 0.05).
  armatus         domains at each --gamma: chrom start end level gamma score (level 0 = smallest
                  gamma = largest domains); boundaries are the edges of --bed-level's domains.

--boundaries writes the boundary bins as BED (chrom start end name score; score = strength, `.`
when the method has none) and --domains the domains as BED (chrom start end name score). With
several insulation windows, the BED files use --bed-window (default: the first window).

Balanced values (count * w1 * w2, the --weight-name column, default `weight`) are used unless
--raw. A window must be a multiple of the bin size. Regions (whole chromosomes, or --view BED)
shorter than the window get truncated diamonds, as in cooltools, with a warning; a --view region
shorter than the window is an error.

Examples:
  contactmap tads data/yeast.10kb.cool --window 30k,50k,100k \\
      -o yeast.insulation.tsv
  contactmap tads in.mcool::/resolutions/10000 --window 200k \\
      --boundaries b.bed --domains d.bed
  contactmap tads in.cool --method directionality --window 500k -o di.tsv \\
      --domains di.bed
  contactmap tads in.cool --method topdom --boundaries topdom.bed
  contactmap score boundaries --truth truth.bed b.bed")]
pub struct TadsArgs {
    /// Matrix URI: file.cool, file.mcool::/resolutions/N, file.hic, text table.
    pub uri: String,
    /// TAD caller.
    #[arg(long, value_enum, default_value_t = MethodArg::Insulation)]
    pub method: MethodArg,
    /// Window(s) in bp, comma-separated, multiples of the bin size (k / M suffixes allowed).
    /// Default: 10 bins (insulation, directionality), 5 bins (topdom).
    #[arg(long, value_delimiter = ',', value_name = "BP[,BP...]")]
    pub window: Vec<String>,
    /// Pixels closer than this to the diagonal (j - i < N) are left out. Default, as cooltools:
    /// the ignore_diags stored with the weights (--weight-name for insulation, `weight` for
    /// directionality), else 2; 2 with --raw and for armatus.
    #[arg(long, value_name = "N")]
    pub ignore_diags: Option<usize>,
    /// Insulation: boundaries need at least this fraction of the fullest diamond's valid pixels.
    #[arg(long, default_value_t = 0.66, value_name = "FRACTION")]
    pub min_frac_valid_pixels: f64,
    /// Mask scores of bins closer than this to a masked bin (insulation default 0, directionality
    /// default 2, as cooltools).
    #[arg(long, value_name = "BINS")]
    pub min_dist_bad_bin: Option<usize>,
    /// Insulation: boundary strength cutoff: li, otsu, or a number.
    #[arg(long, default_value = "li", value_name = "li|otsu|VALUE")]
    pub threshold: String,
    /// Insulation: add sum_counts_W and sum_balanced_W columns.
    #[arg(long)]
    pub append_raw_scores: bool,
    /// TopDom: skip the Wilcoxon filter of false boundaries.
    #[arg(long)]
    pub no_filter: bool,
    /// Armatus: resolution parameters, comma-separated (larger = smaller domains).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.2,0.5,1.0",
        value_name = "G[,G...]"
    )]
    pub gamma: Vec<f64>,
    /// Armatus: largest domain, in bp.
    #[arg(long, default_value = "2M", value_name = "BP")]
    pub max_domain: String,
    /// Armatus: the level whose domain edges are written by --boundaries.
    #[arg(long, default_value_t = 0)]
    pub bed_level: u32,
    /// Directionality: domains shorter than this many bins are dropped.
    #[arg(long, default_value_t = 3, value_name = "BINS")]
    pub min_domain_bins: usize,
    /// Insulation: the window (bp) whose calls go to --boundaries / --domains.
    #[arg(long, value_name = "BP")]
    pub bed_window: Option<String>,
    /// Use raw counts instead of balanced ones (no bin is masked).
    #[arg(long)]
    pub raw: bool,
    /// Weight column for balancing.
    #[arg(long, default_value = "weight", value_name = "COLUMN")]
    pub weight_name: String,
    /// Regions as BED (`chrom start end [name]`), sorted and non-overlapping; default: whole
    /// chromosomes.
    #[arg(long, value_name = "BED")]
    pub view: Option<PathBuf>,
    /// Write the per-bin track (or Armatus' domains) to FILE (gzip if .gz); `-` = stdout.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Print a summary as JSON on standard output (method, boundaries and domains called; per
    /// insulation window its boundaries and strength cutoff); needs -o FILE for the track.
    #[arg(long)]
    pub json: bool,
    /// Write boundaries as BED to FILE (`-` = stdout).
    #[arg(long, value_name = "FILE")]
    pub boundaries: Option<PathBuf>,
    /// Write domains as BED to FILE (`-` = stdout).
    #[arg(long, value_name = "FILE")]
    pub domains: Option<PathBuf>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `contactmap tads`.
pub fn run(args: &TadsArgs) -> Result<()> {
    let inputs: Vec<&Path> = std::iter::once(uri_file(&args.uri))
        .chain(args.view.as_deref())
        .chain(args.input.files())
        .collect();
    refuse_overwrites(
        &inputs,
        &[
            args.out.as_deref(),
            args.boundaries.as_deref(),
            args.domains.as_deref(),
        ],
    )?;
    // Option values are checked before any file is read.
    parse_threshold(args)?;
    if args.json && is_stdout(args.out.as_deref()) {
        return Err(Error::Argument(
            "--json prints the summary on standard output, where the track goes without -o FILE: give -o FILE".into(),
        ));
    }
    let reader = crate::cli::input::open_for_analysis(&args.uri, &args.input)?;
    let bins = reader.bins().clone();
    let resolution = bins.resolution().ok_or_else(|| {
        Error::format(
            reader.source(),
            "TAD calling needs fixed-size bins (windows are counted in bins)",
        )
    })?;
    let windows = windows_bp(args, &bins, resolution)?;
    let explicit_view = args.view.is_some();
    let (weights, view) = weights_and_view(
        reader.as_ref(),
        args.raw,
        &args.weight_name,
        args.view.as_deref(),
    )?;
    let largest = windows.iter().copied().max().unwrap_or(resolution);
    // Printed only once the outputs are written: a warning never comes before an error.
    let mut warnings = Warnings::new();
    if args.method != MethodArg::Armatus {
        let window_bins = (largest / resolution) as usize;
        warnings.extend(check_window_fits(
            &view,
            window_bins,
            largest,
            explicit_view,
        )?);
    }
    let pixels = LoadedPixels::Streamed(StreamedPixels::new(reader.as_ref()));
    let weights = weights.as_deref();
    let caller = caller(args, reader.as_ref(), &windows, resolution)?;
    let calls = call(&pixels, weights, &view, &caller)?;
    warnings.extend(calls.warnings.iter().cloned());
    for note in &calls.notes {
        warnings.note(note.clone());
    }
    let track = calls.track.to_tsv(&bins);
    write_whole(args.out.as_deref(), &track)?;
    if let Some(path) = &args.boundaries {
        write_whole(Some(path), &calls.boundaries_bed(&bins))?;
    }
    if let Some(path) = &args.domains {
        write_whole(Some(path), &calls.domains_bed(&bins))?;
    }
    warnings.note(format!(
        "{}: {} boundaries, {} domains",
        calls.label,
        calls.boundaries.len(),
        calls.domains.len()
    ));
    if args.json {
        print_json(&calls.summary_json(&args.uri, &format!("{:?}", args.method).to_lowercase()))?;
    }
    warnings.extend(reader.warnings());
    warnings.print();
    Ok(())
}

fn parse_threshold(args: &TadsArgs) -> Result<Threshold> {
    if !(0.0..=1.0).contains(&args.min_frac_valid_pixels) {
        return Err(Error::Argument(
            "--min-frac-valid-pixels must be between 0 and 1".into(),
        ));
    }
    args.threshold
        .parse()
        .map_err(|e| Error::Argument(format!("--threshold: {e}")))
}

/// The windows in bp: given (each checked by the library's one check), or the method's default
/// number of bins.
fn windows_bp(args: &TadsArgs, bins: &BinTable, resolution: u64) -> Result<Vec<u64>> {
    let mut windows = Vec::with_capacity(args.window.len());
    for text in &args.window {
        let value = bp_option("--window", text)?;
        window_bins(bins, value).map_err(|e| Error::Argument(format!("--window {text}: {e}")))?;
        windows.push(value);
    }
    if windows.is_empty() {
        let n_bins = match args.method {
            MethodArg::Topdom => TopDomParams::default().window_bins,
            _ => DEFAULT_WINDOW_BINS,
        };
        windows.push(n_bins as u64 * resolution);
    }
    if windows.len() > 1 && args.method != MethodArg::Insulation {
        return Err(Error::Argument(
            format!("--window: {:?} takes a single window", args.method).to_lowercase(),
        ));
    }
    Ok(windows)
}

/// The library's caller for the options: the method, its window and parameters.
fn caller(
    args: &TadsArgs,
    reader: &dyn MatrixReader,
    windows: &[u64],
    resolution: u64,
) -> Result<Caller> {
    // cooltools' default: the diagonals the balancing left out, stored with the weights
    let stored = |column: &str| match args.ignore_diags {
        Some(n) => n,
        None if args.raw => 2,
        None => reader.stored_ignore_diags(column).unwrap_or(2),
    };
    Ok(match args.method {
        MethodArg::Insulation => {
            let calls_window = match &args.bed_window {
                None => 0,
                Some(text) => {
                    let bp = bp_option("--bed-window", text)?;
                    windows.iter().position(|&w| w == bp).ok_or_else(|| {
                        Error::Argument(format!(
                            "--bed-window {text} is not one of the --window values"
                        ))
                    })?
                }
            };
            Caller::Insulation {
                params: InsulationParams {
                    windows_bp: windows.to_vec(),
                    ignore_diags: stored(&args.weight_name),
                    min_frac_valid_pixels: args.min_frac_valid_pixels,
                    min_dist_bad_bin: args.min_dist_bad_bin.unwrap_or(0),
                    threshold: parse_threshold(args)?,
                    append_raw_scores: args.append_raw_scores,
                },
                calls_window,
            }
        }
        MethodArg::Directionality => Caller::Directionality {
            params: DirectionalityParams {
                window_bp: windows[0],
                ignore_diags: stored("weight"),
                min_dist_bad_bin: args.min_dist_bad_bin.unwrap_or(2),
            },
            hmm: HmmParams {
                min_domain_bins: args.min_domain_bins,
                ..HmmParams::default()
            },
        },
        MethodArg::Topdom => Caller::TopDom(TopDomParams {
            window_bins: (windows[0] / resolution) as usize,
            statistical_filter: !args.no_filter,
            ..TopDomParams::default()
        }),
        MethodArg::Armatus => {
            let max_domain_bp = bp_option("--max-domain", &args.max_domain)?;
            let mut gammas = args.gamma.clone();
            if gammas.iter().any(|g| !g.is_finite() || *g < 0.0) {
                return Err(Error::Argument("--gamma values must be >= 0".into()));
            }
            gammas.sort_by(f64::total_cmp);
            gammas.dedup();
            Caller::Armatus {
                params: ArmatusParams {
                    gammas,
                    max_domain_bins: (max_domain_bp / resolution).max(2) as usize,
                },
                ignore_diags: args.ignore_diags.unwrap_or(2),
                boundary_level: args.bed_level,
            }
        }
    })
}
