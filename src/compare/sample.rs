//! Downsampling contacts, as cooltools 0.7.1 `random-sample` does (`cooltools.api.sample`):
//!
//! - **by fraction** ([`Target::Fraction`], cooltools' default): each pixel's count `c` becomes a
//!   binomial draw `Binomial(c, f)` (binomial thinning: every contact kept with probability `f`,
//!   independently), so the total is `f` times the input's on average;
//! - **exactly** ([`Target::Count`], or a fraction with `exact`, cooltools' `--exact`): `N`
//!   distinct contacts drawn without replacement from all of them (a multivariate hypergeometric
//!   draw), so the total is exactly `N` (`round(f * total)`, halves to even, for a fraction).
//!
//! Pixels left with no contact are dropped. The draws are made per block of
//! [`CHUNK_ROWS`] rows, each block with its own random stream derived from the seed (and, in the
//! exact mode, its share of `N` drawn first from the blocks' totals), so a seed gives the same
//! sample whatever the number of threads and whatever part of the map is read. cooltools draws
//! from numpy's global generator, unseeded: its samples cannot be reproduced, ours can; the
//! distribution is the same.
//!
//! The same draws serve HiCRep ([`super::hicrep`]): [`draw_without_replacement`] for hicreppy's
//! 10% subsamples, [`draw_with_replacement`] for hicrep's `bDownSample`.

use std::ops::Range;

use rand::Rng;
use rand_distr::{Binomial, Distribution};
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::genome::BinTable;
use crate::io::{MatrixInfo, MatrixReader, read_ahead};
use crate::matrix::{CountType, PixelBlock, Weights};
use crate::random::stream_rng;

/// Rows per block of draws: each block has its own random stream.
pub const CHUNK_ROWS: usize = 256;

/// Rows read at a time (a whole number of blocks), the next batch read while this one is drawn
/// and written: small, so that a batch stays in cache from reading to writing (batches of 8,192
/// rows took a sixth more time and four times the memory on big.cool).
const BATCH_ROWS: usize = 2 * CHUNK_ROWS;

/// Stream tags of the seed (see [`crate::random::stream_seed`]).
const TAG_BLOCK: u64 = 0x5a3_b10c;
const TAG_SHARES: u64 = 0x5a3_54a2;

/// How many contacts a sample keeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// Each contact kept with this probability (in `(0, 1]`).
    Fraction(f64),
    /// Exactly this many contacts (at most the map's total).
    Count(u64),
}

/// The parameters of [`Sampled`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleParams {
    /// How many contacts to keep.
    pub target: Target,
    /// With [`Target::Fraction`]: keep exactly `round(f * total)` contacts instead of thinning
    /// each pixel independently (always exact with [`Target::Count`]).
    pub exact: bool,
    /// Seed of the random streams.
    pub seed: u64,
}

/// A count as a whole number of contacts, or why it is not one.
fn whole(count: f64, at: impl FnOnce() -> String) -> Result<u64> {
    // (a cast and back instead of fract(), which is a libm call on baseline x86-64)
    if (0.0..9_007_199_254_740_992.0).contains(&count) && (count as u64) as f64 == count {
        Ok(count as u64)
    } else {
        Err(Error::Unsupported(format!(
            "{}: count {count} is not a whole number of contacts; sampling draws contacts, so \
             it needs raw integer counts",
            at()
        )))
    }
}

/// Binomial thinning: each count `c` becomes a draw of `Binomial(c, fraction)`.
///
/// ```
/// use contactmap::compare::sample::thin;
/// use rand::SeedableRng;
///
/// let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(1);
/// let mut counts = vec![10.0, 0.0, 3.0];
/// thin(&mut counts, 1.0, &mut rng);
/// assert_eq!(counts, [10.0, 0.0, 3.0]); // a fraction of 1 keeps everything
/// thin(&mut counts, 0.5, &mut rng);
/// assert!(counts[0] <= 10.0 && counts[1] == 0.0 && counts[2] <= 3.0);
/// ```
pub fn thin(counts: &mut [f64], fraction: f64, rng: &mut impl Rng) {
    if fraction >= 1.0 {
        return;
    }
    let tables = ThinningTables::new(fraction);
    for count in counts {
        *count = tables.draw(*count as u64, rng) as f64;
    }
}

