//! `contactmap hicrep`: HiCRep's stratum-adjusted correlation (SCC) of every pair of samples,
//! per chromosome and genome-wide, as hicrep 0.2.6 computes it.

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::args::InputArgs;
use crate::cli::input::{bp_option, open_for_analysis};
use crate::cli::output::{Output, refuse_overwrites, uri_file};
use crate::cli::warnings::Warnings;
use contactmap::compare::hicrep::{
    DEFAULT_H_MAX, SccParams, Smoothing, chrom_ids, compare_samples,
};
use contactmap::error::{Error, Result};
use contactmap::io::MatrixReader;
use contactmap::io::output::python_float;

/// Arguments of `contactmap hicrep`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
The SCC of hicrep 0.2.6 (`hicrepSCC`), per chromosome: raw counts of the upper triangle from
the first diagonal to --max-distance, smoothed by a 2D mean filter of half-width --h bins, then
per diagonal Pearson's correlation of the two maps over the pixels where either is not zero,
averaged with the weights N (1 + 1/N) / 12 (N pixels). Genome-wide: the chromosomes' SCCs
averaged weighted by length (hicreppy's genome_scc), NaN ones left out. A chromosome without
contacts in one map (where hicrep stops on an assertion) gets nan and a note.

hicrep 0.2.6 has no default h (its --h is required; its help suggests 20 at 10 kb, 10 at 25 kb
and 5 at 40 kb). Ours is --h auto, the training of the HiCRep paper, since no fixed h suits
every map; it costs about 100 one-h comparisons (seconds against a tenth of a second at 10 kb
on two cores): give --h to skip it, as in pipelines that compare many samples at one h.
--h auto chooses h as HiCRep's training (hicreppy h_train): h = 0, 1, ... below --h-max,
each chromosome of both maps subsampled 10 times to 10% of its contacts; the first h whose
genome-wide SCC gains less than 0.01 stops the search and the h before it is used. With more
than two samples, h is trained on the first two and used for every pair (SCCs are comparable
only at one h). --downsample resamples the deeper map of each chromosome to the other's depth
(hicrep's --bDownSample; our seeded random stream, not numpy's).

Output (tab-separated, header): sample1 sample2 chrom length scc, a row per chromosome then
the genome-wide row (chrom `genome`), for every pair; --json for the same with the parameters
and the training.

Examples:
  contactmap hicrep rep1.cool rep2.cool --h 5 --max-distance 5M
  contactmap hicrep rep1.mcool::/resolutions/10000 \\
      rep2.mcool::/resolutions/10000 --h auto
  contactmap hicrep s1.cool s2.cool s3.cool s4.cool --h 3 -o scc.tsv")]
pub struct HicrepArgs {
    /// Two maps or more on the same bins (URIs).
    #[arg(value_name = "URI", required = true, num_args = 2..)]
    pub uris: Vec<String>,
    /// Half-width of the mean filter in bins (0: none), or `auto` (HiCRep's training).
    #[arg(long = "h", value_name = "N|auto", default_value = "auto")]
    pub h: String,
    /// The training tries h = 0 .. h-max - 1.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_H_MAX)]
    pub h_max: usize,
    /// Largest distance compared (bp, or 5M, 500k ...), or `all` (whole chromosomes).
    #[arg(long, value_name = "BP|all", default_value = "5M")]
    pub max_distance: String,
    /// Resample the deeper map of each chromosome to the other's depth.
    #[arg(long)]
    pub downsample: bool,
    /// Seed of --downsample and of the training's subsamples.
    #[arg(long, default_value_t = 10)]
    pub seed: u64,
    /// Only these chromosomes (comma-separated names), in this order.
    #[arg(long, value_delimiter = ',', value_name = "CHROMS")]
    pub chroms: Vec<String>,
    /// Sample names for the table (comma-separated; default: the URIs).
    #[arg(long, value_delimiter = ',', value_name = "NAMES")]
    pub names: Vec<String>,
    /// JSON instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Write to FILE instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// `--h`: a number of bins or `auto`.
fn parse_h(text: &str) -> Result<Option<usize>> {
    if text.eq_ignore_ascii_case("auto") {
        return Ok(None);
    }
    text.trim().parse::<usize>().map(Some).map_err(|_| {
        Error::parameter(
            "h",
            text,
            "a non-negative integer (the filter's half-width in bins) or auto",
        )
    })
}

/// `--max-distance`: bp or `all`.
fn parse_max_distance(text: &str) -> Result<Option<u64>> {
    if text.eq_ignore_ascii_case("all") {
        return Ok(None);
    }
    bp_option("--max-distance", text).map(Some)
}

/// Run `contactmap hicrep`.
pub fn run(args: &HicrepArgs) -> Result<()> {
    let inputs: Vec<&Path> = args
        .uris
        .iter()
        .map(|uri| uri_file(uri))
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let h = parse_h(&args.h)?;
    let max_distance_bp = parse_max_distance(&args.max_distance)?;
    if !args.names.is_empty() && args.names.len() != args.uris.len() {
        return Err(Error::Argument(format!(
            "--names: {} names for {} maps",
            args.names.len(),
            args.uris.len()
        )));
    }
    let names: Vec<&str> = if args.names.is_empty() {
        args.uris.iter().map(String::as_str).collect()
    } else {
        args.names.iter().map(String::as_str).collect()
    };
    let readers: Vec<Box<dyn MatrixReader>> = args
        .uris
        .iter()
        .map(|uri| open_for_analysis(uri, &args.input))
        .collect::<Result<_>>()?;
    let samples: Vec<&dyn MatrixReader> = readers.iter().map(|r| r.as_ref()).collect();
    let chroms = chrom_ids(samples[0].bins(), &args.chroms, samples[0].source())?;
    let smoothing = match h {
        Some(h) => Smoothing::Fixed(h),
        None => Smoothing::Trained { h_max: args.h_max },
    };
    let params = SccParams {
        h: 0,
        max_distance_bp,
        downsample: args.downsample,
        seed: args.seed,
    };
    let comparison = compare_samples(&samples, &chroms, smoothing, &params)?;
    let mut warnings = Warnings::new();
    if let Some(trained) = &comparison.training {
        let tried: Vec<String> = trained
            .tried
            .iter()
            .map(|(h, s)| format!("h={h}: {s:.4}"))
            .collect();
        warnings.note(format!(
            "h = {} chosen by training on {} and {} (SCC of 10% subsamples: {})",
            trained.h,
            names[0],
            names[1],
            tried.join(", ")
        ));
        if !trained.levelled_off {
            let gain = match trained.tried.as_slice() {
                [.., (_, before), (_, last)] => last - before,
                _ => f64::NAN,
            };
            warnings.push(format!(
                "the training's SCC never levelled off: it still gained {gain:.4} at h = {} \
                 (the search stops at a gain under 0.01), so h = {} is the end of the range \
                 tried, not its plateau; raise --h-max or give --h (hicrep 0.2.6 suggests 20 at \
                 10 kb, 10 at 25 kb, 5 at 40 kb)",
                args.h_max - 1,
                trained.h
            ));
        }
    }
    for pair in &comparison.pairs {
        for c in &pair.scc.chroms {
            if let Some(note) = &c.note {
                warnings.note(format!(
                    "{} vs {}, {}: {note}",
                    names[pair.first], names[pair.second], c.chrom
                ));
            }
        }
    }
    let params = &comparison.params;
    let training = &comparison.training;
    let text = if args.json {
        let pairs: Vec<serde_json::Value> = comparison
            .pairs
            .iter()
            .map(|pair| {
                serde_json::json!({
                    "sample1": names[pair.first],
                    "sample2": names[pair.second],
                    "genome_wide": finite(pair.scc.genome_wide),
                    "chroms": pair.scc.chroms.iter().map(|c| serde_json::json!({
                        "chrom": c.chrom, "length": c.length_bp, "scc": finite(c.scc),
                        "note": c.note,
                    })).collect::<Vec<_>>(),
                })
            })
            .collect();
        let value = serde_json::json!({
            "h": params.h,
            "max_distance": max_distance_bp,
            "downsample": params.downsample,
            "seed": params.seed,
            "training": training.as_ref().map(|t| serde_json::json!({
                "h_max": args.h_max,
                "chroms": t.chroms,
                "tried": t.tried.iter().map(|(h, s)| serde_json::json!({"h": h, "scc": finite(*s)})).collect::<Vec<_>>(),
                "h": t.h,
                "levelled_off": t.levelled_off,
            })),
            "pairs": pairs,
        });
        serde_json::to_string_pretty(&value).unwrap_or_default() + "\n"
    } else {
        let mut text = String::from("sample1\tsample2\tchrom\tlength\tscc\n");
        for pair in &comparison.pairs {
            let (a, b, r) = (pair.first, pair.second, &pair.scc);
            for c in &r.chroms {
                text.push_str(&format!(
                    "{}\t{}\t{}\t{}\t{}\n",
                    names[a],
                    names[b],
                    c.chrom,
                    c.length_bp,
                    python_float(c.scc)
                ));
            }
            let length: u64 = r.chroms.iter().map(|c| c.length_bp).sum();
            text.push_str(&format!(
                "{}\t{}\tgenome\t{length}\t{}\n",
                names[a],
                names[b],
                python_float(r.genome_wide)
            ));
        }
        text
    };
    let mut out = Output::open(args.out.as_deref())?;
    out.write_all(text.as_bytes())?;
    out.finish()?;
    warnings.print();
    for reader in &readers {
        crate::cli::warnings::print_reader_warnings(reader.warnings());
    }
    Ok(())
}

/// A number for JSON: NaN as null.
fn finite(value: f64) -> Option<f64> {
    value.is_finite().then_some(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn h_and_distances_are_parsed_or_refused() {
        assert_eq!(parse_h("auto").unwrap(), None);
        assert_eq!(parse_h("3").unwrap(), Some(3));
        for bad in ["-1", "1.5", "x", ""] {
            let message = parse_h(bad).unwrap_err().to_string();
            assert!(message.contains("non-negative integer"), "{message}");
        }
        assert_eq!(parse_max_distance("all").unwrap(), None);
        assert_eq!(parse_max_distance("5M").unwrap(), Some(5_000_000));
        assert!(parse_max_distance("five").is_err());
    }
}
