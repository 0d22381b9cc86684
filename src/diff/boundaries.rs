//! Differential boundaries: the insulation of every replicate (cooltools' diamond insulation,
//! one window), each condition's boundaries called on its replicates' mean `log2` insulation
//! score (prominence of its minima, the Li cutoff, as `contactmap tads` calls them), the union of
//! both conditions' boundaries (a boundary of B within `match_bins` of one of A is the same
//! boundary). At each boundary the raw contacts across it (the diamond's count at the call) are
//! tested against its flanks (the mean diamond count 2 to `window` bins on either side, its
//! expected): DESeq2's negative-binomial model with the flanks as normalisation factors
//! ([`super::offsets`]), as `diff loops` tests loops against their expected. Fewer contacts
//! across it relative to its flanks in B is a deeper, stronger boundary in B. The count model
//! carries each boundary's own noise (a boundary at a chromosome's end or beside masked bins has
//! fewer contacts and so a wider interval); a t-test of insulation depths, limma's moderated t,
//! called 7 boundaries in 4 of 10 null splits of a real map where the count model calls 0
//! (docs/diff.md). A boundary called in both conditions at bins that differ is also tested for
//! a shift: the contacts across A's bin and across B's bin against their flanks, two more
//! features of the same model; shifted when B is weaker at A's bin and stronger at B's, both
//! significant.
//!
//! Statuses at `q < alpha`: `gained` (called in B only, deeper in B), `lost` (called in A only,
//! shallower in B), `shifted` (called in both, the shift test significant), `stronger` /
//! `weaker` (deeper / shallower in B otherwise); `-` when nothing is significant.

use ndarray::Array2;

use super::maps::{check_conditions, check_same_bins};
use super::model::Params;
use super::offsets::test_against_expected;
use super::tables::{condition_mean, number, sample_names};
use crate::error::{Error, Result};
use crate::genome::{BinTable, View};
#[cfg(test)]
use crate::io::InMemory;
use crate::io::{MatrixReader, default_memory_budget, load_pixels};
use crate::tads::insulation::{InsulationParams, insulation};
use crate::tads::peaks::find_peak_prominence;

/// Settings of `diff boundaries`.
#[derive(Debug, Clone)]
pub struct BoundaryParams {
    /// The insulation's settings, with exactly one window.
    pub insulation: InsulationParams,
    /// A boundary of B this many bins or fewer from one of A is the same boundary (2).
    pub match_bins: usize,
    /// q-value under which a change counts (0.05).
    pub alpha: f64,
    /// Set aside the p-values of boundaries with a Cook's outlier (DESeq2's rule; true).
    pub cooks_filter: bool,
    /// The count model's settings.
    pub model: Params,
}

/// The insulation window `diff boundaries` takes when none is given: 10 bins (as `contactmap
/// tads`); bins of several sizes are an error.
pub fn default_window_bp(bins: &BinTable) -> Result<u64> {
    let resolution = bins.resolution().ok_or_else(|| {
        Error::Argument(
            "diff boundaries needs fixed-size bins (windows are counted in bins)".into(),
        )
    })?;
    Ok(crate::tads::insulation::DEFAULT_WINDOW_BINS as u64 * resolution)
}

/// The rows a boundary spans: from its first call to its last (one row when called once or at
/// one bin).
fn span((a, b): (Option<usize>, Option<usize>)) -> (usize, usize) {
    let first = a.or(b).unwrap_or(0);
    let second = b.or(a).unwrap_or(0);
    (first.min(second), first.max(second))
}

impl BoundaryParams {
    /// The defaults with this insulation window (bp).
    pub fn new(window_bp: u64) -> Self {
        BoundaryParams {
            insulation: InsulationParams::new(vec![window_bp]),
            match_bins: 2,
            alpha: 0.05,
            cooks_filter: true,
            model: Params::default(),
        }
    }
}

/// What happened to a boundary between A and B.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoundaryStatus {
    /// Called in B only, significantly deeper in B.
    Gained,
    /// Called in A only, significantly shallower in B.
    Lost,
    /// Called in both at different bins, the shift significant.
    Shifted,
    /// Significantly deeper in B otherwise.
    Stronger,
    /// Significantly shallower in B otherwise.
    Weaker,
    /// No significant change.
    Unchanged,
}

