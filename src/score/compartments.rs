//! Compartment calls against a truth: the fraction of bins whose eigenvector sign is the true
//! compartment's (A positive, B negative) and the correlation of the vector with the truth.

use crate::compartments::phasing::{finite_pairs, pearson};

/// The score of one set of bins.
#[derive(Clone, Debug, PartialEq)]
pub struct CompartmentScore {
    /// Bins with a finite value and a truth.
    pub n_bins: usize,
    /// Fraction of them whose sign is right (0 counts as wrong).
    pub sign_accuracy: f64,
    /// The same after flipping the whole vector when that is better (for vectors whose sign was
    /// not set by a phasing track).
    pub sign_accuracy_up_to_sign: f64,
    /// Pearson correlation of the values with the truth as +1 (A) / -1 (B).
    pub pearson: f64,
}

/// Score `values` against `truth` (+1 for A, -1 for B, NaN for no truth), bin by bin.
///
/// # Examples
///
/// ```
/// use contactmap::score::compartments::score_compartments;
///
/// let truth = [1.0, 1.0, -1.0, -1.0, f64::NAN];
/// let right = score_compartments(&[0.5, 0.2, -0.3, -0.9, 1.0], &truth);
/// assert_eq!((right.n_bins, right.sign_accuracy), (4, 1.0));
/// let flipped = score_compartments(&[-0.5, -0.2, 0.3, 0.1, 1.0], &truth);
/// assert_eq!((flipped.sign_accuracy, flipped.sign_accuracy_up_to_sign), (0.0, 1.0));
/// assert!(flipped.pearson < 0.0);
/// let exact = score_compartments(&truth, &truth);
/// assert!((exact.pearson - 1.0).abs() < 1e-12);
/// ```
pub fn score_compartments(values: &[f64], truth: &[f64]) -> CompartmentScore {
    let (x, y) = finite_pairs(values, truth);
    let right = x.iter().zip(&y).filter(|(v, t)| **v * **t > 0.0).count();
    let wrong_sign = x.iter().zip(&y).filter(|(v, t)| **v * **t < 0.0).count();
    let n = x.len();
    let fraction = |k: usize| {
        if n == 0 {
            f64::NAN
        } else {
            k as f64 / n as f64
        }
    };
    CompartmentScore {
        n_bins: n,
        sign_accuracy: fraction(right),
        sign_accuracy_up_to_sign: fraction(right.max(wrong_sign)),
        pearson: pearson(&x, &y),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_signs_and_correlates() {
        let truth = [1.0, 1.0, -1.0, -1.0, f64::NAN];
        let values = [0.5, -0.1, -2.0, -0.3, 9.0];
        let s = score_compartments(&values, &truth);
        assert_eq!(s.n_bins, 4);
        assert_eq!(s.sign_accuracy, 0.75);
        assert_eq!(s.sign_accuracy_up_to_sign, 0.75);
        let flipped: Vec<f64> = values.iter().map(|v| -v).collect();
        let f = score_compartments(&flipped, &truth);
        assert_eq!(f.sign_accuracy, 0.25);
        assert_eq!(f.sign_accuracy_up_to_sign, 0.75);
        assert!((f.pearson + s.pearson).abs() < 1e-15);
        // numpy.corrcoef([0.5, -0.1, -2.0, -0.3], [1, 1, -1, -1])[0, 1]
        assert!(
            (s.pearson - 0.7270790499578432).abs() < 1e-12,
            "{}",
            s.pearson
        );
    }
}
