//! `contactmap saddle`: the cis saddle of a compartment track, as `cooltools saddle`.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::input::{open_for_analysis, weights_and_view};
use crate::cli::InputArgs;
use crate::compartments::saddle::{digitize, saddle_cis, saddle_strength, Binning, SaddleParams};
use crate::error::{Error, Result};
use crate::expected::{expected_cis, CisParams};
use crate::genome::BinTable;
use crate::io::tables::read_track;
use crate::io::{self, default_memory_budget};

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

Outputs (PREFIX as given by -o):
  PREFIX.saddle.tsv     i j sum count, for the (n-bins + 2)^2 class pairs (class 0 and n-bins+1
                        hold the values outside the range)
  PREFIX.edges.tsv      the n-bins + 1 class edges
  PREFIX.digitized.tsv  chrom start end and the class of each bin (-1: none)
  PREFIX.strength.tsv   k and the saddle strength (AA + BB) / (AB + BA) over k x k corners, as
                        cooltools saddle_strength

Examples:
  contactmap saddle in.cool --track eigs.tsv:E1 -o out/sample
  contactmap saddle in.mcool::/resolutions/100000 --track e1.bedgraph:4 --n-bins 50 --vrange -1,1 -o s")]
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
            return Err(Error::Invalid(format!(
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
    let reader = open_for_analysis(&args.uri, &args.input)?;
    let (weights, view) = weights_and_view(
        reader.as_ref(),
        false,
        &args.weight_name,
        args.view.as_deref(),
    )?;
    let weights = weights.expect("balanced");
    let bins = reader.bins().clone();
    let (path, column) = args.track.rsplit_once(':').ok_or_else(|| {
        Error::Invalid(format!(
            "--track '{}': expected FILE:COLUMN (a header name or a 1-based column number)",
            args.track
        ))
    })?;
    let mut track = track_on_bins(Path::new(path), column, &bins)?;
    for (value, w) in track.iter_mut().zip(&weights) {
        if !w.is_finite() {
            *value = f64::NAN;
        }
    }
    let digitized = digitize(&track, params.n_bins, params.binning)?;
    let pixels = io::load_pixels(reader.as_ref(), default_memory_budget())?;
    let table = expected_cis(&pixels, Some(&weights), &view, &CisParams::default())?;
    let averages = table.balanced_avg.as_ref().expect("balanced expected");
    let mut expected: Vec<Vec<f64>> = vec![Vec::new(); view.len()];
    for (row, &region) in table.region.iter().enumerate() {
        expected[region as usize].push(averages[row]);
    }
    let saddle = saddle_cis(&pixels, &weights, &digitized, &view, &expected, &params)?;
    let strength = saddle_strength(&saddle);

    let prefix = args.out.to_string_lossy().into_owned();
    let n = saddle.n_classes;
    write_file(&format!("{prefix}.saddle.tsv"), |out| {
        writeln!(out, "i\tj\tsum\tcount")?;
        for a in 0..n {
            for b in 0..n {
                writeln!(
                    out,
                    "{a}\t{b}\t{}\t{}",
                    saddle.sum[a * n + b],
                    saddle.count[a * n + b]
                )?;
            }
        }
        Ok(())
    })?;
    write_file(&format!("{prefix}.edges.tsv"), |out| {
        writeln!(out, "edge")?;
        for e in &digitized.edges {
            writeln!(out, "{e}")?;
        }
        Ok(())
    })?;
    write_file(&format!("{prefix}.digitized.tsv"), |out| {
        writeln!(out, "chrom\tstart\tend\t{column}.d")?;
        for (k, bin) in bins.iter().enumerate() {
            writeln!(
                out,
                "{}\t{}\t{}\t{}",
                bins.chroms()[bin.chrom_id].name,
                bin.start,
                bin.end,
                digitized.classes[k]
            )?;
        }
        Ok(())
    })?;
    write_file(&format!("{prefix}.strength.tsv"), |out| {
        writeln!(out, "k\tstrength")?;
        for (k, s) in strength.iter().enumerate().skip(1) {
            writeln!(out, "{k}\t{s}")?;
        }
        Ok(())
    })?;
    super::warnings::print_reader_warnings(reader.warnings());
    Ok(())
}

/// The track's values on `bins` (NaN for bins without a row); a row on no bin is an error.
fn track_on_bins(path: &Path, column: &str, bins: &BinTable) -> Result<Vec<f64>> {
    let rows = read_track(path, column)?;
    let mut values = vec![f64::NAN; bins.n_bins()];
    let chrom_ids: std::collections::HashMap<&str, usize> = bins
        .chroms()
        .iter()
        .enumerate()
        .map(|(k, c)| (c.name.as_str(), k))
        .collect();
    for row in &rows {
        let bin = chrom_ids.get(row.chrom.as_str()).and_then(|&c| {
            let range = bins.chrom_bins(c);
            let at = bins.bin_at(
                c,
                row.start.min(bins.chroms()[c].length_bp.saturating_sub(1)),
            );
            let bin = bins.bin(at);
            (range.contains(&at) && bin.start == row.start && bin.end == row.end).then_some(at)
        });
        let Some(bin) = bin else {
            return Err(Error::format(
                path,
                format!(
                    "track row {}:{}-{} is not a bin of the map{}: the track must be on the map's bins",
                    row.chrom,
                    row.start,
                    row.end,
                    bins.bin_size_bp().map_or(String::new(), |b| format!(" ({b} bp bins)"))
                ),
            ));
        };
        values[bin] = row.value;
    }
    Ok(values)
}

/// Write `path` under a temporary name, renamed when complete.
fn write_file(
    path: &str,
    write: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> Result<()> {
    let path = Path::new(path);
    let tmp = io::temporary_path(path)?;
    let written = (|| {
        let file = std::fs::File::create(&tmp)?;
        let mut out = std::io::BufWriter::new(file);
        write(&mut out)?;
        out.flush()
    })();
    match written {
        Ok(()) => std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e)),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(Error::io(path, e))
        }
    }
}
