//! The room's answers against clodius 0.22.2's on the maps in data/
//! (`scripts/tiles_references.py` wrote them to data/tiles/).

use base64::Engine;
use serde_json::Value;

use super::*;
use crate::io::cool::{CoolReader, HdfContent, inspect};

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

/// The maps clodius answered for, by path under data/.
const MAPS: [&str; 3] = [
    "cooler_test_file.mcool",
    "toy.symm.upper.2.mcool",
    "tiles/square.mcool",
];

fn reference(name: &str, what: &str) -> Value {
    let file = name.rsplit('/').next().unwrap();
    let path = format!("{DATA}/tiles/{file}.{what}.json");
    serde_json::from_str(&read_text(&path)).unwrap()
}

/// A reference file's text, from `path` or `path.gz`.
fn read_text(path: &str) -> String {
    if let Ok(text) = std::fs::read_to_string(path) {
        return text;
    }
    let gz = format!("{path}.gz");
    let file = std::fs::File::open(&gz).unwrap_or_else(|e| panic!("{path}(.gz): {e}"));
    let mut text = String::new();
    std::io::Read::read_to_string(&mut flate2::read::GzDecoder::new(file), &mut text).unwrap();
    text
}

fn tileset(name: &str) -> Tileset {
    let path = format!("{DATA}/{name}");
    let HdfContent::Multires(resolutions) = inspect(&path).unwrap() else {
        panic!("{name} is a multi-resolution file");
    };
    let levels = resolutions
        .iter()
        .map(|&r| {
            let reader = CoolReader::open(&format!("{path}::/resolutions/{r}")).unwrap();
            (r, Box::new(reader) as Box<dyn MatrixReader>)
        })
        .collect();
    Tileset::new(levels, Norms::Cooler).unwrap()
}

#[test]
fn tileset_info_of_an_mcool_equals_clodius() {
    for name in MAPS {
        let mut info = tileset(name).info();
        // the reference lists the transforms by value (clodius' own order is Python's set order)
        let mut transforms = info["transforms"].as_array().unwrap().clone();
        transforms.sort_by_key(|t| t["value"].as_str().unwrap().to_string());
        info["transforms"] = Value::Array(transforms);
        assert_eq!(info, reference(name, "tileset_info"), "{name}");
    }
    assert_eq!(
        tileset("tiles/square.mcool").info()["transforms"]
            .as_array()
            .unwrap()
            .len(),
        2
    );
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

/// What the reference keeps of a tile: dtype, CRC-32 of the decoded bytes, NaN count, min / max.
fn digest(tile: &Value) -> Value {
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(tile["dense"].as_str().unwrap())
        .unwrap();
    let n_nan = match tile["dtype"].as_str().unwrap() {
        "float16" => bytes
            .chunks(2)
            .filter(|b| half::f16::from_le_bytes([b[0], b[1]]).is_nan())
            .count(),
        _ => bytes
            .chunks(4)
            .filter(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]).is_nan())
            .count(),
    };
    serde_json::json!({
        "dtype": tile["dtype"],
        "crc32": crc32fast::hash(&bytes),
        "n_nan": n_nan,
        "min_value": tile["min_value"],
        "max_value": tile["max_value"],
    })
}

/// `min_value` / `max_value` as the float32 they are (serde_json's parser may miss the last bit
/// of a 17-digit decimal).
fn single(digest: &Value) -> Value {
    let mut digest = digest.clone();
    for key in ["min_value", "max_value"] {
        if let Some(v) = digest[key].as_f64() {
            digest[key] = serde_json::json!(v as f32);
        }
    }
    digest
}

