//! Block-structured synthetic Hi-C maps with known domains, for testing TAD callers.
//!
//! Model (intra-chromosomal pixels only; no trans contacts):
//!
//! - each chromosome (`chr1` .. `chrN`, `n_bins` bins of `resolution`) is tiled by domains whose
//!   sizes are drawn uniformly in `[min_domain_bins, max_domain_bins]`; when the stretch left after
//!   a draw would be shorter than `min_domain_bins`, the domain absorbs it (so domains hold between
//!   `min_domain_bins` and `max_domain_bins + min_domain_bins - 1` bins);
//! - a fraction `nested_fraction` of the domains (those with room for two sub-domains of at least
//!   `max(2, min_domain_bins / 2)` bins) is split at a uniform point into two nested sub-domains
//!   (level 1);
//! - the expected count of pixel `(i, j)`, `d = j - i <= max_distance_bins`, is
//!   `c * (d + 1)^-decay_exponent * E * b_i * b_j`, where `E` is `1 + domain_enrichment` when `i`
//!   and `j` share a domain, times `1 + domain_enrichment` again when they share a nested
//!   sub-domain, and 1 otherwise; `b` are per-bin biases `exp(bias_sd * Z)` (Z standard normal),
//!   0 for dead bins (`round(dead_bin_fraction * n_bins_total)` bins picked uniformly); the
//!   constant `c` makes the expected total over all generated pixels equal `depth`;
//! - observed counts are Poisson draws of the expected ones ([`crate::random::poisson`]).
//!
//! Reproducibility: domains, biases and dead bins come from one sequential stream of `seed`; each
//! row's counts from its own stream ([`crate::random::stream_seed`] with the genome-wide row index),
//! so rows are generated in parallel and the result does not depend on the thread count.

use rand::Rng;
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::genome::{BinTable, Chrom};
use crate::matrix::{ContactMatrix, CountType, MatrixBuilder};
use crate::random::{poisson, standard_normal, stream_rng};
use crate::tads::Domain;

/// Stream tags (see [`crate::random::stream_seed`]).
const TAG_STRUCTURE: u64 = 1;
const TAG_ROW: u64 = 2;

/// Parameters of [`block_map`]; [`Default`] gives the documented defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockMapParams {
    /// Number of chromosomes, named `chr1` .. `chrN` (default 1).
    pub n_chroms: usize,
    /// Bins per chromosome (default 2000).
    pub n_bins: usize,
    /// Bin size in bp (default 10 000).
    pub resolution: u64,
    /// Smallest domain, in bins (default 10).
    pub min_domain_bins: usize,
    /// Largest drawn domain, in bins (default 60); the last domain of a chromosome may be longer.
    pub max_domain_bins: usize,
    /// Exponent alpha of the contact probability P(s) ~ (s + 1)^-alpha, s in bins (default 1.0).
    pub decay_exponent: f64,
    /// Contacts inside a domain are multiplied by `1 + domain_enrichment` (default 2.0).
    pub domain_enrichment: f64,
    /// Fraction of domains split into two nested sub-domains, enriched again (default 0).
    pub nested_fraction: f64,
    /// Expected total number of contacts (default 10 000 000).
    pub depth: f64,
    /// Pixels farther from the diagonal than this many bins are not generated (default
    /// `usize::MAX`: the whole chromosome). A narrow band makes ICE converge slowly: it couples
    /// bins only locally (2,000 bins cut at 200 need about 3,000 iterations to reach cooler's
    /// tolerance, the whole chromosome 80).
    pub max_distance_bins: usize,
    /// Standard deviation of the log of the per-bin coverage bias (default 0: no bias).
    pub bias_sd: f64,
    /// Fraction of bins without any contact (default 0).
    pub dead_bin_fraction: f64,
    /// Seed of every random draw (default 0).
    pub seed: u64,
}

impl Default for BlockMapParams {
    fn default() -> Self {
        BlockMapParams {
            n_chroms: 1,
            n_bins: 2000,
            resolution: 10_000,
            min_domain_bins: 10,
            max_domain_bins: 60,
            decay_exponent: 1.0,
            domain_enrichment: 2.0,
            nested_fraction: 0.0,
            depth: 1e7,
            max_distance_bins: usize::MAX,
            bias_sd: 0.0,
            dead_bin_fraction: 0.0,
            seed: 0,
        }
    }
}

