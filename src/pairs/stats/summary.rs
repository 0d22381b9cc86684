//! The `summary/` lines: fractions, the naive library complexity (with the Lambert W function
//! it needs) and the convergence of the strand pairs' distance histograms.

use super::counter::{CIS_KEYS, PairCounter};
use crate::io::output::python_float;

/// The relative departure from the mean of the four strand pairs beyond which a distance bin
/// has not converged (pairtools' `DIST_FREQ_REL_DIFF_THRESHOLD`).
const CONVERGENCE_REL_DIFF: f64 = 0.05;

/// The strand pairs in the order pairtools writes the convergence lines, as indices into
/// [`super::counter::STRAND_PAIRS`] (`++`, `--`, `-+`, `+-`).
const CONVERGENCE_ORDER: [usize; 4] = [3, 2, 1, 0];

/// The number of distinct molecules in a library from which `n_sequences` reads were drawn
/// with `n_duplicates` duplicates among them (pairtools' `estimate_library_complexity` with no
/// optical duplicates, after Picard's `EstimateLibraryComplexity`): the `C` with
/// `n_sequences - n_duplicates = C (1 - exp(-n_sequences / C))`, found as pairtools finds it,
/// `n_sequences / (W0(-exp(-1/u) / u) + 1/u)` with `u` the fraction of unique reads and W0
/// scipy's `lambertw` ([`lambert_w0`]).
///
/// `None` where pairtools returns the integer 0: no reads, or only duplicates. Without
/// duplicates the equation has no finite solution and pairtools' scipy call does not converge:
/// the result is NaN, as pairtools writes it (`nan`).
///
/// ```
/// use contactmap::pairs::stats::estimate_library_complexity;
///
/// let complexity = estimate_library_complexity(1000, 100).unwrap();
/// let unique = complexity * (1.0 - (-1000.0 / complexity).exp());
/// assert!((unique - 900.0).abs() < 1e-9 * 900.0);
/// assert_eq!(estimate_library_complexity(0, 0), None);
/// assert!(estimate_library_complexity(10, 0).unwrap().is_nan());
/// ```
pub fn estimate_library_complexity(n_sequences: u64, n_duplicates: u64) -> Option<f64> {
    if n_sequences == 0 {
        return None;
    }
    let unique_fraction = n_sequences.saturating_sub(n_duplicates) as f64 / n_sequences as f64;
    if unique_fraction == 0.0 {
        return None;
    }
    let z = -(-1.0 / unique_fraction).exp() / unique_fraction;
    let seq_to_complexity = lambert_w0(z) + 1.0 / unique_fraction;
    Some(n_sequences as f64 / seq_to_complexity)
}

/// A complex number, for the few operations of scipy's Lambert W iteration: near the branch
/// point its first guess can leave the real line.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Complex {
    re: f64,
    im: f64,
}

impl Complex {
    fn real(re: f64) -> Complex {
        Complex { re, im: 0.0 }
    }

    fn add(self, other: Complex) -> Complex {
        Complex {
            re: self.re + other.re,
            im: self.im + other.im,
        }
    }

    fn sub(self, other: Complex) -> Complex {
        Complex {
            re: self.re - other.re,
            im: self.im - other.im,
        }
    }

    fn mul(self, other: Complex) -> Complex {
        Complex {
            re: self.re * other.re - self.im * other.im,
            im: self.re * other.im + self.im * other.re,
        }
    }

    fn scale(self, factor: f64) -> Complex {
        Complex {
            re: self.re * factor,
            im: self.im * factor,
        }
    }

    /// Smith's division (exact real division when both imaginary parts are 0).
    fn div(self, other: Complex) -> Complex {
        let (a, b, c, d) = (self.re, self.im, other.re, other.im);
        if c == 0.0 && d == 0.0 {
            return Complex {
                re: a / c,
                im: b / c,
            };
        }
        if c.abs() >= d.abs() {
            let ratio = d / c;
            let denominator = c + d * ratio;
            Complex {
                re: (a + b * ratio) / denominator,
                im: (b - a * ratio) / denominator,
            }
        } else {
            let ratio = c / d;
            let denominator = c * ratio + d;
            Complex {
                re: (a * ratio + b) / denominator,
                im: (b * ratio - a) / denominator,
            }
        }
    }

    fn exp(self) -> Complex {
        let magnitude = self.re.exp();
        if self.im == 0.0 {
            return Complex {
                re: magnitude,
                im: self.im,
            };
        }
        Complex {
            re: magnitude * self.im.cos(),
            im: magnitude * self.im.sin(),
        }
    }

