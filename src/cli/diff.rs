//! `contactmap diff`: what changed between two conditions with replicates
//! ([`contactmap::diff`]). `diff loops` tests each loop's counts.

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};

use crate::cli::args::InputArgs;
use crate::cli::input::open_for_analysis;
use crate::cli::output::{refuse_overwrites, uri_file, write_text_file};
use crate::cli::warnings::Warnings;
use contactmap::diff::calls::called_loops;
use contactmap::diff::loops::{LoopParams, compare_loops, loops_bedpe, sites_of};
use contactmap::error::{Error, Result};
use contactmap::io::MatrixReader;
use contactmap::io::bed::read_bedpe;

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
}

/// Arguments of `contactmap diff loops`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Each loop (a BEDPE record of --loops; a header line is skipped) is placed at the bins of its
anchors' midpoints. Without --loops, each condition's replicates are summed, balanced (ICE,
cooler's defaults) and their dots called as `contactmap dots` calls them (the kernels cooltools
recommends for the bin size); the dots of both conditions are pooled, a dot of B within 20 kb
of one of A on both anchors counted once. Its count in each replicate is the sum of the raw counts of its pixel and
the --half-width pixels around it (3 x 3 by default); its expected count is the sum of the
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
    /// Condition A's maps (the reference), one per replicate.
    #[arg(long = "a", value_name = "MAP", num_args = 1.., required = true)]
    pub first: Vec<String>,
    /// Condition B's maps, one per replicate.
    #[arg(long = "b", value_name = "MAP", num_args = 1.., required = true)]
    pub second: Vec<String>,
    /// The loops to test (BEDPE). Without it, dots are called on each condition's summed
    /// replicates and the two conditions' dots pooled.
    #[arg(long, value_name = "BEDPE")]
    pub loops: Option<PathBuf>,
    /// Output prefix: writes PREFIX.loops.bedpe.
    #[arg(short, long, value_name = "PREFIX")]
    pub out: PathBuf,
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
    }
}

fn run_loops(args: &DiffLoopsArgs) -> Result<()> {
    if !(args.alpha > 0.0 && args.alpha < 1.0) {
        return Err(Error::Argument(format!(
            "--alpha {}: a q-value cut between 0 and 1",
            args.alpha
        )));
    }
    let output = PathBuf::from(format!("{}.loops.bedpe", args.out.display()));
    let inputs: Vec<&Path> = args
        .first
        .iter()
        .chain(&args.second)
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
    let (first, second) = (open(&args.first)?, open(&args.second)?);
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
            let called = called_loops(&first_refs, &second_refs)?;
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
