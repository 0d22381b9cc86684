//! One-dimensional loop extrusion: the model of Fudenberg et al. 2016 ("Formation of
//! chromosomal domains by loop extrusion", Cell Reports 15:2038-2049), whose bound loop
//! extruding factors (LEFs, cohesin) give the dynamic bonds of a 3D bead-spring chain.
//!
//! # Model
//!
//! The polymer has `N` monomers (sites `0..N`), split into chains (chromosomes) given as
//! half-open ranges that cover `0..N` in order. A LEF has a left leg and a right leg at sites
//! `l < r` of one chain; each site holds at most one leg.
//!
//! - **Number of LEFs**: `round(N / separation)`, at least 1.
//! - **Loading**: a LEF loads at a uniformly random `p` with `p` and `p + 1` both free and on the
//!   same chain (left leg at `p`, right leg at `p + 1`): random positions are drawn until one fits,
//!   at most 1000 times ([`LOAD_TRIES`]); if none fits the LEF stays unbound and tries again at
//!   the end of the next step.
//! - **Lifetime and processivity**: with legs moving one site per step each, processivity
//!   `λ = 2 × velocity × lifetime` (Fudenberg 2016) gives a lifetime of `λ / 2` steps: each step a
//!   bound LEF unloads with probability `2 / λ`. Unobstructed, a LEF that has made `t` moves spans
//!   `r - l = 2t + 1`, so in the dilute limit the mean loop size over the (geometric) age
//!   distribution seen after a step is exactly `λ - 1`.
//! - **Boundary elements** (CTCF): [`Orientation::Forward`] (`+`) stops left-moving legs,
//!   [`Orientation::Reverse`] (`-`) stops right-moving legs, [`Orientation::Both`] stops both. A
//!   loop anchored by convergent sites thus has a `+` site at its left leg and a `-` site at its
//!   right leg.
//!
//! # One step
//!
//! Bound LEFs are handled one after the other, in the order of [`Extruder::legs`]. For each:
//!
//! 1. With probability `2 / λ` it unloads, and **reloads at once, in the same step** (as
//!    polychrom's 1D examples do) at a new random position; a LEF that (re)loads does not move in
//!    that step. If no position is found it becomes unbound (it is removed from the list with a
//!    `swap_remove`, so the last LEF takes its index).
//! 2. Otherwise its left leg, then its right leg:
//!    - a **captured** leg is released with the element's `release` probability; if it stays
//!      captured it does not move. A leg released in this step tries to move in the same step.
//!    - an uncaptured leg moves outward by one site (`l - 1`, `r + 1`) unless the target is past
//!      the chain end or holds any leg (legs block each other, so they never cross, and loops
//!      are always nested or disjoint).
//!
//! Then LEFs that were unbound at the start of the step try to load (new LEFs are appended).
//!
//! **Capture rule**: capture is checked **once per arrival**: when a leg steps onto a site whose
//! element stops its direction of motion, or when a LEF is loaded with a leg on such a site, the
//! leg is captured with the element's `capture` probability. A leg that escapes capture is not
//! checked again while it stays on that site (even if it is blocked there); a leg that is
//! released is not captured again by the same site. So `1 - capture` is exactly the probability
//! of passing an element, and the time a captured leg spends there (from the step of its arrival
//! to the step it moves on, if nothing blocks it then) is geometric with mean `1 / release`
//! steps. Unloading frees captured legs too. `capture = 1`, `release = 0` is a permanent
//! barrier: a leg it stops that reaches it (or is loaded on it) stays there until its LEF
//! unloads, so no loop ever strictly straddles a permanent [`Orientation::Both`] barrier.
//!
//! # Cost and determinism
//!
//! [`Extruder::step`] costs O(number of LEFs) (plus up to [`LOAD_TRIES`] draws for each LEF that
//! needs a position): occupancy and the elements are kept in per-site arrays. Memory is O(N).
//! Random numbers are drawn in a fixed order (a probability of exactly 0 or 1 draws nothing), so
//! the same generator state gives the same trajectory.

use std::ops::Range;

use rand::Rng;

/// How many random positions a LEF tries in one step before it gives up loading until the next
/// step (the polymer is then too crowded).
pub const LOAD_TRIES: usize = 1000;

/// Marks a site without an element for a direction in the per-site lookup arrays.
const NO_STOP: u32 = u32::MAX;

