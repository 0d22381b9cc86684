//! Cell lists: the pairs of points closer than a cutoff in O(N), never all pairs.
//!
//! Space is cut into a grid of cubic cells whose side is at least the cutoff, so two points
//! closer than the cutoff lie in the same cell or in adjacent ones. Points are sorted by cell
//! (a counting sort, O(N + cells)), and each cell is compared with itself and with 13 of its 26
//! neighbours (a half shell), so every pair is visited once.
//!
//! Two geometries ([`Space`]):
//!
//! - **Open** (free space, or a confining sphere): the grid covers the bounding box of the
//!   points, rebuilt each time; its cells grow beyond the cutoff when the box is sparse, so the
//!   grid never has more than about `2 N` cells (also in a
//!   periodic box). Cell coordinates are clamped to the grid, which
//!   keeps neighbours neighbours.
//! - **Periodic** cube of side `L`: coordinates are wrapped into `[0, L)`, displacements follow
//!   the minimum-image convention, and the grid wraps around. With fewer than 3 cells along the
//!   side (a box under three cutoffs wide) the list falls back to comparing all pairs.

use rayon::prelude::*;

/// The space the points live in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Space {
    /// Unbounded space (a confining wall, if any, is a force, not a boundary).
    Open,
    /// A periodic cube of this side.
    Periodic(f64),
}

impl Space {
    /// The displacement `a - b`, minimum image in a periodic box.
    #[inline]
    pub fn delta(&self, a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
        let mut d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        if let Space::Periodic(side) = *self {
            for x in &mut d {
                *x -= side * (*x / side).round();
            }
        }
        d
    }
}

/// Points sorted by cell, ready for pair searches within a cutoff.
#[derive(Clone, Debug, Default)]
pub struct CellList {
    cutoff: f64,
    periodic: Option<f64>,
    dims: [usize; 3],
    origin: [f64; 3],
    cell_side: [f64; 3],
    /// `start[c]..start[c + 1]`: the slots of cell `c` in `order` / `sorted`.
    start: Vec<u32>,
    /// Point index of each slot.
    order: Vec<u32>,
    /// Slot of each point (the inverse of `order`).
    slot_of: Vec<u32>,
    /// Coordinates of each slot (wrapped into the box when periodic).
    sorted: Vec<[f64; 3]>,
    cell_of: Vec<u32>,
    /// Cells holding at least one point, ascending.
    occupied: Vec<u32>,
    /// The points of each plane of cells, ascending.
    plane_points: Vec<Vec<u32>>,
    wrapped: Vec<[f64; 3]>,
    brute_force: bool,
    /// Scratch of [`CellList::for_each_point_pair`].
    shell: HalfShell,
}

/// One cell's half shell gathered into one run (structure of arrays), with the slots it came
/// from and the hits of one scan: the scratch of [`CellList::for_each_point_pair`].
#[derive(Clone, Debug, Default)]
struct HalfShell {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    slot: Vec<u32>,
    hits: Vec<u32>,
}

impl HalfShell {
    fn clear(&mut self) {
        self.x.clear();
        self.y.clear();
        self.z.clear();
        self.slot.clear();
    }

    fn push(&mut self, sorted: &[[f64; 3]], slots: std::ops::Range<usize>) {
        let points = &sorted[slots.clone()];
        self.x.extend(points.iter().map(|p| p[0]));
        self.y.extend(points.iter().map(|p| p[1]));
        self.z.extend(points.iter().map(|p| p[2]));
        self.slot.extend(slots.map(|s| s as u32));
    }
}

/// `x` wrapped into `[0, side)` (`rem_euclid` without the cost of `fmod`).
#[inline]
fn wrap_into(x: f64, side: f64) -> f64 {
    let mut wrapped = x - side * (x / side).floor();
    // Rounding can land exactly on `side` for tiny negative x.
    if wrapped >= side {
        wrapped -= side;
    }
    wrapped
}

/// Largest number of grid cells per point: cells grow beyond the cutoff in sparse systems, where
/// visiting many empty cells would cost more than testing a few more distances.
const CELLS_PER_POINT: f64 = 6.0;

/// Below this many points a list is built on the calling thread alone (the result is the same).
const PARALLEL_MIN_POINTS: usize = 4096;