/// Counts up to this are thinned by inverting a table of the binomial distribution (one uniform
/// draw and a binary search); larger ones by rand_distr's sampler.
const TABLE_MAX: usize = 64;

/// The cumulative binomial probabilities `P(X <= k)`, `X ~ Binomial(c, p)`, for `c` up to
/// [`TABLE_MAX`] (most pixels' counts).
struct ThinningTables {
    fraction: f64,
    /// Table `c - 1`: `P(X <= k)` for `k = 0 .. c`.
    cdf: Vec<Vec<f64>>,
}

impl ThinningTables {
    fn new(p: f64) -> ThinningTables {
        let cdf = (1..=TABLE_MAX)
            .map(|c| {
                let mut pmf = (1.0 - p).powi(c as i32);
                let mut sum = pmf;
                let mut table = Vec::with_capacity(c + 1);
                table.push(sum);
                for k in 1..=c {
                    pmf *= (c - k + 1) as f64 / k as f64 * p / (1.0 - p);
                    sum += pmf;
                    table.push(sum);
                }
                table
            })
            .collect();
        ThinningTables { fraction: p, cdf }
    }

    /// A draw of `Binomial(count, p)`.
    fn draw(&self, count: u64, rng: &mut impl Rng) -> u64 {
        match count {
            0 => 0,
            c if c as usize <= TABLE_MAX => {
                let table = &self.cdf[c as usize - 1];
                let u: f64 = rng.r#gen();
                (table.partition_point(|&x| x <= u) as u64).min(c)
            }
            c => Binomial::new(c, self.fraction).map_or(0, |b| b.sample(rng)),
        }
    }
}

/// `n_draw` contacts drawn without replacement from all of `counts` (a multivariate
/// hypergeometric draw, pixel by pixel: pixel `k` keeps `Hypergeometric(remaining contacts, c_k,
/// remaining draws)`); each count becomes the number drawn from it. `n_draw` is at most the total.
///
/// ```
/// use contactmap::compare::sample::draw_without_replacement;
/// use rand::SeedableRng;
///
/// let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
/// let mut counts = vec![4.0, 0.0, 6.0, 5.0];
/// draw_without_replacement(&mut counts, 9, &mut rng);
/// assert_eq!(counts.iter().sum::<f64>(), 9.0);
/// assert!(counts[0] <= 4.0 && counts[1] == 0.0 && counts[2] <= 6.0 && counts[3] <= 5.0);
/// ```
pub fn draw_without_replacement(counts: &mut [f64], n_draw: u64, rng: &mut impl Rng) {
    let mut remaining: u64 = counts.iter().map(|&c| c as u64).sum();
    let mut to_draw = n_draw.min(remaining);
    for count in counts {
        let c = *count as u64;
        let drawn = if to_draw == 0 || c == 0 {
            0
        } else if c == remaining || to_draw == remaining {
            c.min(to_draw)
        } else {
            hypergeometric(remaining, c, to_draw, rng)
        };
        remaining -= c;
        to_draw -= drawn;
        *count = drawn as f64;
    }
}

/// Up to this many sequential trials a hypergeometric draw is made trial by trial; beyond it,
/// by rand_distr's rejection sampler where that one runs in bounded time.
pub const TRIALS_MAX: u64 = 1_000;

/// A draw of `Hypergeometric(population, successes, draws)`: the successes among `draws` items
/// taken without replacement. Exact either way: by sequential trials over the smallest of its
/// symmetric forms (`min(K, n, N - K, N - n)` trials), cheap for the small counts of most pixels;
/// when that is more than [`TRIALS_MAX`] trials and the distribution's mode is 10 or more from
/// its lowest value, by rand_distr's H2PE (Kachitvichyanukul & Schmeiser 1985, bounded expected
/// time whatever the sizes: a 10% subsample of a map's 500 million contacts took 43 s by trials
/// for its large pixels). rand_distr's other method (HIN, for a mode near 0) sets up in time
/// proportional to the draws, so such draws stay with the trials, which then are few: with the
/// mode `m ~ n K / N` under 10, `min(K, n)` is under `sqrt(10 N)`.
pub fn hypergeometric(population: u64, successes: u64, draws: u64, rng: &mut impl Rng) -> u64 {
    let (n_total, k, n) = (population, successes.min(population), draws.min(population));
    let smallest = k.min(n).min(n_total - k).min(n_total - n);
    if smallest > TRIALS_MAX {
        if let Some(distribution) = bounded_time_hypergeometric(n_total, k, n) {
            return distribution.sample(rng);
        }
    }
    if smallest == k {
        special_among(n_total, n, k, rng)
    } else if smallest == n {
        special_among(n_total, k, n, rng)
    } else if smallest == n_total - k {
        // the failures drawn
        n - special_among(n_total, n, n_total - k, rng)
    } else {
        // the successes left undrawn
        k - special_among(n_total, k, n_total - n, rng)
    }
}

