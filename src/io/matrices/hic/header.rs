//! The header and the footer's master index (parsed with [`SeqReader`]).

use std::collections::HashMap;
use std::fs::File;
use std::path::Path;

use super::bytes::{SeqReader, printable};
use super::norms::{NormVector, read_norm_index, skip_expected_values};
use crate::error::{Error, Result};
use crate::genome::Chrom;

/// The first four bytes of every `.hic` file.
pub(super) const MAGIC: &[u8; 4] = b"HIC\0";

/// Longest chromosome accepted, in base pairs: hictk keeps chromosome lengths as 32-bit unsigned
/// integers, and version 8 files store them as 32-bit signed ones.
pub(super) const MAX_CHROM_LENGTH_BP: i64 = u32::MAX as i64;

/// The parsed header.
pub(super) struct Header {
    pub(super) version: i32,
    pub(super) footer_position: u64,
    pub(super) genome_id: String,
    pub(super) norm_vector_index: Option<(i64, i64)>,
    pub(super) attributes: Vec<(String, String)>,
    pub(super) chroms: Vec<Chrom>,
    pub(super) resolutions: Vec<u64>,
}

/// The parts of the footer the reader keeps.
pub(super) struct Footer {
    pub(super) master: HashMap<(usize, usize), u64>,
    pub(super) norm_vectors: Vec<NormVector>,
}
/// Parse the header at the start of the file.
pub(super) fn read_header(reader: &mut SeqReader) -> Result<Header> {
    let path = reader.path;
    let magic: [u8; 4] = reader.array("the magic bytes")?;
    if &magic != MAGIC {
        return Err(Error::format(
            path,
            "not a .hic file: it does not start with the magic bytes HIC\\0",
        ));
    }
    let version = reader.i32("the version")?;
    if version != 8 && version != 9 {
        return Err(Error::format(
            path,
            format!(
                ".hic version {version} is not supported: this reader reads versions 8 and 9 \
                 (newer Juicer Tools or hictk can convert older files)"
            ),
        ));
    }
    let footer_position = reader.i64("the footer position")?;
    if footer_position <= 0 || footer_position as u64 >= reader.file_len {
        return Err(Error::format(
            path,
            format!(
                "the footer position {footer_position} in the header is outside the file ({} \
                 bytes): the file is truncated or corrupt",
                reader.file_len
            ),
        ));
    }
    let genome_id = reader.string("the genome id")?;
    let norm_vector_index = if version >= 9 {
        let position = reader.i64("the normalisation vector index position")?;
        let length = reader.i64("the normalisation vector index length")?;
        Some((position, length))
    } else {
        None
    };
    let n_attributes = reader.i32("the number of header attributes")?;
    let n_attributes = reader.count(i64::from(n_attributes), 2, "the header attributes")?;
    let mut attributes = Vec::with_capacity(n_attributes);
    for _ in 0..n_attributes {
        let key = reader.string("a header attribute key")?;
        let value = reader.string(&format!(
            "the value of header attribute '{}'",
            printable(&key)
        ))?;
        attributes.push((key, value));
    }
    let n_chroms = reader.i32("the number of chromosomes")?;
    let length_bytes = if version >= 9 { 8 } else { 4 };
    let n_chroms = reader.count(i64::from(n_chroms), 1 + length_bytes, "the chromosome list")?;
    if n_chroms == 0 {
        return Err(Error::format(
            path,
            "the number of chromosomes in the header is 0: the file is corrupt",
        ));
    }
    let mut chroms = Vec::with_capacity(n_chroms);
    for _ in 0..n_chroms {
        let name = reader.string("a chromosome name")?;
        let quoted = printable(&name);
        let what = format!("the length of chromosome '{quoted}'");
        let length = if version >= 9 {
            reader.i64(&what)?
        } else {
            i64::from(reader.i32(&what)?)
        };
        if length < 0 {
            return Err(Error::format(
                path,
                format!("chromosome '{quoted}' has a negative length {length}"),
            ));
        }
        if length > MAX_CHROM_LENGTH_BP {
            return Err(Error::format(
                path,
                format!(
                    "the length of chromosome '{quoted}' in the header, {length} bp, is more than \
                     {MAX_CHROM_LENGTH_BP} (Juicer and hictk hold chromosome lengths in 32 bits): \
                     the file is corrupt"
                ),
            ));
        }
        chroms.push(Chrom::new(name, length as u64));
    }
    let n_resolutions = reader.i32("the number of base-pair resolutions")?;
    let n_resolutions = reader.count(i64::from(n_resolutions), 4, "the resolution list")?;
    let mut resolutions = Vec::with_capacity(n_resolutions);
    for _ in 0..n_resolutions {
        let resolution = reader.i32("a base-pair resolution")?;
        if resolution <= 0 {
            return Err(Error::format(
                path,
                format!("resolution {resolution} in the header is not positive"),
            ));
        }
        resolutions.push(resolution as u64);
    }
    // Fragment resolutions (and the fragment sites after them) are not read.
    let n_fragment = reader.i32("the number of fragment resolutions")?;
    reader.count(i64::from(n_fragment), 4, "the fragment resolution list")?;
    Ok(Header {
        version,
        footer_position: footer_position as u64,
        genome_id,
        norm_vector_index,
        attributes,
        chroms,
        resolutions,
    })
}