/// Points per parallel task when locating points in cells.
const BLOCK: usize = 1024;

/// One plane's share of a build: its index, its points, and its ranges of `order`, `sorted` and
/// `start`, with its first slot.
type PlaneSort<'a> = (
    usize,
    (
        (
            ((&'a [u32], &'a mut [u32]), &'a mut [[f64; 3]]),
            &'a mut [u32],
        ),
        usize,
    ),
);

/// `data` cut into consecutive mutable slices of the given lengths.
pub fn split_lengths<T>(mut data: &mut [T], lengths: impl Iterator<Item = usize>) -> Vec<&mut [T]> {
    let mut parts = Vec::new();
    for length in lengths {
        let (head, tail) = data.split_at_mut(length);
        parts.push(head);
        data = tail;
    }
    parts
}

/// Offsets of the 13 neighbours of the half shell.
const HALF_SHELL: [[isize; 3]; 13] = [
    [1, 0, 0],
    [-1, 1, 0],
    [0, 1, 0],
    [1, 1, 0],
    [-1, -1, 1],
    [0, -1, 1],
    [1, -1, 1],
    [-1, 0, 1],
    [0, 0, 1],
    [1, 0, 1],
    [-1, 1, 1],
    [0, 1, 1],
    [1, 1, 1],
];

impl CellList {
    /// An empty list; fill it with [`CellList::build`].
    pub fn new() -> Self {
        Self::default()
    }

    /// Sort `points` into cells at least `cutoff` wide (see the module docs).
    pub fn build(&mut self, points: &[[f64; 3]], cutoff: f64, space: Space) {
        self.build_with_density(points, cutoff, space, CELLS_PER_POINT);
    }

