"""Compare two insulation tables (contactmap tads vs cooltools insulation) column by column.

Prints one Markdown table row: the largest relative difference of the real columns, whether the
NaN positions and the boundary calls are identical. Usage: compare_insulation.py OURS THEIRS
"""
import sys

import numpy as np
import pandas as pd

ours = pd.read_csv(sys.argv[1], sep="\t")
theirs = pd.read_csv(sys.argv[2], sep="\t")
assert len(ours) == len(theirs), "row counts differ"
worst, worst_abs, nan_same, calls_same = 0.0, 0.0, True, True
for column in theirs.columns:
    if column in ("chrom", "region"):
        assert (ours[column].astype(str) == theirs[column].astype(str)).all(), column
        continue
    a, b = ours[column].to_numpy(), theirs[column].to_numpy()
    if column.startswith("is_"):
        same = (a.astype(bool) == b.astype(bool)).all()
        calls_same &= bool(same)
        continue
    a, b = a.astype(float), b.astype(float)
    nan_same &= bool((np.isnan(a) == np.isnan(b)).all())
    finite = ~np.isnan(a) & ~np.isnan(b)
    if finite.any():
        worst_abs = max(worst_abs, float(np.max(np.abs(a[finite] - b[finite]))))
    both = finite & (b != 0)
    if both.any():
        worst = max(worst, float(np.max(np.abs(a[both] - b[both]) / np.abs(b[both]))))
n_calls = int(sum(theirs[c].sum() for c in theirs.columns if c.startswith("is_boundary")))
print(
    f"| tables agree: max relative difference {worst:.1e} (absolute {worst_abs:.1e}), NaN positions "
    f"{'identical' if nan_same else 'DIFFER'}, boundary calls ({n_calls}) "
    f"{'identical' if calls_same else 'DIFFER'} | | |"
)
