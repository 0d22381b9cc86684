//! Armatus: multi-resolution domains by dynamic programming.
//!
//! Reference: Filippova D, Patro R, Duggal G, Kingsford C. "Identification of alternative
//! topological domains in chromatin." Algorithms for Molecular Biology 9:14 (2014).
//!
//! For a resolution parameter `gamma >= 0`, the quality of a candidate domain `[a, b]` (local
//! bins, inclusive, length `l = b - a + 1`) is
//!
//! ```text
//! q(a, b) = s(a, b) / l^gamma - mean_s(l)
//! ```
//!
//! where `s(a, b)` is the sum of the interactions inside the domain (the upper triangle of the
//! sub-matrix, diagonal included) and `mean_s(l)` is the mean of `s / l^gamma` over all
//! `n - l + 1` domains of length `l` in the region. Armatus picks the set of non-overlapping
//! domains with the largest total quality; bins outside every domain are allowed. The dynamic
//! program `OPT(j) = max(OPT(j - 1), max_l OPT(j - l) + q(j - l, j - 1))` over domains of at most
//! `max_domain_bins` bins runs in `O(n * max_domain_bins)` time, `s` being accumulated column by
//! column from the band. Only domains with `q > 0` can improve the optimum and only those are
//! kept (on ties, leaving bins outside a domain wins, then the shorter domain).
//!
//! Small `gamma` rewards large domains, large `gamma` small ones. The paper sweeps `gamma` from 0
//! to a maximum in steps of 0.05 and derives consensus domains; here the caller chooses the
//! `gamma` values (default `[0.2, 0.5, 1.0]`; the Armatus tool's default single resolution is
//! 0.5) and every resolution's optimal domain set is returned, each domain with `level` = the
//! index of its `gamma` in increasing order (level 0 = smallest `gamma` = largest domains) and
//! `score` = its quality `q`. Domains are capped at `max_domain_bins` bins, at most the band's
//! width (the band must hold whole domains; default 100 bins, reduced to the width and to the
//! region size). Masked bins are zero rows and simply contribute no interactions. Bins are
//! genome-wide (`band.first_bin + local`).

use super::band::CisBand;
use super::domains::{Boundary, Domain};
use crate::error::{Error, Result};
use crate::genome::View;

/// Armatus parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmatusParams {
    /// Resolutions (`gamma >= 0`; default `[0.2, 0.5, 1.0]`). Sorted increasingly for the levels.
    pub gammas: Vec<f64>,
    /// Longest domain in bins (default 100); must not exceed the band width.
    pub max_domain_bins: usize,
}

impl ArmatusParams {
    /// Check the values: at least one `gamma`, each finite and `>= 0`; `max_domain_bins` at
    /// least 1 (at most the band's width, which [`armatus`] checks with the band).
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::tads::armatus::ArmatusParams;
    ///
    /// assert!(ArmatusParams::default().check().is_ok());
    /// let bad = ArmatusParams { gammas: vec![0.5, -1.0], ..ArmatusParams::default() };
    /// assert!(bad.check().unwrap_err().to_string().starts_with("gammas -1"));
    /// ```
    pub fn check(&self) -> Result<()> {
        if self.gammas.is_empty() {
            return Err(Error::parameter(
                "gammas",
                "[]",
                "expected at least one gamma",
            ));
        }
        if let Some(g) = self.gammas.iter().find(|g| !(g.is_finite() && **g >= 0.0)) {
            return Err(Error::parameter("gammas", g, "expected finite values >= 0"));
        }
        if self.max_domain_bins == 0 {
            return Err(Error::parameter(
                "max_domain_bins",
                0,
                "expected at least 1",
            ));
        }
        Ok(())
    }
}

impl Default for ArmatusParams {
    fn default() -> Self {
        ArmatusParams {
            gammas: vec![0.2, 0.5, 1.0],
            max_domain_bins: 100,
        }
    }
}

