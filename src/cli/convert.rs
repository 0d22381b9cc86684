//! `contactmap convert`: any supported input to .cool, .mcool or a text table.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};

use crate::cli::progress::WithProgress;
use crate::cli::InputArgs;
use crate::error::{Error, Result};
use crate::io::cool::{write_cool, write_mcool, CoolWriteOptions};
use crate::io::text::{self, TextFormat};
use crate::io::{self, FileKind, MatrixReader};

/// Output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OutputFormat {
    /// single-resolution cooler (format-version 3)
    Cool,
    /// multi-resolution cooler (one group per resolution under /resolutions)
    Mcool,
    /// chrom1 start1 end1 chrom2 start2 end2 count (cooler dump --join)
    Bg2,
    /// bin1_id bin2_id count (cooler dump)
    Coo,
    /// square dense matrix (small matrices only)
    Dense,
}

/// Arguments of `contactmap convert`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
The output format follows the extension of OUT (.cool, .mcool, .bg2, .coo, .dense, each text one
optionally .gz) or --to. Files are written under a temporary name and renamed when complete.

Resolutions for .mcool: a list (10000,50000,100000) or a progression from a base: 10000N for
10000, 20000, 50000, 100000, 200000, ... (steps 1-2-5) and 10000B for 10000, 20000, 40000, ...
(steps of 2), up to the length of the longest chromosome. Each must be a multiple of the input's
bin size. Default: the input's bin size followed by its N progression. Coarser levels are summed
from the input in a single pass, as `cooler zoomify` would make them.

Examples:
  contactmap convert data/hic_test_file.hic out.cool
  contactmap convert in.cool out.mcool --resolutions 100000,200000,500000,1000000
  contactmap convert pairs.txt.gz out.cool --bin-size 2000000 --chrom-sizes hg19.sizes --pairs-columns 1,2,4,5
  contactmap convert in.mcool::/resolutions/100000 - --to bg2 | gzip > out.bg2.gz")]
pub struct ConvertArgs {
    /// Input URI (file.cool, file.mcool::/resolutions/N, file.hic[::/resolutions/N], text, pairs).
    pub input: String,
    /// Output path (`-` for standard output, text formats only).
    pub output: PathBuf,
    /// Output format (default: from the extension of OUTPUT).
    #[arg(long, value_enum)]
    pub to: Option<OutputFormat>,
    /// Resolutions of an .mcool output: a comma-separated list, or BASE N / BASE B progressions.
    #[arg(long, value_delimiter = ',', value_name = "LIST")]
    pub resolutions: Vec<String>,
    /// genome-assembly attribute written into .cool / .mcool outputs.
    #[arg(long)]
    pub assembly: Option<String>,
    /// Options for text inputs (--bin-size bins pairs).
    #[command(flatten)]
    pub input_args: InputArgs,
}

/// Run `contactmap convert`.
pub fn run(args: &ConvertArgs) -> Result<()> {
    let format = match args.to {
        Some(format) => format,
        None => format_from_extension(&args.output)?,
    };
    let (input_path, _) = io::split_uri(&args.input);
    if args.input_args.bin_size.is_some() && io::detect_kind(input_path)? != FileKind::Text {
        return Err(Error::Invalid(
            "--bin-size bins text and pairs inputs; to coarsen a .cool or .hic matrix, write an .mcool with --resolutions".into(),
        ));
    }
    if !args.resolutions.is_empty() && format != OutputFormat::Mcool {
        return Err(Error::Invalid(
            "--resolutions applies to .mcool outputs only".into(),
        ));
    }
    if args.output.as_os_str() == "-" && matches!(format, OutputFormat::Cool | OutputFormat::Mcool)
    {
        return Err(Error::Invalid(
            ".cool and .mcool outputs need a file path, not '-'".into(),
        ));
    }
    let opened = io::open_matrix(&args.input, &args.input_args.to_options()?)?;
    let reader = WithProgress::new(opened.as_ref(), "converting")?;
    let options = CoolWriteOptions {
        assembly: args
            .assembly
            .clone()
            .or_else(|| crate::cli::input::input_assembly(&reader)),
        weight_columns: None,
    };
    let written = match format {
        OutputFormat::Cool => write_cool(&reader, &args.output, &options),
        OutputFormat::Mcool => {
            let base = reader.bins().bin_size_bp().ok_or_else(|| {
                Error::Invalid(format!(
                    "{}: .mcool needs fixed-size bins; this matrix has variable bins",
                    args.input
                ))
            })?;
            let longest = reader
                .bins()
                .chroms()
                .iter()
                .map(|c| c.length_bp)
                .max()
                .unwrap_or(base);
            let resolutions = parse_resolutions(&args.resolutions, base, longest)?;
            write_mcool(&reader, &args.output, &resolutions, &options)
        }
        OutputFormat::Bg2 => text::write_text(&reader, &path_text(&args.output), TextFormat::Bg2),
        OutputFormat::Coo => text::write_text(&reader, &path_text(&args.output), TextFormat::Coo),
        OutputFormat::Dense => {
            text::write_text(&reader, &path_text(&args.output), TextFormat::Dense)
        }
    };
    written?;
    super::warnings::print_reader_warnings(reader.warnings());
    Ok(())
}

