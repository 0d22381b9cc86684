//! Writing a matrix as a BG2 or COO table or a dense matrix.

use std::io::{BufWriter, Write};
use std::path::Path;

use flate2::Compression;
use flate2::write::GzEncoder;

use super::format::TextFormat;
use super::lines::BUFFER_BYTES;
use crate::error::{Error, Result};
use crate::io::matrices::reader::MatrixReader;
use crate::matrix::CountType;

/// The largest number of bins [`write_text`] writes as a dense matrix.
pub const MAX_DENSE_BINS: usize = 20_000;

/// Values per band when writing a dense matrix (32 MB of `f64`).
const DENSE_BAND_VALUES: usize = 1 << 22;

/// Write the matrix of `reader` to `path` (`-` for standard output; a name ending in `.gz` is
/// gzip-compressed) in `format`, streaming its pixels.
///
/// A file is first written next to the target under a temporary name, then renamed, so that a
/// failure never leaves a partial output. Pairs cannot be written (a matrix does not hold read
/// pairs) and dense output is refused above [`MAX_DENSE_BINS`] bins: both are
/// [`Error::Argument`]. A closed standard output comes back as an [`Error::Io`] of kind
/// `BrokenPipe`.
///
/// # Examples
///
/// The 4 bp level of cooler's toy file as BG2 is what `cooler dump --join` prints
/// (`data/reference/toy_4.join.tsv`).
///
/// ```
/// use contactmap::io::text::{write_text, TextFormat};
/// use contactmap::io::{open_matrix, OpenOptions};
///
/// let uri = "data/toy.symm.upper.2.mcool::/resolutions/4";
/// let reader = open_matrix(uri, &OpenOptions::default())?;
/// let path = std::env::temp_dir().join(format!("contactmap-toy-{}.bg2", std::process::id()));
/// write_text(&*reader, path.to_str().unwrap(), TextFormat::Bg2)?;
/// let ours = std::fs::read_to_string(&path)?;
/// assert_eq!(ours, std::fs::read_to_string("data/reference/toy_4.join.tsv")?);
/// std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_text(reader: &dyn MatrixReader, path: &str, format: TextFormat) -> Result<()> {
    let n_bins = reader.bins().n_bins();
    match format {
        TextFormat::Pairs => {
            return Err(Error::Argument(format!(
                "{path}: cannot write pairs: a contact matrix does not hold read pairs (write bg2, \
                 coo or dense instead)"
            )));
        }
        TextFormat::Dense if n_bins > MAX_DENSE_BINS => {
            return Err(Error::Argument(format!(
                "{path}: a dense matrix of {n_bins} x {n_bins} bins is too large to write as text \
                 (at most {MAX_DENSE_BINS} bins): write bg2 or coo, or select a coarser resolution"
            )));
        }
        _ => {}
    }
    if path == "-" {
        let mut out = BufWriter::with_capacity(1 << 16, std::io::stdout().lock());
        write_body(reader, format, &mut out, path)?;
        return out.flush().map_err(|e| Error::io(path, e));
    }
    let (pending, file) = crate::io::plumbing::atomic::Temporary::create(Path::new(path))?;
    let buffered = BufWriter::with_capacity(BUFFER_BYTES, file);
    let buffered = if path.ends_with(".gz") {
        let mut encoder = GzEncoder::new(buffered, Compression::default());
        write_body(reader, format, &mut encoder, path)?;
        encoder.finish().map_err(|e| Error::io(path, e))?
    } else {
        let mut buffered = buffered;
        write_body(reader, format, &mut buffered, path)?;
        buffered
    };
    buffered
        .into_inner()
        .map_err(|e| Error::io(path, e.into_error()))?;
    pending.persist()
}

/// Append the decimal digits of `value`.
fn push_u64(text: &mut Vec<u8>, mut value: u64) {
    let mut digits = [0u8; 20];
    let mut k = digits.len();
    loop {
        k -= 1;
        digits[k] = b'0' + (value % 10) as u8;
        value /= 10;
        if value == 0 {
            break;
        }
    }
    text.extend_from_slice(&digits[k..]);
}

/// Append a count: whole numbers of integer matrices without a decimal point, reals in the
/// shortest form that reads back exactly.
fn push_count(text: &mut Vec<u8>, count: f64, count_type: CountType) -> std::io::Result<()> {
    match count_type {
        CountType::Integer if count.fract() == 0.0 && count.abs() < 1.0e18 => {
            if count < 0.0 {
                text.push(b'-');
            }
            push_u64(text, count.abs() as u64);
            Ok(())
        }
        CountType::Integer => write!(text, "{count}"),
        CountType::Float => write!(text, "{count:?}"),
    }
}

