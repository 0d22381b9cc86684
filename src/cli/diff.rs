//! `contactmap diff`: what changed between two conditions with replicates
//! ([`contactmap::diff`]). `diff loops` tests each loop's counts.

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};

use crate::cli::args::InputArgs;
use crate::cli::input::{bp_option, open_balanced, open_for_analysis, phasing_track, read_weights};
use crate::cli::output::{column_file, refuse_overwrites, uri_file, write_text_file};
use crate::cli::warnings::Warnings;
use contactmap::compartments::cis::CisEigParams;
use contactmap::diff::boundaries::{
    BoundaryParams, BoundaryStatus, boundaries_tsv, compare_boundaries, default_window_bp,
};
use contactmap::diff::calls::called_loops;
use contactmap::diff::compartments::{
    CompartmentParams, Switch, compare_compartments, compartments_tsv, switches_bed,
};
use contactmap::diff::loops::{LoopParams, compare_loops, loops_bedpe, sites_of};
use contactmap::diff::maps::check_same_bins;
use contactmap::diff::regions::{
    RegionParams, compare_regions, pairs_of, regions_tsv, sliding_pairs,
};
use contactmap::error::{Error, Result};
use contactmap::genome::View;
use contactmap::io::MatrixReader;
use contactmap::io::bed::read_bedpe;
use contactmap::tads::insulation::{InsulationParams, window_bins};
use contactmap::tads::threshold::Threshold;

/// Arguments of `contactmap diff`.
#[derive(Debug, Args)]
pub struct DiffArgs {
    /// What to compare.
    #[command(subcommand)]
    pub command: DiffCommand,
}

/// The comparisons.
#[derive(Debug, Subcommand)]
pub enum DiffCommand {
    /// Loops whose contacts changed between two conditions: DESeq2's negative-binomial model of
    /// each loop's counts per replicate, with the expected at its distance as the
    /// normalisation; log2 fold change with its 95% interval, p-value, q-value.
    Loops(DiffLoopsArgs),
    /// Boundaries gained, lost, shifted, stronger or weaker: each replicate's insulation,
    /// boundaries called on each condition's mean, the contacts across each tested against its
    /// flanks (DESeq2's model, as diff loops); q-values.
    Boundaries(DiffBoundariesArgs),
    /// Compartment switches A->B and B->A: each replicate's E1, the difference of the
    /// conditions' means per bin tested with limma's moderated t; q-values, switched segments.
    Compartments(DiffCompartmentsArgs),
    /// Regions whose structure changed: CHESS's structural similarity (SSIM) of each
    /// window's observed/expected in A and B, its z-score and signal-to-noise (chess sim 0.3.8).
    Regions(DiffRegionsArgs),
}

/// Arguments of `contactmap diff regions`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
As `chess sim` (chess-hic 0.3.8; equal to it on the same maps and pairs, docs/diff.md): each
pair's region of A (the reference) and region of B (the query) become observed/expected
matrices (balanced counts over the chromosome's mean at each diagonal, as FAN-C computes it
for CHESS; --raw: raw counts, as CHESS does for a map without weights), compared by the
structural similarity index (SSIM: luminance, contrast and structure over a window the size of
the matrix). A region takes every bin it overlaps. Regions under --min-bins bins, or with more
than --mappability-cutoff of their rows empty in either map, get nan; rows empty in either are
removed from both. z_ssim is each SSIM's z-score against every pair's (population sd); a low
SSIM and a strongly negative z mark a changed region. SN is CHESS's signal-to-noise of the
difference (mean |mean| / variance of 7 x 7 blocks).

The pairs: --pairs BEDPE (chess pairs' format: chrom1 start1 end1 of A, chrom2 start2 end2 of
B, ID, score, strand1, strand2; a region on the other strand is reversed), or --window (and
--step) for windows along every chromosome, the same region in A and B, as `chess pairs`
makes them.

