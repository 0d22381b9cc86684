//! The checks of one cooler group: its datasets, their kinds, and the order of the checks; what
//! they learned about the cooler.

use super::columns::{BinColumns, PixelColumns};
use super::stored::{Attr, Kind, kind_of, read_attr};
use crate::error::{Error, Result};
use crate::genome::{Bin, BinTable, Chrom};
use crate::io::hdf5_guard::read_strings;
use crate::validate::report::{Class, Collector};
use std::fs::File;

/// The checks of one cooler group.
pub(in crate::validate) struct CoolerCheck<'a> {
    pub(in crate::validate) path: &'a str,
    pub(in crate::validate) name: &'a str,
    pub(in crate::validate) group: &'a hdf5::Group,
    pub(in crate::validate) raw: &'a File,
}

/// What the checks learned about one cooler, for the coarsening check and the repair.
pub(in crate::validate) struct CheckedCooler {
    pub(super) name: String,
    pub(super) resolution: Option<u64>,
    /// The bin table when it is valid.
    pub(super) bins: Option<BinTable>,
    /// True when the pixels are in range, upper-triangle (when stored so), sorted and unique.
    pub(super) pixels_clean: bool,
    /// The pixel columns when they could be opened.
    pub(super) pixels: Option<PixelColumns>,
}

impl CoolerCheck<'_> {
    pub(crate) fn add(&self, out: &mut Collector, class: Class, location: &str, message: String) {
        out.add(self.name, class, || (location.to_string(), message));
    }

    /// Open `name` and check that its type is `expected` (one of); report and return `None`
    /// when it is missing or of another type.
    pub(crate) fn dataset(
        &self,
        out: &mut Collector,
        name: &str,
        expected: &[Kind],
    ) -> Option<hdf5::Dataset> {
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

    pub(crate) fn ints(&self, out: &mut Collector, name: &str) -> Result<Option<Vec<i64>>> {
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

    pub(crate) fn prefix(&self) -> String {
        if self.name == "/" {
            String::new()
        } else {
            format!("{}/", self.name.trim_start_matches('/'))
        }
    }

    pub(crate) fn attr(&self, name: &str) -> Option<Attr> {
        read_attr(self.path, self.group, name)
    }

    /// Run every check of the group; `None` when the group is too broken to be used further.
    pub(crate) fn run(&self, out: &mut Collector) -> Result<Option<CheckedCooler>> {
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

    pub(crate) fn check_chroms(&self, out: &mut Collector) -> Result<Option<Vec<Chrom>>> {
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
    pub(crate) fn check_bin_columns(&self, out: &mut Collector) -> Result<Option<BinColumns>> {
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
    pub(crate) fn check_bin_table(
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
        let resolution = self.attr("bin-size").and_then(|a| a.as_i64());
        if bin_type.as_ref().and_then(|a| a.as_str()) == Some("fixed") {
            match resolution {
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
        let hint = resolution.filter(|&s| s > 0).map(|s| s as u64);
        BinTable::from_bins(chroms.to_vec(), &bins, hint).ok()
    }
}
