//! What is stored, as read: a scalar attribute's value, and a dataset's type, coarsely.

use hdf5::types::{TypeDescriptor, VarLenAscii, VarLenUnicode};

use crate::io::hdf5_guard::guarded;

/// A scalar attribute as stored.
#[derive(Clone, Debug, PartialEq)]
pub(in crate::validate) enum Attr {
    Int(i64),
    Float(f64),
    Str(String),
}

impl Attr {
    pub(in crate::validate) fn as_i64(&self) -> Option<i64> {
        match self {
            Attr::Int(v) => Some(*v),
            Attr::Float(v) if v.fract() == 0.0 => Some(*v as i64),
            Attr::Str(s) => s.trim().parse().ok(),
            Attr::Float(_) => None,
        }
    }

    pub(super) fn as_f64(&self) -> Option<f64> {
        match self {
            Attr::Int(v) => Some(*v as f64),
            Attr::Float(v) => Some(*v),
            Attr::Str(s) => s.trim().parse().ok(),
        }
    }

    pub(in crate::validate) fn as_str(&self) -> Option<&str> {
        match self {
            Attr::Str(s) => Some(s),
            _ => None,
        }
    }
}

pub(in crate::validate) fn read_attr(
    path: &str,
    location: &hdf5::Location,
    name: &str,
) -> Option<Attr> {
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
pub(in crate::validate) enum Kind {
    Integer,
    Float,
    Text,
    Other,
}

pub(in crate::validate) fn kind_of(dataset: &hdf5::Dataset) -> Kind {
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