/// Stream the matrix in `format` to `out`; `path` names the output in errors.
fn write_body<W: Write>(
    reader: &dyn MatrixReader,
    format: TextFormat,
    out: &mut W,
    path: &str,
) -> Result<()> {
    let bins = reader.bins();
    let n_bins = bins.n_bins();
    let count_type = reader.count_type();
    let io_error = |e: std::io::Error| Error::io(path, e);
    let mut text: Vec<u8> = Vec::with_capacity(1 << 16);
    match format {
        TextFormat::Bg2 | TextFormat::Coo => {
            reader.read_pixels(0..n_bins, 0..n_bins, &mut |block| {
                text.clear();
                for k in 0..block.len() {
                    let (bin1, bin2) = (block.bin1[k], block.bin2[k]);
                    if bin1 >= n_bins as u64 || bin2 >= n_bins as u64 {
                        return Err(Error::Data(format!(
                            "{}: pixel ({bin1}, {bin2}) is out of range: the bin table has \
                             {n_bins} bins",
                            reader.source()
                        )));
                    }
                    if format == TextFormat::Bg2 {
                        for (bin_id, separator) in [(bin1, b'\t'), (bin2, b'\t')] {
                            let bin = bins.bin(bin_id as usize);
                            text.extend_from_slice(bins.chroms()[bin.chrom_id].name.as_bytes());
                            text.push(b'\t');
                            push_u64(&mut text, bin.start);
                            text.push(b'\t');
                            push_u64(&mut text, bin.end);
                            text.push(separator);
                        }
                    } else {
                        push_u64(&mut text, bin1);
                        text.push(b'\t');
                        push_u64(&mut text, bin2);
                        text.push(b'\t');
                    }
                    push_count(&mut text, block.count[k], count_type).map_err(io_error)?;
                    text.push(b'\n');
                }
                out.write_all(&text).map_err(io_error)
            })
        }
        TextFormat::Dense => {
            let band_rows = (DENSE_BAND_VALUES / n_bins.max(1)).max(1);
            let mut band = vec![0.0f64; band_rows.min(n_bins) * n_bins];
            let mut first = 0;
            while first < n_bins {
                let last = (first + band_rows).min(n_bins);
                band.iter_mut().for_each(|v| *v = 0.0);
                let mut place = |i: usize, j: usize, v: f64| {
                    if (first..last).contains(&i) {
                        band[(i - first) * n_bins + j] = v;
                    }
                    if (first..last).contains(&j) {
                        band[(j - first) * n_bins + i] = v;
                    }
                };
                let mut sink = |block: &crate::matrix::PixelBlock| {
                    for k in 0..block.len() {
                        let (i, j) = (block.bin1[k] as usize, block.bin2[k] as usize);
                        if i >= n_bins || j >= n_bins {
                            return Err(Error::Data(format!(
                                "{}: pixel ({i}, {j}) is out of range: the bin table has \
                                 {n_bins} bins",
                                reader.source()
                            )));
                        }
                        place(i, j, block.count[k]);
                    }
                    Ok(())
                };
                // Rows of the band (upper part), then the band's columns in earlier rows.
                reader.read_pixels(first..last, first..n_bins, &mut sink)?;
                if first > 0 {
                    reader.read_pixels(0..first, first..last, &mut sink)?;
                }
                for row in 0..last - first {
                    text.clear();
                    for (j, &v) in band[row * n_bins..(row + 1) * n_bins].iter().enumerate() {
                        if j > 0 {
                            text.push(b'\t');
                        }
                        push_count(&mut text, v, count_type).map_err(io_error)?;
                    }
                    text.push(b'\n');
                    out.write_all(&text).map_err(io_error)?;
                }
                first = last;
            }
            Ok(())
        }
        TextFormat::Pairs => Err(Error::Argument(format!(
            "{path}: cannot write pairs: a contact matrix does not hold read pairs"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;
    use tempfile::TempDir;

    use super::super::test_support::*;
    use super::super::{guess_format, read_matrix};
    use super::*;
    use crate::genome::{Bin, BinTable, Chrom};
    use crate::io::{InMemory, OpenOptions};
    use crate::matrix::{ContactMatrix, MatrixBuilder, PixelBlock};

    #[test]
    fn bg2_output_of_the_fixture_is_cooler_dump_join() {
        let dir = TempDir::new().unwrap();
        let reader = InMemory::new("fixture".into(), fixture_matrix());
        let out = dir.path().join("out.bg2");
        write_text(&reader, out.to_str().unwrap(), TextFormat::Bg2).unwrap();
        let written = std::fs::read_to_string(&out).unwrap();
        let expected = gunzip(BG2);
        assert_eq!(written.lines().count(), 38156);
        for (k, (a, b)) in written.lines().zip(expected.lines()).enumerate() {
            assert_eq!(a, b, "line {}", k + 1);
        }
        assert_eq!(written, expected);
        // COO is `cooler dump`: 38156 lines, starting "0 0 25", "0 1 2", "0 3 3".
        let out = dir.path().join("out.coo.gz");
        write_text(&reader, out.to_str().unwrap(), TextFormat::Coo).unwrap();
        let coo = gunzip(out.to_str().unwrap());
        assert_eq!(coo.lines().count(), 38156);
        assert!(coo.starts_with("0\t0\t25\n0\t1\t2\n0\t3\t3\n"));
        assert_eq!(
            read_matrix(out.to_str().unwrap(), &bins_options()).unwrap(),
            fixture_matrix()
        );
        // No temporary file is left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
    }

    #[test]
    fn pairs_cannot_be_written_and_large_dense_matrices_are_refused() {
        let dir = TempDir::new().unwrap();
        let reader = InMemory::new("fixture".into(), fixture_matrix());
        let out = dir.path().join("out.pairs");
        let message = argument_message(write_text(
            &reader,
            out.to_str().unwrap(),
            TextFormat::Pairs,
        ));
        assert!(message.contains("cannot write pairs"), "{message}");
        let bins = BinTable::fixed(vec![Chrom::new("c", 20_001)], 1).unwrap();
        let big = InMemory::new(
            "big".into(),
            MatrixBuilder::new(bins, CountType::Integer).build(),
        );
        let out = dir.path().join("out.dense");
        let message = argument_message(write_text(&big, out.to_str().unwrap(), TextFormat::Dense));
        assert!(message.contains("too large"), "{message}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    /// A reader that fails after its first block.
    struct Failing(InMemory);

    impl MatrixReader for Failing {
        fn source(&self) -> &str {
            "failing"
        }
        fn bins(&self) -> &BinTable {
            self.0.bins()
        }
        fn count_type(&self) -> CountType {
            self.0.count_type()
        }
        fn weight_names(&self) -> Vec<String> {
            Vec::new()
        }
        fn weights(&self, name: &str) -> Result<crate::matrix::Weights> {
            self.0.weights(name)
        }
        fn info(&self) -> crate::io::MatrixInfo {
            self.0.info()
        }
        fn read_pixels(
            &self,
            rows: std::ops::Range<usize>,
            cols: std::ops::Range<usize>,
            sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
        ) -> Result<()> {
            self.0.read_pixels(rows, cols, sink)?;
            Err(Error::Data("disk on fire".into()))
        }
    }

    #[test]
    fn a_failed_write_leaves_no_output() {
        let dir = TempDir::new().unwrap();
        let reader = Failing(InMemory::new("f".into(), fixture_matrix()));
        for name in ["out.bg2", "out.coo.gz"] {
            let out = dir.path().join(name);
            let format = guess_format(name).unwrap();
            let result = write_text(&reader, out.to_str().unwrap(), format);
            assert!(matches!(result, Err(Error::Data(m)) if m == "disk on fire"));
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    /// A writer whose reader went away.
    struct ClosedPipe;

    impl Write for ClosedPipe {
        fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
            Err(std::io::ErrorKind::BrokenPipe.into())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_closed_pipe_is_an_io_error_of_kind_broken_pipe() {
        let reader = InMemory::new("fixture".into(), fixture_matrix());
        for format in [TextFormat::Bg2, TextFormat::Coo] {
            let error = write_body(&reader, format, &mut ClosedPipe, "-").unwrap_err();
            assert!(error.is_broken_pipe(), "{error:?}");
        }
    }

    #[test]
    fn counts_are_printed_as_integers_or_shortest_reals() {
        let mut text = Vec::new();
        push_count(&mut text, 25.0, CountType::Integer).unwrap();
        text.push(b' ');
        push_count(&mut text, 2.0, CountType::Float).unwrap();
        text.push(b' ');
        push_count(&mut text, 0.1, CountType::Float).unwrap();
        text.push(b' ');
        push_count(&mut text, 1e-7, CountType::Float).unwrap();
        text.push(b' ');
        push_count(&mut text, 0.0, CountType::Integer).unwrap();
        text.push(b' ');
        push_u64(&mut text, u64::MAX);
        assert_eq!(
            String::from_utf8(text).unwrap(),
            "25 2.0 0.1 1e-7 0 18446744073709551615"
        );
    }

    fn chroms(lengths: &[u64]) -> Vec<Chrom> {
        lengths
            .iter()
            .enumerate()
            .map(|(k, &length)| Chrom::new(format!("chr{}", k + 1), length))
            .collect()
    }

    /// Fixed tables, or variable ones cut at random points.
    fn arb_bins() -> impl Strategy<Value = BinTable> {
        let fixed = (prop::collection::vec(1u64..60, 1..4), 1u64..12)
            .prop_map(|(lengths, size)| BinTable::fixed(chroms(&lengths), size).unwrap());
        let variable = prop::collection::vec(
            (1u64..60, prop::collection::btree_set(1u64..60, 0..5)),
            1..4,
        )
        .prop_map(|specs| {
            let lengths: Vec<u64> = specs.iter().map(|s| s.0).collect();
            let mut bins = Vec::new();
            for (chrom_id, (length, cuts)) in specs.iter().enumerate() {
                let mut start = 0;
                for &cut in cuts.iter().filter(|&&c| c < *length) {
                    bins.push(Bin {
                        chrom_id,
                        start,
                        end: cut,
                    });
                    start = cut;
                }
                bins.push(Bin {
                    chrom_id,
                    start,
                    end: *length,
                });
            }
            BinTable::from_bins(chroms(&lengths), &bins, None).unwrap()
        });
        prop_oneof![fixed, variable]
    }

    /// Random matrices with integer or real counts.
    fn arb_matrix() -> impl Strategy<Value = ContactMatrix> {
        arb_bins()
            .prop_flat_map(|bins| {
                let n = bins.n_bins() as u64;
                let count = prop_oneof![
                    (1u32..1000).prop_map(f64::from),
                    1e-9f64..1e9,
                    (1u32..64).prop_map(|k| f64::from(k) / 8.0),
                ];
                (
                    Just(bins),
                    prop::collection::vec((0..n, 0..n, count), 0..40),
                )
            })
            .prop_map(|(bins, pixels)| {
                let mut builder = MatrixBuilder::new(bins.clone(), CountType::Integer);
                for &(i, j, c) in &pixels {
                    builder.push(i, j, c).unwrap();
                }
                let matrix = builder.build();
                if matrix.all_pixels().count.iter().all(|c| c.fract() == 0.0) {
                    return matrix;
                }
                let mut builder = MatrixBuilder::new(bins, CountType::Float);
                for &(i, j, c) in &pixels {
                    builder.push(i, j, c).unwrap();
                }
                builder.build()
            })
    }

    fn bed_of(bins: &BinTable) -> String {
        bins.iter()
            .map(|b| {
                format!(
                    "{}\t{}\t{}\n",
                    bins.chroms()[b.chrom_id].name,
                    b.start,
                    b.end
                )
            })
            .collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        #[test]
        fn text_formats_round_trip(matrix in arb_matrix(), gz in any::<bool>()) {
            let dir = TempDir::new().unwrap();
            let options = OpenOptions {
                bins_bed: Some(write_plain(&dir, "bins.bed", &bed_of(matrix.bins()))),
                text_resolution: matrix.bins().resolution(),
                ..OpenOptions::default()
            };
            let reader = InMemory::new("random".into(), matrix.clone());
            let suffix = if gz { ".gz" } else { "" };
            for (format, name) in [
                (TextFormat::Bg2, "m.bg2"),
                (TextFormat::Coo, "m.coo"),
                (TextFormat::Dense, "m.dense"),
            ] {
                let path = dir.path().join(format!("{name}{suffix}"));
                let path = path.to_str().unwrap();
                write_text(&reader, path, format).unwrap();
                let back = read_matrix(path, &options).unwrap();
                prop_assert_eq!(&back, &matrix, "{:?}", format);
            }
        }
    }
}
