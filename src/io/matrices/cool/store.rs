//! Storing a weight column into an existing cooler, as `cooler balance` does, and other bin
//! columns (cooltools' coverage, [`store_bin_columns`]).
//!
//! The column is written as `bins/<name>`, float64, gzip level 6 (as h5py writes it for cooler),
//! with the attributes the caller gives (cooler's `converged`, `scale`, `var`, `ignore_diags`,
//! `mad_max`, `min_nnz`, `min_count`, `tol`, `cis_only`) plus `divisive_weights`, which this module
//! sets itself: weights are given multiplicative, and stored so, except under the names `KR`, `VC`
//! and `VC_SQRT`, which cooler always divides by — those are stored inverted with
//! `divisive_weights = true`, as [`super::write_cool`] does.
//!
//! HDF5 has no atomic replace, so the swap is done in steps that always leave one complete column
//! under some name: the new column is written under a hidden temporary name in `bins/`; the old
//! column (if any) is renamed to a hidden backup name; the new one is renamed into place; the
//! backup is removed. A failure while writing removes the temporary column and leaves the file as it
//! was; a failure in the renames puts the old column back. An existing column is replaced only when
//! the caller asks for it (cooler's `--force`).

use hdf5::types::VarLenUnicode;

use super::hdf5_file::file_builder;
use super::reader::CoolReader;
use super::weights::DIVISIVE_BY_NAME;
use crate::error::{Error, Result};
use crate::io::matrices::reader::MatrixReader;
use crate::matrix::{Weights, invert_weight};

/// A value of an HDF5 attribute, as h5py writes the Python values cooler stores.
#[derive(Clone, Debug, PartialEq)]
pub enum AttrValue {
    /// `bool` (HDF5 enum FALSE / TRUE, as numpy booleans).
    Bool(bool),
    /// 64-bit integer.
    Int(i64),
    /// 64-bit float.
    Float(f64),
    /// Variable-length UTF-8 string.
    Str(String),
    /// Array of booleans (per-chromosome `converged` of a cis-only balance).
    Bools(Vec<bool>),
    /// Array of floats (per-chromosome `scale` and `var` of a cis-only balance).
    Floats(Vec<f64>),
}

/// Column names that are not weights.
const RESERVED: [&str; 3] = ["chrom", "start", "end"];

fn check_name(uri: &str, name: &str) -> Result<()> {
    if name.is_empty() || name.contains('/') || name.starts_with('.') || RESERVED.contains(&name) {
        return Err(Error::Argument(format!(
            "{uri}: '{name}' cannot name a weight column (it must be non-empty, without '/', not start with '.', and not be chrom, start or end)"
        )));
    }
    Ok(())
}

/// Open the cooler at `uri` read-only to check it and count its bins.
fn n_bins_of(uri: &str) -> Result<usize> {
    let reader = CoolReader::open(uri)?;
    Ok(reader.bins().n_bins())
}

/// True when the cooler at `uri` has a column `bins/<name>`.
pub fn column_exists(uri: &str, name: &str) -> Result<bool> {
    let reader = CoolReader::open(uri)?;
    Ok(reader.group.link_exists(&format!("bins/{name}")))
}

/// Fail unless `bins/<name>` can be written in the cooler at `uri`: the file is a cooler (one
/// resolution), the name is usable, and the column does not exist yet unless `overwrite`.
pub fn check_target(uri: &str, name: &str, overwrite: bool) -> Result<()> {
    check_name(uri, name)?;
    if column_exists(uri, name)? && !overwrite {
        return Err(existing_column(uri, name));
    }
    Ok(())
}

fn existing_column(uri: &str, name: &str) -> Error {
    let (path, _) = crate::io::matrices::uri::split_uri(uri);
    Error::format(
        path,
        format!(
            "bins/{name} already exists: use --force to replace it (or --name to choose another column)"
        ),
    )
}

