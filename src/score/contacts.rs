//! Predicted residue contacts scored against the contacts of a known structure.
//!
//! **True contacts** ([`TrueContacts`]): two observed residues are in contact when the distance
//! between their representative atoms passes the [`ContactDefinition`]: by default the
//! Cb-Cb distance (Ca for glycine) below 8 Angstrom, the CASP definition
//! ([`ContactAtom::Cb`], [`DistanceTest::Less`], 8.0). [`ContactAtom::Ca`] uses Ca-Ca and
//! [`ContactAtom::Heavy`] the smallest distance between any two heavy (non-hydrogen) atoms.
//! A residue lacking the atom the definition needs (a non-Gly residue without Cb, say) counts as
//! unobserved. Residues are identified by their author number in the structure (see
//! [`crate::io::structure`]); the separation of a pair is the difference of the numbers.
//!
//! **Scoring** ([`score_contacts`]), the CASP assessors' computation (as ConKit, ConEVA and
//! DISTEVAL do it, with their conventions as options):
//!
//! 1. predicted pairs are made `i < j` (swapped when written `j > i`); pairs `i == i` and pairs
//!    with a NaN score are dropped; a pair given more than once keeps its **highest** score, at
//!    the place of its first occurrence;
//! 2. pairs outside the [`SeparationRange`] are dropped, and, unless
//!    [`ScoreParams::drop_unobserved`] is false, so are pairs with a residue not observed in the
//!    structure (when kept, such a pair takes a slot in the list and is never a true positive);
//! 3. the remaining `available` pairs are sorted by score, descending, with a **stable** sort
//!    (equal scores keep the prediction's order);
//! 4. each list size gives `k` ([`ListSize`]: a fraction of `L` rounded by [`Rounding`], a
//!    count, or the number of true contacts in the range, DISTEVAL's "Top-NC"); `L` is the
//!    sequence length or the number of observed residues ([`TargetLength`]);
//! 5. with `TP` the true contacts among the top `min(k, available)` pairs: precision
//!    `= TP / min(k, available)`, recall `= TP / n_true` (true contacts in the range), F1, and
//!    the Matthews correlation over all observed pairs of the range, and Xd. A ratio with a
//!    zero denominator is 0.
//!
//! **Xd** (CASP's distance-distribution score, Ortiz et al. 1999; Graña et al., Proteins 2005):
//! with 15 bins of 4 Angstrom covering 0-60 A, `P_ip` the percentage of the scored pairs whose
//! distance falls in bin `i` and `P_ia` the same for all observed pairs of the range,
//! `Xd = sum_i (P_ip - P_ia) / (d_i * 15)` where `d_i = 4 i / 60` is the upper limit of bin `i`
//! normalised to 60 A, so `Xd = sum_i (P_ip - P_ia) / i`, in percent. Pairs at 60 A or more
//! count in the percentages' denominators only. A list no better than chance has `Xd` near 0;
//! a list of true contacts has a large positive `Xd`. The distance is the one of the contact
//! definition (Cb-Cb by default).
//!
//! **Precision curve**: with [`ScoreParams::curve`], [`ContactScore::curve`] holds the true
//! positives among the top `k` pairs for every `k` from 1 to the curve's size (capped at the
//! available pairs), from which precision and recall at any list size follow.
//!
//! Defaults ([`ScoreParams::default`]): long range (`|i - j| >= 24`), `L` = sequence length,
//! `k = floor(L * f)` for `f` in 1/10, 1/5, 1/2, 1, unobserved pairs dropped: CASP's
//! conventions (Monastyrskyy et al., Proteins 2014, "Evaluation of residue-residue contact
//! prediction in CASP10"). ConKit (Simkovic et al., Bioinformatics 2017) uses the same with
//! `d <= 8`; ConEVA (Adhikari et al., BMC Bioinformatics 2016) rounds half up and takes
//! `L` = observed residues; DISTEVAL (Adhikari, Bioinformatics 2020, ba-lab/disteval) rounds half
//! to even and adds Top-NC. The tests reproduce the published numbers of each
//! (`data/protein/README.md`).
//!
//! Residue numbers of the prediction are those of the chain given to [`TrueContacts::from_chain`]:
//! place the chain on the prediction's sequence first ([`crate::score::register`]) when the
//! structure's numbering is not the sequence's.

