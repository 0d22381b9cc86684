//! Checks of `.cool` / `.mcool` files on the stored HDF5 data.

use super::{BinTable, Column, File, TypeDescriptor, VarLenAscii, VarLenUnicode, guarded};
use crate::error::Result;

/// Cooler groups of a file: (group path, resolution from the group name if any).
pub(super) type CoolerGroups = Vec<(String, Option<u64>)>;

/// The columns `bins/chrom`, `bins/start`, `bins/end` as stored.
pub(super) type BinColumns = (Vec<i64>, Vec<i64>, Vec<i64>);

mod attributes;
mod check;
mod coarsening;
mod offsets;
mod open;
mod pixels;

pub(super) use coarsening::*;
pub(super) use open::*;

/// What the checks learned about one cooler, for the coarsening check and the repair.
pub(super) struct CheckedCooler {
    name: String,
    resolution: Option<u64>,
    /// The bin table when it is valid.
    bins: Option<BinTable>,
    /// True when the pixels are in range, upper-triangle (when stored so), sorted and unique.
    pixels_clean: bool,
    /// The pixel columns when they could be opened.
    pixels: Option<PixelColumns>,
}

pub(super) struct PixelColumns {
    pub(super) bin1: Column,
    pub(super) bin2: Column,
    pub(super) count: Column,
}

impl PixelColumns {
    pub(super) fn len(&self) -> usize {
        self.count.len()
    }

    pub(super) fn read(
        &self,
        raw: &File,
        lo: usize,
        hi: usize,
    ) -> Result<(Vec<i64>, Vec<i64>, Vec<f64>)> {
        let ((bin1, bin2), count) = rayon::join(
            || {
                rayon::join(
                    || self.bin1.read::<i64>(raw, lo, hi),
                    || self.bin2.read::<i64>(raw, lo, hi),
                )
            },
            || self.count.read::<f64>(raw, lo, hi),
        );
        Ok((bin1?, bin2?, count?))
    }
}

/// A scalar attribute as stored.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Attr {
    Int(i64),
    Float(f64),
    Str(String),
}

impl Attr {
    pub(super) fn as_i64(&self) -> Option<i64> {
        match self {
            Attr::Int(v) => Some(*v),
            Attr::Float(v) if v.fract() == 0.0 => Some(*v as i64),
            Attr::Str(s) => s.trim().parse().ok(),
            Attr::Float(_) => None,
        }
    }

    fn as_f64(&self) -> Option<f64> {
        match self {
            Attr::Int(v) => Some(*v as f64),
            Attr::Float(v) => Some(*v),
            Attr::Str(s) => s.trim().parse().ok(),
        }
    }

    pub(super) fn as_str(&self) -> Option<&str> {
        match self {
            Attr::Str(s) => Some(s),
            _ => None,
        }
    }
}

pub(super) fn read_attr(path: &str, location: &hdf5::Location, name: &str) -> Option<Attr> {
    guarded(path, &format!("attribute '{name}'"), || {
        if !location.attr_names().ok()?.iter().any(|n| n == name) {
            return None;
        }
        let attr = location.attr(name).ok()?;
        let n_values = attr
            .shape()
            .iter()
            .try_fold(1usize, |n, &d| n.checked_mul(d));
        if n_values.is_none_or(|n| n > 1) {
            return None;
        }
        match attr.dtype().ok()?.to_descriptor().ok()? {
            TypeDescriptor::Integer(_) | TypeDescriptor::Unsigned(_) | TypeDescriptor::Boolean => {
                attr.read_raw::<i64>().ok()?.first().map(|&v| Attr::Int(v))
            }
            TypeDescriptor::Float(_) => attr
                .read_raw::<f64>()
                .ok()?
                .first()
                .map(|&v| Attr::Float(v)),
            TypeDescriptor::VarLenUnicode => attr
                .read_raw::<VarLenUnicode>()
                .ok()?
                .first()
                .map(|s| Attr::Str(crate::io::hdf5_guard::lossy(s.as_bytes()))),
            TypeDescriptor::VarLenAscii => attr
                .read_raw::<VarLenAscii>()
                .ok()?
                .first()
                .map(|s| Attr::Str(crate::io::hdf5_guard::lossy(s.as_bytes()))),
            TypeDescriptor::FixedAscii(_) | TypeDescriptor::FixedUnicode(_) => attr
                .read_raw::<hdf5::types::FixedAscii<4096>>()
                .ok()?
                .first()
                .map(|s| {
                    Attr::Str(
                        crate::io::hdf5_guard::lossy(s.as_bytes())
                            .trim_end_matches('\0')
                            .to_string(),
                    )
                }),
            _ => None,
        }
    })
}

/// The type of a dataset, coarsely.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    Integer,
    Float,
    Text,
    Other,
}

pub(super) fn kind_of(dataset: &hdf5::Dataset) -> Kind {
    match dataset.dtype().and_then(|t| t.to_descriptor()) {
        Ok(TypeDescriptor::Integer(_) | TypeDescriptor::Unsigned(_) | TypeDescriptor::Enum(_)) => {
            Kind::Integer
        }
        Ok(TypeDescriptor::Float(_)) => Kind::Float,
        Ok(
            TypeDescriptor::VarLenUnicode
            | TypeDescriptor::VarLenAscii
            | TypeDescriptor::FixedAscii(_)
            | TypeDescriptor::FixedUnicode(_),
        ) => Kind::Text,
        _ => Kind::Other,
    }
}

/// The checks of one cooler group.
pub(super) struct CoolerCheck<'a> {
    pub(super) path: &'a str,
    pub(super) name: &'a str,
    pub(super) group: &'a hdf5::Group,
    pub(super) raw: &'a File,
}
