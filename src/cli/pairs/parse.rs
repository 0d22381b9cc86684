//! `contactmap pairs parse`: pairs from the aligner's SAM / BAM ([`contactmap::pairs::parse`]).

use std::path::PathBuf;

use clap::Args;

use super::shared::{Compression, command_line, open_output, refuse_overwrites, write_stats};
use crate::cli::progress::spinner;
use contactmap::error::{Error, Result};
use contactmap::io::pairs::{AlignmentReader, PairsHeader};
use contactmap::io::text::read_chrom_sizes;
use contactmap::pairs::parse::{ChromOrder, ParseParams, WalksPolicy};
use contactmap::pairs::stats::PairCounter;
use contactmap::pairs::stream::parse_alignments;

/// Arguments of `contactmap pairs parse`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
The input is SAM or BAM (told apart by its content; `-` reads standard input) grouped by read
name, as `bwa mem -SP5M` writes it. A coordinate-sorted input is refused: group it first with
`samtools collate` (or `samtools sort -n`).

Each read pair becomes one pair (with --walks-policy all, one per ligation of a walk), written
as pairtools 1.1.2 writes it: readID chrom1 pos1 chrom2 pos2 strand1 strand2 pair_type, the
positions the 5' ends of the two sides' alignments (1-based), flipped so that side 1 comes
first in the --chrom-sizes order. Pair types: UU both unique, NU / MU one side unmapped /
multi-mapping, NN, MM, NM, UR / RU a walk rescued as one ligation (R the linear side), MR, NR,
WW a masked walk, XX a read without alignments. An unmapped side is `!  0  -`.

Walks (reads with more than two alignments that no single ligation explains):
  5unique  the 5'-most unique alignment of each side (the default)
  5any     the 5'-most alignment of each side
  3unique  the 3'-most unique alignment of each side
  3any     the 3'-most alignment of each side
  mask     one pair typed WW at ! 0 -
  all      every ligation of the walk, the part both reads cover counted once

Differences from pairtools: no SAM columns unless --keep-sam (pairtools keeps them unless
--drop-sam); a chromosome of the input missing from --chrom-sizes is an error unless
--add-missing-chroms (pairtools orders them after the listed ones silently), and so is a
length that differs. An output ending in .gz is BGZF (tabix / pairix can index it).

Examples:
  bwa mem -SP5M -t 8 genome.fa R1.fq.gz R2.fq.gz \\
      | samtools view -b -o sample.bam
  contactmap pairs parse sample.bam -c genome.sizes -o sample.pairs.gz \\
      --output-stats sample.parse.stats
  contactmap pairs parse sample.bam -c genome.sizes | contactmap pairs sort \\
      | contactmap pairs dedup -o sample.nodups.pairs.gz")]