use super::fraction::ratio;
use std::collections::HashMap;

use crate::error::{Error, Result};
use crate::io::structure::{Chain, Residue};

pub use crate::io::predictions::Prediction;

/// The atoms whose distance defines a contact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ContactAtom {
    /// Cb, Ca for glycine (CASP).
    #[default]
    Cb,
    /// Ca.
    Ca,
    /// The closest pair of heavy (non-hydrogen) atoms.
    Heavy,
}

/// How a distance is compared with the cutoff.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DistanceTest {
    /// `d < cutoff` (CASP, ConEVA, DISTEVAL).
    #[default]
    Less,
    /// `d <= cutoff` (ConKit).
    LessOrEqual,
}

/// When two residues are in contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactDefinition {
    /// The atoms measured.
    pub atom: ContactAtom,
    /// The distance cutoff in Angstrom.
    pub cutoff_angstrom: f64,
    /// Strict or not.
    pub test: DistanceTest,
}

impl Default for ContactDefinition {
    /// Cb (Ca for Gly), `d < 8` Angstrom.
    fn default() -> Self {
        Self {
            atom: ContactAtom::Cb,
            cutoff_angstrom: 8.0,
            test: DistanceTest::Less,
        }
    }
}

impl ContactDefinition {
    /// A short description, e.g. `Cb (Ca for Gly), d < 8 A`.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::score::contacts::ContactDefinition;
    ///
    /// assert_eq!(ContactDefinition::default().describe(), "Cb (Ca for Gly), d < 8 A");
    /// ```
    pub fn describe(&self) -> String {
        let atom = match self.atom {
            ContactAtom::Cb => "Cb (Ca for Gly)",
            ContactAtom::Ca => "Ca",
            ContactAtom::Heavy => "closest heavy atoms",
        };
        let test = match self.test {
            DistanceTest::Less => "<",
            DistanceTest::LessOrEqual => "<=",
        };
        format!("{atom}, d {test} {} A", self.cutoff_angstrom)
    }

    /// Whether a distance in Angstrom is a contact.
    pub fn is_contact(&self, distance: f64) -> bool {
        match self.test {
            DistanceTest::Less => distance < self.cutoff_angstrom,
            DistanceTest::LessOrEqual => distance <= self.cutoff_angstrom,
        }
    }
}

/// A range of sequence separations `|i - j|`, inclusive at both ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SeparationRange {
    /// Smallest separation.
    pub min: u32,
    /// Largest separation, `None` for no upper bound.
    pub max: Option<u32>,
}

impl SeparationRange {
    /// The largest separation as text: the number, or `inf` for an open range.
    pub fn max_text(&self) -> String {
        self.max
            .map_or_else(|| "inf".to_string(), |max| max.to_string())
    }

    /// Short range, 6-11 (CASP).
    pub const SHORT: Self = Self::new(6, Some(11));
    /// Medium range, 12-23 (CASP).
    pub const MEDIUM: Self = Self::new(12, Some(23));
    /// Long range, 24 and more (CASP).
    pub const LONG: Self = Self::new(24, None);
    /// All ranges, 6 and more (CASP).
    pub const ALL: Self = Self::new(6, None);

    /// The range `min..=max`.
    pub const fn new(min: u32, max: Option<u32>) -> Self {
        Self { min, max }
    }

    /// Whether the pair `(i, j)` falls in the range.
    pub fn contains(&self, i: i32, j: i32) -> bool {
        let separation = i.abs_diff(j);
        separation >= self.min && self.max.is_none_or(|max| separation <= max)
    }
}

/// Number of distance bins of Xd.
pub const XD_BINS: usize = 15;
/// Width of an Xd bin in Angstrom.
pub const XD_BIN_WIDTH: f64 = 4.0;

/// The Xd bin of a distance, or `None` at 60 A and beyond.
fn xd_bin(distance: f64) -> Option<usize> {
    let bin = (distance / XD_BIN_WIDTH).floor();
    (bin >= 0.0 && bin < XD_BINS as f64).then_some(bin as usize)
}

