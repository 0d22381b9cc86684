//! How far a simulated chain has relaxed: the Rouse time scales of the model.
//!
//! Method: the Rouse model (Doi & Edwards, *The Theory of Polymer Dynamics*, 1986, ch. 4). In
//! the simulator's units (bead friction 1, kT 1), a chain segment of `s` beads with mean squared
//! bond `<b²>` relaxes in `τ(s) = s² <b²> / (3π²)`, and the whole chain of `N` beads in its
//! Rouse time `τ_R = N² <b²> / (3π²)`. A conformation sampled at time `t` after the start (a
//! random walk) is at equilibrium over separations up to
//!
//! `s*(t) = π sqrt(3 t / <b²>)` beads,
//!
//! and keeps the start's statistics beyond; its samples are independent at scales up to
//! `s*(Δt)` for an interval `Δt` between them.
//!
//! `<b²>` is the Boltzmann average of the bond energy alone, `∫ r⁴ e^-E(r) dr / ∫ r² e^-E(r)
//! dr` (bonded neighbours feel no excluded volume), times the Flory ratio `(1 + <cos θ>) / (1 −
//! <cos θ>)` of the angle stiffness (`<cos θ> = coth k − 1/k` for `E = k (1 − cos θ)`), so that
//! a stiff chain counts in its effective (Kuhn-like) segments.
//!
//! These are estimates: excluded volume slows the relaxation of long segments (`τ ~ s^{1+2ν}`,
//! 2.18 instead of 2 in good solvent), so `s*` is an upper estimate there, and a confined chain
//! stops swelling at the confinement's scale; attraction (compartments) is slower still. The
//! measured figures (docs/simulation.md, "Equilibration and sampling") say how far they hold.

use crate::error::{Error, Result};
use crate::sim::polymer::{BondModel, PolymerParams, Repulsion};

/// Rouse times in the model's time units (`steps × dt`) and relaxed separations in beads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Relaxation {
    /// `<b²>` of the model's bonds, times the Flory ratio of its angle stiffness.
    pub bond_msd: f64,
}

impl Relaxation {
    /// The time scales of `polymer`'s chains.
    pub fn new(polymer: &PolymerParams) -> Relaxation {
        Relaxation {
            bond_msd: mean_squared_bond(
                polymer.bond,
                (polymer.excluded_neighbours == 0).then_some(polymer.repulsion),
            ) * flory_ratio(polymer.angle_stiffness),
        }
    }

    /// The Rouse time of a chain of `n_beads`: `N² <b²> / (3π²)`.
    pub fn rouse_time(&self, n_beads: usize) -> f64 {
        (n_beads as f64).powi(2) * self.bond_msd / (3.0 * std::f64::consts::PI.powi(2))
    }

    /// The separation (beads) relaxed after `time`: `π sqrt(3 t / <b²>)`.
    pub fn relaxed_separation(&self, time: f64) -> f64 {
        std::f64::consts::PI * (3.0 * time.max(0.0) / self.bond_msd).sqrt()
    }
}

/// A number of steps given as text: a count (`2000`), Rouse times of the longest chain (`3R`,
/// `0.5r`), or `auto` (`auto_rouse` Rouse times); `rouse_steps` is that Rouse time in steps. A
/// Rouse-time count is rounded up, to at least one step. A bad value is an
/// [`Error::Parameter`] named `name` (the option, `equilibration` or `sample_every`).
///
/// ```
/// use contactmap::sim::relaxation::parse_steps;
/// assert_eq!(parse_steps("equilibration", "2000", 3.0, 100.0)?, 2000);
/// assert_eq!(parse_steps("equilibration", "auto", 3.0, 100.5)?, 302);
/// assert_eq!(parse_steps("equilibration", "0.5R", 3.0, 100.0)?, 50);
/// assert!(parse_steps("equilibration", "-2R", 3.0, 100.0).is_err());
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn parse_steps(
    name: &'static str,
    text: &str,
    auto_rouse: f64,
    rouse_steps: f64,
) -> Result<usize> {
    let bad = |expected: String| Error::parameter(name, format!("'{text}'"), expected);
    let trimmed = text.trim();
    let rouse_times = if trimmed.eq_ignore_ascii_case("auto") {
        Some(auto_rouse)
    } else if let Some(number) = trimmed.strip_suffix(['R', 'r']) {
        Some(
            number
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && *x > 0.0)
                .ok_or_else(|| bad("expected a positive number of Rouse times, e.g. 3R".into()))?,
        )
    } else {
        None
    };
    match rouse_times {
        Some(times) => {
            let steps = (times * rouse_steps).ceil();
            if steps >= usize::MAX as f64 {
                return Err(bad(format!("{steps:e} steps is more than can be counted")));
            }
            Ok((steps as usize).max(1))
        }
        None => trimmed
            .parse::<usize>()
            .map_err(|_| bad("expected a number of steps, auto, or Rouse times such as 3R".into())),
    }
}

