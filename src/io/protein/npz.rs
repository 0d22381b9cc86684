//! NumPy `.npz` archives (`numpy.load` reads them): a zip of `.npy` arrays, as `numpy.savez`
//! writes them (stored, not deflated). The `.npy` format (version 1.0): the magic
//! `\x93NUMPY`, the version, a little-endian header length, a Python dict literal
//! (`descr`, `fortran_order`, `shape`) padded with spaces to a multiple of 64 bytes with the
//! preamble, then the values in C order, little-endian. The zip container is the `zip` crate's.

use std::io::{Cursor, Write as _};

use crate::error::{Error, Result};

/// The values of one array.
#[derive(Clone, Debug, PartialEq)]
pub enum NpyData {
    /// `<f8`.
    F64(Vec<f64>),
    /// `<i8`.
    I64(Vec<i64>),
    /// `<U{width}`: fixed-width UTF-32 strings.
    Text(Vec<String>),
}

/// One named array of an archive.
#[derive(Clone, Debug, PartialEq)]
pub struct NpyArray {
    /// Its name in the archive (without `.npy`).
    pub name: String,
    /// Its shape (C order).
    pub shape: Vec<usize>,
    /// Its values, as many as the shape's product.
    pub data: NpyData,
}

/// The bytes of one `.npy` file.
pub fn npy_bytes(array: &NpyArray) -> Vec<u8> {
    let width = match &array.data {
        NpyData::Text(values) => values
            .iter()
            .map(|v| v.chars().count())
            .max()
            .unwrap_or(0)
            .max(1),
        _ => 0,
    };
    let descr = match &array.data {
        NpyData::F64(_) => "<f8".to_string(),
        NpyData::I64(_) => "<i8".to_string(),
        NpyData::Text(_) => format!("<U{width}"),
    };
    let shape = match array.shape.len() {
        1 => format!("({},)", array.shape[0]),
        _ => format!(
            "({})",
            array
                .shape
                .iter()
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut header = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    // magic (6) + version (2) + length (2) + header + '\n', a multiple of 64
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut out = Vec::new();
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    match &array.data {
        NpyData::F64(values) => values
            .iter()
            .for_each(|v| out.extend_from_slice(&v.to_le_bytes())),
        NpyData::I64(values) => values
            .iter()
            .for_each(|v| out.extend_from_slice(&v.to_le_bytes())),
        NpyData::Text(values) => {
            for value in values {
                let mut chars: Vec<u32> = value.chars().map(u32::from).collect();
                chars.resize(width, 0);
                chars
                    .iter()
                    .for_each(|c| out.extend_from_slice(&c.to_le_bytes()));
            }
        }
    }
    out
}

/// The bytes of an `.npz` archive of `arrays`.
pub fn npz_bytes(arrays: &[NpyArray]) -> Result<Vec<u8>> {
    let mut buffer = Cursor::new(Vec::new());
    let mut writer = zip::ZipWriter::new(&mut buffer);
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Stored)
        .large_file(true);
    let failed = |e: &dyn std::fmt::Display| Error::Invalid(format!("writing an npz archive: {e}"));
    for array in arrays {
        writer
            .start_file(format!("{}.npy", array.name), options)
            .map_err(|e| failed(&e))?;
        writer
            .write_all(&npy_bytes(array))
            .map_err(|e| failed(&e))?;
    }
    writer.finish().map_err(|e| failed(&e))?;
    Ok(buffer.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The header numpy 2.2 writes for `np.save(f, np.zeros((2, 3)))`, by hand: 128 bytes in all
    /// with this dict, and the values after it.
    #[test]
    fn npy_headers_are_numpys() {
        let array = NpyArray {
            name: "x".into(),
            shape: vec![2, 3],
            data: NpyData::F64(vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.5]),
        };
        let bytes = npy_bytes(&array);
        let dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }";
        assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
        let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert_eq!((10 + len) % 64, 0);
        let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
        assert_eq!(header.trim_end(), dict);
        assert!(header.ends_with('\n'));
        assert_eq!(bytes.len(), 10 + len + 6 * 8);
        assert_eq!(
            f64::from_le_bytes(bytes[bytes.len() - 8..].try_into().unwrap()),
            5.5
        );
        let text = NpyArray {
            name: "g".into(),
            shape: vec![2],
            data: NpyData::Text(vec!["all".into(), "+-".into()]),
        };
        let bytes = npy_bytes(&text);
        let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert!(
            std::str::from_utf8(&bytes[10..10 + len])
                .unwrap()
                .contains("'<U3'")
        );
        assert!(
            std::str::from_utf8(&bytes[10..10 + len])
                .unwrap()
                .contains("(2,)")
        );
        assert_eq!(bytes.len(), 10 + len + 2 * 3 * 4);
    }

    #[test]
    fn archives_hold_each_array_once() {
        let arrays = [
            NpyArray {
                name: "a".into(),
                shape: vec![1],
                data: NpyData::I64(vec![7]),
            },
            NpyArray {
                name: "b".into(),
                shape: vec![1],
                data: NpyData::F64(vec![0.5]),
            },
        ];
        let bytes = npz_bytes(&arrays).unwrap();
        let mut archive = zip::ZipArchive::new(Cursor::new(bytes)).unwrap();
        let names: Vec<String> = archive.file_names().map(str::to_string).collect();
        assert_eq!(names.len(), 2);
        assert!(names.contains(&"a.npy".to_string()));
        let mut file = archive.by_name("a.npy").unwrap();
        let mut content = Vec::new();
        std::io::Read::read_to_end(&mut file, &mut content).unwrap();
        assert_eq!(content, npy_bytes(&arrays[0]));
    }
}