One map per condition (CHESS compares two maps): merge replicates first (contactmap merge,
then balance --store).

Output PREFIX.regions.tsv: ID SN ssim z_ssim (chess sim's columns), then chrom1 start1 end1
chrom2 start2 end2; one line per pair, in order.

Examples:
  contactmap diff regions --a wt.mcool::/resolutions/25000 \\
      --b ko.mcool::/resolutions/25000 --window 2500k --step 500k -o wt_vs_ko
  contactmap diff regions --a a.cool --b b.cool --pairs pairs.bedpe -o a_vs_b")]
pub struct DiffRegionsArgs {
    #[command(flatten)]
    pub conditions: ConditionArgs,
    /// Output prefix: writes PREFIX.regions.tsv.
    #[arg(short, long, value_name = "PREFIX")]
    pub out: PathBuf,
    /// Pairs of regions to compare (BEDPE, chess pairs' format).
    #[arg(
        long,
        value_name = "BEDPE",
        conflicts_with = "window",
        required_unless_present = "window"
    )]
    pub pairs: Option<PathBuf>,
    /// Windows of this size (bp) along every chromosome instead of --pairs.
    #[arg(long)]
    pub window: Option<String>,
    /// Step between windows (bp; default: the window, no overlap).
    #[arg(long, requires = "window")]
    pub step: Option<String>,
    /// Raw counts instead of balanced ones.
    #[arg(long)]
    pub raw: bool,
    /// Weight column of both maps.
    #[arg(long, default_value = "weight")]
    pub weight_name: String,
    /// Regions of fewer bins get nan.
    #[arg(long, default_value_t = 20)]
    pub min_bins: usize,
    /// Largest fraction of empty rows a region may have in either map.
    #[arg(long, default_value_t = 0.1)]
    pub mappability_cutoff: f64,
    /// SSIM window as a fraction of the matrix's size.
    #[arg(long, default_value_t = 1.0)]
    pub relative_window: f64,
    /// SSIM window in bins (instead of --relative-window).
    #[arg(long)]
    pub absolute_window: Option<usize>,
    #[command(flatten)]
    pub input: InputArgs,
}

/// Arguments of `contactmap diff compartments`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Each replicate's E1 is computed as `contactmap compartments` computes it (cooltools eigs-cis of
the balanced map: observed/expected, clipped, centred; the first eigenvector scaled to norm
sqrt(|eigenvalue|)), oriented by --phasing-track or --fasta where given. An eigenvector's sign
is arbitrary, so every replicate's E1 is then given the sign of the first replicate's (A1) on
each region: give a phasing track (gene density, GC) so that E1 > 0 means the A compartment.

