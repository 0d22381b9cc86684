#!/usr/bin/env python3
"""CHESS 0.3.8 (`chess sim`) on small maps of data/, the references of `diff regions`.

Run from anywhere with a Python that has chess-hic 0.3.8 (it pulls FAN-C 0.9.28, cooler 0.11,
scikit-image; the run that made the committed files used Python 3.11.7, numpy 2.4.6,
scipy 1.17.1, scikit-image 0.26.0, pandas 3.1.1, intervaltree 3.2.1):

    python3 -m venv /tmp/chess_venv
    /tmp/chess_venv/bin/pip install chess-hic==0.3.8
    nice -n 19 /tmp/chess_venv/bin/python scripts/chess_references.py

It runs chess's own command line (`<venv>/bin/chess pairs` and `chess sim`, one process, the
defaults: relative window 1, mappability cutoff 0.1, no background) in a temporary folder, and
writes three files into data/diff/chess/ (gzip with mtime 0; about 7 KB in all):

- `pairs.tsv.gz`: the window pairs of every case, as `chess pairs <sizes> WINDOW STEP
  --file-input [--chromosome C]` wrote them (`<sizes>` is the reference cooler's chromosome
  table): a header `case chrom1 start1 end1 chrom2 start2 end2 ID score strand1 strand2`, then
  each line of each case's pairs file prefixed with the case's name and a tab (cases in the order
  sim, yeast, yeast_chrI, hg19);
- `sim.tsv.gz`: `chess sim REF QUERY PAIRS OUT` of every case: a header `case ID SN ssim z_ssim`,
  then each line of the file chess writes (less its header `ID SN ssim z_ssim`; floats as
  Python's repr, `nan` where chess gives none) prefixed with the case's name and a tab, cases in
  the same order;
- `chess.json`: versions, each case's inputs, window / step, commands and the query's
  perturbation rules, and the largest difference between chess and the plain NumPy
  reimplementation below (`reimplement`), which the script checks before writing anything.

The cases (the reference is the committed map; the query is made here, in a temporary folder,
never committed; a test rebuilds it with the same rules):

- `sim`: data/sim_extrusion.5kb.cool (1 chromosome, 200 bins of 5 kb, balanced) against a
  perturbed copy; windows of 150 kb every 25 kb (35 pairs, 30 bins each);
- `yeast`: data/yeast.10kb.cool (18 chromosomes, 1226 bins of 10 kb, balanced, 42 NaN
  weights) against a perturbed copy; windows of 400 kb every 200 kb genome-wide (36 pairs);
- `yeast_chrI`: the same two maps, chrI only, windows of 215 kb every 5 kb (4 pairs): windows
  off the bin edges (22 bins each), and cells whose O/E is NaN (0 / 0, see the case);
- `hg19`: data/hg19.GM12878-MboI.matrix.2000kb.cool (no weight column: chess uses the raw
  counts) against a perturbed copy; chr2 only, windows of 50 Mb every 10 Mb (20 pairs).

The query of a case is the reference's bins table (with its `weight` column, if any, copied
unchanged) and its pixels, changed by the case's rules in order (bin ids are the cooler's,
genome-wide, 0-based; pixels are the stored upper-triangle ones, bin1 <= bin2; counts int32):

- `multiply` [a, b) x [c, d) by f: every pixel with a <= bin1 < b and c <= bin2 < d gets
  count * f;
- `ceil_div` [a, b) x [c, d) by q: those pixels get ceil(count / q) = (count + q - 1) // q
  (at least 1, no pixel disappears);
- `drop_bins` B: every pixel with bin1 in B or bin2 in B (trans pixels too) is removed;
- `nan_weight` B: the weight of the bins in B becomes NaN (their pixels stay).

Written with `cooler.create_cooler(path, bins, pixels, ordered=True)`.
"""

import gzip
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import cooler
import numpy as np
import pandas as pd
from numpy.lib.stride_tricks import sliding_window_view

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
DATA = os.path.join(ROOT, "data")
OUT = os.path.join(DATA, "diff", "chess")
CHESS = os.path.join(os.path.dirname(sys.executable), "chess")

