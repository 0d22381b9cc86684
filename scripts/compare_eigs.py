"""Compare two eigenvector tables (contactmap compartments vs cooltools eigs_cis) chromosome by
chromosome, each vector up to its sign: the largest absolute difference and the largest relative
eigenvalue difference.
usage: python scripts/compare_eigs.py OURS_PREFIX.cis THEIRS_PREFIX   (reads .vecs.tsv and .lam.txt)"""
import sys
import numpy as np
import pandas as pd

ours, theirs = sys.argv[1], sys.argv[2]
a = pd.read_csv(ours + ".vecs.tsv", sep="\t")
b = pd.read_csv(theirs + ".vecs.tsv", sep="\t")
worst = 0.0
for col in [c for c in a.columns if c.startswith("E")]:
    for chrom in a.chrom.unique():
        x = a[a.chrom == chrom][col].values
        y = b[b.chrom == chrom][col].values
        assert np.array_equal(np.isnan(x), np.isnan(y)), (col, chrom)
        if np.isnan(x).all():
            continue
        worst = max(worst, min(np.nanmax(np.abs(x - y)), np.nanmax(np.abs(x + y))))
la = pd.read_csv(ours + ".lam.txt", sep="\t")
lb = pd.read_csv(theirs + ".lam.txt", sep="\t")
cols = [c for c in la.columns if c.startswith("eigval")]
rel = np.nanmax(np.abs(la[cols].values - lb[cols].values) / np.abs(lb[cols].values))
print(f"vectors: max |difference| up to sign {worst:.3g}; eigenvalues: max relative difference {rel:.3g}")
