//! Ensemble contact maps of conformations (polychrom's `binnedContactMap` and
//! `monomerResolutionContactMap`): the binning, the contact search, the streaming count.

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::genome::{BinTable, Chrom};
use crate::geometry::cells::{CellList, Space};
use crate::io::trajectory::{Conformation, for_each_chunk};
use crate::matrix::{ContactMatrix, CountType, MatrixBuilder};

/// The bins of chains of beads, polychrom's way (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ChainBins {
    /// The chains, `[start, end)` in beads.
    pub chains: Vec<(usize, usize)>,
    /// Beads per bin.
    pub monomers_per_bin: usize,
    /// The first bead of each bin, every chain's bins in order.
    starts: Vec<usize>,
    /// One past the last bead binned: the last chain's end plus one (polychrom's last edge).
    end: usize,
}

impl ChainBins {
    /// The bins of `chains` (`[start, end)` each, in order, not overlapping) of
    /// `monomers_per_bin` beads.
    ///
    /// ```
    /// use contactmap::conformations::ChainBins;
    /// let bins = ChainBins::new(&[(0, 10), (10, 15)], 4)?;
    /// assert_eq!(bins.n_bins(), 3 + 2);
    /// assert_eq!((bins.bin_of(3), bins.bin_of(4), bins.bin_of(9), bins.bin_of(10)), (Some(0), Some(1), Some(2), Some(3)));
    /// assert_eq!((bins.bin_of(15), bins.bin_of(16)), (Some(4), None)); // polychrom's last edge: end + 1
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn new(chains: &[(usize, usize)], monomers_per_bin: usize) -> Result<ChainBins> {
        if monomers_per_bin == 0 {
            return Err(Error::parameter("monomers-per-bin", 0, "1 or more"));
        }
        if chains.is_empty() {
            return Err(Error::parameter("chains", "(none)", "at least one chain"));
        }
        let mut starts = Vec::new();
        let mut previous_end = 0;
        for (k, &(start, end)) in chains.iter().enumerate() {
            if end <= start || (k > 0 && start < previous_end) {
                return Err(Error::parameter(
                    "chains",
                    format!("{start}-{end}"),
                    "chains [start, end) in order, each at least one bead, not overlapping",
                ));
            }
            starts.extend((start..end).step_by(monomers_per_bin));
            previous_end = end;
        }
        Ok(ChainBins {
            chains: chains.to_vec(),
            monomers_per_bin,
            starts,
            end: previous_end + 1,
        })
    }

    /// The number of bins.
    pub fn n_bins(&self) -> usize {
        self.starts.len()
    }

    /// The bins of each chain.
    pub fn bins_per_chain(&self) -> Vec<usize> {
        self.chains
            .iter()
            .map(|&(start, end)| (end - start).div_ceil(self.monomers_per_bin))
            .collect()
    }

    /// The bin of bead `bead`, or `None` before the first chain or past the last edge.
    pub fn bin_of(&self, bead: usize) -> Option<usize> {
        if bead >= self.end {
            return None;
        }
        self.starts.partition_point(|&s| s <= bead).checked_sub(1)
    }

    /// Each bead's bin for conformations of `n_beads` beads (`u32::MAX` outside every bin).
    fn lookup(&self, n_beads: usize) -> Vec<u32> {
        (0..n_beads)
            .map(|b| self.bin_of(b).map_or(u32::MAX, |b| b as u32))
            .collect()
    }
}

/// The contacts of one conformation: the pairs `(i, j)`, `i < j`, of beads at most `radius`
/// apart, sorted. `cells` is a cell list to reuse.
///
/// ```
/// use contactmap::conformations::contact_pairs;
/// use contactmap::geometry::cells::CellList;
/// let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0], [4.5, 0.0, 0.0]];
/// let mut cells = CellList::new();
/// // distance exactly 1.5 counts (at most the radius), as scipy's query_pairs
/// assert_eq!(contact_pairs(&points, 1.5, &mut cells), vec![(0, 1), (2, 3)]);
/// ```
pub fn contact_pairs(positions: &[[f64; 3]], radius: f64, cells: &mut CellList) -> Vec<(u32, u32)> {
    let mut pairs = Vec::new();
    for_each_contact(positions, radius, cells, |i, j| pairs.push((i, j)));
    pairs.sort_unstable();
    pairs
}