impl BoundaryStatus {
    /// The word written in the table.
    pub fn as_str(self) -> &'static str {
        match self {
            BoundaryStatus::Gained => "gained",
            BoundaryStatus::Lost => "lost",
            BoundaryStatus::Shifted => "shifted",
            BoundaryStatus::Stronger => "stronger",
            BoundaryStatus::Weaker => "weaker",
            BoundaryStatus::Unchanged => "-",
        }
    }
}

/// The insulation of each replicate, on the rows of the view's regions.
#[derive(Debug, Clone)]
pub struct InsulationScores {
    /// Genome-wide bin of each row.
    pub bins: Vec<usize>,
    /// The view region of each row.
    pub region: Vec<usize>,
    /// `log2` insulation score, one column per replicate (A's first).
    pub scores: Array2<f64>,
    /// Raw diamond counts (`sum_counts`), one column per replicate.
    pub counts: Array2<f64>,
    /// Whether a row may hold a boundary: enough valid pixels and a score in every replicate.
    pub callable: Vec<bool>,
    /// The insulation window in bins.
    pub window_bins: usize,
}

/// How deep replicate `sample`'s insulation valley is at the boundary called at rows `lo..=hi`:
/// the mean score of the flanks (`2..=w` bins before `lo` and after `hi`, `w` the window, in
/// the same region) minus the lowest score from `lo - 1` to `hi + 1`. A contrast within one
/// track: a shift of the whole track (the median that normalises it moves when boundaries
/// change elsewhere) leaves it unchanged. NaN scores are left out; NaN when a part is empty.
pub fn valley_depth(scores: &InsulationScores, sample: usize, lo: usize, hi: usize) -> f64 {
    let value = |row: usize| scores.scores[[row, sample]];
    let n_rows = scores.bins.len();
    let valley = (lo.saturating_sub(1)..(hi + 2).min(n_rows))
        .filter(|&row| scores.region[row] == scores.region[lo])
        .map(value)
        .filter(|v| !v.is_nan())
        .fold(f64::NAN, f64::min);
    let flanks: Vec<f64> = flank_rows(scores, lo, hi)
        .map(value)
        .filter(|v| !v.is_nan())
        .collect();
    if flanks.is_empty() {
        return f64::NAN;
    }
    flanks.iter().sum::<f64>() / flanks.len() as f64 - valley
}

/// The flanks of a boundary called at rows `lo..=hi`: 2 to `w` rows (the window) before `lo`
/// and after `hi`, in the same region.
fn flank_rows(scores: &InsulationScores, lo: usize, hi: usize) -> impl Iterator<Item = usize> + '_ {
    let n_rows = scores.bins.len();
    let w = scores.window_bins.max(2);
    (lo.saturating_sub(w)..lo.saturating_sub(1))
        .chain((hi + 2).min(n_rows)..(hi + w + 1).min(n_rows))
        .filter(move |&row| scores.region[row] == scores.region[lo])
}

/// Replicate `sample`'s raw contacts across a boundary called at rows `lo..=hi` (their diamond
/// counts summed) and their expected (the flanks' mean diamond count times `hi - lo + 1`); NaN
/// where the flanks have no count.
pub fn across_and_flanks(
    scores: &InsulationScores,
    sample: usize,
    lo: usize,
    hi: usize,
) -> (f64, f64) {
    let count = |row: usize| scores.counts[[row, sample]];
    let across: f64 = (lo..=hi).map(count).sum();
    let flanks: Vec<f64> = flank_rows(scores, lo, hi)
        .map(count)
        .filter(|v| !v.is_nan())
        .collect();
    if flanks.is_empty() {
        return (across, f64::NAN);
    }
    let mean = flanks.iter().sum::<f64>() / flanks.len() as f64;
    (across, mean * (hi - lo + 1) as f64)
}

