"""Check a .hic written by `contactmap convert` with independent readers.

usage: python scripts/check_hic_writer.py SOURCE.cool OUT.hic CONTACTMAP [--straw-full]

For every resolution of OUT.hic:
1. pixels: hictkpy 1.4 `File(OUT.hic, res).fetch()` equals the source cooler's pixels coarsened
   by pandas (bin1 // f, bin2 // f within each chromosome, counts summed, as float32);
2. straw (hic-straw, the Aiden lab's reader): per chromosome pair, the number of records and the
   sum of counts equal the reference (every record too with --straw-full or a small file);
3. normalisation vectors: hictkpy `weights(name, divisive=True)` equal 1 / the weights that
   `contactmap balance OUT.hic::/resolutions/res --method M --cis-only` computes from the same
   file (relative 1e-6: the .hic stores float32), with the same NaN bins; straw's normalised
   records of the first chromosome equal count / (v_i v_j) with those vectors.
Prints one line per check and exits non-zero if any fails.
"""
import subprocess
import sys
import io

import cooler
import hictkpy
import hicstraw
import numpy as np
import pandas as pd

src, out, contactmap = sys.argv[1:4]
straw_full = "--straw-full" in sys.argv
clr = cooler.Cooler(src)
base = clr.binsize
bins = clr.bins()[["chrom", "start"]][:]
chrom_codes = bins["chrom"].cat.codes.values if hasattr(bins["chrom"], "cat") else pd.factorize(bins["chrom"])[0]
local_start = bins["start"].values // base
pixels = clr.pixels()[:]
failures = 0


def report(ok, what):
    global failures
    print(("ok    " if ok else "FAIL  ") + what)
    failures += 0 if ok else 1


resolutions = hictkpy.MultiResFile(out).resolutions() if hasattr(hictkpy, "MultiResFile") else None
resolutions = [int(r) for r in resolutions]
chroms = list(clr.chromnames)
sizes = clr.chromsizes
for res in resolutions:
    f = res // base
    nb = [int(-(-sizes[c] // res)) for c in chroms]
    offsets = np.concatenate([[0], np.cumsum(nb)[:-1]])
    c1 = chrom_codes[pixels.bin1_id.values]
    c2 = chrom_codes[pixels.bin2_id.values]
    b1 = offsets[c1] + local_start[pixels.bin1_id.values] // f
    b2 = offsets[c2] + local_start[pixels.bin2_id.values] // f
    ref = (pd.DataFrame({"bin1_id": b1, "bin2_id": b2, "count": pixels["count"].values.astype(np.float64)})
           .groupby(["bin1_id", "bin2_id"], sort=True)["count"].sum().reset_index())
    ref["count"] = ref["count"].astype(np.float32)
    hf = hictkpy.File(out, res)
    got = hf.fetch(count_type="float").to_df()
    got = got.sort_values(["bin1_id", "bin2_id"]).reset_index(drop=True)
    same = (len(got) == len(ref) and np.array_equal(got.bin1_id.values, ref.bin1_id.values)
            and np.array_equal(got.bin2_id.values, ref.bin2_id.values)
            and np.array_equal(got["count"].values.astype(np.float32), ref["count"].values))
    report(same, f"{res}: hictkpy pixels identical ({len(got)} pixels, sum {got['count'].sum():.0f})")

    # straw, per chromosome pair
    hs = hicstraw.HiCFile(out)
    ref_c1 = np.searchsorted(offsets, ref.bin1_id.values, side="right") - 1
    ref_c2 = np.searchsorted(offsets, ref.bin2_id.values, side="right") - 1
    straw_ok = True
    n_pairs = 0
    full = straw_full or len(ref) < 3_000_000
    for i, ci in enumerate(chroms):
        for j in range(i, len(chroms)):
            cj = chroms[j]
            sel = (ref_c1 == i) & (ref_c2 == j)
            if not sel.any():
                continue
            n_pairs += 1
            mzd = hs.getMatrixZoomData(ci, cj, "observed", "NONE", "BP", res)
            recs = mzd.getRecords(0, int(sizes[ci]), 0, int(sizes[cj]))
            xs = np.array([r.binX for r in recs], dtype=np.int64) // res  # straw gives positions in bp
            ys = np.array([r.binY for r in recs], dtype=np.int64) // res
            vs = np.array([r.counts for r in recs], dtype=np.float32)
            sub = ref[sel]
            if len(recs) != len(sub) or not np.isclose(vs.sum(dtype=np.float64), sub["count"].values.sum(dtype=np.float64), rtol=1e-9):
                straw_ok = False
                print(f"      straw {ci} {cj}: {len(recs)} records, reference {len(sub)}")
                continue
            if full:
                order = np.lexsort((ys, xs))
                lx = sub.bin1_id.values - offsets[i]
                ly = sub.bin2_id.values - offsets[j]
                if not (np.array_equal(xs[order], lx) and np.array_equal(ys[order], ly)
                        and np.array_equal(vs[order], sub["count"].values)):
                    straw_ok = False
                    print(f"      straw {ci} {cj}: records differ")
    report(straw_ok, f"{res}: straw records {'identical' if full else 'count and sum equal'} on {n_pairs} chromosome pairs")

    for name in hf.avail_normalizations():
        method = name.lower().replace("_", "-")
        table = subprocess.run([contactmap, "balance", f"{out}::/resolutions/{res}", "--method", method,
                                "--cis-only", "-o", "-"], capture_output=True, text=True, check=True).stdout
        ours = pd.read_csv(io.StringIO(table), sep="\t", comment="#")["weight"].values
        ours = np.where(np.isfinite(ours) & (ours > 0), 1.0 / ours, np.nan)
        stored = hf.weights(name, divisive=True)
        nan_same = np.array_equal(np.isnan(ours), np.isnan(stored))
        ok = np.isfinite(ours)
        exact = np.array_equal(stored[ok], ours[ok].astype(np.float32).astype(np.float64))
        rel = np.max(np.abs(stored[ok] / ours[ok] - 1)) if ok.any() else 0.0
        report(nan_same and exact,
               f"{res}: {name} read by hictkpy equals contactmap balance --method {method} --cis-only "
               f"rounded to float32 ({int(ok.sum())} values identical, {int((~ok).sum())} NaN bins; "
               f"{rel:.1e} from the float64 vector)")
        # straw applies the vector
        c = chroms[0]
        mzd = hs.getMatrixZoomData(c, c, "observed", name, "BP", res)
        recs = mzd.getRecords(0, int(sizes[c]), 0, int(sizes[c]))
        sub = ref[(ref_c1 == 0) & (ref_c2 == 0)]
        v = stored[: nb[0]]
        want = {(int(a), int(b)): float(cnt) / (v[a] * v[b]) for a, b, cnt in
                zip(sub.bin1_id.values, sub.bin2_id.values, sub["count"].values)}
        worst, n_compared = 0.0, 0
        for r in recs:
            w = want.get((r.binX // res, r.binY // res))
            if w is not None and np.isfinite(w) and w != 0:
                worst = max(worst, abs(r.counts / w - 1))
                n_compared += 1
        report(worst < 1e-5 and n_compared > 0,
               f"{res}: straw {name} records of {c} equal count / (v_i v_j) (max relative {worst:.1e}, {n_compared} of {len(recs)} records)")

print(f"{failures} failed")
sys.exit(1 if failures else 0)
