//! Checks of `.cool` / `.mcool` files on the stored HDF5 data.

use super::*;

/// Cooler groups of a file: (group path, resolution from the group name if any).
pub(super) type CoolerGroups = Vec<(String, Option<u64>)>;

/// The columns `bins/chrom`, `bins/start`, `bins/end` as stored.
pub(super) type BinColumns = (Vec<i64>, Vec<i64>, Vec<i64>);

/// The format name and the coolers of an HDF5 file.
pub(super) fn cooler_groups(
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

pub(super) fn open_hdf5(path: &str) -> Result<hdf5::File> {
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

pub(super) fn validate_hdf5(path: &str, group: Option<&str>) -> Result<Report> {
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
            cooler.resolution = resolution.or(cooler.bins.as_ref().and_then(|b| b.bin_size_bp()));
            coolers.push(cooler);
        }
    }
    if groups.len() > 1 {
        check_coarsening(&raw, &coolers, &mut collector)?;
    }
    Ok(collector.into_report(path, format, checked))
}

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

impl CoolerCheck<'_> {
    fn add(&self, out: &mut Collector, class: Class, location: &str, message: String) {
        out.add(self.name, class, || (location.to_string(), message));
    }

    /// Open `name` and check that its type is `expected` (one of); report and return `None`
    /// when it is missing or of another type.
    fn dataset(&self, out: &mut Collector, name: &str, expected: &[Kind]) -> Option<hdf5::Dataset> {
        if !self.group.link_exists(name) {
            self.add(
                out,
                Class::Schema,
                name,
                format!("missing dataset {name} (cooler schema)"),
            );
            return None;
        }
        let Ok(dataset) = self.group.dataset(name) else {
            self.add(out, Class::Schema, name, format!("{name} is not a dataset"));
            return None;
        };
        let kind = kind_of(&dataset);
        if !expected.contains(&kind) || dataset.ndim() != 1 {
            self.add(
                out,
                Class::Schema,
                name,
                format!(
                    "{name} has type {:?} and shape {:?}; expected a 1-D column of {}",
                    dataset.dtype().and_then(|t| t.to_descriptor()).ok(),
                    dataset.shape(),
                    expected
                        .iter()
                        .map(|k| format!("{k:?}").to_lowercase())
                        .collect::<Vec<_>>()
                        .join(" or ")
                ),
            );
            return None;
        }
        Some(dataset)
    }

    fn ints(&self, out: &mut Collector, name: &str) -> Result<Option<Vec<i64>>> {
        let Some(dataset) = self.dataset(out, name, &[Kind::Integer]) else {
            return Ok(None);
        };
        let full_name = format!("{}{name}", self.prefix());
        crate::io::hdf5_guard::checked_len(
            self.path,
            &dataset,
            &full_name,
            crate::io::cool::file_len(self.path),
        )?;
        dataset
            .read_raw::<i64>()
            .map(Some)
            .map_err(|e| Error::hdf5(self.path, format!("reading {}{name}", self.prefix()), e))
    }

    fn prefix(&self) -> String {
        if self.name == "/" {
            String::new()
        } else {
            format!("{}/", self.name.trim_start_matches('/'))
        }
    }

    fn attr(&self, name: &str) -> Option<Attr> {
        read_attr(self.path, self.group, name)
    }

    /// Run every check of the group; `None` when the group is too broken to be used further.
    fn run(&self, out: &mut Collector) -> Result<Option<CheckedCooler>> {
        for needed in ["chroms", "bins", "pixels", "indexes"] {
            if !self.group.link_exists(needed) || self.group.group(needed).is_err() {
                self.add(
                    out,
                    Class::Schema,
                    needed,
                    format!("missing group {needed} (cooler schema)"),
                );
            }
        }
        let chroms = self.check_chroms(out)?;
        let bin_columns = self.check_bin_columns(out)?;
        let bins = match (&chroms, &bin_columns) {
            (Some(chroms), Some(columns)) => self.check_bin_table(out, chroms, columns),
            _ => None,
        };
        let n_bins = bin_columns.as_ref().map(|c| c.0.len());
        if let (Some(chroms), Some(columns)) = (&chroms, &bin_columns) {
            self.check_chrom_offset(out, chroms.len(), &columns.0)?;
        }
        let pixels = self.open_pixels(out);
        let nnz = pixels.as_ref().map(|p| p.len());
        let bin1_offsets = match (n_bins, nnz) {
            (Some(n), Some(nnz)) => self.check_bin1_offset(out, n, nnz)?,
            _ => None,
        };
        let storage_mode = self.attr("storage-mode");
        let symmetric_upper = match storage_mode.as_ref().and_then(|a| a.as_str()) {
            None | Some("symmetric-upper") => true,
            Some("square") => false,
            Some(other) => {
                self.add(
                    out,
                    Class::Attribute,
                    "storage-mode",
                    format!("storage-mode '{other}'; expected symmetric-upper or square"),
                );
                true
            }
        };
        let mut pixels_clean = false;
        let mut sum = None;
        if let (Some(pixels), Some(n_bins)) = (&pixels, n_bins) {
            let summary = self.check_pixels(
                out,
                pixels,
                n_bins,
                bin1_offsets.as_deref(),
                symmetric_upper,
            )?;
            sum = Some(summary.sum);
            pixels_clean = summary.clean;
        }
        // The sum attribute is not compared with invalid counts (already reported).
        let sum = sum.filter(|_| out.count(self.name, Class::Count) == 0);
        self.check_attributes(
            out,
            chroms.as_ref().map(|c| c.len()),
            n_bins,
            nnz,
            &bins,
            sum,
        );
        if let Some(n_bins) = n_bins {
            self.check_weights(out, n_bins)?;
        }
        Ok(Some(CheckedCooler {
            name: self.name.to_string(),
            resolution: None,
            bins,
            pixels_clean,
            pixels,
        }))
    }

    pub(super) fn check_chroms(&self, out: &mut Collector) -> Result<Option<Vec<Chrom>>> {
        let names = match self.dataset(out, "chroms/name", &[Kind::Text]) {
            Some(d) => Some(read_strings(
                self.path,
                &d,
                &format!("{}chroms/name", self.prefix()),
            )?),
            None => None,
        };
        let lengths = self.ints(out, "chroms/length")?;
        let (Some(names), Some(lengths)) = (names, lengths) else {
            return Ok(None);
        };
        if names.len() != lengths.len() {
            self.add(
                out,
                Class::Schema,
                "chroms",
                format!(
                    "chroms/name has {} entries and chroms/length {}",
                    names.len(),
                    lengths.len()
                ),
            );
            return Ok(None);
        }
        let mut ok = true;
        let mut seen = std::collections::HashMap::new();
        for (k, (name, &length)) in names.iter().zip(&lengths).enumerate() {
            if name.is_empty() {
                ok = false;
                self.add(
                    out,
                    Class::Chroms,
                    &format!("chroms/name[{k}]"),
                    "empty chromosome name".into(),
                );
            } else if let Some(first) = seen.insert(name.as_str(), k) {
                ok = false;
                self.add(
                    out,
                    Class::Chroms,
                    &format!("chroms/name[{k}]"),
                    format!("chromosome '{name}' appears twice (rows {first} and {k})"),
                );
            }
            if length <= 0 {
                ok = false;
                self.add(
                    out,
                    Class::Chroms,
                    &format!("chroms/length[{k}] ({name})"),
                    format!("chromosome length {length}; expected > 0"),
                );
            }
        }
        Ok(ok.then(|| {
            names
                .into_iter()
                .zip(lengths)
                .map(|(n, l)| Chrom::new(n, l as u64))
                .collect()
        }))
    }

    /// bins/chrom, bins/start, bins/end, of equal length.
    pub(super) fn check_bin_columns(&self, out: &mut Collector) -> Result<Option<BinColumns>> {
        let chrom = self.ints(out, "bins/chrom")?;
        let start = self.ints(out, "bins/start")?;
        let end = self.ints(out, "bins/end")?;
        let (Some(chrom), Some(start), Some(end)) = (chrom, start, end) else {
            return Ok(None);
        };
        if chrom.len() != start.len() || start.len() != end.len() {
            self.add(
                out,
                Class::Schema,
                "bins",
                format!(
                    "bins/chrom, bins/start and bins/end have {}, {} and {} rows",
                    chrom.len(),
                    start.len(),
                    end.len()
                ),
            );
            return Ok(None);
        }
        Ok(Some((chrom, start, end)))
    }

    /// Bins tile each chromosome in order; fixed-size bins agree with `bin-size`.
    pub(super) fn check_bin_table(
        &self,
        out: &mut Collector,
        chroms: &[Chrom],
        (chrom_ids, starts, ends): &BinColumns,
    ) -> Option<BinTable> {
        let errors_before = out.count(self.name, Class::BinTable);
        let mut bins = Vec::with_capacity(starts.len());
        // Next chromosome expected and the end of the previous bin.
        let mut current: Option<usize> = None;
        let mut previous_end = 0i64;
        let close = |out: &mut Collector, chrom: usize, previous_end: i64, row: usize| {
            let length = chroms[chrom].length_bp as i64;
            if previous_end != length {
                self.add(
                    out,
                    Class::BinTable,
                    &format!("bins row {row} ({})", chroms[chrom].name),
                    format!(
                        "the last bin of {} ends at {previous_end}; the chromosome is {length} bp long",
                        chroms[chrom].name
                    ),
                );
            }
        };
        for k in 0..starts.len() {
            let (c, s, e) = (chrom_ids[k], starts[k], ends[k]);
            if c < 0 || c as usize >= chroms.len() {
                self.add(
                    out,
                    Class::BinTable,
                    &format!("bins/chrom[{k}]"),
                    format!(
                        "chromosome id {c} is out of range ({} chromosomes)",
                        chroms.len()
                    ),
                );
                continue;
            }
            let c = c as usize;
            let name = &chroms[c].name;
            if current != Some(c) {
                let expected = current.map_or(0, |p| p + 1);
                if let Some(p) = current {
                    close(out, p, previous_end, k.saturating_sub(1));
                }
                if c != expected {
                    self.add(
                        out,
                        Class::BinTable,
                        &format!("bins/chrom[{k}] ({name})"),
                        format!(
                            "bins of chromosome {c} ({name}) follow chromosome {}; expected chromosome {expected} ({}): bins must be in chromosome order with every chromosome present",
                            current.map_or("none".into(), |p| p.to_string()),
                            chroms.get(expected).map_or("none", |x| x.name.as_str())
                        ),
                    );
                }
                current = Some(c);
                previous_end = 0;
                if s > 0 && e > s {
                    // A matrix cut out of the chromosome: cooler and contactmap read it.
                    self.add(
                        out,
                        Class::CutBins,
                        &format!("bins row {k} ({name})"),
                        format!(
                            "the bins of {name} start at {s}, not 0: a matrix cut out of the chromosome (cooler reads it)"
                        ),
                    );
                    previous_end = s;
                }
            }
            if s != previous_end || e <= s || e > chroms[c].length_bp as i64 {
                self.add(
                    out,
                    Class::BinTable,
                    &format!("bins row {k} ({name})"),
                    format!(
                        "bin {name}:{s}-{e} does not follow the previous bin (which ends at {previous_end}), is empty or ends past the chromosome ({} bp)",
                        chroms[c].length_bp
                    ),
                );
            }
            previous_end = e;
            bins.push(Bin {
                chrom_id: c,
                start: s.max(0) as u64,
                end: e.max(0) as u64,
            });
        }
        match current {
            Some(p) => {
                close(out, p, previous_end, starts.len().saturating_sub(1));
                if p + 1 != chroms.len() {
                    self.add(
                        out,
                        Class::BinTable,
                        "bins",
                        format!(
                            "the bins end with chromosome {} ({}); chromosomes after it have no bins",
                            p, chroms[p].name
                        ),
                    );
                }
            }
            None if !chroms.is_empty() => self.add(
                out,
                Class::BinTable,
                "bins",
                "the bin table is empty".into(),
            ),
            None => {}
        }
        if out.count(self.name, Class::BinTable) > errors_before {
            return None;
        }
        let bin_type = self.attr("bin-type");
        let bin_size = self.attr("bin-size").and_then(|a| a.as_i64());
        if bin_type.as_ref().and_then(|a| a.as_str()) == Some("fixed") {
            match bin_size {
                Some(size) if size > 0 => {
                    for (k, bin) in bins.iter().enumerate() {
                        let width = (bin.end - bin.start) as i64;
                        let last = bin.end == chroms[bin.chrom_id].length_bp;
                        if width != size && !(last && width < size) {
                            self.add(
                                out,
                                Class::BinTable,
                                &format!("bins row {k} ({})", chroms[bin.chrom_id].name),
                                format!(
                                    "bin {}:{}-{} is {width} bp; bin-type fixed with bin-size {size}",
                                    chroms[bin.chrom_id].name, bin.start, bin.end
                                ),
                            );
                        }
                    }
                }
                other => self.add(
                    out,
                    Class::Attribute,
                    "bin-size",
                    format!(
                        "bin-type is fixed but bin-size is {}",
                        other.map_or("missing".into(), |v| v.to_string())
                    ),
                ),
            }
        }
        if out.count(self.name, Class::BinTable) > errors_before {
            return None;
        }
        let hint = bin_size.filter(|&s| s > 0).map(|s| s as u64);
        BinTable::from_bins(chroms.to_vec(), &bins, hint).ok()
    }

    fn check_chrom_offset(
        &self,
        out: &mut Collector,
        n_chroms: usize,
        chrom_ids: &[i64],
    ) -> Result<()> {
        let Some(offsets) = self.ints(out, "indexes/chrom_offset")? else {
            return Ok(());
        };
        if offsets.len() != n_chroms + 1 {
            self.add(
                out,
                Class::ChromOffset,
                "indexes/chrom_offset",
                format!(
                    "{} entries; expected {} (number of chromosomes + 1)",
                    offsets.len(),
                    n_chroms + 1
                ),
            );
            return Ok(());
        }
        for (c, &offset) in offsets.iter().enumerate() {
            // First bin of chromosome c: the number of bins of the chromosomes before it.
            let expected = chrom_ids.partition_point(|&id| id < c as i64) as i64;
            if offset != expected {
                self.add(
                    out,
                    Class::ChromOffset,
                    &format!("indexes/chrom_offset[{c}]"),
                    format!("{offset}; the bin table's chromosome {c} starts at bin {expected}"),
                );
            }
        }
        Ok(())
    }

    /// Check `indexes/bin1_offset` alone (length, monotone, ends); return it (with `nnz` appended
    /// to a legacy `nbins`-entry index) when it can be used to locate the pixels' rows.
    fn check_bin1_offset(
        &self,
        out: &mut Collector,
        n_bins: usize,
        nnz: usize,
    ) -> Result<Option<Vec<i64>>> {
        let Some(mut offsets) = self.ints(out, "indexes/bin1_offset")? else {
            return Ok(None);
        };
        if offsets.len() == n_bins && n_bins > 0 {
            self.add(
                out,
                Class::LegacyIndex,
                "indexes/bin1_offset",
                format!(
                    "{n_bins} entries, one per bin (hic2cool 0.3 - 0.4); the format says {} (number of bins + 1). cooler reads it; --repair writes the full index",
                    n_bins + 1
                ),
            );
            offsets.push(nnz as i64);
        } else if offsets.len() != n_bins + 1 {
            self.add(
                out,
                Class::Bin1Offset,
                "indexes/bin1_offset",
                format!(
                    "{} entries; expected {} (number of bins + 1)",
                    offsets.len(),
                    n_bins + 1
                ),
            );
            return Ok(None);
        }
        let mut usable = true;
        if offsets[0] != 0 {
            usable = false;
            self.add(
                out,
                Class::Bin1Offset,
                "indexes/bin1_offset[0]",
                format!("{}; expected 0", offsets[0]),
            );
        }
        if offsets[n_bins] != nnz as i64 {
            usable = false;
            self.add(
                out,
                Class::Bin1Offset,
                &format!("indexes/bin1_offset[{n_bins}]"),
                format!("{}; expected {nnz} (the number of pixels)", offsets[n_bins]),
            );
        }
        for k in 1..offsets.len() {
            if offsets[k] < offsets[k - 1] {
                usable = false;
                self.add(
                    out,
                    Class::Bin1Offset,
                    &format!("indexes/bin1_offset[{k}]"),
                    format!(
                        "{} is below the previous entry {}: the index must be non-decreasing",
                        offsets[k],
                        offsets[k - 1]
                    ),
                );
            }
        }
        Ok(usable.then_some(offsets))
    }

    pub(super) fn open_pixels(&self, out: &mut Collector) -> Option<PixelColumns> {
        let bin1 = self.dataset(out, "pixels/bin1_id", &[Kind::Integer]);
        let bin2 = self.dataset(out, "pixels/bin2_id", &[Kind::Integer]);
        let count = self.dataset(out, "pixels/count", &[Kind::Integer, Kind::Float]);
        let (Some(_), Some(_), Some(_)) = (bin1, bin2, count) else {
            return None;
        };
        let open = |name: &str| Column::open(self.group, name, self.path);
        let columns = match (
            open("pixels/bin1_id"),
            open("pixels/bin2_id"),
            open("pixels/count"),
        ) {
            (Ok(bin1), Ok(bin2), Ok(count)) => PixelColumns { bin1, bin2, count },
            (a, b, c) => {
                let message = [a.err(), b.err(), c.err()]
                    .into_iter()
                    .flatten()
                    .map(|e| e.to_string())
                    .collect::<Vec<_>>()
                    .join("; ");
                self.add(out, Class::Schema, "pixels", message);
                return None;
            }
        };
        if columns.bin1.len() != columns.len() || columns.bin2.len() != columns.len() {
            self.add(
                out,
                Class::Schema,
                "pixels",
                format!(
                    "pixels/bin1_id, pixels/bin2_id and pixels/count have {}, {} and {} rows",
                    columns.bin1.len(),
                    columns.bin2.len(),
                    columns.len()
                ),
            );
            return None;
        }
        Some(columns)
    }

    fn check_pixels(
        &self,
        out: &mut Collector,
        pixels: &PixelColumns,
        n_bins: usize,
        bin1_offsets: Option<&[i64]>,
        symmetric_upper: bool,
    ) -> Result<PixelSummary> {
        let nnz = pixels.len();
        let n = n_bins as i64;
        let mut summary = PixelSummary {
            sum: 0.0,
            clean: true,
        };
        let mut last: Option<(i64, i64)> = None;
        // Row of the pixel according to bin1_offset.
        let mut row = 0usize;
        let mut lo = 0;
        while lo < nnz {
            let hi = (lo + BLOCK_PIXELS).min(nnz);
            let (bin1, bin2, count) = pixels.read(self.raw, lo, hi)?;
            for k in 0..bin1.len() {
                let index = lo + k;
                let (i, j, c) = (bin1[k], bin2[k], count[k]);
                let at = || format!("pixels row {index}");
                if !c.is_finite() || c < 0.0 {
                    out.add(self.name, Class::Count, || {
                        (
                            at(),
                            format!("pixel ({i}, {j}) has count {c}; expected finite and >= 0"),
                        )
                    });
                } else {
                    summary.sum += c;
                }
                if i < 0 || j < 0 || i >= n || j >= n {
                    summary.clean = false;
                    out.add(self.name, Class::BinId, || {
                        (
                            at(),
                            format!("pixel ({i}, {j}) is out of range for {n_bins} bins"),
                        )
                    });
                    continue;
                }
                if symmetric_upper && i > j {
                    summary.clean = false;
                    out.add(self.name, Class::LowerTriangle, || {
                        (
                            at(),
                            format!(
                                "pixel ({i}, {j}) is below the diagonal in symmetric-upper storage"
                            ),
                        )
                    });
                }
                if let Some(previous) = last {
                    if (i, j) < previous {
                        summary.clean = false;
                        out.add(self.name, Class::Unsorted, || {
                            (at(), format!("pixel ({i}, {j}) follows ({}, {}): pixels must be sorted by (bin1_id, bin2_id)", previous.0, previous.1))
                        });
                    } else if (i, j) == previous {
                        summary.clean = false;
                        out.add(self.name, Class::Duplicate, || {
                            (
                                at(),
                                format!(
                                    "pixel ({i}, {j}) is stored twice (rows {} and {index})",
                                    index - 1
                                ),
                            )
                        });
                    }
                }
                last = Some((i, j));
                if let Some(offsets) = bin1_offsets {
                    while row < n_bins && offsets[row + 1] as usize <= index {
                        row += 1;
                    }
                    if i as usize != row {
                        out.add(self.name, Class::Bin1Offset, || {
                            (at(), format!("pixel ({i}, {j}) is in the rows of bin {row} according to indexes/bin1_offset"))
                        });
                    }
                }
            }
            lo = hi;
        }
        Ok(summary)
    }

    fn check_attributes(
        &self,
        out: &mut Collector,
        n_chroms: Option<usize>,
        n_bins: Option<usize>,
        nnz: Option<usize>,
        bins: &Option<BinTable>,
        sum: Option<f64>,
    ) {
        for (name, actual) in [("nchroms", n_chroms), ("nbins", n_bins), ("nnz", nnz)] {
            let (Some(actual), Some(stored)) = (actual, self.attr(name)) else {
                continue;
            };
            if stored.as_i64() != Some(actual as i64) {
                self.add(
                    out,
                    Class::Attribute,
                    name,
                    format!("attribute {name} is {stored:?}; the data has {actual}"),
                );
            }
        }
        if let (Some(bins), Some(stored)) = (bins, self.attr("bin-size")) {
            if let (Some(size), Some(stored_size)) = (bins.bin_size_bp(), stored.as_i64()) {
                if size as i64 != stored_size {
                    self.add(
                        out,
                        Class::Attribute,
                        "bin-size",
                        format!("attribute bin-size is {stored_size}; the bins are {size} bp"),
                    );
                }
            }
        }
        if let Some(version) = self.attr("format-version") {
            if !matches!(version.as_i64(), Some(1..=3)) {
                self.add(
                    out,
                    Class::Attribute,
                    "format-version",
                    format!("format-version {version:?}; expected 1, 2 or 3"),
                );
            }
        }
        if let (Some(sum), Some(stored)) = (sum, self.attr("sum").and_then(|a| a.as_f64())) {
            if (sum - stored).abs() > FLOAT_TOLERANCE * sum.abs().max(1.0) {
                self.add(
                    out,
                    Class::Attribute,
                    "sum",
                    format!("attribute sum is {stored}; the counts sum to {sum}"),
                );
            }
        }
    }

    fn check_weights(&self, out: &mut Collector, n_bins: usize) -> Result<()> {
        let Ok(bins) = self.group.group("bins") else {
            return Ok(());
        };
        let names = bins
            .member_names()
            .map_err(|e| Error::hdf5(self.path, format!("listing {}bins", self.prefix()), e))?;
        let hic2cool = self
            .attr("generated-by")
            .and_then(|a| a.as_str().map(|s| s.starts_with("hic2cool")))
            .unwrap_or(false);
        for name in names {
            if ["chrom", "start", "end"].contains(&name.as_str()) {
                continue;
            }
            let Ok(dataset) = bins.dataset(&name) else {
                continue;
            };
            if kind_of(&dataset) != Kind::Float {
                continue;
            }
            let location = format!("bins/{name}");
            let values = dataset
                .read_raw::<f64>()
                .map_err(|e| Error::hdf5(self.path, format!("reading {location}"), e))?;
            if values.len() != n_bins {
                self.add(
                    out,
                    Class::Weight,
                    &location,
                    format!("{} values for {n_bins} bins", values.len()),
                );
                continue;
            }
            let stored =
                read_attr(self.path, &dataset, "divisive_weights").and_then(|a| a.as_i64());
            let divisive = match stored {
                Some(v) => v != 0,
                None => DIVISIVE_BY_NAME.contains(&name.as_str()) || (hic2cool && name == "SCALE"),
            };
            for (k, &w) in values.iter().enumerate() {
                let bad = w.is_infinite() || w < 0.0 || (w == 0.0 && !divisive);
                if bad {
                    out.add(self.name, Class::Weight, || {
                        (
                            format!("{location}[{k}]"),
                            format!("weight {w}; expected finite and > 0, or NaN for a masked bin"),
                        )
                    });
                }
            }
        }
        Ok(())
    }
}

