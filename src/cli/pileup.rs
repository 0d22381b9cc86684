//! `contactmap pileup`: aggregate maps at features, as coolpuppy ([`contactmap::pileup`]).

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::args::InputArgs;
use crate::cli::input::{
    TableReading, bp_option, expected_column, expected_to_divide, open_for_analysis,
    weights_and_view,
};
use crate::cli::output::{refuse_overwrites, uri_file, write_text_file};
use crate::cli::warnings::Warnings;
use contactmap::error::{Error, Result};
use contactmap::genome::BinTable;
use contactmap::io::bed::{FeatureFormat, FeatureTable, read_features};
use contactmap::io::npz::npz_bytes;
use contactmap::pileup::scores::group_scores;
use contactmap::pileup::shifts::ShiftParams;
use contactmap::pileup::tables::{grid_tsv, groups_tsv, pileup_arrays, scores_tsv};
use contactmap::pileup::windows::Skipped;
use contactmap::pileup::{CoverageNorm, Features, PileupParams, RescaleParams, pileup};

/// `--features-format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum FeaturesFormat {
    /// from the file name's extension (.bed, .bedpe), else from the first data line
    Auto,
    /// one interval per line
    Bed,
    /// a pair of intervals per line
    Bedpe,
}

/// Arguments of `contactmap pileup`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
As coolpuppy 1.1.0 (coolpup.py), the same numbers: each feature at its midpoint's bin, a window
of --flank each side (a whole number of bins); BEDPE lines are pairs (anchor 1 the rows, anchor 2
the columns), BED features pair with each other (every two of a chromosome within --mindist and
--maxdist, the upstream one as rows) or, with --local, each with itself (on the diagonal). A
window that leaves its chromosome (or --view region) is skipped and counted. Pixels closer to the
diagonal than --ignore-diags, and the lower triangle, are left out; so are bins without a weight.

Normalisation: by default each snippet is divided pixel by pixel by the expected of its diagonal
(computed as `contactmap expected` does, or --expected TSV, cooltools' columns) and the pileup is
the mean of these observed/expected snippets (coolpuppy's default with --expected). --no-expected
gives the mean of the balanced (or --raw) snippets, as Juicer APA aggregates.

The format of FEATURES is taken from its extension as coolpuppy does (.bedpe, .bed, also with
.gz), else from its first data line (BEDPE when columns 5 and 6 are coordinates: a BED line's
6th column is its strand; chromosome names may be numbers); --features-format forces it. The
run says what it read and why, and so does an error met while reading it.

Outputs (PREFIX as given by -o):
  PREFIX.pileup.tsv   the pileup, one line per row of the grid (nan where no snippet has a value)
  PREFIX.groups.tsv   with --by-distance / --by-strand / --groupby: every group's grid, rows
                      led by the group's label and the row's index (the group of all last)
  PREFIX.npz          with --npz: the grids, per-pixel counts, n and labels for numpy
  PREFIX.scores.tsv   one line per group: n, then coolpuppy's scores (enrichment of the
                      central --center pixels, corner CV; insulation strength for --local) and
                      Juicer APA's (P2M, P2UL, P2UR, P2LL, P2LR, ZscoreLL; corners 3 wide at
                      5 kb, 6 otherwise)

Examples:
  contactmap pileup s.mcool::/resolutions/10000 loops.bedpe -o loops
  contactmap pileup s.mcool::/resolutions/10000 ctcf.bed --flank 200k -o ctcf
  contactmap pileup s.mcool::/resolutions/10000 tads.bed --local -o tads
  contactmap pileup map.cool peaks.bed --groupby name1,name2 -o by_name
  contactmap pileup map.cool centromeres.bed --trans -o trans
  contactmap pileup map.cool loops.bedpe --no-expected -o apa")]