/// rand_distr's sampler of `Hypergeometric(N, K, n)` when it chooses H2PE, its method of bounded
/// time: the mode of the reduced form (smaller group of K and N - K, drawing at most N / 2) at 10
/// or more (rand_distr 0.4.3's own test; the reduced form's lowest value is 0 there).
fn bounded_time_hypergeometric(n_total: u64, k: u64, n: u64) -> Option<rand_distr::Hypergeometric> {
    let smaller_group = k.min(n_total - k);
    let reduced_draws = if n <= n_total / 2 { n } else { n_total - n };
    let mode =
        ((reduced_draws + 1) as f64 * (smaller_group + 1) as f64 / (n_total + 2) as f64).floor();
    (mode >= 10.0)
        .then(|| rand_distr::Hypergeometric::new(n_total, k, n).ok())
        .flatten()
}

/// The number of `special` items among `picks` items taken without replacement from
/// `population`, trial by trial.
fn special_among(population: u64, special: u64, picks: u64, rng: &mut impl Rng) -> u64 {
    let (mut left, mut special_left, mut found) = (population, special, 0);
    for taken in 0..picks {
        if special_left == 0 {
            break;
        }
        if special_left == left {
            return found + (picks - taken);
        }
        if rng.r#gen::<f64>() * (left as f64) < special_left as f64 {
            found += 1;
            special_left -= 1;
        }
        left -= 1;
    }
    found
}

/// `n_draw` contacts drawn with replacement, each pixel chosen with probability proportional to
/// its count (a multinomial draw, made pixel by pixel as binomials of the remaining draws, as
/// hicrep's `resample` with `np.random.choice(p=...)`); each count becomes the number of draws
/// that chose it.
///
/// ```
/// use contactmap::compare::sample::draw_with_replacement;
/// use rand::SeedableRng;
///
/// let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(3);
/// let mut counts = vec![1.0, 0.0, 2.0];
/// draw_with_replacement(&mut counts, 10, &mut rng); // more draws than contacts
/// assert_eq!(counts.iter().sum::<f64>(), 10.0);
/// assert_eq!(counts[1], 0.0);
/// ```
pub fn draw_with_replacement(counts: &mut [f64], n_draw: u64, rng: &mut impl Rng) {
    let mut remaining: f64 = counts.iter().sum();
    let mut to_draw = n_draw;
    for count in counts {
        let c = *count;
        let drawn = if to_draw == 0 || c <= 0.0 {
            0
        } else if c >= remaining {
            to_draw
        } else {
            Binomial::new(to_draw, c / remaining).map_or(0, |b| b.sample(rng))
        };
        remaining -= c;
        to_draw -= drawn;
        *count = drawn as f64;
    }
}

/// A map downsampled: a [`MatrixReader`] whose pixels are drawn from `inner`'s as [`SampleParams`]
/// say (see the module documentation), ready for any writer.
///
/// # Examples
///
/// A tenth of the yeast map, exactly: the same sample whatever is read, and whenever.
///
/// ```
/// use contactmap::compare::sample::{SampleParams, Sampled, Target};
/// use contactmap::io::{open_matrix, MatrixReader, OpenOptions};
///
/// let input = open_matrix("data/yeast.10kb.cool", &OpenOptions::default())?;
/// let (_, total) = input.totals()?;
/// let params = SampleParams { target: Target::Fraction(0.1), exact: true, seed: 5 };
/// let sampled = Sampled::new(input.as_ref(), params)?;
/// let (_, sum) = sampled.totals()?;
/// assert_eq!(sum, (0.1 * total).round_ties_even());
/// assert_eq!(sampled.totals()?, Sampled::new(input.as_ref(), params)?.totals()?);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub struct Sampled<'a> {
    inner: &'a dyn MatrixReader,
    draws: Draws,
    seed: u64,
    source: String,
}

