//! Checks of Juicer `.hic` files through the reader, every resolution streamed.

use super::*;

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
        let n = reader.bins().n_bins();
        let mut index = 0u64;
        let streamed = reader.read_pixels(0..n, 0..n, &mut |block| {
            for k in 0..block.len() {
                let (i, j, c) = (block.bin1[k], block.bin2[k], block.count[k]);
                if !c.is_finite() || c < 0.0 {
                    collector.add(&name, Class::Count, || {
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
            collector.add(&name, Class::HicRead, || {
                (
                    format!("after {index} pixels"),
                    format!("reading the pixels failed: {e}"),
                )
            });
        }
    }
    let format = version.map_or("hic".into(), |v| format!("hic (version {v})"));
    Ok(collector.into_report(path, format, checked))
}
