//! Proteins: a structure's residue distances and contacts (`contactmap contacts`), and the
//! CASP scores of contact predictions against it (`contactmap score contacts`).

use std::path::Path;

use contactmap::error::Error;
use contactmap::io::predictions::load_prediction;
use contactmap::io::predictions::{read_fasta, PredictionFormat};
use contactmap::io::structure::read_chain;
use contactmap::score::contacts::{
    ContactAtom, ContactDefinition, ContactScore, DistanceTest, ListScore, Rounding,
    SeparationRange,
};
use contactmap::score::lists::{parse_length, parse_list_size, parse_range, NamedRange};
use contactmap::score::target::{
    measure, place_chain, place_prediction, score_prediction, Placed, PredictionScores,
    RegisterChoice, ScorePlan,
};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::convert::{array2, run, vec1, ContactmapError, NamedColumn};

fn definition(atom: &str, cutoff: f64, le: bool) -> PyResult<ContactDefinition> {
    let atom = match atom.to_ascii_lowercase().as_str() {
        "cb" => ContactAtom::Cb,
        "ca" => ContactAtom::Ca,
        "heavy" => ContactAtom::Heavy,
        other => {
            return Err(ContactmapError::new_err(format!(
                "atom '{other}': expected cb, ca or heavy"
            )))
        }
    };
    Ok(ContactDefinition {
        atom,
        cutoff_angstrom: cutoff,
        test: if le {
            DistanceTest::LessOrEqual
        } else {
            DistanceTest::Less
        },
    })
}

fn register_choice(name: &str) -> PyResult<RegisterChoice> {
    match name {
        "auto" => Ok(RegisterChoice::Auto),
        "align" => Ok(RegisterChoice::Align),
        "numbering" => Ok(RegisterChoice::Numbering),
        other => Err(ContactmapError::new_err(format!(
            "register '{other}': expected auto, align or numbering"
        ))),
    }
}

fn format_of(name: Option<&str>) -> PyResult<Option<PredictionFormat>> {
    let Some(name) = name else { return Ok(None) };
    Ok(Some(match name.to_ascii_lowercase().as_str() {
        "rr" => PredictionFormat::Rr,
        "matrix" => PredictionFormat::Matrix,
        "table" => PredictionFormat::Table,
        "npz" => PredictionFormat::Npz,
        "npy" => PredictionFormat::Npy,
        "evfold" => PredictionFormat::Evfold,
        "gremlin" => PredictionFormat::Gremlin,
        other => {
            return Err(ContactmapError::new_err(format!(
                "format '{other}': expected rr, matrix, table, npz, npy, evfold or gremlin"
            )))
        }
    }))
}

fn rounding_of(name: &str) -> PyResult<Rounding> {
    match name {
        "floor" => Ok(Rounding::Floor),
        "half-up" | "half_up" => Ok(Rounding::HalfUp),
        "banker" => Ok(Rounding::Banker),
        other => Err(ContactmapError::new_err(format!(
            "rounding '{other}': expected floor, half-up or banker"
        ))),
    }
}

/// One row of the scores table: a prediction's list of one range.
struct Row<'a> {
    report: &'a PredictionScores,
    named: &'a NamedRange,
    label: &'a String,
    score: &'a ContactScore,
    list: &'a ListScore,
}

/// A chain's observed residues: the chain id, their numbers (on the `fasta` sequence when
/// given), their distances (Angstrom, `n x n`), their contacts, the register's description.
type StructureTuple<'py> = (
    String,
    Bound<'py, PyArray1<i32>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<bool>>,
    Option<String>,
);

/// The residue distances of a chain of `structure` (PDB or mmCIF), as `contactmap contacts`
/// measures them (`atom`: cb, ca or heavy), and the contacts of the definition (`d < cutoff`,
/// or `<=` with `le`; none on the diagonal).
#[allow(clippy::too_many_arguments)]
#[pyfunction]
#[pyo3(signature = (structure, chain=None, atom="cb", cutoff=8.0, le=false, fasta=None, register="auto"))]
pub(crate) fn read_structure<'py>(
    py: Python<'py>,
    structure: &str,
    chain: Option<String>,
    atom: &str,
    cutoff: f64,
    le: bool,
    fasta: Option<String>,
    register: &str,
) -> PyResult<StructureTuple<'py>> {
    let definition = definition(atom, cutoff, le)?;
    let mode = register_choice(register)?;
    let (id, numbers, distances, contacts, described) = run(py, || {
        let path = Path::new(structure);
        let original = read_chain(path, chain.as_deref())?;
        let sequence = fasta
            .as_deref()
            .map(|f| read_fasta(Path::new(f)))
            .transpose()?;
        let (placed, register) = place_chain(path, &original, sequence.as_deref(), mode)?;
        let truth = measure(path, &placed, &definition)?;
        let distances = truth.distance_matrix();
        let contacts = ndarray::Array2::from_shape_fn(distances.dim(), |(a, b)| {
            a != b && definition.is_contact(distances[[a, b]])
        });
        Ok((
            placed.id.clone(),
            truth.numbers().to_vec(),
            distances,
            contacts,
            register.map(|r| r.describe(&original)),
        ))
    })?;
    Ok((
        id,
        vec1(py, numbers),
        array2(py, distances),
        array2(py, contacts),
        described,
    ))
}

