//! Finding the coolers of an HDF5 file and running every check on each.

use super::check::CoolerCheck;
use super::coarsening::check_coarsening;
use crate::error::{Error, Result};
use crate::io::cool::chunks;
use crate::io::hdf5_guard::guarded;
use crate::validate::hic::validate_hicexplorer;
use crate::validate::report::{Collector, Report};
use std::path::Path;

/// Cooler groups of a file: (group path, resolution from the group name if any).
pub(in crate::validate) type CoolerGroups = Vec<(String, Option<u64>)>;

/// The format name and the coolers of an HDF5 file.
pub(crate) fn cooler_groups(
    path: &str,
    file: &hdf5::File,
    group: Option<&str>,
) -> Result<(String, CoolerGroups)> {
    let hdf5_err = |what: &str| {
        let what = what.to_string();
        move |e| Error::hdf5(path, what, e)
    };
    if let Some(g) = group.filter(|g| !g.trim_matches('/').is_empty()) {
        let trimmed = g.trim_matches('/');
        if !file.link_exists(trimmed) || file.group(trimmed).is_err() {
            return Err(Error::format(path, format!("no group '{g}' in this file")));
        }
        let resolution = trimmed
            .strip_prefix("resolutions/")
            .and_then(|r| r.parse().ok());
        return Ok(("cool".into(), vec![(format!("/{trimmed}"), resolution)]));
    }
    if file.link_exists("resolutions") {
        let resolutions = file
            .group("resolutions")
            .map_err(hdf5_err("opening /resolutions"))?;
        let names = resolutions
            .member_names()
            .map_err(hdf5_err("listing /resolutions"))?;
        let mut levels: Vec<u64> = names.iter().filter_map(|n| n.parse().ok()).collect();
        levels.sort_unstable();
        if levels.is_empty() {
            return Err(Error::format(
                path,
                "/resolutions holds no numeric resolution group: not a usable .mcool",
            ));
        }
        let groups = levels
            .into_iter()
            .map(|r| (format!("/resolutions/{r}"), Some(r)))
            .collect();
        return Ok(("mcool".into(), groups));
    }
    let looks_like_cooler = ["chroms", "bins", "pixels", "indexes"]
        .iter()
        .any(|name| file.link_exists(name));
    if looks_like_cooler {
        return Ok(("cool".into(), vec![("/".into(), None)]));
    }
    let names = file.member_names().map_err(hdf5_err("listing the root"))?;
    let mut numeric: Vec<u64> = names.iter().filter_map(|n| n.parse().ok()).collect();
    numeric.sort_unstable();
    if !numeric.is_empty() && numeric[0] == 0 {
        let groups = numeric
            .into_iter()
            .map(|k| (format!("/{k}"), None))
            .collect();
        return Ok(("mcool (legacy numeric layout)".into(), groups));
    }
    Err(Error::format(
        path,
        "this HDF5 file is neither a cooler nor a multi-resolution .mcool (no chroms/bins/pixels/indexes, no /resolutions, no HiCExplorer matrix/ and intervals/)",
    ))
}

pub(crate) fn open_hdf5(path: &str) -> Result<hdf5::File> {
    guarded(path, "the file's superblock and root group", || {
        let mut builder = hdf5::File::with_options();
        builder.fapl().file_locking(false);
        builder.open(path)
    })
    .map_err(|e| {
        Error::format(
            path,
            format!("not a readable HDF5 file (truncated or corrupt?): {e}"),
        )
    })
}

pub(crate) fn validate_hdf5(path: &str, group: Option<&str>) -> Result<Report> {
    if group.is_none() && crate::io::hicexplorer::is_hicexplorer(path)? {
        return validate_hicexplorer(path);
    }
    let file = open_hdf5(path)?;
    let raw = chunks::open_raw(Path::new(path))?;
    let (format, groups) = cooler_groups(path, &file, group)?;
    let mut collector = Collector::default();
    let mut checked = Vec::new();
    let mut coolers = Vec::new();
    for (name, resolution) in &groups {
        let cooler_group = file
            .group(name.trim_start_matches('/'))
            .or_else(|_| file.as_group())
            .map_err(|e| Error::hdf5(path, format!("opening group {name}"), e))?;
        checked.push(name.clone());
        let checker = CoolerCheck {
            path,
            name,
            group: &cooler_group,
            raw: &raw,
        };
        if let Some(mut cooler) = checker.run(&mut collector)? {
            cooler.resolution = resolution.or(cooler.bins.as_ref().and_then(|b| b.resolution()));
            coolers.push(cooler);
        }
    }
    if groups.len() > 1 {
        check_coarsening(&raw, &coolers, &mut collector)?;
    }
    Ok(collector.into_report(path, format, checked))
}