YEAST_RULES = [
    # chrI (bins 9-32): a block gains contacts
    {"op": "multiply", "bin1": [12, 21], "bin2": [12, 21], "factor": 3},
    # chrIV (bins 147-300): a domain gains contacts
    {"op": "multiply", "bin1": [192, 222], "bin2": [192, 222], "factor": 3},
    # chrVII (bins 387-496): a block loses them
    {"op": "ceil_div", "bin1": [397, 407], "bin2": [417, 427], "divisor": 4},
    # chrXII (bins 740-847): 5 empty bins, 5 / 40 > 0.1: NaN for the windows with them
    {"op": "drop_bins", "bins": [765, 766, 767, 768, 769]},
    # chrXIII (bins 848-940): 4 empty bins, 4 / 40 = 0.1: compared, 36 bins left
    {"op": "drop_bins", "bins": [898, 899, 900, 901]},
]

CASES = [
    {
        "name": "sim",
        "reference": "sim_extrusion.5kb.cool",
        "window": 150_000,
        "step": 25_000,
        "chromosome": None,
        "rules": [
            # a domain that gains contacts (bins 60-89 among themselves)
            {"op": "multiply", "bin1": [60, 90], "bin2": [60, 90], "factor": 3},
            # a loop-like block that loses them (around the loop 610-615 kb x 760-765 kb)
            {"op": "ceil_div", "bin1": [118, 128], "bin2": [148, 158], "divisor": 4},
            # one empty bin: masked (row of default 1.0) and removed from both maps
            {"op": "drop_bins", "bins": [100]},
            # three empty bins: 3 / 30 = 0.1 is not above the cutoff, the pair is compared
            {"op": "drop_bins", "bins": [170, 171, 172]},
            # four more: windows that hold 7 (or 4) of them are above the cutoff: NaN
            {"op": "drop_bins", "bins": [185, 186, 187, 188]},
            # a bin with pixels but a NaN weight: its O/E row is 0, not masked
            {"op": "nan_weight", "bins": [40]},
        ],
    },
    {
        "name": "yeast",
        "reference": "yeast.10kb.cool",
        "window": 400_000,
        "step": 200_000,
        "chromosome": None,
        "rules": YEAST_RULES,
    },
    {
        # windows not on bin edges (a window takes every bin it overlaps: 22 bins here), and
        # FAN-C's NaN O/E: chrI's bins 21-23 have NaN weights, so its diagonal 21 sums to 0
        # over 3 possible pairs, and pixel (0, 21) is 0 / 0 = NaN: the windows that hold it
        # get ssim NaN but a finite SN
        "name": "yeast_chrI",
        "reference": "yeast.10kb.cool",
        "window": 215_000,
        "step": 5_000,
        "chromosome": "chrI",
        "rules": YEAST_RULES,
    },
    {
        "name": "hg19",
        "reference": "hg19.GM12878-MboI.matrix.2000kb.cool",
        "window": 50_000_000,
        "step": 10_000_000,
        "chromosome": "chr2",
        "rules": [
            # chr2 (bins 125-246): a domain gains contacts
            {"op": "multiply", "bin1": [155, 170], "bin2": [155, 170], "factor": 3},
            # and a block loses them
            {"op": "ceil_div", "bin1": [200, 205], "bin2": [210, 220], "divisor": 4},
        ],
    },
]


# --------------------------------------------------------------------------------------------
# the query