/// Which moving legs a boundary element stops.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Orientation {
    /// A `+` site: stops left-moving legs (the left anchor of a convergent loop).
    Forward,
    /// A `-` site: stops right-moving legs (the right anchor of a convergent loop).
    Reverse,
    /// Stops legs moving either way.
    Both,
}

impl Orientation {
    /// Whether this element stops left legs (which move leftwards).
    pub fn stops_left(self) -> bool {
        matches!(self, Orientation::Forward | Orientation::Both)
    }

    /// Whether this element stops right legs (which move rightwards).
    pub fn stops_right(self) -> bool {
        matches!(self, Orientation::Reverse | Orientation::Both)
    }
}

/// A boundary element (CTCF site) that can capture the legs it stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryElement {
    /// Its site (monomer index).
    pub position: usize,
    /// Which moving legs it stops.
    pub orientation: Orientation,
    /// Probability that a leg it stops is captured on arriving on its site, in `[0, 1]`.
    pub capture: f64,
    /// Probability per step that a captured leg is released, in `[0, 1]`.
    pub release: f64,
}

impl BoundaryElement {
    /// A permanent barrier: `capture = 1`, `release = 0`.
    pub fn permanent(position: usize, orientation: Orientation) -> Self {
        Self {
            position,
            orientation,
            capture: 1.0,
            release: 0.0,
        }
    }
}

/// Parameters of the extrusion model.
#[derive(Debug, Clone, PartialEq)]
pub struct ExtrusionParams {
    /// The chains as half-open ranges of monomers, covering `0..N` in order without gaps.
    pub chains: Vec<Range<usize>>,
    /// Processivity `λ` (monomers): twice the lifetime, which is `λ / 2` steps; the mean loop
    /// size of unobstructed LEFs (exactly `λ - 1` here, see the module docs). Must be finite and
    /// at least 2 (a lifetime of at least one step).
    pub processivity: f64,
    /// Mean distance between LEFs (monomers): there are `round(N / separation)` LEFs, at least
    /// one. Must be finite and at least 1.
    pub separation: f64,
    /// Boundary elements, at most one per site and direction (a `Forward` and a `Reverse`
    /// element may share a site).
    pub elements: Vec<BoundaryElement>,
}

/// Why [`ExtrusionParams`] are invalid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExtrusionError {
    /// No chains were given.
    #[error("chains: the chain list is empty")]
    NoChains,
    /// A chain does not start where the previous one ended (or chain 0 does not start at 0).
    #[error(
        "chains: chain {index} is {start}..{end} but must start at {expected} \
         (chains must cover 0..N in order, without gaps or overlaps)"
    )]
    ChainGap {
        /// Index of the chain.
        index: usize,
        /// Its start.
        start: usize,
        /// Its end.
        end: usize,
        /// Where it should start.
        expected: usize,
    },
    /// A chain has no monomers.
    #[error("chains: chain {index} ({start}..{end}) is empty")]
    EmptyChain {
        /// Index of the chain.
        index: usize,
        /// Its start.
        start: usize,
        /// Its end.
        end: usize,
    },
    /// The processivity is not finite or below 2.
    #[error(
        "processivity must be a finite number of monomers >= 2 \
         (lifetime = processivity / 2 >= 1 step), got {0}"
    )]
    Processivity(f64),
    /// The separation is not finite or below 1.
    #[error("separation must be a finite number of monomers >= 1, got {0}")]
    Separation(f64),
    /// More LEFs than can fit on the chains.
    #[error(
        "separation {separation} gives {n_lefs} LEFs on {n_monomers} monomers, but at most \
         {capacity} fit (each LEF needs two sites of one chain)"
    )]
    TooManyLefs {
        /// The separation.
        separation: f64,
        /// The number of LEFs it gives.
        n_lefs: usize,
        /// The polymer size.
        n_monomers: usize,
        /// The sum over chains of `floor(length / 2)`.
        capacity: usize,
    },
    /// An element is not on the polymer.
    #[error(
        "element {index}: position {position} is outside the polymer of {n_monomers} monomers \
         (sites 0..{n_monomers})"
    )]
    ElementOutside {
        /// Index of the element.
        index: usize,
        /// Its position.
        position: usize,
        /// The polymer size.
        n_monomers: usize,
    },
    /// A capture or release probability is not in `[0, 1]`.
    #[error("element {index} at position {position}: {which} probability {value} is not in [0, 1]")]
    Probability {
        /// Index of the element.
        index: usize,
        /// Its position.
        position: usize,
        /// `"capture"` or `"release"`.
        which: &'static str,
        /// The bad value.
        value: f64,
    },
    /// More elements than the per-site lookup can index (`u32::MAX - 1`).
    #[error("elements: {count} elements, more than the {max} supported")]
    TooManyElements {
        /// The number of elements.
        count: usize,
        /// The largest number supported.
        max: usize,
    },
    /// Two elements at one site stop the same direction.
    #[error(
        "elements {first} and {second} at position {position} both stop {direction}-moving \
         legs (give at most one element per site and direction)"
    )]
    ConflictingElements {
        /// Index of the first element.
        first: usize,
        /// Index of the second element.
        second: usize,
        /// Their position.
        position: usize,
        /// `"left"` or `"right"`.
        direction: &'static str,
    },
}

