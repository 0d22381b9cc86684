//! Matrices as `cooler dump` prints them: the chromosome table, the bin table with its weight
//! columns, and the pixels (bin ids or joined coordinates, counts, optional balanced values),
//! with cooler's `--float-format` and `--na-rep`.

use std::ops::Range;

use rayon::prelude::*;

use crate::error::Result;
use crate::genome::BinTable;
use crate::io::matrices::reader::MatrixReader;
use crate::io::plumbing::output::{FloatFormat, write_count};
use crate::io::plumbing::tables::write_u64;
use crate::matrix::{CountType, PixelBlock};

/// How the tables are printed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DumpOptions {
    /// Print a header line.
    pub header: bool,
    /// Pixels with chromosome, start and end of both bins instead of bin ids.
    pub join: bool,
    /// The format of real numbers.
    pub float_format: FloatFormat,
    /// The text of a NaN.
    pub na_rep: String,
}

impl DumpOptions {
    fn write_real(&self, text: &mut Vec<u8>, value: f64) {
        if value.is_nan() {
            text.extend_from_slice(self.na_rep.as_bytes());
        } else {
            self.float_format.write(value, text);
        }
    }
}

/// The chromosome table, `name length` per line (with a header line when `options.header`).
pub fn dump_chroms(
    bins: &BinTable,
    options: &DumpOptions,
    mut write: impl FnMut(&[u8]) -> Result<()>,
) -> Result<()> {
    let mut text = Vec::new();
    if options.header {
        text.extend_from_slice(b"name\tlength\n");
    }
    for chrom in bins.chroms() {
        text.extend_from_slice(chrom.name.as_bytes());
        text.push(b'\t');
        write_u64(&mut text, chrom.length_bp);
        text.push(b'\n');
    }
    write(&text)
}

/// The bins `range`, `chrom start end` and every weight column as the file stores it, per line.
pub fn dump_bins(
    reader: &dyn MatrixReader,
    range: Range<usize>,
    options: &DumpOptions,
    mut write: impl FnMut(&[u8]) -> Result<()>,
) -> Result<()> {
    let bins = reader.bins();
    let weights = reader
        .weight_names()
        .iter()
        .map(|name| reader.stored_weights(name))
        .collect::<Result<Vec<_>>>()?;
    let mut text = Vec::with_capacity(1 << 20);
    if options.header {
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
            options.write_real(&mut text, w.values[bin_id]);
        }
        text.push(b'\n');
        if text.len() > (1 << 20) {
            write(&text)?;
            text.clear();
        }
    }
    write(&text)
}

/// Pixels formatted per parallel task.
const FORMAT_TASK_PIXELS: usize = 1 << 15;

/// The stored pixels of `rows x cols` (upper triangle as stored), `bin1_id bin2_id count` per
/// line (`chrom1 start1 end1 chrom2 start2 end2 count` with `options.join`), with `balanced` =
/// count times both bins' `weights` when given. Blocks are formatted in parallel.
pub fn dump_pixels(
    reader: &dyn MatrixReader,
    rows: Range<usize>,
    cols: Range<usize>,
    weights: Option<&[f64]>,
    options: &DumpOptions,
    mut write: impl FnMut(&[u8]) -> Result<()>,
) -> Result<()> {
    let formatter = PixelFormatter {
        bins: reader.bins(),
        join: options.join,
        integer_counts: reader.count_type() == CountType::Integer,
        weights,
        options,
    };
    if options.header {
        let mut header = if options.join {
            b"chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tcount".to_vec()
        } else {
            b"bin1_id\tbin2_id\tcount".to_vec()
        };
        if formatter.weights.is_some() {
            header.extend_from_slice(b"\tbalanced");
        }
        header.push(b'\n');
        write(&header)?;
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
            write(piece)?;
        }
        Ok(())
    })
}

struct PixelFormatter<'a> {
    bins: &'a BinTable,
    join: bool,
    integer_counts: bool,
    weights: Option<&'a [f64]>,
    options: &'a DumpOptions,
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
                &self.options.float_format,
            );
            if let Some(w) = self.weights {
                text.push(b'\t');
                let balanced =
                    block.count[k] * w[block.bin1[k] as usize] * w[block.bin2[k] as usize];
                self.options.write_real(text, balanced);
            }
            text.push(b'\n');
        }
    }
}
