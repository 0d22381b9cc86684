//! The contacts of a frame with a periodic cell by a cell list under the minimum image: only
//! the atom pairs that can be in contact are measured, by MDTraj's formula.
//!
//! The measured atoms are wrapped into the cell in fractional coordinates and binned on a grid
//! of `n_k` slabs along each cell vector, `n_k = floor(d_k / reach)`, `d_k` the spacing of the
//! lattice planes the other two vectors span (the volume over the area of their parallelogram)
//! and `reach` the cutoff with a margin. Two atoms whose true minimum-image distance is within
//! `reach` are then at most one slab apart along each axis (their fractional coordinates differ
//! by at most `reach / d_k`), so the pairs of atoms in neighbouring bins (periodic, with the
//! shift of the cell vectors a bin wrapped across) hold every such pair, once each when every
//! axis has three bins or more (no two images of an atom are then both within reach of
//! another); with fewer, [`Periodic::count`] declines and the caller measures all pairs.
//!
//! The distance across neighbouring bins, from the wrapped coordinates, is the true
//! minimum-image distance whenever that is within reach, and the pairs farther than the cutoff
//! (with the margin) are dropped. The others that join two residues of a pair not yet in
//! contact in the frame are measured by MDTraj's formula ([`super::distance::boxed_below`],
//! [`super::distance::triclinic_below`]), so that the counts are MDTraj's: a pair dropped
//! cannot be in contact by MDTraj's measure either, MDTraj's distance being the length of a
//! lattice translate of the displacement (never below the minimum image) up to the rounding of
//! single precision, which the margin covers: `1e-3 nm + 1e-5 x` (the largest coordinate and the
//! cell vectors' lengths) `x (1 + the sum of the vectors' lengths over their plane spacings)`,
//! some hundreds of roundings of the numbers MDTraj adds.

use super::distance::{Displacements, boxed_below, triclinic_below};
use super::frame::{Cell, Frame};

/// The index of the residue pair `(i, j)`, `i < j`, among the pairs, in constant time.
#[derive(Clone, Debug)]
struct PairIndex {
    /// Each residue's rank among the residues of some pair (`u32::MAX`: in none).
    rank: Vec<u32>,
    /// For each residue `i`: the ranks `lo..=hi` of its partners `j`, and `offset`: the index
    /// of the pair `(i, j)` is `offset + rank[j]`.
    rows: Vec<Row>,
    /// The pairs, sorted, with their indices, when some residue's partners are not every
    /// residue of a range of ranks (searched instead).
    sorted: Option<Vec<((u32, u32), u32)>>,
}

#[derive(Clone, Copy, Debug)]
struct Row {
    lo: u32,
    hi: u32,
    offset: i64,
}

impl PairIndex {
    fn new(pairs: &[(usize, usize)], residues: usize) -> PairIndex {
        let mut rank = vec![u32::MAX; residues];
        let mut member = vec![false; residues];
        for &(i, j) in pairs {
            member[i] = true;
            member[j] = true;
        }
        let members = member.iter().enumerate().filter(|&(_, &m)| m);
        for (next, (r, _)) in members.enumerate() {
            rank[r] = next as u32;
        }
        let empty = Row {
            lo: 1,
            hi: 0,
            offset: 0,
        };
        let mut rows = vec![empty; residues];
        let mut runs = true;
        let mut first = 0;
        while first < pairs.len() && runs {
            let i = pairs[first].0;
            let mut last = first;
            while last + 1 < pairs.len() && pairs[last + 1].0 == i {
                last += 1;
            }
            let (lo, hi) = (rank[pairs[first].1], rank[pairs[last].1]);
            let ascending = pairs[first..=last].windows(2).all(|w| w[0].1 < w[1].1);
            let seen = rows[i].lo <= rows[i].hi;
            runs = ascending && !seen && (hi - lo) as usize == last - first;
            rows[i] = Row {
                lo,
                hi,
                offset: first as i64 - i64::from(lo),
            };
            first = last + 1;
        }
        let sorted = (!runs).then(|| {
            let mut sorted: Vec<((u32, u32), u32)> = pairs
                .iter()
                .enumerate()
                .map(|(k, &(i, j))| ((i as u32, j as u32), k as u32))
                .collect();
            sorted.sort_unstable();
            sorted
        });
        PairIndex { rank, rows, sorted }
    }