/// The comparison: one entry per boundary of either condition, in genome order.
#[derive(Debug, Clone)]
pub struct BoundaryComparison {
    /// The rows of the insulation table where each boundary was called in A and in B.
    pub rows: Vec<(Option<usize>, Option<usize>)>,
    /// The boundary's bin: A's where A called it, else B's.
    pub bins: Vec<usize>,
    /// Genome-wide bins of A's and B's calls.
    pub called_bins: Vec<(Option<usize>, Option<usize>)>,
    /// Boundary strength (prominence on each condition's mean score) at each condition's call.
    pub strength: Vec<(f64, f64)>,
    /// The valley's depth per replicate ([`valley_depth`]), reported.
    pub depth: Array2<f64>,
    /// Raw contacts across each boundary per replicate (the diamond counts at its call(s)).
    pub observed: Array2<f64>,
    /// Their expected: the flanks' mean diamond count (times the calls' number of bins).
    pub expected: Array2<f64>,
    /// Mean normalised count (NaN where untested: a flank without contacts).
    pub base_mean: Vec<f64>,
    /// log2 fold change of the contacts across, B over A (negative: deeper in B).
    pub log2_fold_change: Vec<f64>,
    /// Its standard error.
    pub lfc_se: Vec<f64>,
    /// Wald p-value.
    pub p_value: Vec<f64>,
    /// Benjamini-Hochberg q-value.
    pub q_value: Vec<f64>,
    /// The shift test's p-value and q-value, for boundaries called in both at different bins:
    /// the contacts across A's bin and across B's bin tested against their flanks as two more
    /// features of the same model; a shift is B weaker at A's bin and stronger at B's, its p-
    /// and q-value the larger of the two (1 when the changes point the other way).
    pub shift: Vec<Option<(f64, f64)>>,
    /// Status at `q < alpha`.
    pub status: Vec<BoundaryStatus>,
    /// Replicates in A.
    pub n_first: usize,
}

/// The `log2` insulation score of each of `readers` (maps on the same bins, A's first) with
/// their `weights`, over `view`.
pub fn insulation_scores(
    readers: &[&dyn MatrixReader],
    weights: &[&[f64]],
    view: &View,
    params: &InsulationParams,
) -> Result<InsulationScores> {
    if params.windows_bp.len() != 1 {
        return Err(Error::parameter(
            "windows_bp",
            format!("{:?}", params.windows_bp),
            "expected one window",
        ));
    }
    let params = InsulationParams {
        append_raw_scores: true,
        ..params.clone()
    };
    let params = &params;
    let mut columns = Vec::with_capacity(readers.len());
    let mut count_columns = Vec::with_capacity(readers.len());
    let mut bins = Vec::new();
    let mut region = Vec::new();
    let mut callable: Vec<bool> = Vec::new();
    let mut window_bins = 0;
    for (reader, w) in readers.iter().zip(weights) {
        let pixels = load_pixels(*reader, default_memory_budget())?;
        let table = insulation(&pixels, Some(w), view, params)?;
        let track = &table.tracks[0];
        window_bins = track.window_bins;
        let max_valid = track
            .n_valid_pixels
            .iter()
            .copied()
            .fold(f64::NAN, f64::max);
        let min_valid = max_valid * params.min_frac_valid_pixels;
        let ok = track
            .n_valid_pixels
            .iter()
            .zip(&track.log2_insulation_score)
            .map(|(&n, s)| n >= min_valid && !s.is_nan());
        if callable.is_empty() {
            callable = ok.collect();
            bins = table.bins.clone();
            region = table.region.clone();
        } else {
            callable.iter_mut().zip(ok).for_each(|(c, o)| *c &= o);
        }
        columns.push(track.log2_insulation_score.clone());
        count_columns.push(track.sum_counts.clone().unwrap_or_default());
    }
    let matrix = |columns: &[Vec<f64>]| {
        let mut m = Array2::from_elem((bins.len(), readers.len()), f64::NAN);
        for (s, column) in columns.iter().enumerate() {
            for (row, &value) in column.iter().enumerate() {
                m[[row, s]] = value;
            }
        }
        m
    };
    let (scores, counts) = (matrix(&columns), matrix(&count_columns));
    Ok(InsulationScores {
        bins,
        region,
        scores,
        counts,
        callable,
        window_bins,
    })
}

