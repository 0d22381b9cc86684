#!/usr/bin/env python3
"""The dense fetch of issue 31 in one process: `contactmap.File.fetch(...).to_numpy()` against
`cooler.Cooler.matrix(balance=True).fetch(...)` on a 5,000 x 5,000-bin balanced region of
big_bal.cool (`make_big_cool.py`, then `contactmap balance --store`), after a first call of each
(the first call of a process pays the kernel's first touch of the 200 MB array, for either tool).
Ten rounds of three contactmap calls and one cooler call, alternated; prints the medians, the
minima and the ratio of the medians, and checks that the arrays are identical.

usage: python scripts/bench_dense_fetch.py BIG_BALANCED.cool [REGION]
(pin cores with `taskset -c 0,1 python ...` to time fewer)
"""

from __future__ import annotations

import sys
import time

import cooler
import numpy as np

import contactmap as cm


def main() -> None:
    uri = sys.argv[1]
    region = sys.argv[2] if len(sys.argv) > 2 else "chr2:50,000,000-100,000,000"
    f, clr = cm.File(uri), cooler.Cooler(uri)
    ours_first = f.fetch(region, normalization="weight").to_numpy()
    theirs_first = clr.matrix(balance=True).fetch(region)
    assert np.array_equal(ours_first, theirs_first, equal_nan=True), "the arrays differ"
    del ours_first, theirs_first
    ours, theirs = [], []
    for _ in range(10):
        for _ in range(3):
            t0 = time.perf_counter()
            a = f.fetch(region, normalization="weight").to_numpy()
            ours.append(time.perf_counter() - t0)
            del a
        t0 = time.perf_counter()
        b = clr.matrix(balance=True).fetch(region)
        theirs.append(time.perf_counter() - t0)
        del b
    print(
        "ours median %.4f min %.4f; cooler median %.4f min %.4f; ratio %.1f"
        % (
            np.median(ours),
            min(ours),
            np.median(theirs),
            min(theirs),
            np.median(theirs) / np.median(ours),
        )
    )


if __name__ == "__main__":
    main()
