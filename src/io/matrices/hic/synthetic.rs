//! A test-only `.hic` writer that follows the specification: small version 8 and 9 files with
//! every block layout, to test the reader against.

use std::collections::BTreeMap;
use std::io::Write;

use flate2::Compression;
use flate2::write::ZlibEncoder;

use crate::genome::{BinTable, Chrom};

/// Little-endian writer.
#[derive(Default)]
pub(super) struct Out(pub(super) Vec<u8>);

impl Out {
    pub(super) fn len(&self) -> u64 {
        self.0.len() as u64
    }
    pub(super) fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    pub(super) fn i16(&mut self, v: i16) {
        self.0.extend(v.to_le_bytes());
    }
    pub(super) fn i32(&mut self, v: i64) {
        self.0.extend(i32::try_from(v).unwrap().to_le_bytes());
    }
    pub(super) fn i64(&mut self, v: i64) {
        self.0.extend(v.to_le_bytes());
    }
    pub(super) fn f32(&mut self, v: f32) {
        self.0.extend(v.to_le_bytes());
    }
    pub(super) fn f64(&mut self, v: f64) {
        self.0.extend(v.to_le_bytes());
    }
    /// `int` in version 8, `long` in version 9.
    pub(super) fn int_or_long(&mut self, version: i32, v: i64) {
        if version >= 9 {
            self.i64(v)
        } else {
            self.i32(v)
        }
    }
    /// `double` in version 8, `float` in version 9.
    pub(super) fn value(&mut self, version: i32, v: f64) {
        if version >= 9 {
            self.f32(v as f32)
        } else {
            self.f64(v)
        }
    }
    /// A bin position or count as `int` (wide) or `short`.
    pub(super) fn position(&mut self, wide: bool, v: u64) {
        if wide {
            self.i32(v as i64)
        } else {
            self.i16(i16::try_from(v).unwrap())
        }
    }
    pub(super) fn string(&mut self, s: &str) {
        self.0.extend(s.as_bytes());
        self.0.push(0);
    }
    pub(super) fn patch_i64(&mut self, at: u64, v: i64) {
        self.0[at as usize..at as usize + 8].copy_from_slice(&v.to_le_bytes());
    }
    pub(super) fn patch_i32(&mut self, at: u64, v: i64) {
        let v = i32::try_from(v).unwrap();
        self.0[at as usize..at as usize + 4].copy_from_slice(&v.to_le_bytes());
    }
}