impl ExtrusionParams {
    /// Parameters for one chain of `n_monomers` and no boundary elements.
    pub fn single_chain(n_monomers: usize, processivity: f64, separation: f64) -> Self {
        Self {
            chains: std::iter::once(0..n_monomers).collect(),
            processivity,
            separation,
            elements: Vec::new(),
        }
    }

    /// The polymer size `N` (the end of the last chain; 0 without chains).
    pub fn n_monomers(&self) -> usize {
        self.chains.last().map_or(0, |c| c.end)
    }

    /// The number of LEFs, `round(N / separation)` and at least 1 (meaningful once
    /// [`check`](Self::check) passes).
    pub fn n_lefs(&self) -> usize {
        ((self.n_monomers() as f64 / self.separation).round() as usize).max(1)
    }

    /// The mean residence time of a LEF in steps, `processivity / 2`.
    pub fn lifetime(&self) -> f64 {
        self.processivity / 2.0
    }

    /// Check the parameters: chains non-empty and covering `0..N` contiguously, processivity and
    /// separation finite (at least 2 and 1), no more LEFs than fit (two sites of one chain each),
    /// elements on the polymer with probabilities in `[0, 1]` and at most one per site and
    /// direction.
    pub fn check(&self) -> Result<(), ExtrusionError> {
        if self.chains.is_empty() {
            return Err(ExtrusionError::NoChains);
        }
        let mut expected = 0;
        for (index, c) in self.chains.iter().enumerate() {
            if c.start != expected {
                return Err(ExtrusionError::ChainGap {
                    index,
                    start: c.start,
                    end: c.end,
                    expected,
                });
            }
            if c.end <= c.start {
                return Err(ExtrusionError::EmptyChain {
                    index,
                    start: c.start,
                    end: c.end,
                });
            }
            expected = c.end;
        }
        let n_monomers = expected;
        if !(self.processivity.is_finite() && self.processivity >= 2.0) {
            return Err(ExtrusionError::Processivity(self.processivity));
        }
        if !(self.separation.is_finite() && self.separation >= 1.0) {
            return Err(ExtrusionError::Separation(self.separation));
        }
        let capacity: usize = self.chains.iter().map(|c| c.len() / 2).sum();
        let n_lefs = self.n_lefs();
        if n_lefs > capacity {
            return Err(ExtrusionError::TooManyLefs {
                separation: self.separation,
                n_lefs,
                n_monomers,
                capacity,
            });
        }
        if self.elements.len() >= NO_STOP as usize {
            return Err(ExtrusionError::TooManyElements {
                count: self.elements.len(),
                max: NO_STOP as usize - 1,
            });
        }
        // Which element stops each direction at each site, to find conflicts in O(N + E).
        let mut left = vec![usize::MAX; n_monomers];
        let mut right = vec![usize::MAX; n_monomers];
        for (index, e) in self.elements.iter().enumerate() {
            if e.position >= n_monomers {
                return Err(ExtrusionError::ElementOutside {
                    index,
                    position: e.position,
                    n_monomers,
                });
            }
            for (which, value) in [("capture", e.capture), ("release", e.release)] {
                if !(0.0..=1.0).contains(&value) {
                    return Err(ExtrusionError::Probability {
                        index,
                        position: e.position,
                        which,
                        value,
                    });
                }
            }
            for (stops, table, direction) in [
                (e.orientation.stops_left(), &mut left, "left"),
                (e.orientation.stops_right(), &mut right, "right"),
            ] {
                if !stops {
                    continue;
                }
                let slot = &mut table[e.position];
                if *slot != usize::MAX {
                    return Err(ExtrusionError::ConflictingElements {
                        first: *slot,
                        second: index,
                        position: e.position,
                        direction,
                    });
                }
                *slot = index;
            }
        }
        Ok(())
    }
}