/// Domains at every resolution of `params` for one region's band, ordered by level then start.
///
/// Errors with [`Error::Argument`] when a `gamma` is negative or not finite, no `gamma` is given,
/// `max_domain_bins` is 0 or larger than the band width.
///
/// # Examples
///
/// ```
/// use contactmap::genome::View;
/// use contactmap::genome::{BinTable, Chrom};
/// use contactmap::io::{load_pixels, InMemory};
/// use contactmap::matrix::{CountType, MatrixBuilder};
/// use contactmap::tads::armatus::{armatus, level_boundaries, ArmatusParams};
/// use contactmap::tads::band::cis_bands;
///
/// // four 25-bin domains on a distance decay: boundaries at bins 25, 50 and 75
/// let bins = BinTable::fixed(vec![Chrom::new("chr1", 100_000)], 1_000)?;
/// let mut builder = MatrixBuilder::new(bins.clone(), CountType::Float);
/// for i in 0..100u64 {
///     for j in i..100 {
///         let enrichment = if i / 25 == j / 25 { 4.0 } else { 1.0 };
///         builder.push(i, j, enrichment * 100.0 / (j - i + 1) as f64)?;
///     }
/// }
/// let matrix = InMemory::new("domains".into(), builder.build());
/// let pixels = load_pixels(&matrix, u64::MAX)?;
/// let view = View::chromosomes(&bins);
/// let params = ArmatusParams { gammas: vec![0.5], max_domain_bins: 50 };
/// let bands = cis_bands(&pixels, None, &view, params.max_domain_bins)?;
/// let domains = armatus(&bands[0], &params)?;
/// let spans: Vec<(usize, usize)> = domains.iter().map(|d| (d.start_bin, d.end_bin)).collect();
/// assert_eq!(spans, [(0, 25), (25, 50), (50, 75), (75, 100)]);
/// let edges: Vec<usize> = level_boundaries(&domains, 0, &view).iter().map(|b| b.bin).collect();
/// assert_eq!(edges, [0, 25, 50, 75]);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn armatus(band: &CisBand, params: &ArmatusParams) -> Result<Vec<Domain>> {
    params.check()?;
    if params.max_domain_bins > band.width {
        return Err(Error::Argument(format!(
            "Armatus: max_domain_bins must be in 1..={} (the band width), got {}",
            band.width, params.max_domain_bins
        )));
    }
    let mut gammas = params.gammas.clone();
    gammas.sort_by(f64::total_cmp);
    let max_len = params.max_domain_bins.min(band.n_bins);
    let sums = DomainSums::new(band, max_len);
    let mut out = Vec::new();
    for (level, &gamma) in gammas.iter().enumerate() {
        let quality = Quality::new(&sums, gamma);
        for (a, b, q) in best_domains(&quality) {
            out.push(Domain {
                start_bin: band.first_bin + a,
                end_bin: band.first_bin + b + 1,
                level: level as u32,
                score: q,
            });
        }
    }
    Ok(out)
}

/// `s(a, b)` for every domain of at most `max_len` bins: `s[b * max_len + (l - 1)]` for the domain
/// of length `l` ending at `b`.
struct DomainSums {
    n: usize,
    max_len: usize,
    s: Vec<f64>,
}

impl DomainSums {
    fn new(band: &CisBand, max_len: usize) -> Self {
        let n = band.n_bins;
        let mut s = vec![f64::NAN; n * max_len];
        for b in 0..n {
            // s(a, b) = s(a, b - 1) + sum_{i = a..=b} A[i][b], with a going down from b.
            let mut column = 0.0;
            for l in 1..=max_len.min(b + 1) {
                let a = b + 1 - l;
                column += band.get(a, b);
                let inner = if l == 1 {
                    0.0
                } else {
                    s[(b - 1) * max_len + (l - 2)]
                };
                s[b * max_len + (l - 1)] = inner + column;
            }
        }
        DomainSums { n, max_len, s }
    }

    fn get(&self, b: usize, l: usize) -> f64 {
        self.s[b * self.max_len + (l - 1)]
    }
}

/// Qualities `q(a, b)` at one `gamma`.
struct Quality<'a> {
    sums: &'a DomainSums,
    /// `l^gamma` for `l = 1..=max_len` (index `l - 1`).
    scale: Vec<f64>,
    /// `mean_s(l)`.
    mean: Vec<f64>,
}