Per bin, the conditions' mean E1 are compared with limma's moderated t-test (lmFit ~ condition,
eBayes: each bin's variance shrunk towards that of all bins; docs/diff.md): difference B - A,
standard error, t, degrees of freedom, p-value, Benjamini-Hochberg q-value. A bin switches A->B
when its q-value is under --alpha, its mean E1 positive in A and negative in B (B->A the other
way); consecutive switched bins of a region with the same direction make a segment.

Outputs:
  PREFIX.compartments.tsv   chrom start end E1_A E1_B difference se t df pvalue qvalue switch,
                            then E1_A1 ... E1_B<m>; one line per bin of the view's regions
  PREFIX.switches.bed       chrom start end switch n_bins E1_A E1_B max_qvalue: the segments

Maps must be balanced (--weight-name) and on the same bins; bad input stops the run with one
line and exit status 2 before any output is written.

Examples:
  contactmap diff compartments --a wt1.mcool::/resolutions/100000 \\
      wt2.mcool::/resolutions/100000 --b ko1.mcool::/resolutions/100000 \\
      ko2.mcool::/resolutions/100000 --fasta hg38.fa.gz -o wt_vs_ko
  contactmap diff compartments --a a1.cool a2.cool --b b1.cool b2.cool \\
      --phasing-track genes.tsv:density --view arms.bed -o a_vs_b")]
pub struct DiffCompartmentsArgs {
    #[command(flatten)]
    pub conditions: ConditionArgs,
    /// Output prefix: writes PREFIX.compartments.tsv and PREFIX.switches.bed.
    #[arg(short, long, value_name = "PREFIX")]
    pub out: PathBuf,
    /// Phasing track on the maps' bins: FILE:COLUMN (a header name, or a 1-based column
    /// number for a bedGraph). E1 is oriented to correlate positively with it.
    #[arg(long, value_name = "FILE:COLUMN", conflicts_with = "fasta")]
    pub phasing_track: Option<String>,
    /// Genome FASTA (plain or gzip): the GC content of each bin is the phasing track.
    #[arg(long, value_name = "FASTA")]
    pub fasta: Option<PathBuf>,
    /// Regions (BED: chrom, start, end, optional name) instead of whole chromosomes.
    #[arg(long)]
    pub view: Option<PathBuf>,
    /// Diagonals set to 1 before normalising.
    #[arg(long, default_value_t = 2)]
    pub ignore_diags: usize,
    /// Clip observed/expected above this percentile (0 or 100: no clipping).
    #[arg(long, default_value_t = 99.9)]
    pub clip_percentile: f64,
    /// q-value under which a bin counts as switched.
    #[arg(long, default_value_t = 0.05)]
    pub alpha: f64,
    /// Weight column of every map.
    #[arg(long, default_value = "weight")]
    pub weight_name: String,
    #[command(flatten)]
    pub input: InputArgs,
}

/// Arguments of `contactmap diff boundaries`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Each replicate's insulation is computed as `contactmap tads` (cooltools' diamond insulation of
the balanced map, one --window; log2 of the score over its median). Each condition's
boundaries are the minima of its replicates' mean score, their prominence at or above the
--threshold cutoff (Li by default), over the bins with enough valid pixels in every replicate.
A boundary of B within --match-bins bins of one of A is the same boundary (closest pairs
first); the others stand alone.

At each boundary, each replicate's raw contacts across it (the diamond count at the call) are
tested against its flanks (the mean diamond count 2 to --window bins on either side, as its
expected), as diff loops tests loops against their expected: DESeq2's negative-binomial model,
the flanks as normalisation factors, log2 fold change B over A (negative: fewer contacts across
relative to the flanks in B, a deeper boundary), Wald p-value, Benjamini-Hochberg q-value
(docs/diff.md says why counts and not a t-test of insulation scores). A boundary called in both
at different bins is also tested at A's bin and at B's bin (two more features of the model): it
has shifted when B is weaker at A's bin and stronger at B's, both significant.

Status at q < --alpha: gained (called in B only, deeper in B), lost (called in A only,
shallower in B), shifted (called in both at different bins, the shift significant), stronger /
weaker (deeper / shallower in B otherwise), - (no significant change).