/// What each block of rows draws.
#[derive(Clone, Debug, PartialEq)]
enum Draws {
    /// Binomial thinning with this probability.
    Thin(f64),
    /// Exactly this many contacts from each block of rows (its share of the total asked for).
    Exact(Vec<u64>),
}

impl<'a> Sampled<'a> {
    /// Sample `inner`. The exact mode reads `inner` once here (the totals of its blocks); a
    /// count above the map's total, a fraction outside `(0, 1]` or counts that are not whole
    /// numbers are errors.
    pub fn new(inner: &'a dyn MatrixReader, params: SampleParams) -> Result<Self> {
        if let Target::Fraction(f) = params.target {
            if !(f > 0.0 && f <= 1.0) {
                return Err(Error::parameter(
                    "fraction",
                    f,
                    "a fraction of the contacts, in (0, 1]",
                ));
            }
        }
        if params.target == Target::Count(0) {
            return Err(Error::parameter("count", 0, "at least one contact to keep"));
        }
        let source = format!("{} (downsampled)", inner.source());
        if let (Target::Fraction(f), false) = (params.target, params.exact) {
            return Ok(Sampled {
                inner,
                draws: Draws::Thin(f),
                seed: params.seed,
                source,
            });
        }
        let n = inner.bins().n_bins();
        let mut totals = vec![0u64; n.div_ceil(CHUNK_ROWS)];
        inner.read_pixels(0..n, 0..n, &mut |block| {
            for k in 0..block.len() {
                let c = whole(block.count[k], || {
                    format!(
                        "{}, pixel ({}, {})",
                        inner.source(),
                        block.bin1[k],
                        block.bin2[k]
                    )
                })?;
                totals[block.bin1[k] as usize / CHUNK_ROWS] += c;
            }
            Ok(())
        })?;
        let total: u64 = totals.iter().sum();
        let n_draw = match params.target {
            Target::Count(count) if count > total => {
                return Err(Error::parameter(
                    "count",
                    count,
                    format!(
                        "at most the {total} contacts of {}: a sample cannot hold more than the map",
                        inner.source()
                    ),
                ));
            }
            Target::Count(count) => count,
            Target::Fraction(f) => (f * total as f64).round_ties_even() as u64,
        };
        let mut shares: Vec<f64> = totals.iter().map(|&t| t as f64).collect();
        draw_without_replacement(
            &mut shares,
            n_draw,
            &mut stream_rng(params.seed, TAG_SHARES, 0),
        );
        Ok(Sampled {
            inner,
            draws: Draws::Exact(shares.into_iter().map(|s| s as u64).collect()),
            seed: params.seed,
            source,
        })
    }
}

/// Draw block `chunk`'s pixels (all of its rows' stored pixels, in order) in place: binomial
/// thinning, or the block's share of contacts without replacement (whose counts
/// [`Sampled::new`] checked already).
fn draw(
    source: &str,
    draws: &Draws,
    seed: u64,
    chunk: usize,
    pixels: (&[u64], &[u64], &mut [f64]),
) -> Result<()> {
    let (bin1, bin2, counts) = pixels;
    let mut rng = stream_rng(seed, TAG_BLOCK, chunk as u64);
    match draws {
        Draws::Thin(f) => {
            for (k, &count) in counts.iter().enumerate() {
                whole(count, || {
                    format!("{source}, pixel ({}, {})", bin1[k], bin2[k])
                })?;
            }
            thin(counts, *f, &mut rng);
        }
        Draws::Exact(shares) => {
            let share = shares.get(chunk).copied().unwrap_or(0);
            draw_without_replacement(counts, share, &mut rng);
        }
    }
    Ok(())
}

