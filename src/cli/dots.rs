//! `contactmap dots`: loops called as cooltools' dot caller ([`contactmap::loops`]).

use std::path::PathBuf;

use clap::Args;

use crate::cli::input::{bp_option, open_balanced};
use crate::cli::output::{refuse_overwrites, uri_file};
use crate::cli::warnings::Warnings;
use crate::cli::InputArgs;
use contactmap::error::{Error, Result};
use contactmap::expected::table::read_region_column;
use contactmap::expected::{expected_cis, CisParams};

use contactmap::io::output::write_whole;
use contactmap::loops::kernels::recommended_w_p;
use contactmap::loops::tables::{dots_tsv, enriched_tsv};
use contactmap::loops::{call_dots, DotsParams};

/// Arguments of `contactmap dots`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
As cooltools dots (0.7.1, cooltools.api.dotfinder.dots), step for step, on a balanced map:
  1. every pixel of each region (whole chromosomes, or the regions of --view) up to
     --max-separation from the diagonal gets a locally adjusted expected for each of four
     kernels (donut, vertical, horizontal, lower-left; half-widths --w / --p, by default
     cooltools' choice for the bin size: w=7,p=4 for 4-8 kb bins, 5,2 for 8-18 kb, 3,1 for
     18-28 kb): the expected of its distance times the ratio of observed to expected summed over
     the kernel, in raw counts. A kernel reaching --max-nans-tolerated missing cells (masked bins,
     the diagonal, the region's edge) leaves the pixel out;
  2. per kernel, pixels are binned by that value (lambda bins at 2^(k/3)); in each bin the
     smallest count whose excess over a Poisson background keeps the false discovery rate under
     --fdr is the threshold (cooltools' test, P(X > k); HiCCUPS uses P(X >= k));
  3. the enriched pixels pass the threshold of their bin for all four kernels; each gets a
     q-value per kernel;
  4. enriched pixels are clustered per region (BIRCH with threshold --clustering-radius, as
     scikit-learn computes it), the brightest pixel of a cluster represents it;
  5. HiCCUPS' filter keeps a representative with count > 1.75 x donut and lower-left expected,
     > 1.5 x vertical and horizontal, > 2 x donut or lower-left, and, for a single-pixel
     cluster, q-values summing to at most 0.02 (--no-filter keeps them all).
The expected is computed as `contactmap expected` does (balanced.avg, 2 diagonals ignored)
unless --expected gives a cooltools table (same bins, same view).

Defaults are the cooltools API's (max separation 10 Mb, FDR 0.1, 40 lambda bins, clustering
radius 20 kb); cooltools' command line uses others: --cooltools-cli sets them (2 Mb, FDR 0.02,
45 lambda bins, 39 kb). Unlike cooltools, a pixel above the last lambda bin (8192 raw counts of
local expected for 40 bins) is not an error: the bins continue; and nothing depends on a tile
size (there are no tiles: the band is read a block of rows at a time).

Output: cooltools' columns, tab-separated, with a header: chrom1 start1 end1 chrom2 start2 end2
count la_exp.{donut,vertical,horizontal,lowleft}.value la_exp.{...}.qval region cstart1 cstart2
c_label c_size region1 region2 (22 columns: one row per dot); --no-cluster writes the first 15
for the enriched pixels; --enriched FILE writes those as well as the dots.

Examples:
  contactmap dots sample.mcool::/resolutions/10000 -o sample.dots.bedpe
  contactmap dots sample.mcool::/resolutions/5000 --view arms.bed \\
      --cooltools-cli -o dots.tsv
  contactmap dots map_100kb.cool --w 3 --p 1 --no-cluster -o enriched.tsv")]
