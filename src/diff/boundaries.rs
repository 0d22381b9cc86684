//! Differential boundaries: the insulation of every replicate (cooltools' diamond insulation,
//! one window), each condition's boundaries called on its replicates' mean `log2` insulation
//! score (prominence of its minima, the Li cutoff, as `contactmap tads` calls them), the union of
//! both conditions' boundaries (a boundary of B within `match_bins` of one of A is the same
//! boundary), and at each the depth of the insulation valley per replicate (its flanks' mean
//! score minus its lowest: [`valley_depth`]) tested with limma's moderated t ([`super::moderated`]): the difference of means with its replicate variance, shrunk
//! towards the variance of every boundary. A boundary called in both conditions at bins that
//! differ is also tested for a shift: per replicate, the score at A's bin minus the score at B's
//! bin, compared between the conditions in the same way.
//!
//! Statuses at `q < alpha`: `gained` (called in B only, deeper in B), `lost` (called in A only,
//! shallower in B), `shifted` (called in both, the shift test significant), `stronger` /
//! `weaker` (deeper / shallower in B otherwise); `-` when nothing is significant.

use ndarray::Array2;

use super::maps::{check_conditions, check_same_bins};
use super::moderated::{ModeratedT, moderated_t};
use super::tables::{condition_mean, number, sample_names};
use super::test::benjamini_hochberg;
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
}

impl BoundaryParams {
    /// The defaults with this insulation window (bp).
    pub fn new(window_bp: u64) -> Self {
        BoundaryParams {
            insulation: InsulationParams::new(vec![window_bp]),
            match_bins: 2,
            alpha: 0.05,
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
    let region = scores.region[lo];
    let n_rows = scores.bins.len();
    let value = |row: usize| {
        let v = scores.scores[[row, sample]];
        (scores.region[row] == region && !v.is_nan()).then_some(v)
    };
    let w = scores.window_bins.max(2);
    let valley = (lo.saturating_sub(1)..(hi + 2).min(n_rows))
        .filter_map(value)
        .fold(f64::NAN, f64::min);
    let flanks: Vec<f64> = (lo.saturating_sub(w)..lo.saturating_sub(1))
        .chain((hi + 2).min(n_rows)..(hi + w + 1).min(n_rows))
        .filter_map(value)
        .collect();
    if flanks.is_empty() {
        return f64::NAN;
    }
    flanks.iter().sum::<f64>() / flanks.len() as f64 - valley
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
    /// The valley's depth per replicate ([`valley_depth`]).
    pub depth: Array2<f64>,
    /// The moderated test of the depth (B minus A).
    pub test: ModeratedT,
    /// Benjamini-Hochberg q-values of `test`.
    pub q_value: Vec<f64>,
    /// The shift test's p-value and q-value, for boundaries called in both at different bins.
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
    let mut columns = Vec::with_capacity(readers.len());
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
    }
    let mut scores = Array2::from_elem((bins.len(), readers.len()), f64::NAN);
    for (s, column) in columns.iter().enumerate() {
        for (row, &value) in column.iter().enumerate() {
            scores[[row, s]] = value;
        }
    }
    Ok(InsulationScores {
        bins,
        region,
        scores,
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
    let key = |site: &(Option<usize>, Option<usize>)| {
        let (a, b) = *site;
        (a.or(b).min(b.or(a)), a.or(b).max(b.or(a)))
    };
    sites.sort_by_key(key);
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
    for (site, &(a, b)) in rows.iter().enumerate() {
        let (lo, hi) = (
            a.or(b).min(b.or(a)).unwrap_or(0),
            a.or(b).max(b.or(a)).unwrap_or(0),
        );
        for s in 0..n {
            depth[[site, s]] = valley_depth(&scores, s, lo, hi);
        }
    }
    let test = moderated_t(depth.view(), n_first);
    let q_value = benjamini_hochberg(&test.p_value);

    let shifted: Vec<usize> = (0..n_sites)
        .filter(|&site| matches!(rows[site], (Some(a), Some(b)) if a != b))
        .collect();
    let mut contrast = Array2::from_elem((shifted.len(), n), f64::NAN);
    for (k, &site) in shifted.iter().enumerate() {
        if let (Some(a), Some(b)) = rows[site] {
            for s in 0..n {
                contrast[[k, s]] = scores.scores[[a, s]] - scores.scores[[b, s]];
            }
        }
    }
    let shift_test = moderated_t(contrast.view(), n_first);
    let shift_q = benjamini_hochberg(&shift_test.p_value);
    let mut shift = vec![None; n_sites];
    for (k, &site) in shifted.iter().enumerate() {
        shift[site] = Some((shift_test.p_value[k], shift_q[k]));
    }

    let status = (0..n_sites)
        .map(|site| {
            let significant = q_value[site] < params.alpha;
            let deeper = test.difference[site] > 0.0;
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
        test,
        q_value,
        shift,
        status,
        n_first,
    })
}

/// The comparison as a table with a header line: `chrom start end` (the boundary's bin),
/// `start_A start_B` (each condition's call, `.` where it has none), `strength_A strength_B`,
/// `depth_A depth_B` (mean valley depth), `difference` (B minus A), `se`, `t`, `df`,
/// `pvalue`, `qvalue`, `shift_pvalue`, `shift_qvalue`, `status`, then each replicate's depth
/// (`depth_A1` ...).
pub fn boundaries_tsv(bins: &BinTable, comparison: &BoundaryComparison) -> String {
    let n = comparison.depth.ncols();
    let names: Vec<String> = sample_names(n, comparison.n_first)
        .iter()
        .map(|name| format!("depth_{name}"))
        .collect();
    let mut out = format!(
        "chrom\tstart\tend\tstart_A\tstart_B\tstrength_A\tstrength_B\tdepth_A\tdepth_B\tdifference\tse\tt\tdf\tpvalue\tqvalue\tshift_pvalue\tshift_qvalue\tstatus\t{}\n",
        names.join("\t")
    );
    let start = |bin: Option<usize>| bin.map_or(".".to_string(), |b| bins.bin(b).start.to_string());
    let test = &comparison.test;
    for (site, &bin) in comparison.bins.iter().enumerate() {
        let b = bins.bin(bin);
        let row = comparison.depth.row(site);
        let (shift_p, shift_q) = comparison.shift[site].unwrap_or((f64::NAN, f64::NAN));
        let fields = [
            bins.chroms()[b.chrom_id].name.clone(),
            b.start.to_string(),
            b.end.to_string(),
            start(comparison.called_bins[site].0),
            start(comparison.called_bins[site].1),
            number(comparison.strength[site].0),
            number(comparison.strength[site].1),
            number(condition_mean(row, comparison.n_first, 0)),
            number(condition_mean(row, comparison.n_first, 1)),
            number(test.difference[site]),
            number(test.standard_error(site)),
            number(test.t[site]),
            number(test.df_total[site]),
            number(test.p_value[site]),
            number(comparison.q_value[site]),
            number(shift_p),
            number(shift_q),
            comparison.status[site].as_str().to_string(),
        ];
        out.push_str(&fields.join("\t"));
        for value in row {
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
