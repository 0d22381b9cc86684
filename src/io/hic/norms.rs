//! Normalisation vectors (their index in the footer and their values) and the expected-value
//! sections of the footer (skipped on open, read on demand by [`HicReader::expected_values`]).

use super::header::{printable, Header, SeqReader};
use super::reader::HicReader;
use crate::error::{Error, Result};
use crate::genome::Chrom;

/// One entry of the normalisation-vector index.
#[derive(Clone, Debug)]
pub(super) struct NormVector {
    pub(super) name: String,
    pub(super) file_chrom: usize,
    pub(super) position: u64,
}

impl HicReader {
    /// Read the first `n_bins` values of the divisive vector `vector` of chromosome `chrom`.
    pub(super) fn read_norm_vector(
        &self,
        vector: &NormVector,
        chrom: &Chrom,
        n_bins: usize,
    ) -> Result<Vec<f64>> {
        let what = format!(
            "the {} normalisation vector of {}",
            printable(&vector.name),
            printable(&chrom.name)
        );
        let mut reader = SeqReader::new(&self.file, &self.path, self.file_len, vector.position);
        let n_values = if self.version >= 9 {
            reader.i64(&what)?
        } else {
            i64::from(reader.i32(&what)?)
        };
        let value_bytes: u64 = if self.version >= 9 { 4 } else { 8 };
        let n_values = reader.count(n_values, value_bytes, &what)?;
        // Some writers append a few trailing values; more values than bins is accepted.
        if n_values < n_bins {
            return Err(Error::format(
                &self.path,
                format!("{what} has {n_values} values for the {n_bins} bins of the chromosome"),
            ));
        }
        let bytes = reader.bytes(n_bins * value_bytes as usize, &what)?;
        Ok(if self.version >= 9 {
            bytes
                .chunks_exact(4)
                .map(|b| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])))
                .collect()
        } else {
            bytes
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
                .collect()
        })
    }
}

/// One expected-value vector of the footer at the open resolution.
#[derive(Clone, Debug, PartialEq)]
pub struct HicExpected {
    /// `NONE` for the expected values of the raw counts, else the normalisation's name.
    pub normalization: String,
    /// Bin size.
    pub bin_size_bp: u64,
    /// Expected value at each distance in bins.
    pub values: Vec<f64>,
    /// Chromosome scale factors by chromosome name (the reader divides `values` by them).
    pub chrom_scale_factors: Vec<(String, f64)>,
}

impl HicReader {
    /// The expected-value vectors the footer stores at the open resolution (base pairs): the raw
    /// one (`NONE`) and the normalised ones, in file order.
    pub fn expected_values(&self) -> Result<Vec<HicExpected>> {
        let mut reader =
            SeqReader::new(&self.file, &self.path, self.file_len, self.footer_position);
        let what = "the footer";
        if self.version >= 9 {
            reader.i64(what)?;
        } else {
            reader.i32(what)?;
        }
        let n_entries = reader.i32("the master index")?;
        let n_entries = reader.count(i64::from(n_entries), 16, "the master index")?;
        for _ in 0..n_entries {
            reader.string("a master index key")?;
            reader.skip(12, "the master index")?;
        }
        let mut out = self.read_expected_section(&mut reader, false)?;
        if reader.remaining() > 0 {
            out.extend(self.read_expected_section(&mut reader, true)?);
        }
        Ok(out)
    }

