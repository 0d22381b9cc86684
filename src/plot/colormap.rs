//! Colour maps and colour scales, as matplotlib applies them.
//!
//! A colour map is a 256-entry lookup table; a value `t` in `[0, 1]` takes entry
//! `min(floor(256 t), 255)` (matplotlib's `Colormap.__call__`). Segmented maps interpolate their
//! anchor colours linearly at `i / 255` and truncate to 8 bits, as matplotlib's
//! `LinearSegmentedColormap` with `N = 256` and `bytes=True`:
//!
//! - `fall`, `blues`, `acidblues`: cooltools' palettes (`cooltools.lib.plotting.PALETTES`), the
//!   default of Hi-C maps in cooltools' notebooks;
//! - `RdBu`, `Greys`, `Reds`, `YlOrRd`: the ColorBrewer anchors of matplotlib's `_cm.py`;
//!   `bwr`, `afmhot` and `gray` from their closed forms;
//! - `viridis`, `magma`, `inferno`, `plasma`: matplotlib's 256 listed colours (from the colorous
//!   crate, which carries the same tables).
//!
//! Any name takes an `_r` suffix for the reversed map (`afmhot_r`, `RdBu_r`).

use crate::error::{Error, Result};
use crate::plot::svg::Rgb;

/// A 256-colour lookup table.
#[derive(Clone, Debug, PartialEq)]
pub struct ColorMap {
    /// Name as given (`RdBu_r`).
    pub name: String,
    lut: Vec<Rgb>,
}

/// Entries of a lookup table (matplotlib's default `N`).
const N_COLOURS: usize = 256;

/// Names accepted by [`ColorMap::by_name`] (each also with `_r`).
pub const COLOR_MAP_NAMES: &[&str] = &[
    "fall",
    "blues",
    "acidblues",
    "afmhot",
    "RdBu",
    "bwr",
    "coolwarm",
    "viridis",
    "magma",
    "inferno",
    "plasma",
    "Greys",
    "gray",
    "Reds",
    "YlOrRd",
];

/// Anchor colours (0-255), evenly spaced over `[0, 1]`.
fn anchors(name: &str) -> Option<&'static [[u8; 3]]> {
    Some(match name {
        "fall" => &[
            [255, 255, 255],
            [255, 255, 204],
            [255, 237, 160],
            [254, 217, 118],
            [254, 178, 76],
            [253, 141, 60],
            [252, 78, 42],
            [227, 26, 28],
            [189, 0, 38],
            [128, 0, 38],
            [0, 0, 0],
        ],
        "blues" => &[
            [255, 255, 255],
            [180, 204, 225],
            [116, 169, 207],
            [54, 144, 192],
            [5, 112, 176],
            [4, 87, 135],
            [3, 65, 100],
            [2, 40, 66],
            [1, 20, 30],
            [0, 0, 0],
        ],
        "acidblues" => &[
            [255, 255, 255],
            [162, 192, 222],
            [140, 137, 187],
            [140, 87, 167],
            [140, 45, 143],
            [120, 20, 120],
            [90, 15, 90],
            [60, 10, 60],
            [30, 5, 30],
            [0, 0, 0],
        ],
        "RdBu" => &[
            [103, 0, 31],
            [178, 24, 43],
            [214, 96, 77],
            [244, 165, 130],
            [253, 219, 199],
            [247, 247, 247],
            [209, 229, 240],
            [146, 197, 222],
            [67, 147, 195],
            [33, 102, 172],
            [5, 48, 97],
        ],
        "Greys" => &[
            [255, 255, 255],
            [240, 240, 240],
            [217, 217, 217],
            [189, 189, 189],
            [150, 150, 150],
            [115, 115, 115],
            [82, 82, 82],
            [37, 37, 37],
            [0, 0, 0],
        ],
        "Reds" => &[
            [255, 245, 240],
            [254, 224, 210],
            [252, 187, 161],
            [252, 146, 114],
            [251, 106, 74],
            [239, 59, 44],
            [203, 24, 29],
            [165, 15, 21],
            [103, 0, 13],
        ],
        "YlOrRd" => &[
            [255, 255, 204],
            [255, 237, 160],
            [254, 217, 118],
            [254, 178, 76],
            [253, 141, 60],
            [252, 78, 42],
            [227, 26, 28],
            [189, 0, 38],
            [128, 0, 38],
        ],
        "bwr" => &[[0, 0, 255], [255, 255, 255], [255, 0, 0]],
        // matplotlib's coolwarm (Moreland's diverging map): its 33 control points
        "coolwarm" => &[
            [59, 76, 192],
            [68, 90, 204],
            [77, 104, 215],
            [87, 117, 225],
            [98, 130, 234],
            [108, 142, 241],
            [119, 154, 247],
            [130, 165, 251],
            [141, 176, 254],
            [152, 185, 255],
            [163, 194, 255],
            [174, 201, 253],
            [184, 208, 249],
            [194, 213, 244],
            [204, 217, 238],
            [213, 219, 230],
            [221, 221, 221],
            [229, 216, 209],
            [236, 211, 197],
            [241, 204, 185],
            [245, 196, 173],
            [247, 187, 160],
            [247, 177, 148],
            [247, 166, 135],
            [244, 154, 123],
            [241, 141, 111],
            [236, 127, 99],
            [229, 112, 88],
            [222, 96, 77],
            [213, 80, 66],
            [203, 62, 56],
            [192, 40, 47],
            [180, 4, 38],
        ],
        "gray" => &[[0, 0, 0], [255, 255, 255]],
        _ => return None,
    })
}

