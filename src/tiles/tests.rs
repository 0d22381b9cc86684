//! The room's answers against clodius 0.22.2's on the maps in data/
//! (`scripts/tiles_references.py` wrote them to data/tiles/).

use serde_json::Value;

use super::*;
use crate::io::cool::{CoolReader, HdfContent, inspect};

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

/// clodius' `tileset_info` of `name`, as the reference script wrote it.
fn reference(name: &str) -> Value {
    let path = format!("{DATA}/tiles/{name}.tileset_info.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    serde_json::from_str(&text).unwrap()
}

#[test]
fn tileset_info_of_an_mcool_equals_clodius() {
    for name in ["cooler_test_file.mcool", "toy.symm.upper.2.mcool"] {
        let path = format!("{DATA}/{name}");
        let HdfContent::Multires(resolutions) = inspect(&path).unwrap() else {
            panic!("{name} is a multi-resolution file");
        };
        let readers: Vec<CoolReader> = resolutions
            .iter()
            .map(|r| CoolReader::open(&format!("{path}::/resolutions/{r}")).unwrap())
            .collect();
        let levels: Vec<Level> = resolutions
            .iter()
            .zip(&readers)
            .map(|(&resolution, reader)| Level { resolution, reader })
            .collect();
        assert_eq!(tileset_info(&levels), reference(name), "{name}");
    }
    // Not an empty answer by default: cooler_test_file.mcool stores weight, KR, SCALE, VC and VC_SQRT
    // at 100 kb and none at 1 Mb, and clodius offers only what every resolution has.
    let path = format!("{DATA}/cooler_test_file.mcool");
    let names = |r: u64| {
        CoolReader::open(&format!("{path}::/resolutions/{r}"))
            .unwrap()
            .weight_names()
    };
    assert_eq!(names(100_000), ["KR", "SCALE", "VC", "VC_SQRT", "weight"]);
    assert!(names(1_000_000).is_empty());
}