/// Xd from the bin counts of the scored pairs and of all pairs (see the module docs).
fn xd(list: &[usize; XD_BINS], n_list: usize, all: &[usize; XD_BINS], n_all: usize) -> f64 {
    if n_list == 0 || n_all == 0 {
        return 0.0;
    }
    (0..XD_BINS)
        .map(|bin| {
            let predicted = 100.0 * list[bin] as f64 / n_list as f64;
            let everything = 100.0 * all[bin] as f64 / n_all as f64;
            (predicted - everything) / (bin + 1) as f64
        })
        .sum()
}

/// Distances between the observed residues of a chain, and the contacts they make.
#[derive(Clone, Debug)]
pub struct TrueContacts {
    numbers: Vec<i32>,
    /// `slot[number - first]`: index into `numbers`, or `u32::MAX`.
    slot: Vec<u32>,
    /// Condensed upper triangle of residue distances (index pairs `a < b`).
    distances: Vec<f64>,
    definition: ContactDefinition,
    /// The contacts of an ensemble, when they replace the distances' ([`TrueContacts::
    /// with_frequencies`]).
    ensemble: Option<Ensemble>,
}

/// The contact frequencies of an ensemble, per condensed pair (NaN: not measured), and the
/// smallest frequency of a contact.
#[derive(Clone, Debug)]
struct Ensemble {
    frequencies: Vec<f64>,
    threshold: f64,
}