pub(super) struct PixelSummary {
    sum: f64,
    clean: bool,
}

/// Streams the pixels of a cooler in order, a block at a time.
pub(super) struct PixelCursor<'a> {
    columns: &'a PixelColumns,
    raw: &'a File,
    next_block: usize,
    block: (Vec<i64>, Vec<i64>, Vec<f64>),
    position: usize,
}

impl<'a> PixelCursor<'a> {
    fn new(columns: &'a PixelColumns, raw: &'a File) -> Self {
        PixelCursor {
            columns,
            raw,
            next_block: 0,
            block: Default::default(),
            position: 0,
        }
    }

    fn peek(&mut self) -> Result<Option<(i64, i64, f64)>> {
        if self.position == self.block.0.len() {
            let n = self.columns.len();
            if self.next_block >= n {
                return Ok(None);
            }
            let hi = (self.next_block + BLOCK_PIXELS).min(n);
            self.block = self.columns.read(self.raw, self.next_block, hi)?;
            self.next_block = hi;
            self.position = 0;
        }
        let k = self.position;
        Ok(Some((self.block.0[k], self.block.1[k], self.block.2[k])))
    }

    fn advance(&mut self) {
        self.position += 1;
    }
}

/// The state of one coarse level during the coarsening comparison.
pub(super) struct LevelComparison<'a> {
    name: &'a str,
    /// Coarse bin of every base bin.
    coarse_of: Vec<u64>,
    row: Option<u64>,
    entries: Vec<(u64, f64)>,
    stored: PixelCursor<'a>,
}

