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
//!   grid never has more than about `2 N` cells. Cell coordinates are clamped to the grid, which
//!   keeps neighbours neighbours.
//! - **Periodic** cube of side `L`: coordinates are wrapped into `[0, L)`, displacements follow
//!   the minimum-image convention, and the grid wraps around. With fewer than 3 cells along the
//!   side (a box under three cutoffs wide) the list falls back to comparing all pairs.

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
    /// Coordinates of each slot (wrapped into the box when periodic).
    sorted: Vec<[f64; 3]>,
    cell_of: Vec<u32>,
    brute_force: bool,
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
        let n = points.len();
        self.cutoff = cutoff;
        self.periodic = match space {
            Space::Periodic(side) => Some(side),
            Space::Open => None,
        };
        self.brute_force = false;
        match space {
            Space::Periodic(side) => {
                let per_axis = (side / cutoff).floor() as usize;
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
                let mut low = [f64::INFINITY; 3];
                let mut high = [f64::NEG_INFINITY; 3];
                for p in points {
                    for k in 0..3 {
                        low[k] = low[k].min(p[k]);
                        high[k] = high[k].max(p[k]);
                    }
                }
                if n == 0 {
                    low = [0.0; 3];
                    high = [0.0; 3];
                }
                let extent = [high[0] - low[0], high[1] - low[1], high[2] - low[2]];
                // Cells of at least the cutoff, grown until the grid has at most 2 N cells
                // (and at least 27 allowed), so sparse or elongated clouds stay O(N).
                let limit = (2 * n).max(27) as f64;
                let volume = extent.iter().map(|e| e.max(cutoff)).product::<f64>();
                let mut side = cutoff.max((volume / limit).cbrt());
                let dims_for = |side: f64| extent.map(|e| (e / side).floor() + 1.0);
                while dims_for(side).iter().product::<f64>() > limit {
                    side *= 1.25;
                }
                let dims = dims_for(side);
                for k in 0..3 {
                    self.dims[k] = dims[k] as usize;
                    self.cell_side[k] = side;
                }
                self.origin = low;
            }
        }
        let n_cells = self.dims[0] * self.dims[1] * self.dims[2];
        self.cell_of.clear();
        self.cell_of.reserve(n);
        let mut counts = vec![0u32; n_cells + 1];
        for p in points {
            let cell = self.cell_index(&self.wrap(p));
            self.cell_of.push(cell as u32);
            counts[cell + 1] += 1;
        }
        for c in 0..n_cells {
            counts[c + 1] += counts[c];
        }
        self.start = counts;
        let mut next: Vec<u32> = self.start[..n_cells].to_vec();
        self.order.resize(n, 0);
        self.sorted.resize(n, [0.0; 3]);
        for (index, p) in points.iter().enumerate() {
            let cell = self.cell_of[index] as usize;
            let slot = next[cell] as usize;
            next[cell] += 1;
            self.order[slot] = index as u32;
            self.sorted[slot] = self.wrap(p);
        }
    }

    #[inline]
    fn wrap(&self, p: &[f64; 3]) -> [f64; 3] {
        match self.periodic {
            Some(side) => [
                p[0].rem_euclid(side),
                p[1].rem_euclid(side),
                p[2].rem_euclid(side),
            ],
            None => *p,
        }
    }

    #[inline]
    fn cell_index(&self, p: &[f64; 3]) -> usize {
        let mut index = 0;
        for k in (0..3).rev() {
            let coordinate = ((p[k] - self.origin[k]) / self.cell_side[k]).floor();
            let clamped = coordinate.clamp(0.0, (self.dims[k] - 1) as f64) as usize;
            index = index * self.dims[k] + clamped;
        }
        index
    }

    /// The cell at grid coordinates `(x, y, z)` shifted by `offset`, wrapping when periodic;
    /// `None` outside an open grid.
    #[inline]
    fn neighbour(&self, cell: [usize; 3], offset: [isize; 3]) -> Option<usize> {
        let mut index = 0;
        for k in (0..3).rev() {
            let moved = cell[k] as isize + offset[k];
            let dim = self.dims[k] as isize;
            let moved = if self.periodic.is_some() {
                moved.rem_euclid(dim)
            } else if moved < 0 || moved >= dim {
                return None;
            } else {
                moved
            };
            index = index * self.dims[k] + moved as usize;
        }
        Some(index)
    }

    /// Point indices in cell order: slot `s` holds point `order()[s]`.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Call `visit(slot_a, slot_b, delta, r2)` once for every pair of slots whose points are
    /// closer than the cutoff (`r2 < cutoff²`), with `delta` the displacement from b to a
    /// (minimum image). Slots index [`CellList::order`]; pairs come in a fixed order.
    pub fn for_each_pair(&self, mut visit: impl FnMut(usize, usize, [f64; 3], f64)) {
        let cutoff2 = self.cutoff * self.cutoff;
        let space = match self.periodic {
            Some(side) => Space::Periodic(side),
            None => Space::Open,
        };
        let n = self.sorted.len();
        if self.brute_force {
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
        let mut neighbours = [0usize; 13];
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let cell = (z * ny + y) * nx + x;
                    let (first, last) = (self.start[cell] as usize, self.start[cell + 1] as usize);
                    if first == last {
                        continue;
                    }
                    for a in first..last {
                        let pa = self.sorted[a];
                        for b in a + 1..last {
                            let d = space.delta(&pa, &self.sorted[b]);
                            let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                            if r2 < cutoff2 {
                                visit(a, b, d, r2);
                            }
                        }
                    }
                    let mut n_neighbours = 0;
                    for offset in HALF_SHELL {
                        if let Some(other) = self.neighbour([x, y, z], offset) {
                            neighbours[n_neighbours] = other;
                            n_neighbours += 1;
                        }
                    }
                    for &other in &neighbours[..n_neighbours] {
                        let (other_first, other_last) =
                            (self.start[other] as usize, self.start[other + 1] as usize);
                        for a in first..last {
                            let pa = self.sorted[a];
                            for b in other_first..other_last {
                                let d = space.delta(&pa, &self.sorted[b]);
                                let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                                if r2 < cutoff2 {
                                    visit(a, b, d, r2);
                                }
                            }
                        }
                    }
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

    #[test]
    fn sparse_and_degenerate_inputs() {
        let mut cells = CellList::new();
        cells.build(&[], 1.0, Space::Open);
        assert!(cells.pairs().is_empty());
        // Two clusters far apart: the grid stays small, pairs are found.
        let points = vec![[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1e6, 0.0, 0.0], [1e6, 0.2, 0.0]];
        cells.build(&points, 1.0, Space::Open);
        assert_eq!(cells.pairs(), vec![(0, 1), (2, 3)]);
        assert!(cells.start.len() < 100);
        // All points in one spot.
        let points = vec![[1.0, 1.0, 1.0]; 5];
        cells.build(&points, 1.0, Space::Open);
        assert_eq!(cells.pairs().len(), 10);
    }
}