Output PREFIX.boundaries.tsv, tab-separated with a header, one line per boundary in genome
order: chrom start end (the boundary's bin: A's call, else B's), start_A start_B (each
condition's call, . where none), strength_A strength_B (prominence on the mean score),
depth_A depth_B (mean valley depth: the flanks' mean log2 score minus the valley's lowest),
baseMean log2FoldChange lfcSE pvalue qvalue, shift_pvalue shift_qvalue, status, then count_A1
... count_B<m> (contacts across) and expected_A1 ... (the flanks').

Maps must be balanced (--weight-name) and on the same bins; bad input stops the run with one
line and exit status 2 before any output is written.

Examples:
  contactmap diff boundaries --a wt1.cool wt2.cool --b ko1.cool ko2.cool \\
      --window 100k -o wt_vs_ko
  contactmap diff boundaries --a a1.mcool::/resolutions/10000 \\
      a2.mcool::/resolutions/10000 --b b1.mcool::/resolutions/10000 \\
      b2.mcool::/resolutions/10000 --window 200k --alpha 0.1 -o a_vs_b")]
pub struct DiffBoundariesArgs {
    #[command(flatten)]
    pub conditions: ConditionArgs,
    /// Output prefix: writes PREFIX.boundaries.tsv.
    #[arg(short, long, value_name = "PREFIX")]
    pub out: PathBuf,
    /// Insulation window in bp (a multiple of the bin size; default 10 bins). Take about half
    /// the size of the domains compared: a narrower window sees only the contacts near the
    /// diagonal, which a lost boundary hardly changes (docs/diff.md, Known truth).
    #[arg(long)]
    pub window: Option<String>,
    /// Boundary cutoff on the strength: li, otsu or a number.
    #[arg(long, default_value = "li")]
    pub threshold: String,
    /// Diagonals left out of the insulation diamonds.
    #[arg(long, default_value_t = 2)]
    pub ignore_diags: usize,
    /// A boundary of B this many bins or fewer from one of A is the same boundary.
    #[arg(long, default_value_t = 2)]
    pub match_bins: usize,
    /// q-value under which a change counts.
    #[arg(long, default_value_t = 0.05)]
    pub alpha: f64,
    /// Regions (BED: chrom, start, end, optional name) instead of whole chromosomes.
    #[arg(long)]
    pub view: Option<PathBuf>,
    /// Weight column of every map.
    #[arg(long, default_value = "weight")]
    pub weight_name: String,
    #[command(flatten)]
    pub input: InputArgs,
}

/// The two conditions' maps.
#[derive(Debug, Args)]
pub struct ConditionArgs {
    /// Condition A's maps (the reference), one per replicate.
    #[arg(long = "a", value_name = "MAP", num_args = 1.., required = true)]
    pub first: Vec<String>,
    /// Condition B's maps, one per replicate.
    #[arg(long = "b", value_name = "MAP", num_args = 1.., required = true)]
    pub second: Vec<String>,
}

impl ConditionArgs {
    /// Every map, A's first.
    pub fn all(&self) -> impl Iterator<Item = &String> {
        self.first.iter().chain(&self.second)
    }
}

/// Arguments of `contactmap diff loops`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Each loop (a BEDPE record of --loops; a header line is skipped) is placed at the bins of its
anchors' midpoints. Without --loops, each condition's replicates are summed, balanced (ICE,
cooler's defaults) and their dots called as `contactmap dots` calls them (the kernels cooltools
recommends for the bin size, or --w / --p); the dots of both conditions are pooled, a dot of B
within 20 kb of one of A on both anchors counted once. Its count in each replicate is the sum
of the raw counts of its pixel and the --half-width pixels around it (3 x 3 by default); its expected count is the sum of the
map's cis expected at the same pixels' distances (count.avg per chromosome, smoothed as
cooltools' count.avg.smoothed, so that a loop that changes hardly moves its own expected). A
loop's normalisation factor in a replicate is its expected count over the geometric mean of its
expected counts across the replicates (DESeq2's normalizationFactors): sequencing depth and a
change of the contact law P(s) between conditions are not called changes of loops.

The counts are tested as DESeq2 tests genes (pydeseq2 0.5.4's statistics, equal to 1e-6 on the
same counts; docs/diff.md): dispersions shared across loops and shrunk towards their trend,
the Wald test of B against A, Benjamini-Hochberg q-values (no independent filtering). With 3 or
more replicates in a condition, a loop with a Cook's outlier gets no p-value (DESeq2's rule;
--no-cooks-filter keeps them).

Output PREFIX.loops.bedpe, tab-separated with a header line, one line per loop in the order of
--loops: chrom1 start1 end1 chrom2 start2 end2 (as given), baseMean (mean normalised count),
log2FoldChange (B over A), lfc_low lfc_high (95% interval), lfcSE, pvalue, qvalue, mean_A mean_B
(mean normalised counts), direction (up / down at qvalue < --alpha, else -), then count_A1 ...
count_B<m>: each replicate's count, in the order given.

Maps are raw counts on the same bins (the same resolution of each .mcool / .hic). Bad input
stops the run with one line and exit status 2, before any output is written: maps on other bins,
a condition without a map, no replicate at all, a loop between two chromosomes, on a chromosome
the maps lack or past its end.

Examples:
  contactmap diff loops --a wt1.mcool::/resolutions/10000 \\
      wt2.mcool::/resolutions/10000 --b ko1.mcool::/resolutions/10000 \\
      ko2.mcool::/resolutions/10000 --loops loops.bedpe -o wt_vs_ko
  contactmap diff loops --a a1.cool a2.cool a3.cool \\
      --b b1.cool b2.cool b3.cool --loops union.bedpe --half-width 2 \\
      --alpha 0.1 -o a_vs_b")]
pub struct DiffLoopsArgs {
    #[command(flatten)]
    pub conditions: ConditionArgs,
    /// The loops to test (BEDPE). Without it, dots are called on each condition's summed
    /// replicates and the two conditions' dots pooled.
    #[arg(long, value_name = "BEDPE")]
    pub loops: Option<PathBuf>,
    /// Output prefix: writes PREFIX.loops.bedpe.
    #[arg(short, long, value_name = "PREFIX")]
    pub out: PathBuf,
    /// Without --loops: the dots' kernel outer half-width (bins; default: cooltools' for bins
    /// of 4-28 kb, as `contactmap dots`).
    #[arg(long, requires = "p", conflicts_with = "loops")]
    pub w: Option<usize>,
    /// Without --loops: the dots' kernel inner half-width (bins).
    #[arg(long, requires = "w", conflicts_with = "loops")]
    pub p: Option<usize>,
    /// Pixels each side of a loop's pixel counted with it.
    #[arg(long, default_value_t = 1)]
    pub half_width: usize,
    /// q-value under which a loop's direction is up or down.
    #[arg(long, default_value_t = 0.05)]
    pub alpha: f64,
    /// Keep the p-values of loops with a Cook's outlier.
    #[arg(long)]
    pub no_cooks_filter: bool,
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `contactmap diff`.
pub fn run(args: &DiffArgs) -> Result<()> {
    match &args.command {
        DiffCommand::Loops(args) => run_loops(args),
        DiffCommand::Boundaries(args) => run_boundaries(args),
        DiffCommand::Compartments(args) => run_compartments(args),
        DiffCommand::Regions(args) => run_regions(args),
    }
}

fn check_alpha(alpha: f64) -> Result<()> {
    if !(alpha > 0.0 && alpha < 1.0) {
        return Err(Error::Argument(format!(
            "--alpha {alpha}: a q-value cut between 0 and 1"
        )));
    }
    Ok(())
}

/// Every map of both conditions (A's first), each one's weights, the view on their bins.
type WeightedMaps = (Vec<Box<dyn MatrixReader>>, Vec<Vec<f64>>, View);

/// A map with its weights (`None`: raw counts).
type MaybeWeighted = (Box<dyn MatrixReader>, Option<Vec<f64>>);

/// Each map opened with its weights, A's first; the view of the first map's bins.
fn open_weighted(
    conditions: &ConditionArgs,
    input: &InputArgs,
    weight_name: &str,
    view: Option<&Path>,
) -> Result<WeightedMaps> {
    let mut readers = Vec::new();
    let mut weights = Vec::new();
    let mut first_view = None;
    for uri in conditions.all() {
        let (reader, w, v) = open_balanced(uri, input, weight_name, view)?;
        first_view.get_or_insert(v);
        readers.push(reader);
        weights.push(w);
    }
    let view = first_view.expect("clap requires a map in each condition");
    Ok((readers, weights, view))
}

fn run_regions(args: &DiffRegionsArgs) -> Result<()> {
    let conditions = &args.conditions;
    if conditions.first.len() != 1 || conditions.second.len() != 1 {
        return Err(Error::Argument(format!(
            "diff regions compares one map per condition ({} in A, {} in B): merge the \
             replicates first (contactmap merge, then balance --store)",
            conditions.first.len(),
            conditions.second.len()
        )));
    }
    if !(0.0..=1.0).contains(&args.mappability_cutoff)
        || args.relative_window.is_nan()
        || args.relative_window <= 0.0
    {
        return Err(Error::Argument(format!(
            "--mappability-cutoff {} / --relative-window {}: a fraction in 0..1 and a positive \
             fraction",
            args.mappability_cutoff, args.relative_window
        )));
    }
    let output = PathBuf::from(format!("{}.regions.tsv", args.out.display()));
    let inputs: Vec<&Path> = conditions
        .all()
        .map(|uri| uri_file(uri))
        .chain(args.pairs.as_deref())
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[Some(output.as_path())])?;
    let open = |uri: &str| -> Result<MaybeWeighted> {
        let reader = open_for_analysis(uri, &args.input)?;
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
        Ok((reader, weights))
    };
    let (reference, reference_weights) = open(&conditions.first[0])?;
    let (query, query_weights) = open(&conditions.second[0])?;
    check_same_bins(&[reference.as_ref(), query.as_ref()])?;
    let (pairs, source) = match (&args.pairs, &args.window) {
        (Some(path), _) => {
            let source = path.display().to_string();
            let records = read_bedpe(path)?;
            (
                pairs_of(reference.as_ref(), query.as_ref(), &records, &source)?,
                source,
            )
        }
        (None, Some(window)) => {
            let window_bp = bp_option("--window", window)?;
            let step_bp = match &args.step {
                Some(step) => bp_option("--step", step)?,
                None => window_bp,
            };
            if window_bp == 0 || step_bp == 0 {
                return Err(Error::Argument(
                    "--window and --step must be positive".into(),
                ));
            }
            let pairs = sliding_pairs(reference.bins(), window_bp, step_bp);
            (
                pairs,
                format!("windows of {window_bp} bp every {step_bp} bp"),
            )
        }
        (None, None) => unreachable!("clap requires --pairs or --window"),
    };
    let params = RegionParams {
        min_bins: args.min_bins,
        mappability_cutoff: args.mappability_cutoff,
        relative_window: args.relative_window,
        absolute_window: args.absolute_window,
    };
    let similarity = compare_regions(
        reference.as_ref(),
        reference_weights.as_deref(),
        query.as_ref(),
        query_weights.as_deref(),
        &pairs,
        &params,
    )?;
    write_text_file(&output, regions_tsv(reference.bins(), &pairs, &similarity))?;
    let mut notes = Warnings::new();
    let answered = similarity.ssim.iter().filter(|s| !s.is_nan()).count();
    let low = similarity.z_ssim.iter().filter(|z| **z < -2.0).count();
    notes.note(format!(
        "diff regions: {} pairs ({source}): {answered} compared, {} too small or too empty \
         (nan), {low} with z_ssim < -2; wrote {}",
        pairs.len(),
        pairs.len() - answered,
        output.display()
    ));
    notes.print();
    Ok(())
}

fn run_compartments(args: &DiffCompartmentsArgs) -> Result<()> {
    check_alpha(args.alpha)?;
    let params = CompartmentParams {
        eigs: CisEigParams {
            n_eigs: 1,
            ignore_diags: args.ignore_diags,
            clip_percentile: args.clip_percentile,
        },
        alpha: args.alpha,
    };
    params.eigs.check()?;
    let prefix = args.out.display().to_string();
    let table_path = PathBuf::from(format!("{prefix}.compartments.tsv"));
    let bed_path = PathBuf::from(format!("{prefix}.switches.bed"));
    let inputs: Vec<&Path> = args
        .conditions
        .all()
        .map(|uri| uri_file(uri))
        .chain(args.phasing_track.as_deref().map(column_file))
        .chain(args.fasta.as_deref())
        .chain(args.view.as_deref())
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[Some(&table_path), Some(&bed_path)])?;
    let (readers, weights, view) = open_weighted(
        &args.conditions,
        &args.input,
        &args.weight_name,
        args.view.as_deref(),
    )?;
    let bins = readers[0].bins();
    let track = phasing_track(
        args.phasing_track.as_deref(),
        args.fasta.as_deref(),
        bins,
        &weights[0],
    )?;
    let refs: Vec<&dyn MatrixReader> = readers.iter().map(|r| r.as_ref()).collect();
    let weight_refs: Vec<&[f64]> = weights.iter().map(|w| w.as_slice()).collect();
    let comparison = compare_compartments(
        &refs,
        &weight_refs,
        args.conditions.first.len(),
        &view,
        track.as_deref(),
        &params,
    )?;
    write_text_file(&table_path, compartments_tsv(bins, &comparison))?;
    write_text_file(&bed_path, switches_bed(bins, &comparison))?;
    let mut notes = Warnings::new();
    for warning in &comparison.warnings {
        notes.push(format!("diff compartments: {warning}"));
    }
    if track.is_none() {
        notes.push(
            "diff compartments: no phasing track: E1's sign follows the first replicate's \
             coverage, so A->B may mean B->A; give --phasing-track or --fasta"
                .to_string(),
        );
    }
    let count = |switch: Switch| comparison.switch.iter().filter(|s| **s == switch).count();
    notes.note(format!(
        "diff compartments: {} bins, {} + {} maps: {} A->B and {} B->A at q < {} ({} segments); \
         wrote {} and {}",
        comparison.bins.len(),
        args.conditions.first.len(),
        args.conditions.second.len(),
        count(Switch::AToB),
        count(Switch::BToA),
        args.alpha,
        comparison.segments().len(),
        table_path.display(),
        bed_path.display()
    ));
    notes.print();
    Ok(())
}

fn run_boundaries(args: &DiffBoundariesArgs) -> Result<()> {
    check_alpha(args.alpha)?;
    let threshold: Threshold = args.threshold.parse()?;
    let output = PathBuf::from(format!("{}.boundaries.tsv", args.out.display()));
    let inputs: Vec<&Path> = args
        .conditions
        .all()
        .map(|uri| uri_file(uri))
        .chain(args.view.as_deref())
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[Some(output.as_path())])?;
    let (readers, weights, view) = open_weighted(
        &args.conditions,
        &args.input,
        &args.weight_name,
        args.view.as_deref(),
    )?;
    let bins = readers[0].bins();
    let window_bp = match &args.window {
        Some(text) => {
            let value = bp_option("--window", text)?;
            window_bins(bins, value)
                .map_err(|e| Error::Argument(format!("--window {text}: {e}")))?;
            value
        }
        None => default_window_bp(bins)?,
    };
    let params = BoundaryParams {
        insulation: InsulationParams {
            ignore_diags: args.ignore_diags,
            threshold,
            ..InsulationParams::new(vec![window_bp])
        },
        match_bins: args.match_bins,
        alpha: args.alpha,
        ..BoundaryParams::new(window_bp)
    };
    let refs: Vec<&dyn MatrixReader> = readers.iter().map(|r| r.as_ref()).collect();
    let weight_refs: Vec<&[f64]> = weights.iter().map(|w| w.as_slice()).collect();
    let comparison = compare_boundaries(
        &refs,
        &weight_refs,
        args.conditions.first.len(),
        &view,
        &params,
    )?;
    write_text_file(&output, boundaries_tsv(bins, &comparison))?;
    let count = |status: BoundaryStatus| comparison.status.iter().filter(|s| **s == status).count();
    let mut notes = Warnings::new();
    notes.note(format!(
        "diff boundaries: {} boundaries ({} called in A, {} in B; window {} bp), {} + {} maps: \
         {} gained, {} lost, {} shifted, {} stronger, {} weaker in B at q < {}; wrote {}",
        comparison.bins.len(),
        comparison.rows.iter().filter(|(a, _)| a.is_some()).count(),
        comparison.rows.iter().filter(|(_, b)| b.is_some()).count(),
        window_bp,
        args.conditions.first.len(),
        args.conditions.second.len(),
        count(BoundaryStatus::Gained),
        count(BoundaryStatus::Lost),
        count(BoundaryStatus::Shifted),
        count(BoundaryStatus::Stronger),
        count(BoundaryStatus::Weaker),
        args.alpha,
        output.display()
    ));
    notes.print();
    Ok(())
}

fn run_loops(args: &DiffLoopsArgs) -> Result<()> {
    check_alpha(args.alpha)?;
    let output = PathBuf::from(format!("{}.loops.bedpe", args.out.display()));
    let inputs: Vec<&Path> = args
        .conditions
        .all()
        .map(|uri| uri_file(uri))
        .chain(args.loops.as_deref())
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[Some(output.as_path())])?;
    let open = |uris: &[String]| -> Result<Vec<Box<dyn MatrixReader>>> {
        uris.iter()
            .map(|uri| open_for_analysis(uri, &args.input))
            .collect()
    };
    let (first, second) = (
        open(&args.conditions.first)?,
        open(&args.conditions.second)?,
    );
    let first_refs: Vec<&dyn MatrixReader> = first.iter().map(|r| r.as_ref()).collect();
    let second_refs: Vec<&dyn MatrixReader> = second.iter().map(|r| r.as_ref()).collect();
    let mut notes = Warnings::new();
    let (records, sites, source) = match &args.loops {
        Some(path) => {
            let records = read_bedpe(path)?;
            let source = path.display().to_string();
            let sites = sites_of(first[0].bins(), &records, &source)?;
            (records, sites, source)
        }
        None => {
            let kernels = args.w.zip(args.p);
            let called = called_loops(&first_refs, &second_refs, kernels)?;
            for (name, n_iterations) in &called.unconverged {
                notes.push(format!(
                    "diff loops: ICE did not converge on {name}'s summed replicates \
                     ({n_iterations} iterations); its dots are called with the last weights"
                ));
            }
            notes.note(format!(
                "diff loops: dots called on the summed replicates: {} in A, {} in B, {} pooled \
                 (within {} bp on both anchors counted once)",
                called.n_first,
                called.n_second,
                called.sites.len(),
                called.radius_bp
            ));
            (called.records, called.sites, "the dots called".to_string())
        }
    };
    let params = LoopParams {
        half_width: args.half_width,
        alpha: args.alpha,
        cooks_filter: !args.no_cooks_filter,
        ..LoopParams::default()
    };
    let comparison = compare_loops(&first_refs, &second_refs, &sites, &params)?;
    write_text_file(&output, loops_bedpe(&records, &comparison))?;
    let directions: Vec<&str> = (0..sites.len()).map(|l| comparison.direction(l)).collect();
    let up = directions.iter().filter(|d| **d == "up").count();
    let down = directions.iter().filter(|d| **d == "down").count();
    let untested = comparison
        .results
        .p_value
        .iter()
        .filter(|p| p.is_nan())
        .count();
    notes.note(format!(
        "diff loops: {} loops of {}, {} + {} maps, {}x{} pixels each: {} changed at q < {} ({up} \
         up, {down} down in B), {untested} without a p-value; wrote {}",
        sites.len(),
        source,
        first.len(),
        second.len(),
        2 * args.half_width + 1,
        2 * args.half_width + 1,
        up + down,
        args.alpha,
        output.display()
    ));
    notes.print();
    Ok(())
}