/// Write `weights` (multiplicative, one per bin) as the column `bins/<weights.name>` of the cooler at
/// `uri`, with `attributes`; replace an existing column only when `overwrite`.
///
/// # Examples
///
/// What `contactmap balance --store` does, on a copy of the mm9 cooler:
///
/// ```
/// use contactmap::balance::{balance, BalanceParams};
/// use contactmap::io::cool::store::{store_weights, AttrValue};
/// use contactmap::io::{load_pixels_for_balancing, open_matrix, MatrixReader, OpenOptions};
/// use contactmap::matrix::Weights;
///
/// let dir = std::env::temp_dir().join(format!("contactmap-store-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("mm9.cool");
/// std::fs::copy("data/CN.mm9.10000kb.cool", &path)?;
/// let uri = path.to_str().unwrap();
/// let ice = {
///     let reader = open_matrix(uri, &OpenOptions::default())?;
///     balance(&load_pixels_for_balancing(&*reader, u64::MAX)?, &BalanceParams::default())?
/// };
/// let weights = Weights { name: "ice".into(), values: ice.weights.clone(), provenance: None };
/// let attributes = [("converged".to_string(), AttrValue::Bool(ice.converged))];
/// store_weights(uri, &weights, &attributes, false)?;
/// assert!(store_weights(uri, &weights, &attributes, false).is_err()); // no silent overwrite
/// let reader = open_matrix(uri, &OpenOptions::default())?;
/// let stored = reader.weights("ice")?.values;
/// assert!(stored.iter().zip(&ice.weights).all(|(a, b)| a.to_bits() == b.to_bits()));
/// assert!(reader.weight_attribute("ice", "converged").is_some());
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn store_weights(
    uri: &str,
    weights: &Weights,
    attributes: &[(String, AttrValue)],
    overwrite: bool,
) -> Result<()> {
    let name = weights.name.as_str();
    check_name(uri, name)?;
    let n_bins = n_bins_of(uri)?;
    if weights.values.len() != n_bins {
        return Err(Error::Argument(format!(
            "{uri}: {} weights for {n_bins} bins",
            weights.values.len()
        )));
    }
    in_cooler(uri, |path, _, bins| {
        if bins.link_exists(name) && !overwrite {
            return Err(existing_column(uri, name));
        }
        replace_column(path, bins, name, |bins, tmp| {
            write_column(path, bins, tmp, weights, attributes)
        })
    })
}

/// Open the cooler at `uri` for writing, run `write(path, group, bins)` on its group and its
/// `bins` group, then flush and close the file.
fn in_cooler(
    uri: &str,
    write: impl FnOnce(&str, &hdf5::Group, &hdf5::Group) -> Result<()>,
) -> Result<()> {
    let (path, group_path) = crate::io::matrices::uri::split_uri(uri);
    let err = |what: String| move |e| Error::hdf5(path, what, e);
    let file = file_builder()
        .open_rw(path)
        .map_err(err("opening the file for writing".into()))?;
    {
        let group = match group_path.map(|g| g.trim_start_matches('/')) {
            None | Some("") => file
                .as_group()
                .map_err(err("opening the root group".into()))?,
            Some(g) => file.group(g).map_err(err(format!("opening group {g}")))?,
        };
        let bins = group.group("bins").map_err(err("opening bins".into()))?;
        write(path, &group, &bins)?;
    }
    file.flush().map_err(err("flushing the file".into()))?;
    file.close().map_err(err("closing the file".into()))
}