/// `contactmap score contacts`: the scores of each prediction (a file) against a chain of
/// `structure`, as columns (`prediction range min_sep max_sep list k n_scored tp precision
/// recall f1 mcc xd length n_true n_available`), the warnings (numbering) and per prediction
/// how the chain was placed on its sequence.
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pyfunction]
#[pyo3(signature = (structure, predictions, chain=None, fasta=None, format=None, atom="cb", cutoff=8.0, le=false, register="auto", ranges=None, top=None, min_sep=None, length=None, rounding="floor", keep_unobserved=false))]
pub(crate) fn score_contacts<'py>(
    py: Python<'py>,
    structure: &str,
    predictions: Vec<String>,
    chain: Option<String>,
    fasta: Option<String>,
    format: Option<&str>,
    atom: &str,
    cutoff: f64,
    le: bool,
    register: &str,
    ranges: Option<Vec<String>>,
    top: Option<Vec<String>>,
    min_sep: Option<u32>,
    length: Option<String>,
    rounding: &str,
    keep_unobserved: bool,
) -> PyResult<(Vec<NamedColumn<'py>>, Vec<String>, Vec<(String, String)>)> {
    let definition = definition(atom, cutoff, le)?;
    let mode = register_choice(register)?;
    let format = format_of(format)?;
    let rounding = rounding_of(rounding)?;
    let (reports, warnings, registers) = run(py, || {
        let ranges = match min_sep {
            Some(min) => vec![NamedRange {
                name: format!("{min}+"),
                range: SeparationRange::new(min, None),
            }],
            None => ranges
                .unwrap_or_else(|| {
                    ["short", "medium", "long", "all"]
                        .map(String::from)
                        .to_vec()
                })
                .iter()
                .map(|t| parse_range(t))
                .collect::<Result<_, Error>>()?,
        };
        let sizes = top
            .unwrap_or_else(|| ["L/10", "L/5", "L/2", "L"].map(String::from).to_vec())
            .iter()
            .map(|t| parse_list_size(t))
            .collect::<Result<_, Error>>()?;
        let plan = ScorePlan {
            ranges,
            sizes,
            length: parse_length(length.as_deref())?,
            rounding,
            keep_unobserved,
            curve_size: None,
        };
        let path = Path::new(structure);
        let sequence = fasta
            .as_deref()
            .map(|f| read_fasta(Path::new(f)))
            .transpose()?;
        let original = read_chain(path, chain.as_deref())?;
        // one placement per distinct sequence (usually one for all predictions)
        let mut placements: Vec<(Option<String>, Placed)> = Vec::new();
        let (mut reports, mut warnings, mut registers) = (Vec::new(), Vec::new(), Vec::new());
        for file in &predictions {
            let file = Path::new(file);
            let prediction = load_prediction(file, format, sequence.as_deref())?;
            let index = match placements
                .iter()
                .position(|(s, _)| *s == prediction.sequence)
            {
                Some(index) => index,
                None => {
                    let mut placed =
                        place_prediction(path, &original, &prediction, file, mode, &definition)?;
                    warnings.extend(placed.warning.take());
                    if let Some(register) = &placed.register {
                        registers.push((file.display().to_string(), register.text.clone()));
                    }
                    placements.push((prediction.sequence.clone(), placed));
                    placements.len() - 1
                }
            };
            reports.push(score_prediction(
                file,
                &prediction,
                &placements[index].1,
                &plan,
            )?);
        }
        Ok((reports, warnings, registers))
    })?;
    let rows: Vec<Row<'_>> = reports
        .iter()
        .flat_map(|report| {
            report
                .scores
                .iter()
                .flat_map(move |(named, labels, score)| {
                    labels
                        .iter()
                        .zip(&score.lists)
                        .map(move |(label, list)| Row {
                            report,
                            named,
                            label,
                            score,
                            list,
                        })
                })
        })
        .collect();
    let text = |f: fn(&Row<'_>) -> String| -> PyResult<Bound<'py, PyAny>> {
        Ok(rows
            .iter()
            .map(f)
            .collect::<Vec<String>>()
            .into_pyobject(py)?
            .into_any())
    };
    let ints = |f: fn(&Row<'_>) -> i64| vec1(py, rows.iter().map(f).collect()).into_any();
    let reals = |f: fn(&Row<'_>) -> f64| vec1(py, rows.iter().map(f).collect()).into_any();
    let columns = vec![
        ("prediction".to_string(), text(|r| r.report.path.clone())?),
        ("range".to_string(), text(|r| r.named.name.clone())?),
        ("min_sep".to_string(), ints(|r| r.named.range.min as i64)),
        (
            "max_sep".to_string(),
            reals(|r| r.named.range.max.map_or(f64::INFINITY, f64::from)),
        ),
        ("list".to_string(), text(|r| r.label.clone())?),
        ("k".to_string(), ints(|r| r.list.k as i64)),
        ("n_scored".to_string(), ints(|r| r.list.n_scored as i64)),
        ("tp".to_string(), ints(|r| r.list.true_positives as i64)),
        ("precision".to_string(), reals(|r| r.list.precision)),
        ("recall".to_string(), reals(|r| r.list.recall)),
        ("f1".to_string(), reals(|r| r.list.f1)),
        ("mcc".to_string(), reals(|r| r.list.mcc)),
        ("xd".to_string(), reals(|r| r.list.xd)),
        ("length".to_string(), ints(|r| r.score.length as i64)),
        ("n_true".to_string(), ints(|r| r.score.n_true as i64)),
        (
            "n_available".to_string(),
            ints(|r| r.score.n_available as i64),
        ),
    ];
    Ok((columns, warnings, registers))
}

/// The residue pairs of `contactmap contacts --trajectory` and their frames in contact: the
/// chain id, the residues' author numbers (with insertion codes) and names, their indices in
/// the topology, the frames in contact, and the frames measured.
type FrequencyColumns<'py> = (
    Vec<String>,
    Vec<String>,
    Vec<String>,
    Vec<String>,
    Vec<String>,
    Bound<'py, PyArray1<u64>>,
    Bound<'py, PyArray1<u64>>,
    Bound<'py, PyArray1<u32>>,
    usize,
);

/// `contactmap contacts --trajectory`: the residue contact frequencies of MD trajectories
/// (DCD, XTC, multi-model PDB / mmCIF) with the atoms of `topology`, as MDTraj's
/// `compute_contacts` measures the `definition` (cb, ca, closest, closest-heavy, sidechain,
/// sidechain-heavy), contacts `d < cutoff` Angstrom.
#[allow(clippy::too_many_arguments)]
#[pyfunction]
#[pyo3(signature = (trajectories, topology, definition="cb", cutoff=8.0, stride=1, periodic=true, min_sep=3))]
pub(crate) fn contact_frequencies<'py>(
    py: Python<'py>,
    trajectories: Vec<String>,
    topology: &str,
    definition: &str,
    cutoff: f64,
    stride: usize,
    periodic: bool,
    min_sep: usize,
) -> PyResult<FrequencyColumns<'py>> {
    use contactmap::io::topology::read_topology;
    use contactmap::score::frequency::{
        chain_column, contact_frequencies_of, FrequencySpec, Scheme,
    };
    let schemes = [
        Scheme::Cb,
        Scheme::Ca,
        Scheme::Closest,
        Scheme::ClosestHeavy,
        Scheme::Sidechain,
        Scheme::SidechainHeavy,
    ];
    let Some(scheme) = schemes
        .into_iter()
        .find(|s| s.name() == definition.to_ascii_lowercase())
    else {
        let names: Vec<&str> = schemes.iter().map(|s| s.name()).collect();
        return Err(ContactmapError::new_err(format!(
            "definition '{definition}': expected one of {}",
            names.join(", ")
        )));
    };
    let spec = FrequencySpec {
        scheme,
        cutoff_angstrom: cutoff,
        min_separation: min_sep,
        periodic,
        stride,
    };
    let (topology, frequencies) = run(py, || {
        let topology = read_topology(topology)?;
        let frequencies = contact_frequencies_of(&topology, &trajectories, &spec, |_| {})?;
        Ok((topology, frequencies))
    })?;
    let number = |r: usize| topology.residues[r].label();
    let pairs = &frequencies.pairs.pairs;
    let text = |f: &dyn Fn(usize, usize) -> String| pairs.iter().map(|&(i, j)| f(i, j)).collect();
    Ok((
        text(&|i, _| chain_column(&topology, topology.residues[i].chain).to_string()),
        text(&|i, _| number(i)),
        text(&|_, j| number(j)),
        text(&|i, _| topology.residues[i].name.clone()),
        text(&|_, j| topology.residues[j].name.clone()),
        vec1(py, pairs.iter().map(|&(i, _)| i as u64).collect()),
        vec1(py, pairs.iter().map(|&(_, j)| j as u64).collect()),
        vec1(py, frequencies.counts.clone()),
        frequencies.frames,
    ))
}