    /// The principal square root (C's `csqrt` on the real line: a negative number's root is
    /// imaginary).
    fn sqrt(self) -> Complex {
        if self.im == 0.0 {
            return if self.re >= 0.0 {
                Complex {
                    re: self.re.sqrt(),
                    im: self.im,
                }
            } else {
                Complex {
                    re: 0.0,
                    im: (-self.re).sqrt().copysign(self.im),
                }
            };
        }
        let modulus = self.abs();
        let re = ((modulus + self.re) / 2.0).sqrt();
        let im = ((modulus - self.re) / 2.0).sqrt().copysign(self.im);
        Complex { re, im }
    }

    fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }

    /// `c0 z^2 + c1 z + c2` as scipy evaluates a real polynomial at a complex point (with
    /// `r = 2 Re z`, `s = |z|^2` and fused multiply-adds).
    fn polynomial(self, [c0, c1, c2]: [f64; 3]) -> Complex {
        let r = 2.0 * self.re;
        let s = self.re * self.re + self.im * self.im;
        let b = (-s).mul_add(c0, c2);
        let a = r.mul_add(c0, c1);
        self.scale(a).add(Complex::real(b))
    }
}

/// The principal branch of the Lambert W function (`w` with `w e^w = z`) at a real `z >= -1/e`,
/// computed as scipy's `lambertw(z).real` (the default tolerance 1e-8 of Halley's iteration)
/// so that pairtools' complexity is reproduced where W is ill-conditioned, next to `-1/e`:
/// the first guess is the series at the branch point within 0.3 of `-1/e`, the (3, 2) Padé
/// approximant near 0, `log z - log log z` elsewhere; Halley's iteration stops when a step is
/// at most 1e-8 of the value; after 100 steps the result is NaN (as at `z` = the `f64` nearest
/// `-1/e`, where the iteration divides 0 by 0).
///
/// ```
/// use contactmap::pairs::stats::lambert_w0;
///
/// for x in [-0.9f64, -0.5, -0.1, 0.0, 0.5, 2.0] {
///     let w = lambert_w0(x * x.exp());
///     assert!((w - x).abs() < 1e-12, "{x} {w}");
/// }
/// ```
pub fn lambert_w0(z: f64) -> f64 {
    const EXP_MINUS_1: f64 = 0.367_879_441_171_442_33;
    const TOLERANCE: f64 = 1e-8;
    if z.is_nan() || z == f64::INFINITY || z == 0.0 {
        return z;
    }
    let z = Complex::real(z);
    let mut w = if z.add(Complex::real(EXP_MINUS_1)).abs() < 0.3 {
        let p = z
            .scale(std::f64::consts::E)
            .add(Complex::real(1.0))
            .scale(2.0)
            .sqrt();
        p.polynomial([-1.0 / 3.0, 1.0, -1.0])
    } else if z.re > -0.2 && z.re < 1.5 {
        let numerator = z.polynomial([12.851_063_829_787_234, 12.340_425_531_914_894, 1.0]);
        let denominator = z.polynomial([32.531_914_893_617_02, 14.340_425_531_914_894, 1.0]);
        z.mul(numerator).div(denominator)
    } else {
        let log = Complex::real(z.re.ln());
        log.sub(Complex::real(log.re.ln()))
    };
    for _ in 0..100 {
        let two = Complex::real(2.0);
        let next = if w.re >= 0.0 {
            let residual = w.sub(z.mul(w.scale(-1.0).exp()));
            let correction = w
                .add(Complex::real(1.0))
                .sub(w.add(two).mul(residual).div(w.scale(2.0).add(two)));
            w.sub(residual.div(correction))
        } else {
            let exp_w = w.exp();
            let w_exp_w = w.mul(exp_w);
            let residual = w_exp_w.sub(z);
            let correction = w_exp_w
                .add(exp_w)
                .sub(w.add(two).mul(residual).div(w.scale(2.0).add(two)));
            w.sub(residual.div(correction))
        };
        if next.sub(w).abs() <= TOLERANCE * next.abs() {
            return next.re;
        }
        w = next;
    }
    f64::NAN
}

/// `n / d` as pairtools writes a top-level summary fraction: the integer 0 when `d` is 0.
fn fraction_or_zero(n: u64, d: u64) -> String {
    if d > 0 {
        python_float(n as f64 / d as f64)
    } else {
        "0".into()
    }
}