impl<'a> Quality<'a> {
    fn new(sums: &'a DomainSums, gamma: f64) -> Self {
        let scale: Vec<f64> = (1..=sums.max_len).map(|l| (l as f64).powf(gamma)).collect();
        let mean = (1..=sums.max_len)
            .map(|l| {
                let count = sums.n + 1 - l;
                (l - 1..sums.n).map(|b| sums.get(b, l)).sum::<f64>() / scale[l - 1] / count as f64
            })
            .collect();
        Quality { sums, scale, mean }
    }

    /// `q` of the domain of length `l` ending at local bin `b`.
    fn q(&self, b: usize, l: usize) -> f64 {
        self.sums.get(b, l) / self.scale[l - 1] - self.mean[l - 1]
    }
}

/// The optimal domain set `(a, b, q)` (local, inclusive), sorted by start.
fn best_domains(quality: &Quality) -> Vec<(usize, usize, f64)> {
    let n = quality.sums.n;
    let max_len = quality.sums.max_len;
    let mut opt = vec![0.0; n + 1];
    let mut choice = vec![0usize; n + 1];
    for j in 1..=n {
        let mut best = opt[j - 1];
        let mut pick = 0;
        for l in 1..=max_len.min(j) {
            let q = quality.q(j - 1, l);
            if q > 0.0 && opt[j - l] + q > best {
                best = opt[j - l] + q;
                pick = l;
            }
        }
        opt[j] = best;
        choice[j] = pick;
    }
    let mut out = Vec::new();
    let mut j = n;
    while j > 0 {
        match choice[j] {
            0 => j -= 1,
            l => {
                out.push((j - l, j - 1, quality.q(j - 1, l)));
                j -= l;
            }
        }
    }
    out.reverse();
    out
}

