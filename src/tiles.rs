//! HiGlass tiles of a contact map, as clodius 0.22.2 computes them for higlass-server
//! (`clodius.tiles.cooler`): what a viewer asks first (`tileset_info`: the resolutions, the
//! normalisations offered, the genome's extent and chromosomes), then 256 x 256 tiles.
//!
//! The room computes from readers it is given (one per resolution); opening the files is the
//! caller's (the server's, Python's).
//!
//! A [`Tileset`] holds a map's levels; [`Tileset::info`] is clodius' `tileset_info`,
//! [`Tileset::tile`] one tile's values and [`dense_json`] the JSON a viewer receives for them.

mod dense;
mod format;
mod id;
mod intervals;
mod rectangles;
mod vector;

use serde_json::{Value, json};

use crate::error::{Error, Result};
use crate::io::{FileKind, MatrixReader};

pub use dense::TILE_SIZE;
pub use format::{Sample, dense_json, dense_json_text};
pub use id::{TileId, shown};
pub use intervals::{Intervals, MAX_PER_TILE};
pub use rectangles::{MAX_RECTANGLES_PER_TILE, Rectangles};
pub use vector::{Aggregation, VECTOR_TILE_SIZE, Vector};

/// The normalisations HiGlass offers, by the bin-table column that holds each, with the name
/// clodius shows (`transform_descriptions`).
const TRANSFORMS: [(&str, &str); 4] = [
    ("weight", "ICE"),
    ("KR", "KR"),
    ("VC", "VC"),
    ("VC_SQRT", "VC_SQRT"),
];

/// Which normalisations a tileset offers, and how it applies them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Norms {
    /// A cooler's, as clodius: `weight` (ICE, multiplicative) and the divisive KR, VC and
    /// VC_SQRT that hic2cool stores, where every resolution has them; `default` is `weight`
    /// where the map has it.
    Cooler,
    /// A `.hic`'s norm vectors (KR, VC, VC_SQRT, SCALE, ...), divisive as Juicer stores them,
    /// each offered where every resolution has it; `default` is the counts.
    Hic,
}

impl Norms {
    /// The normalisations of a file of `kind`: a `.hic`'s norm vectors, else a cooler's columns.
    pub fn of(kind: FileKind) -> Norms {
        if kind == FileKind::Hic {
            Norms::Hic
        } else {
            Norms::Cooler
        }
    }
}

/// A multi-resolution contact map (an `.mcool`'s or a `.hic`'s resolutions, or one `.cool`) to
/// cut into tiles. Zoom level 0 is the coarsest resolution.
///
/// A tileset may be shared between threads; the weight columns a tile needs are read once and
/// kept.
pub struct Tileset {
    /// By resolution, coarsest first: zoom level `z` is `levels[z]`.
    levels: Vec<dense::Level>,
    /// The level clodius takes the genome and the storage mode from (the first it lists).
    first: usize,
    norms: Norms,
}

impl Tileset {
    /// The tileset of `levels`: each resolution in base pairs with the map's reader at it. The
    /// levels must share one genome and have bins of their resolution.
    pub fn new(levels: Vec<(u64, Box<dyn MatrixReader>)>, norms: Norms) -> Result<Tileset> {
        if levels.is_empty() {
            return Err(Error::Argument(
                "a tileset needs at least one resolution".into(),
            ));
        }
        let mut levels = levels
            .into_iter()
            .map(|(resolution, reader)| dense::Level::new(resolution, reader))
            .collect::<Result<Vec<_>>>()?;
        levels.sort_by_key(|l| std::cmp::Reverse(l.resolution));
        let chroms = levels[0].reader.bins().chroms().to_vec();
        if let Some(other) = levels[1..]
            .iter()
            .find(|l| l.reader.bins().chroms() != chroms.as_slice())
        {
            return Err(Error::Argument(format!(
                "{}: its chromosomes differ from those of {}",
                other.reader.source(),
                levels[0].reader.source()
            )));
        }
        // clodius lists an .mcool's groups as HDF5 orders their names: as text.
        let first = (0..levels.len())
            .min_by_key(|&i| levels[i].resolution.to_string())
            .unwrap_or(0);
        Ok(Tileset {
            levels,
            first,
            norms,
        })
    }

    /// The resolutions, coarsest first (zoom level 0 first).
    pub fn resolutions(&self) -> Vec<u64> {
        self.levels.iter().map(|l| l.resolution).collect()
    }

