//! Polymer statistics of conformations as polychrom's `polymer_analyses` computes them:
//!
//! - [`generate_bins`]: its separations, log-spaced (`numpy.logspace(log10(4), log10(N - 1) +
//!   1e-6, num, dtype=int)`, about 10 per decade, unique), the last one `N - 1`;
//! - [`contact_scaling`]: P(s), the contacts (at most `cutoff` apart) whose separation `j - i` lies
//!   in `[b_k, b_k+1)`, over the pairs possible there, `diff(N b + b / 2 - b^2 / 2)`, at the
//!   geometric mid `sqrt(b_k (b_k+1 - 1))`;
//! - [`r2_scaling`]: `<|x_i+s - x_i|^2>` over `i`, at each `s`;
//! - [`rg2_scaling`]: the mean squared radius of gyration of the subchains of `s` beads, from
//!   cumulative sums as polychrom computes it;
//! - [`rg2`]: a conformation's squared radius of gyration.
//!
//! Each is one conformation's; [`EnsembleStats`] averages them over conformations (the mean of the
//! per-conformation values, as one averages polychrom's outputs).

use rayon::prelude::*;

use super::map::contact_pairs;
use crate::error::{Error, Result};
use crate::geometry::cells::CellList;
use crate::io::trajectory::{Conformation, for_each_chunk};

/// polychrom's `generate_bins(N, start=4, bins_per_order_magn=10)`: log-spaced separations from
/// `start` to `N - 1` (numpy's `linspace`, `10^x` and the cast to integers, replayed).
///
/// ```
/// use contactmap::conformations::stats::generate_bins;
/// let bins = generate_bins(150, 4, 10);
/// assert_eq!(bins.first(), Some(&4));
/// assert_eq!(bins.last(), Some(&149));
/// assert!(bins.windows(2).all(|w| w[0] < w[1]));
/// ```
pub fn generate_bins(n: usize, start: usize, per_decade: usize) -> Vec<usize> {
    if n < 2 {
        return Vec::new();
    }
    let lstart = (start as f64).log10();
    let lend = ((n - 1) as f64).log10() + 1e-6;
    let num = ((lend - lstart) * per_decade as f64).ceil();
    let num = if num > 0.0 { num as usize } else { 0 };
    let mut bins: Vec<usize> = match num {
        0 => Vec::new(),
        1 => vec![10f64.powf(lstart) as usize],
        _ => {
            let step = (lend - lstart) / (num - 1) as f64;
            (0..num)
                .map(|i| {
                    let y = if i == num - 1 {
                        lend
                    } else {
                        i as f64 * step + lstart
                    };
                    10f64.powf(y) as usize
                })
                .collect()
        }
    };
    bins.sort_unstable();
    bins.dedup();
    bins
}

/// polychrom's `contact_scaling(data, bins0, cutoff)` of one conformation: per bin `[b_k,
/// b_k+1)` its geometric mid and contact probability.
pub fn contact_scaling(
    positions: &[[f64; 3]],
    bins: &[usize],
    cutoff: f64,
    cells: &mut CellList,
) -> (Vec<f64>, Vec<f64>) {
    let n = positions.len() as f64;
    let mut lengths: Vec<u32> = contact_pairs(positions, cutoff, cells)
        .into_iter()
        .map(|(i, j)| j - i)
        .collect();
    lengths.sort_unstable();
    let below = |b: usize| lengths.partition_point(|&s| (s as usize) < b);
    let possible = |b: usize| {
        let b = b as f64;
        n * b + 0.5 * b - 0.5 * (b * b)
    };
    let mut mids = Vec::new();
    let mut probabilities = Vec::new();
    for w in bins.windows(2) {
        let count = (below(w[1]) - below(w[0])) as f64;
        probabilities.push(count / (possible(w[1]) - possible(w[0])));
        mids.push(((w[0] * (w[1] - 1)) as f64).sqrt());
    }
    (mids, probabilities)
}

