//! Compartment calls against a truth: the fraction of bins whose eigenvector sign is the true
//! compartment's (A positive, B negative) and the correlation of the vector with the truth.

use std::collections::HashMap;
use std::path::Path;

use crate::compartments::phasing::{finite_pairs, pearson};
use crate::error::{Error, Result};
use crate::io::bed::BedRecord;
use crate::io::tables::{TrackRow, real_text as real};

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

/// `score compartments`: an eigenvector column (`rows`, from the table at `eigs`: `chrom start
/// end` then columns, as `compartments` writes) against the truth BED (`truth`, read from
/// `truth_path`: 4th column `A`, `B` or a signed number, on the same bins; both paths are named
/// in messages), scored per chromosome then over all bins:
/// TSV `chrom n_bins sign_accuracy sign_accuracy_up_to_sign pearson`. A truth that matches no
/// bin of the table is an error.
///
/// ```
/// use contactmap::io::{bed::read_bed, tables::read_track};
/// use contactmap::score::compartments::score_track_table;
/// let dir = std::env::temp_dir().join(format!("cm-score-ab-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let (truth, eigs) = (dir.join("truth.bed"), dir.join("eigs.tsv"));
/// std::fs::write(&truth, "chr1\t0\t10\tA\nchr1\t10\t20\tB\n").unwrap();
/// std::fs::write(&eigs, "chrom\tstart\tend\tE1\nchr1\t0\t10\t0.4\nchr1\t10\t20\t-0.2\n").unwrap();
/// let table = score_track_table(&truth, &read_bed(&truth)?, &eigs, &read_track(&eigs, "E1")?)?;
/// assert!(table.ends_with("all\t2\t1\t1\t1\n"), "{table}");
/// std::fs::remove_dir_all(&dir).unwrap();
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn score_track_table(
    truth_path: &Path,
    truth_records: &[BedRecord],
    eigs: &Path,
    rows: &[TrackRow],
) -> Result<String> {
    let mut truth: HashMap<(String, u64, u64), f64> = HashMap::new();
    for record in truth_records {
        let name = record.name.as_deref().unwrap_or("");
        let sign = match name.to_ascii_uppercase().as_str() {
            "A" => 1.0,
            "B" => -1.0,
            other => match other.parse::<f64>() {
                Ok(v) if v != 0.0 && v.is_finite() => v.signum(),
                _ => {
                    return Err(Error::format(
                        truth_path,
                        format!(
                            "{}:{}-{}: the 4th column must be A, B or a signed number, found '{name}'",
                            record.chrom, record.start, record.end
                        ),
                    ));
                }
            },
        };
        truth.insert((record.chrom.clone(), record.start, record.end), sign);
    }
    let mut chroms: Vec<String> = Vec::new();
    let mut by_chrom: HashMap<String, (Vec<f64>, Vec<f64>)> = HashMap::new();
    let mut matched = 0usize;
    for row in rows {
        let t = truth
            .get(&(row.chrom.clone(), row.start, row.end))
            .copied()
            .unwrap_or(f64::NAN);
        matched += t.is_finite() as usize;
        let entry = by_chrom.entry(row.chrom.clone()).or_insert_with(|| {
            chroms.push(row.chrom.clone());
            (Vec::new(), Vec::new())
        });
        entry.0.push(row.value);
        entry.1.push(t);
    }
    if matched == 0 {
        return Err(Error::format(
            eigs,
            format!(
                "no bin of the table is an interval of {} (the truth must be on the same bins)",
                truth_path.display()
            ),
        ));
    }
    let mut text =
        String::from("chrom\tn_bins\tsign_accuracy\tsign_accuracy_up_to_sign\tpearson\n");
    let (mut all_v, mut all_t) = (Vec::new(), Vec::new());
    let mut line = |name: &str, values: &[f64], t: &[f64]| {
        let s = score_compartments(values, t);
        text.push_str(&format!(
            "{name}\t{}\t{}\t{}\t{}\n",
            s.n_bins,
            real(s.sign_accuracy),
            real(s.sign_accuracy_up_to_sign),
            real(s.pearson)
        ));
    };
    for chrom in &chroms {
        let (v, t) = &by_chrom[chrom];
        line(chrom, v, t);
        all_v.extend_from_slice(v);
        all_t.extend_from_slice(t);
    }
    line("all", &all_v, &all_t);
    Ok(text)
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