/// `<b²>` of a bond, `∫ r⁴ e^-E(r) dr / ∫ r² e^-E(r) dr`, by the midpoint rule over the range
/// where the weight is not negligible; `E` is the bond energy, plus `repulsion` when bonded
/// neighbours feel it (`excluded_neighbours` 0, as Kremer-Grest's FENE + WCA).
pub fn mean_squared_bond(bond: BondModel, repulsion: Option<Repulsion>) -> f64 {
    let (low, high) = match bond {
        BondModel::Harmonic { length, wiggle } => {
            ((length - 12.0 * wiggle).max(0.0), length + 12.0 * wiggle)
        }
        BondModel::Fene { max_length, .. } => (0.0, max_length * 0.99),
    };
    let n = 20_000;
    let step = (high - low) / n as f64;
    let (mut zeroth, mut second) = (0.0, 0.0);
    for k in 0..n {
        let r = low + (k as f64 + 0.5) * step;
        let mut energy = crate::sim::polymer::bond_terms(bond, r * r).0;
        if let Some(repulsion) = &repulsion {
            energy += crate::sim::polymer::pair_terms(repulsion, None, r * r).0;
        }
        let weight = r * r * (-energy).exp();
        zeroth += weight;
        second += weight * r * r;
    }
    second / zeroth
}

/// The Flory characteristic ratio `(1 + <cos θ>) / (1 − <cos θ>)` of the angle energy
/// `k (1 − cos θ)` (1 without stiffness).
pub fn flory_ratio(stiffness: f64) -> f64 {
    if stiffness < 1e-6 {
        return 1.0;
    }
    // The Langevin function; its series near 0 avoids the cancellation.
    let cos = if stiffness < 1e-3 {
        stiffness / 3.0
    } else {
        1.0 / stiffness.tanh() - 1.0 / stiffness
    };
    (1.0 + cos) / (1.0 - cos)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_are_given_as_steps_or_rouse_times() {
        assert_eq!(parse_steps("x", "2000", 3.0, 100.0).unwrap(), 2000);
        assert_eq!(parse_steps("x", "auto", 3.0, 100.5).unwrap(), 302);
        assert_eq!(parse_steps("x", "0.5R", 3.0, 100.0).unwrap(), 50);
        assert_eq!(parse_steps("x", "2r", 3.0, 100.0).unwrap(), 200);
        assert_eq!(parse_steps("x", "1e-9R", 3.0, 100.0).unwrap(), 1);
        for bad in ["-1", "R", "0R", "-2R", "x", "1.5", "nanR"] {
            let error = parse_steps("x", bad, 3.0, 100.0).unwrap_err().to_string();
            assert!(error.starts_with(&format!("x '{bad}': ")), "{bad}: {error}");
        }
    }

    /// `<b²>` against closed forms: a harmonic bond of small wiggle `w` has `r = 1 + δ` with
    /// `δ ~ N(w², w²/2)` to first order (the `r²` Jacobian shifts the mean), so `<b²> ≈ 1 + 2.5
    /// w²`; at w = 0.3 the ideal-chain dynamics measure 1.2348 (docs/simulation.md).
    #[test]
    fn mean_squared_bonds() {
        for w in [0.05, 0.1] {
            let b2 = mean_squared_bond(
                BondModel::Harmonic {
                    length: 1.0,
                    wiggle: w,
                },
                None,
            );
            assert!((b2 - (1.0 + 2.5 * w * w)).abs() < 0.02 * w * w, "{w}: {b2}");
        }
        let b2 = mean_squared_bond(
            BondModel::Harmonic {
                length: 1.0,
                wiggle: 0.3,
            },
            None,
        );
        // The dynamics measure 1.2348 at dt 0.01: Euler-Maruyama widens the bonds by O(dt).
        assert!(b2 < 1.2348 && 1.2348 - b2 < 0.02, "{b2}");
        // FENE alone pulls the beads together: p(r) ~ r² (1 - r²/R0²)^(K R0²/2), about
        // r² exp(-K r² / 2), so <b²> is near 3 / K = 0.1 (0.093 with the logarithm's tail);
        // with WCA between bonded neighbours too (Kremer-Grest), the bond sits near 0.97.
        let fene = BondModel::Fene {
            stiffness: 30.0,
            max_length: 1.5,
        };
        let b2 = mean_squared_bond(fene, None);
        assert!((b2 - 0.093).abs() < 0.01, "{b2}");
        let wca = Repulsion::Wca {
            epsilon: 1.0,
            sigma: 1.0,
        };
        let b2 = mean_squared_bond(fene, Some(wca));
        assert!((b2.sqrt() - 0.97).abs() < 0.02, "{b2}");
    }

    #[test]
    fn flory_ratio_limits() {
        assert_eq!(flory_ratio(0.0), 1.0);
        // Large k: <cos> -> 1 - 1/k, ratio -> 2k - 1.
        assert!((flory_ratio(100.0) / 199.0 - 1.0).abs() < 1e-3);
        assert!((flory_ratio(1e-4) - (1.0 + 2.0 * 1e-4 / 3.0)).abs() < 1e-6);
    }

    /// `s*` is the inverse of `τ(s)`: the separation relaxed after one Rouse time is the chain.
    #[test]
    fn relaxed_separation_inverts_the_rouse_time() {
        let relaxation = Relaxation { bond_msd: 1.025 };
        for n in [16, 64, 1000] {
            let s = relaxation.relaxed_separation(relaxation.rouse_time(n));
            assert!((s - n as f64).abs() < 1e-9 * n as f64, "{n}: {s}");
        }
    }
}
