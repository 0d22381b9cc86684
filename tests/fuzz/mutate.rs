//! The mutation engine of the fuzz harness: turns a real fixture into a corrupt variant, reproducibly
//! from a seed.
//!
//! Shared by the CI test (`tests/fuzz.rs`) and the campaign driver (`examples/fuzz_campaign.rs`),
//! which include this file with `#[path = ...]`; it is not part of the library.
//!
//! Every mutant applies one to four mutations, each drawn from the operators of the seed's kind:
//!
//! - bytes (every format): a bit flip; a byte overwritten with an interesting value (0, 0xff, 0x7f,
//!   0x80, 1); 2, 4 or 8 bytes overwritten with an interesting integer (0, -1, 1, the i16 / i32 / i64
//!   extremes, a large length such as 0x7fff_fff0), little- or big-endian; truncation; deletion,
//!   duplication or insertion (random or copied bytes) of a range. Half of the positions are drawn
//!   in the first 4 KiB and in the last 1 KiB, where the headers, superblocks and footers live.
//! - lines (text formats): delete, duplicate or swap lines; replace a field with NaN, inf, -1, a
//!   huge number, nothing or garbage; overwrite a fixed-width column range (PDB) with such a value,
//!   padded to the same width; change the delimiter of a line; truncate mid-line; gzip the result
//!   (sometimes cut short).
//! - `.npy` headers (a `.npy` file, or a member of an `.npz`): a number of the header's text (a
//!   dimension of the shape, the width of the `descr`) replaced by 0, -1, a huge or an overflowing
//!   value, or a shape entry added or removed, the header's length field kept consistent.
//! - zip members (`.npz`): the archive unpacked, one member mutated with the byte operators (biased
//!   to its `.npy` header) and repacked stored or deflated; or the archive's own bytes mutated.

use std::io::{Read, Write};

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// How a seed file is mutated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Binary container (HDF5, .hic, .npy): byte operators only.
    Binary,
    /// Text (tables, pairs, PDB, mmCIF, RR, matrices): line operators, with some byte operators.
    Text,
    /// A zip archive of `.npy` members (`.npz`).
    Zip,
    /// A BGZF file (BAM) held inflated: byte operators on its content, then deflated again as
    /// BGZF blocks (with their checksums right, so that the mutations reach the records), now
    /// and then cut short.
    Bgzf,
}

/// The random generator of mutant number `index` of format `format` in a campaign seeded with
/// `seed`: the same triple always gives the same mutant.
pub fn mutant_rng(seed: u64, format: &str, index: u64) -> Xoshiro256PlusPlus {
    // FNV-1a of the format name, so that formats of one campaign draw different streams.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in format.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ h);
    for _ in 0..(index % 64) {
        rng.jump();
    }
    Xoshiro256PlusPlus::seed_from_u64(
        rng.r#gen::<u64>() ^ index.wrapping_mul(0x9e37_79b9_7f4a_7c15),
    )
}

/// Mutate `input` (a seed of kind `kind`) with 1 to 4 mutations; returns the mutant and one short
/// description per mutation applied.
pub fn mutate(input: &[u8], kind: Kind, rng: &mut Xoshiro256PlusPlus) -> (Vec<u8>, Vec<String>) {
    let mut data = input.to_vec();
    let mut log = Vec::new();
    let count = rng.gen_range(1..=4);
    for _ in 0..count {
        let note = match kind {
            Kind::Binary if data.starts_with(b"\x93NUMPY") && rng.gen_bool(0.3) => {
                mutate_npy_header(&mut data, rng)
            }
            Kind::Binary => mutate_bytes(&mut data, rng, 4096),
            Kind::Text => {
                if rng.gen_bool(0.8) {
                    mutate_lines(&mut data, rng)
                } else {
                    mutate_bytes(&mut data, rng, 4096)
                }
            }
            Kind::Zip => {
                if rng.gen_bool(0.75) {
                    mutate_zip_member(&mut data, rng)
                } else {
                    mutate_bytes(&mut data, rng, 4096)
                }
            }
            Kind::Bgzf => mutate_bytes(&mut data, rng, 256),
        };
        log.push(note);
    }
    if kind == Kind::Bgzf {
        let mut writer = noodles::bgzf::io::Writer::new(Vec::new());
        writer.write_all(&data).expect("BGZF in memory");
        data = writer.finish().expect("BGZF in memory");
        if rng.gen_bool(0.1) && data.len() > 1 {
            let keep = rng.gen_range(0..data.len());
            data.truncate(keep);
            log.push(format!("BGZF, cut at {keep}"));
        }
    }
    if kind == Kind::Text && rng.gen_bool(0.08) {
        let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        encoder.write_all(&data).expect("gzip in memory");
        data = encoder.finish().expect("gzip in memory");
        if rng.gen_bool(0.5) && data.len() > 1 {
            let keep = rng.gen_range(0..data.len());
            data.truncate(keep);
            log.push(format!("gzip, cut at {keep}"));
        } else {
            log.push("gzip".into());
        }
    }
    (data, log)
}

