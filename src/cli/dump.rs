//! `contactmap dump`: print pixels, bins or chromosomes as tab-separated text, as `cooler dump`.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use rayon::prelude::*;

use crate::cli::output::{refuse_overwrites, uri_file};
use crate::cli::output::{write_count, FloatFormat, Output};
use crate::cli::InputArgs;
use contactmap::error::Result;
use contactmap::genome::BinTable;
use contactmap::io::tables::write_u64;
use contactmap::io::{self, MatrixReader};
use contactmap::matrix::{CountType, PixelBlock};

/// Which table to print.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Table {
    /// bin1_id bin2_id count (as stored: upper triangle, both for storage-mode square)
    Pixels,
    /// chrom start end [weight columns]
    Bins,
    /// name length
    Chroms,
}

/// Arguments of `contactmap dump`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Output follows `cooler dump`: no header unless -H, tab-separated, counts as integers when they
are integers, other numbers with the printf format of --float-format (default %g, 6 significant
digits; use --float-format .17g to print every digit), missing values (masked bins) as --na-rep.
Pixels are printed as stored, as cooler dump prints them: the upper triangle (bin1 <= bin2) of
symmetric matrices, both triangles of coolers with storage-mode square. With --region R and
--region2 R2, the stored pixels with bin1 in R and bin2 in R2.

-t bins prints the weight columns as stored in the file, as cooler dump does: Juicer's divisive
columns (KR, VC, VC_SQRT written by hic2cool or contactmap, columns marked divisive_weights, and
a .hic file's normalisation vectors) hold the values counts are divided by. Wherever weights are applied (--balanced, balance, expected, tads,
normalize) such columns are inverted first, so balanced = count * w1 * w2 always holds for the
weights in use.

Examples:
  contactmap dump data/cooler_test_file.mcool::/resolutions/100000 | head
  contactmap dump data/hic_test_file.hic -r chr2L:1,000,000-2,000,000 \\
      --join --balanced=KR
  contactmap dump data/yeast.10kb.cool -t bins -H")]
pub struct DumpArgs {
    /// Matrix URI: file.cool, file.mcool::/resolutions/N, file.hic[::/resolutions/N], text table.
    pub uri: String,
    /// Table to print.
    #[arg(short, long, value_enum, default_value_t = Table::Pixels)]
    pub table: Table,
    /// Rows: a region such as chr2L or chr2L:1,000,000-2,000,000 (0-based, half-open).
    #[arg(short, long, visible_alias = "range", value_name = "REGION")]
    pub region: Option<String>,
    /// Columns: a second region (default: the same as --region).
    #[arg(long, visible_alias = "range2", value_name = "REGION")]
    pub region2: Option<String>,
    /// Add a `balanced` column = count * w1 * w2 from weight column COLUMN (default `weight`).
    #[arg(short, long, value_name = "COLUMN", num_args = 0..=1, require_equals = true, default_missing_value = "weight")]
    pub balanced: Option<String>,
    /// Print chrom, start, end for each bin instead of bin ids.
    #[arg(long)]
    pub join: bool,
    /// Print a header line with column names.
    #[arg(short = 'H', long)]
    pub header: bool,
    /// Text for missing values (NaN weights, masked bins).
    #[arg(long, default_value = "", value_name = "TEXT")]
    pub na_rep: String,
    /// printf format for real numbers: g, .12g, .3f, .4e ...
    #[arg(long, default_value = "g", value_name = "FORMAT")]
    pub float_format: FloatFormat,
    /// Write to FILE (gzip if it ends in .gz) instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Options for text inputs.
    #[command(flatten)]
    pub input: InputArgs,
}

/// Run `contactmap dump`.
pub fn run(args: &DumpArgs) -> Result<()> {
    let inputs: Vec<&Path> = std::iter::once(uri_file(&args.uri))
        .chain(args.input.files())
        .collect();
    refuse_overwrites(&inputs, &[args.out.as_deref()])?;
    let reader = io::open_matrix(&args.uri, &args.input.to_options()?)?;
    let mut out = Output::open(args.out.as_deref())?;
    match args.table {
        Table::Chroms => dump_chroms(reader.bins(), args, &mut out)?,
        Table::Bins => dump_bins(reader.as_ref(), args, &mut out)?,
        Table::Pixels => dump_pixels(reader.as_ref(), args, &mut out)?,
    }
    out.finish()?;
    super::warnings::print_reader_warnings(reader.warnings());
    Ok(())
}

fn dump_chroms(bins: &BinTable, args: &DumpArgs, out: &mut Output) -> Result<()> {
    let mut text = Vec::new();
    if args.header {
        text.extend_from_slice(b"name\tlength\n");
    }
    for chrom in bins.chroms() {
        text.extend_from_slice(chrom.name.as_bytes());
        text.push(b'\t');
        write_u64(&mut text, chrom.length_bp);
        text.push(b'\n');
    }
    out.write_all(&text)
}