/// 8-bit channel of a value in `[0, 1]`, truncated as matplotlib's `bytes=True`.
fn channel(value: f64) -> u8 {
    (value.clamp(0.0, 1.0) * 255.0) as u8
}

impl ColorMap {
    /// The colour map `name` (see [`COLOR_MAP_NAMES`]; `_r` reverses).
    pub fn by_name(name: &str) -> Result<ColorMap> {
        let (base, reversed) = match name.strip_suffix("_r") {
            Some(base) => (base, true),
            None => (name, false),
        };
        let mut lut = Self::table(base).ok_or_else(|| {
            Error::Argument(format!(
                "unknown colour map '{name}' (known: {}; add _r to reverse)",
                COLOR_MAP_NAMES.join(", ")
            ))
        })?;
        if reversed {
            lut.reverse();
        }
        Ok(ColorMap {
            name: name.to_string(),
            lut,
        })
    }

    fn table(base: &str) -> Option<Vec<Rgb>> {
        let listed = match base {
            "viridis" => Some(colorous::VIRIDIS),
            "magma" => Some(colorous::MAGMA),
            "inferno" => Some(colorous::INFERNO),
            "plasma" => Some(colorous::PLASMA),
            _ => None,
        };
        if let Some(gradient) = listed {
            return Some(
                (0..N_COLOURS)
                    .map(|i| {
                        let c = gradient.eval_rational(i, N_COLOURS);
                        Rgb(c.r, c.g, c.b)
                    })
                    .collect(),
            );
        }
        if base == "afmhot" {
            // gnuplot's afmhot: r = 2x, g = 2x - 1/2, b = 2x - 1.
            return Some(
                (0..N_COLOURS)
                    .map(|i| {
                        let x = i as f64 / (N_COLOURS - 1) as f64;
                        Rgb(
                            channel(2.0 * x),
                            channel(2.0 * x - 0.5),
                            channel(2.0 * x - 1.0),
                        )
                    })
                    .collect(),
            );
        }
        let anchors = anchors(base)?;
        let segments = (anchors.len() - 1) as f64;
        Some(
            (0..N_COLOURS)
                .map(|i| {
                    let position = i as f64 / (N_COLOURS - 1) as f64 * segments;
                    let k = (position.floor() as usize).min(anchors.len() - 2);
                    let f = position - k as f64;
                    let mix = |c: usize| {
                        let (a, b) = (
                            f64::from(anchors[k][c]) / 255.0,
                            f64::from(anchors[k + 1][c]) / 255.0,
                        );
                        channel(a + f * (b - a))
                    };
                    Rgb(mix(0), mix(1), mix(2))
                })
                .collect(),
        )
    }

    /// The colour of `t` in `[0, 1]` (clamped).
    pub fn colour(&self, t: f64) -> Rgb {
        let index = if t.is_nan() {
            0
        } else {
            ((t * N_COLOURS as f64).max(0.0) as usize).min(N_COLOURS - 1)
        };
        self.lut[index]
    }
}

/// How values map to `[0, 1]` before the colour map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScaleKind {
    /// `(v - vmin) / (vmax - vmin)`.
    Linear,
    /// `(ln v - ln vmin) / (ln vmax - ln vmin)`; values `<= 0` take the lowest colour.
    Log,
}

/// A colour scale: limits and their mapping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColorScale {
    /// Linear or log.
    pub kind: ScaleKind,
    /// Value of the lowest colour.
    pub vmin: f64,
    /// Value of the highest colour.
    pub vmax: f64,
}

impl ColorScale {
    /// Check the limits (finite, ordered, positive for a log scale).
    pub fn new(kind: ScaleKind, vmin: f64, vmax: f64) -> Result<ColorScale> {
        if !(vmin.is_finite() && vmax.is_finite() && vmin < vmax) {
            return Err(Error::Argument(format!(
                "colour limits must be finite with vmin < vmax (got {vmin} and {vmax})"
            )));
        }
        if kind == ScaleKind::Log && vmin <= 0.0 {
            return Err(Error::Argument(format!(
                "a log colour scale needs vmin > 0 (got {vmin}); use --linear for zero or negative values"
            )));
        }
        Ok(ColorScale { kind, vmin, vmax })
    }

