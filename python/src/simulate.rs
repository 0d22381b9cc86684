//! The polymer simulator (`contactmap simulate polymer`): the map's pixels, the sampled
//! conformations, the radii of gyration and the truth tables of a run.

use std::path::Path;

use contactmap::error::Error;
use contactmap::io::bed::read_bed_if_file;
use contactmap::io::cool::{write_cool, CoolWriteOptions};
use contactmap::io::InMemory;
use contactmap::sim::files::parse_type_pattern;
use contactmap::sim::gpu::{Backend, Device};
use contactmap::sim::spec::{
    BondKind, BoundarySites, ConfinementKind, RepulsionKind, SimulationSpec,
};
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{py_err, run, vec1, ContactmapError};

fn kind<T>(key: &str, value: &str, choices: &[(&str, T)]) -> PyResult<T>
where
    T: Copy,
{
    choices
        .iter()
        .find(|(name, _)| *name == value)
        .map(|(_, kind)| *kind)
        .ok_or_else(|| {
            let names: Vec<&str> = choices.iter().map(|(name, _)| *name).collect();
            ContactmapError::new_err(format!("{key} '{value}': expected {}", names.join(", ")))
        })
}

/// The library's specification from keyword arguments (each overrides its default).
fn spec_of(options: &Bound<'_, PyDict>) -> PyResult<SimulationSpec> {
    let mut spec = SimulationSpec::default();
    for (key, value) in options.iter() {
        let key: String = key.extract()?;
        let bad = |e: PyErr| PyTypeError::new_err(format!("{key}: {e}"));
        match key.as_str() {
            "chains" => spec.chains = value.extract().map_err(bad)?,
            "monomer_bp" => spec.monomer_bp = value.extract().map_err(bad)?,
            "monomers_per_bin" => spec.monomers_per_bin = value.extract().map_err(bad)?,
            "bonds" => {
                let name: String = value.extract().map_err(bad)?;
                spec.bonds = kind(
                    "bonds",
                    &name,
                    &[("harmonic", BondKind::Harmonic), ("fene", BondKind::Fene)],
                )?;
            }
            "bond_wiggle" => spec.bond_wiggle = value.extract().map_err(bad)?,
            "stiffness" => spec.stiffness = value.extract().map_err(bad)?,
            "repulsion" => {
                let name: String = value.extract().map_err(bad)?;
                spec.repulsion = kind(
                    "repulsion",
                    &name,
                    &[
                        ("polynomial", RepulsionKind::Polynomial),
                        ("wca", RepulsionKind::Wca),
                        ("none", RepulsionKind::None),
                    ],
                )?;
            }
            "repulsion_energy" => spec.repulsion_energy = value.extract().map_err(bad)?,
            "repulsion_radius" => spec.repulsion_radius = value.extract().map_err(bad)?,
            "exclude_neighbours" => spec.exclude_neighbours = value.extract().map_err(bad)?,
            "ideal" => spec.ideal = value.extract().map_err(bad)?,
            "saw" => spec.saw = value.extract().map_err(bad)?,
            "types" => spec.types = value.extract().map_err(bad)?,
            "attraction" => spec.attraction = value.extract().map_err(bad)?,
            "attraction_radius" => spec.attraction_radius = value.extract().map_err(bad)?,
            "density" => spec.density = value.extract().map_err(bad)?,
            "confinement" => {
                let name: Option<String> = value.extract().map_err(bad)?;
                spec.confinement = name
                    .map(|name| {
                        kind(
                            "confinement",
                            &name,
                            &[
                                ("sphere", ConfinementKind::Sphere),
                                ("box", ConfinementKind::Box),
                                ("none", ConfinementKind::None),
                            ],
                        )
                    })
                    .transpose()?;
            }
            "dt" => spec.dt = value.extract().map_err(bad)?,
            "replicas" => spec.replicas = value.extract().map_err(bad)?,
            "equilibration" => spec.equilibration = value.str()?.to_string(),
            "sample_every" => spec.sample_every = value.str()?.to_string(),
            "samples" => spec.samples = value.extract().map_err(bad)?,
            "contact_radius" => spec.contact_radius = value.extract().map_err(bad)?,
            "seed" => spec.seed = value.extract().map_err(bad)?,
            "extrusion" => spec.extrusion = value.extract().map_err(bad)?,
            "ctcf" => {
                let value: Option<String> = value.extract().map_err(bad)?;
                spec.ctcf = match value {
                    Some(value) => {
                        let bed = read_bed_if_file(&value).map_err(py_err)?;
                        Some(BoundarySites::new(&value, bed))
                    }
                    None => None,
                };
            }
            "processivity" => spec.processivity = value.extract().map_err(bad)?,
            "separation" => spec.separation = value.extract().map_err(bad)?,
            "capture" => spec.capture = value.extract().map_err(bad)?,
            "release" => spec.release = value.extract().map_err(bad)?,
            "steps_per_move" => spec.steps_per_move = value.extract().map_err(bad)?,
            "keep_conformations" => spec.keep_conformations = value.extract().map_err(bad)?,
            other => {
                return Err(PyTypeError::new_err(format!(
                    "simulate_polymer: no parameter '{other}'"
                )))
            }
        }
    }
    Ok(spec)
}