    /// The index of the pair `(i, j)` (`i < j`), if it is one.
    #[inline(always)]
    fn get(&self, i: u32, j: u32) -> Option<usize> {
        if let Some(sorted) = &self.sorted {
            let k = sorted.binary_search_by_key(&(i, j), |&(p, _)| p).ok()?;
            return Some(sorted[k].1 as usize);
        }
        let row = self.rows[i as usize];
        let r = self.rank[j as usize];
        (row.lo <= r && r <= row.hi).then(|| (row.offset + i64::from(r)) as usize)
    }
}

/// What the cell list needs of the pairs: their index and each measured atom's residue.
#[derive(Clone, Debug)]
pub(super) struct Periodic {
    index: PairIndex,
    /// The residue of each measured atom (`u32::MAX`: none).
    owner: Vec<u32>,
    /// The cutoff, in nm.
    cutoff: f32,
    /// [`super::distance::sqrt_threshold`] of the cutoff.
    below: f32,
}

/// Candidates measured at a time.
const BATCH: usize = 512;

/// One thread's buffers, kept from frame to frame.
#[derive(Debug, Default)]
pub(super) struct Workspace {
    bins: Bins,
    near: Near,
    batch: Batch,
}

/// The atoms of a frame by bin.
#[derive(Debug, Default)]
struct Bins {
    /// Each atom's bin and wrapped position.
    bin: Vec<u32>,
    wrapped: Vec<[f32; 3]>,
    /// Each bin's first atom below (prefix sums: one more than the bins).
    start: Vec<u32>,
    /// The atoms by bin: wrapped position, atom and residue.
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    atom: Vec<u32>,
    residue: Vec<u32>,
}

/// The atoms a bin's atoms are paired with: its own, then those of the bins ahead of it in the
/// half shell, moved next to it.
#[derive(Debug, Default)]
struct Near {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    /// Their indices in [`Bins`].
    index: Vec<u32>,
    /// The squared distances from one of them to those after it, and the indices of those
    /// within reach.
    d2: Vec<f32>,
    close: Vec<u32>,
}

impl Near {
    fn clear(&mut self) {
        self.x.clear();
        self.y.clear();
        self.z.clear();
        self.index.clear();
    }

    /// Adds the atoms `range` of `bins`, moved by `shift`.
    fn extend(&mut self, bins: &Bins, range: std::ops::Range<usize>, shift: [f32; 3]) {
        self.x
            .extend(bins.x[range.clone()].iter().map(|x| x + shift[0]));
        self.y
            .extend(bins.y[range.clone()].iter().map(|y| y + shift[1]));
        self.z
            .extend(bins.z[range.clone()].iter().map(|z| z + shift[2]));
        self.index.extend(range.map(|q| q as u32));
    }

    /// Puts into `close` the atoms after atom `i` whose squared distance from it is at most
    /// `limit`; their number.
    fn within(&mut self, i: usize, limit: f32) -> usize {
        let (px, py, pz) = (self.x[i], self.y[i], self.z[i]);
        // the squared distances (in vector instructions), then the atoms within reach kept
        // without a branch: each written, kept by moving on
        self.d2.clear();
        let after = self.x[i + 1..]
            .iter()
            .zip(&self.y[i + 1..])
            .zip(&self.z[i + 1..]);
        self.d2.extend(after.map(|((&x, &y), &z)| {
            let (dx, dy, dz) = (x - px, y - py, z - pz);
            dx * dx + dy * dy + dz * dz
        }));
        self.close.resize(self.d2.len(), 0);
        let mut m = 0;
        for (q, &d2) in (i as u32 + 1..).zip(&self.d2) {
            self.close[m] = q;
            m += usize::from(d2 <= limit);
        }
        m
    }
}

/// Candidate pairs waiting to be measured, and the frame each pair was last found in contact.
#[derive(Debug, Default)]
struct Batch {
    /// The frame each pair was last found in contact (its number in this workspace).
    stamp: Vec<u32>,
    frame: u32,
    /// The candidates' displacements, pairs, and whether each is in contact.
    r: Displacements,
    pair: Vec<u32>,
    hit: Vec<bool>,
}