fn distance(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn representative_atoms(residue: &Residue, atom: ContactAtom) -> Vec<[f64; 3]> {
    let named = |name: &str| residue.atom(name).map(|atom| vec![atom.xyz]);
    match atom {
        ContactAtom::Ca => named("CA"),
        ContactAtom::Cb if residue.name == "GLY" => named("CA"),
        ContactAtom::Cb => named("CB"),
        ContactAtom::Heavy => Some(
            residue
                .atoms
                .iter()
                .filter(|atom| !atom.is_hydrogen())
                .map(|atom| atom.xyz)
                .collect(),
        ),
    }
    .unwrap_or_default()
}

impl TrueContacts {
    /// Measure the residues of `chain` as `definition` says. Residue numbers must be unique (a
    /// chain with insertion codes must be placed on a sequence first,
    /// [`crate::score::register::Register::renumber`]).
    pub fn from_chain(chain: &Chain, definition: ContactDefinition) -> Result<Self> {
        if !(definition.cutoff_angstrom.is_finite() && definition.cutoff_angstrom > 0.0) {
            return Err(Error::Invalid(format!(
                "contact cutoff must be a positive number of Angstrom, got {}",
                definition.cutoff_angstrom
            )));
        }
        let mut residues: Vec<(i32, Vec<[f64; 3]>)> = chain
            .residues
            .iter()
            .map(|residue| {
                (
                    residue.number,
                    representative_atoms(residue, definition.atom),
                )
            })
            .filter(|(_, atoms)| !atoms.is_empty())
            .collect();
        residues.sort_by_key(|(number, _)| *number);
        if let Some(pair) = residues.windows(2).find(|pair| pair[0].0 == pair[1].0) {
            return Err(Error::Invalid(format!(
                "chain {} has residue number {} more than once (insertion codes): scoring by \
                 residue number needs unique numbers",
                chain.id, pair[0].0
            )));
        }
        let numbers: Vec<i32> = residues.iter().map(|(number, _)| *number).collect();
        let mut slot = Vec::new();
        if let (Some(first), Some(last)) = (numbers.first(), numbers.last()) {
            slot = vec![u32::MAX; (last - first) as usize + 1];
            for (index, number) in numbers.iter().enumerate() {
                slot[(number - first) as usize] = index as u32;
            }
        }
        let n = residues.len();
        let mut distances = Vec::with_capacity(n * n.saturating_sub(1) / 2);
        for a in 0..n {
            for b in a + 1..n {
                let mut closest = f64::INFINITY;
                for x in &residues[a].1 {
                    for y in &residues[b].1 {
                        closest = closest.min(distance(x, y));
                    }
                }
                distances.push(closest);
            }
        }
        Ok(Self {
            numbers,
            slot,
            distances,
            definition,
            ensemble: None,
        })
    }

    /// The contacts of an ensemble (an MD trajectory) instead of the structure's: a pair is a
    /// contact when its `frequency` (the fraction of frames in contact) is at least
    /// `threshold`. `frequencies` gives `(i, j, frequency)` by residue number; pairs it does
    /// not give are unmeasured, scored as unobserved ([`TrueContacts::distance`] is `None`);
    /// pairs with a residue not observed here are ignored. The structure's distances remain
    /// for the distance-based measures (Xd).
    ///
    /// ```
    /// use contactmap::io::structure::read_structure;
    /// use contactmap::score::contacts::{ContactDefinition, TrueContacts};
    /// let structure = read_structure("data/protein/toxd/toxd.pdb.gz")?;
    /// let truth = TrueContacts::from_chain(structure.chain(None)?, ContactDefinition::default())?;
    /// let (a, b, c) = (truth.numbers()[0], truth.numbers()[1], truth.numbers()[30]);
    /// let ensemble = truth.clone().with_frequencies([(a, c, 0.75), (b, c, 0.25)], 0.5)?;
    /// assert_eq!((ensemble.is_contact(a, c), ensemble.is_contact(c, b)), (Some(true), Some(false)));
    /// // not in the ensemble's table: unmeasured
    /// assert_eq!((ensemble.is_contact(a, b), ensemble.distance(a, b)), (None, None));
    /// assert_eq!(ensemble.distance(a, c), truth.distance(a, c));
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn with_frequencies(
        mut self,
        frequencies: impl IntoIterator<Item = (i32, i32, f64)>,
        threshold: f64,
    ) -> Result<Self> {
        if !(threshold > 0.0 && threshold <= 1.0) {
            return Err(Error::Argument(format!(
                "the contact frequency threshold must be a fraction of frames above 0 and at \
                 most 1, got {threshold}"
            )));
        }
        let mut measured = vec![f64::NAN; self.distances.len()];
        for (i, j, frequency) in frequencies {
            if let (Some(a), Some(b)) = (self.index(i), self.index(j)) {
                if a != b {
                    measured[self.condensed(a, b)] = frequency;
                }
            }
        }
        self.ensemble = Some(Ensemble {
            frequencies: measured,
            threshold,
        });
        Ok(self)
    }

    /// Whether the pair at condensed `index` is a contact; `None` when an ensemble did not
    /// measure it.
    fn contact_at(&self, index: usize) -> Option<bool> {
        match &self.ensemble {
            None => Some(self.definition.is_contact(self.distances[index])),
            Some(ensemble) => {
                let frequency = ensemble.frequencies[index];
                (!frequency.is_nan()).then_some(frequency >= ensemble.threshold)
            }
        }
    }

    /// The contact definition used.
    pub fn definition(&self) -> &ContactDefinition {
        &self.definition
    }

    /// Numbers of the observed residues, ascending.
    pub fn numbers(&self) -> &[i32] {
        &self.numbers
    }

    /// Number of observed residues.
    pub fn n_observed(&self) -> usize {
        self.numbers.len()
    }

    /// The distances (Angstrom) between the observed residues, `n x n` in the order of
    /// [`TrueContacts::numbers`], 0 on the diagonal.
    pub fn distance_matrix(&self) -> ndarray::Array2<f64> {
        let n = self.numbers.len();
        ndarray::Array2::from_shape_fn((n, n), |(a, b)| {
            if a == b {
                0.0
            } else {
                self.distances[self.condensed(a, b)]
            }
        })
    }

    fn index(&self, number: i32) -> Option<usize> {
        let first = *self.numbers.first()?;
        let offset = usize::try_from(i64::from(number) - i64::from(first)).ok()?;
        match self.slot.get(offset) {
            Some(&index) if index != u32::MAX => Some(index as usize),
            _ => None,
        }
    }

    fn condensed(&self, a: usize, b: usize) -> usize {
        let (a, b) = if a < b { (a, b) } else { (b, a) };
        let n = self.numbers.len();
        a * n - a * (a + 1) / 2 + (b - a - 1)
    }

    /// Distance in Angstrom between residues `i` and `j` (author numbers), or `None` when
    /// either is not observed (or an ensemble did not measure the pair) or `i == j`.
    pub fn distance(&self, i: i32, j: i32) -> Option<f64> {
        let index = self.pair_index(i, j)?;
        self.contact_at(index)?;
        Some(self.distances[index])
    }

    /// The condensed index of the pair of residues `i` and `j` when both are observed and differ.
    fn pair_index(&self, i: i32, j: i32) -> Option<usize> {
        let (a, b) = (self.index(i)?, self.index(j)?);
        (a != b).then(|| self.condensed(a, b))
    }

    /// Whether `i` and `j` are in contact, or `None` when either is not observed (or the
    /// ensemble did not measure them) or `i == j`.
    pub fn is_contact(&self, i: i32, j: i32) -> Option<bool> {
        self.contact_at(self.pair_index(i, j)?)
    }

    /// The true contacts `(i, j)`, `i < j`, whose separation is in `range`, sorted.
    pub fn contacts(&self, range: SeparationRange) -> Vec<(i32, i32)> {
        let n = self.numbers.len();
        let mut contacts = Vec::new();
        let mut index = 0;
        for a in 0..n {
            for b in a + 1..n {
                let (i, j) = (self.numbers[a], self.numbers[b]);
                if range.contains(i, j) && self.contact_at(index) == Some(true) {
                    contacts.push((i, j));
                }
                index += 1;
            }
        }
        contacts
    }

    /// Number of true contacts whose separation is in `range`.
    pub fn n_contacts(&self, range: SeparationRange) -> usize {
        self.contacts(range).len()
    }

    /// Xd bin counts of the pairs of observed residues whose separation is in `range`, and
    /// the number of those pairs.
    pub fn distance_histogram(&self, range: SeparationRange) -> ([usize; XD_BINS], usize) {
        let n = self.numbers.len();
        let mut counts = [0usize; XD_BINS];
        let mut total = 0;
        let mut index = 0;
        for a in 0..n {
            for b in a + 1..n {
                if range.contains(self.numbers[a], self.numbers[b])
                    && self.contact_at(index).is_some()
                {
                    total += 1;
                    if let Some(bin) = xd_bin(self.distances[index]) {
                        counts[bin] += 1;
                    }
                }
                index += 1;
            }
        }
        (counts, total)
    }
}

/// How `L * f` becomes a list size.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Rounding {
    /// `floor(L * f)` (CASP, ConKit's `int(L * f)`).
    #[default]
    Floor,
    /// `floor(L * f + 0.5)` (ConEVA).
    HalfUp,
    /// Half to even, Python's `round` (DISTEVAL).
    Banker,
}

