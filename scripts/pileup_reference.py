#!/usr/bin/env python3
"""coolpuppy 1.1.0 and cooltools 0.7.1 pileup references for `contactmap pileup` (tests/,
issue 29).

Usage: pileup_reference.py OUT_DIR   (run from the repository root; needs coolpuppy 1.1.0,
cooltools 0.7.1, pandas < 3)

Every case goes into pileups.tsv.gz, led by a line `## NAME`; each holds one block per group
(the group of all snippets last; ungrouped
cases have only that one), each a header line `# n=N [control_n=M] [group=LABEL]` then the
pileup grid (tab-separated, `nan` for NaN, Python's repr of each float). LABEL is as contactmap
prints it: strands `+-`, distance band `0.05Mb-0.1Mb` or `0.4Mb+`, then the values of the
groupby columns, joined by `,`.

On data/sim_extrusion.5kb.cool (balanced, 5 kb) with cooltools' expected_cis (defaults):
  bedpe_oe     the truth loops (data/sim_extrusion.truth_loops.bedpe), observed/expected, flank 20 kb
  bed_raw      ten anchors (anchors.bed) paired, raw counts, flank 30 kb, maxdist 400 kb
  bed_local_oe the same anchors on the diagonal (local), observed/expected, flank 50 kb
  bed_oe       the anchors paired, balanced, observed/expected, flank 20 kb, mindist 100 kb
  bed_local_rescale_oe  four domains (domains.bed) on the diagonal, rescaled (flank 1, 33
               pixels), observed/expected
  bedpe_rescale_shifts  the truth loops rescaled (flank 2, 11 pixels), 2 shifted controls, seed 3
  bed_shifts   the anchors paired, 5 shifted controls, seed 7, flank 30 kb
  bed_local_shifts  the anchors on the diagonal, 3 shifted controls, seed 1, flank 50 kb
  bed_by_distance_oe  the anchors paired, by distance band (coolpuppy's edges), observed/expected,
               flank 20 kb, mindist 100 kb
  bed_by_distance_raw  the anchors paired, raw counts, edges 150, 300, 600 kb, flank 30 kb
  bed_by_strand_flip_oe  the stranded anchors (anchors.stranded.bed) by strand, minus-strand
               snippets flipped, observed/expected, flank 20 kb, mindist 100 kb
  bed_groupby_oe  the anchors with a class in their name column (anchors.grouped.bed, no header)
               paired, grouped by name1 and name2, observed/expected, flank 20 kb, mindist 100 kb
  bedpe_groupby_shifts  the truth loops with a class column (loops.grouped.bedpe, header),
               grouped by it, 3 shifted controls, seed 9, flank 20 kb
On data/yeast.10kb.cool (a real map, with masked bins), cooltools' expected_cis:
  yeast_bed_oe  anchors (yeast_anchors.bed) paired, observed/expected, flank 30 kb, maxdist 300 kb
  yeast_local_rescale_oe  domains (yeast_domains.bed) rescaled (flank 1, 21 pixels), obs/exp
  yeast_bed_shifts  the anchors paired, 4 shifted controls, seed 5, flank 30 kb, maxdist 300 kb
  yeast_trans_oe  the anchors paired between chromosomes (trans: chrII x chrIV), observed over
               cooltools' expected_trans, flank 30 kb
  yeast_trans_shifts  the same, 2 shifted controls, seed 4
  yeast_trans_bedpe_raw  12 chrII-chrIV pairs (yeast_trans.bedpe), trans, raw counts, flank
               20 kb, mindist 0 (coolpuppy applies mindist to trans pairs too)
Coverage normalisation (raw counts; coolpuppy stores the coverage in the cooler, so it runs on
copies of the maps in a temporary directory):
  bed_covnorm  the anchors paired, flank 30 kb
  bedpe_covnorm_shifts  the truth loops, 3 shifted controls, seed 2, flank 20 kb
  yeast_bed_covnorm  the yeast anchors paired, flank 30 kb, maxdist 300 kb (total coverage: trans
               pixels count)
cooltools 0.7.1 `pileup` (the nanmean of its snippet stack) where the two overlap:
  cooltools_bedpe_oe        the truth loops, observed/expected, flank 20 kb
  cooltools_yeast_local_oe  the yeast anchors on the diagonal, observed/expected, flank 30 kb
and scores.tsv: coolpuppy's scores (lib/numutils.py) of those pileups (case, score, argument,
value).
"""
import gzip
import logging
import os
import shutil
import sys
import tempfile
import warnings

import cooler
import cooltools
import cooltools.lib
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


def bed(name, names=("chrom", "start", "end")):
    return pd.read_csv(os.path.join("data/reference/pileup", name), sep="\t", header=None,
                       names=list(names))