impl Batch {
    /// Starts a frame.
    fn next_frame(&mut self) {
        self.frame = self.frame.wrapping_add(1);
        if self.frame == u32::MAX {
            self.stamp.fill(u32::MAX);
            self.frame = 0;
        }
    }
}

/// The bins a bin's pairs are taken with: itself and half of its 26 neighbours (the other
/// half take it).
const HALF_SHELL: [[i32; 3]; 14] = [
    [0, 0, 0],
    [0, 0, 1],
    [0, 1, -1],
    [0, 1, 0],
    [0, 1, 1],
    [1, -1, -1],
    [1, -1, 0],
    [1, -1, 1],
    [1, 0, -1],
    [1, 0, 0],
    [1, 0, 1],
    [1, 1, -1],
    [1, 1, 0],
    [1, 1, 1],
];

impl Periodic {
    /// For the residue pairs `pairs`, residue `r` measured by the atoms `residue_atoms[r]`,
    /// which index the frames' measured atoms (`atoms` of them), and a cutoff (nm).
    pub(super) fn new(
        pairs: &[(usize, usize)],
        residue_atoms: &[Vec<u32>],
        atoms: usize,
        cutoff: f32,
    ) -> Periodic {
        let mut owner = vec![u32::MAX; atoms];
        for (r, list) in residue_atoms.iter().enumerate() {
            for &a in list {
                owner[a as usize] = r as u32;
            }
        }
        Periodic {
            index: PairIndex::new(pairs, residue_atoms.len()),
            owner,
            cutoff,
            below: super::distance::sqrt_threshold(cutoff),
        }
    }

    /// A workspace for `pairs` pairs.
    pub(super) fn workspace(&self, pairs: usize) -> Workspace {
        Workspace {
            batch: Batch {
                stamp: vec![u32::MAX; pairs],
                ..Batch::default()
            },
            ..Workspace::default()
        }
    }

    /// Adds to `counts` the pairs in contact in `frame`, which has a periodic cell; `false`
    /// (nothing counted) when the cell list does not apply: no cell, a cell under three bins
    /// across (or not a cell MDTraj reduces), or a coordinate not finite.
    pub(super) fn count(&self, frame: &Frame, ws: &mut Workspace, counts: &mut [u32]) -> bool {
        let vectors = match &frame.cell {
            Some(Cell::Box(e)) => [[e[0], 0.0, 0.0], [0.0, e[1], 0.0], [0.0, 0.0, e[2]]],
            Some(Cell::Triclinic(v, recip)) if recip.iter().all(|r| r.is_finite()) => *v,
            _ => return false,
        };
        let Some(grid) = Grid::new(&vectors, &frame.xyz, self.cutoff) else {
            return false;
        };
        let Workspace { bins, near, batch } = ws;
        if !grid.bin(&frame.xyz, bins) {
            return false;
        }
        for (o, owner) in bins.atom.iter().zip(bins.residue.iter_mut()) {
            *owner = self.owner[*o as usize];
        }
        batch.next_frame();
        let [n0, n1, n2] = grid.n;
        // the shift of the cell vectors for each wrap (-1, 0, 1 per axis)
        let mut shifts = [[0.0f32; 3]; 27];
        for (k, shift) in shifts.iter_mut().enumerate() {
            let w = [k / 9, k / 3 % 3, k % 3].map(|w| w as f64 - 1.0);
            *shift = [0, 1, 2].map(|d| (0..3).map(|a| w[a] * grid.h[a][d]).sum::<f64>() as f32);
        }
        let wrap = |c: usize, o: i32, n: usize| -> (usize, usize) {
            match c as i64 + i64::from(o) {
                -1 => (n - 1, 0),
                b if b as usize == n => (0, 2),
                b => (b as usize, 1),
            }
        };
        let range = |b: usize| bins.start[b] as usize..bins.start[b + 1] as usize;
        for c0 in 0..n0 {
            for c1 in 0..n1 {
                for c2 in 0..n2 {
                    let own = range((c0 * n1 + c1) * n2 + c2);
                    if own.is_empty() {
                        continue;
                    }
                    // the bin's atoms, then the others' images next to it (itself first)
                    near.clear();
                    for o in &HALF_SHELL {
                        let (b0, w0) = wrap(c0, o[0], n0);
                        let (b1, w1) = wrap(c1, o[1], n1);
                        let (b2, w2) = wrap(c2, o[2], n2);
                        let shift = shifts[w0 * 9 + w1 * 3 + w2];
                        near.extend(bins, range((b0 * n1 + b1) * n2 + b2), shift);
                    }
                    for (i, p) in own.enumerate() {
                        let m = near.within(i, grid.limit);
                        for &q in &near.close[..m] {
                            let q = near.index[q as usize] as usize;
                            self.candidate(frame, bins, batch, counts, p, q);
                        }
                    }
                }
            }
        }
        self.flush(frame, batch, counts);
        true
    }