impl BlockMapParams {
    /// Check the parameters; the error says which one is wrong and what is allowed.
    pub fn check(&self) -> Result<()> {
        let fail = |message: String| Err(Error::Argument(message));
        if self.n_chroms == 0 {
            return fail("the number of chromosomes must be at least 1".into());
        }
        if self.resolution == 0 {
            return fail("the bin size must be positive".into());
        }
        if self.min_domain_bins == 0 {
            return fail("the minimum domain size must be at least 1 bin".into());
        }
        if self.min_domain_bins > self.max_domain_bins {
            return fail(format!(
                "the minimum domain size ({} bins) is larger than the maximum ({} bins)",
                self.min_domain_bins, self.max_domain_bins
            ));
        }
        if self.n_bins < self.min_domain_bins {
            return fail(format!(
                "{} bins per chromosome cannot hold a domain of at least {} bins",
                self.n_bins, self.min_domain_bins
            ));
        }
        let total_bins = self.n_chroms.checked_mul(self.n_bins);
        if total_bins.is_none_or(|n| n > u32::MAX as usize) {
            return fail(format!(
                "{} chromosomes x {} bins is too many bins",
                self.n_chroms, self.n_bins
            ));
        }
        if !self.decay_exponent.is_finite() || self.decay_exponent < 0.0 {
            return fail(format!(
                "the decay exponent must be a finite number >= 0, not {}",
                self.decay_exponent
            ));
        }
        if !self.domain_enrichment.is_finite() || self.domain_enrichment < 0.0 {
            return fail(format!(
                "the domain enrichment must be a finite number >= 0, not {}",
                self.domain_enrichment
            ));
        }
        if !(0.0..=1.0).contains(&self.nested_fraction) {
            return fail(format!(
                "the nested fraction must be in [0, 1], not {}",
                self.nested_fraction
            ));
        }
        if !self.depth.is_finite() || self.depth <= 0.0 {
            return fail(format!(
                "the depth must be a positive number, not {}",
                self.depth
            ));
        }
        if !self.bias_sd.is_finite() || self.bias_sd < 0.0 {
            return fail(format!(
                "the bias standard deviation must be a finite number >= 0, not {}",
                self.bias_sd
            ));
        }
        if !(0.0..1.0).contains(&self.dead_bin_fraction) {
            return fail(format!(
                "the dead bin fraction must be in [0, 1), not {}",
                self.dead_bin_fraction
            ));
        }
        Ok(())
    }
}

/// A simulated map and its ground truth.
#[derive(Clone, Debug)]
pub struct BlockMap {
    /// Integer counts, intra-chromosomal pixels within `max_distance_bins` of the diagonal.
    pub matrix: ContactMatrix,
    /// The domains, sorted by start then level: level 0 for top domains, level 1 for nested
    /// sub-domains; `score` holds the domain's enrichment factor `1 + domain_enrichment`.
    pub domains: Vec<Domain>,
    /// Genome-wide bin index where each domain (of any level) starts, sorted and deduplicated,
    /// excluding each chromosome's first bin.
    pub boundaries: Vec<usize>,
    /// The per-bin bias used (0 for dead bins).
    pub biases: Vec<f64>,
}

impl BlockMap {
    /// The true domains as BED (`chrom start end level`, level 0 for top domains), what
    /// `simulate blocks --truth-domains` writes.
    ///
    /// ```
    /// use contactmap::sim::blocks::{block_map, BlockMapParams};
    /// let map = block_map(&BlockMapParams { n_chroms: 1, n_bins: 100, ..BlockMapParams::default() })?;
    /// let bed = String::from_utf8(map.truth_domains_bed()).unwrap();
    /// assert_eq!(bed.lines().count(), map.domains.len());
    /// let boundaries = String::from_utf8(map.truth_boundaries_bed()).unwrap();
    /// assert_eq!(boundaries.lines().count(), map.boundaries.len());
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn truth_domains_bed(&self) -> Vec<u8> {
        let rows = self
            .domains
            .iter()
            .map(|d| (d.start_bin, d.end_bin, vec![d.level.to_string()]));
        crate::io::bed::bins_bed(self.matrix.bins(), rows)
    }

    /// The true boundaries as BED, one bin each (`simulate blocks --truth-boundaries`).
    pub fn truth_boundaries_bed(&self) -> Vec<u8> {
        let rows = self.boundaries.iter().map(|&b| (b, b + 1, Vec::new()));
        crate::io::bed::bins_bed(self.matrix.bins(), rows)
    }
}