impl Rounding {
    /// The name of the rule: `floor`, `half-up` or `banker`.
    pub fn name(self) -> &'static str {
        match self {
            Rounding::Floor => "floor",
            Rounding::HalfUp => "half-up",
            Rounding::Banker => "banker",
        }
    }

    /// Round a non-negative list size.
    pub fn apply(self, value: f64) -> usize {
        let rounded = match self {
            Rounding::Floor => value.floor(),
            Rounding::HalfUp => (value + 0.5).floor(),
            Rounding::Banker => value.round_ties_even(),
        };
        rounded.max(0.0) as usize
    }
}

/// What `L` is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TargetLength {
    /// The length of the prediction's sequence (CASP, ConKit, DISTEVAL).
    #[default]
    Sequence,
    /// The number of residues observed in the structure (ConEVA).
    Observed,
    /// A given number.
    Residues(usize),
}

/// The size of a top list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ListSize {
    /// `k = round(L * fraction)`, rounded by [`ScoreParams::rounding`].
    Fraction(f64),
    /// A fixed number of pairs.
    Count(usize),
    /// The number of true contacts in the range (DISTEVAL's "Top-NC").
    TrueContacts,
}

/// Options of [`score_contacts`].
#[derive(Clone, Debug, PartialEq)]
pub struct ScoreParams {
    /// Separation range of the scored pairs.
    pub range: SeparationRange,
    /// What `L` is.
    pub length: TargetLength,
    /// Rounding of `L * f`.
    pub rounding: Rounding,
    /// List sizes to report, in order.
    pub list_sizes: Vec<ListSize>,
    /// Drop pairs with an unobserved residue before ranking.
    pub drop_unobserved: bool,
    /// Compute the precision curve up to this list size ([`ContactScore::curve`]).
    pub curve: Option<ListSize>,
}