def make_query(ref_path, rules, path):
    clr = cooler.Cooler(ref_path)
    bins = clr.bins()[:]
    pixels = clr.pixels()[:]
    count = pixels["count"].to_numpy().astype(np.int64)
    b1 = pixels["bin1_id"].to_numpy()
    b2 = pixels["bin2_id"].to_numpy()
    keep = np.ones(len(pixels), dtype=bool)
    for rule in rules:
        op = rule["op"]
        if op in ("multiply", "ceil_div"):
            (a, b), (c, d) = rule["bin1"], rule["bin2"]
            sel = (b1 >= a) & (b1 < b) & (b2 >= c) & (b2 < d)
            if op == "multiply":
                count[sel] = count[sel] * rule["factor"]
            else:
                q = rule["divisor"]
                count[sel] = (count[sel] + q - 1) // q
        elif op == "drop_bins":
            drop = np.isin(b1, rule["bins"]) | np.isin(b2, rule["bins"])
            keep &= ~drop
        elif op == "nan_weight":
            bins.loc[rule["bins"], "weight"] = np.nan
        else:
            raise ValueError(op)
    assert count.max() < 2**31
    out = pd.DataFrame(
        {"bin1_id": b1[keep], "bin2_id": b2[keep], "count": count[keep].astype(np.int32)}
    )
    cooler.create_cooler(path, bins, out, ordered=True)


# --------------------------------------------------------------------------------------------
# a plain reimplementation (what /tmp/chess_spec.md describes), checked against chess


def oe_by_chromosome(path):
    """FAN-C's per-chromosome O/E of a cooler, dense, 1.0 where no pixel is stored."""
    clr = cooler.Cooler(path)
    bins = clr.bins()[:]
    pix = clr.pixels()[:]
    nb = len(bins)
    if "weight" in bins:
        w = bins["weight"].to_numpy(dtype=np.float64)
        w = np.where(np.isfinite(w), w, 0.0)
    else:
        w = np.ones(nb)
    b1 = pix["bin1_id"].to_numpy()
    b2 = pix["bin2_id"].to_numpy()
    cnt = pix["count"].to_numpy().astype(np.float64)
    mappable = np.zeros(nb, dtype=bool)
    mappable[b1] = True
    mappable[b2] = True
    out = {}
    for chrom in clr.chromnames:
        lo, hi = clr.extent(chrom)
        n = hi - lo
        sel = (b1 >= lo) & (b1 < hi) & (b2 >= lo) & (b2 < hi)
        i, j, c = b1[sel], b2[sel], cnt[sel]
        d = j - i
        v = c * (w[i] * w[j])
        sums = np.bincount(d, weights=v, minlength=n)
        m = mappable[lo:hi].astype(np.int64)
        possible = np.array([np.sum(m[: n - k] * m[k:]) for k in range(n)], dtype=np.float64)
        expected = np.zeros(n)
        nz = possible > 0
        expected[nz] = sums[nz] / possible[nz]
        with np.errstate(divide="ignore", invalid="ignore"):
            oe = v / expected[d]
        dense = np.ones((n, n))
        dense[i - lo, j - lo] = oe
        dense[j - lo, i - lo] = oe
        starts = bins["start"].to_numpy()[lo:hi]
        ends = bins["end"].to_numpy()[lo:hi]
        out[chrom] = (dense, starts, ends)
    return out


def ssim(x, y, win, data_range):
    """skimage's structural_similarity (uniform window, sample covariance, K1 0.01, K2 0.03)."""
    np_ = win * win
    cov_norm = np_ / (np_ - 1)
    c1 = (0.01 * data_range) ** 2
    c2 = (0.03 * data_range) ** 2

    def mean(a):
        return sliding_window_view(a, (win, win)).mean(axis=(2, 3))

    ux, uy = mean(x), mean(y)
    vx = cov_norm * (mean(x * x) - ux * ux)
    vy = cov_norm * (mean(y * y) - uy * uy)
    vxy = cov_norm * (mean(x * y) - ux * uy)
    s = ((2 * ux * uy + c1) * (2 * vxy + c2)) / ((ux**2 + uy**2 + c1) * (vx + vy + c2))
    return float(s.mean())


def signal_to_noise(x, y, size=7):
    m = x - y
    h = size // 2
    p = np.full((m.shape[0] + 2 * h, m.shape[1] + 2 * h), np.nan)
    p[h:-h, h:-h] = m
    win = sliding_window_view(p, (size, size))
    with np.errstate(divide="ignore", invalid="ignore"):
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mu = np.nanmean(win, axis=(2, 3))
            var = np.nanvar(win, axis=(2, 3))
            return float(np.nanmean(np.abs(mu) / var))


