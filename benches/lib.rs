//! Deterministic synthetic Hi-C matrices for the criterion benches: P(s) ~ s^-1.08 decay out to a
//! maximum diagonal with a fixed linear congruential noise, optional dead bins, sparse trans.

use contactmap::genome::{BinTable, Chrom};
use contactmap::matrix::{CountType, PixelBlock, Pixels};

/// Bin size of the synthetic matrices.
pub const BIN_SIZE: u64 = 10_000;

/// A 64-bit linear congruential generator (Knuth's MMIX constants).
pub struct Lcg(u64);

impl Lcg {
    /// A generator started at `seed`.
    pub fn new(seed: u64) -> Self {
        Lcg(seed)
    }

    /// The next number in [0, 1).
    pub fn next_unit(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) as f64 / (1u64 << 31) as f64
    }
}

/// The shape of a synthetic matrix.
pub struct Synthetic {
    /// Number of chromosomes.
    pub n_chroms: usize,
    /// Bins per chromosome.
    pub bins_per_chrom: u64,
    /// Pixels are generated for diagonals `0..max_diagonal`.
    pub max_diagonal: u64,
    /// Every bin `b` with `b % dead_every == 13` has no contacts.
    pub dead_every: Option<u64>,
    /// Trans pixels per row, to later chromosomes.
    pub trans_per_row: u64,
}

impl Synthetic {
    /// The bin table and the pixels, sorted by `(bin1, bin2)`.
    pub fn build(&self) -> (BinTable, PixelBlock) {
        let chroms = (0..self.n_chroms)
            .map(|c| Chrom::new(format!("chr{}", c + 1), self.bins_per_chrom * BIN_SIZE))
            .collect();
        let bins = BinTable::fixed(chroms, BIN_SIZE).expect("valid bins");
        let n = bins.n_bins() as u64;
        let mut random = Lcg::new(12345);
        let dead = |b: u64| self.dead_every.is_some_and(|k| b % k == 13);
        let mut block = PixelBlock::default();
        for i in 0..n {
            let chrom_end = (i / self.bins_per_chrom + 1) * self.bins_per_chrom;
            for j in i..(i + self.max_diagonal).min(chrom_end) {
                let noise = 0.5 + random.next_unit();
                let count = (1000.0 * ((j - i + 1) as f64).powf(-1.08) * noise).floor();
                if count > 0.0 && !dead(i) && !dead(j) {
                    block.push(i, j, count);
                }
            }
            if chrom_end < n && self.trans_per_row > 0 {
                // one pixel per equal part of the span after this chromosome: sorted by column
                let step = ((n - chrom_end) / self.trans_per_row).max(1);
                for k in 0..self.trans_per_row {
                    let j = chrom_end + k * step + (i * 7919) % step;
                    if j < n && !dead(i) && !dead(j) {
                        block.push(i, j, 1.0 + (random.next_unit() * 3.0).floor());
                    }
                }
            }
        }
        (bins, block)
    }
}

/// The in-memory matrix of the `expected` and `tads` benches: 4 chromosomes x 5,000 bins,
/// diagonals up to 300, one trans pixel a row (about 6 M pixels), and weights with every 97th bin
/// masked.
#[allow(dead_code)] // not every bench uses it
pub fn six_million_pixels() -> (Pixels, Vec<f64>) {
    let (bins, block) = Synthetic {
        n_chroms: 4,
        bins_per_chrom: 5_000,
        max_diagonal: 300,
        dead_every: None,
        trans_per_row: 1,
    }
    .build();
    let n_bins = bins.n_bins();
    let mut pixels = Pixels::with_capacity(bins, CountType::Integer, block.len()).expect("bins");
    pixels.extend(&block).expect("sorted pixels");
    let mut random = Lcg::new(777);
    let weights = (0..n_bins)
        .map(|i| {
            if i % 97 == 0 {
                f64::NAN
            } else {
                0.5 + random.next_unit()
            }
        })
        .collect();
    (pixels, weights)
}
