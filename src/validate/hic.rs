//! Checks of the formats read through their readers, every pixel streamed: Juicer `.hic` (every
//! resolution) and HiCExplorer `.h5`.

use super::report::{Class, Collector, Report};
use crate::error::Result;
use crate::io::hic::HicReader;
use crate::io::{self, MatrixReader};
use std::path::Path;

pub(super) fn validate_hic(uri: &str, path: &str, group: Option<&str>) -> Result<Report> {
    let file = Path::new(path);
    let resolutions = match group {
        Some(g) => vec![io::parse_resolution_group(uri, g)?],
        None => HicReader::list_resolutions(file)?,
    };
    let mut collector = Collector::default();
    let mut checked = Vec::new();
    let mut version = None;
    for resolution in resolutions {
        let name = format!("/resolutions/{resolution}");
        checked.push(name.clone());
        let reader = match HicReader::open(file, Some(resolution)) {
            Ok(reader) => reader,
            Err(e) => {
                collector.add(&name, Class::HicRead, || ("open".into(), e.to_string()));
                continue;
            }
        };
        version = Some(reader.version());
        check_streamed(&reader, &name, &mut collector);
    }
    let format = version.map_or("hic".into(), |v| format!("hic (version {v})"));
    Ok(collector.into_report(path, format, checked))
}

/// Stream every pixel of `reader`: counts finite and >= 0; a read error is a finding.
fn check_streamed(reader: &dyn MatrixReader, name: &str, collector: &mut Collector) {
    let n = reader.bins().n_bins();
    let mut index = 0u64;
    let streamed = reader.read_pixels(0..n, 0..n, &mut |block| {
        for k in 0..block.len() {
            let (i, j, c) = (block.bin1[k], block.bin2[k], block.count[k]);
            if !c.is_finite() || c < 0.0 {
                collector.add(name, Class::Count, || {
                    (
                        format!("pixel ({i}, {j})"),
                        format!("count {c}; expected finite and >= 0"),
                    )
                });
            }
            index += 1;
        }
        Ok(())
    });
    if let Err(e) = streamed {
        collector.add(name, Class::HicRead, || {
            (
                format!("after {index} pixels"),
                format!("reading the pixels failed: {e}"),
            )
        });
    }
}

/// A HiCExplorer `.h5` matrix, through [`crate::io::hicexplorer::HicExplorerReader`] (which checks
/// the datasets' lengths against each other and the CSR structure on open): every pixel
/// streamed, counts finite and >= 0, the correction factors finite and > 0 or NaN.
pub(super) fn validate_hicexplorer(path: &str) -> Result<Report> {
    let mut collector = Collector::default();
    let name = "/";
    match crate::io::hicexplorer::HicExplorerReader::open(path) {
        Ok(reader) => {
            check_streamed(&reader, name, &mut collector);
            for column in reader.weight_names() {
                match reader.weights(&column) {
                    Ok(weights) => {
                        for (bin, &w) in weights.values.iter().enumerate() {
                            if !(w.is_nan() || (w.is_finite() && w > 0.0)) {
                                collector.add(name, Class::Weight, || {
                                    (
                                        format!("{column}[{bin}]"),
                                        format!("weight {w}; expected finite and > 0, or NaN for a masked bin"),
                                    )
                                });
                            }
                        }
                    }
                    Err(e) => collector.add(name, Class::Weight, || {
                        (column.clone(), format!("reading the weights failed: {e}"))
                    }),
                }
            }
        }
        Err(e) => collector.add(name, Class::HicRead, || ("open".into(), e.to_string())),
    }
    Ok(collector.into_report(path, "hicexplorer h5".into(), vec![name.into()]))
}