fn dump_bins(reader: &dyn MatrixReader, args: &DumpArgs, out: &mut Output) -> Result<()> {
    let bins = reader.bins();
    let weights = reader
        .weight_names()
        .iter()
        .map(|name| reader.stored_weights(name))
        .collect::<Result<Vec<_>>>()?;
    let range = match &args.region {
        Some(region) => bins.parse_region_bins(region)?,
        None => 0..bins.n_bins(),
    };
    let mut text = Vec::with_capacity(1 << 20);
    if args.header {
        text.extend_from_slice(b"chrom\tstart\tend");
        for w in &weights {
            text.push(b'\t');
            text.extend_from_slice(w.name.as_bytes());
        }
        text.push(b'\n');
    }
    for bin_id in range {
        let bin = bins.bin(bin_id);
        text.extend_from_slice(bins.chroms()[bin.chrom_id].name.as_bytes());
        text.push(b'\t');
        write_u64(&mut text, bin.start);
        text.push(b'\t');
        write_u64(&mut text, bin.end);
        for w in &weights {
            text.push(b'\t');
            write_real(&mut text, w.values[bin_id], args);
        }
        text.push(b'\n');
        if text.len() > (1 << 20) {
            out.write_all(&text)?;
            text.clear();
        }
    }
    out.write_all(&text)
}

fn write_real(text: &mut Vec<u8>, value: f64, args: &DumpArgs) {
    if value.is_nan() {
        text.extend_from_slice(args.na_rep.as_bytes());
    } else {
        args.float_format.write(value, text);
    }
}

/// Pixels formatted per parallel task.
const FORMAT_TASK_PIXELS: usize = 1 << 15;

fn dump_pixels(reader: &dyn MatrixReader, args: &DumpArgs, out: &mut Output) -> Result<()> {
    let bins = reader.bins();
    let rows = match &args.region {
        Some(region) => bins.parse_region_bins(region)?,
        None => 0..bins.n_bins(),
    };
    let cols = match (&args.region2, &args.region) {
        (Some(region2), _) => bins.parse_region_bins(region2)?,
        (None, _) => rows.clone(),
    };
    let weights = match &args.balanced {
        Some(name) => Some(crate::cli::input::read_weights(
            reader,
            name,
            "--balanced",
            false,
        )?),
        None => None,
    };
    let formatter = PixelFormatter {
        bins,
        join: args.join,
        integer_counts: reader.count_type() == CountType::Integer,
        weights: weights.as_deref(),
        args,
    };
    if args.header {
        let mut header = if args.join {
            b"chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tcount".to_vec()
        } else {
            b"bin1_id\tbin2_id\tcount".to_vec()
        };
        if weights.is_some() {
            header.extend_from_slice(b"\tbalanced");
        }
        header.push(b'\n');
        out.write_all(&header)?;
    }
    reader.read_stored_pixels(rows, cols, &mut |block| {
        let pieces: Vec<Vec<u8>> = (0..block.len())
            .step_by(FORMAT_TASK_PIXELS)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|start| {
                let end = (start + FORMAT_TASK_PIXELS).min(block.len());
                let mut text = Vec::with_capacity((end - start) * 24);
                formatter.write(block, start..end, &mut text);
                text
            })
            .collect();
        for piece in &pieces {
            out.write_all(piece)?;
        }
        Ok(())
    })
}

struct PixelFormatter<'a> {
    bins: &'a BinTable,
    join: bool,
    integer_counts: bool,
    weights: Option<&'a [f64]>,
    args: &'a DumpArgs,
}

impl PixelFormatter<'_> {
    fn write_bin(&self, text: &mut Vec<u8>, bin_id: u64) {
        if self.join {
            let bin = self.bins.bin(bin_id as usize);
            text.extend_from_slice(self.bins.chroms()[bin.chrom_id].name.as_bytes());
            text.push(b'\t');
            write_u64(text, bin.start);
            text.push(b'\t');
            write_u64(text, bin.end);
        } else {
            write_u64(text, bin_id);
        }
    }

    fn write(&self, block: &PixelBlock, range: std::ops::Range<usize>, text: &mut Vec<u8>) {
        for k in range {
            self.write_bin(text, block.bin1[k]);
            text.push(b'\t');
            self.write_bin(text, block.bin2[k]);
            text.push(b'\t');
            write_count(
                text,
                block.count[k],
                self.integer_counts,
                &self.args.float_format,
            );
            if let Some(w) = self.weights {
                text.push(b'\t');
                let balanced =
                    block.count[k] * w[block.bin1[k] as usize] * w[block.bin2[k] as usize];
                write_real(text, balanced, self.args);
            }
            text.push(b'\n');
        }
    }
}
