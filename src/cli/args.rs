//! Argument types several subcommands share: the options of text and pairs inputs.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use contactmap::error::Result;
use contactmap::io::{OpenOptions, text::TextFormat};

/// Text input layouts, for `--format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TextFormatArg {
    /// chrom1 start1 end1 chrom2 start2 end2 count (cooler dump --join)
    Bg2,
    /// bin1_id bin2_id count (cooler dump), with --bins
    Coo,
    /// pairs (4DN .pairs or chrom1 pos1 .. chrom2 pos2 ..), binned with --bin-size
    Pairs,
    /// square dense matrix, with --bins
    Dense,
}

impl From<TextFormatArg> for TextFormat {
    fn from(arg: TextFormatArg) -> Self {
        match arg {
            TextFormatArg::Bg2 => TextFormat::Bg2,
            TextFormatArg::Coo => TextFormat::Coo,
            TextFormatArg::Pairs => TextFormat::Pairs,
            TextFormatArg::Dense => TextFormat::Dense,
        }
    }
}

/// Options for inputs that are text tables or pairs (ignored for .cool / .mcool / .hic).
#[derive(Debug, Args, Clone, Default)]
#[command(next_help_heading = "Text and pairs input")]
pub struct InputArgs {
    /// Layout of a text input (default: from the extension, then from the first line).
    #[arg(long = "format", value_enum)]
    pub format: Option<TextFormatArg>,
    /// Bin size in bp, to bin pairs (or a BG2 table read with --chrom-sizes).
    #[arg(long)]
    pub bin_size: Option<u64>,
    /// Chromosome sizes file: `name<TAB>length` per line (UCSC .chrom.sizes).
    #[arg(long, value_name = "FILE")]
    pub chrom_sizes: Option<PathBuf>,
    /// Bin table as BED (`chrom start end`), for COO and dense inputs (or BG2 / pairs).
    #[arg(long = "bins", value_name = "BED")]
    pub bins_bed: Option<PathBuf>,
    /// 1-based columns of chrom1,pos1,chrom2,pos2 in a pairs file (e.g. 1,2,4,5); default from
    /// the `#columns:` header, else the 4DN layout 2,3,4,5.
    #[arg(long, value_name = "C1,P1,C2,P2", value_delimiter = ',')]
    pub pairs_columns: Option<Vec<usize>>,
    /// Pairs positions are 0-based (default: 1-based, as the 4DN spec and `cooler cload pairs`).
    #[arg(long)]
    pub zero_based: bool,
    /// Resolution (bin size in bp) to read in an .mcool or .hic named without one: the same as
    /// FILE::/resolutions/BP (hictk's --resolution); a map of one resolution must have this one.
    #[arg(long, value_name = "BP", help_heading = "Input")]
    pub resolution: Option<u64>,
}

impl InputArgs {
    /// The files these options name (chromosome sizes, bin table), inputs of the command.
    pub fn files(&self) -> impl Iterator<Item = &std::path::Path> {
        self.chrom_sizes
            .iter()
            .chain(&self.bins_bed)
            .map(|p| p.as_path())
    }

    /// Check the values and build the library's options.
    pub fn to_options(&self) -> Result<OpenOptions> {
        let pairs_columns = match &self.pairs_columns {
            None => None,
            Some(cols) => {
                if cols.len() != 4 || cols.contains(&0) {
                    return Err(contactmap::Error::Argument(
                        "--pairs-columns takes four 1-based column numbers: chrom1,pos1,chrom2,pos2".into(),
                    ));
                }
                Some([cols[0], cols[1], cols[2], cols[3]])
            }
        };
        if self.bin_size == Some(0) {
            return Err(contactmap::Error::Argument(
                "--bin-size must be positive".into(),
            ));
        }
        Ok(OpenOptions {
            text_format: self.format.map(Into::into),
            text_resolution: self.bin_size,
            chrom_sizes: self.chrom_sizes.clone(),
            bins_bed: self.bins_bed.clone(),
            pairs_columns,
            pairs_zero_based: self.zero_based,
            resolution: self.resolution,
        })
    }

    /// The URI of `uri`'s level at --resolution (`uri` itself without it), for commands that
    /// use the URI beyond opening it (to store into it, to name it).
    pub fn uri_at_resolution(&self, uri: &str) -> Result<String> {
        match self.resolution {
            Some(resolution) => contactmap::io::uri_at_resolution(uri, resolution),
            None => Ok(uri.to_string()),
        }
    }
}