/// Generate a block-structured map (see the module docs for the model).
///
/// # Examples
///
/// Pixels that share a domain hold `1 + domain_enrichment` times the counts of pixels at the
/// same distance that do not; no contact crosses chromosomes; the same seed gives the same map.
///
/// ```
/// use contactmap::sim::{block_map, BlockMapParams};
///
/// let params = BlockMapParams {
///     n_chroms: 2,
///     n_bins: 200,
///     depth: 1e7,
///     domain_enrichment: 2.0,
///     seed: 3,
///     ..BlockMapParams::default()
/// };
/// let map = block_map(&params)?;
/// let bins = map.matrix.bins();
/// assert_eq!(bins.n_bins(), 400);
/// let block = map.matrix.all_pixels();
/// assert!((0..block.len()).all(|k| {
///     bins.chrom_of(block.bin1[k] as usize) == bins.chrom_of(block.bin2[k] as usize)
/// }));
/// // mean counts at distance 5, inside and across domains
/// let domain_of = |bin: usize| map.domains.iter().position(|d| (d.start_bin..d.end_bin).contains(&bin));
/// let (mut inside, mut across) = ((0.0, 0.0), (0.0, 0.0));
/// for i in 0..395 {
///     if bins.chrom_of(i) != bins.chrom_of(i + 5) {
///         continue;
///     }
///     let sums = if domain_of(i) == domain_of(i + 5) { &mut inside } else { &mut across };
///     sums.0 += map.matrix.get(i, i + 5);
///     sums.1 += 1.0;
/// }
/// let ratio = (inside.0 / inside.1) / (across.0 / across.1);
/// assert!((ratio - 3.0).abs() < 0.3, "{ratio}");
/// assert_eq!(block_map(&params)?.matrix.all_pixels(), block);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn block_map(params: &BlockMapParams) -> Result<BlockMap> {
    params.check()?;
    let chroms: Vec<Chrom> = (1..=params.n_chroms)
        .map(|k| Chrom::new(format!("chr{k}"), params.n_bins as u64 * params.resolution))
        .collect();
    let bins = BinTable::fixed(chroms, params.resolution)?;
    let n_total = bins.n_bins();

    let mut rng = stream_rng(params.seed, TAG_STRUCTURE, 0);
    let mut domains = Vec::new();
    for chrom in 0..params.n_chroms {
        domains.extend(draw_domains(&mut rng, bins.chrom_bins(chrom), params));
    }
    let biases = draw_biases(&mut rng, n_total, params);

    // Domain membership per bin: top-level and nested ids (usize::MAX: none).
    let mut top = vec![usize::MAX; n_total];
    let mut nested = vec![usize::MAX; n_total];
    for (id, domain) in domains.iter().enumerate() {
        let ids = if domain.level == 0 {
            &mut top
        } else {
            &mut nested
        };
        ids[domain.start_bin..domain.end_bin].fill(id);
    }
    let factor = 1.0 + params.domain_enrichment;
    let max_distance = params.max_distance_bins.min(params.n_bins);
    let decay: Vec<f64> = (0..=max_distance)
        .map(|d| ((d + 1) as f64).powf(-params.decay_exponent))
        .collect();
    let chrom_end: Vec<usize> = (0..n_total)
        .map(|i| bins.chrom_bins(bins.chrom_of(i)).end)
        .collect();
    let weight = |i: usize, j: usize| -> f64 {
        let mut w = decay[j - i] * biases[i] * biases[j];
        if top[i] == top[j] && top[i] != usize::MAX {
            w *= factor;
        }
        if nested[i] == nested[j] && nested[i] != usize::MAX {
            w *= factor;
        }
        w
    };
    let row_end = |i: usize| chrom_end[i].min(i + max_distance + 1);

    // Row sums in parallel, summed in row order so the scale does not depend on threads.
    let row_sums: Vec<f64> = (0..n_total)
        .into_par_iter()
        .map(|i| (i..row_end(i)).map(|j| weight(i, j)).sum())
        .collect();
    let total: f64 = row_sums.iter().sum();
    if total <= 0.0 {
        return Err(Error::Argument(
            "every generated pixel has an expected count of 0 (all bins dead?)".into(),
        ));
    }
    let scale = params.depth / total;

    let rows: Vec<Vec<(u32, u32)>> = (0..n_total)
        .into_par_iter()
        .map(|i| {
            let mut rng = stream_rng(params.seed, TAG_ROW, i as u64);
            (i..row_end(i))
                .filter_map(|j| {
                    let count = poisson(&mut rng, scale * weight(i, j));
                    (count > 0).then(|| (j as u32, count.min(u32::MAX as u64) as u32))
                })
                .collect()
        })
        .collect();
    let mut builder = MatrixBuilder::new(bins, CountType::Integer);
    for (i, row) in rows.iter().enumerate() {
        for &(j, count) in row {
            builder.push(i as u64, j as u64, count as f64)?;
        }
    }
    let matrix = builder.build();

    let mut boundaries: Vec<usize> = domains
        .iter()
        .map(|d| d.start_bin)
        .filter(|&b| matrix.bins().chrom_bins(matrix.bins().chrom_of(b)).start != b)
        .collect();
    boundaries.sort_unstable();
    boundaries.dedup();
    Ok(BlockMap {
        matrix,
        domains,
        boundaries,
        biases,
    })
}