    /// Queues the atoms `p` and `q` (by bin) for measuring if they join the residues of a pair
    /// not yet in contact in the frame.
    #[inline(always)]
    fn candidate(
        &self,
        frame: &Frame,
        bins: &Bins,
        batch: &mut Batch,
        counts: &mut [u32],
        p: usize,
        q: usize,
    ) {
        let (ri, rj) = (bins.residue[p], bins.residue[q]);
        if ri == rj || ri == u32::MAX || rj == u32::MAX {
            return;
        }
        let Some(k) = self.index.get(ri.min(rj), ri.max(rj)) else {
            return;
        };
        if batch.stamp[k] == batch.frame {
            return;
        }
        batch.r.push(&frame.xyz, bins.atom[p], bins.atom[q]);
        batch.pair.push(k as u32);
        if batch.pair.len() == BATCH {
            self.flush(frame, batch, counts);
        }
    }

    /// Measures the batch and counts its pairs in contact.
    fn flush(&self, frame: &Frame, batch: &mut Batch, counts: &mut [u32]) {
        match &frame.cell {
            Some(Cell::Box(e)) => boxed_below(&batch.r, e, self.below, &mut batch.hit),
            Some(Cell::Triclinic(v, recip)) => {
                triclinic_below(&batch.r, v, recip, self.below, &mut batch.hit)
            }
            None => unreachable!("the cell list measures periodic frames"),
        }
        for (&k, &hit) in batch.pair.iter().zip(&batch.hit) {
            let k = k as usize;
            if hit && batch.stamp[k] != batch.frame {
                batch.stamp[k] = batch.frame;
                counts[k] += 1;
            }
        }
        batch.r.clear();
        batch.pair.clear();
    }
}

/// The bins of a frame's cell.
struct Grid {
    /// The cell vectors (rows), and the inverse of their matrix.
    h: [[f64; 3]; 3],
    inverse: [[f64; 3]; 3],
    /// Bins along each vector.
    n: [usize; 3],
    /// Squared distance across neighbouring bins beyond which a pair is dropped.
    limit: f32,
}

impl Grid {
    /// The grid of the cell `vectors` for the atoms `xyz` and the cutoff (nm); `None` when an
    /// axis would have fewer than three bins.
    fn new(vectors: &[[f32; 3]; 3], xyz: &[[f32; 3]], cutoff: f32) -> Option<Grid> {
        let h = vectors.map(|row| row.map(f64::from));
        let cross = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let norm = |a: [f64; 3]| dot(a, a).sqrt();
        let det = dot(h[0], cross(h[1], h[2]));
        if !(det.is_finite() && det != 0.0) {
            return None;
        }
        // the rows of the adjugate's transpose over the determinant: x = s h, s = x inverse
        let (c12, c20, c01) = (cross(h[1], h[2]), cross(h[2], h[0]), cross(h[0], h[1]));
        let mut inverse = [[0.0; 3]; 3];
        for d in 0..3 {
            inverse[d] = [c12[d] / det, c20[d] / det, c01[d] / det];
        }
        let spacing = [c12, c20, c01].map(|c| det.abs() / norm(c));
        // MDTraj's rounding grows with the coordinates, the cell vectors, and the multiples of
        // them subtracted (more in a skewed cell, whose vectors are long for its spacings)
        let largest = xyz
            .iter()
            .flatten()
            .fold(0.0f64, |m, &x| m.max(f64::from(x).abs()));
        let lengths = h.map(norm);
        let skew: f64 = (0..3).map(|k| lengths[k] / spacing[k]).sum();
        let margin = 1e-3 + 1e-5 * (largest + lengths.iter().sum::<f64>()) * (1.0 + skew);
        let reach = f64::from(cutoff) + 2.0 * margin;
        let mut n = spacing.map(|d| (d / reach).floor());
        if !n.iter().all(|&k| k >= 3.0) {
            return None;
        }
        // no more bins than a few per atom (a small protein in a large box)
        let most = (4 * xyz.len()).max(27) as f64;
        let total = n[0] * n[1] * n[2];
        if total > most {
            let f = (most / total).cbrt();
            n = n.map(|k| (k * f).floor().max(3.0));
        }
        let limit = (f64::from(cutoff) + 1.5 * margin).powi(2) as f32;
        Some(Grid {
            h,
            inverse,
            n: n.map(|k| k as usize),
            limit,
        })
    }

