#!/usr/bin/env bash
# contactmap pileup against coolpuppy 1.1.0 on big.cool (issue 29): the same run, the same
# machine, the same expected table; wall time and peak memory (/usr/bin/time), then the grids
# compared (coolpuppy's Python API, float64) for every grid value, the NaN mask and n.
#
# Usage: scripts/pileup_bench.sh BALANCED.cool [WORK_DIR=/tmp/pileup_bench]
#        [CONTACTMAP=target/release/contactmap] [PYTHON=python3 with coolpuppy 1.1.0]
# Features (made here, seeded): 10,000 BEDPE loops (200 kb - 2 Mb, 10 kb anchors) and 10,000
# BED sites (10 kb, piled up --local) at random on the map's chromosomes.
# Modes: observed/expected (--expected, flank 100 kb: coolpuppy's default) and 10 shifted
# controls with seed 1 (coolpuppy's CLI default normalisation; its controls are reproducible
# only with one process, so the identity check of that mode runs coolpuppy with nproc 1).
# About 10 minutes on 2 cores (coolpuppy ~160 s timed, ~4 min for the identity checks).
set -euo pipefail
cool=$(realpath "$1")
work=${2:-/tmp/pileup_bench}
cm=$(realpath "${3:-target/release/contactmap}")
py=${4:-python3}
coolpup=$(dirname "$(command -v "$py")")/coolpup.py
mkdir -p "$work"
cd "$work"
"$py" - "$cool" <<'PY'
import random, sys, cooler
sizes = cooler.Cooler(sys.argv[1]).chromsizes
chroms = [c for c in sizes.index if sizes[c] > 3_000_000]
random.seed(29)
loops, sites = [], []
for _ in range(10000):
    c = random.choice(chroms)
    a = random.randrange(200000, sizes[c] - 2_300_000) // 10000 * 10000
    d = random.randrange(200000, 2000000) // 10000 * 10000
    loops.append((c, a, a + 10000, c, a + d, a + d + 10000))
for _ in range(10000):
    c = random.choice(chroms)
    a = random.randrange(200000, sizes[c] - 200000) // 10000 * 10000
    sites.append((c, a, a + 10000))
order = {c: i for i, c in enumerate(sizes.index)}
with open("loops.bedpe", "w") as f:
    for r in sorted(loops, key=lambda r: (order[r[0]], r[1], r[4])):
        f.write("\t".join(map(str, r)) + "\n")
with open("sites.bed", "w") as f:
    for r in sorted(sites, key=lambda r: (order[r[0]], r[1])):
        f.write("\t".join(map(str, r)) + "\n")
PY
rm -f expected.tsv ./*.pileup.tsv ./*.scores.tsv ./*.clpy
"$cm" expected "$cool" -o expected.tsv 2>/dev/null
t() { /usr/bin/time -f "$1	%e	%M" "${@:2}" > /dev/null 2> "time.$1" || { cat "time.$1"; exit 1; }; tail -1 "time.$1"; }
printf "run\twall_s\tpeak_kb\n"
for kind in loops sites; do
  if [ $kind = loops ]; then f=loops.bedpe; cp=(--features_format bedpe); ours=(); else
    f=sites.bed; cp=(--features_format bed --local); ours=(--local); fi
  t "coolpuppy_${kind}_oe" "$coolpup" "$cool" $f "${cp[@]}" --expected expected.tsv --nproc 2 --outname cp_${kind}_oe.clpy
  t "contactmap_${kind}_oe" "$cm" pileup "$cool" $f "${ours[@]}" --expected expected.tsv -o cm_${kind}_oe
  t "coolpuppy_${kind}_shifts" "$coolpup" "$cool" $f "${cp[@]}" --nshifts 10 --seed 1 --nproc 2 --outname cp_${kind}_sh.clpy
  t "contactmap_${kind}_shifts" "$cm" pileup "$cool" $f "${ours[@]}" --nshifts 10 --seed 1 -o cm_${kind}_sh
done
"$py" - "$cool" <<'PY'
import sys, warnings, logging
import numpy as np, pandas as pd, cooler
from coolpuppy import coolpup
warnings.filterwarnings("ignore"); logging.disable(logging.CRITICAL)
clr = cooler.Cooler(sys.argv[1])
exp = pd.read_csv("expected.tsv", sep="\t")
loops = pd.read_csv("loops.bedpe", sep="\t", header=None,
                    names=["chrom1", "start1", "end1", "chrom2", "start2", "end2"])
sites = pd.read_csv("sites.bed", sep="\t", header=None, names=["chrom", "start", "end"])
print("case\tn_coolpuppy\tn_contactmap\tsame_nan\tmax_rel_diff")
for kind, feats, fmt, local in [("loops", loops, "bedpe", False), ("sites", sites, "bed", True)]:
    for mode, kw in [("oe", dict(expected_df=exp, nproc=2)), ("sh", dict(nshifts=10, seed=1, nproc=1))]:
        pup = coolpup.pileup(clr, feats, features_format=fmt, local=local, flank=100000, **kw)
        want, n = pup["data"].iloc[0], int(pup["n"].iloc[0])
        got = np.loadtxt(f"cm_{kind}_{mode}.pileup.tsv")
        ours_n = pd.read_csv(f"cm_{kind}_{mode}.scores.tsv", sep="\t").set_index("group").loc["all", "n"]
        same = bool((np.isnan(got) == np.isnan(want)).all())
        ok = ~np.isnan(want)
        rel = float(np.max(np.abs(got[ok] - want[ok]) / np.abs(want[ok])))
        print(f"{kind}_{mode}\t{n}\t{ours_n}\t{same}\t{rel:.2e}")
PY