    /// [`CellList::build`] with a grid of at most `cells_per_point` cells per point (instead of
    /// 6): more, smaller cells suit sparse clouds such as polymer conformations, whose bounding
    /// box is mostly empty.
    pub fn build_with_density(
        &mut self,
        points: &[[f64; 3]],
        cutoff: f64,
        space: Space,
        cells_per_point: f64,
    ) {
        let n = points.len();
        let parallel = n >= PARALLEL_MIN_POINTS && rayon::current_num_threads() > 1;
        self.cutoff = cutoff;
        self.periodic = match space {
            Space::Periodic(side) => Some(side),
            Space::Open => None,
        };
        self.brute_force = false;
        match space {
            Space::Periodic(side) => {
                let width = cutoff.max((side.powi(3) / (cells_per_point * n.max(1) as f64)).cbrt());
                let per_axis = (side / width).floor() as usize;
                if per_axis < 3 {
                    self.brute_force = true;
                    self.dims = [1, 1, 1];
                } else {
                    self.dims = [per_axis; 3];
                }
                self.origin = [0.0; 3];
                let width = side / self.dims[0] as f64;
                self.cell_side = [width; 3];
            }
            Space::Open => {
                // Minima and maxima are exact in any order.
                let bounds = |block: &[[f64; 3]]| {
                    let mut low = [f64::INFINITY; 3];
                    let mut high = [f64::NEG_INFINITY; 3];
                    for p in block {
                        for k in 0..3 {
                            low[k] = low[k].min(p[k]);
                            high[k] = high[k].max(p[k]);
                        }
                    }
                    (low, high)
                };
                let (mut low, mut high) = if parallel {
                    points.par_chunks(BLOCK).map(bounds).reduce(
                        || bounds(&[]),
                        |(l1, h1), (l2, h2)| {
                            (
                                std::array::from_fn(|k| l1[k].min(l2[k])),
                                std::array::from_fn(|k| h1[k].max(h2[k])),
                            )
                        },
                    )
                } else {
                    bounds(points)
                };
                if n == 0 {
                    low = [0.0; 3];
                    high = [0.0; 3];
                }
                let extent = [high[0] - low[0], high[1] - low[1], high[2] - low[2]];
                // Cells of at least the cutoff, grown until the grid has at most 2 N cells
                // (and at least 27 allowed), so sparse or elongated clouds stay O(N).
                let limit = (cells_per_point * n as f64).max(27.0);
                let volume = extent.iter().map(|e| e.max(cutoff)).product::<f64>();
                let mut side = cutoff.max((volume / limit).cbrt());
                let dims_for = |side: f64| extent.map(|e| (e / side).floor() + 1.0);
                while dims_for(side).iter().product::<f64>() > limit {
                    side *= 1.25;
                }
                let dims = dims_for(side);
                // One empty layer of cells around the grid: every occupied cell is interior,
                // so its half shell lies in the grid (the row ranges of `for_each_pair`).
                for k in 0..3 {
                    self.dims[k] = dims[k] as usize + 2;
                    self.cell_side[k] = side;
                    self.origin[k] = low[k] - side;
                }
            }
        }
        let n_cells = self.dims[0] * self.dims[1] * self.dims[2];
        let plane = self.dims[0] * self.dims[1];
        let n_planes = self.dims[2];
        // Wrapped coordinates and cells, point by point.
        let mut wrapped = std::mem::take(&mut self.wrapped);
        let mut cell_of = std::mem::take(&mut self.cell_of);
        wrapped.resize(n, [0.0; 3]);
        cell_of.resize(n, 0);
        {
            let this = &*self;
            let locate = |(block, (wrapped, cell_of)): (usize, (&mut [[f64; 3]], &mut [u32]))| {
                let offset = block * BLOCK;
                for (k, (w, c)) in wrapped.iter_mut().zip(cell_of.iter_mut()).enumerate() {
                    *w = this.wrap(&points[offset + k]);
                    *c = this.cell_index(w) as u32;
                }
            };
            if parallel {
                wrapped
                    .par_chunks_mut(BLOCK)
                    .zip(cell_of.par_chunks_mut(BLOCK))
                    .enumerate()
                    .for_each(locate);
            } else {
                wrapped
                    .chunks_mut(BLOCK)
                    .zip(cell_of.chunks_mut(BLOCK))
                    .enumerate()
                    .for_each(locate);
            }
        }
        // The points of each plane, ascending (a stable bucket pass).
        self.plane_points.resize_with(n_planes, Vec::new);
        for points in &mut self.plane_points {
            points.clear();
        }
        for (index, &cell) in cell_of.iter().enumerate() {
            self.plane_points[cell as usize / plane].push(index as u32);
        }
        // Each plane sorts its points into its cells (a counting sort, stable): its own ranges
        // of `start`, `order` and `sorted`.
        self.start.clear();
        self.start.resize(n_cells + 1, 0);
        self.start[n_cells] = n as u32;
        self.order.resize(n, 0);
        self.sorted.resize(n, [0.0; 3]);
        let sizes = || self.plane_points.iter().map(Vec::len);
        let bases: Vec<usize> = sizes()
            .scan(0, |total, size| {
                *total += size;
                Some(*total - size)
            })
            .collect();
        let orders = split_lengths(&mut self.order, sizes());
        let sorted = split_lengths(&mut self.sorted, sizes());
        let starts = self.start[..n_cells].chunks_mut(plane.max(1));
        let (cell_of_ref, wrapped_ref) = (&cell_of, &wrapped);
        let sort_plane = |(z, ((((members, order), sorted), start), base)): PlaneSort| {
            let first_cell = z * plane;
            for &index in members {
                start[cell_of_ref[index as usize] as usize - first_cell] += 1;
            }
            let mut occupied = Vec::new();
            let mut running = base;
            for (cell, entry) in start.iter_mut().enumerate() {
                let count = *entry as usize;
                if count > 0 {
                    occupied.push((first_cell + cell) as u32);
                }
                *entry = running as u32;
                running += count;
            }
            // `start` as the cursor of each cell, then shifted back one cell.
            for &index in members {
                let cell = cell_of_ref[index as usize] as usize - first_cell;
                let slot = start[cell] as usize - base;
                start[cell] += 1;
                order[slot] = index;
                sorted[slot] = wrapped_ref[index as usize];
            }
            for cell in (1..start.len()).rev() {
                start[cell] = start[cell - 1];
            }
            if let Some(entry) = start.first_mut() {
                *entry = base as u32;
            }
            occupied
        };
        let tasks = self
            .plane_points
            .iter()
            .map(Vec::as_slice)
            .zip(orders)
            .zip(sorted)
            .zip(starts)
            .zip(bases)
            .enumerate();
        let occupied: Vec<Vec<u32>> = if parallel {
            tasks
                .collect::<Vec<_>>()
                .into_par_iter()
                .map(sort_plane)
                .collect()
        } else {
            tasks.map(sort_plane).collect()
        };
        self.occupied.clear();
        for cells in occupied {
            self.occupied.extend_from_slice(&cells);
        }
        self.slot_of.resize(n, 0);
        for (slot, &index) in self.order.iter().enumerate() {
            self.slot_of[index as usize] = slot as u32;
        }
        self.wrapped = wrapped;
        self.cell_of = cell_of;
    }

