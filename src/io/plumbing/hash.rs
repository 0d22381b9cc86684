//! A fast hasher for the maps that readers fill once per record (chromosome names, pair types,
//! pixel keys): a splitmix64 finaliser over 8-byte words. The keys come from the user's own
//! files, not from an adversary, so SipHash's protection is not needed, and its cost is: a
//! tenth of `pairs dedup --output-stats`.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A `HashMap` with [`FastHasher`].
pub type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<FastHasher>>;

/// See the module notes.
#[derive(Default)]
pub struct FastHasher(u64);

impl Hasher for FastHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for chunk in &mut chunks {
            let mut word = [0u8; 8];
            word.copy_from_slice(chunk);
            self.write_u64(self.0 ^ u64::from_le_bytes(word));
        }
        // The last bytes are gathered into a register: copied into a stack word and loaded
        // back whole, they stalled the load (a third of `pairs sort`'s name lookups).
        let word = chunks
            .remainder()
            .iter()
            .rev()
            .fold(0u64, |word, &byte| word << 8 | u64::from(byte));
        self.write_u64(self.0 ^ word ^ (bytes.len() as u64) << 56);
    }

    // Lengths (of slices, before their bytes) and other integers are mixed in whole.
    fn write_usize(&mut self, value: usize) {
        self.write_u64(self.0 ^ value as u64);
    }

    fn write_u64(&mut self, value: u64) {
        let mut z = value.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        self.0 = z ^ (z >> 31);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_that_differ_hash_apart_and_the_map_finds_them() {
        let hash = |bytes: &[u8]| {
            let mut h = FastHasher::default();
            h.write(bytes);
            h.finish()
        };
        // Lengths and trailing zero bytes count: these would collide without the length.
        assert_ne!(hash(b"chr1"), hash(b"chr1\0"));
        assert_ne!(hash(b""), hash(b"\0"));
        assert_ne!(hash(b"chr1\tchr2"), hash(b"chr2\tchr1"));
        let mut map: FastMap<Vec<u8>, usize> = FastMap::default();
        let keys: Vec<Vec<u8>> = (0..10_000)
            .map(|i| format!("chr{i}").into_bytes())
            .collect();
        for (i, key) in keys.iter().enumerate() {
            map.insert(key.clone(), i);
        }
        assert!(keys.iter().enumerate().all(|(i, k)| map[k] == i));
    }

    #[test]
    fn the_last_bytes_are_read_as_a_zero_padded_little_endian_word() {
        // The reference: each 8-byte word, the last one zero-padded, read little-endian.
        let naive = |bytes: &[u8]| {
            let mut h = FastHasher::default();
            for chunk in bytes.chunks(8) {
                let mut word = [0u8; 8];
                word[..chunk.len()].copy_from_slice(chunk);
                let mut value = h.0 ^ u64::from_le_bytes(word);
                if chunk.len() < 8 {
                    value ^= (bytes.len() as u64) << 56;
                }
                h.write_u64(value);
            }
            if bytes.len().is_multiple_of(8) {
                h.write_u64(h.0 ^ (bytes.len() as u64) << 56);
            }
            h.finish()
        };
        let bytes: Vec<u8> = (0..40u32).map(|i| (i * 37 + 11) as u8 | 0x80).collect();
        for len in 0..bytes.len() {
            let mut h = FastHasher::default();
            h.write(&bytes[..len]);
            assert_eq!(h.finish(), naive(&bytes[..len]), "length {len}");
        }
    }
}