/// A run: the chromosomes (name, bp), the bins (chromosome index, start, end), the pixels (bin1, bin2, count), the
/// conformations (samples x beads x 3, when kept), the radii of gyration (samples x chains),
/// the truth tables as text (boundaries, domains, loops, compartments), the relaxation note and
/// its warning, and the backend's description.
type SimulationTuple<'py> = (
    Vec<(String, u64)>,
    crate::file::BinArrays<'py>,
    (
        Bound<'py, PyArray1<i64>>,
        Bound<'py, PyArray1<i64>>,
        Bound<'py, PyArray1<i64>>,
    ),
    Option<Bound<'py, PyArray3<f64>>>,
    Bound<'py, PyArray2<f64>>,
    (String, String, Option<String>, Option<String>),
    (String, Option<String>, String),
);

/// `contactmap simulate polymer` with the options `options` (the command line's names, with
/// `_` for `-`), on `device` (auto, cpu, gpu) with `threads` CPU threads (None: every core);
/// with `output`, the map is also written there as a .cool.
#[pyfunction]
#[pyo3(signature = (options, device="auto", threads=None, output=None))]
pub(crate) fn simulate_polymer<'py>(
    py: Python<'py>,
    options: &Bound<'py, PyDict>,
    device: &str,
    threads: Option<usize>,
    output: Option<String>,
) -> PyResult<SimulationTuple<'py>> {
    let spec = spec_of(options)?;
    let device = kind(
        "device",
        device,
        &[
            ("auto", Device::Auto),
            ("cpu", Device::Cpu),
            ("gpu", Device::Gpu),
        ],
    )?;
    if threads == Some(0) {
        return Err(ContactmapError::new_err("threads: at least 1"));
    }
    let done = run(py, || {
        let params = spec.params()?;
        let bins = params.bin_table(spec.monomer_bp)?;
        let backend = Backend::open(device)?;
        let simulate = || backend.run(&params, &|_| {});
        let ensemble = match threads {
            None => simulate()?,
            Some(threads) => rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|err| Error::Argument(format!("threads {threads}: {err}")))?
                .install(simulate)?,
        };
        if let Some(path) = &output {
            let reader = InMemory::new("simulate polymer".into(), ensemble.matrix(bins.clone())?);
            write_cool(&reader, Path::new(path), &CoolWriteOptions::default())?;
        }
        let text = |bytes: Vec<u8>| String::from_utf8_lossy(&bytes).into_owned();
        let compartments = match &spec.types {
            Some(pattern) => {
                let (_, letters) = parse_type_pattern(pattern)?;
                params.truth_compartments_bed(&bins, &letters).map(text)
            }
            None => None,
        };
        let truths = (
            text(params.truth_boundaries_bed(&bins)),
            text(params.truth_domains_bed(&bins, spec.monomer_bp)),
            spec.extrusion
                .then(|| text(ensemble.truth_loops_bedpe(&bins))),
            compartments,
        );
        let report = params.relaxation_report();
        let chroms: Vec<(String, u64)> = bins
            .chroms()
            .iter()
            .map(|c| (c.name.clone(), c.length_bp))
            .collect();
        Ok((
            chroms,
            bins,
            ensemble,
            truths,
            (report.note, report.warning, backend.description()),
        ))
    })?;
    let (chroms, bins, ensemble, truths, notes) = done;
    let bin_columns = crate::file::bin_arrays(py, &bins);
    let pixels = (
        vec1(py, ensemble.pixels.iter().map(|p| p.0 as i64).collect()),
        vec1(py, ensemble.pixels.iter().map(|p| p.1 as i64).collect()),
        vec1(py, ensemble.pixels.iter().map(|p| p.2 as i64).collect()),
    );
    let n_chains = ensemble.radii_of_gyration.first().map_or(0, Vec::len);
    let radii: Vec<f64> = ensemble.radii_of_gyration.concat();
    let radii = vec1(py, radii)
        .reshape([ensemble.radii_of_gyration.len(), n_chains])
        .map_err(|e| ContactmapError::new_err(e.to_string()))?;
    let conformations = if ensemble.conformations.is_empty() {
        None
    } else {
        let (n, beads) = (
            ensemble.conformations.len(),
            ensemble.conformations[0].len(),
        );
        let flat: Vec<f64> = ensemble
            .conformations
            .iter()
            .flat_map(|c| c.iter().flatten().copied())
            .collect();
        Some(
            vec1(py, flat)
                .reshape([n, beads, 3])
                .map_err(|e| ContactmapError::new_err(e.to_string()))?,
        )
    };
    Ok((
        chroms,
        bin_columns,
        pixels,
        conformations,
        radii,
        truths,
        notes,
    ))
}