def compare(r, q, min_bins=20, cutoff=0.1):
    n = r.shape[0]
    if n < min_bins or q.shape[0] < min_bins:
        return math.nan, math.nan
    masked = []
    for m in (r, q):
        idx = np.where(np.sum(m, 0) == n * 1)[0]
        if len(idx) / n > cutoff:
            return math.nan, math.nan
        masked.append(idx)
    drop = np.union1d(*masked)
    keep = np.setdiff1d(np.arange(n), drop)
    r = r[np.ix_(keep, keep)]
    q = q[np.ix_(keep, keep)]
    win = r.shape[0]
    if win % 2 == 0:
        win -= 1
    win = max(win, 3)
    rng = max(r.max(), q.max()) - min(r.min(), q.min())
    return signal_to_noise(r, q), ssim(r, q, win, rng)


def reimplement(ref_path, qry_path, pairs_path):
    ref = oe_by_chromosome(ref_path)
    qry = oe_by_chromosome(qry_path)
    pairs = pd.read_csv(pairs_path, sep="\t", header=None, dtype={6: str})

    def sub(oe, chrom, start, end):
        dense, starts, ends = oe[chrom]
        idx = np.where((starts < end) & (ends > start))[0]
        lo, hi = idx.min(), idx.max()
        return dense[lo : hi + 1, lo : hi + 1].copy()

    rows = []
    for t in pairs.itertuples(index=False):
        r = sub(ref, t[0], t[1], t[2])
        q = sub(qry, t[3], t[4], t[5])
        assert r.shape == q.shape and t[8] == t[9]
        sn, s = compare(r, q)
        rows.append((t[6], sn, s))
    df = pd.DataFrame(rows, columns=["ID", "SN", "ssim"])
    ok = np.isfinite(df["ssim"].to_numpy())
    mu = df["ssim"][ok].mean()
    sd = df["ssim"][ok].std(ddof=0)
    df["z_ssim"] = np.where(ok, (df["ssim"] - mu) / sd, np.nan)
    return df


def max_difference(chess_df, ours):
    worst = {}
    assert list(chess_df["ID"]) == list(ours["ID"])
    for col in ("SN", "ssim", "z_ssim"):
        a = chess_df[col].to_numpy(dtype=np.float64)
        b = ours[col].to_numpy(dtype=np.float64)
        assert np.array_equal(np.isnan(a), np.isnan(b)), col
        f = ~np.isnan(a)
        rel = np.abs(a[f] - b[f]) / np.maximum(1.0, np.abs(a[f]))
        worst[col] = float(rel.max()) if f.any() else 0.0
    return worst


# --------------------------------------------------------------------------------------------


PAIRS_COLUMNS = ["chrom1", "start1", "end1", "chrom2", "start2", "end2", "ID", "score", "strand1",
                 "strand2"]
SIM_COLUMNS = ["ID", "SN", "ssim", "z_ssim"]


def write_gz(path, text):
    # mtime 0 and the file's own name less .gz in the header: the same text gives the same bytes
    with open(path, "wb") as raw:
        with gzip.GzipFile(filename=os.path.basename(path), mode="wb", fileobj=raw, mtime=0,
                           compresslevel=9) as f:
            f.write(text.encode())