/// The state of the 1D extrusion: where the legs of the bound LEFs are.
#[derive(Debug, Clone)]
pub struct Extruder {
    chains: Vec<Range<usize>>,
    n_monomers: usize,
    n_lefs: usize,
    unload_prob: f64,
    /// `(capture, release)` of each element.
    stops: Vec<(f64, f64)>,
    /// Per site: index into `stops` of the element stopping left legs there, or `NO_STOP`.
    left_stop: Vec<u32>,
    /// Per site: the same for right legs.
    right_stop: Vec<u32>,
    /// Per site: whether a leg stands there.
    occupied: Vec<bool>,
    /// Per bound LEF: `(left, right)`.
    legs: Vec<(usize, usize)>,
    /// Per bound LEF: whether its left and right legs are captured.
    captured: Vec<[bool; 2]>,
    /// Per bound LEF: where it was loaded (left leg at `p`, right leg at `p + 1`).
    load_sites: Vec<usize>,
    /// Per bound LEF: its chain as `(start, end)`.
    bounds: Vec<(usize, usize)>,
    n_unbound: usize,
    steps: u64,
}

/// A Bernoulli draw that draws nothing when `p` is 0 or 1.
fn bernoulli<R: Rng + ?Sized>(rng: &mut R, p: f64) -> bool {
    if p >= 1.0 {
        true
    } else if p <= 0.0 {
        false
    } else {
        rng.r#gen::<f64>() < p
    }
}

impl Extruder {
    /// Check `params` and load every LEF at a random position (see the module docs; a LEF that
    /// finds no room in [`LOAD_TRIES`] draws stays unbound and retries at each step).
    pub fn new<R: Rng + ?Sized>(
        params: &ExtrusionParams,
        rng: &mut R,
    ) -> Result<Self, ExtrusionError> {
        params.check()?;
        let n_monomers = params.n_monomers();
        let n_lefs = params.n_lefs();
        let mut left_stop = vec![NO_STOP; n_monomers];
        let mut right_stop = vec![NO_STOP; n_monomers];
        let mut stops = Vec::with_capacity(params.elements.len());
        for (index, e) in params.elements.iter().enumerate() {
            // `check` bounds the number of elements below `NO_STOP`.
            let id = index as u32;
            if e.orientation.stops_left() {
                left_stop[e.position] = id;
            }
            if e.orientation.stops_right() {
                right_stop[e.position] = id;
            }
            stops.push((e.capture, e.release));
        }
        let mut ex = Self {
            chains: params.chains.clone(),
            n_monomers,
            n_lefs,
            unload_prob: 1.0 / params.lifetime(),
            stops,
            left_stop,
            right_stop,
            occupied: vec![false; n_monomers],
            legs: Vec::with_capacity(n_lefs),
            captured: Vec::with_capacity(n_lefs),
            load_sites: Vec::with_capacity(n_lefs),
            bounds: Vec::with_capacity(n_lefs),
            n_unbound: n_lefs,
            steps: 0,
        };
        ex.load_unbound(n_lefs, rng);
        Ok(ex)
    }

    /// Advance the model by one step (see the module docs for the order of events).
    pub fn step<R: Rng + ?Sized>(&mut self, rng: &mut R) {
        let retry = self.n_unbound;
        let mut i = 0;
        while i < self.legs.len() {
            if bernoulli(rng, self.unload_prob) {
                let (l, r) = self.legs[i];
                self.occupied[l] = false;
                self.occupied[r] = false;
                match self.find_load_site(rng) {
                    Some((p, chain)) => self.place(i, p, chain, rng),
                    None => {
                        self.legs.swap_remove(i);
                        self.captured.swap_remove(i);
                        self.load_sites.swap_remove(i);
                        self.bounds.swap_remove(i);
                        self.n_unbound += 1;
                        // The LEF now at `i` has not been handled yet.
                        continue;
                    }
                }
            } else {
                self.move_left(i, rng);
                self.move_right(i, rng);
            }
            i += 1;
        }
        self.load_unbound(retry, rng);
        self.steps += 1;
    }

    /// `(left, right)` of each bound LEF, `left < right`: the dynamic bonds. Indices follow
    /// a LEF while it stays bound (an unload followed by an immediate reload keeps the index; a
    /// failed reload moves the last LEF into the freed index; new loads are appended).
    pub fn legs(&self) -> &[(usize, usize)] {
        &self.legs
    }

    /// Whether the `[left, right]` legs of each bound LEF are captured, in the order of
    /// [`legs`](Self::legs).
    pub fn captured(&self) -> &[[bool; 2]] {
        &self.captured
    }