    #[inline]
    fn wrap(&self, p: &[f64; 3]) -> [f64; 3] {
        match self.periodic {
            Some(side) => p.map(|x| wrap_into(x, side)),
            None => *p,
        }
    }

    #[inline]
    fn cell_index(&self, p: &[f64; 3]) -> usize {
        let mut index = 0;
        for k in (0..3).rev() {
            // Truncation is the floor for the non-negative values kept by the clamp.
            let coordinate = (p[k] - self.origin[k]) / self.cell_side[k];
            let clamped = coordinate.clamp(0.0, (self.dims[k] - 1) as f64) as usize;
            index = index * self.dims[k] + clamped;
        }
        index
    }

    /// The cell at grid coordinates `(x, y, z)` shifted by `offset`, wrapping when periodic,
    /// with the shift to add to its points' coordinates to bring them next to the first cell
    /// (non-zero only across a periodic boundary); `None` outside an open grid.
    #[inline]
    fn neighbour(&self, cell: [usize; 3], offset: [isize; 3]) -> Option<(usize, [f64; 3])> {
        let mut index = 0;
        let mut shift = [0.0; 3];
        for k in (0..3).rev() {
            let moved = cell[k] as isize + offset[k];
            let dim = self.dims[k] as isize;
            let moved = match self.periodic {
                Some(side) => {
                    if moved < 0 {
                        shift[k] = -side;
                    } else if moved >= dim {
                        shift[k] = side;
                    }
                    moved.rem_euclid(dim)
                }
                None if moved < 0 || moved >= dim => return None,
                None => moved,
            };
            index = index * self.dims[k] + moved as usize;
        }
        Some((index, shift))
    }

    /// Point indices in cell order: slot `s` holds point `order()[s]`.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Slot of each point: point `i` sits at slot `slot_of()[i]` (the inverse of
    /// [`CellList::order`]).
    pub fn slot_of(&self) -> &[u32] {
        &self.slot_of
    }

    /// Number of planes of cells along z (1 when the list compares all pairs). Slots are sorted
    /// by cell with x fastest and z slowest, so each plane holds a contiguous range of slots
    /// ([`CellList::plane_slots`]).
    pub fn n_planes(&self) -> usize {
        self.dims[2]
    }

    /// The slots of the cells of plane `z` (`z < n_planes()`).
    pub fn plane_slots(&self, z: usize) -> std::ops::Range<usize> {
        let plane = self.dims[0] * self.dims[1];
        self.start[z * plane] as usize..self.start[(z + 1) * plane] as usize
    }

    /// Call `visit(slot_a, slot_b, delta, r2)` once for every pair of slots whose points are
    /// closer than the cutoff (`r2 < cutoff²`), with `delta` the displacement from b to a
    /// (minimum image). Slots index [`CellList::order`]; pairs come in a fixed order: plane by
    /// plane, as [`CellList::for_each_pair_in_plane`] visits them.
    pub fn for_each_pair(&self, mut visit: impl FnMut(usize, usize, [f64; 3], f64)) {
        for z in 0..self.n_planes() {
            self.for_each_pair_in_plane(z, &mut visit);
        }
    }