anchors = bed("anchors.bed")
domains = bed("domains.bed")
stranded = bed("anchors.stranded.bed", ("chrom", "start", "end", "name", "score", "strand"))
yeast = cooler.Cooler("data/yeast.10kb.cool")
yeast_expected = cooltools.expected_cis(yeast, nproc=1)
yeast_anchors = bed("yeast_anchors.bed")
yeast_domains = bed("yeast_domains.bed")


def mb(bp):
    return f"{float(bp) / 1e6!r}Mb"


def label(row, groupby=()):
    if isinstance(row["group"], str) and row["group"] == "all":
        return "all"
    parts = []
    if "strand1" in row.index:
        parts.append(f"{row['strand1']}{row['strand2']}")
    if "distance_band" in row.index:
        band = row["distance_band"]
        parts.append(f"{mb(band[0])}-{mb(band[1])}" if len(band) == 2 else f"{mb(band[0])}+")
    parts.extend(str(row[column]) for column in groupby)
    return ",".join(parts)


def grid_lines(f, data):
    for row in data:
        f.write("\t".join("nan" if np.isnan(v) else repr(float(v)) for v in row) + "\n")


def write(name, pup, groupby=()):
    """Every group (the group of all last); returns the grid of all."""
    label = globals()["label"]
    if groupby:
        label = lambda row, plain=label: plain(row, groupby)  # noqa: E731
    rows = [r for _, r in pup.iterrows()]
    rows = [r for r in rows if label(r) != "all"] + [r for r in rows if label(r) == "all"]
    with gzip.open(os.path.join(out, f"{name}.tsv.gz"), "wt") as f:
        for row in rows:
            head = f"# n={int(row['n'])}"
            if "control_n" in row.index:
                head += f" control_n={int(row['control_n'])}"
            if label(row) != "all":
                head += f" group={label(row)}"
            f.write(head + "\n")
            grid_lines(f, row["data"])
    print(name, rows[-1]["data"].shape, [(label(r), int(r["n"])) for r in rows])
    return rows[-1]["data"]


