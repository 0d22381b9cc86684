//! Hierarchical clustering of samples by a distance (for HiCRep, `1 - SCC`), as scipy's
//! `linkage(method="average")` (UPGMA) builds the tree and `dendrogram` orders its leaves, so
//! that a clustered heatmap lists the samples in the order a seaborn `clustermap` shows them.
//!
//! At each step the two clusters at the least average distance are merged (ties: the pair that
//! comes first, by the order of the clusters' ids); leaves are `0 .. n`, the cluster made by
//! merge `k` is `n + k`, and each merge lists the smaller id first (scipy's convention). The
//! leaves are ordered by visiting each merge's first cluster before its second (scipy's
//! `dendrogram` without sorting).

use crate::error::{Error, Result};

/// One merge of two clusters.
#[derive(Clone, Debug, PartialEq)]
pub struct Merge {
    /// The cluster listed first (the smaller id).
    pub left: usize,
    /// The cluster listed second.
    pub right: usize,
    /// The average distance between their members.
    pub distance: f64,
    /// Leaves under the new cluster.
    pub size: usize,
}

/// The tree of `n` leaves: `n - 1` merges.
#[derive(Clone, Debug, PartialEq)]
pub struct Dendrogram {
    /// Number of leaves.
    pub n: usize,
    /// Merges in order (scipy's linkage matrix `Z`, one row per merge).
    pub merges: Vec<Merge>,
}

impl Dendrogram {
    /// Average-linkage clustering of `n` items from their distances (row-major `n x n`,
    /// symmetric; the diagonal is ignored). Distances must be finite and not negative.
    ///
    /// # Examples
    ///
    /// Two pairs of close samples: each pair merges first.
    ///
    /// ```
    /// use contactmap::compare::cluster::Dendrogram;
    ///
    /// let d = [
    ///     0.0, 0.9, 0.1, 0.8, //
    ///     0.9, 0.0, 0.7, 0.2, //
    ///     0.1, 0.7, 0.0, 0.9, //
    ///     0.8, 0.2, 0.9, 0.0,
    /// ];
    /// let tree = Dendrogram::average_linkage(&d, 4)?;
    /// assert_eq!((tree.merges[0].left, tree.merges[0].right), (0, 2));
    /// assert_eq!((tree.merges[1].left, tree.merges[1].right), (1, 3));
    /// // the last merge joins the two pairs at their average distance
    /// assert!((tree.merges[2].distance - (0.9 + 0.8 + 0.7 + 0.9) / 4.0).abs() < 1e-12);
    /// assert_eq!(tree.leaf_order(), vec![0, 2, 1, 3]);
    /// # Ok::<(), contactmap::Error>(())
    /// ```
    pub fn average_linkage(distances: &[f64], n: usize) -> Result<Dendrogram> {
        if distances.len() != n * n {
            return Err(Error::Argument(format!(
                "clustering {n} items needs {} distances, not {}",
                n * n,
                distances.len()
            )));
        }
        if let Some(k) = (0..n * n)
            .find(|&k| k / n != k % n && (!distances[k].is_finite() || distances[k] < 0.0))
        {
            return Err(Error::Data(format!(
                "distance between items {} and {} is {}: distances must be finite and not negative",
                k / n,
                k % n,
                distances[k]
            )));
        }
        // Active clusters: (id, members' count); d[a][b] the average distance between the
        // active clusters at positions a and b.
        let mut active: Vec<(usize, usize)> = (0..n).map(|k| (k, 1)).collect();
        let mut d: Vec<Vec<f64>> = (0..n)
            .map(|i| (0..n).map(|j| distances[i * n + j]).collect())
            .collect();
        let mut merges = Vec::with_capacity(n.saturating_sub(1));
        while active.len() > 1 {
            let mut best = (0, 1);
            for a in 0..active.len() {
                for b in a + 1..active.len() {
                    if d[a][b] < d[best.0][best.1] {
                        best = (a, b);
                    }
                }
            }
            let (a, b) = best;
            let ((id_a, size_a), (id_b, size_b)) = (active[a], active[b]);
            let (wa, wb) = (size_a as f64, size_b as f64);
            // The merged cluster takes position a; position b goes.
            let merged: Vec<f64> = d[a]
                .iter()
                .zip(&d[b])
                .map(|(x, y)| (wa * x + wb * y) / (wa + wb))
                .collect();
            for (c, value) in merged.into_iter().enumerate() {
                if c != a && c != b {
                    d[a][c] = value;
                    d[c][a] = value;
                }
            }
            merges.push(Merge {
                left: id_a.min(id_b),
                right: id_a.max(id_b),
                distance: d[a][b],
                size: size_a + size_b,
            });
            active[a] = (n + merges.len() - 1, size_a + size_b);
            active.remove(b);
            d.remove(b);
            for row in &mut d {
                row.remove(b);
            }
        }
        Ok(Dendrogram { n, merges })
    }

