//! Differential compartments: each replicate's first cis eigenvector (E1, cooltools' `eigs_cis`
//! of the balanced map, oriented by a phasing track where one is given), every replicate's E1
//! given the sign of the first replicate's on each region (an eigenvector's sign is arbitrary;
//! this makes the replicates comparable whatever the track), then per bin the difference of the
//! conditions' mean E1 tested with limma's moderated t ([`super::moderated`]) and
//! Benjamini-Hochberg q-values. A bin switches `A->B` when its mean E1 is positive in A,
//! negative in B and its q-value under `alpha` (`B->A` the other way); consecutive bins of a
//! region with the same switch make a segment.

use ndarray::Array2;

use super::maps::{check_conditions, check_same_bins};
use super::moderated::{ModeratedT, moderated_t};
use super::tables::{condition_mean, number, sample_names};
use super::test::benjamini_hochberg;
use crate::compartments::cis::CisEigParams;
use crate::compartments::eigs::{Phasing, eigs_cis};
use crate::error::Result;
use crate::genome::{BinTable, View};
#[cfg(test)]
use crate::io::InMemory;
use crate::io::MatrixReader;

/// Settings of `diff compartments`.
#[derive(Debug, Clone)]
pub struct CompartmentParams {
    /// The eigenvectors' settings (cooltools' defaults; only E1 is used).
    pub eigs: CisEigParams,
    /// q-value under which a bin counts as switched (0.05).
    pub alpha: f64,
}

impl Default for CompartmentParams {
    fn default() -> Self {
        CompartmentParams {
            eigs: CisEigParams {
                n_eigs: 1,
                ..CisEigParams::default()
            },
            alpha: 0.05,
        }
    }
}

/// A bin's change of compartment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Switch {
    /// Positive mean E1 in A, negative in B, significant.
    AToB,
    /// Negative in A, positive in B, significant.
    BToA,
    /// Neither.
    None,
}

impl Switch {
    /// The word written in the tables.
    pub fn as_str(self) -> &'static str {
        match self {
            Switch::AToB => "A->B",
            Switch::BToA => "B->A",
            Switch::None => "-",
        }
    }
}

/// The comparison, one row per bin of the view's regions.
#[derive(Debug, Clone)]
pub struct CompartmentComparison {
    /// Genome-wide bin of each row.
    pub bins: Vec<usize>,
    /// View region of each row.
    pub region: Vec<usize>,
    /// E1 per replicate (A's first), sign-aligned.
    pub e1: Array2<f64>,
    /// The moderated test of E1 (B minus A).
    pub test: ModeratedT,
    /// Benjamini-Hochberg q-values.
    pub q_value: Vec<f64>,
    /// Each row's switch at `q < alpha`.
    pub switch: Vec<Switch>,
    /// Replicates in A.
    pub n_first: usize,
    /// Problems met computing the eigenvectors (one line each).
    pub warnings: Vec<String>,
}

impl CompartmentComparison {
    /// The mean E1 of A (`condition` 0) or B (1) at `row`.
    pub fn mean(&self, row: usize, condition: usize) -> f64 {
        condition_mean(self.e1.row(row), self.n_first, condition)
    }

    /// Runs of consecutive rows of one region with the same switch: `(first row, last row + 1,
    /// switch)`.
    pub fn segments(&self) -> Vec<(usize, usize, Switch)> {
        let mut segments = Vec::new();
        let mut row = 0;
        while row < self.bins.len() {
            let switch = self.switch[row];
            let mut end = row + 1;
            while end < self.bins.len()
                && self.switch[end] == switch
                && self.region[end] == self.region[row]
                && self.bins[end] == self.bins[end - 1] + 1
            {
                end += 1;
            }
            if switch != Switch::None {
                segments.push((row, end, switch));
            }
            row = end;
        }
        segments
    }
}

