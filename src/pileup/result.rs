//! What a pileup returns: the mean snippet of each group of features, with its counts.

use ndarray::Array2;

use super::groups::GroupKey;
use super::windows::Skipped;

/// The pileup of one group of snippets.
#[derive(Clone, Debug, PartialEq)]
pub struct Pileup {
    /// The group (the one of all snippets: [`GroupKey::all`]).
    pub key: GroupKey,
    /// The mean snippet (over the mean control with shifts).
    pub data: Array2<f64>,
    /// Per pixel, the number of snippets with a finite value there.
    pub num: Array2<u64>,
    /// Snippets piled up.
    pub n: usize,
    /// Controls piled up (with shifts).
    pub control_n: Option<usize>,
}

/// The pileups of a set of features: per group, then the one of all snippets.
#[derive(Clone, Debug, PartialEq)]
pub struct Pileups {
    /// Per group (sorted by strands, then distance band), the group of all snippets last.
    pub groups: Vec<Pileup>,
    /// Features left out, by reason.
    pub skipped: Skipped,
    /// Controls left out: their window left the region.
    pub controls_at_edge: usize,
    /// The minimum distance used (bp).
    pub min_dist_bp: f64,
    /// Snippets whose anchor 2 lies upstream of anchor 1 (BEDPE pairs given that way): below
    /// the diagonal, every pixel left out, yet counted in `n` (as coolpuppy counts them).
    pub below_diagonal: usize,
    /// The distance bands' edges (bp) with `by_distance`.
    pub distance_edges: Option<Vec<u64>>,
}

impl Pileups {
    /// The pileup of all snippets.
    pub fn all(&self) -> &Pileup {
        self.groups
            .last()
            .expect("the group of all snippets is always there")
    }
}
