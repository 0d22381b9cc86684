//! BIRCH clustering of 2-D points exactly as scikit-learn's `Birch(threshold, n_clusters=None,
//! branching_factor=50)` computes it, the clustering cooltools' dot caller uses on the enriched
//! pixels' `(start1, start2)`.
//!
//! The points are inserted one by one, in order, into a CF tree: each goes down to the closest
//! subcluster (by `-2 c.x + |c|^2`), joins the closest leaf subcluster when the merged radius
//! stays within the threshold, else opens a new one; a node holding more than 50 subclusters
//! splits around its farthest pair. The subcluster centres are the leaves' centroids in leaf
//! order, and each point's label is its closest centre (which need not be the subcluster it
//! joined). The result depends on the order of the points.
//!
//! The floating-point operations are scikit-learn's as numpy and OpenBLAS evaluate them on
//! x86-64 (checked against scikit-learn 1.9 on random and gridded inputs): a matrix-vector
//! product `c0 * x0 + c1 * x1` is `fma(c0, x0, c1 * x1)`, a matrix-matrix product
//! `fma(a1, b1, a0 * b0)`, a vector dot product and row norms plain `a0 * b0 + a1 * b1`. With
//! points on a genomic grid, many distances tie exactly; these orders decide the ties as
//! scikit-learn does.

/// `np.dot(matrix, vector)` for one row.
fn dot_mv(c: [f64; 2], x: [f64; 2]) -> f64 {
    c[0].mul_add(x[0], c[1] * x[1])
}