/// [`contact_pairs`] without the sort: `visit(i, j)`, `i < j`, once per contact, in the cell
/// list's order.
pub fn for_each_contact(
    positions: &[[f64; 3]],
    radius: f64,
    cells: &mut CellList,
    visit: impl FnMut(u32, u32),
) {
    sort_into_cells(positions, radius, cells);
    visit_contacts(radius, cells, visit);
}

/// The cell list of [`for_each_contact`] (built in parallel for many beads).
fn sort_into_cells(positions: &[[f64; 3]], radius: f64, cells: &mut CellList) {
    // the list finds pairs strictly closer than its cutoff: one ulp wider, then `<=` radius
    cells.build_with_density(positions, radius.next_up(), Space::Open, CELLS_PER_POINT);
}

/// The contacts of a list built by [`sort_into_cells`] (on this thread alone).
fn visit_contacts(radius: f64, cells: &mut CellList, mut visit: impl FnMut(u32, u32)) {
    let r2 = radius * radius;
    cells.for_each_point_pair(|i, j, d2| {
        if d2 <= r2 {
            visit(i.min(j), i.max(j));
        }
    });
}

/// The grid density of the contact search: conformations are sparse in their bounding box
/// (`polymer-map` of 1,000 random walks of 10,000 beads, contact radius 1.7, one thread: 2.28 s
/// at 6 cells per point, the simulator's density; 2.08 s at 16; no faster beyond).
const CELLS_PER_POINT: f64 = 16.0;

/// Chains `[start, end)` of consecutive lengths, from bead 0 (`--chains 90,60`: `(0, 90)`,
/// `(90, 150)`).
///
/// ```
/// use contactmap::conformations::chains_of_lengths;
/// assert_eq!(chains_of_lengths(&[90, 60]), vec![(0, 90), (90, 150)]);
/// ```
pub fn chains_of_lengths(lengths: &[usize]) -> Vec<(usize, usize)> {
    let mut start = 0;
    lengths
        .iter()
        .map(|&n| {
            let chain = (start, start + n);
            start += n;
            chain
        })
        .collect()
}

/// The parameters of an ensemble contact map.
#[derive(Clone, Debug, PartialEq)]
pub struct MapParams {
    /// Beads at most this far apart are in contact (the positions' units).
    pub contact_radius: f64,
    /// Beads per bin: 1 for a monomer-resolution map.
    pub monomers_per_bin: usize,
    /// The chains, `[start, end)` in beads; `None`: one chain of every bead.
    pub chains: Option<Vec<(usize, usize)>>,
}

/// The contact map of a set of conformations.
#[derive(Clone, Debug, PartialEq)]
pub struct EnsembleMap {
    /// Beads per conformation.
    pub n_beads: usize,
    /// The bins.
    pub bins: ChainBins,
    /// `(bin1, bin2, contacts)`, `bin1 <= bin2`, sorted, non-zero.
    pub pixels: Vec<(u32, u32, u64)>,
    /// Conformations counted.
    pub n_conformations: usize,
}

impl EnsembleMap {
    /// The map as a contact matrix of integer counts: one chromosome per chain (`chr1..chrK`,
    /// its beads times `monomer_bp` long), bins of `monomers_per_bin` beads.
    pub fn matrix(&self, monomer_bp: u64) -> Result<ContactMatrix> {
        let chroms: Vec<Chrom> = self
            .bins
            .chains
            .iter()
            .enumerate()
            .map(|(k, &(start, end))| {
                Chrom::new(format!("chr{}", k + 1), (end - start) as u64 * monomer_bp)
            })
            .collect();
        let bins = BinTable::fixed(chroms, self.bins.monomers_per_bin as u64 * monomer_bp)?;
        let mut builder = MatrixBuilder::new(bins, CountType::Integer);
        for &(a, b, count) in &self.pixels {
            builder.push(u64::from(a), u64::from(b), count as f64)?;
        }
        Ok(builder.build())
    }
}