pub struct ParseArgs {
    /// SAM or BAM, grouped by read name (`-`: standard input).
    #[arg(default_value = "-")]
    pub input: PathBuf,
    /// Chromosome sizes (name<TAB>length): the order pairs are flipped to.
    #[arg(
        short = 'c',
        long = "chrom-sizes",
        alias = "chroms-path",
        value_name = "SIZES"
    )]
    pub chrom_sizes: PathBuf,
    /// Output pairs (`.gz`: BGZF); standard output when not given.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub compression: Compression,
    /// Genome assembly for the header (e.g. hg38).
    #[arg(long)]
    pub assembly: Option<String>,
    /// The smallest MAPQ of a unique alignment.
    #[arg(long, default_value_t = 1)]
    pub min_mapq: u8,
    /// The largest molecule a single ligation read through may imply (rescued walks).
    #[arg(long, default_value_t = 750)]
    pub max_molecule_size: i64,
    /// Read stretches longer than this that no alignment covers count as null alignments.
    #[arg(long, default_value_t = 20)]
    pub max_inter_align_gap: i64,
    /// How walks are reported: 5unique, 5any, 3unique, 3any, mask, all.
    #[arg(long, default_value = "5unique", value_name = "POLICY")]
    pub walks_policy: String,
    /// Extra columns, comma-separated: mapq, pos5, pos3, cigar, read_len, matched_bp,
    /// algn_ref_span, algn_read_span, dist_to_5, dist_to_3, seq, mismatches, read_side,
    /// algn_idx, same_side_algn_count (each written for side 1 and side 2).
    #[arg(long, value_name = "COLUMNS", default_value = "")]
    pub add_columns: String,
    /// Report the 3' end of each side's alignment instead of the 5' end.
    #[arg(long, value_name = "END", default_value = "5", value_parser = ["5", "3"])]
    pub report_alignment_end: String,
    /// Write `.` instead of read names.
    #[arg(long)]
    pub drop_readid: bool,
    /// Accepted for pairtools' command lines: SAM columns are left out unless --keep-sam.
    #[arg(long)]
    pub drop_sam: bool,
    /// Keep the SAM records in columns sam1, sam2 (pairtools' .pairsam).
    #[arg(long, conflicts_with = "drop_sam")]
    pub keep_sam: bool,
    /// With --keep-sam: leave bases and qualities out of the SAM records.
    #[arg(long)]
    pub drop_seq: bool,
    /// Add walk_pair_index and walk_pair_type columns.
    #[arg(long)]
    pub add_pair_index: bool,
    /// Keep the order in which the reads were sequenced instead of flipping to the upper
    /// triangle.
    #[arg(long)]
    pub no_flip: bool,
    /// Order chromosomes of the input that --chrom-sizes does not list after the listed ones,
    /// by name (pairtools' behaviour) instead of refusing the input.
    #[arg(long)]
    pub add_missing_chroms: bool,
    /// Write pairtools' statistics of the pairs to this file.
    #[arg(long, value_name = "FILE")]
    pub output_stats: Option<PathBuf>,
}

/// Run `contactmap pairs parse`.
pub fn run(args: &ParseArgs) -> Result<()> {
    refuse_overwrites(
        &[&args.input, &args.chrom_sizes],
        &[args.output.as_ref(), args.output_stats.as_ref()],
    )?;
    let walks_policy = WalksPolicy::from_name(&args.walks_policy).ok_or_else(|| {
        Error::Argument(format!(
            "--walks-policy {}: expected one of 5unique, 5any, 3unique, 3any, mask, all",
            args.walks_policy
        ))
    })?;
    let params = ParseParams {
        min_mapq: args.min_mapq,
        max_molecule_size: args.max_molecule_size,
        max_inter_align_gap: args.max_inter_align_gap,
        walks_policy,
        report_3_end: args.report_alignment_end == "3",
        no_flip: args.no_flip,
        drop_readid: args.drop_readid,
        keep_sam: args.keep_sam,
        drop_seq: args.drop_seq,
        add_pair_index: args.add_pair_index,
        add_columns: args
            .add_columns
            .split(',')
            .filter(|c| !c.is_empty())
            .map(str::to_string)
            .collect(),
    };
    params.check()?;
    let sizes: Vec<(String, u64)> = read_chrom_sizes(&args.chrom_sizes)?
        .into_iter()
        .map(|c| (c.name, c.length_bp))
        .collect();
    let reader = AlignmentReader::open(&args.input)?;
    let order = ChromOrder::new(
        &reader.chromosomes(),
        &sizes,
        args.add_missing_chroms,
        &args.chrom_sizes.display().to_string(),
    )?;
    let mut header = PairsHeader::standard(
        args.assembly.as_deref(),
        &order.chromsizes(),
        &params.columns(),
        !args.no_flip,
    );
    header.insert_sam_header(&reader.header_lines());
    header.push_program("contactmap_pairs_parse", &command_line());
    let mut output = open_output(args.output.as_deref(), &header, args.compression)?;
    let bar = spinner("read pairs parsed");
    let mut counter = args.output_stats.as_ref().map(|_| PairCounter::new());
    parse_alignments(
        reader,
        &order,
        &params,
        counter.as_mut(),
        &mut |bytes| output.write_all(bytes),
        &mut |n| bar.set_position(n),
    )?;
    bar.finish_and_clear();
    if let (Some(path), Some(counter)) = (&args.output_stats, &counter) {
        write_stats(Some(path), counter)?;
    }
    output.finish()
}