    /// Bins the atoms `xyz` into `ws` (wrapped, sorted by bin); `false` if a position is not
    /// finite.
    fn bin(&self, xyz: &[[f32; 3]], ws: &mut Bins) -> bool {
        let [n0, n1, n2] = self.n;
        let bins = n0 * n1 * n2;
        ws.bin.clear();
        ws.wrapped.clear();
        ws.start.clear();
        ws.start.resize(bins + 1, 0);
        for p in xyz {
            let x = p.map(f64::from);
            let mut cell = [0usize; 3];
            let mut wrapped = x;
            for (k, cell) in cell.iter_mut().enumerate() {
                let s = x[0] * self.inverse[0][k]
                    + x[1] * self.inverse[1][k]
                    + x[2] * self.inverse[2][k];
                if !s.is_finite() {
                    return false;
                }
                let whole = s.floor();
                *cell = (((s - whole) * self.n[k] as f64) as usize).min(self.n[k] - 1);
                for (w, h) in wrapped.iter_mut().zip(self.h[k]) {
                    *w -= whole * h;
                }
            }
            let b = (cell[0] * n1 + cell[1]) * n2 + cell[2];
            ws.bin.push(b as u32);
            ws.wrapped.push(wrapped.map(|x| x as f32));
            ws.start[b + 1] += 1;
        }
        for b in 0..bins {
            ws.start[b + 1] += ws.start[b];
        }
        let atoms = xyz.len();
        for v in [&mut ws.x, &mut ws.y, &mut ws.z] {
            v.clear();
            v.resize(atoms, 0.0);
        }
        ws.atom.clear();
        ws.atom.resize(atoms, 0);
        ws.residue.clear();
        ws.residue.resize(atoms, 0);
        // a cursor per bin: its next free slot (the bin starts are restored after)
        for (a, &b) in ws.bin.iter().enumerate() {
            let slot = &mut ws.start[b as usize];
            let k = *slot as usize;
            *slot += 1;
            let w = ws.wrapped[a];
            (ws.x[k], ws.y[k], ws.z[k]) = (w[0], w[1], w[2]);
            ws.atom[k] = a as u32;
        }
        // each start moved to the next bin's: shift back
        for b in (1..=bins).rev() {
            ws.start[b] = ws.start[b - 1];
        }
        ws.start[0] = 0;
        true
    }
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};

    use super::super::distance::{boxed, sqrt_threshold, triclinic};
    use super::super::{
        ContactPairs, FrequencySpec, Scheme, contact_frequencies, contact_pairs, count_frame,
        single_runs,
    };
    use super::*;
    use crate::io::trajectory::{Conformation, LengthUnit};

    /// MDTraj's counts by brute force: every atom pair of every pair, by the pairwise formulas.
    fn brute_force(frame: &Frame, pairs: &ContactPairs, cutoff: f32, counts: &mut [u32]) {
        let below = sqrt_threshold(cutoff);
        let xyz = &frame.xyz;
        let distance2 = |i: u32, j: u32| match &frame.cell {
            Some(Cell::Box(e)) => boxed(xyz, e, i, j),
            Some(Cell::Triclinic(v, recip)) => triclinic(xyz, v, recip, i, j),
            None => unreachable!(),
        };
        for (k, &(i, j)) in pairs.pairs.iter().enumerate() {
            let (a, b) = (&pairs.atoms[i], &pairs.atoms[j]);
            if a.iter()
                .any(|&p| b.iter().any(|&q| distance2(p, q) < below))
            {
                counts[k] += 1;
            }
        }
    }

    /// A cell: rectangular, or triclinic with its vectors' off-diagonal parts up to `skew`
    /// times the previous vectors' lengths (reduced by MDTraj's rule when it makes the frame).
    fn random_cell(
        rng: &mut impl Rng,
        edges: [f64; 3],
        triclinic: bool,
        skew: f64,
    ) -> [[f64; 3]; 3] {
        let mut v = [
            [edges[0], 0.0, 0.0],
            [0.0, edges[1], 0.0],
            [0.0, 0.0, edges[2]],
        ];
        if triclinic {
            v[1][0] = rng.gen_range(-skew..skew) * edges[0];
            v[2][0] = rng.gen_range(-skew..skew) * edges[0];
            v[2][1] = rng.gen_range(-skew..skew) * edges[1];
        }
        v
    }

    #[test]
    fn the_cell_list_counts_mdtrajs_contacts_in_random_cells() {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(51);
        let (mut gridded, mut cases, mut contacts) = (0, 0, 0);
        for case in 0..400 {
            // residues of one atom (ca, cb) or several, two chains, some residues in no pair
            let residues = rng.gen_range(8..50);
            let most = if case % 2 == 0 { 1 } else { 6 };
            let separation = rng.gen_range(1..=3);
            let split = rng.gen_range(0..residues);
            let mut atoms = Vec::new();
            let mut next = 0u32;
            for _ in 0..residues {
                let n = rng.gen_range(1..=most);
                atoms.push((next..next + n).collect::<Vec<u32>>());
                next += n;
            }
            let skipped: Vec<bool> = (0..residues).map(|_| rng.gen_bool(0.1)).collect();
            let mut pairs = Vec::new();
            for i in 0..residues {
                for j in i + separation..residues {
                    if (i < split) == (j < split) && !skipped[i] && !skipped[j] {
                        pairs.push((i, j));
                    }
                }
            }
            let pairs = ContactPairs { pairs, atoms };
            let triclinic = case % 4 >= 2;
            let edges = [0; 3].map(|_| rng.gen_range(1.0..4.0));
            let skew = if case % 8 >= 6 { 1.6 } else { 0.5 };
            let vectors = random_cell(&mut rng, edges, triclinic, skew);
            // positions across the cell and beyond it (fractional -1.5 .. 2.5), or a cluster
            let cluster = rng.gen_bool(0.3);
            let centre = [0; 3].map(|_| rng.gen_range(-1.5..2.5));
            let spacing = edges.iter().fold(f64::MAX, |m, &e| m.min(e));
            // cutoffs from a twentieth of the smallest edge to past half of it
            let cutoff = (spacing * rng.gen_range(0.05..0.6)) as f32;
            let periodic = Periodic::new(&pairs.pairs, &pairs.atoms, next as usize, cutoff);
            let mut ws = periodic.workspace(pairs.pairs.len());
            let single = single_runs(&pairs);
            assert_eq!(single.is_some(), most == 1);
            let mut expected = vec![0; pairs.pairs.len()];
            let mut found = vec![0; pairs.pairs.len()];
            // and by the whole frame's measure: the cell list, the runs, or all pairs
            let mut framed = vec![0; pairs.pairs.len()];
            let mut other = periodic.workspace(pairs.pairs.len());
            let mut counted = true;
            for _ in 0..3 {
                let positions: Vec<[f64; 3]> = (0..next)
                    .map(|_| {
                        let s = [0; 3].map(|k| {
                            if cluster {
                                centre[k] + rng.gen_range(-0.3..0.3)
                            } else {
                                rng.gen_range(-1.5..2.5)
                            }
                        });
                        [0, 1, 2].map(|d| (0..3).map(|k| s[k] * vectors[k][d]).sum())
                    })
                    .collect();
                let conformation = Conformation {
                    label: String::new(),
                    positions,
                    cell: Some(vectors),
                    unit: LengthUnit::Nanometre,
                };
                let frame = Frame::new(&conformation, None, true);
                brute_force(&frame, &pairs, cutoff, &mut expected);
                counted &= periodic.count(&frame, &mut ws, &mut found);
                let (single, counts) = (single.as_deref(), &mut framed);
                count_frame(
                    &frame, &pairs, single, cutoff, counts, &periodic, &mut other,
                );
            }
            assert_eq!(
                framed, expected,
                "case {case}: cutoff {cutoff}, cell {vectors:?}"
            );
            cases += 1;
            if counted {
                gridded += 1;
                assert_eq!(
                    found, expected,
                    "case {case}: cutoff {cutoff}, cell {vectors:?}"
                );
                contacts += usize::from(expected.iter().any(|&n| n > 0));
            }
        }
        assert!(contacts * 4 > gridded * 3, "{contacts} of {gridded}");
        // most cases are the cell list's (the others: cutoffs over a third of the cell)
        assert!(gridded * 2 > cases, "{gridded} of {cases}");
    }

    #[test]
    fn the_six_schemes_count_mdtrajs_contacts_in_periodic_cells() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/data/md/adk.pdb.gz");
        let topology = crate::io::topology::read_topology(path).unwrap();
        let mut models = crate::io::trajectory::open_trajectories(&[path.to_string()]).unwrap();
        let model = models.next().unwrap().unwrap();
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
        // adk spans about 60 x 52 x 42 A: a cell it fits in and one where it meets its images
        let cells = [
            random_cell(&mut rng, [85.0; 3], false, 0.0),
            [[85.0, 0.0, 0.0], [0.0, 85.0, 0.0], [42.5, 42.5, 60.1]],
            random_cell(&mut rng, [45.0, 52.0, 40.0], true, 0.5),
        ];
        let frames: Vec<Conformation> = cells
            .iter()
            .map(|&cell| {
                let shift = [0; 3].map(|_| rng.gen_range(-60.0..60.0));
                let positions = model
                    .positions
                    .iter()
                    .map(|p| [0, 1, 2].map(|d| p[d] + shift[d] + rng.gen_range(-0.5..0.5)))
                    .collect();
                Conformation {
                    label: String::new(),
                    positions,
                    cell: Some(cell),
                    unit: LengthUnit::Angstrom,
                }
            })
            .collect();
        for (scheme, cutoff) in [
            (Scheme::Ca, 8.0),
            (Scheme::Cb, 8.0),
            (Scheme::Closest, 4.5),
            (Scheme::ClosestHeavy, 4.5),
            (Scheme::Sidechain, 4.5),
            (Scheme::SidechainHeavy, 4.5),
        ] {
            let spec = FrequencySpec {
                scheme,
                cutoff_angstrom: cutoff,
                ..FrequencySpec::default()
            };
            let found =
                contact_frequencies(&topology, frames.iter().cloned().map(Ok), &spec, |_| {})
                    .unwrap();
            let pairs = contact_pairs(&topology, &spec).unwrap();
            let mut expected = vec![0; pairs.pairs.len()];
            for conformation in &frames {
                let frame = Frame::new(conformation, None, true);
                // the cell list applies
                let periodic = Periodic::new(
                    &pairs.pairs,
                    &pairs.atoms,
                    topology.atoms.len(),
                    (cutoff / 10.0) as f32,
                );
                let mut ws = periodic.workspace(pairs.pairs.len());
                assert!(periodic.count(&frame, &mut ws, &mut vec![0; pairs.pairs.len()]));
                brute_force(&frame, &pairs, (cutoff / 10.0) as f32, &mut expected);
            }
            assert_eq!(found.counts, expected, "{}", scheme.name());
            assert!(expected.iter().filter(|&&n| n > 0).count() > 100);
        }
    }

    #[test]
    fn pairs_are_found_by_index() {
        let pairs = vec![(0, 3), (0, 4), (0, 6), (1, 4), (1, 6), (3, 6)];
        let index = PairIndex::new(&pairs, 7);
        assert!(index.sorted.is_none());
        // 0's partners skip 4, which is in a pair
        let gaps = vec![(0, 3), (0, 5), (1, 4), (3, 6)];
        let searched = PairIndex::new(&gaps, 7);
        assert!(searched.sorted.is_some());
        for (index, pairs) in [(index, pairs), (searched, gaps)] {
            for i in 0..7u32 {
                for j in i + 1..7 {
                    let k = pairs.iter().position(|&p| p == (i as usize, j as usize));
                    assert_eq!(index.get(i, j), k, "({i}, {j})");
                }
            }
        }
    }
}