/// Conformations whose contacts are found at once (per thread).
const CHUNK_PER_THREAD: usize = 4;

/// Maps of at most this many bin pairs (a triangle of 2,048 bins) are counted in dense
/// triangles; larger ones as sorted keys.
const DENSE_MAX: usize = triangle_len(DENSE_MAX_SIDE);

/// The bins of the largest dense triangle.
const DENSE_MAX_SIDE: usize = 2048;

/// Dense triangles are held one per thread while they take at most this many bytes together
/// (one shared triangle of atomic counters beyond).
const PER_THREAD_BYTES: usize = 256 << 20;

/// The bin pairs `(a, b)`, `a <= b`, of `n` bins.
const fn triangle_len(n: usize) -> usize {
    n * (n + 1) / 2
}

/// The index of bin pair `(a, b)`, `a <= b`, in the row-major upper triangle of `n` bins
/// (polychrom's `indexing`).
fn triangle_index(a: u32, b: u32, n: usize) -> usize {
    let (a, b) = (a as usize, b as usize);
    a * n - a * (a.saturating_sub(1)) / 2 - a + b
}

/// The contacts of a map of `n_bins` bins, added up.
struct Tally {
    n_bins: usize,
    counts: Counts,
}

/// How [`Tally`] adds the contacts up.
enum Counts {
    /// Triangles of counts, one per thread at work (a pool: a conformation takes one and gives
    /// it back), summed at the end: no atomic operation per contact (they cost a sixth of the
    /// time of a map of 10,000 beads, and more across cores contending for the same bins).
    PerThread(std::sync::Mutex<Vec<Vec<u64>>>),
    /// One triangle of atomic counters, shared by the threads.
    Shared(Vec<AtomicU64>),
    /// Sorted `(key, count)`, `key = bin1 * n_bins + bin2`, merged chunk by chunk.
    Keys(Vec<(u64, u64)>),
}

impl Tally {
    /// The tally of a map of `n_bins` bins: per thread while the triangles take at most
    /// `per_thread_bytes`.
    fn new(n_bins: usize, per_thread_bytes: usize) -> Tally {
        let triangle = triangle_len(n_bins);
        let per_thread = triangle * std::mem::size_of::<u64>() * rayon::current_num_threads();
        let counts = if triangle > DENSE_MAX {
            Counts::Keys(Vec::new())
        } else if per_thread <= per_thread_bytes {
            Counts::PerThread(std::sync::Mutex::new(Vec::new()))
        } else {
            Counts::Shared((0..triangle).map(|_| AtomicU64::new(0)).collect())
        };
        Tally { n_bins, counts }
    }

    /// Add the contacts of `chunk` (at most `radius` apart; `bead_bin`: each bead's bin, or
    /// `u32::MAX`), in parallel.
    fn add_chunk(&mut self, chunk: &[Conformation], radius: f64, bead_bin: &[u32]) {
        // `add(bin1, bin2)`, `bin1 <= bin2`, once per contact of a binned bead pair, in a list
        // built by `sort_into_cells`
        fn contacts(
            cells: &mut CellList,
            radius: f64,
            bead_bin: &[u32],
            mut add: impl FnMut(u32, u32),
        ) {
            visit_contacts(radius, cells, |i, j| {
                let (a, b) = (bead_bin[i as usize], bead_bin[j as usize]);
                if a != u32::MAX && b != u32::MAX {
                    add(a.min(b), a.max(b));
                }
            });
        }
        let (n_bins, triangle) = (self.n_bins, triangle_len(self.n_bins));
        match &mut self.counts {
            Counts::PerThread(pool) => {
                let pool = &*pool;
                let lock = || {
                    pool.lock()
                        .unwrap_or_else(std::sync::PoisonError::into_inner)
                };
                chunk.par_iter().for_each_init(CellList::new, |cells, c| {
                    // the build may run in parallel, and this thread take up another
                    // conformation meanwhile: a triangle is taken once the list is built, so a
                    // thread holds one at a time
                    sort_into_cells(&c.positions, radius, cells);
                    let mut counts = lock().pop().unwrap_or_else(|| vec![0; triangle]);
                    contacts(cells, radius, bead_bin, |a, b| {
                        counts[triangle_index(a, b, n_bins)] += 1
                    });
                    lock().push(counts);
                });
            }
            Counts::Shared(total) => {
                chunk.par_iter().for_each_init(CellList::new, |cells, c| {
                    sort_into_cells(&c.positions, radius, cells);
                    contacts(cells, radius, bead_bin, |a, b| {
                        total[triangle_index(a, b, n_bins)].fetch_add(1, Ordering::Relaxed);
                    });
                });
            }
            Counts::Keys(counts) => {
                let n = n_bins as u64;
                let mut keys: Vec<u64> = chunk
                    .par_iter()
                    .map_init(CellList::new, |cells, c| {
                        let mut keys = Vec::new();
                        sort_into_cells(&c.positions, radius, cells);
                        contacts(cells, radius, bead_bin, |a, b| {
                            keys.push(u64::from(a) * n + u64::from(b))
                        });
                        keys
                    })
                    .flatten_iter()
                    .collect();
                keys.par_sort_unstable();
                *counts = merge_counts(counts, &run_lengths(&keys));
            }
        }
    }

