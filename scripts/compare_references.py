"""References for the sample comparisons (issue 30), in data/reference/compare/:

scc.tsv.gz: hicrep 0.2.6 `hicrepSCC` on pairs of real maps from data/:
Pairs of real maps from data/:
  gm12878   hg19.GM12878-MboI.matrix.2000kb.cool against the same library's subsampled pairs
            (hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz) binned at 2 Mb by `cooler cload
            pairs` (columns 1,2,4,5, 1-based positions) on the cool's chromosomes
  yeast     yeast.10kb.cool against a thinned copy: `contactmap sample --fraction 0.3 --seed 30`
  mm9       CN.mm9.10000kb.cool against `contactmap sample --fraction 0.05 --seed 31`
  dm6       cooler_test_file.mcool::/resolutions/100000 against `contactmap sample --count
            10000000 --seed 32`
  sim       sim_extrusion.5kb.cool against `contactmap sample --fraction 0.5 --seed 33`
For each, `hicrep.hicrepSCC(cool1, cool2, h, dBPMax, bDownSample=False, chrNames=[chrom])`
per chromosome (hicrep stops the whole call on an assertion when a chromosome is empty in one
map: such chromosomes are written `assert`), for several h and dBPMax (-1: whole chromosomes).

hicreppy.tsv.gz: hicreppy 0.1.0's SCC of whole chromosomes (`get_scc(smooth(diag_trim(chrom,
max_bins + h)), ...)`, the SCC its `h_train` computes on subsamples) of yeast.10kb.cool against the
thinned yeast copy above, for h = 0, 2, 5 and max_dist 500 kb and 200 kb.

cooltools.tsv.gz: cooltools 0.7.1 `coverage` and `virtual4c` (the API the CLI calls), each case led
by a line `## NAME`, then the table as the cooltools CLI writes it (tab-separated, nan):
  coverage_mm9_raw       CN.mm9.10000kb.cool, ignore_diags from its weight (2), raw
  coverage_mm9_weight    the same, clr_weight_name="weight"
  coverage_mm9_raw0      the same, ignore_diags=0
  v4c_mm9_weight         CN.mm9.10000kb.cool, viewpoint chr1:50000000-60000000, balanced
  v4c_mm9_raw            the same, viewpoint chr2:35000000-55000000, raw
  v4c_mm9_partial        the same, viewpoint chr3:55000000-72000000 (two bins partly inside), balanced
Only the rows of chr1 to chr4 are kept (data/ has little room left); each is compared row by row.

usage: python scripts/compare_references.py CONTACTMAP_BINARY [OUT_DIR=data/reference/compare]
(needs cooler 0.11, cooltools 0.7.1 and hicrep 0.2.6 in the Python running it)
"""
import gzip
import os
import subprocess
import sys
import tempfile
import warnings

import cooler
import numpy as np
import pandas as pd
from hicrep import hicrepSCC

warnings.filterwarnings("ignore")
binary = os.path.abspath(sys.argv[1])
out_dir = sys.argv[2] if len(sys.argv) > 2 else "data/reference/compare"
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
data = os.path.join(root, "data")
tmp = tempfile.mkdtemp(prefix="hicrep-ref-")


def sampled(uri, args, name):
    path = os.path.join(tmp, name + ".cool")
    subprocess.run([binary, "sample", uri, *args, "-o", path], check=True)
    return path


gm = os.path.join(data, "hg19.GM12878-MboI.matrix.2000kb.cool")
clr = cooler.Cooler(gm)
sizes = os.path.join(tmp, "hg19.sizes")
clr.chromsizes.to_csv(sizes, sep="\t", header=False)
pairs_cool = os.path.join(tmp, "gm12878_pairs.2000kb.cool")
subprocess.run(
    ["cooler", "cload", "pairs", "-c1", "1", "-p1", "2", "-c2", "4", "-p2", "5",
     f"{sizes}:2000000", os.path.join(data, "hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz"),
     pairs_cool],
    check=True,
)
dm6 = os.path.join(data, "cooler_test_file.mcool") + "::/resolutions/100000"
cases = [
    ("gm12878", gm, pairs_cool, [(0, -1), (1, 20_000_000), (2, 50_000_000), (5, -1)]),
    ("yeast", os.path.join(data, "yeast.10kb.cool"),
     sampled(os.path.join(data, "yeast.10kb.cool"), ["--fraction", "0.3", "--seed", "30"], "yeast"),
     [(0, 500_000), (2, 200_000), (5, 5_000_000), (10, -1)]),
    ("mm9", os.path.join(data, "CN.mm9.10000kb.cool"),
     sampled(os.path.join(data, "CN.mm9.10000kb.cool"), ["--fraction", "0.05", "--seed", "31"], "mm9"),
     [(0, 100_000_000), (1, 50_000_000), (3, -1)]),
    ("dm6", dm6, sampled(dm6, ["--count", "10000000", "--seed", "32"], "dm6"),
     [(1, 5_000_000), (3, 2_000_000), (5, 5_000_000)]),
    ("sim", os.path.join(data, "sim_extrusion.5kb.cool"),
     sampled(os.path.join(data, "sim_extrusion.5kb.cool"), ["--fraction", "0.5", "--seed", "33"], "sim"),
     [(0, 200_000), (2, 500_000), (4, -1)]),
]
rows = []
for name, a, b, settings in cases:
    c1, c2 = cooler.Cooler(a), cooler.Cooler(b)
    for h, dmax in settings:
        for chrom in c1.chromnames:
            try:
                value = hicrepSCC(c1, c2, h, dmax, False, chrNames=[chrom])[0]
                text = repr(float(value)) if not np.isnan(value) else "nan"
            except AssertionError:
                text = "assert"
            rows.append((name, h, dmax, chrom, text))