/// Integers worth writing over a length, an offset or a count.
const INTERESTING: [i64; 16] = [
    0,
    1,
    -1,
    2,
    0x7f,
    0xff,
    0x7fff,
    -0x8000,
    0xffff,
    0x7fff_ffff,
    -0x8000_0000,
    0xffff_ffff,
    0x7fff_fff0,
    0x1_0000_0000,
    i64::MAX,
    i64::MIN,
];

/// A position in `0..len`: half the time in the first `head` bytes or the last 1 KiB.
fn position(rng: &mut Xoshiro256PlusPlus, len: usize, head: usize) -> usize {
    if len == 0 {
        return 0;
    }
    if rng.gen_bool(0.5) {
        if rng.gen_bool(0.75) {
            rng.gen_range(0..len.min(head).max(1))
        } else {
            rng.gen_range(len.saturating_sub(1024)..len)
        }
    } else {
        rng.gen_range(0..len)
    }
}

/// A range length: mostly short, sometimes long.
fn span(rng: &mut Xoshiro256PlusPlus, max: usize) -> usize {
    if max == 0 {
        return 0;
    }
    let limit = if rng.gen_bool(0.8) { 16 } else { 4096 };
    rng.gen_range(1..=limit.min(max))
}

/// One byte-level mutation; `head` is the size of the region favoured at the start.
pub fn mutate_bytes(data: &mut Vec<u8>, rng: &mut Xoshiro256PlusPlus, head: usize) -> String {
    if data.is_empty() {
        data.push(rng.r#gen());
        return "insert 1 byte into an empty file".into();
    }
    let len = data.len();
    let at = position(rng, len, head);
    match rng.gen_range(0..9) {
        0 => {
            let bit = rng.gen_range(0..8);
            data[at] ^= 1 << bit;
            format!("flip bit {bit} at {at}")
        }
        1 => {
            let value = [0u8, 0xff, 0x7f, 0x80, 1][rng.gen_range(0..5)];
            data[at] = value;
            format!("byte {value:#04x} at {at}")
        }
        2 => {
            let width = [2usize, 4, 8][rng.gen_range(0..3)];
            let value = INTERESTING[rng.gen_range(0..INTERESTING.len())];
            let le = rng.gen_bool(0.7);
            let bytes = if le {
                value.to_le_bytes()
            } else {
                value.to_be_bytes()
            };
            let bytes = if le {
                &bytes[..width]
            } else {
                &bytes[8 - width..]
            };
            let end = (at + width).min(len);
            data[at..end].copy_from_slice(&bytes[..end - at]);
            let order = if le { "le" } else { "be" };
            format!("{width}-byte {order} {value} at {at}")
        }
        3 => {
            data.truncate(at);
            format!("truncate at {at}")
        }
        4 => {
            let n = span(rng, len - at);
            data.drain(at..at + n);
            format!("delete {n} bytes at {at}")
        }
        5 => {
            let n = span(rng, len - at);
            let copy = data[at..at + n].to_vec();
            data.splice(at..at, copy);
            format!("duplicate {n} bytes at {at}")
        }
        6 => {
            let n = span(rng, 64);
            let bytes: Vec<u8> = (0..n).map(|_| rng.r#gen()).collect();
            data.splice(at..at, bytes);
            format!("insert {n} random bytes at {at}")
        }
        7 => {
            let from = rng.gen_range(0..len);
            let n = span(rng, (len - from).min(len - at));
            let copy = data[from..from + n].to_vec();
            data[at..at + n].copy_from_slice(&copy);
            format!("copy {n} bytes from {from} over {at}")
        }
        _ => {
            let n = span(rng, len - at);
            for b in &mut data[at..at + n] {
                *b = rng.r#gen();
            }
            format!("randomise {n} bytes at {at}")
        }
    }
}

/// Values written over a field.
const FIELDS: [&str; 22] = [
    "NaN",
    "nan",
    "inf",
    "-inf",
    "-1",
    "0",
    "-0",
    "1e308",
    "1e-320",
    "99999999999999999999999",
    "18446744073709551616",
    "2147483648",
    "-9223372036854775809",
    "4294967296",
    "",
    "x",
    "1.5.3",
    "0x10",
    "\u{fffd}",
    "chrUn_\u{00e9}",
    "\"",
    "#",
];

/// Split `data` into lines, each with its terminator.
fn lines(data: &[u8]) -> Vec<Vec<u8>> {
    data.split_inclusive(|&b| b == b'\n')
        .map(<[u8]>::to_vec)
        .collect()
}

/// One line-level mutation of a text file.
pub fn mutate_lines(data: &mut Vec<u8>, rng: &mut Xoshiro256PlusPlus) -> String {
    let mut rows = lines(data);
    if rows.is_empty() {
        return mutate_bytes(data, rng, 4096);
    }
    // Favour the first lines (headers, sequence lines, the first records).
    let pick = |rng: &mut Xoshiro256PlusPlus, n: usize| {
        if rng.gen_bool(0.4) {
            rng.gen_range(0..n.min(20))
        } else {
            rng.gen_range(0..n)
        }
    };
    let n = rows.len();
    let i = pick(rng, n);
    let note = match rng.gen_range(0..8) {
        0 => {
            rows.remove(i);
            format!("delete line {}", i + 1)
        }
        1 => {
            let copies = if rng.gen_bool(0.8) { 1 } else { 50 };
            for _ in 0..copies {
                rows.insert(i, rows[i].clone());
            }
            format!("duplicate line {} x{copies}", i + 1)
        }
        2 => {
            let j = pick(rng, n);
            rows.swap(i, j);
            format!("swap lines {} and {}", i + 1, j + 1)
        }
        3 | 4 => {
            let value = FIELDS[rng.gen_range(0..FIELDS.len())];
            let (row, k) = replace_field(&rows[i], value, rng);
            rows[i] = row;
            format!("line {} field {k} = {value:?}", i + 1)
        }
        5 => {
            // A fixed-width overwrite keeps the other columns in place (PDB records).
            let value = FIELDS[rng.gen_range(0..FIELDS.len())].as_bytes();
            let row = &mut rows[i];
            let body = row.len() - usize::from(row.last() == Some(&b'\n'));
            if body == 0 {
                return "no-op on an empty line".into();
            }
            let at = rng.gen_range(0..body);
            let width = rng.gen_range(1..=8).min(body - at);
            let mut field = value.to_vec();
            field.resize(width, b' ');
            row[at..at + width].copy_from_slice(&field[..width]);
            format!(
                "line {} columns {}-{} = {:?}",
                i + 1,
                at + 1,
                at + width,
                String::from_utf8_lossy(&field)
            )
        }
        6 => {
            let (from, to): (&[u8], &[u8]) = match rng.gen_range(0..4) {
                0 => (b"\t", b" "),
                1 => (b"\t", b","),
                2 => (b" ", b"\t"),
                _ => (b" ", b""),
            };
            let row = &rows[i];
            let mut out = Vec::with_capacity(row.len());
            let mut k = 0;
            while k < row.len() {
                if row[k..].starts_with(from) {
                    out.extend_from_slice(to);
                    k += from.len();
                } else {
                    out.push(row[k]);
                    k += 1;
                }
            }
            rows[i] = out;
            format!(
                "line {} delimiter {:?} -> {:?}",
                i + 1,
                String::from_utf8_lossy(from),
                String::from_utf8_lossy(to)
            )
        }
        _ => {
            let row = &mut rows[i];
            let cut = rng.gen_range(0..row.len().max(1));
            row.truncate(cut);
            rows.truncate(i + 1);
            format!("truncate at line {} column {}", i + 1, cut + 1)
        }
    };
    *data = rows.concat();
    note
}

/// `row` with its `k`-th whitespace- or comma-separated field replaced by `value`; returns the row
/// and `k` (1-based).
fn replace_field(row: &[u8], value: &str, rng: &mut Xoshiro256PlusPlus) -> (Vec<u8>, usize) {
    let is_sep = |b: u8| b == b' ' || b == b'\t' || b == b',' || b == b'\n' || b == b'\r';
    let mut fields = Vec::new();
    let mut start = None;
    for (k, &b) in row.iter().enumerate() {
        match (is_sep(b), start) {
            (false, None) => start = Some(k),
            (true, Some(s)) => {
                fields.push((s, k));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        fields.push((s, row.len()));
    }
    if fields.is_empty() {
        let mut out = value.as_bytes().to_vec();
        out.extend_from_slice(row);
        return (out, 1);
    }
    let k = rng.gen_range(0..fields.len());
    let (s, e) = fields[k];
    let mut out = row[..s].to_vec();
    out.extend_from_slice(value.as_bytes());
    out.extend_from_slice(&row[e..]);
    (out, k + 1)
}

/// Unpack a zip archive, mutate one member and repack it; falls back to a byte mutation when the
/// archive does not open (an earlier mutation broke it).
pub fn mutate_zip_member(data: &mut Vec<u8>, rng: &mut Xoshiro256PlusPlus) -> String {
    let Ok(mut archive) = zip::ZipArchive::new(std::io::Cursor::new(data.clone())) else {
        return mutate_bytes(data, rng, 4096);
    };
    let mut members = Vec::new();
    for k in 0..archive.len() {
        let Ok(mut file) = archive.by_index(k) else {
            return mutate_bytes(data, rng, 4096);
        };
        let name = file.name().to_string();
        let mut bytes = Vec::new();
        if file.read_to_end(&mut bytes).is_err() {
            return mutate_bytes(data, rng, 4096);
        }
        members.push((name, bytes));
    }
    if members.is_empty() {
        return mutate_bytes(data, rng, 4096);
    }
    let k = rng.gen_range(0..members.len());
    let inner = if members[k].1.starts_with(b"\x93NUMPY") && rng.gen_bool(0.4) {
        mutate_npy_header(&mut members[k].1, rng)
    } else {
        mutate_bytes(&mut members[k].1, rng, 160)
    };
    let method = if rng.gen_bool(0.5) {
        zip::CompressionMethod::Stored
    } else {
        zip::CompressionMethod::Deflated
    };
    let mut writer = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default().compression_method(method);
    for (name, bytes) in &members {
        writer
            .start_file(name.as_str(), options)
            .expect("zip in memory");
        writer.write_all(bytes).expect("zip in memory");
    }
    *data = writer.finish().expect("zip in memory").into_inner();
    format!("member {} ({method:?}): {inner}", members[k].0)
}

/// Numbers written into a `.npy` header.
const NPY_NUMBERS: [&str; 10] = [
    "0",
    "-1",
    "1",
    "65536",
    "3000000",
    "4294967296",
    "9223372036854775807",
    "18446744073709551615",
    "18446744073709551616",
    "",
];

/// Rewrite a number in the text header of a `.npy` file (version 1: 2-byte length at offset 8),
/// keeping the length field consistent with the new header; or add / drop a shape entry.
pub fn mutate_npy_header(data: &mut Vec<u8>, rng: &mut Xoshiro256PlusPlus) -> String {
    if data.len() < 10 || data[6] != 1 {
        return mutate_bytes(data, rng, 160);
    }
    let length = usize::from(u16::from_le_bytes([data[8], data[9]]));
    let Some(header) = data.get(10..10 + length) else {
        return mutate_bytes(data, rng, 160);
    };
    let header = header.to_vec();
    let digits: Vec<(usize, usize)> = {
        let mut runs = Vec::new();
        let mut k = 0;
        while k < header.len() {
            if header[k].is_ascii_digit() {
                let start = k;
                while k < header.len() && header[k].is_ascii_digit() {
                    k += 1;
                }
                runs.push((start, k));
            } else {
                k += 1;
            }
        }
        runs
    };
    let (new_header, note) = if digits.is_empty() || rng.gen_bool(0.2) {
        // Add or drop a dimension.
        let text = String::from_utf8_lossy(&header).into_owned();
        let Some(open) = text.find("'shape': (") else {
            return mutate_bytes(data, rng, 160);
        };
        let at = open + "'shape': (".len();
        if rng.gen_bool(0.5) {
            let mut t = text.clone();
            t.insert_str(at, "7, ");
            (t.into_bytes(), "npy header: add a shape entry".to_string())
        } else {
            let end = text[at..].find([',', ')']).map_or(at, |e| at + e + 1);
            let mut t = text.clone();
            t.replace_range(at..end.min(t.len()), "");
            (t.into_bytes(), "npy header: drop a shape entry".to_string())
        }
    } else {
        let (start, end) = digits[rng.gen_range(0..digits.len())];
        let value = NPY_NUMBERS[rng.gen_range(0..NPY_NUMBERS.len())];
        let mut h = header[..start].to_vec();
        h.extend_from_slice(value.as_bytes());
        h.extend_from_slice(&header[end..]);
        let old = String::from_utf8_lossy(&header[start..end]).into_owned();
        (h, format!("npy header: {old} -> {value:?}"))
    };
    let Ok(new_length) = u16::try_from(new_header.len()) else {
        return mutate_bytes(data, rng, 160);
    };
    let mut out = data[..8].to_vec();
    out.extend_from_slice(&new_length.to_le_bytes());
    out.extend_from_slice(&new_header);
    out.extend_from_slice(&data[10 + length..]);
    *data = out;
    note
}