    /// The leaves from left to right: each merge's first cluster, then its second.
    pub fn leaf_order(&self) -> Vec<usize> {
        let mut order = Vec::with_capacity(self.n);
        if self.n == 0 {
            return order;
        }
        let mut stack = vec![self.n + self.merges.len() - 1];
        while let Some(id) = stack.pop() {
            if id < self.n {
                order.push(id);
            } else {
                let merge = &self.merges[id - self.n];
                stack.push(merge.right);
                stack.push(merge.left);
            }
        }
        order
    }

    /// Where each cluster is drawn: its position along the leaves (leaves at `0, 1, ...` in
    /// [`leaf_order`](Self::leaf_order); a merge midway between its two clusters) and its height
    /// (0 for leaves, the merge distance), by cluster id.
    pub fn positions(&self) -> Vec<(f64, f64)> {
        let mut at = vec![(0.0, 0.0); self.n + self.merges.len()];
        for (slot, &leaf) in self.leaf_order().iter().enumerate() {
            at[leaf] = (slot as f64, 0.0);
        }
        for (k, merge) in self.merges.iter().enumerate() {
            at[self.n + k] = ((at[merge.left].0 + at[merge.right].0) / 2.0, merge.distance);
        }
        at
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// scipy 1.x on the same distances: `Z = linkage(squareform(D), "average")` and
    /// `dendrogram(Z, no_plot=True)["leaves"]` (the Python lines are in the test).
    #[test]
    fn equals_scipy_average_linkage() {
        // import numpy as np; from scipy.cluster.hierarchy import linkage, dendrogram
        // from scipy.spatial.distance import squareform
        // rng = np.random.default_rng(3); x = rng.random((6, 2))
        // D = np.sqrt(((x[:, None] - x[None]) ** 2).sum(-1)).round(6)
        // Z = linkage(squareform(D, checks=False), "average")
        // leaves = dendrogram(Z, no_plot=True)["leaves"]
        let d = SCIPY_D;
        let tree = Dendrogram::average_linkage(&d, 6).unwrap();
        for (merge, z) in tree.merges.iter().zip(SCIPY_Z) {
            assert_eq!((merge.left, merge.right, merge.size), (z.0, z.1, z.3));
            assert!((merge.distance - z.2).abs() < 1e-9, "{merge:?} vs {z:?}");
        }
        assert_eq!(tree.leaf_order(), SCIPY_LEAVES);
    }

    #[test]
    fn refuses_bad_distances_and_handles_one_leaf() {
        assert!(Dendrogram::average_linkage(&[0.0, f64::NAN, f64::NAN, 0.0], 2).is_err());
        assert!(Dendrogram::average_linkage(&[0.0, -1.0, -1.0, 0.0], 2).is_err());
        assert!(Dendrogram::average_linkage(&[0.0; 3], 2).is_err());
        let one = Dendrogram::average_linkage(&[0.0], 1).unwrap();
        assert!(one.merges.is_empty());
        assert_eq!(one.leaf_order(), vec![0]);
        assert_eq!(one.positions(), vec![(0.0, 0.0)]);
    }

    #[test]
    fn positions_put_merges_between_their_clusters() {
        let d = SCIPY_D;
        let tree = Dendrogram::average_linkage(&d, 6).unwrap();
        let at = tree.positions();
        for (k, merge) in tree.merges.iter().enumerate() {
            let (x, y) = at[6 + k];
            assert_eq!(y, merge.distance);
            let (a, b) = (at[merge.left].0, at[merge.right].0);
            assert!(x > a.min(b) && x < a.max(b));
        }
    }

    const SCIPY_D: [f64; 36] = [
        0.0, 0.794599, 0.196499, 0.400881, 0.660508, 0.414414, //
        0.794599, 0.0, 0.72268, 0.53129, 0.473214, 0.415232, //
        0.196499, 0.72268, 0.0, 0.47213, 0.715699, 0.308641, //
        0.400881, 0.53129, 0.47213, 0.0, 0.259645, 0.367645, //
        0.660508, 0.473214, 0.715699, 0.259645, 0.0, 0.529483, //
        0.414414, 0.415232, 0.308641, 0.367645, 0.529483, 0.0,
    ];
    const SCIPY_Z: [(usize, usize, f64, usize); 5] = [
        (0, 2, 0.196499, 2),
        (3, 4, 0.259645, 2),
        (5, 6, 0.3615275, 3),
        (1, 7, 0.502252, 3),
        (8, 9, 0.5643174444444444, 6),
    ];
    const SCIPY_LEAVES: [usize; 6] = [5, 0, 2, 1, 3, 4];
}
