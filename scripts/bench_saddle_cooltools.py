"""cooltools 0.7.1 saddle (with its expected_cis) on a balanced cooler and a track, timed, for
the side-by-side with `contactmap saddle` (docs/performance.md).
usage: python scripts/bench_saddle_cooltools.py IN.cool TRACK.tsv OUT_PREFIX   (writes OUT_PREFIX.S.npy / .C.npy)"""
import sys, time, cooler, cooltools, pandas as pd
clr = cooler.Cooler(sys.argv[1])
track = pd.read_csv(sys.argv[2], sep="\t")
t = time.time()
exp = cooltools.expected_cis(clr, ignore_diags=2, nproc=2)
S, C = cooltools.saddle(clr, exp, track, "cis", n_bins=50, qrange=(0.025, 0.975))
print("cooltools saddle (with expected_cis)", time.time() - t, "s")
import numpy as np
np.save(sys.argv[3] + ".S.npy", S); np.save(sys.argv[3] + ".C.npy", C)