/// polychrom's `R2_scaling(data, bins)` of one conformation: the mean squared distance of beads
/// `s` apart, at each `s` of `bins`.
pub fn r2_scaling(positions: &[[f64; 3]], bins: &[usize]) -> Vec<f64> {
    bins.iter()
        .map(|&s| {
            let terms = positions.len() - s;
            let sum: f64 = (0..terms)
                .map(|i| {
                    let (a, b) = (positions[i], positions[i + s]);
                    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
                })
                .sum();
            sum / terms as f64
        })
        .collect()
}

/// polychrom's `Rg2_scaling(data, bins)` of one conformation: the mean squared radius of
/// gyration of the subchains of `s` beads, at each `s` of `bins`, from cumulative sums.
pub fn rg2_scaling(positions: &[[f64; 3]], bins: &[usize]) -> Vec<f64> {
    let n = positions.len();
    let mut coms = vec![[0.0f64; 3]; n + 1];
    let mut coms2 = vec![[0.0f64; 3]; n + 1];
    for (k, p) in positions.iter().enumerate() {
        for d in 0..3 {
            coms[k + 1][d] = coms[k][d] + p[d];
            coms2[k + 1][d] = coms2[k][d] + p[d] * p[d];
        }
    }
    bins.iter()
        .map(|&len| {
            let l = len as f64;
            let terms = n + 1 - len;
            let sum: f64 = (0..terms)
                .map(|i| {
                    (0..3)
                        .map(|d| {
                            let second = (-coms2[i][d] + coms2[i + len][d]) / l;
                            let first = ((coms[i][d] - coms[i + len][d]) / l).powi(2);
                            second - first
                        })
                        .sum::<f64>()
                })
                .sum();
            sum / terms as f64
        })
        .collect()
}

/// polychrom's `Rg2(data)`: the squared radius of gyration, `3 mean((x - mean(x))^2)`.
pub fn rg2(positions: &[[f64; 3]]) -> f64 {
    let n = positions.len() as f64;
    let mut mean = [0.0; 3];
    for p in positions {
        for d in 0..3 {
            mean[d] += p[d];
        }
    }
    for m in &mut mean {
        *m /= n;
    }
    let sum: f64 = positions
        .iter()
        .map(|p| (0..3).map(|d| (p[d] - mean[d]).powi(2)).sum::<f64>())
        .sum();
    sum / (3.0 * n) * 3.0
}

/// The statistics of a set of conformations.
#[derive(Clone, Debug, PartialEq)]
pub struct EnsembleStats {
    /// Beads per conformation.
    pub n_beads: usize,
    /// The separations ([`generate_bins`]).
    pub bins: Vec<usize>,
    /// P(s): per bin `[b_k, b_k+1)`, its geometric mid and mean contact probability.
    pub contact_scaling: Vec<(f64, f64)>,
    /// Per separation of `bins`: the mean `<R^2(s)>` and `<Rg^2(s)>`.
    pub r2: Vec<f64>,
    /// See `r2`.
    pub rg2_of_s: Vec<f64>,
    /// Each conformation's label and `Rg^2`, in order.
    pub rg2: Vec<(String, f64)>,
}