pub struct DotsArgs {
    /// The map (balanced: it needs a weight column).
    pub uri: String,
    /// Output table (standard output when not given or `-`; .gz compresses).
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Also write the enriched pixels (15 columns) here.
    #[arg(long, value_name = "FILE")]
    pub enriched: Option<PathBuf>,
    /// Weight column.
    #[arg(long, alias = "balanced", default_value = "weight")]
    pub weight_name: String,
    /// A cooltools cis expected table (expected-cis / `contactmap expected`) on the same bins
    /// and view, instead of computing it.
    #[arg(long, value_name = "TSV")]
    pub expected: Option<String>,
    /// Column of --expected to use.
    #[arg(long, default_value = "balanced.avg", requires = "expected")]
    pub expected_column: String,
    /// Regions (BED: chrom, start, end, optional name) instead of whole chromosomes.
    #[arg(long)]
    pub view: Option<PathBuf>,
    /// Kernel outer half-width (bins); default by bin size as cooltools.
    #[arg(long, requires = "p")]
    pub w: Option<usize>,
    /// Kernel inner half-width (bins).
    #[arg(long, requires = "w")]
    pub p: Option<usize>,
    /// Largest separation of the pixels scored (bp: 10M, 2000000 ...); default 10 Mb.
    #[arg(long, value_name = "BP")]
    pub max_separation: Option<String>,
    /// A kernel with this many missing cells leaves the pixel out.
    #[arg(long, default_value_t = 1)]
    pub max_nans_tolerated: usize,
    /// Lambda bins (40 to 50); default 40.
    #[arg(long)]
    pub n_lambda_bins: Option<usize>,
    /// False discovery rate per lambda bin; default 0.1.
    #[arg(long)]
    pub fdr: Option<f64>,
    /// BIRCH clustering threshold (bp); default 20 kb.
    #[arg(long, value_name = "BP")]
    pub clustering_radius: Option<String>,
    /// No clustering: write the enriched pixels (15 columns).
    #[arg(long)]
    pub no_cluster: bool,
    /// Keep every cluster's representative (no HiCCUPS enrichment filter).
    #[arg(long)]
    pub no_filter: bool,
    /// cooltools' command-line defaults: --max-separation 2M --fdr 0.02 --n-lambda-bins 45
    /// --clustering-radius 39000 (options given still win).
    #[arg(long)]
    pub cooltools_cli: bool,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

impl DotsArgs {
    /// The library's parameters for bins of `bin_size` bp.
    fn params(&self, bin_size: u64) -> Result<DotsParams> {
        let (w, p) = match (self.w, self.p) {
            (Some(w), Some(p)) => (w, p),
            _ => recommended_w_p(bin_size).ok_or_else(|| {
                Error::Invalid(format!(
                    "no kernel size for {bin_size} bp bins: cooltools recommends kernels for 4-28 kb \
                     bins only; give --w and --p (HiCCUPS: --w 7 --p 4 at 5 kb, --w 5 --p 2 at 10 kb, \
                     --w 3 --p 1 at 25 kb)"
                ))
            })?,
        };
        let mut params = DotsParams {
            w,
            p,
            ..DotsParams::default()
        };
        if self.cooltools_cli {
            params = params.cooltools_cli();
        }
        if let Some(text) = &self.max_separation {
            params.max_separation_bp = bp_option("--max-separation", text)?;
        }
        if let Some(text) = &self.clustering_radius {
            params.clustering_radius_bp = Some(bp_option("--clustering-radius", text)? as f64);
        }
        if self.no_cluster {
            params.clustering_radius_bp = None;
        }
        if let Some(n) = self.n_lambda_bins {
            params.n_lambda_bins = n;
        }
        if let Some(fdr) = self.fdr {
            params.fdr = fdr;
        }
        params.max_nans_tolerated = self.max_nans_tolerated;
        params.cluster_filtering = !self.no_filter;
        params.check()?;
        if params.max_separation_bp < 2 * bin_size {
            return Err(Error::Invalid(format!(
                "--max-separation {}: at least two bins ({} bp)",
                params.max_separation_bp,
                2 * bin_size
            )));
        }
        Ok(params)
    }
}

/// Run `contactmap dots`.
pub fn run(args: &DotsArgs) -> Result<()> {
    let inputs: Vec<&std::path::Path> = std::iter::once(uri_file(&args.uri))
        .chain(args.view.as_deref())
        .chain(args.expected.as_deref().map(std::path::Path::new))
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref(), args.enriched.as_deref()])?;
    if args.no_cluster && args.enriched.is_some() {
        return Err(Error::Invalid(
            "--no-cluster writes the enriched pixels to -o: leave out --enriched".into(),
        ));
    }
    let (reader, weights, view) = open_balanced(
        &args.uri,
        &args.input,
        &args.weight_name,
        args.view.as_deref(),
    )?;
    let bins = reader.bins();
    let bin_size = bins.bin_size_bp().ok_or_else(|| {
        Error::format(
            reader.source(),
            "dots needs fixed-size bins (kernels are counted in bins)",
        )
    })?;
    let params = args.params(bin_size)?;
    let expected = match &args.expected {
        Some(path) => read_region_column(path, bins, &view, &args.expected_column)?,
        None => {
            let pixels = contactmap::io::StreamedPixels::new(reader.as_ref());
            let pixels = contactmap::io::LoadedPixels::Streamed(pixels);
            expected_cis(&pixels, Some(&weights), &view, &CisParams::default())?.average_by_region()
        }
    };
    let calls = call_dots(reader.as_ref(), &weights, &view, &expected, &params)?;
    let table = match dots_tsv(&calls, bins, &view) {
        Some(dots) => {
            if let Some(path) = &args.enriched {
                write_whole(Some(path), enriched_tsv(&calls, bins).as_bytes())?;
            }
            dots
        }
        None => enriched_tsv(&calls, bins),
    };
    write_whole(args.out.as_deref(), table.as_bytes())?;
    let mut notes = Warnings::new();
    let mut summary = format!(
        "dots: {} pixels scored (w={}, p={}, up to {} bp), {} enriched",
        calls.n_scored,
        params.w,
        params.p,
        params.max_separation_bp,
        calls.enriched.len()
    );
    if let Some(dots) = &calls.dots {
        summary.push_str(&format!(", {} dots", dots.len()));
    }
    notes.note(summary);
    if calls.extra_lambda_bins > 0 {
        notes.note(format!(
            "{} lambda bin(s) past cooltools' last edge hold pixels (cooltools stops with an \
             error on this map; the bins continue at 2^(1/3))",
            calls.extra_lambda_bins
        ));
    }
    notes.extend(reader.warnings());
    notes.print();
    Ok(())
}
