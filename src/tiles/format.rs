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
pub fn dense_json(values: &[f32]) -> Value {
    let finite = values.iter().filter(|v| !v.is_nan());
    let min = finite.clone().copied().reduce(f32::min);
    let max = finite.copied().reduce(f32::max);
    let has_nan = min.is_none() || values.iter().any(|v| v.is_nan());
    let in_f16 = |v: Option<f32>| {
        v.is_some_and(|v| {
            let rounded = f16::from_f32(v);
            rounded > f16::MIN && rounded < f16::MAX
        })
    };
    let (dense, dtype) = if !has_nan && in_f16(min) && in_f16(max) {
        let bytes: Vec<u8> = values
            .iter()
            .flat_map(|&v| f16::from_f32(v).to_le_bytes())
            .collect();
        (STANDARD.encode(bytes), "float16")
    } else {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        (STANDARD.encode(bytes), "float32")
    };
    json!({
        "min_value": wire(min),
        "max_value": wire(max),
        "dense": dense,
        "size": 1,
        "dtype": dtype,
    })
}

/// A tile's smallest or largest value as the server sends it.
fn wire(value: Option<f32>) -> Value {
    match value {
        None => json!("NaN"),
        Some(v) if v == f32::INFINITY => json!("Infinity"),
        Some(v) if v == f32::NEG_INFINITY => json!("-Infinity"),
        Some(v) => json!(v as f64),
    }
}
