//! The expected tables: cis per (region, diagonal), trans per pair of regions.

use crate::genome::View;
use crate::io::tables::Column;

/// The cis expected table: one row per (region, diagonal), regions in view order.
#[derive(Clone, Debug, PartialEq)]
pub struct CisExpected {
    /// The bin size in bp.
    pub resolution: u64,
    /// Names of the regions (`region1` = `region2` of each row).
    pub region_names: Vec<String>,
    /// Index into `region_names` of each row.
    pub region: Vec<u32>,
    /// Diagonal (distance in bins).
    pub dist: Vec<u64>,
    /// Distance in bp: `dist * resolution`.
    pub dist_bp: Vec<u64>,
    /// Pixels on the diagonal.
    pub n_total: Vec<u64>,
    /// Pixels on the diagonal whose two bins are not masked.
    pub n_valid: Vec<u64>,
    /// Sum of raw counts (of valid pixels in balanced mode); NaN for ignored diagonals.
    pub count_sum: Vec<f64>,
    /// Sum of balanced values (balanced mode only).
    pub balanced_sum: Option<Vec<f64>>,
    /// `count_sum / n_total`.
    pub count_avg: Vec<f64>,
    /// `balanced_sum / n_valid` (balanced mode only).
    pub balanced_avg: Option<Vec<f64>>,
    /// Per-region log-smoothed average (`balanced.avg.smoothed` or `count.avg.smoothed`).
    pub avg_smoothed: Option<Vec<f64>>,
    /// Log-smoothed average over all regions (`*.avg.smoothed.agg`).
    pub avg_smoothed_agg: Option<Vec<f64>>,
}

impl CisExpected {
    /// Number of rows.
    pub fn n_rows(&self) -> usize {
        self.dist.len()
    }

    /// True for balanced tables.
    pub fn is_balanced(&self) -> bool {
        self.balanced_sum.is_some()
    }

    /// `balanced` or `count`: the prefix of the averaged columns.
    pub fn prefix(&self) -> &'static str {
        if self.is_balanced() {
            "balanced"
        } else {
            "count"
        }
    }

    /// The name of the region of `row`.
    pub fn region_name(&self, row: usize) -> &str {
        &self.region_names[self.region[row] as usize]
    }

    /// The average that P(s) analyses use: `balanced.avg`, else `count.avg`.
    pub fn average(&self) -> &[f64] {
        self.balanced_avg.as_deref().unwrap_or(&self.count_avg)
    }

    /// [`Self::average`] region by region: `by_region[r][d]` for diagonal `d` of region `r`
    /// (rows are in region then distance order).
    pub fn average_by_region(&self) -> Vec<Vec<f64>> {
        let mut by_region: Vec<Vec<f64>> = vec![Vec::new(); self.region_names.len()];
        for (&region, &value) in self.region.iter().zip(self.average()) {
            by_region[region as usize].push(value);
        }
        by_region
    }

    /// The summed values behind [`Self::average`]: `balanced.sum`, else `count.sum`.
    pub fn summary(&self) -> &[f64] {
        self.balanced_sum.as_deref().unwrap_or(&self.count_sum)
    }

    /// The "most processed" values, cooltools' `contact_frequency`: the last of the average,
    /// smoothed and aggregated-smoothed columns present.
    pub fn contact_frequency(&self) -> &[f64] {
        self.avg_smoothed_agg
            .as_deref()
            .or(self.avg_smoothed.as_deref())
            .unwrap_or_else(|| self.average())
    }

    /// The columns after `region1` and `region2`, named and ordered as cooltools writes them.
    pub fn columns(&self) -> Vec<(String, Column<'_>)> {
        let prefix = self.prefix();
        let mut columns = vec![
            ("dist".to_string(), Column::Integer(&self.dist)),
            ("dist_bp".to_string(), Column::Integer(&self.dist_bp)),
            (
                "contact_frequency".to_string(),
                Column::Real(self.contact_frequency()),
            ),
            ("n_total".to_string(), Column::Integer(&self.n_total)),
            ("n_valid".to_string(), Column::Integer(&self.n_valid)),
            ("count.sum".to_string(), Column::Real(&self.count_sum)),
        ];
        if let Some(sum) = &self.balanced_sum {
            columns.push(("balanced.sum".to_string(), Column::Real(sum)));
        }
        columns.push(("count.avg".to_string(), Column::Real(&self.count_avg)));
        if let Some(avg) = &self.balanced_avg {
            columns.push(("balanced.avg".to_string(), Column::Real(avg)));
        }
        if let Some(smoothed) = &self.avg_smoothed {
            columns.push((format!("{prefix}.avg.smoothed"), Column::Real(smoothed)));
        }
        if let Some(agg) = &self.avg_smoothed_agg {
            columns.push((format!("{prefix}.avg.smoothed.agg"), Column::Real(agg)));
        }
        columns
    }
}

/// The trans expected table: one row per pair of regions on different chromosomes.
#[derive(Clone, Debug, PartialEq)]
pub struct TransExpected {
    /// First region of each pair.
    pub region1: Vec<String>,
    /// Second region of each pair (later in the view).
    pub region2: Vec<String>,
    /// Pixels of the block whose two bins are not masked.
    pub n_valid: Vec<u64>,
    /// Sum of raw counts of valid pixels.
    pub count_sum: Vec<f64>,
    /// Sum of balanced values (balanced mode only).
    pub balanced_sum: Option<Vec<f64>>,
    /// `count_sum / n_valid`.
    pub count_avg: Vec<f64>,
    /// `balanced_sum / n_valid` (balanced mode only).
    pub balanced_avg: Option<Vec<f64>>,
}

impl TransExpected {
    /// Number of rows.
    pub fn n_rows(&self) -> usize {
        self.n_valid.len()
    }

    /// The average of each pair of regions of `view` (`balanced.avg`, else `count.avg`), as a
    /// matrix indexed `[earlier region][later region]`; NaN for pairs without a row.
    pub fn average_by_pair(&self, view: &View) -> Vec<Vec<f64>> {
        let average = self.balanced_avg.as_deref().unwrap_or(&self.count_avg);
        let index = |name: &str| view.regions().iter().position(|r| r.name == name);
        let mut by_pair = vec![vec![f64::NAN; view.len()]; view.len()];
        for ((r1, r2), &value) in self.region1.iter().zip(&self.region2).zip(average) {
            if let (Some(a), Some(b)) = (index(r1), index(r2)) {
                by_pair[a.min(b)][a.max(b)] = value;
            }
        }
        by_pair
    }

    /// The columns after `region1` and `region2`, as cooltools writes them.
    pub fn columns(&self) -> Vec<(String, Column<'_>)> {
        let mut columns = vec![
            ("n_valid".to_string(), Column::Integer(&self.n_valid)),
            ("count.sum".to_string(), Column::Real(&self.count_sum)),
        ];
        if let Some(sum) = &self.balanced_sum {
            columns.push(("balanced.sum".to_string(), Column::Real(sum)));
        }
        columns.push(("count.avg".to_string(), Column::Real(&self.count_avg)));
        if let Some(avg) = &self.balanced_avg {
            columns.push(("balanced.avg".to_string(), Column::Real(avg)));
        }
        columns
    }
}