def run(cmd, cwd):
    t0 = time.perf_counter()
    subprocess.run(cmd, cwd=cwd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0


def main():
    import chess
    import fanc
    import scipy
    import skimage

    os.makedirs(OUT, exist_ok=True)
    manifest = {
        "chess-hic": chess.__version__,
        "fanc": fanc.__version__,
        "cooler": cooler.__version__,
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "scikit-image": skimage.__version__,
        "pandas": pd.__version__,
        "python": sys.version.split()[0],
        "script": "scripts/chess_references.py",
        "cases": [],
    }
    pairs_lines = ["\t".join(["case"] + PAIRS_COLUMNS)]
    sim_lines = ["\t".join(["case"] + SIM_COLUMNS)]
    with tempfile.TemporaryDirectory(prefix="chess_refs_") as tmp:
        for case in CASES:
            name = case["name"]
            ref = os.path.join(DATA, case["reference"])
            qry = os.path.join(tmp, f"{name}.query.cool")
            make_query(ref, case["rules"], qry)

            sizes = os.path.join(tmp, f"{name}.sizes")
            cooler.Cooler(ref).chroms()[:].to_csv(sizes, sep="\t", header=False, index=False)
            pairs = os.path.join(tmp, f"{name}.pairs.bedpe")
            pcmd = [CHESS, "pairs", sizes, str(case["window"]), str(case["step"]), pairs,
                    "--file-input"]
            if case["chromosome"]:
                pcmd += ["--chromosome", case["chromosome"]]
            run(pcmd, tmp)

            sim = os.path.join(tmp, f"{name}.sim.tsv")
            seconds = run([CHESS, "sim", ref, qry, pairs, sim], tmp)

            chess_df = pd.read_csv(sim, sep="\t", dtype={"ID": str})
            ours = reimplement(ref, qry, pairs)
            worst = max_difference(chess_df, ours)
            assert max(worst.values()) < 1e-9, worst
            s = chess_df["ssim"]
            print(
                f"{name}: {len(chess_df)} pairs, {s.isna().sum()} NaN, ssim "
                f"{s.min():.4f}..{s.max():.4f}, chess sim {seconds:.1f} s, "
                f"reimplementation within {max(worst.values()):.1e}"
            )
            print(chess_df.to_string(index=False))

            with open(pairs) as f:
                lines = f.read().splitlines()
            assert len(lines) == len(chess_df)
            assert all(len(line.split("\t")) == len(PAIRS_COLUMNS) for line in lines)
            pairs_lines += [f"{name}\t{line}" for line in lines]
            with open(sim) as f:
                lines = f.read().splitlines()
            assert lines[0] == "\t".join(SIM_COLUMNS), lines[0]
            assert len(lines) == len(chess_df) + 1
            sim_lines += [f"{name}\t{line}" for line in lines[1:]]
            manifest["cases"].append(
                {
                    "name": name,
                    "reference": "data/" + case["reference"],
                    "window": case["window"],
                    "step": case["step"],
                    "chromosome": case["chromosome"],
                    "pairs_command": "chess pairs <reference's chroms table> "
                    f"{case['window']} {case['step']} {name}.pairs.bedpe --file-input"
                    + (f" --chromosome {case['chromosome']}" if case["chromosome"] else ""),
                    "sim_command": f"chess sim data/{case['reference']} {name}.query.cool "
                    f"{name}.pairs.bedpe {name}.sim.tsv",
                    "query_rules": case["rules"],
                    "pairs": len(chess_df),
                    "nan_pairs": int(s.isna().sum()),
                    "reimplementation_max_rel_difference": worst,
                }
            )

    write_gz(os.path.join(OUT, "pairs.tsv.gz"), "\n".join(pairs_lines) + "\n")
    write_gz(os.path.join(OUT, "sim.tsv.gz"), "\n".join(sim_lines) + "\n")
    # one line per rule and per difference table
    inline = {}
    for c in manifest["cases"]:
        for key in ("query_rules",):
            c[key] = [inline.setdefault(f"@{len(inline)}@", r) and f"@{len(inline) - 1}@"
                      for r in c[key]]
        key = "reimplementation_max_rel_difference"
        inline[f"@{len(inline)}@"] = c[key]
        c[key] = f"@{len(inline) - 1}@"
    text = json.dumps(manifest, indent=1)
    for token, value in inline.items():
        text = text.replace(json.dumps(token), json.dumps(value))
    with open(os.path.join(OUT, "chess.json"), "w") as f:
        f.write(text + "\n")
    total = sum(os.path.getsize(os.path.join(OUT, f))
                for f in ("chess.json", "pairs.tsv.gz", "sim.tsv.gz"))
    print(f"wrote {OUT}: {total} bytes")


if __name__ == "__main__":
    main()