/// Parse the footer: master index, expected values (skipped) and the normalisation-vector index
/// (entries at `resolution`, in base pairs).
pub(super) fn read_footer(
    file: &File,
    path: &Path,
    file_len: u64,
    header: &Header,
    resolution: u64,
) -> Result<Footer> {
    let version = header.version;
    let mut reader = SeqReader::new(file, path, file_len, header.footer_position);
    let what = "the footer";
    if version >= 9 {
        reader.i64(what)?; // nBytes of the "version 5" footer
    } else {
        reader.i32(what)?;
    }
    let n_entries = reader.i32("the master index")?;
    // key (>= 4 bytes: "0_0\0"), position (8), size (4)
    let n_entries = reader.count(i64::from(n_entries), 16, "the master index")?;
    let mut master = HashMap::with_capacity(n_entries);
    for _ in 0..n_entries {
        let key = reader.string("a master index key")?;
        let position = reader.i64("the master index")?;
        let size = reader.i32("the master index")?;
        let Some((i, j)) = key
            .split_once('_')
            .and_then(|(a, b)| Some((a.parse::<usize>().ok()?, b.parse::<usize>().ok()?)))
        else {
            continue; // not a chromosome pair: nothing we can look up
        };
        if i >= header.chroms.len() || j >= header.chroms.len() || i > j {
            continue;
        }
        let end = u64::try_from(position)
            .ok()
            .zip(u64::try_from(size).ok())
            .map(|(p, s)| p.saturating_add(s));
        match end {
            Some(end) if end <= file_len => {
                master.insert((i, j), position as u64);
            }
            _ => {
                return Err(Error::format(
                    path,
                    format!(
                        "the matrix record of {}-{} (offset {position}, {size} bytes) lies \
                         outside the file ({file_len} bytes): the file is truncated or corrupt",
                        header.chroms[i].name, header.chroms[j].name
                    ),
                ));
            }
        }
    }

    // Version 9 gives the position of the normalisation vector index; version 8 (and version 9
    // files without it) have it after the expected-value sections.
    let index_position = match header.norm_vector_index {
        Some((position, length)) if position > 0 && length > 0 => {
            if (position as u64).saturating_add(length as u64) > file_len {
                return Err(Error::format(
                    path,
                    format!(
                        "the normalisation vector index (offset {position}, {length} bytes) lies \
                         outside the file ({file_len} bytes): the file is truncated"
                    ),
                ));
            }
            Some(position as u64)
        }
        _ => {
            skip_expected_values(&mut reader, version, false)?;
            if reader.remaining() > 0 {
                skip_expected_values(&mut reader, version, true)?;
            }
            (reader.remaining() > 0).then_some(reader.pos)
        }
    };
    let mut norm_vectors = Vec::new();
    if let Some(position) = index_position {
        reader.pos = position;
        norm_vectors = read_norm_index(&mut reader, header.version, &header.chroms, resolution)?;
    }
    Ok(Footer {
        master,
        norm_vectors,
    })
}