    /// The non-zero pixels `(bin1, bin2, count)`, sorted.
    fn pixels(self) -> Vec<(u32, u32, u64)> {
        let (n_bins, triangle) = (self.n_bins, triangle_len(self.n_bins));
        let dense = |counts: Vec<u64>| -> Vec<(u32, u32, u64)> {
            (0..n_bins)
                .flat_map(|a| (a..n_bins).map(move |b| (a as u32, b as u32)))
                .zip(counts)
                .filter(|&(_, count)| count > 0)
                .map(|((a, b), count)| (a, b, count))
                .collect()
        };
        match self.counts {
            Counts::PerThread(pool) => {
                let triangles = pool.into_inner().unwrap_or_else(|e| e.into_inner());
                let mut total = vec![0u64; triangle];
                for counts in triangles {
                    total.par_iter_mut().zip(counts).for_each(|(t, c)| *t += c);
                }
                dense(total)
            }
            Counts::Shared(total) => dense(total.into_iter().map(AtomicU64::into_inner).collect()),
            Counts::Keys(counts) => {
                let n = n_bins as u64;
                counts
                    .into_iter()
                    .map(|(key, count)| ((key / n) as u32, (key % n) as u32, count))
                    .collect()
            }
        }
    }
}

/// Count the contacts of `conformations` (read a chunk at a time, each chunk's conformations
/// in parallel) into the map of `params`; `progress` is told the number of conformations done.
/// Every conformation must have the beads of the first; the first error of the stream ends the
/// count.
pub fn contact_map(
    conformations: impl Iterator<Item = Result<Conformation>>,
    params: &MapParams,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<EnsembleMap> {
    super::beads::check_radius(params.contact_radius)?;
    let chunk_size = CHUNK_PER_THREAD * rayon::current_num_threads();
    let mut conformations = conformations.peekable();
    let n_beads = super::beads::first_beads(&mut conformations)?;
    let chains = params.chains.clone().unwrap_or_else(|| vec![(0, n_beads)]);
    if let Some(&(_, end)) = chains.last() {
        if end > n_beads {
            let lengths: Vec<String> = chains.iter().map(|(a, b)| (b - a).to_string()).collect();
            return Err(Error::parameter(
                "chains",
                lengths.join(","),
                format!(
                    "chain lengths adding up to at most the conformations' {n_beads} beads \
                     (these add up to {end})"
                ),
            ));
        }
    }
    let bins = ChainBins::new(&chains, params.monomers_per_bin)?;
    let bead_bin = bins.lookup(n_beads);
    let n_bins = bins.n_bins();
    let mut tally = Tally::new(n_bins, PER_THREAD_BYTES);
    // each chunk's contacts are counted on the pool while this thread reads the next chunk
    let mut done = 0;
    for_each_chunk(
        &mut conformations,
        chunk_size,
        |_, c| super::beads::same_beads(c, n_beads),
        |chunk| {
            tally.add_chunk(chunk, params.contact_radius, &bead_bin);
            done += chunk.len();
            progress(done);
        },
    )?;
    Ok(EnsembleMap {
        n_beads,
        pixels: tally.pixels(),
        bins,
        n_conformations: done,
    })
}

/// `(key, occurrences)` of sorted keys.
fn run_lengths(keys: &[u64]) -> Vec<(u64, u64)> {
    let mut runs: Vec<(u64, u64)> = Vec::new();
    for &key in keys {
        match runs.last_mut() {
            Some((last, count)) if *last == key => *count += 1,
            _ => runs.push((key, 1)),
        }
    }
    runs
}

/// The sum of two sorted `(key, count)` lists.
fn merge_counts(a: &[(u64, u64)], b: &[(u64, u64)]) -> Vec<(u64, u64)> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].0.cmp(&b[j].0) {
            std::cmp::Ordering::Less => {
                out.push(a[i]);
                i += 1;
            }
            std::cmp::Ordering::Greater => {
                out.push(b[j]);
                j += 1;
            }
            std::cmp::Ordering::Equal => {
                out.push((a[i].0, a[i].1 + b[j].1));
                i += 1;
                j += 1;
            }
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// All pairs by hand against the cell list, on random points (ties included: a lattice).
    #[test]
    fn contact_pairs_are_every_pair_within_the_radius() {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(3);
        let mut points: Vec<[f64; 3]> = (0..400)
            .map(|_| {
                [
                    rng.r#gen::<f64>() * 8.0,
                    rng.r#gen::<f64>() * 8.0,
                    rng.r#gen::<f64>() * 8.0,
                ]
            })
            .collect();
        // a lattice: distances exactly 1.0 and sqrt(2)
        for x in 0..4 {
            for y in 0..4 {
                points.push([20.0 + x as f64, 20.0 + y as f64, 0.0]);
            }
        }
        for radius in [0.5, 1.0, 1.7] {
            let mut want = Vec::new();
            for i in 0..points.len() {
                for j in i + 1..points.len() {
                    let d: f64 = (0..3).map(|k| (points[i][k] - points[j][k]).powi(2)).sum();
                    if d <= radius * radius {
                        want.push((i as u32, j as u32));
                    }
                }
            }
            let got = contact_pairs(&points, radius, &mut CellList::new());
            assert_eq!(got, want, "radius {radius}");
        }
    }

    /// `count` conformations `c0, c1 ...` of `n` beads uniform in a cube of side `side`.
    fn cloud(
        rng: &mut rand_xoshiro::Xoshiro256PlusPlus,
        count: usize,
        n: usize,
        side: f64,
    ) -> Vec<Conformation> {
        (0..count)
            .map(|k| Conformation {
                label: format!("c{k}"),
                cell: None,
                unit: crate::io::trajectory::LengthUnit::Model,
                positions: (0..n)
                    .map(|_| [0; 3].map(|_| rng.r#gen::<f64>() * side))
                    .collect(),
            })
            .collect()
    }

    /// The binned map of random conformations equals a naive count with polychrom's binning.
    #[test]
    fn the_map_is_the_naive_binned_count() {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(5);
        let n = 57;
        let conformations = cloud(&mut rng, 9, n, 4.0);
        let chains = vec![(0, 20), (25, 56)];
        let params = MapParams {
            contact_radius: 1.2,
            monomers_per_bin: 3,
            chains: Some(chains.clone()),
        };
        let map = contact_map(conformations.clone().into_iter().map(Ok), &params, &|_| {}).unwrap();
        // naive: polychrom's edges (chain starts every 3 beads, last edge 57), searchsorted
        let mut edges: Vec<f64> = Vec::new();
        for &(s, e) in &chains {
            let mut b = s;
            while b < e {
                edges.push(b as f64 - 0.5);
                b += 3;
            }
        }
        edges.push(56.0 + 1.0 - 0.5);
        let bin = |m: usize| edges.iter().filter(|&&e| e < m as f64).count() - 1;
        let nb = edges.len() - 1;
        let mut want = vec![0u64; nb * nb];
        for c in &conformations {
            for i in 0..n {
                for j in i + 1..n {
                    let d: f64 = (0..3)
                        .map(|k| (c.positions[i][k] - c.positions[j][k]).powi(2))
                        .sum();
                    if d <= 1.2 * 1.2 && i < 57 && j < 57 {
                        want[bin(i) * nb + bin(j)] += 1;
                    }
                }
            }
        }
        let want: Vec<(u32, u32, u64)> = (0..nb)
            .flat_map(|a| (a..nb).map(move |b| (a, b)))
            .filter(|&(a, b)| want[a * nb + b] > 0)
            .map(|(a, b)| (a as u32, b as u32, want[a * nb + b]))
            .collect();
        assert_eq!(map.pixels, want);
        assert_eq!((map.n_conformations, map.bins.n_bins()), (9, nb));
        // a conformation with another number of beads is an error naming it
        let mut bad = conformations;
        bad[4].positions.pop();
        let err = contact_map(bad.into_iter().map(Ok), &params, &|_| {}).unwrap_err();
        assert!(err.to_string().contains("c4: 56 beads"), "{err}");
    }

    /// The three tallies (per-thread triangles, one shared atomic triangle, sorted keys) add
    /// up the same pixels, on 1 and 3 threads; conformations of 4,200 beads (cell lists built
    /// in parallel: a thread may take up another conformation meanwhile) leave at most one
    /// per-thread triangle per thread.
    #[test]
    fn every_tally_counts_the_same() {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(11);
        let n = 4200;
        let conformations = cloud(&mut rng, 20, n, 20.0);
        let bins = ChainBins::new(&[(0, n)], 70).unwrap();
        let (n_bins, bead_bin) = (bins.n_bins(), bins.lookup(n));
        let tally = |tally: Tally, threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut tally = tally;
                for chunk in conformations.chunks(6) {
                    tally.add_chunk(chunk, 1.1, &bead_bin);
                }
                if let Counts::PerThread(pool) = &tally.counts {
                    assert!(pool.lock().unwrap().len() <= threads);
                }
                tally.pixels()
            })
        };
        let per_thread = Tally::new(n_bins, usize::MAX);
        assert!(matches!(per_thread.counts, Counts::PerThread(_)));
        let want = tally(per_thread, 1);
        assert!(want.iter().map(|p| p.2).sum::<u64>() > 1000);
        for threads in [1, 3] {
            let shared = Tally::new(n_bins, 0);
            assert!(matches!(shared.counts, Counts::Shared(_)));
            assert_eq!(tally(shared, threads), want);
            let keys = Tally {
                n_bins,
                counts: Counts::Keys(Vec::new()),
            };
            assert_eq!(tally(keys, threads), want);
            assert_eq!(tally(Tally::new(n_bins, usize::MAX), threads), want);
        }
    }

    /// A map of more bins than the dense triangle takes (counted as sorted keys) equals the
    /// naive count too.
    #[test]
    fn a_large_map_is_the_naive_count() {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(8);
        let n = DENSE_MAX_SIDE + 300;
        let walk = |rng: &mut rand_xoshiro::Xoshiro256PlusPlus| {
            let mut p = [0.0f64; 3];
            (0..n)
                .map(|_| {
                    for x in &mut p {
                        *x += rng.r#gen::<f64>() - 0.5;
                    }
                    p
                })
                .collect::<Vec<_>>()
        };
        let conformations: Vec<Conformation> = (0..3)
            .map(|k| Conformation {
                label: format!("w{k}"),
                cell: None,
                unit: crate::io::trajectory::LengthUnit::Model,
                positions: walk(&mut rng),
            })
            .collect();
        let params = MapParams {
            contact_radius: 0.9,
            monomers_per_bin: 1,
            chains: None,
        };
        let map = contact_map(conformations.clone().into_iter().map(Ok), &params, &|_| {}).unwrap();
        let mut want = std::collections::BTreeMap::new();
        for c in &conformations {
            for (i, j) in contact_pairs(&c.positions, 0.9, &mut CellList::new()) {
                *want.entry((i, j)).or_insert(0u64) += 1;
            }
        }
        let want: Vec<(u32, u32, u64)> = want.into_iter().map(|((i, j), c)| (i, j, c)).collect();
        assert_eq!(map.bins.n_bins(), n);
        assert_eq!(map.pixels, want);
    }
}
