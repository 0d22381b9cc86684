//! HiGlass tiles of a map (`contactmap.tiles`): clodius' `tileset_info` and `tiles` as
//! higlass-python's tilesets answer them, for a notebook's own tile server.

use contactmap::error::Error;
use contactmap::io;
use contactmap::tiles::{dense_json_text, Norms, TileId, Tileset};
use pyo3::prelude::*;

use crate::convert::run;

/// A map's tileset: every resolution of an `.mcool` or `.hic`, or a `.cool`'s one.
#[pyclass(frozen, module = "contactmap._native")]
pub(crate) struct NativeTileset {
    tileset: Tileset,
}

#[pymethods]
impl NativeTileset {
    #[new]
    fn new(py: Python<'_>, path: &str) -> PyResult<Self> {
        let tileset = run(py, || {
            let (kind, levels) = io::open_levels(path)?;
            Tileset::new(levels, Norms::of(kind))
        })?;
        Ok(NativeTileset { tileset })
    }

    /// clodius' tileset_info, as JSON text.
    fn tileset_info(&self) -> String {
        self.tileset.info().to_string()
    }

    /// The tiles of `tile_ids` (`UID.z.x.y[.transform]`), as JSON text of `[[id, tile], ...]`;
    /// an id past the last zoom level is left out, as clodius leaves it out.
    fn tiles(&self, py: Python<'_>, tile_ids: Vec<String>) -> PyResult<String> {
        let tileset = &self.tileset;
        run(py, || {
            let mut out = String::from("[");
            for id in &tile_ids {
                let tile = TileId::parse(id).map_err(Error::Argument)?;
                let Some(y) = tile.y else {
                    return Err(Error::Argument(format!(
                        "tile id '{id}': a map's tiles are UID.z.x.y"
                    )));
                };
                let transform = tile.transform.unwrap_or("default");
                if let Some(values) = tileset.tile(tile.zoom, tile.x, y, transform)? {
                    if out.len() > 1 {
                        out.push(',');
                    }
                    out.push('[');
                    out.push_str(&serde_json::Value::from(id.as_str()).to_string());
                    out.push(',');
                    out.push_str(&dense_json_text(&values));
                    out.push(']');
                }
            }
            out.push(']');
            Ok(out)
        })
    }
}