    fn read_expected_section(
        &self,
        reader: &mut SeqReader,
        normalized: bool,
    ) -> Result<Vec<HicExpected>> {
        let what = if normalized {
            "the normalised expected values"
        } else {
            "the expected values"
        };
        let version = self.version;
        let value_bytes: u64 = if version >= 9 { 4 } else { 8 };
        let value = |reader: &mut SeqReader| -> Result<f64> {
            if version >= 9 {
                Ok(f64::from(reader.f32(what)?))
            } else {
                Ok(f64::from_le_bytes(reader.array::<8>(what)?))
            }
        };
        let n_vectors = reader.i32(what)?;
        let n_vectors = reader.count(i64::from(n_vectors), 10, what)?;
        let mut out = Vec::new();
        for _ in 0..n_vectors {
            let normalization = if normalized {
                reader.string(what)?
            } else {
                "NONE".to_string()
            };
            let unit = reader.string(what)?;
            let bin_size = reader.i32(what)?;
            let n_values = if version >= 9 {
                reader.i64(what)?
            } else {
                i64::from(reader.i32(what)?)
            };
            let n_values = reader.count(n_values, value_bytes, what)?;
            let keep = unit == "BP" && i64::from(bin_size) == self.resolution as i64;
            let mut values = Vec::new();
            if keep {
                values.reserve(n_values);
                for _ in 0..n_values {
                    values.push(value(reader)?);
                }
            } else {
                reader.skip(n_values as u64 * value_bytes, what)?;
            }
            let n_factors = reader.i32(what)?;
            let n_factors = reader.count(i64::from(n_factors), 4 + value_bytes, what)?;
            let mut factors = Vec::new();
            for _ in 0..n_factors {
                let chrom = reader.i32(what)?;
                let factor = value(reader)?;
                let name = usize::try_from(chrom)
                    .ok()
                    .and_then(|f| self.file_chrom.iter().position(|&c| c == f))
                    .map(|k| self.bins.chroms()[k].name.clone());
                if let (true, Some(name)) = (keep, name) {
                    factors.push((name, factor));
                }
            }
            if keep {
                out.push(HicExpected {
                    normalization,
                    bin_size_bp: bin_size as u64,
                    values,
                    chrom_scale_factors: factors,
                });
            }
        }
        Ok(out)
    }
}

/// Skip the expected-value vectors (`normalized`: the normalised expected-value vectors, which
/// carry a normalisation name first).
pub(super) fn skip_expected_values(
    reader: &mut SeqReader,
    version: i32,
    normalized: bool,
) -> Result<()> {
    let what = if normalized {
        "the normalised expected values"
    } else {
        "the expected values"
    };
    let value_bytes: u64 = if version >= 9 { 4 } else { 8 };
    let n_vectors = reader.i32(what)?;
    let n_vectors = reader.count(i64::from(n_vectors), 10, what)?;
    for _ in 0..n_vectors {
        if normalized {
            reader.string(what)?; // normalisation
        }
        reader.string(what)?; // unit
        reader.i32(what)?; // bin size
        let n_values = if version >= 9 {
            reader.i64(what)?
        } else {
            i64::from(reader.i32(what)?)
        };
        let n_values = reader.count(n_values, value_bytes, what)?;
        reader.skip(n_values as u64 * value_bytes, what)?;
        let n_factors = reader.i32(what)?;
        let n_factors = reader.count(i64::from(n_factors), 4 + value_bytes, what)?;
        reader.skip(n_factors as u64 * (4 + value_bytes), what)?;
    }
    Ok(())
}

/// Read the normalisation vector index, keeping the base-pair vectors at `resolution`.
pub(super) fn read_norm_index(
    reader: &mut SeqReader,
    header: &Header,
    resolution: u64,
) -> Result<Vec<NormVector>> {
    let what = "the normalisation vector index";
    let size_bytes: u64 = if header.version >= 9 { 8 } else { 4 };
    let n_entries = reader.i32(what)?;
    let n_entries = reader.count(i64::from(n_entries), 18 + size_bytes, what)?;
    let mut vectors = Vec::new();
    for _ in 0..n_entries {
        let name = reader.string(what)?;
        let chrom = reader.i32(what)?;
        let unit = reader.string(what)?;
        let bin_size = reader.i32(what)?;
        let position = reader.i64(what)?;
        let n_bytes = if header.version >= 9 {
            reader.i64(what)?
        } else {
            i64::from(reader.i32(what)?)
        };
        if unit != "BP" || i64::from(bin_size) != resolution as i64 || name == "NONE" {
            continue;
        }
        let chrom_name = usize::try_from(chrom)
            .ok()
            .and_then(|c| header.chroms.get(c))
            .map(|c| printable(&c.name));
        let Some(chrom_name) = chrom_name else {
            return Err(Error::format(
                reader.path,
                format!(
                    "{what}: the {} vector names chromosome index {chrom}, not in the header",
                    printable(&name)
                ),
            ));
        };
        let end = u64::try_from(position)
            .ok()
            .zip(u64::try_from(n_bytes).ok())
            .map(|(p, n)| p.saturating_add(n));
        if end.is_none_or(|end| end > reader.file_len) {
            return Err(Error::format(
                reader.path,
                format!(
                    "the {} normalisation vector of {chrom_name} (offset {position}, {n_bytes} \
                     bytes) lies outside the file ({} bytes): the file is truncated or corrupt",
                    printable(&name),
                    reader.file_len
                ),
            ));
        }
        vectors.push(NormVector {
            name,
            file_chrom: chrom as usize,
            position: position as u64,
        });
    }
    Ok(vectors)
}