    /// [`CellList::for_each_pair`] for the pairs whose first slot lies in plane `z`: the second
    /// slot lies in plane `z` or in the next one, `(z + 1) % n_planes()` (the half shell reaches
    /// one plane up, wrapping around in a periodic box). Planes can thus be visited in parallel,
    /// each writing to its own slots and to those of the next plane. The pairs of a plane come
    /// in a fixed order.
    pub fn for_each_pair_in_plane(
        &self,
        z: usize,
        mut visit: impl FnMut(usize, usize, [f64; 3], f64),
    ) {
        let cutoff2 = self.cutoff * self.cutoff;
        let n = self.sorted.len();
        if self.brute_force {
            let space = match self.periodic {
                Some(side) => Space::Periodic(side),
                None => Space::Open,
            };
            for a in 0..n {
                for b in a + 1..n {
                    let d = space.delta(&self.sorted[a], &self.sorted[b]);
                    let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                    if r2 < cutoff2 {
                        visit(a, b, d, r2);
                    }
                }
            }
            return;
        }
        let [nx, ny, nz] = self.dims;
        let plane = nx * ny;
        let first_cell = self.occupied.partition_point(|&c| (c as usize) < z * plane);
        let last_cell = self
            .occupied
            .partition_point(|&c| (c as usize) < (z + 1) * plane);
        let mut neighbours = [(0usize, [0.0f64; 3]); 13];
        for &cell in &self.occupied[first_cell..last_cell] {
            let cell = cell as usize;
            let (x, y) = (cell % nx, cell / nx % ny);
            let (first, last) = (self.start[cell] as usize, self.start[cell + 1] as usize);
            let interior =
                (1..nx - 1).contains(&x) && (1..ny - 1).contains(&y) && (1..nz - 1).contains(&z);
            if interior {
                // Cells adjacent along x are adjacent in slot order, so the half shell is five
                // slot ranges: this cell with the next one along x, and four rows of three
                // cells (y + 1 at this z; y - 1, y, y + 1 at z + 1).
                let row_end = self.start[cell + 2] as usize;
                for a in first..last {
                    let pa = self.sorted[a];
                    self.scan(a, pa, a + 1..row_end, cutoff2, &mut visit);
                }
                for row in [
                    cell + nx,
                    cell + plane - nx,
                    cell + plane,
                    cell + plane + nx,
                ] {
                    let range = self.start[row - 1] as usize..self.start[row + 2] as usize;
                    if range.is_empty() {
                        continue;
                    }
                    for a in first..last {
                        let pa = self.sorted[a];
                        self.scan(a, pa, range.clone(), cutoff2, &mut visit);
                    }
                }
                continue;
            }
            // A cell on the faces of a periodic grid: neighbours one by one, with the shift of
            // the periodic image. (Within the cell no image can be closer: cells are at least
            // the cutoff wide and at least 3 along each side.)
            for a in first..last {
                let pa = self.sorted[a];
                self.scan(a, pa, a + 1..last, cutoff2, &mut visit);
            }
            let mut n_neighbours = 0;
            for offset in HALF_SHELL {
                if let Some(found) = self.neighbour([x, y, z], offset) {
                    neighbours[n_neighbours] = found;
                    n_neighbours += 1;
                }
            }
            for &(other, shift) in &neighbours[..n_neighbours] {
                let range = self.start[other] as usize..self.start[other + 1] as usize;
                for a in first..last {
                    let pa = self.sorted[a];
                    let pa = [pa[0] - shift[0], pa[1] - shift[1], pa[2] - shift[2]];
                    self.scan(a, pa, range.clone(), cutoff2, &mut visit);
                }
            }
        }
    }