impl LevelComparison<'_> {
    fn push(&mut self, i: u64, j: u64, c: f64, out: &mut Collector) -> Result<()> {
        let (ci, cj) = (self.coarse_of[i as usize], self.coarse_of[j as usize]);
        if self.row != Some(ci) {
            self.flush(out)?;
            self.row = Some(ci);
        }
        self.entries.push((cj, c));
        Ok(())
    }

    /// Compare the accumulated coarse row with the stored pixels of that row (and report stored
    /// rows before it, which the base does not have).
    fn flush(&mut self, out: &mut Collector) -> Result<()> {
        let Some(row) = self.row.take() else {
            return Ok(());
        };
        self.entries.sort_unstable_by_key(|&(j, _)| j);
        let mut expected: Vec<(u64, f64)> = Vec::with_capacity(self.entries.len());
        for &(j, c) in &self.entries {
            match expected.last_mut() {
                Some(last) if last.0 == j => last.1 += c,
                _ => expected.push((j, c)),
            }
        }
        self.entries.clear();
        self.drain_before(row as i64, out)?;
        let mut next = expected.iter().peekable();
        loop {
            let stored = match self.stored.peek()? {
                Some((i, j, c)) if i == row as i64 => Some((j as u64, c)),
                _ => None,
            };
            let computed = next.peek().copied().copied();
            let (j, stored_count, computed_count) = match (stored, computed) {
                (None, None) => break,
                (Some((sj, sc)), Some((cj, cc))) if sj == cj => {
                    self.stored.advance();
                    next.next();
                    (sj, sc, cc)
                }
                (Some((sj, sc)), Some((cj, _))) if sj < cj => {
                    self.stored.advance();
                    (sj, sc, 0.0)
                }
                (Some((sj, sc)), None) => {
                    self.stored.advance();
                    (sj, sc, 0.0)
                }
                (_, Some((cj, cc))) => {
                    next.next();
                    (cj, 0.0, cc)
                }
            };
            self.compare(row, j, stored_count, computed_count, out);
        }
        Ok(())
    }

    fn compare(&self, i: u64, j: u64, stored: f64, computed: f64, out: &mut Collector) {
        if (stored - computed).abs() > FLOAT_TOLERANCE * stored.abs().max(computed.abs()) {
            out.add(self.name, Class::Coarsening, || {
                (
                    format!("pixel ({i}, {j})"),
                    format!("stored count {stored}; the base resolution's pixels sum to {computed} in this coarse pixel"),
                )
            });
        }
    }

    /// Stored pixels in rows before `row` (all rows when `row` is `i64::MAX`) have no base pixel.
    fn drain_before(&mut self, row: i64, out: &mut Collector) -> Result<()> {
        while let Some((i, j, c)) = self.stored.peek()? {
            if i >= row {
                break;
            }
            self.stored.advance();
            self.compare(i as u64, j as u64, c, 0.0, out);
        }
        Ok(())
    }
}