/// Every tile clodius was asked for (the diagonal at every zoom level, the tiles beside it,
/// trans tiles, past the end; each transform a level stores and `default`): the same bytes
/// (dtype, NaN positions, values), the same min / max, the same absent tiles.
#[test]
fn tiles_equal_clodius_bit_for_bit() {
    for name in MAPS {
        let tiles = tileset(name);
        let Value::Object(expected) = reference(name, "tiles") else {
            panic!("{name}: the reference is a map of tiles");
        };
        let mut float16 = 0;
        for (id, want) in &expected {
            let parts: Vec<&str> = id.split('.').collect();
            let [z, x, y] = [0, 1, 2].map(|i| parts[i].parse::<u64>().unwrap());
            let transform = parts.get(3).copied().unwrap_or("default");
            let got = tiles
                .tile(z as usize, x, y, transform)
                .unwrap_or_else(|e| panic!("{name} {id}: {e}"))
                .map(|values| digest(&dense_json(&values)));
            let want = if want.is_null() {
                Value::Null
            } else {
                single(want)
            };
            assert_eq!(
                got.map_or(Value::Null, |t| single(&t)),
                want,
                "{name} tile {id}"
            );
            float16 += usize::from(want["dtype"] == "float16");
        }
        assert!(expected.len() >= 20 && float16 > 0, "{name}: {float16}");
    }
}

/// A `.hic` is tiled as the cooler of the same pixels: hic_test_file.hic holds
/// cooler_test_file.mcool's 100 kb counts (hic2cool made the .mcool from it); its norm vectors are
/// divisive, as the .mcool's KR / VC columns (which hic2cool copied) are.
#[test]
fn a_hic_tiles_as_the_cooler_of_its_pixels() {
    use crate::io::{OpenOptions, open_matrix};
    let hic = open_matrix(
        &format!("{DATA}/hic_test_file.hic"),
        &OpenOptions::default(),
    )
    .unwrap();
    let names = hic.weight_names();
    let hic = Tileset::new(vec![(100_000, hic)], Norms::Hic).unwrap();
    let cool = tileset("cooler_test_file.mcool");
    let info = hic.info();
    let offered: Vec<&str> = info["transforms"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["value"].as_str().unwrap())
        .collect();
    assert_eq!(
        offered,
        names.iter().map(String::as_str).collect::<Vec<_>>()
    );
    assert!(!offered.is_empty());
    let mut nonzero = 0;
    for (x, y) in [(0, 0), (1, 1), (0, 1), (2, 4), (5, 5)] {
        let a = hic.tile(0, x, y, "default").unwrap().unwrap();
        let b = cool.tile(1, x, y, "counts").unwrap().unwrap();
        assert_eq!(a, b, "tile {x} {y}");
        nonzero += a.iter().filter(|&&v| v > 0.0).count();
        // a norm divides, and masks what the vector leaves NaN
        let normed = hic.tile(0, x, y, offered[0]).unwrap().unwrap();
        assert!(
            normed
                .iter()
                .zip(&a)
                .all(|(n, c)| n.is_nan() || (*c == 0.0) == (*n == 0.0))
        );
    }
    assert!(nonzero > 10_000);
    assert!(hic.tile(0, 0, 0, "weight").is_err());
}

#[test]
fn a_transform_the_map_lacks_is_an_error_and_another_name_gives_counts() {
    let tiles = tileset("cooler_test_file.mcool");
    // zoom 0 is 1 Mb, which stores no weights
    let err = tiles.tile(0, 0, 0, "KR").unwrap_err().to_string();
    assert!(err.contains("no 'KR' column at 1000000 bp"), "{err}");
    let raw = tiles.tile(1, 0, 0, "no-such").unwrap().unwrap();
    let default_without_weight = tiles.tile(0, 0, 0, "default").unwrap().unwrap();
    assert!(raw.iter().all(|v| !v.is_nan()));
    assert!(default_without_weight.iter().any(|&v| v > 0.0));
    assert_eq!(tiles.tile(2, 0, 0, "default").unwrap(), None);
    assert!(tiles.tile(1, u64::MAX / 2, 0, "default").is_err());
}