os.makedirs(out_dir, exist_ok=True)
out = os.path.join(out_dir, "scc.tsv.gz")
text = pd.DataFrame(rows, columns=["case", "h", "max_distance", "chrom", "scc"]).to_csv(
    sep="\t", index=False
)
with gzip.GzipFile(out, "wb", mtime=0) as f:
    f.write(text.encode())
print(f"{len(rows)} rows written to {out}")

import hicreppy.utils.mat_process as cu
from hicreppy.hicrep import get_scc

yeast_a = cooler.Cooler(os.path.join(data, "yeast.10kb.cool"))
yeast_b = cooler.Cooler(cases[1][2])
rows = []
for max_dist in (500_000, 200_000):
    max_bins = max_dist // yeast_a.binsize
    for h in (0, 2, 5):
        for chrom in yeast_a.chromnames:
            if yeast_a.chromsizes[chrom] < max((2 * h + 1) * yeast_a.binsize, max_dist):
                continue  # hicreppy drops chromosomes shorter than its kernel or max_dist
            m = [
                cu.diag_trim(c.matrix(sparse=True, balance=False).fetch(chrom).todia(), max_bins + h).tocoo()
                for c in (yeast_a, yeast_b)
            ]
            value = get_scc(cu.smooth(m[0], h), cu.smooth(m[1], h), max_bins=max_bins)
            rows.append((max_dist, h, chrom, repr(float(value))))
text = pd.DataFrame(rows, columns=["max_distance", "h", "chrom", "scc"]).to_csv(sep="\t", index=False)
out = os.path.join(out_dir, "hicreppy.tsv.gz")
with gzip.GzipFile(out, "wb", mtime=0) as f:
    f.write(text.encode())
print(f"{len(rows)} rows written to {out}")

from cooltools.api.coverage import coverage
from cooltools.api.virtual4c import virtual4c

mm9 = cooler.Cooler(os.path.join(data, "CN.mm9.10000kb.cool"))
sections = []


def coverage_table(clr, ignore_diags, weight):
    cis, tot = coverage(clr, ignore_diags=ignore_diags, clr_weight_name=weight)
    table = clr.bins()[:][["chrom", "start", "end"]]
    suffix = "raw" if weight is None else weight
    kind = int if weight is None else float
    table[f"cov_cis_{suffix}"] = cis.astype(kind)
    table[f"cov_tot_{suffix}"] = tot.astype(kind)
    return table


def v4c_table(clr, viewpoint, weight):
    return virtual4c(clr, viewpoint, clr_weight_name=weight)


for name, table in [
    ("coverage_mm9_raw", coverage_table(mm9, None, None)),
    ("coverage_mm9_weight", coverage_table(mm9, None, "weight")),
    ("coverage_mm9_raw0", coverage_table(mm9, 0, None)),
    ("v4c_mm9_weight", v4c_table(mm9, "chr1:50000000-60000000", "weight")),
    ("v4c_mm9_raw", v4c_table(mm9, "chr2:35000000-55000000", None)),
    ("v4c_mm9_partial", v4c_table(mm9, "chr3:55000000-72000000", "weight")),
]:
    table = table[table["chrom"].isin(["chr1", "chr2", "chr3", "chr4"])]
    sections.append(f"## {name}\n" + table.to_csv(sep="\t", index=False, na_rep="nan"))
out = os.path.join(out_dir, "cooltools.tsv.gz")
with gzip.GzipFile(out, "wb", mtime=0) as f:
    f.write("".join(sections).encode())
print(f"{len(sections)} cooltools tables written to {out}")