    /// Visit the slots `range` closer than the cutoff to the point `pa` of slot `a`.
    #[inline(always)]
    fn scan(
        &self,
        a: usize,
        pa: [f64; 3],
        range: std::ops::Range<usize>,
        cutoff2: f64,
        visit: &mut impl FnMut(usize, usize, [f64; 3], f64),
    ) {
        let first = range.start;
        for (k, pb) in self.sorted[range].iter().enumerate() {
            let d = [pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]];
            let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            if r2 < cutoff2 {
                visit(a, first + k, d, r2);
            }
        }
    }

    /// Call `visit(i, j, r2)` once for every pair of points `i`, `j` (point indices, not
    /// slots) closer than the cutoff, `r2` their squared distance: the pairs of
    /// [`CellList::for_each_pair`], in another fixed order, found faster in an open space.
    /// Each cell's half shell (five runs of slots) is gathered into one run, so that each point
    /// is compared with one long run instead of five short ones, without a branch per
    /// candidate (polymer conformations hold a few points per cell: short runs cost more than
    /// their distances). A periodic list visits its pairs as [`CellList::for_each_pair`] does.
    pub fn for_each_point_pair(&mut self, mut visit: impl FnMut(u32, u32, f64)) {
        if self.brute_force || self.periodic.is_some() {
            let order = &self.order;
            self.for_each_pair(|a, b, _, r2| visit(order[a], order[b], r2));
            return;
        }
        let cutoff2 = self.cutoff * self.cutoff;
        let [nx, ny, _] = self.dims;
        let plane = nx * ny;
        let (start, sorted, order, shell) =
            (&self.start, &self.sorted, &self.order, &mut self.shell);
        for &cell in &self.occupied {
            // every occupied cell of an open grid is interior (see `build`)
            let cell = cell as usize;
            let (first, last) = (start[cell] as usize, start[cell + 1] as usize);
            shell.clear();
            // this cell and the next along x first: a point's partners in its own cell are the
            // points after it in the run
            shell.push(sorted, first..start[cell + 2] as usize);
            for row in [
                cell + nx,
                cell + plane - nx,
                cell + plane,
                cell + plane + nx,
            ] {
                shell.push(sorted, start[row - 1] as usize..start[row + 2] as usize);
            }
            shell.hits.resize(shell.x.len(), 0);
            for k in 0..last - first {
                let (px, py, pz) = (shell.x[k], shell.y[k], shell.z[k]);
                let candidates = shell.x[k + 1..]
                    .iter()
                    .zip(&shell.y[k + 1..])
                    .zip(&shell.z[k + 1..]);
                // the indices of the hits, without a branch: each candidate is written, and
                // kept when close
                let mut n_hits = 0;
                for (j, ((x, y), z)) in candidates.enumerate() {
                    let (dx, dy, dz) = (px - x, py - y, pz - z);
                    shell.hits[n_hits] = j as u32;
                    n_hits += usize::from(dx * dx + dy * dy + dz * dz < cutoff2);
                }
                let i = order[first + k];
                for &j in &shell.hits[..n_hits] {
                    let b = k + 1 + j as usize;
                    let (dx, dy, dz) = (px - shell.x[b], py - shell.y[b], pz - shell.z[b]);
                    visit(
                        i,
                        order[shell.slot[b] as usize],
                        dx * dx + dy * dy + dz * dz,
                    );
                }
            }
        }
    }

    /// The pairs `(i, j)`, `i < j`, of points closer than the cutoff, sorted.
    pub fn pairs(&self) -> Vec<(usize, usize)> {
        let mut pairs = Vec::new();
        self.for_each_pair(|a, b, _, _| {
            let (i, j) = (self.order[a] as usize, self.order[b] as usize);
            pairs.push((i.min(j), i.max(j)));
        });
        pairs.sort_unstable();
        pairs
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn brute_force(points: &[[f64; 3]], cutoff: f64, space: Space) -> Vec<(usize, usize)> {
        let mut pairs = Vec::new();
        for i in 0..points.len() {
            for j in i + 1..points.len() {
                let d = space.delta(&points[i], &points[j]);
                if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cutoff * cutoff {
                    pairs.push((i, j));
                }
            }
        }
        pairs
    }

    fn points_strategy() -> impl Strategy<Value = Vec<[f64; 3]>> {
        proptest::collection::vec(
            (-8.0f64..8.0, -8.0f64..8.0, -8.0f64..8.0).prop_map(|(x, y, z)| [x, y, z]),
            0..300,
        )
    }

    proptest! {
        /// Open space: exactly the brute-force pair set, for any cutoff.
        #[test]
        fn open_space_equals_brute_force(points in points_strategy(), cutoff in 0.3f64..4.0) {
            let mut cells = CellList::new();
            cells.build(&points, cutoff, Space::Open);
            prop_assert_eq!(cells.pairs(), brute_force(&points, cutoff, Space::Open));
        }

        /// Periodic box (points also outside the box, wrapped): the brute-force minimum-image
        /// pair set, including boxes too small for a grid.
        #[test]
        fn periodic_equals_brute_force(
            points in points_strategy(),
            cutoff in 0.3f64..3.0,
            side in 2.0f64..12.0,
        ) {
            let space = Space::Periodic(side);
            let cutoff = cutoff.min(side / 2.0 - 1e-9);
            let mut cells = CellList::new();
            cells.build(&points, cutoff, space);
            prop_assert_eq!(cells.pairs(), brute_force(&points, cutoff, space));
        }
    }

    proptest! {
        /// `for_each_point_pair` (the gathered half shells) visits the brute-force pairs, each
        /// once, with their squared distances, at any grid density, open or periodic (the
        /// periodic list visits as `for_each_pair`).
        #[test]
        fn point_pairs_equal_brute_force(
            points in points_strategy(),
            cutoff in 0.3f64..4.0,
            side in 2.0f64..12.0,
            cells_per_point in 1.0f64..40.0,
            periodic: bool,
        ) {
            let space = if periodic { Space::Periodic(side) } else { Space::Open };
            let cutoff = if periodic { cutoff.min(side / 2.0 - 1e-9) } else { cutoff };
            let mut cells = CellList::new();
            cells.build_with_density(&points, cutoff, space, cells_per_point);
            let mut pairs = Vec::new();
            cells.for_each_point_pair(|i, j, r2| {
                let (i, j) = (i as usize, j as usize);
                let d = space.delta(&points[i], &points[j]);
                let want = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                assert!((r2 - want).abs() <= 1e-9 * want.max(1.0), "{r2} vs {want}");
                pairs.push((i.min(j), i.max(j)));
            });
            pairs.sort_unstable();
            prop_assert_eq!(pairs, brute_force(&points, cutoff, space));
        }
    }

    /// The pairs of each plane start in that plane and end in it or in the next one (wrapping
    /// around), so planes can write their forces apart; `slot_of` inverts `order`.
    fn check_planes(cells: &CellList) -> Result<(), TestCaseError> {
        let n_planes = cells.n_planes();
        let mut covered = 0;
        for z in 0..n_planes {
            let own = cells.plane_slots(z);
            prop_assert_eq!(own.start, covered);
            covered = own.end;
            let next = cells.plane_slots((z + 1) % n_planes);
            let mut outside = None;
            cells.for_each_pair_in_plane(z, |a, b, _, _| {
                if !own.contains(&a) || !(own.contains(&b) || next.contains(&b)) {
                    outside = Some((a, b));
                }
            });
            prop_assert_eq!(outside, None, "plane {}", z);
        }
        prop_assert_eq!(covered, cells.order().len());
        for (slot, &point) in cells.order().iter().enumerate() {
            prop_assert_eq!(cells.slot_of()[point as usize] as usize, slot);
        }
        Ok(())
    }

    proptest! {
        #[test]
        fn planes_write_to_themselves_and_the_next_one(
            points in points_strategy(),
            cutoff in 0.3f64..3.0,
            side in 2.0f64..12.0,
            periodic: bool,
        ) {
            let space = if periodic { Space::Periodic(side) } else { Space::Open };
            let cutoff = cutoff.min(side / 2.0 - 1e-9);
            let mut cells = CellList::new();
            cells.build(&points, cutoff, space);
            check_planes(&cells)?;
        }
    }

    /// A list of 30,000 points built on 2 and 5 threads equals the one built on 1 (slots,
    /// cells, occupied cells), in open space and in a periodic box.
    #[test]
    fn parallel_build_equals_the_serial_build() {
        use rand::Rng;
        let mut rng = crate::random::stream_rng(8, 0, 0);
        let points: Vec<[f64; 3]> = (0..30_000)
            .map(|_| [0; 3].map(|_| rng.r#gen::<f64>() * 60.0 - 10.0))
            .collect();
        for space in [Space::Open, Space::Periodic(50.0)] {
            let build = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let mut cells = CellList::new();
                pool.install(|| cells.build(&points, 1.05, space));
                cells
            };
            let one = build(1);
            for threads in [2, 5] {
                let other = build(threads);
                assert_eq!(one.order, other.order);
                assert_eq!(one.start, other.start);
                assert_eq!(one.occupied, other.occupied);
                assert_eq!(one.slot_of, other.slot_of);
                assert!(one.sorted == other.sorted);
            }
        }
    }

    /// Everything a build leaves behind: equal for two lists holding the same points.
    fn assert_same_list(reused: &CellList, fresh: &CellList) -> Result<(), TestCaseError> {
        prop_assert_eq!(reused.dims, fresh.dims);
        prop_assert_eq!(reused.brute_force, fresh.brute_force);
        prop_assert_eq!(&reused.order, &fresh.order);
        prop_assert_eq!(&reused.slot_of, &fresh.slot_of);
        prop_assert_eq!(&reused.start, &fresh.start);
        prop_assert_eq!(&reused.occupied, &fresh.occupied);
        prop_assert!(reused.sorted == fresh.sorted);
        prop_assert_eq!(reused.plane_points.len(), fresh.plane_points.len());
        Ok(())
    }

    proptest! {
        /// A list built once with one cutoff (and other points, maybe another space) and then
        /// rebuilt with another equals a fresh list, slot for slot, and finds the brute-force
        /// pairs: nothing sized for the first build survives into the second (issue 12).
        #[test]
        fn rebuilding_with_another_cutoff_equals_a_fresh_list(
            first_points in points_strategy(),
            points in points_strategy(),
            first_cutoff in 0.3f64..3.0,
            cutoff in 0.3f64..3.0,
            side in 2.0f64..12.0,
            first_periodic: bool,
            periodic: bool,
        ) {
            let space_of = |periodic| if periodic { Space::Periodic(side) } else { Space::Open };
            let (first_space, space) = (space_of(first_periodic), space_of(periodic));
            let first_cutoff = first_cutoff.min(side / 2.0 - 1e-9);
            let cutoff = cutoff.min(side / 2.0 - 1e-9);
            let mut reused = CellList::new();
            reused.build(&first_points, first_cutoff, first_space);
            reused.build(&points, cutoff, space);
            let mut fresh = CellList::new();
            fresh.build(&points, cutoff, space);
            assert_same_list(&reused, &fresh)?;
            prop_assert_eq!(reused.pairs(), brute_force(&points, cutoff, space));
            check_planes(&reused)?;
        }
    }

    /// The push-off of issue 12 as fixed cases: 800 points in a periodic box of side 12.6,
    /// built at the overlap distance 0.85 and then at the WCA range 2^(1/6) (and back), and
    /// the same in open space and with a list reused many times.
    #[test]
    fn alternating_cutoffs_equal_fresh_lists() {
        use rand::Rng;
        let mut rng = crate::random::stream_rng(12, 0, 0);
        let side = (800.0f64 / 0.4).cbrt();
        let points: Vec<[f64; 3]> = (0..800)
            .map(|_| [0; 3].map(|_| rng.r#gen::<f64>() * side * 1.5 - side / 4.0))
            .collect();
        let wca = 2f64.powf(1.0 / 6.0);
        let mut reused = CellList::new();
        for space in [Space::Periodic(side), Space::Open] {
            for cutoff in [0.85, wca, 0.85, 3.0, wca, 0.5, wca] {
                reused.build(&points, cutoff, space);
                let mut fresh = CellList::new();
                fresh.build(&points, cutoff, space);
                assert_same_list(&reused, &fresh).unwrap();
                assert_eq!(reused.pairs(), brute_force(&points, cutoff, space));
            }
        }
    }

    #[test]
    fn sparse_and_degenerate_inputs() {
        let mut cells = CellList::new();
        cells.build(&[], 1.0, Space::Open);
        assert!(cells.pairs().is_empty());
        // Two clusters far apart: the grid stays small, pairs are found.
        let points = vec![
            [0.0, 0.0, 0.0],
            [0.5, 0.0, 0.0],
            [1e6, 0.0, 0.0],
            [1e6, 0.2, 0.0],
        ];
        cells.build(&points, 1.0, Space::Open);
        assert_eq!(cells.pairs(), vec![(0, 1), (2, 3)]);
        assert!(cells.start.len() < 1000, "{}", cells.start.len());
        // All points in one spot.
        let points = vec![[1.0, 1.0, 1.0]; 5];
        cells.build(&points, 1.0, Space::Open);
        assert_eq!(cells.pairs().len(), 10);
    }
}
