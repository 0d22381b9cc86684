"""cooltools 0.7.1 eigs_cis on a balanced cooler, timed, for the side-by-side with `contactmap
compartments` (docs/performance.md, "Compartments").
usage: python scripts/bench_eigs_cooltools.py IN.cool OUT_PREFIX   (writes OUT_PREFIX.lam.txt / .vecs.tsv)"""
import sys, time, cooler, cooltools
clr = cooler.Cooler(sys.argv[1])
t = time.time()
vals, vecs = cooltools.eigs_cis(clr, n_eigs=3)
print("cooltools eigs_cis", time.time() - t, "s")
vals.to_csv(sys.argv[2] + ".lam.txt", sep="\t", index=False)
vecs.to_csv(sys.argv[2] + ".vecs.tsv", sep="\t", index=False)