    /// Where each bound LEF was last loaded (left leg at `p`, right leg at `p + 1`), in the order
    /// of [`legs`](Self::legs).
    pub fn load_sites(&self) -> &[usize] {
        &self.load_sites
    }

    /// The polymer size `N`.
    pub fn n_monomers(&self) -> usize {
        self.n_monomers
    }

    /// The number of LEFs, bound or not.
    pub fn n_lefs(&self) -> usize {
        self.n_lefs
    }

    /// The number of LEFs waiting for room to load (usually 0).
    pub fn n_unbound(&self) -> usize {
        self.n_unbound
    }

    /// The number of steps made.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Try to load up to `count` unbound LEFs, appending those that find room.
    fn load_unbound<R: Rng + ?Sized>(&mut self, count: usize, rng: &mut R) {
        for _ in 0..count {
            if let Some((p, chain)) = self.find_load_site(rng) {
                let i = self.legs.len();
                self.legs.push((p, p + 1));
                self.captured.push([false; 2]);
                self.load_sites.push(p);
                self.bounds.push((0, 0));
                self.place(i, p, chain, rng);
                self.n_unbound -= 1;
            }
        }
    }

    /// A uniformly random `p` with `p`, `p + 1` free and on one chain, and the chain index; `None`
    /// after [`LOAD_TRIES`] failed draws.
    fn find_load_site<R: Rng + ?Sized>(&self, rng: &mut R) -> Option<(usize, usize)> {
        // `check` guarantees room for a LEF, so N >= 2.
        for _ in 0..LOAD_TRIES {
            let p = rng.gen_range(0..self.n_monomers - 1);
            if self.occupied[p] || self.occupied[p + 1] {
                continue;
            }
            let chain = self.chains.partition_point(|c| c.end <= p);
            if p + 1 < self.chains[chain].end {
                return Some((p, chain));
            }
        }
        None
    }

    /// Put LEF `i` at `(p, p + 1)` on `chain` (both sites free), checking capture on arrival.
    fn place<R: Rng + ?Sized>(&mut self, i: usize, p: usize, chain: usize, rng: &mut R) {
        self.occupied[p] = true;
        self.occupied[p + 1] = true;
        self.legs[i] = (p, p + 1);
        self.load_sites[i] = p;
        let c = &self.chains[chain];
        self.bounds[i] = (c.start, c.end);
        let left = self.arrival_capture(self.left_stop[p], rng);
        let right = self.arrival_capture(self.right_stop[p + 1], rng);
        self.captured[i] = [left, right];
    }

    /// Whether a leg arriving on a site with element `stop` (maybe `NO_STOP`) is captured.
    fn arrival_capture<R: Rng + ?Sized>(&self, stop: u32, rng: &mut R) -> bool {
        stop != NO_STOP && bernoulli(rng, self.stops[stop as usize].0)
    }

    /// Whether a leg captured by element `stop` stays captured this step.
    fn stays_captured<R: Rng + ?Sized>(&self, stop: u32, rng: &mut R) -> bool {
        debug_assert_ne!(stop, NO_STOP, "a captured leg stands on an element");
        !bernoulli(rng, self.stops[stop as usize].1)
    }

    fn move_left<R: Rng + ?Sized>(&mut self, i: usize, rng: &mut R) {
        let l = self.legs[i].0;
        if self.captured[i][0] {
            if self.stays_captured(self.left_stop[l], rng) {
                return;
            }
            self.captured[i][0] = false;
        }
        if l > self.bounds[i].0 && !self.occupied[l - 1] {
            self.occupied[l] = false;
            self.occupied[l - 1] = true;
            self.legs[i].0 = l - 1;
            self.captured[i][0] = self.arrival_capture(self.left_stop[l - 1], rng);
        }
    }

    fn move_right<R: Rng + ?Sized>(&mut self, i: usize, rng: &mut R) {
        let r = self.legs[i].1;
        if self.captured[i][1] {
            if self.stays_captured(self.right_stop[r], rng) {
                return;
            }
            self.captured[i][1] = false;
        }
        if r + 1 < self.bounds[i].1 && !self.occupied[r + 1] {
            self.occupied[r] = false;
            self.occupied[r + 1] = true;
            self.legs[i].1 = r + 1;
            self.captured[i][1] = self.arrival_capture(self.right_stop[r + 1], rng);
        }
    }
}

#[cfg(test)]
mod tests;