impl PairCounter {
    /// The `summary/` lines (key without `summary/`, value), in pairtools' order.
    pub(super) fn summary_lines(&self) -> Vec<(String, String)> {
        let mut lines = Vec::new();
        lines.push((
            "frac_cis".into(),
            fraction_or_zero(self.cis, self.total_nodups),
        ));
        for (key, count) in CIS_KEYS.iter().zip(self.cis_beyond) {
            lines.push((
                format!("frac_{key}"),
                fraction_or_zero(count, self.total_nodups),
            ));
        }
        lines.push((
            "frac_dups".into(),
            fraction_or_zero(self.total_dups, self.total_mapped),
        ));
        let complexity = estimate_library_complexity(self.total_mapped, self.total_dups);
        lines.push((
            "complexity_naive".into(),
            complexity.map_or_else(|| "0".into(), python_float),
        ));
        for (key, value) in self.convergence_lines() {
            lines.push((format!("dist_freq_convergence/{key}"), value));
        }
        lines
    }

    /// pairtools' `find_dist_freq_convergence_distance`: the lines under
    /// `summary/dist_freq_convergence/`.
    fn convergence_lines(&self) -> Vec<(String, String)> {
        let strand_names = super::counter::STRAND_PAIRS;
        let n_bins = self.dist_bins.len();
        let mean: Vec<f64> = (0..n_bins)
            .map(|bin| {
                CONVERGENCE_ORDER
                    .iter()
                    .map(|&s| self.dist_freq[s][bin] as f64)
                    .fold(0.0, |sum, count| sum + count)
                    / 4.0
            })
            .collect();
        // The last bin where a strand pair departs from the mean by more than the threshold
        // (0 when none does; a bin with a mean of 0 departs by 0).
        let last_departure = |s: usize| {
            (0..n_bins)
                .rev()
                .find(|&bin| {
                    let departure = (self.dist_freq[s][bin] as f64 - mean[bin]).abs() / mean[bin];
                    !departure.is_nan() && departure > CONVERGENCE_REL_DIFF
                })
                .unwrap_or(0)
        };
        let mut convergence_bin = 0;
        let mut convergence_strands = "??";
        let mut convergence_dist = "0".to_string();
        for s in CONVERGENCE_ORDER {
            let bin = last_departure(s);
            if bin > convergence_bin {
                convergence_bin = bin;
                convergence_strands = strand_names[s];
                // pairtools fails on the last bin (1e9+); it meant the largest int64 there.
                convergence_dist = self
                    .dist_bins
                    .get(bin + 1)
                    .map_or_else(|| i64::MAX.to_string(), u64::to_string);
            }
        }
        let below: Vec<u64> = CONVERGENCE_ORDER
            .iter()
            .map(|&s| self.dist_freq[s][..=convergence_bin].iter().sum())
            .collect();
        let n_below: u64 = below.iter().sum();
        let n_above: u64 = CONVERGENCE_ORDER
            .iter()
            .map(|&s| self.dist_freq[s][convergence_bin + 1..].iter().sum::<u64>())
            .sum();

        let mut lines = vec![
            ("convergence_dist".to_string(), convergence_dist),
            (
                "strands_w_max_convergence_dist".into(),
                convergence_strands.to_string(),
            ),
            (
                "convergence_rel_diff_threshold".into(),
                python_float(CONVERGENCE_REL_DIFF),
            ),
        ];
        for (&s, count) in CONVERGENCE_ORDER.iter().zip(&below) {
            lines.push((
                format!("n_cis_pairs_below_convergence_dist/{}", strand_names[s]),
                count.to_string(),
            ));
        }
        lines.push((
            "n_cis_pairs_below_convergence_dist_all_strands".into(),
            n_below.to_string(),
        ));
        lines.push((
            "n_cis_pairs_above_convergence_dist_all_strands".into(),
            n_above.to_string(),
        ));
        for (name, norm) in [
            ("cis", self.cis),
            ("total_mapped", self.total_mapped),
            ("total_nodups", self.total_nodups),
        ] {
            // numpy's division: 0 / 0 is NaN.
            let fractions: Vec<f64> = below.iter().map(|&n| n as f64 / norm as f64).collect();
            for (&s, fraction) in CONVERGENCE_ORDER.iter().zip(&fractions) {
                lines.push((
                    format!(
                        "frac_{name}_in_cis_below_convergence_dist/{}",
                        strand_names[s]
                    ),
                    python_float(*fraction),
                ));
            }
            let sum = fractions.iter().fold(0.0, |sum, fraction| sum + fraction);
            lines.push((
                format!("frac_{name}_in_cis_below_convergence_dist_all_strands"),
                python_float(sum),
            ));
            lines.push((
                format!("frac_{name}_in_cis_above_convergence_dist_all_strands"),
                python_float(n_above as f64 / norm as f64),
            ));
        }
        lines
    }
}