impl Sampled<'_> {
    /// Draw a batch of rows (`batch_rows`, its pixels in `batch`) in place, each block of rows in
    /// parallel, and hand the contacts kept inside the rectangle asked for to `sink`.
    fn draw_batch(
        &self,
        batch_rows: Range<usize>,
        batch: &mut PixelBlock,
        asked: (&Range<usize>, &Range<usize>, bool),
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        let (rows, cols, whole_rows) = asked;
        let mut pieces = Vec::new();
        let mut rest: &mut [f64] = &mut batch.count;
        let mut offset = 0;
        for chunk_start in batch_rows.step_by(CHUNK_ROWS) {
            let chunk_end = (chunk_start + CHUNK_ROWS) as u64;
            let stop = batch.bin1.partition_point(|&b| b < chunk_end);
            let (head, tail) = rest.split_at_mut(stop - offset);
            pieces.push((chunk_start / CHUNK_ROWS, offset, head));
            rest = tail;
            offset = stop;
        }
        let source = self.inner.source();
        let (draws, seed) = (&self.draws, self.seed);
        let (bin1, bin2) = (&batch.bin1, &batch.bin2);
        pieces
            .into_par_iter()
            .try_for_each(|(chunk, offset, counts)| {
                let span = offset..offset + counts.len();
                let pixels = (&bin1[span.clone()], &bin2[span], counts);
                draw(source, draws, seed, chunk, pixels)
            })?;
        // Kept: contacts left, inside the rectangle asked for.
        batch.retain(|i, j, count| {
            count > 0.0
                && rows.contains(&(i as usize))
                && (whole_rows || cols.contains(&(j as usize)))
        });
        if batch.is_empty() {
            Ok(())
        } else {
            sink(batch)
        }
    }
}