/// The boundaries of one level of Armatus domains: both edges of every domain of `level` (the
/// bin where it starts and the bin just after it ends), sorted and unique, leaving out the end
/// of the last view region (past the last bin); strength NaN (Armatus has none).
pub fn level_boundaries(domains: &[Domain], level: u32, view: &View) -> Vec<Boundary> {
    let mut edges: Vec<usize> = domains
        .iter()
        .filter(|d| d.level == level)
        .flat_map(|d| [d.start_bin, d.end_bin])
        .collect();
    let n_bins = view.regions().last().map_or(0, |r| r.bins.end);
    edges.retain(|&bin| bin < n_bins);
    edges.sort_unstable();
    edges.dedup();
    edges
        .into_iter()
        .map(|bin| Boundary {
            bin,
            strength: f64::NAN,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Best total quality over all sets of non-overlapping domains, by enumerating every
    /// partition of the bins into runs and every choice of which runs are domains.
    fn brute_force(quality: &Quality, n: usize, max_len: usize) -> f64 {
        let mut best = f64::NEG_INFINITY;
        for cuts in 0..1u32 << (n - 1) {
            let mut runs = Vec::new();
            let mut start = 0;
            for k in 0..n - 1 {
                if cuts >> k & 1 == 1 {
                    runs.push((start, k));
                    start = k + 1;
                }
            }
            runs.push((start, n - 1));
            for pick in 0..1u32 << runs.len() {
                let mut total = 0.0;
                let mut ok = true;
                for (r, &(a, b)) in runs.iter().enumerate() {
                    if pick >> r & 1 == 1 {
                        if b - a + 1 > max_len {
                            ok = false;
                            break;
                        }
                        total += quality.q(b, b - a + 1);
                    }
                }
                if ok && total > best {
                    best = total;
                }
            }
        }
        best
    }

    #[test]
    fn sums_match_dense_triangle() {
        let mut state = 7;
        let (n, width) = (9, 5);
        let mut band = CisBand::zeros(0, n, width);
        for i in 0..n {
            for j in i..(i + width).min(n) {
                band.add(i, j, lcg(&mut state));
            }
        }
        let sums = DomainSums::new(&band, width);
        for b in 0..n {
            for l in 1..=width.min(b + 1) {
                let a = b + 1 - l;
                let naive: f64 = (a..=b)
                    .flat_map(|i| (i..=b).map(move |j| (i, j)))
                    .map(|(i, j)| band.get(i, j))
                    .sum();
                assert!((sums.get(b, l) - naive).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn dynamic_program_matches_brute_force() {
        let mut state = 2024;
        for trial in 0..30 {
            let n = 3 + trial % 6;
            let width = 1 + trial % 4;
            let width = width.min(n);
            let mut band = CisBand::zeros(10, n, width);
            for i in 0..n {
                for j in i..(i + width).min(n) {
                    band.add(i, j, lcg(&mut state) * 5.0 / (1 + j - i) as f64);
                }
            }
            for gamma in [0.0, 0.3, 1.0, 2.5] {
                let sums = DomainSums::new(&band, width);
                let quality = Quality::new(&sums, gamma);
                let dp = best_domains(&quality);
                let dp_total: f64 = dp.iter().map(|d| d.2).sum();
                let brute = brute_force(&quality, n, width).max(0.0);
                assert!(
                    (dp_total - brute).abs() < 1e-9,
                    "n {n} width {width} gamma {gamma}: {dp_total} vs {brute}"
                );
                assert!(dp.iter().all(|d| d.2 > 0.0 && d.1 - d.0 < width));
                assert!(dp.windows(2).all(|p| p[0].1 < p[1].0));
            }
        }
    }

    #[test]
    fn nested_blocks_resolve_by_gamma() {
        let n = 96;
        let width = 40;
        let big = |i: usize| i / 32;
        let small = |i: usize| i / 8;
        let mut band = CisBand::zeros(500, n, width);
        for i in 0..n {
            for j in i..(i + width).min(n) {
                // Mild power-law decay: with a steep decay the contrast between aligned and
                // shifted windows is dominated by the sub-blocks at every gamma.
                let mut v = 20.0 * (1.0 + (j - i) as f64).powf(-0.25);
                if big(i) == big(j) {
                    v *= 2.0;
                }
                if small(i) == small(j) {
                    v *= 1.8;
                }
                band.add(i, j, v);
            }
        }
        let params = ArmatusParams {
            gammas: vec![1.0, 0.2],
            max_domain_bins: 40,
        };
        let domains = armatus(&band, &params).unwrap();
        let level = |k: u32| -> Vec<(usize, usize)> {
            domains
                .iter()
                .filter(|d| d.level == k)
                .map(|d| (d.start_bin - 500, d.end_bin - 500))
                .collect()
        };
        assert_eq!(level(0), vec![(0, 32), (32, 64), (64, 96)]);
        let fine: Vec<(usize, usize)> = (0..12).map(|k| (8 * k, 8 * k + 8)).collect();
        assert_eq!(level(1), fine);
        assert!(domains.iter().all(|d| d.score > 0.0));
    }

    #[test]
    fn invalid_parameters() {
        let band = CisBand::zeros(0, 10, 4);
        let bad = |gammas: Vec<f64>, max_domain_bins| {
            armatus(
                &band,
                &ArmatusParams {
                    gammas,
                    max_domain_bins,
                },
            )
            .is_err()
        };
        assert!(bad(vec![0.5], 5));
        assert!(bad(vec![0.5], 0));
        assert!(bad(vec![-1.0], 4));
        assert!(bad(vec![], 4));
        assert!(!bad(vec![0.5], 4));
    }

    #[test]
    fn level_boundaries_are_the_sorted_unique_edges_of_one_level() {
        use crate::genome::{BinTable, Chrom};
        let bins = BinTable::fixed(vec![Chrom::new("a", 1000)], 100).unwrap();
        let view = View::chromosomes(&bins);
        let domain = |start_bin, end_bin, level| Domain {
            start_bin,
            end_bin,
            level,
            score: 1.0,
        };
        let domains = [
            domain(0, 3, 0),
            domain(3, 6, 0),
            domain(7, 10, 0),
            domain(1, 2, 1),
        ];
        let bins_of = |level| -> Vec<usize> {
            level_boundaries(&domains, level, &view)
                .iter()
                .map(|b| b.bin)
                .collect()
        };
        assert_eq!(bins_of(0), vec![0, 3, 6, 7]);
        assert_eq!(bins_of(1), vec![1, 2]);
    }
}
