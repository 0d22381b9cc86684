#!/usr/bin/env python3
"""coolpuppy 1.1.0 pileup references for `contactmap pileup` (tests/, issue 29).

Usage: pileup_reference.py OUT_DIR   (run from the repository root; needs coolpuppy 1.1.0,
cooltools 0.7.1, pandas < 3)

On data/sim_extrusion.5kb.cool (balanced, 5 kb) with cooltools' expected_cis (defaults), writes
for each case NAME.tsv.gz: a header line `# n=N` then the pileup grid (tab-separated, `nan` for
NaN, Python's repr of each float). Cases:
  bedpe_oe     the truth loops (data/sim_extrusion.truth_loops.bedpe), observed/expected, flank 20 kb
  bed_raw      ten anchors (data/reference/pileup/anchors.bed) paired, raw counts, flank 30 kb,
               maxdist 400 kb
  bed_local_oe the same anchors on the diagonal (local), observed/expected, flank 50 kb
  bed_oe       the anchors paired, balanced, observed/expected, flank 20 kb, mindist 100 kb
and scores.tsv: coolpuppy's scores (lib/numutils.py) of those pileups (case, score, argument,
value).
"""
import gzip
import logging
import os
import sys
import warnings

import cooler
import cooltools
import numpy as np
import pandas as pd
from coolpuppy import coolpup
from coolpuppy.lib import numutils

warnings.filterwarnings("ignore")
logging.disable(logging.CRITICAL)

out = sys.argv[1]
os.makedirs(out, exist_ok=True)
clr = cooler.Cooler("data/sim_extrusion.5kb.cool")
expected = cooltools.expected_cis(clr, nproc=1)
loops = pd.read_csv("data/sim_extrusion.truth_loops.bedpe", sep="\t")
anchors = pd.read_csv(
    "data/reference/pileup/anchors.bed", sep="\t", header=None, names=["chrom", "start", "end"]
)


def write(name, pup):
    data = pup["data"].iloc[0]
    with gzip.open(os.path.join(out, f"{name}.tsv.gz"), "wt") as f:
        f.write(f"# n={int(pup['n'].iloc[0])}\n")
        for row in data:
            f.write("\t".join("nan" if np.isnan(v) else repr(float(v)) for v in row) + "\n")
    print(name, data.shape, int(pup["n"].iloc[0]))
    return data


pups = {
    "bedpe_oe": write("bedpe_oe", coolpup.pileup(clr, loops, features_format="bedpe",
                                                 expected_df=expected, flank=20000)),
    "bed_raw": write("bed_raw", coolpup.pileup(clr, anchors, features_format="bed",
                                               clr_weight_name=None, flank=30000, maxdist=400000)),
    "bed_local_oe": write("bed_local_oe", coolpup.pileup(clr, anchors, features_format="bed",
                                                         local=True, expected_df=expected,
                                                         flank=50000)),
    "bed_oe": write("bed_oe", coolpup.pileup(clr, anchors, features_format="bed",
                                             expected_df=expected, flank=20000, mindist=100000)),
}
with open(os.path.join(out, "scores.tsv"), "w") as f:
    f.write("case\tscore\targument\tvalue\n")
    for case in ["bedpe_oe", "bed_raw", "bed_oe"]:
        for k in [1, 3]:
            f.write(f"{case}\tenrichment\t{k}\t{float(numutils.get_enrichment(pups[case], k))!r}\n")
        for k in [2, 4]:
            f.write(f"{case}\tcorner_cv\t{k}\t{float(numutils.corner_cv(pups[case], k))!r}\n")
    for k in [0, 3]:
        value = float(numutils.get_insulation_strength(pups["bed_local_oe"], k))
        f.write(f"bed_local_oe\tinsulation_strength\t{k}\t{value!r}\n")