    /// Position of `value` in `[0, 1]` (clamped); `None` for NaN.
    pub fn position(&self, value: f64) -> Option<f64> {
        if value.is_nan() {
            return None;
        }
        let t = match self.kind {
            ScaleKind::Linear => (value - self.vmin) / (self.vmax - self.vmin),
            ScaleKind::Log => {
                if value <= 0.0 {
                    0.0
                } else {
                    (value.ln() - self.vmin.ln()) / (self.vmax.ln() - self.vmin.ln())
                }
            }
        };
        Some(t.clamp(0.0, 1.0))
    }

    /// The value at position `t` in `[0, 1]` (the inverse of [`ColorScale::position`]).
    pub fn value_at(&self, t: f64) -> f64 {
        match self.kind {
            ScaleKind::Linear => self.vmin + t * (self.vmax - self.vmin),
            ScaleKind::Log => (self.vmin.ln() + t * (self.vmax.ln() - self.vmin.ln())).exp(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// matplotlib 3.11.2 `cmap(i / 255, bytes=True)` at i = 0, 1, 64, 127, 128, 200, 254, 255.
    #[test]
    fn tables_match_matplotlib() {
        let indices = [0usize, 1, 64, 127, 128, 200, 254, 255];
        let reference: &[(&str, [[u8; 3]; 8])] = &[
            (
                "RdBu",
                [
                    [103, 0, 31],
                    [105, 0, 31],
                    [229, 131, 104],
                    [247, 246, 246],
                    [246, 246, 246],
                    [79, 154, 199],
                    [6, 50, 99],
                    [5, 48, 97],
                ],
            ),
            (
                "Greys",
                [
                    [255, 255, 255],
                    [254, 254, 254],
                    [216, 216, 216],
                    [150, 150, 150],
                    [149, 149, 149],
                    [69, 69, 69],
                    [1, 1, 1],
                    [0, 0, 0],
                ],
            ),
            (
                "afmhot",
                [
                    [0, 0, 0],
                    [2, 0, 0],
                    [128, 0, 0],
                    [254, 126, 0],
                    [255, 128, 0],
                    [255, 255, 145],
                    [255, 255, 253],
                    [255, 255, 255],
                ],
            ),
            (
                "bwr",
                [
                    [0, 0, 255],
                    [2, 2, 255],
                    [128, 128, 255],
                    [254, 254, 255],
                    [255, 254, 254],
                    [255, 110, 110],
                    [255, 1, 1],
                    [255, 0, 0],
                ],
            ),
            (
                "viridis",
                [
                    [68, 1, 84],
                    [68, 2, 85],
                    [58, 82, 139],
                    [32, 143, 140],
                    [32, 144, 140],
                    [112, 206, 86],
                    [250, 230, 34],
                    [253, 231, 36],
                ],
            ),
            (
                "fall",
                [
                    [255, 255, 255],
                    [255, 255, 253],
                    [254, 226, 138],
                    [253, 141, 60],
                    [252, 139, 59],
                    [194, 4, 36],
                    [5, 0, 1],
                    [0, 0, 0],
                ],
            ),
        ];
        for (name, colours) in reference {
            let map = ColorMap::by_name(name).unwrap();
            for (&i, expected) in indices.iter().zip(colours) {
                let got = map.colour(i as f64 / 255.0);
                let close = |a: u8, b: u8| (i32::from(a) - i32::from(b)).abs() <= 1;
                assert!(
                    close(got.0, expected[0])
                        && close(got.1, expected[1])
                        && close(got.2, expected[2]),
                    "{name}({i}/255): {got:?} vs matplotlib {expected:?}"
                );
            }
        }
    }

    #[test]
    fn reversed_and_unknown_maps() {
        let map = ColorMap::by_name("afmhot_r").unwrap();
        assert_eq!(map.colour(0.0), Rgb(255, 255, 255));
        assert_eq!(map.colour(1.0), Rgb(0, 0, 0));
        let error = ColorMap::by_name("jet").unwrap_err().to_string();
        assert!(error.contains("unknown colour map 'jet'"), "{error}");
    }

    #[test]
    fn scales_map_and_invert() {
        let log = ColorScale::new(ScaleKind::Log, 1.0, 100.0).unwrap();
        assert_eq!(log.position(10.0), Some(0.5));
        assert_eq!(log.position(0.0), Some(0.0));
        assert_eq!(log.position(1e6), Some(1.0));
        assert_eq!(log.position(f64::NAN), None);
        assert!((log.value_at(0.5) - 10.0).abs() < 1e-12);
        let linear = ColorScale::new(ScaleKind::Linear, -1.0, 1.0).unwrap();
        assert_eq!(linear.position(0.0), Some(0.5));
        assert!(ColorScale::new(ScaleKind::Log, 0.0, 1.0).is_err());
        assert!(ColorScale::new(ScaleKind::Linear, 2.0, 1.0).is_err());
    }
}