/// Compare the compartments of `readers[..n_first]` (A) and `readers[n_first..]` (B), maps on
/// the same bins balanced by `weights`, over `view`, E1 oriented by `track` (one value per bin)
/// where given.
pub fn compare_compartments(
    readers: &[&dyn MatrixReader],
    weights: &[&[f64]],
    n_first: usize,
    view: &View,
    track: Option<&[f64]>,
    params: &CompartmentParams,
) -> Result<CompartmentComparison> {
    check_conditions(readers.len(), n_first)?;
    check_same_bins(readers)?;
    let n = readers.len();
    let rows: Vec<(usize, usize)> = view
        .regions()
        .iter()
        .enumerate()
        .flat_map(|(r, region)| region.bins.clone().map(move |bin| (bin, r)))
        .collect();
    let mut e1 = Array2::from_elem((rows.len(), n), f64::NAN);
    let mut warnings = Vec::new();
    let phasing = Phasing { track, sort: None };
    for (s, (reader, w)) in readers.iter().zip(weights).enumerate() {
        let eigs = eigs_cis(*reader, w, view, phasing, &params.eigs)?;
        warnings.extend(
            eigs.warnings
                .iter()
                .map(|line| format!("{}: {line}", reader.source())),
        );
        let mut row = 0;
        for region in &eigs.eigs {
            for value in &region.vectors[0] {
                e1[[row, s]] = *value;
                row += 1;
            }
        }
    }
    // every replicate's sign made that of the first replicate, region by region
    let mut start = 0;
    for region in view.regions() {
        let rows_of_region = start..start + region.n_bins();
        for s in 1..n {
            let agreement: f64 = rows_of_region
                .clone()
                .map(|row| e1[[row, 0]] * e1[[row, s]])
                .filter(|v| !v.is_nan())
                .sum();
            if agreement < 0.0 {
                for row in rows_of_region.clone() {
                    e1[[row, s]] = -e1[[row, s]];
                }
            }
        }
        start = rows_of_region.end;
    }
    let test = moderated_t(e1.view(), n_first);
    let q_value = benjamini_hochberg(&test.p_value);
    let mut comparison = CompartmentComparison {
        bins: rows.iter().map(|(bin, _)| *bin).collect(),
        region: rows.iter().map(|(_, r)| *r).collect(),
        e1,
        test,
        q_value,
        switch: Vec::new(),
        n_first,
        warnings,
    };
    comparison.switch = (0..rows.len())
        .map(|row| {
            let (a, b) = (comparison.mean(row, 0), comparison.mean(row, 1));
            if comparison.q_value[row] >= params.alpha || comparison.q_value[row].is_nan() {
                Switch::None
            } else if a > 0.0 && b < 0.0 {
                Switch::AToB
            } else if a < 0.0 && b > 0.0 {
                Switch::BToA
            } else {
                Switch::None
            }
        })
        .collect();
    Ok(comparison)
}

/// The per-bin table with a header line: `chrom start end E1_A E1_B` (mean E1), `difference`
/// (B minus A), `se t df pvalue qvalue switch`, then each replicate's E1 (`E1_A1` ...).
pub fn compartments_tsv(bins: &BinTable, comparison: &CompartmentComparison) -> String {
    let n = comparison.e1.ncols();
    let names: Vec<String> = sample_names(n, comparison.n_first)
        .iter()
        .map(|name| format!("E1_{name}"))
        .collect();
    let mut out = format!(
        "chrom\tstart\tend\tE1_A\tE1_B\tdifference\tse\tt\tdf\tpvalue\tqvalue\tswitch\t{}\n",
        names.join("\t")
    );
    let test = &comparison.test;
    for (row, &bin) in comparison.bins.iter().enumerate() {
        let b = bins.bin(bin);
        let fields = [
            bins.chroms()[b.chrom_id].name.clone(),
            b.start.to_string(),
            b.end.to_string(),
            number(comparison.mean(row, 0)),
            number(comparison.mean(row, 1)),
            number(test.difference[row]),
            number(test.standard_error(row)),
            number(test.t[row]),
            number(test.df_total[row]),
            number(test.p_value[row]),
            number(comparison.q_value[row]),
            comparison.switch[row].as_str().to_string(),
        ];
        out.push_str(&fields.join("\t"));
        for value in comparison.e1.row(row) {
            out.push('\t');
            out.push_str(&number(*value));
        }
        out.push('\n');
    }
    out
}