/// Tile `range` with domains (and nested sub-domains), sorted by start then level.
fn draw_domains(
    rng: &mut impl Rng,
    range: std::ops::Range<usize>,
    params: &BlockMapParams,
) -> Vec<Domain> {
    let (min, max) = (params.min_domain_bins, params.max_domain_bins);
    let score = 1.0 + params.domain_enrichment;
    let min_sub = (min / 2).max(2);
    let mut domains = Vec::new();
    let mut start = range.start;
    while start < range.end {
        let remaining = range.end - start;
        let mut size = rng.gen_range(min..=max);
        if size >= remaining || remaining - size < min {
            size = remaining;
        }
        let end = start + size;
        domains.push(Domain {
            start_bin: start,
            end_bin: end,
            level: 0,
            score,
        });
        // Always draw, so the stream does not depend on the domain's size.
        let split_draw: f64 = rng.r#gen();
        let position_draw: f64 = rng.r#gen();
        if split_draw < params.nested_fraction && size >= 2 * min_sub {
            let n_positions = size - 2 * min_sub + 1;
            let offset = ((position_draw * n_positions as f64) as usize).min(n_positions - 1);
            let split = start + min_sub + offset;
            for (s, e) in [(start, split), (split, end)] {
                domains.push(Domain {
                    start_bin: s,
                    end_bin: e,
                    level: 1,
                    score,
                });
            }
        }
        start = end;
    }
    domains
}