/// A BED file's tiles against clodius' `bedfile` tiles: the same records in each tile (every
/// zoom level: the first, a middle and the last tile), each with clodius' xStart, xEnd,
/// chrOffset and typed fields; the same tileset_info.
#[test]
fn bed_intervals_equal_clodius() {
    let path = format!("{DATA}/tiles/domains.bed.gz");
    let table = crate::io::bed::read_bed_table(std::path::Path::new(&path)).unwrap();
    let cool = tileset("cooler_test_file.mcool");
    let chroms = cool.reader(0).unwrap().bins().chroms().to_vec();
    let bed = Intervals::new(&chroms, &table.fields, &path).unwrap();
    assert_eq!(bed.info(), reference("domains.bed", "tileset_info"));
    let expected = reference("domains.bed", "tiles");
    let records = &expected["records"];
    let mut compared = 0;
    for (id, uids) in expected["tiles"].as_object().unwrap() {
        let (z, x) = id.split_once('.').unwrap();
        let tile = bed.tile(z.parse().unwrap(), x.parse().unwrap());
        let got: Vec<u64> = tile
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["uid"].as_u64().unwrap())
            .collect();
        let want: Vec<u64> = uids
            .as_array()
            .unwrap()
            .iter()
            .map(|u| u.as_u64().unwrap())
            .collect();
        assert_eq!(got, want, "tile {id}");
        for record in tile.as_array().unwrap() {
            let mut record = record.clone();
            let importance = record
                .as_object_mut()
                .unwrap()
                .remove("importance")
                .unwrap();
            assert!((0.0..1.0).contains(&importance.as_f64().unwrap()));
            let uid = record.as_object_mut().unwrap().remove("uid").unwrap();
            let mut want = records[uid.to_string()].clone();
            // clodius passes the table through pandas' JSON (to_json, read_json), which turns a
            // score of 5.706 into 5.7059999999999995: the values are compared to 1e-12
            for (got, want) in record["fields"]
                .as_array()
                .unwrap()
                .iter()
                .zip(want["fields"].as_array_mut().unwrap())
            {
                if let (Some(g), Some(w)) = (got.as_f64(), want.as_f64()) {
                    if got.is_f64() && (g - w).abs() <= 1e-12 * w.abs() {
                        *want = got.clone();
                    }
                }
            }
            assert_eq!(record, want, "tile {id} record {uid}");
            compared += 1;
        }
    }
    assert!(compared > 1000, "{compared}");
}

/// Past 1,024 records a tile keeps the 1,024 most important, the same ones on every request;
/// a chromosome the map lacks is an error naming the record.
#[test]
fn crowded_interval_tiles_keep_the_most_important() {
    let chroms = vec![crate::genome::Chrom::new("chr1", 1_000_000)];
    let records: Vec<Vec<String>> = (0..3000)
        .map(|k| {
            vec![
                "chr1".into(),
                (k * 300).to_string(),
                (k * 300 + 10).to_string(),
            ]
        })
        .collect();
    let bed = Intervals::new(&chroms, &records, "many.bed").unwrap();
    let tile = bed.tile(0, 0);
    let kept = tile.as_array().unwrap();
    assert_eq!(kept.len(), MAX_PER_TILE);
    assert_eq!(tile, bed.tile(0, 0));
    let least_kept = kept
        .iter()
        .map(|r| r["importance"].as_f64().unwrap())
        .fold(f64::INFINITY, f64::min);
    let all = bed.tile(12, 0).as_array().unwrap().len() + bed.tile(1, 1).as_array().unwrap().len();
    assert!(all > 0 && least_kept > 0.5, "{least_kept}");
    let bad = vec![vec!["chrZ".to_string(), "1".into(), "2".into()]];
    let err = Intervals::new(&chroms, &bad, "z.bed")
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("z.bed: record 1: chromosome 'chrZ'"), "{err}");
}