pub struct PileupArgs {
    /// The map (balanced unless --raw).
    pub uri: String,
    /// Features: BED or BEDPE.
    pub features: PathBuf,
    /// Output prefix.
    #[arg(short, long, value_name = "PREFIX")]
    pub out: PathBuf,
    /// Format of FEATURES.
    #[arg(long, value_enum, default_value = "auto")]
    pub features_format: FeaturesFormat,
    /// Flank each side of the feature's bin (bp: 100k, 50000 ...).
    #[arg(long, value_name = "BP", default_value = "100000")]
    pub flank: String,
    /// Smallest distance between paired features' midpoints (bp; default 2 x flank + 2 bins).
    #[arg(long, value_name = "BP")]
    pub mindist: Option<String>,
    /// Largest distance between paired features' midpoints (bp; default none).
    #[arg(long, value_name = "BP")]
    pub maxdist: Option<String>,
    /// BED features on the diagonal, each with itself (TADs, boundaries).
    #[arg(long)]
    pub local: bool,
    /// Pixels with j - i below this are left out (2, as coolpuppy: the number stored with the
    /// weights is not read).
    #[arg(long, alias = "min-diag", default_value_t = 2)]
    pub ignore_diags: usize,
    /// A cooltools cis expected table (trans with --trans) on the same bins and view, instead
    /// of computing it.
    #[arg(long, value_name = "TSV")]
    pub expected: Option<String>,
    /// Column of --expected to use [default: balanced.avg, count.avg with --raw].
    #[arg(long, requires = "expected")]
    pub expected_column: Option<String>,
    /// No expected: the mean of the snippets themselves (Juicer APA style).
    #[arg(long, conflicts_with = "expected")]
    pub no_expected: bool,
    /// Raw counts instead of balanced ones.
    #[arg(long)]
    pub raw: bool,
    /// Weight column.
    #[arg(long, alias = "balanced", default_value = "weight")]
    pub weight_name: String,
    /// Regions (BED: chrom, start, end, optional name) instead of whole chromosomes.
    #[arg(long)]
    pub view: Option<PathBuf>,
    /// Shifted random controls per pair instead of an expected: the pileup is the mean snippet
    /// over the mean control (coolpuppy's CLI default is 10).
    #[arg(long, value_name = "N", conflicts_with_all = ["expected", "no_expected"])]
    pub nshifts: Option<usize>,
    /// Smallest shift of a control (bp).
    #[arg(
        long,
        value_name = "BP",
        default_value = "100000",
        requires = "nshifts"
    )]
    pub minshift: String,
    /// Largest shift of a control (bp, excluded).
    #[arg(
        long,
        value_name = "BP",
        default_value = "1000000",
        requires = "nshifts"
    )]
    pub maxshift: String,
    /// Seed of the controls' random draws (numpy's MT19937: coolpuppy's --seed gives the same
    /// controls).
    #[arg(long, default_value_t = 0, requires = "nshifts")]
    pub seed: u32,
    /// Windows of each feature's own size (widened by --rescale-flank of its length each side),
    /// all zoomed to one grid of --rescale-size pixels: domains, genes of any length.
    #[arg(long)]
    pub rescale: bool,
    /// Reach of a rescaled window each side, in lengths of its feature.
    #[arg(long, value_name = "X", default_value_t = 1.0, requires = "rescale")]
    pub rescale_flank: f64,
    /// Side of the rescaled grid (odd, pixels).
    #[arg(long, value_name = "N", default_value_t = 99, requires = "rescale")]
    pub rescale_size: usize,
    /// A pileup per distance band between the anchors, beside the one of all: coolpuppy's bands
    /// (0, 50k, 100k, 200k ... doubling), or the edges given as --by-distance=150k,300k,600k.
    #[arg(long, value_name = "EDGES", num_args = 0..=1, require_equals = true,
          default_missing_value = "default", conflicts_with = "local")]
    pub by_distance: Option<String>,
    /// A pileup per pair of strands of the anchors (++, +-, -+, --), beside the one of all.
    #[arg(long)]
    pub by_strand: bool,
    /// A pileup per value of feature columns, beside the one of all: column names of the
    /// file's header line, or coolpuppy's (BED: chrom start end name score strand ...; BEDPE:
    /// chrom1 ... end2 name score strand1 strand2). BED pairs take the anchor's suffix as in
    /// coolpuppy: name1 is the upstream feature's name, name2 the other's.
    #[arg(long, value_name = "COLUMNS", value_delimiter = ',', num_args = 1..)]
    pub groupby: Vec<String>,
    /// Pairs between chromosomes instead of within them: every BED feature of one chromosome
    /// with every one of another, or the BEDPE pairs whose anchors are on two chromosomes;
    /// observed/expected divides by the chromosomes' trans expected; no distance limits.
    #[arg(long, conflicts_with_all = ["local", "by_distance"])]
    pub trans: bool,
    /// Snippets whose (first) anchor is on the minus strand flipped about the anti-diagonal,
    /// so that every feature points the same way.
    #[arg(long)]
    pub flip_negative_strand: bool,
    /// Normalise a raw pileup (--raw) by coverage as coolpuppy's --coverage_norm: the summed
    /// snippets over the outer product of their bins' summed coverage (cooltools' cov_tot_raw,
    /// or cov_cis_raw with `cis`), scaled to mean 1.
    #[arg(long, value_name = "KIND", num_args = 0..=1, require_equals = true,
          default_missing_value = "total", value_parser = ["total", "cis"])]
    pub coverage_norm: Option<String>,
    /// Also write PREFIX.npz (numpy.load): every group's pileup (data, G x N x N), its
    /// per-pixel counts (num), n, control_n (with shifts) and labels (group), all last.
    #[arg(long)]
    pub npz: bool,
    /// Side of the central square of the enrichment score (pixels).
    #[arg(long, default_value_t = 3)]
    pub center: usize,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// An optional distance option in bp.