impl ScoreParams {
    /// Check the values: list-size fractions that are numbers `>= 0`, a separation range whose
    /// end is not below its start. [`score_contacts`] checks them first.
    ///
    /// # Examples
    ///
    /// ```
    /// use contactmap::score::contacts::{ListSize, ScoreParams};
    ///
    /// let params = ScoreParams::default();
    /// assert!(params.check().is_ok());
    /// let bad = ScoreParams { list_sizes: vec![ListSize::Fraction(f64::NAN)], ..params };
    /// assert!(bad.check().is_err());
    /// ```
    pub fn check(&self) -> Result<()> {
        for size in self.list_sizes.iter().chain(&self.curve) {
            if let ListSize::Fraction(f) = size {
                if !(f.is_finite() && *f >= 0.0) {
                    return Err(Error::parameter(
                        "list_sizes",
                        format!("{f}L"),
                        "expected fractions of L that are numbers >= 0",
                    ));
                }
            }
        }
        if let Some(max) = self.range.max.filter(|&max| max < self.range.min) {
            return Err(Error::parameter(
                "range",
                format!("{}-{max}", self.range.min),
                "expected MIN-MAX with MAX >= MIN",
            ));
        }
        Ok(())
    }
}

impl Default for ScoreParams {
    /// Long range, `L` = sequence length, `floor`, L/10, L/5, L/2, L, unobserved dropped.
    fn default() -> Self {
        Self {
            range: SeparationRange::LONG,
            length: TargetLength::Sequence,
            rounding: Rounding::Floor,
            list_sizes: [0.1, 0.2, 0.5, 1.0]
                .into_iter()
                .map(ListSize::Fraction)
                .collect(),
            drop_unobserved: true,
            curve: None,
        }
    }
}

/// The scores of one top list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ListScore {
    /// The requested size.
    pub size: ListSize,
    /// `k`, the requested number of pairs.
    pub k: usize,
    /// `min(k, available)`: the pairs actually scored.
    pub n_scored: usize,
    /// True contacts among them.
    pub true_positives: usize,
    /// `true_positives / n_scored`.
    pub precision: f64,
    /// `true_positives / n_true`.
    pub recall: f64,
    /// Harmonic mean of precision and recall.
    pub f1: f64,
    /// Matthews correlation coefficient over the observed pairs of the range.
    pub mcc: f64,
    /// CASP's Xd, in percent (see the module docs).
    pub xd: f64,
}

/// Result of [`score_contacts`] for one separation range.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactScore {
    /// The range.
    pub range: SeparationRange,
    /// `L`.
    pub length: usize,
    /// True contacts in the range.
    pub n_true: usize,
    /// Pairs of observed residues in the range.
    pub n_pairs: usize,
    /// Predicted pairs left to rank after steps 1-2 of the module docs.
    pub n_available: usize,
    /// One score per requested list size.
    pub lists: Vec<ListScore>,
    /// `curve[k - 1]`: true positives among the top `k` pairs, for `k` from 1 to the size of
    /// [`ScoreParams::curve`] (capped at the available pairs); empty without one.
    pub curve: Vec<usize>,
}