/// Write `bins/<name>` by `write(bins, temporary_name)` and move it into place, replacing a
/// column of that name: the steps always leave one complete column under some name.
fn replace_column(
    path: &str,
    bins: &hdf5::Group,
    name: &str,
    write: impl FnOnce(&hdf5::Group, &str) -> Result<()>,
) -> Result<()> {
    let err = |what: String| move |e| Error::hdf5(path, what, e);
    let exists = bins.link_exists(name);
    let pid = std::process::id();
    let tmp = format!(".{name}.contactmap-new-{pid}");
    let backup = format!(".{name}.contactmap-old-{pid}");
    for leftover in [&tmp, &backup] {
        if bins.link_exists(leftover) {
            bins.unlink(leftover)
                .map_err(err(format!("removing bins/{leftover}")))?;
        }
    }
    if let Err(e) = write(bins, &tmp) {
        let _ = bins.unlink(&tmp);
        return Err(e);
    }
    if exists {
        if let Err(e) = bins.relink(name, &backup) {
            let _ = bins.unlink(&tmp);
            return Err(Error::hdf5(
                path,
                format!("renaming bins/{name} (the file is unchanged)"),
                e,
            ));
        }
    }
    if let Err(e) = bins.relink(&tmp, name) {
        let restored = !exists || bins.relink(&backup, name).is_ok();
        let _ = bins.unlink(&tmp);
        let state = if restored {
            "the old column is kept"
        } else {
            "the old column is left under the name bins/.<name>.contactmap-old-<pid>"
        };
        return Err(Error::hdf5(
            path,
            format!("moving the new column into bins/{name} ({state})"),
            e,
        ));
    }
    if exists {
        bins.unlink(&backup)
            .map_err(err(format!("removing the old column bins/{backup}")))?;
    }
    Ok(())
}

/// Values of a bin column written by [`store_bin_columns`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BinColumn<'a> {
    /// 64-bit integers (cooltools' raw coverage).
    Int(&'a [i64]),
    /// 64-bit floats.
    Float(&'a [f64]),
}

impl BinColumn<'_> {
    fn len(&self) -> usize {
        match self {
            BinColumn::Int(v) => v.len(),
            BinColumn::Float(v) => v.len(),
        }
    }
}

