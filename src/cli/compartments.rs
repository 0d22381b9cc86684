//! `contactmap compartments`: compartment eigenvectors, as `cooltools eigs-cis` (and
//! `eigs-trans` with `--trans`).

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::args::InputArgs;
use crate::cli::input::{open_balanced, phasing_track};
use crate::cli::output::{Output, column_file, refuse_overwrites, uri_file, write_text_file};
use crate::cli::progress::Progress;
use contactmap::compartments::cis::{CisEigParams, RegionEigs};
use contactmap::compartments::eigs::{Eigs, Phasing, eigs_cis, eigs_trans};
use contactmap::compartments::phasing::SortMetric;
use contactmap::compartments::tables::{
    cis_eigenvalue_table, eigenvector_table, trans_eigenvalue_table,
};
use contactmap::compartments::trans::TransEigParams;
use contactmap::error::{Error, Result};
use contactmap::genome::BinTable;
use contactmap::io::MatrixReader;

/// Measures of agreement with the phasing track, for `--sort-metric`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SortMetricArg {
    /// Spearman's correlation
    Spearmanr,
    /// Pearson's correlation
    Pearsonr,
    /// sign(r) r^2 var(E): the variance of E the track explains
    #[value(name = "var_explained")]
    VarExplained,
    /// COMED(track, E) MAD(E): its robust counterpart
    #[value(name = "MAD_explained")]
    MadExplained,
}

impl From<SortMetricArg> for SortMetric {
    fn from(arg: SortMetricArg) -> Self {
        match arg {
            SortMetricArg::Spearmanr => SortMetric::Spearman,
            SortMetricArg::Pearsonr => SortMetric::Pearson,
            SortMetricArg::VarExplained => SortMetric::VarExplained,
            SortMetricArg::MadExplained => SortMetric::MadExplained,
        }
    }
}

/// Arguments of `contactmap compartments`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
As cooltools eigs-cis (0.7.1): for each region (whole chromosomes, or the regions of --view),
the balanced map is divided by its distance decay (diagonals grouped in log-spaced bins, the
first --ignore-diags set to 1), clipped at its --clip-percentile, centred (minus 1), and the
--n-eigs eigenvectors of largest |eigenvalue| are computed, each scaled to norm
sqrt(|eigenvalue|). Nothing is held as a dense matrix: a 1 kb chromosome takes memory in
proportion to its stored pixels.

With --trans, as cooltools eigs-trans: one genome-wide decomposition of the inter-chromosomal
map (cis blocks filled with values drawn from the bins' own trans rows, then balanced again).

Sign: an eigenvector's sign is arbitrary. With --phasing-track (e.g. GC content, gene density)
or --fasta (GC content of each bin from the genome sequence, as cooltools genome gc), each
vector is flipped to correlate positively (Spearman) with it on each region, so that E1 > 0 is
the A (GC-rich) compartment on every chromosome. Without either, each vector is oriented to
correlate positively with the bins' coverage (raw contacts in the region), which usually but
not always puts A positive: give a track or a FASTA for a reliable sign.

Outputs (PREFIX as given by -o; cis, or trans with --trans):
  PREFIX.cis.vecs.tsv   chrom start end, the bin table's weight columns as stored, E1 .. En, one
                        row per bin of the view's regions (nan where a bin has no weight or no
                        contact)
  PREFIX.cis.lam.txt    chrom start end name eigval1 .. eigvaln, one row per region (trans: one
                        row, eigval1 .. eigvaln)

Examples:
  contactmap compartments in.mcool::/resolutions/100000 --fasta hg38.fa.gz \\
      -o out/sample
  contactmap compartments in.cool --phasing-track gc.bedgraph:4 --n-eigs 3 \\
      -o eigs
  contactmap compartments in.cool --view arms.bed \\
      --phasing-track genes.tsv:density -o arms
  contactmap compartments in.mcool::/resolutions/1000000 --trans -o trans")]
