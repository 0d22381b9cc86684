#!/usr/bin/env python3
"""scikit-learn Birch references for contactmap's loops::birch (the clustering of cooltools dots).

Usage: birch_reference.py OUT.tsv.gz [SEED]

Random sets of enriched-pixel-like points (start1, start2 on a bin grid, in clumps), clustered
with Birch(threshold=T, n_clusters=None) as cooltools does. Lines: `case K T` starts a case,
`p x y label` one point (input order), `c x y` one subcluster centre (leaf order).
"""
import gzip
import sys

import numpy as np
from sklearn.cluster import Birch

out, seed = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 28
rng = np.random.default_rng(seed)
with gzip.open(out, "wt") as f:
    for case in range(12):
        bs = int(rng.choice([5000, 10000, 25000]))
        n_clumps = int(rng.integers(1, 30))
        pts = []
        for _ in range(n_clumps):
            cx = int(rng.integers(0, 5000)) * bs
            cy = cx + int(rng.integers(3, 400)) * bs
            for _ in range(int(rng.integers(1, 12))):
                pts.append((cx + int(rng.integers(-3, 4)) * bs, cy + int(rng.integers(-3, 4)) * bs))
        # cooltools clusters the enriched pixels sorted by (bin1, bin2)
        pts = sorted(set(pts))
        if case % 6 == 0:  # large sets to reach node splits (branching factor 50)
            pts = sorted({(int(x), int(x) + int(d)) for x, d in zip(rng.integers(0, 3000, 260) * bs, rng.integers(1, 200, 260) * bs)})
        X = np.array(pts, dtype=np.float64)
        threshold = float(rng.choice([20000, 39000, 2 * bs]))
        b = Birch(n_clusters=None, threshold=threshold, compute_labels=True).fit(X)
        f.write(f"case {case} {float(threshold)!r}\n")
        for (x, y), label in zip(pts, b.labels_):
            f.write(f"p {x} {y} {label}\n")
        for cx, cy in b.subcluster_centers_:
            f.write(f"c {float(cx)!r} {float(cy)!r}\n")