/// Per-bin biases: lognormal, with `round(dead_bin_fraction * n)` dead bins (bias 0).
fn draw_biases(rng: &mut impl Rng, n: usize, params: &BlockMapParams) -> Vec<f64> {
    let mut biases: Vec<f64> = (0..n)
        .map(|_| {
            let z = standard_normal(rng);
            (params.bias_sd * z).exp()
        })
        .collect();
    let n_dead = (params.dead_bin_fraction * n as f64).round() as usize;
    // Partial Fisher-Yates: the first n_dead entries of a random permutation.
    let mut order: Vec<usize> = (0..n).collect();
    for k in 0..n_dead.min(n) {
        let pick = rng.gen_range(k..n);
        order.swap(k, pick);
        biases[order[k]] = 0.0;
    }
    biases
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small(seed: u64) -> BlockMapParams {
        BlockMapParams {
            n_chroms: 2,
            n_bins: 300,
            depth: 1e5,
            max_distance_bins: 50,
            nested_fraction: 0.5,
            bias_sd: 0.2,
            dead_bin_fraction: 0.02,
            seed,
            ..BlockMapParams::default()
        }
    }

    fn pixels(map: &BlockMap) -> Vec<(u64, u64, f64)> {
        let block = map.matrix.all_pixels();
        (0..block.len())
            .map(|k| (block.bin1[k], block.bin2[k], block.count[k]))
            .collect()
    }

    #[test]
    fn same_seed_same_map_whatever_the_thread_count() {
        let a = block_map(&small(11)).unwrap();
        let one_thread = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let b = one_thread.install(|| block_map(&small(11)).unwrap());
        assert_eq!(pixels(&a), pixels(&b));
        assert_eq!(a.domains, b.domains);
        assert_eq!(a.boundaries, b.boundaries);
        let c = block_map(&small(12)).unwrap();
        assert_ne!(pixels(&a), pixels(&c));
    }

    #[test]
    fn domains_tile_chromosomes_and_boundaries_follow() {
        let params = small(3);
        let map = block_map(&params).unwrap();
        let bins = map.matrix.bins();
        assert_eq!(bins.n_chroms(), 2);
        assert_eq!(bins.chroms()[1].name, "chr2");
        let mut n_nested = 0;
        for chrom in 0..2 {
            let range = bins.chrom_bins(chrom);
            let top: Vec<&Domain> = map
                .domains
                .iter()
                .filter(|d| d.level == 0 && range.contains(&d.start_bin))
                .collect();
            assert_eq!(top[0].start_bin, range.start);
            assert_eq!(top.last().unwrap().end_bin, range.end);
            for pair in top.windows(2) {
                assert_eq!(pair[0].end_bin, pair[1].start_bin);
            }
            for d in &top {
                assert!(d.n_bins() >= params.min_domain_bins);
                assert!(d.n_bins() < params.max_domain_bins + params.min_domain_bins);
            }
            n_nested += map
                .domains
                .iter()
                .filter(|d| d.level == 1 && range.contains(&d.start_bin))
                .count();
        }
        assert!(n_nested > 0);
        let mut starts: Vec<usize> = map
            .domains
            .iter()
            .map(|d| d.start_bin)
            .filter(|&b| b != 0 && b != 300)
            .collect();
        starts.sort_unstable();
        starts.dedup();
        assert_eq!(map.boundaries, starts);
        // No trans pixels, nothing beyond max_distance_bins, dead bins empty.
        for (i, j, _) in pixels(&map) {
            assert_eq!(bins.chrom_of(i as usize), bins.chrom_of(j as usize));
            assert!(j - i <= params.max_distance_bins as u64);
            assert!(map.biases[i as usize] > 0.0 && map.biases[j as usize] > 0.0);
        }
        assert_eq!(map.biases.iter().filter(|&&b| b == 0.0).count(), 12);
    }

    #[test]
    fn total_is_about_the_depth() {
        let map = block_map(&small(5)).unwrap();
        let sum = map.matrix.sum();
        assert!((sum - 1e5).abs() < 5.0 * 1e5f64.sqrt(), "{sum}");
    }

    /// Mean count per diagonal at high depth, without domains or biases: a power law.
    #[test]
    fn diagonal_means_follow_the_power_law() {
        for alpha in [0.75, 1.0, 1.5] {
            let params = BlockMapParams {
                n_bins: 600,
                depth: 1e8,
                max_distance_bins: 100,
                domain_enrichment: 0.0,
                decay_exponent: alpha,
                seed: 9,
                ..BlockMapParams::default()
            };
            let map = block_map(&params).unwrap();
            let mut sums = vec![0.0; 101];
            for (i, j, c) in pixels(&map) {
                sums[(j - i) as usize] += c;
            }
            let points: Vec<(f64, f64)> = (1..=100)
                .map(|d| ((d + 1) as f64, sums[d] / (600 - d) as f64))
                .collect();
            let slope = crate::sim::analysis::loglog_slope(&points);
            assert!((slope + alpha).abs() < 0.05, "alpha {alpha}: slope {slope}");
        }
    }

    /// At the same distance, pixels inside a domain hold 1 + enrichment times more contacts.
    #[test]
    fn domains_are_enriched_by_the_factor() {
        let params = BlockMapParams {
            n_bins: 2000,
            depth: 1e8,
            max_distance_bins: 10,
            domain_enrichment: 2.0,
            seed: 4,
            ..BlockMapParams::default()
        };
        let map = block_map(&params).unwrap();
        let mut domain_of = vec![0usize; 2000];
        for (id, d) in map.domains.iter().enumerate() {
            domain_of[d.start_bin..d.end_bin].fill(id);
        }
        for d in 1..=5u64 {
            let (mut inside, mut n_inside, mut outside, mut n_outside) = (0.0, 0, 0.0, 0);
            for i in 0..(2000 - d) {
                let c = map.matrix.get(i as usize, (i + d) as usize);
                if domain_of[i as usize] == domain_of[(i + d) as usize] {
                    inside += c;
                    n_inside += 1;
                } else {
                    outside += c;
                    n_outside += 1;
                }
            }
            let ratio = (inside / n_inside as f64) / (outside / n_outside as f64);
            assert!((ratio - 3.0).abs() < 0.05, "distance {d}: ratio {ratio}");
        }
    }

    #[test]
    fn bad_parameters_are_refused() {
        let base = BlockMapParams::default();
        for (params, expected) in [
            (
                BlockMapParams {
                    min_domain_bins: 70,
                    ..base.clone()
                },
                "larger than the maximum",
            ),
            (
                BlockMapParams {
                    depth: 0.0,
                    ..base.clone()
                },
                "depth",
            ),
            (
                BlockMapParams {
                    n_bins: 5,
                    ..base.clone()
                },
                "cannot hold",
            ),
            (
                BlockMapParams {
                    dead_bin_fraction: 1.0,
                    ..base.clone()
                },
                "dead bin",
            ),
            (
                BlockMapParams {
                    n_chroms: 0,
                    ..base.clone()
                },
                "chromosomes",
            ),
        ] {
            let message = block_map(&params).unwrap_err().to_string();
            assert!(message.contains(expected), "{message}");
        }
    }
}