/// Pairs made `i < j`, without self pairs and NaN scores, duplicates keeping their highest
/// score at the place of their first occurrence (step 1 of the module docs).
pub fn normalize_pairs(pairs: &[(i32, i32, f64)]) -> Vec<(i32, i32, f64)> {
    let mut first_seen: HashMap<(i32, i32), usize> = HashMap::with_capacity(pairs.len());
    let mut normalized: Vec<(i32, i32, f64)> = Vec::with_capacity(pairs.len());
    for &(i, j, score) in pairs {
        if i == j || score.is_nan() {
            continue;
        }
        let (i, j) = if i < j { (i, j) } else { (j, i) };
        match first_seen.entry((i, j)) {
            std::collections::hash_map::Entry::Occupied(entry) => {
                let kept = &mut normalized[*entry.get()].2;
                *kept = kept.max(score);
            }
            std::collections::hash_map::Entry::Vacant(entry) => {
                entry.insert(normalized.len());
                normalized.push((i, j, score));
            }
        }
    }
    normalized
}

/// The pairs of `prediction` whose separation is in `range`, made `i < j` and deduplicated
/// ([`normalize_pairs`]), sorted by score, descending and stably (equal scores keep the
/// prediction's order): steps 1 and 3 of the module docs, shared with
/// [`crate::score::overlap`].
pub fn rank_pairs(prediction: &Prediction, range: SeparationRange) -> Vec<(i32, i32, f64)> {
    let mut pairs: Vec<(i32, i32, f64)> = normalize_pairs(&prediction.pairs)
        .into_iter()
        .filter(|&(i, j, _)| range.contains(i, j))
        .collect();
    // NaN scores were dropped, so the comparison is total.
    pairs.sort_by(|a, b| b.2.partial_cmp(&a.2).unwrap_or(std::cmp::Ordering::Equal));
    pairs
}

/// A predicted pair in rank order, with what the structure says of it ([`ranked_predictions`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RankedPair {
    /// First residue (`i < j`), in the prediction's numbering.
    pub i: i32,
    /// Second residue.
    pub j: i32,
    /// The prediction's score.
    pub score: f64,
    /// Distance in the structure in Angstrom; `None` when a residue is not observed.
    pub distance_angstrom: Option<f64>,
    /// Whether the pair is a true contact (never for an unobserved pair).
    pub is_contact: bool,
}

/// The pairs [`score_contacts`] ranks: steps 1-3 of the module docs, pairs outside `range`
/// dropped, and pairs with an unobserved residue dropped when `drop_unobserved`; the top `k`
/// of the result are a top-`k` list.
pub fn ranked_predictions(
    truth: &TrueContacts,
    prediction: &Prediction,
    range: SeparationRange,
    drop_unobserved: bool,
) -> Vec<RankedPair> {
    // Dropping pairs after a stable sort leaves the same order as dropping them before.
    rank_pairs(prediction, range)
        .into_iter()
        .map(|(i, j, score)| RankedPair {
            i,
            j,
            score,
            distance_angstrom: truth.distance(i, j),
            is_contact: truth.is_contact(i, j) == Some(true),
        })
        .filter(|pair| pair.distance_angstrom.is_some() || !drop_unobserved)
        .collect()
}

/// `L` as `length` says: the prediction's sequence length (an error without one), the observed
/// residues of `truth`, or a given number.
pub fn target_length(
    truth: &TrueContacts,
    prediction: &Prediction,
    length: TargetLength,
) -> Result<usize> {
    match length {
        TargetLength::Sequence => prediction
            .sequence
            .as_ref()
            .map(|sequence| sequence.chars().count())
            .ok_or_else(|| {
                Error::Data(
                    "L is the sequence length, but the prediction has no sequence: give one \
                     (FASTA) or take L from the observed residues"
                        .into(),
                )
            }),
        TargetLength::Observed => Ok(truth.n_observed()),
        TargetLength::Residues(n) => Ok(n),
    }
}

/// `k` of a list size: `L * fraction` rounded, a count, or `n_true` (step 4 of the module
/// docs).
pub fn list_length(size: ListSize, length: usize, rounding: Rounding, n_true: usize) -> usize {
    match size {
        ListSize::Fraction(fraction) => rounding.apply(length as f64 * fraction),
        ListSize::Count(count) => count,
        ListSize::TrueContacts => n_true,
    }
}

