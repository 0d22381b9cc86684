//! What the pairs room's unit tests share: pairtools 1.1.2's outputs on the simulated BAM
//! (`data/pairs/README.md`).

use std::io::Read;

const REFERENCE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/pairs/reference");

/// A file of `data/pairs/reference/` (gzip), as text.
pub fn reference(name: &str) -> String {
    let path = format!("{REFERENCE}/{name}");
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut text = String::new();
    flate2::read::MultiGzDecoder::new(&bytes[..])
        .read_to_string(&mut text)
        .unwrap_or_else(|e| panic!("{path}: {e}"));
    text
}