fn path_text(path: &Path) -> String {
    path.to_string_lossy().into_owned()
}

/// The output format named by the extension of `path` (a `.gz` suffix aside).
pub fn format_from_extension(path: &Path) -> Result<OutputFormat> {
    let name = path.to_string_lossy().to_ascii_lowercase();
    let name = name.strip_suffix(".gz").unwrap_or(&name);
    let format = if name.ends_with(".mcool") {
        OutputFormat::Mcool
    } else if name.ends_with(".cool") {
        OutputFormat::Cool
    } else if name.ends_with(".bg2") || name.ends_with(".bedpe") {
        OutputFormat::Bg2
    } else if name.ends_with(".coo") || name.ends_with(".pixels") {
        OutputFormat::Coo
    } else if name.ends_with(".dense") || name.ends_with(".matrix") || name.ends_with(".mat") {
        OutputFormat::Dense
    } else {
        return Err(Error::Invalid(format!(
            "cannot tell the output format from '{}': use an extension (.cool, .mcool, .bg2, .coo, .dense) or --to",
            path.display()
        )));
    };
    Ok(format)
}

/// Expand `--resolutions` (numbers, `BASE`N and `BASE`B progressions) into a sorted list.
pub fn parse_resolutions(items: &[String], base: u64, longest_bp: u64) -> Result<Vec<u64>> {
    let nice = |start: u64| {
        let mut out = Vec::new();
        let mut decade = 1u64;
        while start.saturating_mul(decade) <= longest_bp.max(start) {
            for step in [1, 2, 5] {
                let r = start.saturating_mul(decade).saturating_mul(step);
                if r <= longest_bp.max(start) {
                    out.push(r);
                }
            }
            decade = decade.saturating_mul(10);
        }
        out
    };
    let doubling = |start: u64| {
        let mut out = Vec::new();
        let mut r = start;
        while r <= longest_bp.max(start) {
            out.push(r);
            r = r.saturating_mul(2);
        }
        out
    };
    let mut resolutions = Vec::new();
    if items.is_empty() {
        resolutions = nice(base);
    }
    for item in items {
        let item = item.trim();
        let bad = || {
            Error::Invalid(format!(
                "--resolutions: '{item}' is not a resolution (a bin size in bp, or BASE N / BASE B)"
            ))
        };
        if let Some(start) = item.strip_suffix(['N', 'n']) {
            resolutions.extend(nice(start.parse().map_err(|_| bad())?));
        } else if let Some(start) = item.strip_suffix(['B', 'b']) {
            resolutions.extend(doubling(start.parse().map_err(|_| bad())?));
        } else {
            resolutions.push(item.parse().map_err(|_| bad())?);
        }
    }
    resolutions.sort_unstable();
    resolutions.dedup();
    for &r in &resolutions {
        if r == 0 || r % base != 0 {
            return Err(Error::Invalid(format!(
                "--resolutions: {r} is not a multiple of the input's bin size {base}"
            )));
        }
    }
    Ok(resolutions)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolution_lists_and_progressions() {
        let list = |items: &[&str]| {
            parse_resolutions(
                &items.iter().map(|s| s.to_string()).collect::<Vec<_>>(),
                1000,
                30_000,
            )
        };
        assert_eq!(
            list(&["1000", "5000", "2000"]).unwrap(),
            vec![1000, 2000, 5000]
        );
        assert_eq!(
            list(&["1000N"]).unwrap(),
            vec![1000, 2000, 5000, 10000, 20000]
        );
        assert_eq!(
            list(&["1000B"]).unwrap(),
            vec![1000, 2000, 4000, 8000, 16000]
        );
        assert_eq!(list(&[]).unwrap(), vec![1000, 2000, 5000, 10000, 20000]);
        assert!(list(&["1500"]).is_err());
        assert!(list(&["abc"]).is_err());
    }
}
