//! `--repair`: a corrected copy of a cooler written through the library writer.

use super::cooler::{CoolerCheck, Kind, cooler_groups, kind_of, open_hdf5, read_attr};
use super::report::{Class, Collector, Report, Severity};
use crate::error::{Error, Result};
use crate::io::cool::{self, BLOCK_PIXELS, CoolWriteOptions, DIVISIVE_BY_NAME, chunks};
use crate::io::{self, FileKind, InMemory};
use crate::matrix::{CountType, MatrixBuilder, Weights};
use std::fs::File;
use std::path::Path;

/// The result of [`repair`].
#[derive(Clone, Debug, PartialEq)]
pub enum RepairOutcome {
    /// A corrected copy was written; what was done.
    Written(Vec<String>),
    /// Nothing was written: the defects that cannot be repaired.
    Refused(Vec<String>),
}

/// Write a corrected copy of the cooler at `uri` (checked first with [`validate`](super::validate), giving
/// `report`) to `out`. `out` must not be the input (same path or same file through a link).
///
/// The base resolution (the only cooler of a `.cool`, the finest level of an `.mcool`) is read
/// in full into memory, its pixels transposed to the upper triangle, sorted and summed; the
/// output is a `.cool`, or an `.mcool` whose every level is regenerated from the base (coarser
/// levels carry no weight columns then, as with `cooler zoomify`: rebalance them).
pub fn repair(uri: &str, report: &Report, out: &Path) -> Result<RepairOutcome> {
    let (path, group) = io::split_uri(uri);
    if io::same_file(Path::new(path), out) {
        return Err(Error::Argument(format!(
            "--repair {}: the output is the input file; write the corrected copy elsewhere",
            out.display()
        )));
    }
    if io::detect_kind(path)? != FileKind::Hdf5 || report.format.starts_with("hicexplorer") {
        return Ok(RepairOutcome::Refused(vec![
            "only .cool / .mcool files can be repaired".into(),
        ]));
    }
    let refused: Vec<String> = report
        .findings
        .iter()
        .filter(|f| f.class.severity() == Severity::Error && !f.class.is_repairable())
        .map(|f| {
            format!(
                "{} {} {}: {} (cannot be repaired)",
                f.class.name(),
                f.group,
                f.location,
                f.message
            )
        })
        .collect();
    if !refused.is_empty() {
        return Ok(RepairOutcome::Refused(refused));
    }
    let file = open_hdf5(path)?;
    let (_, groups) = cooler_groups(path, &file, group)?;
    let raw = chunks::open_raw(Path::new(path))?;
    let (base_name, _) = &groups[0];
    let base_group = file
        .group(base_name.trim_start_matches('/'))
        .or_else(|_| file.as_group())
        .map_err(|e| Error::hdf5(path, format!("opening group {base_name}"), e))?;
    let mut actions = Vec::new();
    let (matrix, assembly) = load_base(path, base_name, &base_group, &raw, &mut actions)?;
    let options = CoolWriteOptions {
        assembly,
        weight_columns: None,
    };
    if groups.len() == 1 {
        cool::write_cool(&matrix, out, &options)?;
    } else {
        let mut resolutions = Vec::new();
        for (name, resolution) in &groups {
            let resolution = match resolution {
                Some(r) => *r,
                None => {
                    let g = file
                        .group(name.trim_start_matches('/'))
                        .map_err(|e| Error::hdf5(path, format!("opening group {name}"), e))?;
                    read_attr(path, &g, "bin-size")
                        .and_then(|a| a.as_i64())
                        .filter(|&s| s > 0)
                        .ok_or_else(|| {
                            Error::format(
                                path,
                                format!("{name}: no bin-size attribute: its resolution is unknown"),
                            )
                        })? as u64
                }
            };
            resolutions.push(resolution);
        }
        cool::write_mcool(&matrix, out, &resolutions, &options)?;
        actions.push(format!(
            "zoom levels {} regenerated from the base resolution {base_name} (coarser levels carry no weight columns: rebalance them)",
            resolutions[1..]
                .iter()
                .map(|r| r.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    let classes: std::collections::BTreeSet<Class> =
        report.findings.iter().map(|f| f.class).collect();
    if classes.iter().any(|c| {
        matches!(
            c,
            Class::ChromOffset | Class::Bin1Offset | Class::LegacyIndex
        )
    }) {
        actions.push("indexes/chrom_offset and indexes/bin1_offset rebuilt".into());
    }
    if classes.contains(&Class::Attribute) {
        actions.push("attributes recomputed from the data".into());
    }
    Ok(RepairOutcome::Written(actions))
}

/// Read the base cooler in full: bins, pixels (upper triangle, sorted, summed), weights.
pub(super) fn load_base(
    path: &str,
    name: &str,
    group: &hdf5::Group,
    raw: &File,
    actions: &mut Vec<String>,
) -> Result<(InMemory, Option<String>)> {
    let checker = CoolerCheck {
        path,
        name,
        group,
        raw,
    };
    let mut scratch = Collector::default();
    let chroms = checker.check_chroms(&mut scratch)?;
    let columns = checker.check_bin_columns(&mut scratch)?;
    let bins = match (&chroms, &columns) {
        (Some(chroms), Some(columns)) => checker.check_bin_table(&mut scratch, chroms, columns),
        _ => None,
    };
    let bins =
        bins.ok_or_else(|| Error::format(path, format!("{name}: the bin table is not usable")))?;
    let pixels = checker
        .open_pixels(&mut scratch)
        .ok_or_else(|| Error::format(path, format!("{name}: the pixel table is not usable")))?;
    let count_type = if pixels.count.is_float() {
        CountType::Float
    } else {
        CountType::Integer
    };
    let mut builder = MatrixBuilder::new(bins.clone(), count_type);
    let nnz = pixels.len();
    let (mut n_lower, mut last, mut n_unsorted, mut n_duplicates) = (0u64, None, 0u64, 0u64);
    let mut n_zero = 0u64;
    let mut lo = 0;
    while lo < nnz {
        let hi = (lo + BLOCK_PIXELS).min(nnz);
        let (bin1, bin2, count) = pixels.read(raw, lo, hi)?;
        for k in 0..bin1.len() {
            let (i, j, c) = (bin1[k], bin2[k], count[k]);
            if i < 0 || j < 0 || !c.is_finite() || c < 0.0 {
                return Err(Error::format(
                    path,
                    format!(
                        "{name}: pixel row {}: ({i}, {j}, {c}) cannot be repaired",
                        lo + k
                    ),
                ));
            }
            let key = (i.min(j), i.max(j));
            n_lower += u64::from(i > j);
            n_zero += u64::from(c == 0.0);
            match last {
                Some(previous) if key < previous => n_unsorted += 1,
                Some(previous) if key == previous => n_duplicates += 1,
                _ => {}
            }
            last = Some(key);
            builder
                .push(i as u64, j as u64, c)
                .map_err(|e| e.in_file(Path::new(path)))?;
        }
        lo = hi;
    }
    if n_lower > 0 {
        actions.push(format!(
            "{n_lower} lower-triangle pixels transposed to the upper triangle"
        ));
    }
    if n_unsorted > 0 {
        actions.push(format!(
            "pixels resorted by (bin1_id, bin2_id) ({n_unsorted} were out of order)"
        ));
    }
    if n_duplicates > 0 {
        actions.push(format!(
            "{n_duplicates} duplicate pixels summed into the first of each (bin1_id, bin2_id)"
        ));
    }
    if n_zero > 0 {
        actions.push(format!("{n_zero} stored zero counts dropped"));
    }
    let hic2cool = read_attr(path, group, "generated-by")
        .and_then(|a| a.as_str().map(|s| s.starts_with("hic2cool")))
        .unwrap_or(false);
    if let Ok(bins_group) = group.group("bins") {
        let mut names = bins_group
            .member_names()
            .map_err(|e| Error::hdf5(path, "listing bins", e))?;
        names.sort();
        for column in names {
            if ["chrom", "start", "end"].contains(&column.as_str()) {
                continue;
            }
            let Ok(dataset) = bins_group.dataset(&column) else {
                continue;
            };
            if kind_of(&dataset) != Kind::Float {
                continue;
            }
            let values = dataset
                .read_raw::<f64>()
                .map_err(|e| Error::hdf5(path, format!("reading bins/{column}"), e))?;
            let stored = read_attr(path, &dataset, "divisive_weights").and_then(|a| a.as_i64());
            let divisive = match stored {
                Some(v) => v != 0,
                None => {
                    DIVISIVE_BY_NAME.contains(&column.as_str()) || (hic2cool && column == "SCALE")
                }
            };
            let weights = if divisive {
                Weights::from_divisive(column.as_str(), &values, String::new())
            } else {
                Weights {
                    name: column.clone(),
                    values,
                    provenance: None,
                }
            };
            builder
                .add_weights(weights)
                .map_err(|e| e.in_file(Path::new(path)))?;
        }
    }
    let assembly = read_attr(path, group, "genome-assembly")
        .or_else(|| read_attr(path, group, "assembly"))
        .and_then(|a| a.as_str().map(String::from));
    Ok((
        InMemory::new(format!("{path}::{name}"), builder.build()),
        assembly,
    ))
}