impl MatrixReader for Sampled<'_> {
    fn source(&self) -> &str {
        &self.source
    }

    fn bins(&self) -> &BinTable {
        self.inner.bins()
    }

    fn count_type(&self) -> CountType {
        CountType::Integer
    }

    fn weight_names(&self) -> Vec<String> {
        Vec::new()
    }

    fn weights(&self, name: &str) -> Result<Weights> {
        Err(Error::Argument(format!(
            "{}: a downsampled map has no weight column '{name}' (balance the sample itself)",
            self.source
        )))
    }

    fn info(&self) -> MatrixInfo {
        let mut info = self.inner.info();
        info.notes
            .push("pixels downsampled (contactmap sample); weights not carried over".into());
        info
    }

    fn read_pixels(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        sink: &mut dyn FnMut(&PixelBlock) -> Result<()>,
    ) -> Result<()> {
        let n = self.bins().n_bins();
        let (rows, cols) = (rows.start..rows.end.min(n), cols.start..cols.end.min(n));
        if rows.is_empty() || cols.is_empty() {
            return Ok(());
        }
        // Whole blocks are read and drawn (a block's draws depend on all of its pixels), then
        // cut to the rectangle asked for.
        let first = rows.start / CHUNK_ROWS * CHUNK_ROWS;
        let whole_rows = cols.start == 0 && cols.end == n;
        // The batch of rows starting at `start`, its pixels in one block (the reader's first
        // block kept, the others appended).
        let batch_rows = |start: usize| start..(start + BATCH_ROWS).min(n);
        let read_batch = |&start: &usize| -> Result<PixelBlock> {
            let mut batch = PixelBlock::default();
            self.inner
                .read_rows_owned(batch_rows(start), &mut |block| {
                    if batch.is_empty() {
                        batch = block;
                    } else {
                        batch.bin1.extend_from_slice(&block.bin1);
                        batch.bin2.extend_from_slice(&block.bin2);
                        batch.count.extend_from_slice(&block.count);
                        self.inner.recycle(block);
                    }
                    Ok(())
                })?;
            Ok(batch)
        };
        // The next batch read while this one is drawn and handed on.
        let batches = (first..rows.end).step_by(BATCH_ROWS);
        read_ahead(batches, read_batch, |start, mut batch| {
            self.draw_batch(
                batch_rows(start),
                &mut batch,
                (&rows, &cols, whole_rows),
                sink,
            )?;
            self.inner.recycle(batch);
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::Chrom;
    use crate::io::InMemory;
    use crate::matrix::MatrixBuilder;
    use rand::SeedableRng;
    use statrs::distribution::{ChiSquared, ContinuousCDF};

    fn rng(seed: u64) -> rand_xoshiro::Xoshiro256PlusPlus {
        rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed)
    }

    /// Binomial probabilities of `0..=n` successes (independent of the sampler: by the recurrence
    /// of the probability mass function).
    fn binomial_pmf(n: u64, p: f64) -> Vec<f64> {
        let mut pmf = vec![(1.0 - p).powi(n as i32)];
        for k in 1..=n {
            let prev = pmf[k as usize - 1];
            pmf.push(prev * (n - k + 1) as f64 / k as f64 * p / (1.0 - p));
        }
        pmf
    }

    /// Pearson's chi-square p-value of `observed` counts against probabilities `pmf`.
    fn chi_square_p(observed: &[u64], pmf: &[f64]) -> f64 {
        let total: u64 = observed.iter().sum();
        let statistic: f64 = observed
            .iter()
            .zip(pmf)
            .map(|(&o, &p)| {
                let e = p * total as f64;
                (o as f64 - e).powi(2) / e
            })
            .sum();
        1.0 - ChiSquared::new((pmf.len() - 1) as f64)
            .unwrap()
            .cdf(statistic)
    }

    #[test]
    fn thinning_draws_binomial_counts() {
        // 20,000 pixels of c contacts thinned to 30%: the kept counts follow Binomial(c, 0.3),
        // for a count inverted from the table (8) and one drawn by rand_distr (100).
        for c in [8u64, 100] {
            let mut counts = vec![c as f64; 20_000];
            thin(&mut counts, 0.3, &mut rng(11));
            let mut observed = vec![0u64; c as usize + 1];
            for k in &counts {
                observed[*k as usize] += 1;
            }
            let pmf = binomial_pmf(c, 0.3);
            // classes expecting fewer than 5 pooled into one
            let (mut kept_pmf, mut kept) = (Vec::new(), Vec::new());
            let (mut rest_p, mut rest) = (0.0, 0u64);
            for (p, o) in pmf.iter().zip(&observed) {
                if p * 20_000.0 >= 5.0 {
                    kept_pmf.push(*p);
                    kept.push(*o);
                } else {
                    rest_p += p;
                    rest += o;
                }
            }
            kept_pmf.push(rest_p);
            kept.push(rest);
            let p = chi_square_p(&kept, &kept_pmf);
            assert!(p > 1e-3, "c {c}: chi-square p = {p}, observed {observed:?}");
        }
    }

    #[test]
    fn exact_draws_are_hypergeometric() {
        // Each of the sampler's four forms (trials over K, n, N - K or N - n), checked by
        // chi-square against the closed form C(K,k) C(N-K,n-k) / C(N,n).
        fn choose(n: u64, k: u64) -> f64 {
            (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
        }
        let mut r = rng(2);
        for (n_total, k, n) in [(20u64, 3u64, 10u64), (20, 6, 5), (20, 15, 12), (20, 9, 17)] {
            let support = (n + k).saturating_sub(n_total)..=k.min(n);
            let pmf: Vec<f64> = support
                .clone()
                .map(|x| choose(k, x) * choose(n_total - k, n - x) / choose(n_total, n))
                .collect();
            let mut observed = vec![0u64; pmf.len()];
            for _ in 0..20_000 {
                let x = hypergeometric(n_total, k, n, &mut r);
                assert!(support.contains(&x), "{x} outside {support:?}");
                observed[(x - support.start()) as usize] += 1;
            }
            let keep: Vec<usize> = (0..pmf.len())
                .filter(|&i| pmf[i] * 20_000.0 >= 5.0)
                .collect();
            let mut kept_pmf: Vec<f64> = keep.iter().map(|&i| pmf[i]).collect();
            let mut kept: Vec<u64> = keep.iter().map(|&i| observed[i]).collect();
            // the rare classes pooled into the last kept one
            let last = kept.len() - 1;
            kept_pmf[last] += 1.0 - kept_pmf.iter().sum::<f64>();
            kept[last] += 20_000 - kept.iter().sum::<u64>();
            let p = chi_square_p(&kept, &kept_pmf);
            assert!(
                p > 1e-3,
                "N {n_total} K {k} n {n}: p = {p}, observed {observed:?}"
            );
        }
        // Two pixels: the total drawn is exact.
        for _ in 0..1000 {
            let mut counts = [6.0, 14.0];
            draw_without_replacement(&mut counts, 5, &mut r);
            assert_eq!(counts[0] + counts[1], 5.0);
        }
    }

    #[test]
    fn large_draws_are_hypergeometric() {
        // Draws past TRIALS_MAX: by H2PE in each symmetric form (K or n past half of N) and
        // by trials where the mode is near 0, checked by chi-square against the closed form
        // (log-binomials by ln_gamma), in bins of about a quarter standard deviation.
        use statrs::function::gamma::ln_gamma;
        let ln_choose = |a: u64, b: u64| {
            ln_gamma(a as f64 + 1.0) - ln_gamma(b as f64 + 1.0) - ln_gamma((a - b) as f64 + 1.0)
        };
        let mut r = rng(3);
        let draws = 20_000;
        for (n_total, k, n) in [
            (1_000_000_000u64, 1_000_000u64, 100_000_000u64),
            (1_000_000_000, 999_000_000, 100_000_000),
            (1_000_000_000, 1_000_000, 900_000_000),
            (10_000_000, 4_000_000, 5_000_000),
            (1_000_000_000, 2_000, 2_000),
        ] {
            let ln_all = ln_choose(n_total, n);
            let pmf = |x: u64| (ln_choose(k, x) + ln_choose(n_total - k, n - x) - ln_all).exp();
            let (nf, kf, nt) = (n as f64, k as f64, n_total as f64);
            let mean = nf * kf / nt;
            let sd = (mean * (1.0 - kf / nt) * (nt - nf) / (nt - 1.0)).sqrt();
            let low = (n + k)
                .saturating_sub(n_total)
                .max((mean - 6.0 * sd).max(0.0) as u64);
            let high = k.min(n).min((mean + 6.0 * sd).ceil() as u64 + 2);
            let width = ((sd / 4.0).ceil() as u64).max(1);
            let bins = ((high - low) / width + 1) as usize;
            let mut class_pmf = vec![0.0; bins];
            for x in low..=high {
                class_pmf[((x - low) / width) as usize] += pmf(x);
            }
            let mut observed = vec![0u64; bins];
            let mut outside = 0u64;
            for _ in 0..draws {
                let x = hypergeometric(n_total, k, n, &mut r);
                assert!(x <= k.min(n) && n - x <= n_total - k, "{x} impossible");
                if (low..=high).contains(&x) {
                    observed[((x - low) / width) as usize] += 1;
                } else {
                    outside += 1;
                }
            }
            // classes expecting fewer than 5, and what lies outside the range, pooled
            let (mut kept_pmf, mut kept) = (Vec::new(), Vec::new());
            let (mut rest_p, mut rest) = (1.0 - class_pmf.iter().sum::<f64>(), outside);
            for (p, o) in class_pmf.iter().zip(&observed) {
                if p * draws as f64 >= 5.0 {
                    kept_pmf.push(*p);
                    kept.push(*o);
                } else {
                    rest_p += p;
                    rest += o;
                }
            }
            let last = kept.len() - 1;
            kept_pmf[last] += rest_p.max(0.0);
            kept[last] += rest;
            let p = chi_square_p(&kept, &kept_pmf);
            assert!(
                p > 1e-3,
                "N {n_total} K {k} n {n}: p = {p}, observed {kept:?}, expected {kept_pmf:?}"
            );
        }
    }

    #[test]
    fn draws_with_replacement_are_multinomial() {
        // 12 draws over counts 1 : 3: the first pixel gets Binomial(12, 0.25).
        let mut observed = vec![0u64; 13];
        let mut r = rng(4);
        for _ in 0..20_000 {
            let mut counts = [1.0, 3.0];
            draw_with_replacement(&mut counts, 12, &mut r);
            assert_eq!(counts[0] + counts[1], 12.0);
            observed[counts[0] as usize] += 1;
        }
        // Classes with an expectation under 5 pooled into the last kept one.
        let pmf = binomial_pmf(12, 0.25);
        let keep = pmf.iter().take_while(|&&p| p * 20_000.0 >= 5.0).count();
        let mut pooled_pmf = pmf[..keep].to_vec();
        let mut pooled = observed[..keep].to_vec();
        pooled_pmf[keep - 1] += pmf[keep..].iter().sum::<f64>();
        pooled[keep - 1] += observed[keep..].iter().sum::<u64>();
        let p = chi_square_p(&pooled, &pooled_pmf);
        assert!(p > 1e-3, "chi-square p = {p}, observed {observed:?}");
    }

    fn toy() -> InMemory {
        // 600 bins over two chromosomes (three blocks of rows), every pixel within 5 bins of
        // the diagonal with 1..=9 contacts.
        let bins =
            BinTable::fixed(vec![Chrom::new("a", 40_000), Chrom::new("b", 20_000)], 100).unwrap();
        let mut builder = MatrixBuilder::new(bins, CountType::Integer);
        for i in 0..600u64 {
            for j in i..(i + 5).min(600) {
                builder
                    .push(i, j, (1 + (i * 7 + j * 3) % 9) as f64)
                    .unwrap();
            }
        }
        InMemory::new("toy".into(), builder.build())
    }

    fn pixels(reader: &dyn MatrixReader, rows: Range<usize>) -> Vec<(u64, u64, f64)> {
        let mut out = Vec::new();
        let n = reader.bins().n_bins();
        reader
            .read_pixels(rows, 0..n, &mut |b| {
                out.extend((0..b.len()).map(|k| (b.bin1[k], b.bin2[k], b.count[k])));
                Ok(())
            })
            .unwrap();
        out
    }

    #[test]
    fn samples_are_reproducible_exact_and_independent_of_what_is_read() {
        let map = toy();
        let total: f64 = pixels(&map, 0..600).iter().map(|p| p.2).sum();
        for target in [Target::Count(1234), Target::Fraction(0.25)] {
            for exact in [false, true] {
                let params = SampleParams {
                    target,
                    exact,
                    seed: 9,
                };
                let sampled = Sampled::new(&map, params).unwrap();
                let all = pixels(&sampled, 0..600);
                // Same seed, same sample, under one thread or several.
                let one_thread = rayon::ThreadPoolBuilder::new()
                    .num_threads(1)
                    .build()
                    .unwrap()
                    .install(|| pixels(&Sampled::new(&map, params).unwrap(), 0..600));
                assert_eq!(all, one_thread);
                // A part read alone is that part of the whole.
                let part = pixels(&sampled, 300..420);
                let want: Vec<_> = all
                    .iter()
                    .copied()
                    .filter(|p| (300..420).contains(&(p.0 as usize)))
                    .collect();
                assert_eq!(part, want);
                let sum: f64 = all.iter().map(|p| p.2).sum();
                match (target, exact) {
                    (Target::Count(n), _) => assert_eq!(sum, n as f64),
                    (Target::Fraction(f), true) => assert_eq!(sum, (f * total).round_ties_even()),
                    // Binomial thinning: within 5 standard deviations of f * total.
                    (Target::Fraction(f), false) => {
                        let sd = (total * f * (1.0 - f)).sqrt();
                        assert!((sum - f * total).abs() < 5.0 * sd, "{sum} vs {}", f * total);
                    }
                }
                // Every kept pixel is a pixel of the input with at most its count.
                let input = pixels(&map, 0..600);
                for p in &all {
                    let q = input.iter().find(|q| (q.0, q.1) == (p.0, p.1)).unwrap();
                    assert!(p.2 >= 1.0 && p.2 <= q.2);
                }
                // Another seed, another sample.
                let other = Sampled::new(&map, SampleParams { seed: 10, ..params }).unwrap();
                assert_ne!(pixels(&other, 0..600), all);
            }
        }
    }

    #[test]
    fn bad_targets_are_refused() {
        let map = toy();
        for f in [0.0, -0.5, 1.5, f64::NAN] {
            let params = SampleParams {
                target: Target::Fraction(f),
                exact: false,
                seed: 0,
            };
            let message = Sampled::new(&map, params).err().unwrap().to_string();
            assert!(message.contains("(0, 1]"), "{message}");
        }
        let params = SampleParams {
            target: Target::Count(1_000_000),
            exact: true,
            seed: 0,
        };
        let message = Sampled::new(&map, params).err().unwrap().to_string();
        assert!(message.contains("at most the"), "{message}");
    }
}