/// Score `prediction` against `truth` (see the module docs).
///
/// # Examples
///
/// CCMpred's prediction for toxd against its crystal structure, CASP's long-range top L/10,
/// L/5, L/2 and L lists: 5 of 5, 9 of 11, 17 of 29 and 22 of 59 pairs are true contacts, the
/// numbers of the reference computation in `data/protein/README.md`.
///
/// ```
/// use contactmap::io::predictions::{read_fasta, read_prediction};
/// use contactmap::io::structure::read_structure;
/// use contactmap::score::contacts::{score_contacts, ContactDefinition, ScoreParams, TrueContacts};
///
/// let structure = read_structure("data/protein/toxd/toxd.pdb.gz")?;
/// let truth = TrueContacts::from_chain(structure.chain(None)?, ContactDefinition::default())?;
/// let sequence = read_fasta("data/protein/toxd/toxd.fasta")?;
/// let prediction = read_prediction("data/protein/toxd/toxd.mat.gz", None)?.with_sequence(&sequence)?;
/// let score = score_contacts(&truth, &prediction, &ScoreParams::default())?;
/// assert_eq!(score.length, 59);
/// let found: Vec<(usize, usize)> =
///     score.lists.iter().map(|list| (list.true_positives, list.n_scored)).collect();
/// assert_eq!(found, [(5, 5), (9, 11), (17, 29), (22, 59)]);
/// assert_eq!(score.lists[0].precision, 1.0);
/// # Ok::<(), contactmap::Error>(())
/// ```
pub fn score_contacts(
    truth: &TrueContacts,
    prediction: &Prediction,
    params: &ScoreParams,
) -> Result<ContactScore> {
    params.check()?;
    let length = target_length(truth, prediction, params.length)?;
    // (contact, distance: None when a residue is unobserved), still in rank order.
    let ranked: Vec<(bool, Option<f64>)> =
        ranked_predictions(truth, prediction, params.range, params.drop_unobserved)
            .into_iter()
            .map(|pair| (pair.is_contact, pair.distance_angstrom))
            .collect();
    let n_true = truth.n_contacts(params.range);
    let (all_bins, n_pairs) = truth.distance_histogram(params.range);
    let list_size = |size: ListSize| list_length(size, length, params.rounding, n_true);
    let lists = params
        .list_sizes
        .iter()
        .map(|&size| {
            let k = list_size(size);
            let n_scored = k.min(ranked.len());
            let top = &ranked[..n_scored];
            let tp = top.iter().filter(|(contact, _)| *contact).count();
            let observed = top
                .iter()
                .filter(|(_, distance)| distance.is_some())
                .count();
            let fp = observed - tp;
            let mut bins = [0usize; XD_BINS];
            for bin in top.iter().filter_map(|(_, distance)| xd_bin((*distance)?)) {
                bins[bin] += 1;
            }
            let precision = ratio(tp, n_scored);
            let recall = ratio(tp, n_true);
            let f1 = if precision + recall > 0.0 {
                2.0 * precision * recall / (precision + recall)
            } else {
                0.0
            };
            let false_negatives = n_true - tp;
            let true_negatives = n_pairs.saturating_sub(tp + fp + false_negatives);
            let (tp_f, fp_f, fn_f, tn_f) = (
                tp as f64,
                fp as f64,
                false_negatives as f64,
                true_negatives as f64,
            );
            let denominator =
                ((tp_f + fp_f) * (tp_f + fn_f) * (tn_f + fp_f) * (tn_f + fn_f)).sqrt();
            let mcc = if denominator > 0.0 {
                (tp_f * tn_f - fp_f * fn_f) / denominator
            } else {
                0.0
            };
            ListScore {
                size,
                k,
                n_scored,
                true_positives: tp,
                precision,
                recall,
                f1,
                mcc,
                xd: xd(&bins, observed, &all_bins, n_pairs),
            }
        })
        .collect();
    let curve = match params.curve {
        None => Vec::new(),
        Some(size) => ranked[..list_size(size).min(ranked.len())]
            .iter()
            .scan(0usize, |tp, (contact, _)| {
                *tp += usize::from(*contact);
                Some(*tp)
            })
            .collect(),
    };
    Ok(ContactScore {
        range: params.range,
        length,
        n_true,
        n_pairs,
        n_available: ranked.len(),
        lists,
        curve,
    })
}

#[cfg(test)]
mod tests;