/// A divisive vector: normalisation name, chromosome, values.
pub(super) type NormSpec = (&'static str, usize, Vec<f64>);
/// One resolution: bin size, upper-triangle pixels (genome-wide bins), vectors.
pub(super) type Level = (u64, BTreeMap<(u64, u64), f32>, Vec<NormSpec>);

/// A small genome with pixels at two resolutions and a few normalisation vectors.
pub(super) struct Synthetic {
    pub(super) version: i32,
    pub(super) chroms: Vec<Chrom>,
    pub(super) block_bin_count: u64,
    pub(super) levels: Vec<Level>,
    /// Store intra-chromosomal records with x >= y (the other triangle).
    pub(super) intra_lower: bool,
    /// Store intra-chromosomal off-diagonal pixels in both triangles, the second record with
    /// [`MIRROR_EXTRA`] added to its count (a reader that keeps it is seen).
    pub(super) both_triangles: bool,
    /// Extra records at the first resolution, `(chrom1, chrom2, x, y, count)` in the matrix's own
    /// bins, written as they are (records past a chromosome's end, for instance).
    pub(super) extra_records: Vec<(usize, usize, u64, u64, f32)>,
}

/// What [`Synthetic::both_triangles`] adds to the count of the second record of a pixel.
pub(super) const MIRROR_EXTRA: f32 = 1000.0;

pub(super) fn synthetic(version: i32) -> Synthetic {
    let chroms = vec![
        Chrom::new("c1", 365),
        Chrom::new("c2", 230),
        Chrom::new("c3", 41),
    ];
    let fine = BinTable::fixed(chroms.clone(), 10).unwrap();
    let coarse = BinTable::fixed(chroms.clone(), 20).unwrap();
    let mut state = 0x9E37_79B9_7F4A_7C15u64 ^ version as u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let n = fine.n_bins() as u64;
    let mut pixels = BTreeMap::new();
    for i in 0..n {
        for j in i..n {
            let (ci, cj) = (fine.chrom_of(i as usize), fine.chrom_of(j as usize));
            let p = if ci == cj {
                0.7 / (1.0 + (j - i) as f64 / 6.0)
            } else {
                0.1
            };
            if (next() % 1000) as f64 >= p * 1000.0 {
                continue;
            }
            let count = match next() % 50 {
                0 => 40_000.0,        // too large for a short: a float block
                1 if ci != cj => 2.5, // not a whole number: a float block
                k => (k % 17 + 1) as f32,
            };
            pixels.insert((i, j), count);
        }
    }
    let mut coarse_pixels: BTreeMap<(u64, u64), f32> = BTreeMap::new();
    for (&(i, j), &v) in &pixels {
        let to_coarse = |b: u64| {
            let chrom = fine.chrom_of(b as usize);
            let local = b as usize - fine.chrom_bins(chrom).start;
            (coarse.chrom_bins(chrom).start + local / 2) as u64
        };
        *coarse_pixels
            .entry((to_coarse(i), to_coarse(j)))
            .or_default() += v;
    }
    let vector = |n: usize, seed: u64| -> Vec<f64> {
        (0..n)
            .map(|k| match (k as u64 + seed) % 11 {
                0 => 0.0, // masked: NaN after inversion
                r => 0.5 + r as f64 / 8.0,
            })
            .collect()
    };
    let fine_norms = vec![
        ("KR", 0, vector(37, 1)),
        ("KR", 1, vector(23, 2)),
        ("VC", 0, vector(37, 3)),
        ("VC", 1, vector(23, 4)),
        ("VC", 2, vector(5, 5)),
    ];
    let coarse_norms = vec![("SCALE", 0, vector(19, 6))];
    Synthetic {
        version,
        chroms,
        block_bin_count: 4,
        levels: vec![(10, pixels, fine_norms), (20, coarse_pixels, coarse_norms)],
        intra_lower: version == 8,
        both_triangles: false,
        extra_records: Vec::new(),
    }
}

/// The block a record `(x, y)` belongs to, as the spec numbers blocks.
pub(super) fn block_number(rotated: bool, x: u64, y: u64, size: u64, columns: u64) -> u64 {
    if rotated {
        let along = (x + y) / 2 / size;
        let distance = (x as f64 - y as f64).abs();
        let depth = (1.0 + distance / std::f64::consts::SQRT_2 / size as f64).log2() as u64;
        depth * columns + along
    } else {
        (y / size) * columns + x / size
    }
}

/// One compressed block; the representation and field widths vary with the block number so
/// that every combination is written.
pub(super) fn encode_block(version: i32, number: u64, records: &[(u64, u64, f32)]) -> Vec<u8> {
    let x0 = records.iter().map(|r| r.0).min().unwrap();
    let y0 = records.iter().map(|r| r.1).min().unwrap();
    let short = !number.is_multiple_of(3)
        && records
            .iter()
            .all(|r| r.2.fract() == 0.0 && r.2.abs() <= 32_767.0);
    let dense = number % 4 == 1;
    let (wide_x, wide_y) = if version >= 9 {
        (number % 2 == 1, number / 2 % 2 == 1)
    } else {
        (false, false)
    };
    let mut raw = Out::default();
    raw.i32(records.len() as i64);
    raw.i32(x0 as i64);
    raw.i32(y0 as i64);
    raw.u8(u8::from(!short));
    if version >= 9 {
        raw.u8(u8::from(wide_x));
        raw.u8(u8::from(wide_y));
    }
    raw.u8(if dense { 2 } else { 1 });
    if dense {
        let width = records.iter().map(|r| r.0).max().unwrap() - x0 + 1;
        let height = records.iter().map(|r| r.1).max().unwrap() - y0 + 1;
        let mut grid = vec![None; (width * height) as usize];
        for &(x, y, v) in records {
            grid[((y - y0) * width + (x - x0)) as usize] = Some(v);
        }
        raw.i32((width * height) as i64);
        raw.i16(width as i16);
        for cell in grid {
            match (cell, short) {
                (Some(v), true) => raw.i16(v as i16),
                (None, true) => raw.i16(i16::MIN),
                (Some(v), false) => raw.f32(v),
                (None, false) => raw.f32(f32::NAN),
            }
        }
    } else {
        let mut rows: BTreeMap<u64, Vec<(u64, f32)>> = BTreeMap::new();
        for &(x, y, v) in records {
            rows.entry(y).or_default().push((x, v));
        }
        raw.position(wide_y, rows.len() as u64);
        for (y, cells) in rows {
            raw.position(wide_y, y - y0);
            raw.position(wide_x, cells.len() as u64);
            for (x, v) in cells {
                raw.position(wide_x, x - x0);
                if short {
                    raw.i16(v as i16);
                } else {
                    raw.f32(v);
                }
            }
        }
    }
    let mut encoder = ZlibEncoder::new(Vec::new(), Compression::default());
    encoder.write_all(&raw.0).unwrap();
    encoder.finish().unwrap()
}

pub(super) fn write_hic(s: &Synthetic) -> Vec<u8> {
    write_hic_with_offsets(s).0
}

/// Where [`write_hic_with_offsets`] wrote some header, footer and index fields, by name.
pub(super) type Offsets = std::collections::HashMap<&'static str, u64>;

/// The file, and the offsets of the fields that size allocations or loops in a reader (the
/// first occurrence of each), for corruption tests.
pub(super) fn write_hic_with_offsets(s: &Synthetic) -> (Vec<u8>, Offsets) {
    let version = s.version;
    let mut out = Out::default();
    let mut at = Offsets::new();
    let mut mark = |name: &'static str, offset: u64| {
        at.entry(name).or_insert(offset);
    };
    out.0.extend(b"HIC\0");
    out.i32(version.into());
    let footer_slot = out.len();
    mark("footer_position", out.len());
    out.i64(0);
    mark("genome_id", out.len());
    out.string("synthetic");
    let index_slot = out.len();
    if version >= 9 {
        out.i64(0);
        out.i64(0);
    }
    mark("n_attributes", out.len());
    out.i32(2);
    out.string("software");
    out.string("contactmap test writer");
    out.string("hicFileScalingFactor");
    out.string("1.0");
    mark("n_chroms", out.len());
    out.i32(s.chroms.len() as i64 + 1);
    out.string("All");
    out.int_or_long(version, 1);
    for chrom in &s.chroms {
        out.string(&chrom.name);
        mark("chrom_length", out.len());
        out.int_or_long(version, chrom.length_bp as i64);
    }
    mark("n_resolutions", out.len());
    out.i32(s.levels.len() as i64);
    for level in &s.levels {
        mark("resolution", out.len());
        out.i32(level.0 as i64);
    }
    out.i32(0); // fragment resolutions

    // The "All" matrix: one level at another bin size, no blocks.
    let mut master: Vec<(String, u64, u64)> = Vec::new();
    let start = out.len();
    for v in [0, 0, 1] {
        out.i32(v);
    }
    out.string("BP");
    out.i32(0);
    out.f32(0.0);
    out.i32(0);
    out.f32(0.0);
    out.f32(0.0);
    for v in [1, 1, 1, 0] {
        out.i32(v);
    }
    master.push(("0_0".into(), start, out.len() - start));

    let size = s.block_bin_count;
    for c1 in 0..s.chroms.len() {
        for c2 in c1..s.chroms.len() {
            let mut metadata = Vec::new();
            for (level, (resolution, pixels, _)) in s.levels.iter().enumerate() {
                let table = BinTable::fixed(s.chroms.clone(), *resolution).unwrap();
                let (o1, o2) = (
                    table.chrom_bins(c1).start as u64,
                    table.chrom_bins(c2).start as u64,
                );
                let (n1, n2) = (
                    table.chrom_bins(c1).len() as u64,
                    table.chrom_bins(c2).len() as u64,
                );
                let intra = c1 == c2;
                let rotated = intra && version >= 9;
                let columns = if rotated {
                    n1 / size + 1
                } else {
                    n1.max(n2) / size + 1
                };
                let mut blocks: BTreeMap<u64, Vec<(u64, u64, f32)>> = BTreeMap::new();
                let mut sum = 0.0;
                for (&(i, j), &v) in pixels {
                    let (ci, cj) = (table.chrom_of(i as usize), table.chrom_of(j as usize));
                    if (ci, cj) != (c1, c2) {
                        continue;
                    }
                    let (mut x, mut y) = (i - o1, j - o2);
                    if intra && s.intra_lower {
                        std::mem::swap(&mut x, &mut y);
                    }
                    let number = block_number(rotated, x, y, size, columns);
                    blocks.entry(number).or_default().push((x, y, v));
                    sum += v;
                    if intra && s.both_triangles && x != y {
                        let number = block_number(rotated, y, x, size, columns);
                        blocks
                            .entry(number)
                            .or_default()
                            .push((y, x, v + MIRROR_EXTRA));
                    }
                }
                for &(e1, e2, x, y, v) in &s.extra_records {
                    if level == 0 && (e1, e2) == (c1, c2) {
                        let number = block_number(rotated, x, y, size, columns);
                        blocks.entry(number).or_default().push((x, y, v));
                    }
                }
                let mut entries = Vec::new();
                for (number, records) in &blocks {
                    let bytes = encode_block(version, *number, records);
                    entries.push((*number, out.len(), bytes.len() as u64));
                    out.0.extend(bytes);
                }
                metadata.push((level, *resolution, columns, sum, entries));
            }
            if metadata.iter().all(|m| m.4.is_empty()) {
                continue;
            }
            let start = out.len();
            out.i32(c1 as i64 + 1);
            out.i32(c2 as i64 + 1);
            mark("n_levels", out.len());
            out.i32(metadata.len() as i64);
            for (level, resolution, columns, sum, entries) in metadata {
                out.string("BP");
                out.i32(level as i64);
                out.f32(sum);
                out.i32(0);
                out.f32(0.0);
                out.f32(0.0);
                out.i32(resolution as i64);
                mark("block_bin_count", out.len());
                out.i32(size as i64);
                mark("block_column_count", out.len());
                out.i32(columns as i64);
                mark("n_blocks", out.len());
                out.i32(entries.len() as i64);
                for (number, position, bytes) in entries {
                    mark("block_number", out.len());
                    out.i32(number as i64);
                    mark("block_position", out.len());
                    out.i64(position as i64);
                    mark("block_size", out.len());
                    out.i32(bytes as i64);
                }
            }
            master.push((format!("{}_{}", c1 + 1, c2 + 1), start, out.len() - start));
        }
    }

    // Footer: master index, expected values, normalised expected values, vector index.
    let footer = out.len();
    out.patch_i64(footer_slot, footer as i64);
    out.int_or_long(version, 0); // nBytes, patched below
    mark("master_n_entries", out.len());
    out.i32(master.len() as i64);
    for (key, position, bytes) in &master {
        out.string(key);
        mark("master_position", out.len());
        out.i64(*position as i64);
        out.i32(*bytes as i64);
    }
    mark("expected_n_vectors", out.len());
    out.i32(s.levels.len() as i64);
    for (resolution, _, _) in &s.levels {
        out.string("BP");
        out.i32(*resolution as i64);
        mark("expected_n_values", out.len());
        out.int_or_long(version, 3);
        for v in [10.0, 5.0, 2.5] {
            out.value(version, v);
        }
        mark("expected_n_factors", out.len());
        out.i32(1);
        out.i32(1);
        out.value(version, 1.5);
    }
    let n_bytes = out.len() - footer - if version >= 9 { 8 } else { 4 };
    if version >= 9 {
        out.patch_i64(footer, n_bytes as i64);
    } else {
        out.patch_i32(footer, n_bytes as i64);
    }
    mark("norm_expected_n_vectors", out.len());
    out.i32(s.levels.len() as i64);
    for (resolution, _, _) in &s.levels {
        out.string("VC");
        out.string("BP");
        out.i32(*resolution as i64);
        out.int_or_long(version, 2);
        out.value(version, 1.0);
        out.value(version, 0.5);
        out.i32(0);
    }
    let index_position = out.len();
    let vectors: Vec<(u64, &str, usize, &Vec<f64>)> = s
        .levels
        .iter()
        .flat_map(|(r, _, norms)| norms.iter().map(move |(n, c, v)| (*r, *n, *c, v)))
        .collect();
    mark("norm_index_n_entries", out.len());
    out.i32(vectors.len() as i64 + 1);
    let mut slots = Vec::new();
    for &(resolution, name, chrom, values) in &vectors {
        out.string(name);
        out.i32(chrom as i64 + 1);
        out.string("BP");
        out.i32(resolution as i64);
        mark("norm_vector_position", out.len());
        slots.push(out.len());
        out.i64(0);
        let (count_bytes, value_bytes) = if version >= 9 { (8, 4) } else { (4, 8) };
        out.int_or_long(
            version,
            count_bytes + (values.len() as i64 + 1) * value_bytes,
        );
    }
    // a fragment-unit vector, which the reader skips (it points nowhere)
    out.string("KR");
    out.i32(1);
    out.string("FRAG");
    out.i32(1);
    out.i64(0);
    out.int_or_long(version, 0);
    if version >= 9 {
        out.patch_i64(index_slot, index_position as i64);
        out.patch_i64(index_slot + 8, (out.len() - index_position) as i64);
    }
    for (slot, &(_, _, _, values)) in slots.into_iter().zip(&vectors) {
        out.patch_i64(slot, out.len() as i64);
        // one trailing value more than there are bins, as some writers leave
        mark("norm_vector_n_values", out.len());
        out.int_or_long(version, values.len() as i64 + 1);
        for &v in values.iter().chain([0.0].iter()) {
            out.value(version, v);
        }
    }
    (out.0, at)
}
