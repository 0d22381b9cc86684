//! Checks of `.cool` / `.mcool` files on the stored HDF5 data.

mod attributes;
mod check;
mod coarsening;
mod columns;
mod offsets;
mod open;
mod pixels;
mod stored;

pub(super) use check::CoolerCheck;
pub(super) use open::{cooler_groups, open_hdf5, validate_hdf5};
pub(super) use stored::{Kind, kind_of, read_attr};
