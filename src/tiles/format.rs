//! A dense tile as JSON, as clodius' `format_dense_tile` writes it.

use base64::Engine;
use base64::engine::general_purpose::STANDARD;
use half::f16;
use serde_json::{Value, json};

/// The JSON a viewer receives for a dense tile: `dense`, its values' little-endian bytes in
/// base64, as float16 where clodius uses float16 (no NaN, and the smallest and largest values
/// inside float16's range as numpy compares them: rounded to float16 first, so 65490 is not
/// inside, 65480 is), else float32; `dtype`; `size` 1; `min_value` / `max_value` over the
/// values that are not NaN, `"NaN"` when all are.
///
/// One difference: where a value is infinite (a zero in a divisive column), clodius writes a
/// bare `Infinity`, which is not JSON and which a browser's `JSON.parse` refuses; this writes
/// the string `"Infinity"` (or `"-Infinity"`), as clodius writes `"NaN"`.
///
/// ```
/// use contactmap::tiles::dense_json;
///
/// let tile = dense_json(&[1.0, 2.5, 0.0, 3.0]);
/// assert_eq!(tile["dtype"], "float16");
/// assert_eq!(tile["dense"], "ADwAQQAAAEI="); // 1, 2.5, 0, 3 as float16
/// assert_eq!(tile["max_value"], 3.0);
/// let masked = dense_json(&[f32::NAN, 2.0]);
/// assert_eq!(masked["dtype"], "float32");
/// assert_eq!(masked["min_value"], 2.0);
/// assert_eq!(dense_json(&[f32::NAN])["max_value"], "NaN");
/// ```
pub fn dense_json<T: Sample>(values: &[T]) -> Value {
    let tile = Encoded::of(values);
    json!({
        "min_value": tile.min_value,
        "max_value": tile.max_value,
        "dense": tile.dense,
        "size": 1,
        "dtype": tile.dtype,
    })
}

/// [`dense_json`] as JSON text, written directly (a tile's base64 text is a third of a megabyte:
/// no JSON value is built and no string escaped).
///
/// ```
/// use contactmap::tiles::{dense_json, dense_json_text};
///
/// let values = [1.0, f32::NAN, 2.5];
/// let text = dense_json_text(&values);
/// assert_eq!(serde_json::from_str::<serde_json::Value>(&text)?, dense_json(&values));
/// # Ok::<(), serde_json::Error>(())
/// ```
pub fn dense_json_text<T: Sample>(values: &[T]) -> String {
    let tile = Encoded::of(values);
    let mut text = String::with_capacity(tile.dense.len() + 128);
    text.push_str("{\"min_value\":");
    text.push_str(&tile.min_value.to_string());
    text.push_str(",\"max_value\":");
    text.push_str(&tile.max_value.to_string());
    text.push_str(",\"dense\":\"");
    text.push_str(&tile.dense); // base64: nothing to escape
    text.push_str("\",\"size\":1,\"dtype\":\"");
    text.push_str(tile.dtype);
    text.push_str("\"}");
    text
}

/// A tile encoded: its values' base64 text and dtype, its smallest and largest values.
struct Encoded {
    min_value: Value,
    max_value: Value,
    dense: String,
    dtype: &'static str,
}

/// Values encoded at a time: 768 float32 are 3,072 bytes, a multiple of 3, so the base64 text
/// of the pieces joined is that of the whole.
const PIECE: usize = 768;

impl Encoded {
    fn of<T: Sample>(values: &[T]) -> Encoded {
        let (mut min, mut max, mut has_nan) = (f64::INFINITY, f64::NEG_INFINITY, false);
        for v in values {
            let v = v.wide();
            if v.is_nan() {
                has_nan = true;
            } else {
                min = min.min(v);
                max = max.max(v);
            }
        }
        let any = min <= max;
        let (min, max) = (any.then_some(min), any.then_some(max));
        let in_f16 = |v: Option<f64>| {
            v.is_some_and(|v| {
                let rounded = f16::from_f64(v);
                rounded > f16::MIN && rounded < f16::MAX
            })
        };
        let half = !has_nan && in_f16(min) && in_f16(max);
        let width = if half { 2 } else { 4 };
        let mut dense = String::with_capacity((values.len() * width).div_ceil(3) * 4);
        let mut bytes = Vec::with_capacity(PIECE * 4);
        for piece in values.chunks(PIECE) {
            bytes.clear();
            if half {
                bytes.extend(piece.iter().flat_map(|v| v.half().to_le_bytes()));
            } else {
                bytes.extend(piece.iter().flat_map(|v| v.single().to_le_bytes()));
            }
            STANDARD.encode_string(&bytes, &mut dense);
        }
        Encoded {
            min_value: wire(min),
            max_value: wire(max),
            dense,
            dtype: if half { "float16" } else { "float32" },
        }
    }
}

/// A tile's values: float32 (a map's tiles, as clodius fills them) or float64 (a vector track's,
/// as clodius' bigWig tiles are), each cast to float16 or float32 directly, as numpy's `astype`.
pub trait Sample: Copy {
    /// As float64 (exact).
    fn wide(self) -> f64;
    /// Rounded to float32.
    fn single(self) -> f32;
    /// Rounded to float16 (from the value itself, not through float32).
    fn half(self) -> f16;
}

impl Sample for f32 {
    fn wide(self) -> f64 {
        self as f64
    }
    fn single(self) -> f32 {
        self
    }
    fn half(self) -> f16 {
        f16::from_f32(self)
    }
}

impl Sample for f64 {
    fn wide(self) -> f64 {
        self
    }
    fn single(self) -> f32 {
        self as f32
    }
    fn half(self) -> f16 {
        f16::from_f64(self)
    }
}

/// A tile's smallest or largest value as the server sends it.
fn wire(value: Option<f64>) -> Value {
    match value {
        None => json!("NaN"),
        Some(v) if v == f64::INFINITY => json!("Infinity"),
        Some(v) if v == f64::NEG_INFINITY => json!("-Infinity"),
        Some(v) => json!(v),
    }
}
