#!/usr/bin/env python3
"""cooltools 0.7.1 `dots` references for `contactmap dots` (tests/ and the closing note of issue 28).

Usage: dots_reference.py COOL_URI OUT_PREFIX [--w W --p P] [--max-sep BP] [--nans N] [--expected TSV]

Writes OUT_PREFIX.expected.tsv (cooltools expected_cis, defaults, balanced by `weight`),
OUT_PREFIX.dots.tsv (cooltools.dots with the API defaults: the 22 columns) and
OUT_PREFIX.enriched.tsv (clustering_radius=None: the enriched pixels, 15 columns).
Kernels are cooltools' recommendation for the bin size, or get_kernel(W, P, type) for the
four HiCCUPS types when --w/--p are given. Needs cooltools 0.7.1 with pandas < 3 (its dots
fails on pandas 3) and scikit-learn.
"""
import argparse
import logging

import cooler
import cooltools
import pandas as pd
from cooltools.lib.numutils import get_kernel

logging.disable(logging.INFO)

p = argparse.ArgumentParser()
p.add_argument("uri")
p.add_argument("prefix")
p.add_argument("--w", type=int)
p.add_argument("--p", type=int)
p.add_argument("--max-sep", type=int, default=10_000_000)
p.add_argument("--nans", type=int, default=1)
p.add_argument("--expected")
a = p.parse_args()

clr = cooler.Cooler(a.uri)
if a.expected:
    expected = pd.read_csv(a.expected, sep="\t")
else:
    expected = cooltools.expected_cis(clr, nproc=1)
    expected.to_csv(f"{a.prefix}.expected.tsv", sep="\t", index=False, na_rep="nan")
kernels = None
if a.w is not None:
    kernels = {k: get_kernel(a.w, a.p, k) for k in ["donut", "vertical", "horizontal", "lowleft"]}
common = dict(kernels=kernels, max_loci_separation=a.max_sep, max_nans_tolerated=a.nans)
dots = cooltools.dots(clr, expected, **common)
dots.to_csv(f"{a.prefix}.dots.tsv", sep="\t", index=False, na_rep="nan")
enriched = cooltools.dots(clr, expected, clustering_radius=None, **common)
enriched.to_csv(f"{a.prefix}.enriched.tsv", sep="\t", index=False, na_rep="nan")
print(f"{a.uri}: {len(enriched)} enriched pixels, {len(dots)} dots")