/// A condition's boundaries: the prominence of the minima of its replicates' mean score over
/// the callable rows of each region, kept at or above `params.insulation.threshold`'s cutoff.
/// Returns each row's strength (NaN where none) and the boundary rows.
pub fn condition_boundaries(
    scores: &InsulationScores,
    replicates: std::ops::Range<usize>,
    params: &BoundaryParams,
) -> (Vec<f64>, Vec<usize>) {
    let n_rows = scores.bins.len();
    let mean: Vec<f64> = (0..n_rows)
        .map(|row| {
            let values = scores.scores.row(row);
            let part = values.slice(ndarray::s![replicates.clone()]);
            part.sum() / part.len() as f64
        })
        .collect();
    let mut strength = vec![f64::NAN; n_rows];
    let mut start = 0;
    while start < n_rows {
        let mut end = start;
        while end < n_rows && scores.region[end] == scores.region[start] {
            end += 1;
        }
        let kept: Vec<usize> = (start..end).filter(|&r| scores.callable[r]).collect();
        let track: Vec<f64> = kept.iter().map(|&r| -mean[r]).collect();
        for (pos, prominence) in find_peak_prominence(&track) {
            strength[kept[pos]] = prominence;
        }
        start = end;
    }
    let cutoff = params.insulation.threshold.cutoff(&strength);
    let called = (0..n_rows).filter(|&r| strength[r] >= cutoff).collect();
    (strength, called)
}

/// Pairs the boundaries of A and B within `match_bins` in the same region, closest first (then
/// upstream first), one to one; the rest stand alone. Sorted by their first row.
pub fn match_boundaries(
    first: &[usize],
    second: &[usize],
    region: &[usize],
    match_bins: usize,
) -> Vec<(Option<usize>, Option<usize>)> {
    let mut candidates: Vec<(usize, usize, usize)> = Vec::new();
    for &a in first {
        for &b in second {
            if region[a] == region[b] && a.abs_diff(b) <= match_bins {
                candidates.push((a.abs_diff(b), a.min(b), a * region.len() + b));
            }
        }
    }
    candidates.sort_unstable();
    let mut used_first = std::collections::HashSet::new();
    let mut used_second = std::collections::HashSet::new();
    let mut sites = Vec::new();
    for (_, _, key) in candidates {
        let (a, b) = (key / region.len(), key % region.len());
        if !used_first.contains(&a) && !used_second.contains(&b) {
            used_first.insert(a);
            used_second.insert(b);
            sites.push((Some(a), Some(b)));
        }
    }
    sites.extend(
        first
            .iter()
            .filter(|a| !used_first.contains(*a))
            .map(|&a| (Some(a), None)),
    );
    sites.extend(
        second
            .iter()
            .filter(|b| !used_second.contains(*b))
            .map(|&b| (None, Some(b))),
    );
    sites.sort_by_key(|site| span(*site));
    sites
}

