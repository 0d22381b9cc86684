//! Shifted random controls, drawn as coolpuppy 1.1.0 draws them: from numpy's legacy global
//! `RandomState` (MT19937 seeded with `init_genrand`), `randint(minshift, maxshift, N)` then
//! `choice([-1, 1], N)` per batch of pairs, so that a seed gives coolpuppy's own controls.
//!
//! A batch of `m` pairs gets `N = nshifts * m` controls, replica-major (control `k` copies pair
//! `k mod m`); each moves both anchors by `round_half_even(shift / bin size)` bins, so a control
//! keeps its pair's distance from the diagonal. MT19937 is the published algorithm (Matsumoto and
//! Nishimura, 1998); numpy's bounded integers draw 32-bit words and reject above a bit mask.

/// The Mersenne Twister MT19937, 32-bit output, seeded as `init_genrand` (numpy's
/// `np.random.seed(int)`).
#[derive(Clone)]
pub struct Mt19937 {
    state: [u32; 624],
    index: usize,
}

impl Mt19937 {
    const N: usize = 624;
    const M: usize = 397;

    /// Seeded with `seed` (`init_genrand`).
    pub fn new(seed: u32) -> Mt19937 {
        let mut state = [0u32; 624];
        state[0] = seed;
        for i in 1..Self::N {
            let prev = state[i - 1];
            state[i] = 1_812_433_253u32
                .wrapping_mul(prev ^ (prev >> 30))
                .wrapping_add(i as u32);
        }
        Mt19937 {
            state,
            index: Self::N,
        }
    }

    fn twist(&mut self) {
        const UPPER: u32 = 0x8000_0000;
        const LOWER: u32 = 0x7fff_ffff;
        const MATRIX_A: u32 = 0x9908_b0df;
        for i in 0..Self::N {
            let y = (self.state[i] & UPPER) | (self.state[(i + 1) % Self::N] & LOWER);
            let mag = if y & 1 == 1 { MATRIX_A } else { 0 };
            self.state[i] = self.state[(i + Self::M) % Self::N] ^ (y >> 1) ^ mag;
        }
        self.index = 0;
    }

    /// The next 32-bit output (`genrand_int32`).
    pub fn next_u32(&mut self) -> u32 {
        if self.index >= Self::N {
            self.twist();
        }
        let mut y = self.state[self.index];
        self.index += 1;
        y ^= y >> 11;
        y ^= (y << 7) & 0x9d2c_5680;
        y ^= (y << 15) & 0xefc6_0000;
        y ^ (y >> 18)
    }

    /// numpy's legacy `randint(low, high, size)` (`high` excluded; `high - low - 1` must fit in
    /// 32 bits): each value a masked 32-bit draw, redrawn while above the range.
    pub fn randint(&mut self, low: i64, high: i64, size: usize) -> Vec<i64> {
        let range = (high - low - 1) as u64;
        debug_assert!(range <= u32::MAX as u64);
        let range = range as u32;
        if range == 0 {
            return vec![low; size];
        }
        let mask = u32::MAX >> range.leading_zeros();
        (0..size)
            .map(|_| {
                loop {
                    let v = self.next_u32() & mask;
                    if v <= range {
                        break low + v as i64;
                    }
                }
            })
            .collect()
    }
}

/// Where controls are drawn (coolpuppy's `--nshifts`, `--minshift`, `--maxshift`, `--seed`).
#[derive(Clone, Debug, PartialEq)]
pub struct ShiftParams {
    /// Controls per pair.
    pub n: usize,
    /// Smallest shift (bp, included).
    pub min_bp: u64,
    /// Largest shift (bp, excluded, as numpy's `randint`).
    pub max_bp: u64,
    /// The seed of the generator.
    pub seed: u32,
}

impl Default for ShiftParams {
    /// coolpuppy's: 10 shifts of 100 kb to 1 Mb, seed 0.
    fn default() -> Self {
        ShiftParams {
            n: 10,
            min_bp: 100_000,
            max_bp: 1_000_000,
            seed: 0,
        }
    }
}

/// For a batch of `m` pairs, the bin shift of each of its `n * m` controls (control `k` moves
/// pair `k mod m`), drawn from `rng` as coolpuppy draws them. In `trans` coolpuppy draws a
/// second shift and sign for anchor 2 but moves both windows by the first (only its base-pair
/// columns take the second): the draws are made and left unused, so that seeds agree.
pub fn batch_shifts(
    rng: &mut Mt19937,
    params: &ShiftParams,
    m: usize,
    resolution: u64,
    trans: bool,
) -> Vec<i64> {
    let count = params.n * m;
    let shifts = rng.randint(params.min_bp as i64, params.max_bp as i64, count);
    let signs = rng.randint(0, 2, count);
    if trans {
        rng.randint(params.min_bp as i64, params.max_bp as i64, count);
        rng.randint(0, 2, count);
    }
    shifts
        .iter()
        .zip(&signs)
        .map(|(&shift, &sign)| {
            let signed = if sign == 0 { -shift } else { shift };
            (signed as f64 / resolution as f64).round_ties_even() as i64
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// numpy 2.2: `np.random.seed(0); [np.random.randint(2**32, dtype=np.uint64) ...]` is the
    /// reference MT19937 output for `init_genrand(0)`; the others are `np.random.seed(s)` then
    /// `randint(100000, 1000000, k)`, `choice([-1, 1], k)`, as in the developer notes.
    #[test]
    fn draws_equal_numpy_legacy_random_state() {
        let mut rng = Mt19937::new(0);
        let first: Vec<u32> = (0..5).map(|_| rng.next_u32()).collect();
        assert_eq!(
            first,
            [2357136044, 2546248239, 3071714933, 3626093760, 2588848963]
        );
        let mut rng = Mt19937::new(0);
        assert_eq!(
            rng.randint(100_000, 1_000_000, 5),
            [405711, 535829, 217952, 252315, 982371]
        );
        assert_eq!(rng.randint(0, 2, 5), [1, 1, 1, 1, 0]);
        let mut rng = Mt19937::new(42);
        assert_eq!(
            rng.randint(100_000, 1_000_000, 4),
            [221958, 771155, 231932, 465838]
        );
        assert_eq!(rng.randint(0, 2, 4), [0, 1, 0, 0]);
    }

    #[test]
    fn the_reference_sequence_continues_past_a_twist() {
        // MT19937's published check: the 10000th output of the default seed 5489 is 4123659995
        let mut rng = Mt19937::new(5489);
        let last = (0..10_000).map(|_| rng.next_u32()).last();
        assert_eq!(last, Some(4_123_659_995));
    }
}