    /// The reader at zoom level `zoom`.
    pub fn reader(&self, zoom: usize) -> Option<&dyn MatrixReader> {
        self.levels.get(zoom).map(|l| l.reader.as_ref())
    }

    /// `tileset_info` as clodius' `make_mats` writes it for an `.mcool`: `resolutions`
    /// ascending; `transforms`, the normalisations whose columns every resolution has (clodius
    /// lists them in Python's set order, which varies from run to run; here in the order weight,
    /// KR, VC, VC_SQRT); `min_pos` `[1, 1]` and `max_pos` the genome's length twice;
    /// `chromsizes` as `[name, length]` pairs; `mirror_tiles: "false"` when both triangles are
    /// stored (`storage-mode: square`).
    pub fn info(&self) -> Value {
        let mut resolutions = self.resolutions();
        resolutions.sort_unstable();
        let names: Vec<Vec<String>> = self
            .levels
            .iter()
            .map(|l| l.reader.weight_names())
            .collect();
        let everywhere = |column: &str| names.iter().all(|n| n.iter().any(|w| w == column));
        let transforms: Vec<Value> = match self.norms {
            Norms::Cooler => TRANSFORMS
                .iter()
                .filter(|(column, _)| everywhere(column))
                .map(|(column, name)| json!({"name": name, "value": column}))
                .collect(),
            Norms::Hic => names[0]
                .iter()
                .filter(|column| everywhere(column))
                .map(|column| json!({"name": column, "value": column}))
                .collect(),
        };
        let first = &self.levels[self.first];
        let chroms = first.reader.bins().chroms();
        let mut info = json!({
            "resolutions": resolutions,
            "transforms": transforms,
            "max_pos": [first.length, first.length],
            "min_pos": [1, 1],
            "chromsizes": chroms.iter().map(|c| json!([c.name, c.length_bp])).collect::<Vec<_>>(),
        });
        if first.reader.stores_both_triangles() {
            info["mirror_tiles"] = json!("false");
        }
        info
    }

    /// The tile at zoom level `zoom`, column `x` (the first bin's axis) and row `y`, under
    /// `transform`: 256 x 256 values, row-major, a row per bin of the second axis; `None` past
    /// the last zoom level. A cooler's transforms are `default`, `weight`, `KR`, `VC`, `VC_SQRT`
    /// (another name gives the raw counts, as clodius does); a `.hic`'s, `default` (the counts)
    /// and its norms' names (another name is an error).
    ///
    /// As clodius computes it: the pixels stored in the rectangle (one triangle of a
    /// symmetric-upper map), each placed by its bins' start on the concatenated genome; `default`
    /// balances with `weight` where the map has it; a bin whose weight is NaN is NaN across the
    /// tile, and so is what lies past the genome's end.
    pub fn tile(&self, zoom: usize, x: u64, y: u64, transform: &str) -> Result<Option<Vec<f32>>> {
        let Some(level) = self.levels.get(zoom) else {
            return Ok(None);
        };
        let balance = self.balance(level, transform)?;
        level.tile(x, y, balance.as_ref()).map(Some)
    }

    /// What `transform` does to the counts at `level`.
    fn balance(&self, level: &dense::Level, transform: &str) -> Result<Option<dense::Balance>> {
        let (column, divide) = match (self.norms, transform) {
            (Norms::Cooler, "default") if level.has_column("weight") => ("weight", false),
            (Norms::Cooler, "weight") => ("weight", false),
            (Norms::Cooler, "KR" | "VC" | "VC_SQRT") => (transform, true),
            (Norms::Hic, "default") | (Norms::Cooler, _) => return Ok(None),
            (Norms::Hic, _) => (transform, true),
        };
        if !level.has_column(column) {
            return Err(Error::Argument(format!(
                "{}: no '{column}' column at {} bp (the transforms of this map are {})",
                level.reader.source(),
                level.resolution,
                self.transform_names().join(", ")
            )));
        }
        Ok(Some(dense::Balance {
            weights: level.column(column)?,
            divide,
        }))
    }

    /// The transforms offered (`tileset_info`'s `transforms` values), with `default`.
    fn transform_names(&self) -> Vec<String> {
        let mut names = vec!["default".to_string()];
        if let Some(list) = self.info()["transforms"].as_array() {
            names.extend(
                list.iter()
                    .filter_map(|t| t["value"].as_str().map(String::from)),
            );
        }
        names
    }
}

#[cfg(test)]
mod tests;
