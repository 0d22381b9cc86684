//! The normalisation-vector index of the footer and the expected-value records (skipped on open;
//! [`HicReader::expected_values`] and [`HicReader::read_norm_vector`] read them on demand).
//!
//! [`HicReader::expected_values`]: super::HicReader::expected_values
//! [`HicReader::read_norm_vector`]: super::HicReader

use super::bytes::{SeqReader, printable};
use crate::error::{Error, Result};
use crate::genome::Chrom;

/// One entry of the normalisation-vector index.
#[derive(Clone, Debug)]
pub(super) struct NormVector {
    pub(super) name: String,
    pub(super) file_chrom: usize,
    pub(super) position: u64,
}

/// One expected-value vector of the footer at the open resolution.
#[derive(Clone, Debug, PartialEq)]
pub struct HicExpected {
    /// `NONE` for the expected values of the raw counts, else the normalisation's name.
    pub normalization: String,
    /// Bin size.
    pub resolution: u64,
    /// Expected value at each distance in bins.
    pub values: Vec<f64>,
    /// Chromosome scale factors by chromosome name (the reader divides `values` by them).
    pub chrom_scale_factors: Vec<(String, f64)>,
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
    version: i32,
    chroms: &[Chrom],
    resolution: u64,
) -> Result<Vec<NormVector>> {
    let what = "the normalisation vector index";
    let size_bytes: u64 = if version >= 9 { 8 } else { 4 };
    let n_entries = reader.i32(what)?;
    let n_entries = reader.count(i64::from(n_entries), 18 + size_bytes, what)?;
    let mut vectors = Vec::new();
    for _ in 0..n_entries {
        let name = reader.string(what)?;
        let chrom = reader.i32(what)?;
        let unit = reader.string(what)?;
        let vector_resolution = reader.i32(what)?;
        let position = reader.i64(what)?;
        let n_bytes = if version >= 9 {
            reader.i64(what)?
        } else {
            i64::from(reader.i32(what)?)
        };
        if unit != "BP" || i64::from(vector_resolution) != resolution as i64 || name == "NONE" {
            continue;
        }
        let chrom_name = usize::try_from(chrom)
            .ok()
            .and_then(|c| chroms.get(c))
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
