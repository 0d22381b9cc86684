//! `contactmap simulate`: synthetic contact maps with a known truth. `simulate blocks` writes a
//! block-structured Hi-C-like map ([`contactmap::sim::blocks`]) as a .cool, with its true domains and
//! boundaries as BED files; `simulate polymer` samples a simulated bead-spring chain
//! ([`contactmap::sim::polymer`]) into a .cool, with its boundary elements as BED.

mod polymer;

use std::path::PathBuf;

use clap::{Args, Subcommand};

use crate::cli::output::{check_cool_output, refuse_overwrites, write_text_file};
use contactmap::error::Result;
use contactmap::io::InMemory;
use contactmap::io::cool::{CoolWriteOptions, write_cool};
use contactmap::sim::blocks::{BlockMapParams, block_map};

/// Arguments of `contactmap simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// What to simulate.
    #[command(subcommand)]
    pub command: SimulateCommand,
}

/// The simulators.
#[derive(Debug, Subcommand)]
pub enum SimulateCommand {
    /// Block-structured Hi-C-like map with known domains (TADs): power-law decay, enriched
    /// domains, optional nesting, coverage biases and dead bins, Poisson counts.
    Blocks(BlocksArgs),
    /// Bead-spring polymer under Brownian dynamics (excluded volume, confinement, loop
    /// extrusion, block copolymer): contact maps of conformation ensembles, with the boundary
    /// elements as truth.
    Polymer(Box<polymer::PolymerArgs>),
}

/// Arguments of `contactmap simulate blocks`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Model: chromosomes chr1..chrN of --bins bins each are tiled by domains whose sizes are drawn
uniformly in [--min-domain, --max-domain] bins (a domain absorbs a leftover shorter than
--min-domain, so the last one of a chromosome can be longer). The expected count of an
intra-chromosomal pixel (i, j), d = j - i <= --max-distance, is

    c * (d + 1)^-alpha * E * b_i * b_j

where E = 1 + --enrichment when i and j are in the same domain (and again when they are in the
same nested sub-domain, see --nested-fraction), 1 otherwise; b are per-bin lognormal biases
exp(--bias-sd * Z), 0 for the --dead-bins fraction of bins; c scales the expected total to
--depth. Counts are Poisson draws of the expected ones. No trans (inter-chromosomal) pixels.
The same --seed gives the same files, whatever the number of threads.

Balancing: the default map (one chromosome, every distance) balances with `contactmap balance
--store` and cooler's defaults (about 80 ICE iterations for 2,000 bins). With --chroms 2 or more
there are no trans contacts, so balance each chromosome: `contactmap balance OUT.cool --store
--cis-only`. A map cut at --max-distance balances slowly, the band coupling bins only locally
(2,000 bins cut at 200 need about 3,000 iterations): give `balance` more --max-iters then.

Outputs:
  OUT.cool             integer counts (no weight column; balance it with `contactmap balance`)
  --truth-domains      BED: chrom start end level (0 for domains, 1 for nested sub-domains),
                       sorted by start then level
  --truth-boundaries   BED: chrom start end of the first bin of every domain (any level), except
                       each chromosome's first bin; score calls with `contactmap score boundaries`

Examples:
  contactmap simulate blocks -o sim.cool --truth-domains tads.bed \\
      --truth-boundaries bounds.bed
  contactmap simulate blocks --chroms 2 --bins 500 --depth 2e6 --bias-sd 0.3 \\
      --dead-bins 0.02 --nested-fraction 0.3 --seed 7 -o sim.cool \\
      --truth-boundaries bounds.bed")]
pub struct BlocksArgs {
    /// Output .cool file.
    #[arg(short, long, value_name = "OUT.cool")]
    pub output: PathBuf,
    /// Write the true domains here (BED: chrom start end level).
    #[arg(long, value_name = "BED")]
    pub truth_domains: Option<PathBuf>,
    /// Write the true boundary bins here (BED: chrom start end).
    #[arg(long, value_name = "BED")]
    pub truth_boundaries: Option<PathBuf>,
    /// Number of chromosomes (named chr1..chrN).
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub chroms: usize,
    /// Bins per chromosome.
    #[arg(long, default_value_t = 2000, value_name = "N")]
    pub bins: usize,
    /// Bin size in bp.
    #[arg(long, default_value_t = 10_000, value_name = "BP")]
    pub bin_size: u64,
    /// Smallest domain, in bins.
    #[arg(long, default_value_t = 10, value_name = "BINS")]
    pub min_domain: usize,
    /// Largest drawn domain, in bins.
    #[arg(long, default_value_t = 60, value_name = "BINS")]
    pub max_domain: usize,
    /// Distance-decay exponent alpha: P(s) ~ (s + 1)^-alpha, s in bins.
    #[arg(long, default_value_t = 1.0)]
    pub alpha: f64,
    /// Contacts inside a domain are multiplied by 1 + this.
    #[arg(long, default_value_t = 2.0)]
    pub enrichment: f64,
    /// Fraction of domains split into two nested sub-domains (enriched again).
    #[arg(long, default_value_t = 0.0, value_name = "FRACTION")]
    pub nested_fraction: f64,
    /// Expected total number of contacts (e.g. 1e7).
    #[arg(long, default_value_t = 1e7, value_name = "CONTACTS")]
    pub depth: f64,
    /// Pixels farther than this many bins from the diagonal are not generated [default: the
    /// whole chromosome].
    #[arg(long, value_name = "BINS")]
    pub max_distance: Option<usize>,
    /// Standard deviation of the log per-bin coverage bias (0: no bias).
    #[arg(long, default_value_t = 0.0, value_name = "SD")]
    pub bias_sd: f64,
    /// Fraction of bins without contacts.
    #[arg(long, default_value_t = 0.0, value_name = "FRACTION")]
    pub dead_bins: f64,
    /// Seed of every random draw.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
}

impl BlocksArgs {
    /// The library's parameters (checked by [`block_map`]).
    pub fn params(&self) -> BlockMapParams {
        BlockMapParams {
            n_chroms: self.chroms,
            n_bins: self.bins,
            resolution: self.bin_size,
            min_domain_bins: self.min_domain,
            max_domain_bins: self.max_domain,
            decay_exponent: self.alpha,
            domain_enrichment: self.enrichment,
            nested_fraction: self.nested_fraction,
            depth: self.depth,
            max_distance_bins: self.max_distance.unwrap_or(usize::MAX),
            bias_sd: self.bias_sd,
            dead_bin_fraction: self.dead_bins,
            seed: self.seed,
        }
    }
}

/// Run `contactmap simulate`.
pub fn run(args: &SimulateArgs) -> Result<()> {
    match &args.command {
        SimulateCommand::Blocks(blocks) => run_blocks(blocks),
        SimulateCommand::Polymer(args) => polymer::run(args),
    }
}

fn run_blocks(args: &BlocksArgs) -> Result<()> {
    check_cool_output("simulate", &args.output)?;
    refuse_overwrites(
        &[],
        &[
            Some(&args.output),
            args.truth_domains.as_deref(),
            args.truth_boundaries.as_deref(),
        ],
    )?;
    let map = block_map(&args.params())?;
    let (domains, boundaries) = (map.truth_domains_bed(), map.truth_boundaries_bed());
    let reader = InMemory::new("simulate blocks".into(), map.matrix);
    write_cool(&reader, &args.output, &CoolWriteOptions::default())?;
    if let Some(path) = &args.truth_domains {
        write_text_file(path, domains)?;
    }
    if let Some(path) = &args.truth_boundaries {
        write_text_file(path, boundaries)?;
    }
    Ok(())
}