/// The statistics of `conformations` (every one with the beads of the first), contacts at most
/// `cutoff` apart; the conformations of a chunk are computed in parallel.
pub fn ensemble_stats(
    conformations: impl Iterator<Item = Result<Conformation>>,
    cutoff: f64,
) -> Result<EnsembleStats> {
    super::beads::check_radius(cutoff)?;
    let chunk_size = 4 * rayon::current_num_threads();
    let mut conformations = conformations.peekable();
    let n_beads = super::beads::first_beads(&mut conformations)?;
    if n_beads < 6 {
        return Err(Error::Data(format!(
            "{n_beads} beads: polymer statistics need at least 6 (separations from 4 to N - 1)"
        )));
    }
    let bins = generate_bins(n_beads, 4, 10);
    let mut sums_p = vec![0.0; bins.len().saturating_sub(1)];
    let mut sums_r2 = vec![0.0; bins.len()];
    let mut sums_rg2 = vec![0.0; bins.len()];
    let mut mids = Vec::new();
    let mut rg2s = Vec::new();
    for_each_chunk(
        &mut conformations,
        chunk_size,
        |_, c| super::beads::same_beads(c, n_beads),
        |chunk| {
            let results: Vec<_> = chunk
                .par_iter()
                .map_init(CellList::new, |cells, c| {
                    let (m, p) = contact_scaling(&c.positions, &bins, cutoff, cells);
                    (
                        m,
                        p,
                        r2_scaling(&c.positions, &bins),
                        rg2_scaling(&c.positions, &bins),
                        rg2(&c.positions),
                    )
                })
                .collect();
            for (c, (m, p, r2, rg2s_of_s, g)) in chunk.iter().zip(results) {
                mids = m;
                for (s, v) in sums_p.iter_mut().zip(p) {
                    *s += v;
                }
                for (s, v) in sums_r2.iter_mut().zip(r2) {
                    *s += v;
                }
                for (s, v) in sums_rg2.iter_mut().zip(rg2s_of_s) {
                    *s += v;
                }
                rg2s.push((c.label.clone(), g));
            }
        },
    )?;
    let count = rg2s.len() as f64;
    Ok(EnsembleStats {
        n_beads,
        contact_scaling: mids
            .into_iter()
            .zip(sums_p.iter().map(|s| s / count))
            .collect(),
        r2: sums_r2.iter().map(|s| s / count).collect(),
        rg2_of_s: sums_rg2.iter().map(|s| s / count).collect(),
        bins,
        rg2: rg2s,
    })
}

/// The local slopes `d ln y / d ln x` of a curve: between consecutive points with positive
/// coordinates, `ln(y1 / y0) / ln(x1 / x0)` at the geometric mean `sqrt(x0 x1)` (the exponent of
/// a power law `y = a x^k` is `k` everywhere). Pairs with a non-positive value are skipped.
///
/// ```
/// use contactmap::conformations::stats::log_slopes;
/// let curve: Vec<(f64, f64)> = [4.0, 8.0, 20.0].iter().map(|&s: &f64| (s, 3.0 * s.powf(-1.5))).collect();
/// let slopes = log_slopes(&curve);
/// assert_eq!(slopes.len(), 2);
/// assert!((slopes[0].0 - 32f64.sqrt()).abs() < 1e-12);
/// assert!(slopes.iter().all(|&(_, k)| (k + 1.5).abs() < 1e-12));
/// ```
pub fn log_slopes(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    points
        .windows(2)
        .filter(|w| w[0].0 > 0.0 && w[1].0 > w[0].0 && w[0].1 > 0.0 && w[1].1 > 0.0)
        .map(|w| {
            let ((x0, y0), (x1, y1)) = (w[0], w[1]);
            ((x0 * x1).sqrt(), (y1 / y0).ln() / (x1 / x0).ln())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight rod of unit bonds: R^2(s) = s^2 and the rod's Rg^2(s) = (s^2 - 1) / 12.
    #[test]
    fn a_rod_has_the_closed_forms() {
        let rod: Vec<[f64; 3]> = (0..40).map(|k| [k as f64, 0.0, 0.0]).collect();
        let bins = generate_bins(40, 4, 10);
        for (&s, r2) in bins.iter().zip(r2_scaling(&rod, &bins)) {
            assert!((r2 - (s * s) as f64).abs() < 1e-9 * (s * s) as f64);
        }
        for (&s, g) in bins.iter().zip(rg2_scaling(&rod, &bins)) {
            let want = ((s * s) as f64 - 1.0) / 12.0;
            assert!(
                (g - want).abs() < 1e-9 * want.max(1.0),
                "{s}: {g} vs {want}"
            );
        }
        assert!((rg2(&rod) - (40.0 * 40.0 - 1.0) / 12.0).abs() < 1e-9);
        // on a rod every pair 1 apart is in contact at cutoff 1 and none farther: P(s) is 0
        // from s = 4 on
        let (_, p) = contact_scaling(&rod, &bins, 1.0, &mut CellList::new());
        assert!(p.iter().all(|&v| v == 0.0));
    }
}