/// Compare the boundaries of `readers[..n_first]` (A) and `readers[n_first..]` (B), maps on the
/// same bins balanced by `weights`, over `view`.
///
/// # Examples
///
/// The same map as every replicate: the boundaries match, nothing differs, nothing is
/// significant.
///
/// ```
/// use contactmap::diff::boundaries::{BoundaryParams, BoundaryStatus, compare_boundaries};
/// use contactmap::genome::View;
/// use contactmap::io::{MatrixReader, OpenOptions, open_matrix};
///
/// let reader = open_matrix("data/sim_extrusion.5kb.cool", &OpenOptions::default())?;
/// let weights = reader.weights("weight")?.values;
/// let readers: Vec<&dyn MatrixReader> = vec![reader.as_ref(); 4];
/// let view = View::chromosomes(reader.bins());
/// let params = BoundaryParams::new(50_000);
/// let comparison = compare_boundaries(&readers, &[&weights[..]; 4], 2, &view, &params)?;
/// assert!(!comparison.bins.is_empty());
/// assert!(comparison.rows.iter().all(|(a, b)| a == b));
/// assert!(comparison.status.iter().all(|s| *s == BoundaryStatus::Unchanged));
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn compare_boundaries(
    readers: &[&dyn MatrixReader],
    weights: &[&[f64]],
    n_first: usize,
    view: &View,
    params: &BoundaryParams,
) -> Result<BoundaryComparison> {
    check_conditions(readers.len(), n_first)?;
    check_same_bins(readers)?;
    let scores = insulation_scores(readers, weights, view, &params.insulation)?;
    let n = readers.len();
    let (strength_first, called_first) = condition_boundaries(&scores, 0..n_first, params);
    let (strength_second, called_second) = condition_boundaries(&scores, n_first..n, params);
    let rows = match_boundaries(
        &called_first,
        &called_second,
        &scores.region,
        params.match_bins,
    );
    let n_sites = rows.len();
    let mut depth = Array2::from_elem((n_sites, n), f64::NAN);
    // the features tested: each boundary at its call(s), and a boundary called at different
    // bins also at A's bin and at B's bin (for the shift)
    let mut features: Vec<(usize, usize)> = Vec::with_capacity(n_sites);
    let mut shift_features: Vec<Option<(usize, usize)>> = vec![None; n_sites];
    for (site, &(a, b)) in rows.iter().enumerate() {
        let (lo, hi) = span((a, b));
        for s in 0..n {
            depth[[site, s]] = valley_depth(&scores, s, lo, hi);
        }
        features.push((lo, hi));
    }
    for (site, &(a, b)) in rows.iter().enumerate() {
        if let (Some(a), Some(b)) = (a, b) {
            if a != b {
                shift_features[site] = Some((features.len(), features.len() + 1));
                features.push((a, a));
                features.push((b, b));
            }
        }
    }
    let n_features = features.len();
    let mut observed = Array2::from_elem((n_features, n), f64::NAN);
    let mut expected = Array2::from_elem((n_features, n), f64::NAN);
    for (f, &(lo, hi)) in features.iter().enumerate() {
        for s in 0..n {
            let (across, flanks) = across_and_flanks(&scores, s, lo, hi);
            observed[[f, s]] = across;
            expected[[f, s]] = flanks;
        }
    }
    // features whose flanks have contacts in every replicate are tested, in one model
    let tested: Vec<usize> = (0..n_features)
        .filter(|&f| {
            expected.row(f).iter().all(|e| *e > 0.0)
                && observed.row(f).iter().all(|o| o.is_finite())
        })
        .collect();
    let pick =
        |m: &Array2<f64>| Array2::from_shape_fn((tested.len(), n), |(k, s)| m[[tested[k], s]]);
    let untested = || vec![f64::NAN; n_features];
    let (base_mean, log2_fold_change, lfc_se, p_value, q_value) = if tested.is_empty() {
        // no boundary (a map too sparse to call one), or none with contacts on its flanks
        (untested(), untested(), untested(), untested(), untested())
    } else {
        let (results, _) = test_against_expected(
            pick(&observed).view(),
            pick(&expected).view(),
            n_first,
            &params.model,
            params.cooks_filter,
        )?;
        let spread = |values: &[f64]| {
            let mut out = untested();
            for (k, &f) in tested.iter().enumerate() {
                out[f] = values[k];
            }
            out
        };
        (
            spread(&results.base_mean),
            spread(&results.log2_fold_change),
            spread(&results.lfc_se),
            spread(&results.p_value),
            spread(&results.q_value),
        )
    };
    // shifted: fewer contacts across A's bin relative to its flanks in A than in B (B weaker
    // there), and more across B's bin in A (B stronger there); both significant
    let shift: Vec<Option<(f64, f64)>> = shift_features
        .iter()
        .map(|pair| {
            pair.map(|(fa, fb)| {
                let moved = log2_fold_change[fa] > 0.0 && log2_fold_change[fb] < 0.0;
                if moved {
                    (p_value[fa].max(p_value[fb]), q_value[fa].max(q_value[fb]))
                } else {
                    (1.0, 1.0)
                }
            })
        })
        .collect();

    let status = (0..n_sites)
        .map(|site| {
            let significant = q_value[site] < params.alpha;
            let deeper = log2_fold_change[site] < 0.0;
            let shift_significant = shift[site].is_some_and(|(_, q)| q < params.alpha);
            match rows[site] {
                (Some(_), Some(_)) if shift_significant => BoundaryStatus::Shifted,
                _ if !significant => BoundaryStatus::Unchanged,
                (None, Some(_)) if deeper => BoundaryStatus::Gained,
                (Some(_), None) if !deeper => BoundaryStatus::Lost,
                _ if deeper => BoundaryStatus::Stronger,
                _ => BoundaryStatus::Weaker,
            }
        })
        .collect();
    let bin_of = |row: Option<usize>| row.map(|r| scores.bins[r]);
    Ok(BoundaryComparison {
        bins: rows
            .iter()
            .map(|&(a, b)| scores.bins[a.or(b).unwrap_or(0)])
            .collect(),
        called_bins: rows.iter().map(|&(a, b)| (bin_of(a), bin_of(b))).collect(),
        strength: rows
            .iter()
            .map(|&(a, b)| {
                (
                    a.map_or(f64::NAN, |r| strength_first[r]),
                    b.map_or(f64::NAN, |r| strength_second[r]),
                )
            })
            .collect(),
        rows,
        depth,
        observed: observed.slice(ndarray::s![..n_sites, ..]).to_owned(),
        expected: expected.slice(ndarray::s![..n_sites, ..]).to_owned(),
        base_mean: base_mean[..n_sites].to_vec(),
        log2_fold_change: log2_fold_change[..n_sites].to_vec(),
        lfc_se: lfc_se[..n_sites].to_vec(),
        p_value: p_value[..n_sites].to_vec(),
        q_value: q_value[..n_sites].to_vec(),
        shift,
        status,
        n_first,
    })
}

