//! `contactmap saddle`: the cis saddle of a compartment track, as `cooltools saddle`.

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::args::InputArgs;
use crate::cli::input::{open_balanced, track_argument};
use crate::cli::output::{column_file, refuse_overwrites, uri_file, write_text_file};
use contactmap::compartments::saddle::{
    Binning, SaddleParams, digitize, saddle_cis, saddle_strength, saddle_trans,
};
use contactmap::compartments::tables::{
    digitized_table, edges_table, saddle_table, strength_table,
};
use contactmap::error::{Error, Result};
use contactmap::expected::{CisParams, expected_cis, expected_trans};
use contactmap::io::{self, default_memory_budget};

/// Which contacts a saddle sums, for `--contact-type`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ContactType {
    /// within each region
    Cis,
    /// between regions on different chromosomes
    Trans,
}

/// Arguments of `contactmap saddle`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
As cooltools saddle (0.7.1) with contact type cis: the track (an eigenvector table, a bedGraph,
any table whose first columns are chrom start end, one row per bin of the map; bins without a
row, and bins without a balancing weight, have no class) is cut into --n-bins classes by
quantiles (--qrange, default 0.025,0.975) or values (--vrange), plus one class below and one
above; every pair of bins of a region (whole chromosomes, or the regions of --view) at least
--min-diag bins apart adds its balanced count over the expected of its distance (cooltools'
expected_cis balanced.avg over the same view, ignoring 2 diagonals) to its class pair. Pairs
without a stored pixel count as 0. The arrays are symmetrised as cooltools does (added to their
transposes).

With --contact-type trans (cooltools' contact_type='trans'): every pair of regions on different
chromosomes adds its balanced values over its expected_trans balanced.avg instead.

Outputs (PREFIX as given by -o):
  PREFIX.saddle.tsv     i j sum count, for the (n-bins + 2)^2 class pairs (class 0 and n-bins+1
                        hold the values outside the range)
  PREFIX.edges.tsv      the n-bins + 1 class edges
  PREFIX.digitized.tsv  chrom start end and the class of each bin (-1: none)
  PREFIX.strength.tsv   k and the saddle strength (AA + BB) / (AB + BA) over k x k corners, as
                        cooltools saddle_strength

Examples:
  contactmap saddle in.cool --track eigs.tsv:E1 -o out/sample
  contactmap saddle in.mcool::/resolutions/100000 --track e1.bedgraph:4 \\
      --n-bins 50 --vrange -1,1 -o s")]
pub struct SaddleArgs {
    /// The map (balanced: it needs a weight column).
    pub uri: String,
    /// The track: FILE:COLUMN (a header name, or a 1-based column number for a bedGraph).
    #[arg(long, value_name = "FILE:COLUMN")]
    pub track: String,
    /// Output prefix.
    #[arg(short, long, value_name = "PREFIX")]
    pub out: PathBuf,
    /// Classes between the edges.
    #[arg(long, default_value_t = 50)]
    pub n_bins: usize,
    /// Edges at these quantiles of the track (fractions).
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "LO,HI",
        conflicts_with = "vrange"
    )]
    pub qrange: Option<Vec<f64>>,
    /// Edges at these track values.
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "LO,HI",
        allow_hyphen_values = true
    )]
    pub vrange: Option<Vec<f64>>,
    /// Leave out pairs closer than this many bins.
    #[arg(long, default_value_t = 3)]
    pub min_diag: usize,
    /// Leave out pairs farther than this many bins.
    #[arg(long)]
    pub max_diag: Option<usize>,
    /// Weight column.
    #[arg(long, default_value = "weight")]
    pub weight_name: String,
    /// cis: pairs within each region; trans: pairs between regions of different chromosomes,
    /// each block over its expected_trans balanced.avg (--min-diag and --max-diag do not apply).
    #[arg(long, value_enum, default_value = "cis")]
    pub contact_type: ContactType,
    /// Regions (BED: chrom, start, end, optional name) instead of whole chromosomes.
    #[arg(long)]
    pub view: Option<PathBuf>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `contactmap saddle`.
pub fn run(args: &SaddleArgs) -> Result<()> {
    for (name, range) in [("--qrange", &args.qrange), ("--vrange", &args.vrange)] {
        if range.as_ref().is_some_and(|r| r.len() != 2) {
            return Err(Error::Argument(format!(
                "{name}: expected two numbers LO,HI"
            )));
        }
    }
    let binning = match (&args.qrange, &args.vrange) {
        (_, Some(v)) => Binning::Values(v[0], v[1]),
        (Some(q), None) => Binning::Quantiles(q[0], q[1]),
        (None, None) => Binning::Quantiles(0.025, 0.975),
    };
    let params = SaddleParams {
        n_bins: args.n_bins,
        binning,
        min_diag: args.min_diag,
        max_diag: args.max_diag,
    };
    let prefix = args.out.to_string_lossy().into_owned();
    let outputs: Vec<PathBuf> = ["saddle", "edges", "digitized", "strength"]
        .iter()
        .map(|what| PathBuf::from(format!("{prefix}.{what}.tsv")))
        .collect();
    let inputs: Vec<&Path> = [uri_file(&args.uri), column_file(&args.track)]
        .into_iter()
        .chain(args.view.as_deref())
        .chain(args.input.files())
        .collect();
    refuse_overwrites(
        &inputs,
        &outputs
            .iter()
            .map(|p| Some(p.as_path()))
            .collect::<Vec<_>>(),
    )?;
    let (reader, weights, view) = open_balanced(
        &args.uri,
        &args.input,
        &args.weight_name,
        args.view.as_deref(),
    )?;
    let bins = reader.bins().clone();
    let (track, column) = track_argument(&args.track, "--track", &bins, &weights)?;
    let digitized = digitize(&track, params.n_bins, params.binning)?;
    let pixels = io::load_pixels(reader.as_ref(), default_memory_budget())?;
    let saddle = if args.contact_type == ContactType::Trans {
        let expected = expected_trans(&pixels, Some(&weights), &view)?.average_by_pair(&view);
        saddle_trans(&pixels, &weights, &digitized, &view, &expected)?
    } else {
        let table = expected_cis(&pixels, Some(&weights), &view, &CisParams::default())?;
        let expected = table.average_by_region();
        saddle_cis(&pixels, &weights, &digitized, &view, &expected, &params)?
    };
    let strength = saddle_strength(&saddle);

    write_text_file(format!("{prefix}.saddle.tsv"), saddle_table(&saddle))?;
    write_text_file(format!("{prefix}.edges.tsv"), edges_table(&digitized))?;
    let classes = digitized_table(&bins, &column, &digitized);
    write_text_file(format!("{prefix}.digitized.tsv"), classes)?;
    write_text_file(format!("{prefix}.strength.tsv"), strength_table(&strength))?;
    let mut notes = super::warnings::Warnings::new();
    notes.extend(reader.warnings());
    // The headline figure: the corners of the fifth of the classes at each end (k = 10 of 50,
    // the workflows' report column), every k in the table.
    let k = (params.n_bins / 5).max(1);
    if let Some(value) = strength.get(k) {
        notes.note(format!(
            "{column} saddle strength {value:.4}: (AA + BB) / (AB + BA) over the {k} x {k} \
             corners of {} classes (20% at each end); every k in {prefix}.strength.tsv",
            params.n_bins
        ));
    }
    notes.print();
    Ok(())
}
