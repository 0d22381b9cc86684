//! HiGlass tiles of a contact map, as clodius 0.22.2 computes them for higlass-server
//! (`clodius.tiles.cooler`): what a viewer asks first (`tileset_info`: the resolutions, the
//! normalisations offered, the genome's extent and chromosomes), then 256 x 256 tiles.
//!
//! The room computes from readers it is given (one per resolution); opening the files is the
//! caller's (the server's, Python's).

use serde_json::{Value, json};

use crate::io::MatrixReader;

/// The normalisations HiGlass offers, by the bin-table column that holds each, with the name
/// clodius shows (`transform_descriptions`).
const TRANSFORMS: [(&str, &str); 4] = [
    ("weight", "ICE"),
    ("KR", "KR"),
    ("VC", "VC"),
    ("VC_SQRT", "VC_SQRT"),
];

/// One resolution of a multi-resolution map: its bin size and its reader.
pub struct Level<'a> {
    /// The bin size in base pairs.
    pub resolution: u64,
    /// The map at that resolution.
    pub reader: &'a dyn MatrixReader,
}

/// `tileset_info` of a multi-resolution map (an `.mcool`'s levels), as clodius' `make_mats`
/// writes it: `resolutions` ascending; `transforms`, the normalisations whose columns every
/// resolution has (clodius lists them in Python's set order, which varies from run to run; here
/// in the order weight, KR, VC, VC_SQRT); `min_pos` `[1, 1]` and `max_pos` the genome's length twice;
/// `chromsizes` as `[name, length]` pairs; `mirror_tiles: "false"` when both triangles are
/// stored (`storage-mode: square`). `levels` must not be empty.
pub fn tileset_info(levels: &[Level]) -> Value {
    let mut resolutions: Vec<u64> = levels.iter().map(|l| l.resolution).collect();
    resolutions.sort_unstable();
    let names: Vec<Vec<String>> = levels.iter().map(|l| l.reader.weight_names()).collect();
    let transforms: Vec<Value> = TRANSFORMS
        .iter()
        .filter(|(column, _)| names.iter().all(|n| n.iter().any(|w| w == column)))
        .map(|(column, name)| json!({"name": name, "value": column}))
        .collect();
    // clodius takes the genome and the storage mode from the first group it lists.
    let first = levels
        .iter()
        .min_by_key(|l| l.resolution.to_string())
        .expect("a map has at least one resolution");
    let chroms = first.reader.bins().chroms();
    let length: u64 = chroms.iter().map(|c| c.length_bp).sum();
    let mut info = json!({
        "resolutions": resolutions,
        "transforms": transforms,
        "max_pos": [length, length],
        "min_pos": [1, 1],
        "chromsizes": chroms.iter().map(|c| json!([c.name, c.length_bp])).collect::<Vec<_>>(),
    });
    if first.reader.stores_both_triangles() {
        info["mirror_tiles"] = json!("false");
    }
    info
}

#[cfg(test)]
mod tests;