/// The switched segments as BED with a header line: `chrom start end switch n_bins E1_A E1_B`
/// (mean over the segment's bins) `max_qvalue`.
pub fn switches_bed(bins: &BinTable, comparison: &CompartmentComparison) -> String {
    let mut out = String::from("chrom\tstart\tend\tswitch\tn_bins\tE1_A\tE1_B\tmax_qvalue\n");
    for (first, end, switch) in comparison.segments() {
        let (a, b) = (
            bins.bin(comparison.bins[first]),
            bins.bin(comparison.bins[end - 1]),
        );
        let mean = |condition: usize| {
            (first..end)
                .map(|row| comparison.mean(row, condition))
                .sum::<f64>()
                / (end - first) as f64
        };
        let max_q = comparison.q_value[first..end]
            .iter()
            .copied()
            .fold(f64::NAN, f64::max);
        out.push_str(&format!(
            "{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\n",
            bins.chroms()[a.chrom_id].name,
            a.start,
            b.end,
            switch.as_str(),
            end - first,
            number(mean(0)),
            number(mean(1)),
            number(max_q)
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::maps::synthetic::replicate;
    use super::*;

    /// Alternating 20-bin compartments (sign `s`), contacts `(1 + 0.5 s_i s_j)` times a
    /// distance decay; B turns bins 60..80 from B (negative) to A.
    fn checkerboard(flip: bool) -> impl Fn(u64, u64) -> f64 {
        move |i, j| {
            let sign = |b: u64| {
                let s = if (b / 20).is_multiple_of(2) {
                    1.0
                } else {
                    -1.0
                };
                if flip && (60..80).contains(&b) { -s } else { s }
            };
            (1.0 + 0.5 * sign(i) * sign(j)) * 300.0 / (j - i + 1) as f64
        }
    }

    fn compare(first: &[InMemory], second: &[InMemory], track: &[f64]) -> CompartmentComparison {
        let readers: Vec<&dyn MatrixReader> = first
            .iter()
            .chain(second)
            .map(|r| r as &dyn MatrixReader)
            .collect();
        let ones = vec![1.0; 200];
        let weights = vec![&ones[..]; readers.len()];
        let view = View::chromosomes(readers[0].bins());
        let params = CompartmentParams::default();
        compare_compartments(&readers, &weights, first.len(), &view, Some(track), &params).unwrap()
    }

    #[test]
    fn a_planted_switch_is_found_and_nothing_else() {
        let track: Vec<f64> = (0..200)
            .map(|b: usize| if (b / 20).is_multiple_of(2) { 1.0 } else { 0.0 })
            .collect();
        let first: Vec<InMemory> = (1..=2)
            .map(|s| replicate(200, 200, s, checkerboard(false)))
            .collect();
        let second: Vec<InMemory> = (3..=4)
            .map(|s| replicate(200, 200, s, checkerboard(true)))
            .collect();
        let comparison = compare(&first, &second, &track);
        let switched: Vec<usize> = (0..200)
            .filter(|&row| comparison.switch[row] != Switch::None)
            .collect();
        assert!(
            switched
                .iter()
                .all(|&row| (60..80).contains(&row) && comparison.switch[row] == Switch::BToA),
            "{switched:?}"
        );
        assert!(switched.len() >= 16, "{switched:?}");
        let segments = comparison.segments();
        assert!(!segments.is_empty() && segments.len() <= 3, "{segments:?}");
        // E1 follows the track: positive on the track's 1s in A
        assert!(comparison.mean(5, 0) > 0.0 && comparison.mean(25, 0) < 0.0);

        let again: Vec<InMemory> = (5..=6)
            .map(|s| replicate(200, 200, s, checkerboard(false)))
            .collect();
        let null = compare(&first, &again, &track);
        assert!(null.switch.iter().all(|s| *s == Switch::None));
    }

    /// A bin masked in one replicate (no E1 there) is tested on the others, and its condition's
    /// mean is theirs: the switch is still called.
    #[test]
    fn a_bin_masked_in_one_replicate_can_still_switch() {
        let track: Vec<f64> = (0..200)
            .map(|b: usize| if (b / 20).is_multiple_of(2) { 1.0 } else { 0.0 })
            .collect();
        let maps: Vec<InMemory> = (1..=2)
            .map(|s| replicate(200, 200, s, checkerboard(false)))
            .chain((3..=4).map(|s| replicate(200, 200, s, checkerboard(true))))
            .collect();
        let readers: Vec<&dyn MatrixReader> = maps.iter().map(|r| r as &dyn MatrixReader).collect();
        let ones = vec![1.0; 200];
        let mut masked = ones.clone();
        masked[70] = f64::NAN;
        let weights = vec![&ones[..], &ones[..], &masked[..], &ones[..]];
        let view = View::chromosomes(readers[0].bins());
        let params = CompartmentParams::default();
        let comparison =
            compare_compartments(&readers, &weights, 2, &view, Some(&track), &params).unwrap();
        assert!(comparison.e1[[70, 2]].is_nan() && !comparison.e1[[70, 3]].is_nan());
        assert_eq!(comparison.mean(70, 1), comparison.e1[[70, 3]]);
        assert_eq!(comparison.switch[70], Switch::BToA);
    }

    /// Without a track each replicate's sign is arbitrary: a replicate whose E1 came out the
    /// other way is turned to agree with the first.
    #[test]
    fn replicates_are_given_the_first_replicates_sign() {
        let first: Vec<InMemory> = (1..=2)
            .map(|s| replicate(200, 200, s, checkerboard(false)))
            .collect();
        let second: Vec<InMemory> = (3..=4)
            .map(|s| replicate(200, 200, s, checkerboard(false)))
            .collect();
        let flipped: Vec<f64> = (0..200)
            .map(|b: usize| if (b / 20).is_multiple_of(2) { 0.0 } else { 1.0 })
            .collect();
        let readers: Vec<&dyn MatrixReader> = first
            .iter()
            .chain(&second)
            .map(|r| r as &dyn MatrixReader)
            .collect();
        let ones = vec![1.0; 200];
        let weights = vec![&ones[..]; 4];
        let view = View::chromosomes(readers[0].bins());
        let comparison = compare_compartments(
            &readers,
            &weights,
            2,
            &view,
            Some(&flipped),
            &CompartmentParams::default(),
        )
        .unwrap();
        for s in 1..4 {
            let agreement: f64 = (0..200)
                .map(|row| comparison.e1[[row, 0]] * comparison.e1[[row, s]])
                .sum();
            assert!(agreement > 0.0, "replicate {s}");
        }
        assert!(comparison.switch.iter().all(|s| *s == Switch::None));
    }
}