fn distance(option: &str, text: &Option<String>) -> Result<Option<f64>> {
    text.as_deref()
        .map(|t| bp_option(option, t).map(|bp| bp as f64))
        .transpose()
}

/// Run `contactmap pileup`.
pub fn run(args: &PileupArgs) -> Result<()> {
    let prefix = args.out.to_string_lossy().into_owned();
    let grouped = args.by_distance.is_some() || args.by_strand || !args.groupby.is_empty();
    let outputs = [
        PathBuf::from(format!("{prefix}.pileup.tsv")),
        PathBuf::from(format!("{prefix}.scores.tsv")),
        PathBuf::from(format!("{prefix}.groups.tsv")),
        PathBuf::from(format!("{prefix}.npz")),
    ];
    let inputs: Vec<&Path> = [uri_file(&args.uri), args.features.as_path()]
        .into_iter()
        .chain(args.view.as_deref())
        .chain(args.expected.as_deref().map(Path::new))
        .chain(args.input.files())
        .collect();
    refuse_overwrites(
        &inputs,
        &[
            Some(&outputs[0]),
            Some(&outputs[1]),
            grouped.then_some(&outputs[2]),
        ],
    )?;
    // the expected table read while the features are read and the map opened
    let expected_table = TableReading::start(match args.no_expected || args.nshifts.is_some() {
        true => None,
        false => args.expected.as_deref(),
    });
    let format = match args.features_format {
        FeaturesFormat::Auto => FeatureFormat::Auto,
        FeaturesFormat::Bed => FeatureFormat::Bed,
        FeaturesFormat::Bedpe => FeatureFormat::Bedpe,
    };
    let (table, detection) = read_features(&args.features, format)?;
    let mut notes = Warnings::new();
    notes.note(match &table {
        FeatureTable::Bed(bed) => format!(
            "read {} BED features from {}{} (BED: {})",
            bed.records.len(),
            args.features.display(),
            if args.local {
                " (on the diagonal)"
            } else {
                " (paired)"
            },
            detection.reason
        ),
        FeatureTable::Bedpe(bedpe) => format!(
            "read {} BEDPE pairs from {} (BEDPE: {})",
            bedpe.records.len(),
            args.features.display(),
            detection.reason
        ),
    });
    if args.local && matches!(table, FeatureTable::Bedpe(_)) {
        return Err(Error::Argument(format!(
            "--local piles up BED features on the diagonal; {} is read as BEDPE (pairs), \
             since {} (--features-format bed reads it as BED)",
            args.features.display(),
            detection.reason
        )));
    }
    let (features, groupby) = Features::of_table(table, &args.groupby, args.local)?;
    let reader = open_for_analysis(&args.uri, &args.input)?;
    let (weights, view) = weights_and_view(
        reader.as_ref(),
        args.raw,
        &args.weight_name,
        args.view.as_deref(),
    )?;
    let bins = reader.bins();
    let resolution = bins
        .resolution()
        .ok_or_else(|| Error::format(reader.source(), "pileups need fixed-size bins"))?;
    let params = PileupParams {
        flank_bp: bp_option("--flank", &args.flank)?,
        min_dist_bp: distance("--mindist", &args.mindist)?,
        max_dist_bp: distance("--maxdist", &args.maxdist)?,
        ignore_diags: args.ignore_diags,
        rescale: args.rescale.then_some(RescaleParams {
            flank: args.rescale_flank,
            size: args.rescale_size,
        }),
        shifts: match args.nshifts {
            Some(n) => Some(ShiftParams {
                n,
                min_bp: bp_option("--minshift", &args.minshift)?,
                max_bp: bp_option("--maxshift", &args.maxshift)?,
                seed: args.seed,
            }),
            None => None,
        },
        by_distance: match args.by_distance.as_deref() {
            None => None,
            Some("default") => Some(Vec::new()),
            Some(text) => Some(
                text.split(',')
                    .map(|edge| bp_option("--by-distance", edge.trim()))
                    .collect::<Result<Vec<u64>>>()?,
            ),
        },
        by_strand: args.by_strand,
        flip_negative_strand: args.flip_negative_strand,
        groupby,
        trans: args.trans,
        coverage_norm: match args.coverage_norm.as_deref() {
            None => None,
            Some("cis") => Some(CoverageNorm::Cis),
            Some(_) => Some(CoverageNorm::Total),
        },
    };
    params.check(resolution)?;
    let expected_table = expected_table.finish()?;
    let expected = if args.no_expected || args.nshifts.is_some() {
        None
    } else {
        let column = expected_column(args.expected_column.as_deref(), args.raw);
        Some(expected_to_divide(
            reader.as_ref(),
            weights.as_deref(),
            &view,
            expected_table.as_ref(),
            column,
            args.trans,
        )?)
    };
    let pups = pileup(
        reader.as_ref(),
        weights.as_deref(),
        &view,
        &features,
        expected.as_deref(),
        &params,
    )?;
    let s = &pups.skipped;
    let limits = if args.local {
        String::from("on the diagonal")
    } else if args.trans {
        String::from("between chromosomes")
    } else {
        format!("pairs {} bp apart or more", pups.min_dist_bp)
    };
    let left_out = format!(
        "left out: {} on chromosomes the map lacks{}, {} outside the view, {} {}, {} outside \
         the distance limits, {} too close to an edge",
        s.unknown_chromosome,
        unknown_names(s, reader.bins()),
        s.outside_view,
        s.other_kind,
        if args.trans {
            "within one chromosome"
        } else {
            "between chromosomes (see --trans)"
        },
        s.distance,
        s.at_edge
    );
    if pups.all().n == 0 {
        return Err(Error::Data(format!(
            "no snippet to pile up from {} ({limits}; {left_out}): nothing was written",
            args.features.display()
        )));
    }
    let rescale_flank = args.rescale.then_some(args.rescale_flank);
    let scores = group_scores(&pups, args.local, rescale_flank, args.center, resolution)?;
    let pup = pups.all();
    write_text_file(format!("{prefix}.pileup.tsv"), grid_tsv(pup))?;
    if grouped {
        write_text_file(format!("{prefix}.groups.tsv"), groups_tsv(&pups))?;
    }
    write_text_file(format!("{prefix}.scores.tsv"), scores_tsv(&scores))?;
    if args.npz {
        write_text_file(format!("{prefix}.npz"), npz_bytes(&pileup_arrays(&pups))?)?;
    }
    notes.note(format!(
        "pileup of {} snippets ({} x {} bins, {limits}); {left_out}",
        pup.n,
        pup.data.nrows(),
        pup.data.ncols(),
    ));
    if let Some(control_n) = pup.control_n {
        notes.note(format!(
            "{control_n} shifted controls (seed {}), {} more left their region",
            args.seed, pups.controls_at_edge
        ));
    }
    if grouped {
        notes.note(format!(
            "{} groups beside the one of all: {}",
            pups.groups.len() - 1,
            pups.groups[..pups.groups.len() - 1]
                .iter()
                .map(|p| format!("{} (n={})", p.key, p.n))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    if pups.below_diagonal > 0 {
        notes.push(format!(
            "{} pairs have anchor 2 upstream of anchor 1: their snippets lie below the diagonal, \
             where every pixel is left out, yet count in n (as in coolpuppy); swap their anchors \
             to pile them up",
            pups.below_diagonal
        ));
    }
    notes.extend(reader.warnings());
    notes.print();
    Ok(())
}

/// The names of the first chromosomes the map lacks, with how to match them when they differ
/// from the map's by the `chr` prefix: ` (chr21, chr22: the matrix names it '21': ...)`.
fn unknown_names(skipped: &Skipped, bins: &BinTable) -> String {
    let Some(first) = skipped.unknown_names.first() else {
        return String::new();
    };
    let more = if skipped.unknown_names.len() >= 5 {
        ", ..."
    } else {
        ""
    };
    let hint = bins
        .naming_hint(first)
        .map(|h| format!(": {h}"))
        .unwrap_or_default();
    format!(" ({}{more}{hint})", skipped.unknown_names.join(", "))
}
