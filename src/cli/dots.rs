//! `contactmap dots`: loops called as cooltools' dot caller ([`contactmap::loops`]).

use std::path::PathBuf;

use clap::Args;

use crate::cli::args::InputArgs;
use crate::cli::input::{bp_option, expected_to_divide, open_balanced};
use crate::cli::output::{refuse_overwrites, uri_file};
use crate::cli::warnings::Warnings;
use contactmap::error::{Error, Result};
use contactmap::io::MatrixReader;
use contactmap::io::bed::read_bedpe_table;
use contactmap::io::output::write_whole;
use contactmap::io::tables::Table;
use contactmap::loops::kernels::recommended_w_p;
use contactmap::loops::lists::{ResolutionList, merge_lists};
use contactmap::loops::merge::{MergeParams, check_resolutions};
use contactmap::loops::tables::{dots_tsv, enriched_tsv};
use contactmap::loops::{DotCalls, DotsParams, call_dots};

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
45 lambda bins, 39 kb); on deep maps the API's FDR 0.1 also calls weaker structure (on
simulated extrusion maps the preset keeps only the true loops: docs/loops.md). Unlike
cooltools, a pixel above the last lambda bin (8192 raw counts of local expected for 40 bins) is
not an error: the bins continue; and nothing depends on a tile size (there are no tiles: the
band is read a block of rows at a time).

Output: cooltools' columns, tab-separated, with a header: chrom1 start1 end1 chrom2 start2 end2
count la_exp.{donut,vertical,horizontal,lowleft}.value la_exp.{...}.qval region cstart1 cstart2
c_label c_size region1 region2 (22 columns: one row per dot); --no-cluster writes the first 15
for the enriched pixels; --enriched FILE writes those as well as the dots.