/// Every coarser level equals the base (finest) level summed into its bins.
pub(super) fn check_coarsening(
    raw: &File,
    coolers: &[CheckedCooler],
    out: &mut Collector,
) -> Result<()> {
    let Some(base) = coolers.first() else {
        return Ok(());
    };
    let (Some(base_bins), Some(base_pixels), true, Some(base_resolution)) = (
        &base.bins,
        &base.pixels,
        base.pixels_clean,
        base.resolution.filter(|&r| r > 0),
    ) else {
        out.notes.push(format!(
            "coarsening not checked: the base resolution {} has defects (listed above) or no fixed bin size",
            base.name
        ));
        return Ok(());
    };
    let mut levels = Vec::new();
    for level in &coolers[1..] {
        let Some(resolution) = level.resolution else {
            out.notes.push(format!(
                "{}: no resolution known (no bin-size): coarsening not checked",
                level.name
            ));
            continue;
        };
        if resolution % base_resolution != 0 {
            out.add(&level.name, Class::Coarsening, || {
                (
                    "bins".into(),
                    format!("resolution {resolution} is not a multiple of the base resolution {base_resolution}"),
                )
            });
            continue;
        }
        let Ok(expected_bins) = base_bins.coarsen(resolution / base_resolution) else {
            continue;
        };
        let (Some(bins), Some(pixels), true) = (&level.bins, &level.pixels, level.pixels_clean)
        else {
            out.notes.push(format!(
                "{}: coarsening not checked (the level's own defects are listed above)",
                level.name
            ));
            continue;
        };
        let same_bins = bins.n_bins() == expected_bins.n_bins()
            && bins.chroms() == expected_bins.chroms()
            && bins.iter().zip(expected_bins.iter()).all(|(a, b)| a == b);
        if !same_bins {
            out.add(&level.name, Class::Coarsening, || {
                (
                    "bins".into(),
                    format!(
                        "the bin table ({} bins) is not the base resolution's bins coarsened to {resolution} bp ({} bins)",
                        bins.n_bins(),
                        expected_bins.n_bins()
                    ),
                )
            });
            continue;
        }
        let coarse_of = base_bins
            .iter()
            .map(|b| expected_bins.bin_at(b.chrom_id, b.start) as u64)
            .collect();
        levels.push(LevelComparison {
            name: &level.name,
            coarse_of,
            row: None,
            entries: Vec::new(),
            stored: PixelCursor::new(pixels, raw),
        });
    }
    if levels.is_empty() {
        return Ok(());
    }
    let mut cursor = PixelCursor::new(base_pixels, raw);
    while let Some((i, j, c)) = cursor.peek()? {
        cursor.advance();
        let (i, j) = (i as u64, j as u64);
        for level in &mut levels {
            level.push(i, j, c, out)?;
        }
    }
    for level in &mut levels {
        level.flush(out)?;
        level.drain_before(i64::MAX, out)?;
    }
    Ok(())
}