def write_stack_mean(name, stack):
    """cooltools' snippet stack (n x D x D): its nanmean over the snippets."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = np.nanmean(stack, axis=0)
    with gzip.open(os.path.join(out, f"{name}.tsv.gz"), "wt") as f:
        f.write(f"# n={stack.shape[0]}\n")
        grid_lines(f, data)
    print(name, data.shape, stack.shape[0])


pups = {
    "bedpe_oe": write("bedpe_oe", coolpup.pileup(
        clr, loops, features_format="bedpe", expected_df=expected, flank=20000)),
    "bed_raw": write("bed_raw", coolpup.pileup(
        clr, anchors, features_format="bed", clr_weight_name=None, flank=30000, maxdist=400000)),
    "bed_local_oe": write("bed_local_oe", coolpup.pileup(
        clr, anchors, features_format="bed", local=True, expected_df=expected, flank=50000)),
    "bed_oe": write("bed_oe", coolpup.pileup(
        clr, anchors, features_format="bed", expected_df=expected, flank=20000, mindist=100000)),
    "bed_local_rescale_oe": write("bed_local_rescale_oe", coolpup.pileup(
        clr, domains, features_format="bed", local=True, rescale=True, rescale_flank=1,
        rescale_size=33, expected_df=expected)),
    "bedpe_rescale_shifts": write("bedpe_rescale_shifts", coolpup.pileup(
        clr, loops, features_format="bedpe", rescale=True, rescale_flank=2, rescale_size=11,
        nshifts=2, seed=3)),
    "bed_shifts": write("bed_shifts", coolpup.pileup(
        clr, anchors, features_format="bed", nshifts=5, seed=7, flank=30000)),
    "bed_local_shifts": write("bed_local_shifts", coolpup.pileup(
        clr, anchors, features_format="bed", local=True, nshifts=3, seed=1, flank=50000)),
    "bed_by_distance_oe": write("bed_by_distance_oe", coolpup.pileup(
        clr, anchors, features_format="bed", expected_df=expected, flank=20000, mindist=100000,
        by_distance=True)),
    "bed_by_distance_raw": write("bed_by_distance_raw", coolpup.pileup(
        clr, anchors, features_format="bed", clr_weight_name=None, flank=30000,
        by_distance=[150000, 300000, 600000])),
    "bed_by_strand_flip_oe": write("bed_by_strand_flip_oe", coolpup.pileup(
        clr, stranded, features_format="bed", expected_df=expected, flank=20000, mindist=100000,
        by_strand=True, flip_negative_strand=True)),
    "yeast_bed_oe": write("yeast_bed_oe", coolpup.pileup(
        yeast, yeast_anchors, features_format="bed", expected_df=yeast_expected, flank=30000,
        maxdist=300000)),
    "yeast_local_rescale_oe": write("yeast_local_rescale_oe", coolpup.pileup(
        yeast, yeast_domains, features_format="bed", local=True, rescale=True, rescale_flank=1,
        rescale_size=21, expected_df=yeast_expected)),
    "yeast_bed_shifts": write("yeast_bed_shifts", coolpup.pileup(
        yeast, yeast_anchors, features_format="bed", nshifts=4, seed=5, flank=30000,
        maxdist=300000)),
}
grouped = bed("anchors.grouped.bed", ("chrom", "start", "end", "name"))
pups["bed_groupby_oe"] = write("bed_groupby_oe", coolpup.pileup(
    clr, grouped, features_format="bed", expected_df=expected, flank=20000, mindist=100000,
    groupby=["name1", "name2"]), ("name1", "name2"))
grouped_loops = pd.read_csv("data/reference/pileup/loops.grouped.bedpe", sep="\t")
pups["bedpe_groupby_shifts"] = write("bedpe_groupby_shifts", coolpup.pileup(
    clr, grouped_loops, features_format="bedpe", nshifts=3, seed=9, flank=20000,
    groupby=["class"]), ("class",))
yeast_trans_expected = cooltools.expected_trans(yeast, nproc=1)
pups["yeast_trans_oe"] = write("yeast_trans_oe", coolpup.pileup(
    yeast, yeast_anchors, features_format="bed", trans=True, expected_df=yeast_trans_expected,
    flank=30000))
pups["yeast_trans_shifts"] = write("yeast_trans_shifts", coolpup.pileup(
    yeast, yeast_anchors, features_format="bed", trans=True, nshifts=2, seed=4, flank=30000))
trans_pairs = pd.read_csv("data/reference/pileup/yeast_trans.bedpe", sep="\t", header=None,
                          names=["chrom1", "start1", "end1", "chrom2", "start2", "end2"])
pups["yeast_trans_bedpe_raw"] = write("yeast_trans_bedpe_raw", coolpup.pileup(
    yeast, trans_pairs, features_format="bedpe", trans=True, clr_weight_name=None, flank=20000,
    mindist=0))
copies = tempfile.mkdtemp()
for name in ["sim_extrusion.5kb.cool", "yeast.10kb.cool"]:
    shutil.copy(os.path.join("data", name), copies)
sim_copy = cooler.Cooler(os.path.join(copies, "sim_extrusion.5kb.cool"))
yeast_copy = cooler.Cooler(os.path.join(copies, "yeast.10kb.cool"))
# coolpuppy 1.1.0 computes missing coverage columns with a call that cooltools 0.7.1 refuses
# (`map=`): store them first, as it would (cooltools coverage, ignore_diags = 2, raw)
for c in [sim_copy, yeast_copy]:
    cooltools.coverage(c, ignore_diags=2, store=True)
pups["bed_covnorm"] = write("bed_covnorm", coolpup.pileup(
    sim_copy, anchors, features_format="bed", clr_weight_name=None, coverage_norm=True,
    flank=30000))
pups["bedpe_covnorm_shifts"] = write("bedpe_covnorm_shifts", coolpup.pileup(
    sim_copy, loops, features_format="bedpe", clr_weight_name=None, coverage_norm=True,
    nshifts=3, seed=2, flank=20000))
pups["yeast_bed_covnorm"] = write("yeast_bed_covnorm", coolpup.pileup(
    yeast_copy, yeast_anchors, features_format="bed", clr_weight_name=None, coverage_norm=True,
    flank=30000, maxdist=300000))
shutil.rmtree(copies)
write_stack_mean("cooltools_bedpe_oe", cooltools.pileup(
    clr, loops, expected_df=expected, flank=20000))
write_stack_mean("cooltools_yeast_local_oe", cooltools.pileup(
    yeast, yeast_anchors, view_df=cooltools.lib.make_cooler_view(yeast),
    expected_df=yeast_expected, flank=30000))

# one file for all the cases (each led by `## NAME`): small files cost a disk block each
names = sorted(f[:-7] for f in os.listdir(out) if f.endswith(".tsv.gz") and f != "pileups.tsv.gz")
with open(os.path.join(out, "pileups.tsv.gz"), "wb") as raw:
    with gzip.GzipFile(fileobj=raw, mode="wb", mtime=0) as f:
        for name in names:
            f.write(f"## {name}\n".encode())
            with gzip.open(os.path.join(out, f"{name}.tsv.gz")) as case:
                f.write(case.read())
            os.remove(os.path.join(out, f"{name}.tsv.gz"))

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
    for case in ["bed_local_rescale_oe", "yeast_local_rescale_oe"]:
        for score, fn in [("domain_score", numutils.get_domain_score),
                          ("local_enrichment", numutils.get_local_enrichment)]:
            f.write(f"{case}\t{score}\t1\t{float(fn(pups[case], 1))!r}\n")
    for case in ["bed_shifts", "yeast_bed_oe", "yeast_bed_shifts", "bedpe_rescale_shifts",
                 "yeast_trans_oe", "yeast_trans_shifts", "bed_groupby_oe"]:
        f.write(f"{case}\tenrichment\t3\t{float(numutils.get_enrichment(pups[case], 3))!r}\n")