Several resolutions: --resolutions 5000,10000,25000 on an .mcool or .hic (the file alone, no
::/resolutions/N) calls dots at each (cooltools' kernels for each bin size, each level's own
weights and expected) and merges the three lists as Juicer's HiCCUPS does (`contactmap
dots-merge --help`); the table gets a last column, resolution.

Examples:
  contactmap dots sample.mcool::/resolutions/10000 -o sample.dots.bedpe
  contactmap dots sample.mcool --resolutions 5k,10k,25k -o merged.bedpe
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
    /// Call at each of these resolutions of a multi-resolution file (5k,10k,25k or some of
    /// them) and merge the calls as HiCCUPS does.
    #[arg(long, value_name = "BP,...", value_delimiter = ',')]
    pub resolutions: Option<Vec<String>>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

impl DotsArgs {
    /// The library's parameters for bins of `resolution` bp.
    fn params(&self, resolution: u64) -> Result<DotsParams> {
        let (w, p) = match (self.w, self.p) {
            (Some(w), Some(p)) => (w, p),
            _ => recommended_w_p(resolution).ok_or_else(|| {
                Error::Argument(format!(
                    "no kernel size for {resolution} bp bins: cooltools recommends kernels for 4-28 kb \
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
        if params.max_separation_bp < 2 * resolution {
            return Err(Error::Argument(format!(
                "--max-separation {}: at least two bins ({} bp)",
                params.max_separation_bp,
                2 * resolution
            )));
        }
        Ok(params)
    }
}

/// A map's dots, with what is needed to write and report them.
struct Called {
    reader: Box<dyn MatrixReader>,
    view: contactmap::genome::View,
    params: DotsParams,
    calls: DotCalls,
}

/// Call the dots of `uri` (opened with `input`) with the options of `args`.
fn call(args: &DotsArgs, uri: &str, input: &InputArgs) -> Result<Called> {
    let (reader, weights, view) =
        open_balanced(uri, input, &args.weight_name, args.view.as_deref())?;
    let bins = reader.bins();
    let resolution = bins.resolution().ok_or_else(|| {
        Error::format(
            reader.source(),
            "dots needs fixed-size bins (kernels are counted in bins)",
        )
    })?;
    let params = args.params(resolution)?;
    let table = args.expected.as_deref().map(Table::read).transpose()?;
    let expected = expected_to_divide(
        reader.as_ref(),
        Some(&weights),
        &view,
        table.as_ref(),
        &args.expected_column,
        false,
    )?;
    let calls = call_dots(reader.as_ref(), &weights, &view, &expected, &params)?;
    Ok(Called {
        reader,
        view,
        params,
        calls,
    })
}

/// The one-line summary of a call, and its warnings, to `notes`.
fn report(called: &Called, notes: &mut Warnings, label: &str) {
    let Called { calls, params, .. } = called;
    let mut summary = format!(
        "dots{label}: {} pixels scored (w={}, p={}, up to {} bp), {} enriched",
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
    notes.extend(called.reader.warnings());
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
        return Err(Error::Argument(
            "--no-cluster writes the enriched pixels to -o: leave out --enriched".into(),
        ));
    }
    if let Some(resolutions) = &args.resolutions {
        return run_resolutions(args, resolutions);
    }
    let called = call(args, &args.uri, &args.input)?;
    let bins = called.reader.bins();
    let table = match dots_tsv(&called.calls, bins, &called.view) {
        Some(dots) => {
            if let Some(path) = &args.enriched {
                write_whole(Some(path), enriched_tsv(&called.calls, bins).as_bytes())?;
            }
            dots
        }
        None => enriched_tsv(&called.calls, bins),
    };
    write_whole(args.out.as_deref(), table.as_bytes())?;
    let mut notes = Warnings::new();
    report(&called, &mut notes, "");
    notes.print();
    Ok(())
}

/// `dots --resolutions`: call each level of a multi-resolution file, merge as HiCCUPS.
fn run_resolutions(args: &DotsArgs, resolutions: &[String]) -> Result<()> {
    let refuse = |option: &str, why: &str| -> Result<()> {
        Err(Error::Argument(format!(
            "--resolutions: leave out {option} ({why})"
        )))
    };
    if args.w.is_some() {
        refuse(
            "--w / --p",
            "each resolution takes cooltools' kernel for its bin size",
        )?;
    }
    if args.expected.is_some() {
        refuse(
            "--expected",
            "each resolution's expected is computed from its own level",
        )?;
    }
    if args.enriched.is_some() || args.no_cluster {
        refuse(
            "--enriched and --no-cluster",
            "the merge works on clustered dots",
        )?;
    }
    if args.input.resolution.is_some() {
        refuse("--resolution", "the levels come from --resolutions")?;
    }
    if contactmap::io::split_uri(&args.uri).1.is_some() {
        return Err(Error::Argument(format!(
            "--resolutions needs the multi-resolution file alone, not '{}': the levels come \
             from --resolutions",
            args.uri
        )));
    }
    let resolutions = resolutions
        .iter()
        .map(|text| bp_option("--resolutions", text))
        .collect::<Result<Vec<u64>>>()?;
    check_resolutions(&resolutions)?;
    let mut lists = Vec::new();
    let mut notes = Warnings::new();
    for resolution in resolutions {
        let input = InputArgs {
            resolution: Some(resolution),
            ..args.input.clone()
        };
        let called = call(args, &args.uri, &input)?;
        report(&called, &mut notes, &format!(" at {resolution} bp"));
        let bins = called.reader.bins();
        lists.extend(ResolutionList::of_dots(
            called.reader.source(),
            resolution,
            &called.calls,
            bins,
            &called.view,
        ));
    }
    let merged = merge_lists(&lists, &MergeParams::default())?;
    write_whole(args.out.as_deref(), merged.to_tsv().as_bytes())?;
    notes.note(merged.summary());
    notes.print();
    Ok(())
}

/// Arguments of `contactmap dots-merge`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Merges dot calls made at 5, 10 and 25 kb into one list as Juicer's HiCCUPS merges its
resolutions (HiCCUPSUtils.mergeAllResolutions):
  1. 5 and 10 kb: the 5 kb calls with a 10 kb call within 20 kb (confirmed), the 10 kb calls with
     no 5 kb call within 20 kb, and the 5 kb calls near the diagonal (anchors' starts less than
     --near-diagonal apart, 110 kb) or strong (count above --strong, 100), confirmed or not;
     with only one of the two lists, all of its calls;
  2. 25 kb: the calls with no call of step 1 within 50 kb (all of them without a 5 or 10 kb list).
Distances are between the calls' (start1, start2), as Juicer measures them. Juicer defines the
rule for these three resolutions only: another resolution is an error here (Juicer drops it).

Inputs: `contactmap dots` (or cooltools dots) tables, each as FILE@RESOLUTION, or FILE alone when
its rows are all one bin wide (the resolution is their width). The strength is the `count`
column (cooltools) or `observed` (Juicer); the files must have the same columns.

Output: the kept rows as they were, with a last column, resolution; sorted by chromosome, start1,
start2.

Examples:
  contactmap dots s.mcool::/resolutions/5000 -o d5.bedpe
  contactmap dots s.mcool::/resolutions/10000 -o d10.bedpe
  contactmap dots s.mcool::/resolutions/25000 -o d25.bedpe
  contactmap dots-merge d5.bedpe@5000 d10.bedpe@10000 d25.bedpe@25000 \\
      -o merged.bedpe
  # the same, in one step:
  contactmap dots s.mcool --resolutions 5k,10k,25k -o merged.bedpe")]
pub struct DotsMergeArgs {
    /// Dot tables, each FILE@RESOLUTION (bp: 5000, 10k ...) or FILE.
    #[arg(required = true, value_name = "FILE[@RES]")]
    pub lists: Vec<String>,
    /// Output table (standard output when not given or `-`; .gz compresses).
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// 5 kb calls with anchors' starts closer than this are kept unconfirmed (bp).
    #[arg(long, value_name = "BP", default_value = "110000")]
    pub near_diagonal: String,
    /// 5 kb calls with a count above this are kept unconfirmed.
    #[arg(long, default_value_t = 100.0)]
    pub strong: f64,
}

/// `FILE@RES` split; `None` for the resolution when there is no `@` followed by a bp value.
fn split_list(text: &str) -> Result<(&str, Option<u64>)> {
    match text.rsplit_once('@') {
        Some((path, res)) if !std::path::Path::new(text).exists() => {
            Ok((path, Some(bp_option(&format!("{text}: resolution"), res)?)))
        }
        _ => Ok((text, None)),
    }
}

/// Read one dots table (`FILE` or `FILE@RESOLUTION`) for the merge.
fn read_list(text: &str) -> Result<ResolutionList> {
    let (path_text, given) = split_list(text)?;
    let path = std::path::Path::new(path_text);
    ResolutionList::of_table(path, &read_bedpe_table(path)?, given)
}

/// Run `contactmap dots-merge`.
pub fn run_merge(args: &DotsMergeArgs) -> Result<()> {
    let mut paths = Vec::new();
    for text in &args.lists {
        paths.push(split_list(text)?.0);
    }
    let inputs: Vec<&std::path::Path> = paths.iter().map(std::path::Path::new).collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let lists = args
        .lists
        .iter()
        .map(|text| read_list(text))
        .collect::<Result<Vec<_>>>()?;
    let params = MergeParams {
        near_diagonal_bp: bp_option("--near-diagonal", &args.near_diagonal)?,
        strong_count: args.strong,
    };
    let merged = merge_lists(&lists, &params)?;
    write_whole(args.out.as_deref(), merged.to_tsv().as_bytes())?;
    let mut notes = Warnings::new();
    notes.note(merged.summary());
    notes.print();
    Ok(())
}