pub struct CompartmentsArgs {
    /// The map (balanced: it needs a weight column).
    pub uri: String,
    /// Output prefix.
    #[arg(short, long, value_name = "PREFIX")]
    pub out: PathBuf,
    /// Phasing track on the map's bins: FILE:COLUMN (a header name, or a 1-based column number
    /// for a bedGraph). Vectors are flipped to correlate positively with it.
    #[arg(long, value_name = "FILE:COLUMN", conflicts_with = "fasta")]
    pub phasing_track: Option<String>,
    /// Genome FASTA (plain or gzip): the GC content of each bin is the phasing track.
    #[arg(long, value_name = "FASTA")]
    pub fasta: Option<PathBuf>,
    /// Regions (BED: chrom, start, end, optional name) instead of whole chromosomes (cis only).
    #[arg(long, conflicts_with = "trans")]
    pub view: Option<PathBuf>,
    /// Number of eigenvectors.
    #[arg(long, default_value_t = 3)]
    pub n_eigs: usize,
    /// Diagonals set to 1 before normalising (default: the weight column's ignore_diags
    /// attribute, else 2).
    #[arg(long)]
    pub ignore_diags: Option<usize>,
    /// Clip observed/expected above this percentile (0 or 100: no clipping; cis only).
    #[arg(long, default_value_t = 99.9)]
    pub clip_percentile: f64,
    /// Weight column.
    #[arg(long, alias = "clr-weight-name", default_value = "weight")]
    pub weight_name: String,
    /// eigs-trans: one decomposition of the genome-wide inter-chromosomal map.
    #[arg(long)]
    pub trans: bool,
    /// With a phasing track or FASTA: reorder each region's eigenvectors by decreasing
    /// agreement with it, measured this way (cooltools' sort_metric; off by default, as in
    /// cooltools). The sign is then set by the same measure.
    #[arg(long, value_enum)]
    pub sort_metric: Option<SortMetricArg>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `contactmap compartments`.
pub fn run(args: &CompartmentsArgs) -> Result<()> {
    let cis_params = CisEigParams {
        n_eigs: args.n_eigs,
        ignore_diags: 0,
        clip_percentile: args.clip_percentile,
    };
    cis_params.check()?;
    if args.sort_metric.is_some() && args.phasing_track.is_none() && args.fasta.is_none() {
        return Err(Error::Argument(
            "--sort-metric ranks eigenvectors by their agreement with a phasing track: give --phasing-track or --fasta".into(),
        ));
    }
    let prefix = args.out.to_string_lossy().into_owned();
    let kind = if args.trans { "trans" } else { "cis" };
    let vecs_path = PathBuf::from(format!("{prefix}.{kind}.vecs.tsv"));
    let lam_path = PathBuf::from(format!("{prefix}.{kind}.lam.txt"));
    let inputs: Vec<&Path> = std::iter::once(uri_file(&args.uri))
        .chain(args.phasing_track.as_deref().map(column_file))
        .chain(args.fasta.as_deref())
        .chain(args.view.as_deref())
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[Some(&vecs_path), Some(&lam_path)])?;
    let (reader, weights, view) = open_balanced(
        &args.uri,
        &args.input,
        &args.weight_name,
        args.view.as_deref(),
    )?;
    let bins = reader.bins();
    let phasing = phasing_track(
        args.phasing_track.as_deref(),
        args.fasta.as_deref(),
        bins,
        &weights,
    )?;
    let sort = args.sort_metric.map(SortMetric::from);
    let ignore_diags = match args.ignore_diags {
        Some(n) => n,
        None => reader.stored_ignore_diags(&args.weight_name).unwrap_or(2),
    };
    let bar = Progress::new(reader.as_ref(), "eigenvectors")?;
    let progress = bar.reader();
    let phased_by = Phasing {
        track: phasing.as_deref(),
        sort,
    };
    if args.trans {
        let params = TransEigParams {
            n_eigs: args.n_eigs,
            ..TransEigParams::default()
        };
        let Eigs { eigs, warnings } = eigs_trans(&progress, &weights, phased_by, &params)?;
        print_warnings(&warnings);
        write_vecs(
            &format!("{prefix}.trans.vecs.tsv"),
            bins,
            &bin_columns(reader.as_ref())?,
            &[(0..bins.n_bins(), &eigs)],
            args.n_eigs,
        )?;
        let lam = trans_eigenvalue_table(&eigs, args.n_eigs);
        write_text_file(format!("{prefix}.trans.lam.txt"), &lam)?;
    } else {
        let params = CisEigParams {
            ignore_diags,
            ..cis_params
        };
        let Eigs {
            eigs: results,
            warnings,
        } = eigs_cis(&progress, &weights, &view, phased_by, &params)?;
        print_warnings(&warnings);
        let regions: Vec<_> = view
            .regions()
            .iter()
            .zip(&results)
            .map(|(r, e)| (r.bins.clone(), e))
            .collect();
        write_vecs(
            &format!("{prefix}.cis.vecs.tsv"),
            bins,
            &bin_columns(reader.as_ref())?,
            &regions,
            args.n_eigs,
        )?;
        let lam = cis_eigenvalue_table(bins, &view, &results, args.n_eigs);
        write_text_file(format!("{prefix}.cis.lam.txt"), &lam)?;
    }
    drop(progress);
    drop(bar);
    let mut notes = super::warnings::Warnings::new();
    notes.extend(reader.warnings());
    if phasing.is_none() {
        notes.note(
            "no phasing track: each eigenvector's sign makes it correlate positively with the \
             bins' coverage, which is not A/B; give --fasta GENOME.fa (GC content) or \
             --phasing-track FILE:COLUMN (gene density) to make E1 > 0 the A compartment",
        );
    }
    notes.print();
    Ok(())
}

/// The bin table's columns as cooltools writes them before E1..En: every weight column, as the
/// file stores it (cooler's order: by name).
fn bin_columns(reader: &dyn MatrixReader) -> Result<Vec<(String, Vec<f64>)>> {
    let mut names = reader.weight_names();
    names.sort();
    names
        .into_iter()
        .map(|name| {
            let values = reader.stored_weights(&name)?.values;
            Ok((name, values))
        })
        .collect()
}

fn write_vecs(
    path: &str,
    bins: &BinTable,
    columns: &[(String, Vec<f64>)],
    regions: &[(std::ops::Range<usize>, &RegionEigs)],
    n_eigs: usize,
) -> Result<()> {
    let mut out = Output::open(Some(Path::new(path)))?;
    eigenvector_table(bins, columns, regions, n_eigs, |bytes| out.write_all(bytes))?;
    out.finish()
}

/// The warnings of the eigensolver, as they were printed while it ran.
fn print_warnings(warnings: &[String]) {
    for warning in warnings {
        eprintln!("contactmap: WARNING: {warning}");
    }
}
