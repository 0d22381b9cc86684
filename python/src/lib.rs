//! `contactmap._native`: the library's functions as Python sees them. This crate only converts
//! (Python arguments to the library's parameters, its results to numpy arrays, lists and
//! strings); every computation is the library's, the same calls the command line makes. The
//! GIL is released while the library works, and numpy arrays take over the library's vectors
//! without a copy.
//!
//! `convert` holds what every part shares (the exception, the GIL-free run, numpy arrays). One
//! module per part of the API: `file` (opening and fetching), `tables` (expected,
//! insulation, directionality, balance), `compartments` (eigenvectors and saddles), `loops`
//! (dots and pileups), `writers` (convert, zoomify, merge, create_cooler), `protein`
//! (structures and contact scores), `simulate` (the polymer simulator), `tiles` (HiGlass
//! tiles).

mod compartments;
mod convert;
mod diff;
mod file;
mod loops;
mod protein;
mod simulate;
mod tables;
mod tiles;
mod writers;

use convert::{ContactmapError, FormatError};
use pyo3::prelude::*;

/// The native part of the `contactmap` package.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ContactmapError", m.py().get_type::<ContactmapError>())?;
    m.add("FormatError", m.py().get_type::<FormatError>())?;
    m.add_class::<file::NativeFile>()?;
    m.add_class::<tiles::NativeTileset>()?;
    m.add_function(wrap_pyfunction!(file::resolutions, m)?)?;
    m.add_function(wrap_pyfunction!(diff::diff_loops, m)?)?;
    m.add_function(wrap_pyfunction!(diff::diff_boundaries, m)?)?;
    m.add_function(wrap_pyfunction!(diff::diff_compartments, m)?)?;
    m.add_function(wrap_pyfunction!(diff::diff_regions, m)?)?;
    m.add_function(wrap_pyfunction!(tables::expected_cis, m)?)?;
    m.add_function(wrap_pyfunction!(tables::expected_trans, m)?)?;
    m.add_function(wrap_pyfunction!(tables::insulation, m)?)?;
    m.add_function(wrap_pyfunction!(tables::directionality, m)?)?;
    m.add_function(wrap_pyfunction!(tables::balance, m)?)?;
    m.add_function(wrap_pyfunction!(tables::balance_store, m)?)?;
    m.add_function(wrap_pyfunction!(compartments::eigs_cis, m)?)?;
    m.add_function(wrap_pyfunction!(compartments::eigs_trans, m)?)?;
    m.add_function(wrap_pyfunction!(compartments::digitize, m)?)?;
    m.add_function(wrap_pyfunction!(compartments::saddle, m)?)?;
    m.add_function(wrap_pyfunction!(compartments::saddle_strength, m)?)?;
    m.add_function(wrap_pyfunction!(loops::dots, m)?)?;
    m.add_function(wrap_pyfunction!(loops::merge_dots, m)?)?;
    m.add_function(wrap_pyfunction!(loops::pileup, m)?)?;
    m.add_function(wrap_pyfunction!(writers::convert, m)?)?;
    m.add_function(wrap_pyfunction!(writers::zoomify, m)?)?;
    m.add_function(wrap_pyfunction!(writers::merge, m)?)?;
    m.add_function(wrap_pyfunction!(writers::create_cooler, m)?)?;
    m.add_function(wrap_pyfunction!(protein::read_structure, m)?)?;
    m.add_function(wrap_pyfunction!(protein::score_contacts, m)?)?;
    m.add_function(wrap_pyfunction!(protein::contact_frequencies, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::simulate_polymer, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::polymer_map, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::polymer_stats, m)?)?;
    Ok(())
}