/// `contactmap polymer-stats`: P(s) `(s_mid, contact probability)`, the separations with
/// `<R^2(s)>` and `<Rg^2(s)>`, and each conformation's label and `Rg^2`, as polychrom's
/// `polymer_analyses` computes them, over the conformations of `trajectories`.
#[allow(clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (trajectories, contact_radius=1.1))]
pub(crate) fn polymer_stats<'py>(
    py: Python<'py>,
    trajectories: Vec<String>,
    contact_radius: f64,
) -> PyResult<(
    (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>),
    (
        Bound<'py, PyArray1<u64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
    ),
    (Vec<String>, Bound<'py, PyArray1<f64>>),
)> {
    use contactmap::conformations::stats::ensemble_stats;
    use contactmap::io::trajectory::open_trajectories;
    let stats = run(py, || {
        ensemble_stats(open_trajectories(&trajectories)?, contact_radius)
    })?;
    let (mids, probabilities): (Vec<f64>, Vec<f64>) = stats.contact_scaling.into_iter().unzip();
    let (labels, rg2): (Vec<String>, Vec<f64>) = stats.rg2.into_iter().unzip();
    Ok((
        (vec1(py, mids), vec1(py, probabilities)),
        (
            vec1(py, stats.bins.iter().map(|&s| s as u64).collect()),
            vec1(py, stats.r2),
            vec1(py, stats.rg2_of_s),
        ),
        (labels, vec1(py, rg2)),
    ))
}

/// `contactmap polymer-map`: the ensemble contact map of the conformations of `trajectories`,
/// as polychrom's `binnedContactMap` counts it: the upper-triangle pixels `(bin1, bin2, count)`,
/// the bins of each chain, the conformations counted and their beads.
#[allow(clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (trajectories, contact_radius, monomers_per_bin=1, chains=None))]
pub(crate) fn polymer_map<'py>(
    py: Python<'py>,
    trajectories: Vec<String>,
    contact_radius: f64,
    monomers_per_bin: usize,
    chains: Option<Vec<usize>>,
) -> PyResult<(
    (
        Bound<'py, PyArray1<i64>>,
        Bound<'py, PyArray1<i64>>,
        Bound<'py, PyArray1<i64>>,
    ),
    Vec<usize>,
    usize,
    usize,
)> {
    use contactmap::conformations::{chains_of_lengths, contact_map, MapParams};
    use contactmap::io::trajectory::open_trajectories;
    let params = MapParams {
        contact_radius,
        monomers_per_bin,
        chains: chains.as_deref().map(chains_of_lengths),
    };
    let map = run(py, || {
        contact_map(open_trajectories(&trajectories)?, &params, &|_| {})
    })?;
    let column = |f: fn(&(u32, u32, u64)) -> i64| vec1(py, map.pixels.iter().map(f).collect());
    Ok((
        (
            column(|p| i64::from(p.0)),
            column(|p| i64::from(p.1)),
            column(|p| p.2 as i64),
        ),
        map.bins.bins_per_chain(),
        map.n_conformations,
        map.n_beads,
    ))
}