/// `np.dot(vector, vector)`, row norms.
fn dot_vv(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// One element of `A @ B.T` (BLAS dgemm).
fn gemm(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[1].mul_add(b[1], a[0] * b[0])
}

#[derive(Clone, Debug)]
struct Subcluster {
    n: usize,
    linear_sum: [f64; 2],
    squared_sum: f64,
    centroid: [f64; 2],
    sq_norm: f64,
    child: Option<usize>,
}

impl Subcluster {
    fn empty() -> Subcluster {
        Subcluster {
            n: 0,
            linear_sum: [0.0; 2],
            squared_sum: 0.0,
            centroid: [0.0; 2],
            sq_norm: 0.0,
            child: None,
        }
    }

    fn point(x: [f64; 2]) -> Subcluster {
        let sq = dot_vv(x, x);
        Subcluster {
            n: 1,
            linear_sum: x,
            squared_sum: sq,
            centroid: x,
            sq_norm: sq,
            child: None,
        }
    }

    fn update(&mut self, other: &Subcluster) {
        self.n += other.n;
        self.linear_sum = [
            self.linear_sum[0] + other.linear_sum[0],
            self.linear_sum[1] + other.linear_sum[1],
        ];
        self.squared_sum += other.squared_sum;
        let n = self.n as f64;
        self.centroid = [self.linear_sum[0] / n, self.linear_sum[1] / n];
        self.sq_norm = dot_vv(self.centroid, self.centroid);
    }

    fn merge(&mut self, other: &Subcluster, threshold: f64) -> bool {
        let new_ss = self.squared_sum + other.squared_sum;
        let new_ls = [
            self.linear_sum[0] + other.linear_sum[0],
            self.linear_sum[1] + other.linear_sum[1],
        ];
        let new_n = self.n + other.n;
        let inv = 1.0 / new_n as f64;
        let new_centroid = [inv * new_ls[0], inv * new_ls[1]];
        let new_sq_norm = dot_vv(new_centroid, new_centroid);
        let sq_radius = new_ss / new_n as f64 - new_sq_norm;
        if sq_radius <= threshold * threshold {
            self.n = new_n;
            self.linear_sum = new_ls;
            self.squared_sum = new_ss;
            self.centroid = new_centroid;
            self.sq_norm = new_sq_norm;
            true
        } else {
            false
        }
    }
}

#[derive(Clone, Debug)]
struct Node {
    leaf: bool,
    subclusters: Vec<Subcluster>,
    prev_leaf: Option<usize>,
    next_leaf: Option<usize>,
}

/// The tree, nodes in an arena.
struct Tree {
    nodes: Vec<Node>,
    threshold: f64,
    branching_factor: usize,
}

impl Tree {
    fn new_node(&mut self, leaf: bool) -> usize {
        self.nodes.push(Node {
            leaf,
            subclusters: Vec::new(),
            prev_leaf: None,
            next_leaf: None,
        });
        self.nodes.len() - 1
    }

    /// `_CFNode.insert_cf_subcluster`: true when the node must split.
    fn insert(&mut self, node: usize, sub: Subcluster) -> bool {
        if self.nodes[node].subclusters.is_empty() {
            self.nodes[node].subclusters.push(sub);
            return false;
        }
        let mut best = f64::INFINITY;
        let mut closest = 0;
        for (k, c) in self.nodes[node].subclusters.iter().enumerate() {
            let mut d = dot_mv(c.centroid, sub.centroid);
            d *= -2.0;
            d += c.sq_norm;
            // np.argmin: the first minimum (a NaN would win; distances are finite)
            if d < best || k == 0 {
                best = d;
                closest = k;
            }
        }
        if let Some(child) = self.nodes[node].subclusters[closest].child {
            let split = self.insert(child, sub.clone());
            if !split {
                self.nodes[node].subclusters[closest].update(&sub);
                return false;
            }
            let (s1, s2) = self.split(child);
            let subs = &mut self.nodes[node].subclusters;
            subs[closest] = s1;
            subs.push(s2);
            return subs.len() > self.branching_factor;
        }
        let threshold = self.threshold;
        if self.nodes[node].subclusters[closest].merge(&sub, threshold) {
            return false;
        }
        let subs = &mut self.nodes[node].subclusters;
        subs.push(sub);
        subs.len() > self.branching_factor
    }

    /// `_split_node`: two new subclusters (with new child nodes) sharing `node`'s subclusters.
    fn split(&mut self, node: usize) -> (Subcluster, Subcluster) {
        let leaf = self.nodes[node].leaf;
        let n1 = self.new_node(leaf);
        let n2 = self.new_node(leaf);
        let mut s1 = Subcluster::empty();
        let mut s2 = Subcluster::empty();
        s1.child = Some(n1);
        s2.child = Some(n2);
        if leaf {
            let (prev, next) = (self.nodes[node].prev_leaf, self.nodes[node].next_leaf);
            if let Some(p) = prev {
                self.nodes[p].next_leaf = Some(n1);
            }
            self.nodes[n1].prev_leaf = prev;
            self.nodes[n1].next_leaf = Some(n2);
            self.nodes[n2].prev_leaf = Some(n1);
            self.nodes[n2].next_leaf = next;
            if let Some(nx) = next {
                self.nodes[nx].prev_leaf = Some(n2);
            }
        }
        let subs = std::mem::take(&mut self.nodes[node].subclusters);
        let m = subs.len();
        let norms: Vec<f64> = subs
            .iter()
            .map(|s| dot_vv(s.centroid, s.centroid))
            .collect();
        let centroids: Vec<[f64; 2]> = subs.iter().map(|s| s.centroid).collect();
        let dist = |i: usize, j: usize| -> f64 {
            if i == j {
                return 0.0;
            }
            let mut d = -2.0 * gemm(centroids[i], centroids[j]);
            d += norms[i];
            d += norms[j];
            d.max(0.0)
        };
        let (mut far, mut best) = ((0, 0), f64::NEG_INFINITY);
        for i in 0..m {
            for j in 0..m {
                let d = dist(i, j);
                if d > best {
                    best = d;
                    far = (i, j);
                }
            }
        }
        for (k, sub) in subs.into_iter().enumerate() {
            let closer_to_first = k == far.0 || dist(far.0, k) < dist(far.1, k);
            if closer_to_first {
                s1.update(&sub);
                self.nodes[n1].subclusters.push(sub);
            } else {
                s2.update(&sub);
                self.nodes[n2].subclusters.push(sub);
            }
        }
        (s1, s2)
    }
}

/// The BIRCH result: subcluster centres (leaf order) and each point's label (index of its
/// closest centre).
#[derive(Clone, Debug, PartialEq)]
pub struct Birch {
    /// Subcluster centroids.
    pub centres: Vec<[f64; 2]>,
    /// Per point, the index of its centre.
    pub labels: Vec<usize>,
}

/// `Birch(threshold=threshold, n_clusters=None).fit(points)` with scikit-learn's default
/// branching factor (50): centres and labels.
///
/// ```
/// use contactmap::loops::birch::birch;
/// let points = [[0.0, 100_000.0], [10_000.0, 100_000.0], [500_000.0, 900_000.0]];
/// let fit = birch(&points, 20_000.0);
/// assert_eq!(fit.labels, [0, 0, 1]);
/// assert_eq!(fit.centres[0], [5_000.0, 100_000.0]);
/// ```
pub fn birch(points: &[[f64; 2]], threshold: f64) -> Birch {
    const BRANCHING_FACTOR: usize = 50;
    let mut tree = Tree {
        nodes: Vec::new(),
        threshold,
        branching_factor: BRANCHING_FACTOR,
    };
    let dummy = tree.new_node(true);
    let mut root = tree.new_node(true);
    tree.nodes[dummy].next_leaf = Some(root);
    tree.nodes[root].prev_leaf = Some(dummy);
    for &x in points {
        if tree.insert(root, Subcluster::point(x)) {
            let (s1, s2) = tree.split(root);
            root = tree.new_node(false);
            tree.nodes[root].subclusters = vec![s1, s2];
        }
    }
    let mut centres = Vec::new();
    let mut leaf = tree.nodes[dummy].next_leaf;
    while let Some(l) = leaf {
        centres.extend(tree.nodes[l].subclusters.iter().map(|s| s.centroid));
        leaf = tree.nodes[l].next_leaf;
    }
    let labels = closest_centres(points, &centres);
    Birch { centres, labels }
}

/// scikit-learn's `predict`: each point's centre with the smallest `|x|^2 - 2 x.c + |c|^2` (in
/// its floating-point order), the first one on ties. Only the centres that can be the closest
/// are looked at: walking outwards from the point's first coordinate among the centres sorted
/// by theirs, until the gap on that coordinate alone exceeds the best distance by a margin far
/// above the formula's rounding (1e-9 relative; the rounding is 1e-15): the same labels as
/// comparing every centre (tested), without its points x centres work.
fn closest_centres(points: &[[f64; 2]], centres: &[[f64; 2]]) -> Vec<usize> {
    use rayon::prelude::*;
    let norms: Vec<f64> = centres.iter().map(|&c| dot_vv(c, c)).collect();
    let mut order: Vec<usize> = (0..centres.len()).collect();
    order.sort_by(|&a, &b| centres[a][0].total_cmp(&centres[b][0]));
    let firsts: Vec<f64> = order.iter().map(|&k| centres[k][0]).collect();
    let largest_norm = norms.iter().copied().fold(0.0, f64::max);
    points
        .par_iter()
        .map(|&x| {
            let xn = dot_vv(x, x);
            let margin = 1e-9 * (xn + largest_norm) + 1.0;
            let mut best = (f64::INFINITY, 0usize);
            let distance = |k: usize| ((xn + -2.0 * gemm(x, centres[k])) + norms[k]).max(0.0);
            let better = |best: (f64, usize), k: usize| {
                let d = distance(k);
                if d < best.0 || (d == best.0 && k < best.1) {
                    (d, k)
                } else {
                    best
                }
            };
            let gap = |at: usize| (firsts[at] - x[0]) * (firsts[at] - x[0]);
            let start = firsts.partition_point(|&c| c < x[0]);
            let (mut below, mut above) = (start, start);
            loop {
                let left = if below > 0 {
                    gap(below - 1)
                } else {
                    f64::INFINITY
                };
                let right = if above < firsts.len() {
                    gap(above)
                } else {
                    f64::INFINITY
                };
                let nearest = left.min(right);
                if nearest == f64::INFINITY || nearest > best.0 + margin {
                    break;
                }
                if left <= right {
                    below -= 1;
                    best = better(best, order[below]);
                } else {
                    best = better(best, order[above]);
                    above += 1;
                }
            }
            best.1
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// Every centre compared, the first of the smallest (scikit-learn's `argmin`).
    fn brute_force(points: &[[f64; 2]], centres: &[[f64; 2]]) -> Vec<usize> {
        let norms: Vec<f64> = centres.iter().map(|&c| dot_vv(c, c)).collect();
        points
            .iter()
            .map(|&x| {
                let xn = dot_vv(x, x);
                let mut best = (f64::INFINITY, 0);
                for (k, &c) in centres.iter().enumerate() {
                    let d = ((xn + -2.0 * gemm(x, c)) + norms[k]).max(0.0);
                    if d < best.0 {
                        best = (d, k);
                    }
                }
                best.1
            })
            .collect()
    }

    #[test]
    fn closest_centres_are_those_of_every_comparison() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(55);
        for case in 0..40 {
            // on a genomic grid (many exact ties, centres repeated) or anywhere
            let grid = case % 2 == 0;
            let scale = [1e3, 1e6, 2.5e8][case % 3];
            let point = |rng: &mut rand::rngs::StdRng| {
                if grid {
                    let a = rng.gen_range(0..200) as f64 * 10_000.0;
                    let b = a + rng.gen_range(0..50) as f64 * 10_000.0;
                    [a, b]
                } else {
                    [rng.r#gen::<f64>() * scale, rng.r#gen::<f64>() * scale]
                }
            };
            let centres: Vec<[f64; 2]> = (0..rng.gen_range(1..300))
                .map(|_| {
                    let [a, b] = point(&mut rng);
                    if grid { [a + 5_000.0, b] } else { [a, b] }
                })
                .collect();
            let points: Vec<[f64; 2]> = (0..500).map(|_| point(&mut rng)).collect();
            assert_eq!(
                closest_centres(&points, &centres),
                brute_force(&points, &centres),
                "case {case}"
            );
        }
    }
}