/// Write `columns` (one value per bin) into `bins/` of the cooler at `uri`, gzip level 6 as h5py
/// writes them for cooltools, replacing columns of the same names (as cooltools `--store`
/// does), and set `attributes` on the cooler's group (replacing them). Each column is written under a temporary
/// name first and moved into place, so a failure leaves the old column.
///
/// ```
/// use contactmap::io::cool::store::{store_bin_columns, AttrValue, BinColumn};
/// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
///
/// let dir = std::env::temp_dir().join(format!("contactmap-columns-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("mm9.cool");
/// std::fs::copy("data/CN.mm9.10000kb.cool", &path)?;
/// let uri = path.to_str().unwrap();
/// let n = open_matrix(uri, &OpenOptions::default())?.bins().n_bins();
/// let ranks: Vec<i64> = (0..n as i64).collect();
/// let attributes = [("cis".to_string(), AttrValue::Int(7))];
/// store_bin_columns(uri, &[("rank", BinColumn::Int(&ranks))], &attributes)?;
/// store_bin_columns(uri, &[("rank", BinColumn::Int(&ranks))], &attributes)?; // replaced
/// let file = hdf5::File::open(&path)?;
/// assert_eq!(file.dataset("bins/rank")?.read_raw::<i64>()?, ranks);
/// assert_eq!(file.attr("cis")?.read_scalar::<i64>()?, 7);
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn store_bin_columns(
    uri: &str,
    columns: &[(&str, BinColumn<'_>)],
    attributes: &[(String, AttrValue)],
) -> Result<()> {
    let n_bins = n_bins_of(uri)?;
    for (name, values) in columns {
        check_name(uri, name)?;
        if values.len() != n_bins {
            return Err(Error::Argument(format!(
                "{uri}: column {name} has {} values for {n_bins} bins",
                values.len()
            )));
        }
    }
    in_cooler(uri, |path, group, bins| {
        let err = |what: String| move |e| Error::hdf5(path, what, e);
        for (name, values) in columns {
            replace_column(path, bins, name, |bins, dataset_name| {
                match values {
                    BinColumn::Int(v) => create_column(bins, dataset_name, v),
                    BinColumn::Float(v) => create_column(bins, dataset_name, v),
                }
                .map(|_| ())
                .map_err(err(format!("writing bins/{name}")))
            })?;
        }
        for (key, value) in attributes {
            if group.attr_names().is_ok_and(|names| names.contains(key)) {
                group
                    .delete_attr(key)
                    .map_err(err(format!("replacing attribute {key} of the cooler")))?;
            }
            write_attr(group, key, value)
                .map_err(err(format!("writing attribute {key} of the cooler")))?;
        }
        Ok(())
    })
}

/// Create `bins/<name>` holding `values`, gzip level 6 in chunks of up to 65,536 values (as
/// h5py writes cooler's bin columns).
fn create_column<T: hdf5::H5Type>(
    bins: &hdf5::Group,
    name: &str,
    values: &[T],
) -> hdf5::Result<hdf5::Dataset> {
    let builder = bins.new_dataset_builder().with_data(values);
    if values.is_empty() {
        builder.create(name)
    } else {
        builder
            .chunk(values.len().min(1 << 16))
            .deflate(6)
            .create(name)
    }
}

fn write_column(
    path: &str,
    bins: &hdf5::Group,
    dataset_name: &str,
    weights: &Weights,
    attributes: &[(String, AttrValue)],
) -> Result<()> {
    let err = |what: String| move |e| Error::hdf5(path, what, e);
    let divisive = DIVISIVE_BY_NAME.contains(&weights.name.as_str());
    let values: Vec<f64> = if divisive {
        weights.values.iter().map(|&w| invert_weight(w)).collect()
    } else {
        weights.values.clone()
    };
    let dataset = create_column(bins, dataset_name, &values)
        .map_err(err(format!("writing bins/{}", weights.name)))?;
    for (key, value) in attributes {
        if key == "divisive_weights" {
            continue;
        }
        write_attr(&dataset, key, value).map_err(err(format!(
            "writing attribute bins/{}.{key}",
            weights.name
        )))?;
    }
    write_attr(&dataset, "divisive_weights", &AttrValue::Bool(divisive)).map_err(err(format!(
        "writing attribute bins/{}.divisive_weights",
        weights.name
    )))
}

fn write_attr(location: &hdf5::Location, key: &str, value: &AttrValue) -> hdf5::Result<()> {
    match value {
        AttrValue::Bool(v) => location.new_attr::<bool>().create(key)?.write_scalar(v),
        AttrValue::Int(v) => location.new_attr::<i64>().create(key)?.write_scalar(v),
        AttrValue::Float(v) => location.new_attr::<f64>().create(key)?.write_scalar(v),
        AttrValue::Str(v) => {
            let text: VarLenUnicode = v
                .parse()
                .map_err(|e| hdf5::Error::from(format!("attribute {key}: {e}")))?;
            location
                .new_attr::<VarLenUnicode>()
                .create(key)?
                .write_scalar(&text)
        }
        AttrValue::Bools(v) => location
            .new_attr_builder()
            .with_data(&v[..])
            .create(key)
            .map(|_| ()),
        AttrValue::Floats(v) => location
            .new_attr_builder()
            .with_data(&v[..])
            .create(key)
            .map(|_| ()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::{BinTable, Chrom};
    use crate::io::InMemory;
    use crate::io::matrices::cool::{CoolWriteOptions, write_cool};
    use crate::matrix::{CountType, MatrixBuilder};

    fn small_cool(dir: &std::path::Path) -> String {
        let bins = BinTable::fixed(vec![Chrom::new("a", 50), Chrom::new("b", 30)], 10).unwrap();
        let mut builder = MatrixBuilder::new(bins, CountType::Integer);
        for i in 0..8u64 {
            for j in i..8 {
                builder.push(i, j, (1 + i + j) as f64).unwrap();
            }
        }
        let path = dir.join("small.cool");
        let matrix = InMemory::new("small".into(), builder.build());
        write_cool(&matrix, &path, &CoolWriteOptions::default()).unwrap();
        path.to_string_lossy().into_owned()
    }

    #[test]
    fn stores_replaces_only_when_asked_and_keeps_attributes() {
        let dir = tempfile::tempdir().unwrap();
        let uri = small_cool(dir.path());
        let weights = Weights {
            name: "weight".into(),
            values: vec![0.5, f64::NAN, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
            provenance: None,
        };
        let attributes = vec![
            ("converged".to_string(), AttrValue::Bool(true)),
            ("scale".to_string(), AttrValue::Float(12.5)),
            ("min_nnz".to_string(), AttrValue::Int(10)),
            ("var".to_string(), AttrValue::Floats(vec![1e-6, 2e-6])),
        ];
        assert!(!column_exists(&uri, "weight").unwrap());
        store_weights(&uri, &weights, &attributes, false).unwrap();
        let reader = CoolReader::open(&uri).unwrap();
        assert_eq!(reader.weight_names(), vec!["weight".to_string()]);
        let read = reader.weights("weight").unwrap();
        assert_eq!(read.values[0], 0.5);
        assert!(read.values[1].is_nan());
        drop(reader);
        // A second store without overwrite fails and changes nothing.
        let before = std::fs::read(&uri).unwrap();
        let other = Weights {
            values: vec![9.0; 8],
            ..weights.clone()
        };
        assert!(store_weights(&uri, &other, &attributes, false).is_err());
        assert!(check_target(&uri, "weight", false).is_err());
        assert_eq!(std::fs::read(&uri).unwrap(), before);
        // With overwrite the column is replaced and no temporary name is left behind.
        store_weights(&uri, &other, &attributes, true).unwrap();
        let file = file_builder().open(&uri).unwrap();
        let bins = file.group("bins").unwrap();
        let mut names = bins.member_names().unwrap();
        names.sort();
        assert_eq!(names, vec!["chrom", "end", "start", "weight"]);
        let dataset = bins.dataset("weight").unwrap();
        assert_eq!(dataset.read_raw::<f64>().unwrap(), vec![9.0; 8]);
        assert!(
            dataset
                .attr("converged")
                .unwrap()
                .read_scalar::<bool>()
                .unwrap()
        );
        assert!(
            !dataset
                .attr("divisive_weights")
                .unwrap()
                .read_scalar::<bool>()
                .unwrap()
        );
        assert_eq!(
            dataset.attr("var").unwrap().read_raw::<f64>().unwrap(),
            vec![1e-6, 2e-6]
        );
    }

    #[test]
    fn juicer_names_are_stored_divisive() {
        let dir = tempfile::tempdir().unwrap();
        let uri = small_cool(dir.path());
        let weights = Weights {
            name: "KR".into(),
            values: vec![0.5, f64::NAN, 1.0, 2.0, 4.0, 4.0, 5.0, 8.0],
            provenance: None,
        };
        store_weights(&uri, &weights, &[], false).unwrap();
        let file = file_builder().open(&uri).unwrap();
        let raw = file.dataset("bins/KR").unwrap().read_raw::<f64>().unwrap();
        assert_eq!(raw[0], 2.0);
        drop(file);
        let back = CoolReader::open(&uri).unwrap().weights("KR").unwrap();
        assert_eq!(back.values[0], 0.5);
        assert!(back.values[1].is_nan());
        assert_eq!(back.values[7], 8.0);
    }

    #[test]
    fn bad_names_and_lengths_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let uri = small_cool(dir.path());
        for name in ["", "start", "a/b", ".hidden"] {
            let weights = Weights {
                name: name.into(),
                values: vec![1.0; 8],
                provenance: None,
            };
            assert!(store_weights(&uri, &weights, &[], true).is_err());
        }
        let short = Weights {
            name: "w".into(),
            values: vec![1.0; 3],
            provenance: None,
        };
        assert!(store_weights(&uri, &short, &[], true).is_err());
    }
}
