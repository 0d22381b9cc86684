//! The attributes of a cooler and its weight columns.

use super::check::CoolerCheck;
use super::stored::{Kind, kind_of, read_attr};
use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::io::cool::DIVISIVE_BY_NAME;
use crate::validate::report::{Class, Collector};
use crate::validate::tolerance::FLOAT_TOLERANCE;

impl CoolerCheck<'_> {
    pub(crate) fn check_attributes(
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
            if let (Some(size), Some(stored_size)) = (bins.resolution(), stored.as_i64()) {
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

    pub(crate) fn check_weights(&self, out: &mut Collector, n_bins: usize) -> Result<()> {
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