/// A bedGraph's vector tiles against clodius' bigWig tiles of the same intervals (pyBigWig wrote
/// the bigWig, pybigtools summarised it): every zoom level's first, middle and last tile and the
/// one at chr4's start, in each aggregation mode: the same dtype, bytes, NaN count and length
/// (clodius' joins give 1,025 values to some tiles).
#[test]
fn vector_tiles_equal_clodius_bigwig_tiles() {
    let path = format!("{DATA}/tiles/track.bedgraph.gz");
    let table = crate::io::bed::read_bed_table(std::path::Path::new(&path)).unwrap();
    let records: Vec<(String, u64, u64, f64)> = table
        .fields
        .iter()
        .map(|f| {
            (
                f[0].clone(),
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
                f[3].parse().unwrap(),
            )
        })
        .collect();
    let cool = tileset("cooler_test_file.mcool");
    let chroms = cool.reader(0).unwrap().bins().chroms().to_vec();
    let track = Vector::new(&chroms, &records, &path).unwrap();
    assert_eq!(track.info(), reference("track.bedgraph", "tileset_info"));
    let Value::Object(expected) = reference("track.bedgraph", "tiles") else {
        panic!()
    };
    let mut float16 = 0;
    for (id, want) in &expected {
        let parts: Vec<&str> = id.split('.').collect();
        let mode = Aggregation::parse(parts.get(2).copied()).unwrap();
        let values = track
            .tile(parts[0].parse().unwrap(), parts[1].parse().unwrap(), mode)
            .unwrap()
            .unwrap();
        let mut got = single(&digest(&dense_json(&values)));
        got["length"] = values.len().into();
        assert_eq!(got, single(want), "tile {id}");
        float16 += usize::from(want["dtype"] == "float16");
    }
    assert!(expected.len() > 200 && float16 > 0);
    assert!(track.tile(99, 0, Aggregation::Mean).unwrap().is_none());
    assert!(Aggregation::parse(Some("std")).is_err());
}

/// A BEDPE file's tiles against clodius' `bedpe` tiles: the same records in each 2D tile (the
/// diagonal's first, middle and last, and beside it) and 1D tile, with clodius' positions,
/// offsets and typed fields; the same tileset_info (its header line included).
#[test]
fn bedpe_rectangles_equal_clodius() {
    let path = format!("{DATA}/tiles/dots.bedpe.gz");
    let table = crate::io::bed::read_bedpe_table(std::path::Path::new(&path)).unwrap();
    let fields: Vec<Vec<String>> = table.records.iter().map(|r| r.fields()).collect();
    let cool = tileset("cooler_test_file.mcool");
    let chroms = cool.reader(0).unwrap().bins().chroms().to_vec();
    let dots = Rectangles::new(&chroms, &fields, table.header.as_deref(), &path).unwrap();
    assert_eq!(dots.info(), reference("dots.bedpe", "tileset_info"));
    let expected = reference("dots.bedpe", "tiles");
    let mut compared = 0;
    for (id, uids) in expected["tiles"].as_object().unwrap() {
        let parts: Vec<u64> = id.split('.').map(|p| p.parse().unwrap()).collect();
        let tile = dots.tile(parts[0] as u32, parts[1], parts.get(2).copied());
        let got: Vec<&Value> = tile.as_array().unwrap().iter().map(|r| &r["uid"]).collect();
        let want: Vec<&Value> = uids.as_array().unwrap().iter().collect();
        assert_eq!(got, want, "tile {id}");
        for record in tile.as_array().unwrap() {
            let mut record = record.clone();
            let object = record.as_object_mut().unwrap();
            assert!((0.0..1.0).contains(&object.remove("importance").unwrap().as_f64().unwrap()));
            let uid = object.remove("uid").unwrap();
            assert_eq!(
                record,
                expected["records"][uid.to_string()],
                "tile {id} record {uid}"
            );
            compared += 1;
        }
    }
    assert!(compared > 500, "{compared}");
}