/// The comparison as a table with a header line: `chrom start end` (the boundary's bin),
/// `start_A start_B` (each condition's call, `.` where it has none), `strength_A strength_B`,
/// `depth_A depth_B` (mean valley depth), `baseMean log2FoldChange lfcSE pvalue qvalue` (the
/// contacts across it against its flanks, B over A), `shift_pvalue shift_qvalue status`, then
/// each replicate's contacts across (`count_A1` ...) and their expected (`expected_A1` ...).
pub fn boundaries_tsv(bins: &BinTable, comparison: &BoundaryComparison) -> String {
    let names = sample_names(comparison.depth.ncols(), comparison.n_first);
    let mut out = String::from(
        "chrom\tstart\tend\tstart_A\tstart_B\tstrength_A\tstrength_B\tdepth_A\tdepth_B\tbaseMean\tlog2FoldChange\tlfcSE\tpvalue\tqvalue\tshift_pvalue\tshift_qvalue\tstatus",
    );
    for prefix in ["count", "expected"] {
        for name in &names {
            out.push_str(&format!("\t{prefix}_{name}"));
        }
    }
    out.push('\n');
    let start = |bin: Option<usize>| bin.map_or(".".to_string(), |b| bins.bin(b).start.to_string());
    for (site, &bin) in comparison.bins.iter().enumerate() {
        let b = bins.bin(bin);
        let depth = comparison.depth.row(site);
        let (shift_p, shift_q) = comparison.shift[site].unwrap_or((f64::NAN, f64::NAN));
        let fields = [
            bins.chroms()[b.chrom_id].name.clone(),
            b.start.to_string(),
            b.end.to_string(),
            start(comparison.called_bins[site].0),
            start(comparison.called_bins[site].1),
            number(comparison.strength[site].0),
            number(comparison.strength[site].1),
            number(condition_mean(depth, comparison.n_first, 0)),
            number(condition_mean(depth, comparison.n_first, 1)),
            number(comparison.base_mean[site]),
            number(comparison.log2_fold_change[site]),
            number(comparison.lfc_se[site]),
            number(comparison.p_value[site]),
            number(comparison.q_value[site]),
            number(shift_p),
            number(shift_q),
            comparison.status[site].as_str().to_string(),
        ];
        out.push_str(&fields.join("\t"));
        for value in comparison.observed.row(site) {
            out.push_str(&format!("\t{value}"));
        }
        for value in comparison.expected.row(site) {
            out.push('\t');
            out.push_str(&number(*value));
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::maps::synthetic::replicate;
    use super::*;

    /// Domains on a distance decay, each `1 + 0.5 k` times denser inside (k = 1, 2, 3 in turn,
    /// so that minima are single bins); boundaries at the `edges`.
    fn domains(edges: &'static [u64]) -> impl Fn(u64, u64) -> f64 {
        move |i, j| {
            let domain = |b: u64| edges.iter().filter(|&&e| e <= b).count() as u64;
            let enrichment = if domain(i) == domain(j) {
                1.5 + 0.5 * (domain(i) % 3) as f64
            } else {
                1.0
            };
            enrichment * 400.0 / (j - i + 1) as f64
        }
    }

    fn compare(first: &[InMemory], second: &[InMemory]) -> BoundaryComparison {
        let readers: Vec<&dyn MatrixReader> = first
            .iter()
            .chain(second)
            .map(|r| r as &dyn MatrixReader)
            .collect();
        let ones = vec![1.0; 200];
        let weights = vec![&ones[..]; readers.len()];
        let view = View::chromosomes(readers[0].bins());
        let params = BoundaryParams::new(8_000);
        compare_boundaries(&readers, &weights, first.len(), &view, &params).unwrap()
    }

    /// B loses the boundary at 120 and moves the one at 160 to 161: the first is `lost`, the second
    /// `shifted`, the others unchanged; A against A with other seeds changes nothing.
    #[test]
    fn planted_changes_are_found_and_nothing_else() {
        let a_edges: &'static [u64] = &[40, 80, 120, 160];
        let b_edges: &'static [u64] = &[40, 80, 161];
        let first: Vec<InMemory> = (1..=2)
            .map(|s| replicate(200, 30, s, domains(a_edges)))
            .collect();
        let second: Vec<InMemory> = (3..=4)
            .map(|s| replicate(200, 30, s, domains(b_edges)))
            .collect();
        let comparison = compare(&first, &second);
        let called: Vec<(Option<usize>, Option<usize>, &str)> = comparison
            .called_bins
            .iter()
            .zip(&comparison.status)
            .map(|(&(a, b), s)| (a, b, s.as_str()))
            .collect();
        // a boundary is called at its edge or the bin before (where the diamond straddles it)
        let near =
            |bin: Option<usize>, edge: usize| bin.is_some_and(|b| b + 1 >= edge && b <= edge);
        let status_at = |edge: usize| {
            called
                .iter()
                .find(|(a, b, _)| near(*a, edge) || near(*b, edge))
                .map(|c| c.2)
        };
        assert_eq!(status_at(40), Some("-"), "{called:?}");
        assert_eq!(status_at(80), Some("-"), "{called:?}");
        assert_eq!(status_at(120), Some("lost"), "{called:?}");
        assert_eq!(status_at(161), Some("shifted"), "{called:?}");
        assert_eq!(
            called.iter().filter(|c| c.2 != "-").count(),
            2,
            "{called:?}"
        );

        let again: Vec<InMemory> = (5..=6)
            .map(|s| replicate(200, 30, s, domains(a_edges)))
            .collect();
        let null = compare(&first, &again);
        assert!(
            null.status.iter().all(|s| *s == BoundaryStatus::Unchanged),
            "{:?}",
            null.status
        );
    }

    /// Maps too sparse to call a boundary: an empty comparison, not an error.
    #[test]
    fn no_boundary_is_an_empty_comparison() {
        let empty: Vec<InMemory> = (1..=4).map(|s| replicate(200, 30, s, |_, _| 0.0)).collect();
        let comparison = compare(&empty[..2], &empty[2..]);
        assert!(comparison.bins.is_empty() && comparison.status.is_empty());
    }

    #[test]
    fn boundaries_pair_closest_first_one_to_one() {
        let region = vec![0; 50];
        let sites = match_boundaries(&[10, 20, 30], &[11, 19, 21, 45], &region, 2);
        assert_eq!(
            sites,
            vec![
                (Some(10), Some(11)),
                (Some(20), Some(19)),
                (None, Some(21)),
                (Some(30), None),
                (None, Some(45)),
            ]
        );
        // other regions never pair
        let split: Vec<usize> = (0..50).map(|b| usize::from(b >= 15)).collect();
        let sites = match_boundaries(&[14], &[15], &split, 2);
        assert_eq!(sites, vec![(Some(14), None), (None, Some(15))]);
    }
}
