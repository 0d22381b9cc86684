#!/usr/bin/env bash
# Compare `contactmap balance` and `contactmap expected` with the cooler 0.11 / cooltools 0.7.1
# reference outputs for every dataset of ../shared/data/hic/reference (gen_refs.py there made them):
# ICE weights genome-wide and cis-only, expected-cis raw and with the stored weight.
# Prints the largest relative difference per dataset and output; exits 1 on a mismatch (1e-6 for
# weights, 1e-8 for expected, NaN masks identical).
# Usage: scripts/check_numerics.sh [HIC_DATA_DIR] [VENV]   (defaults ../shared/data/hic and .venv)
set -euo pipefail
cd "$(dirname "$0")/.."
exec "${2:-.venv}/bin/python" - "${1:-../shared/data/hic}" target/release/contactmap <<'PY'
import io, subprocess, sys
import numpy as np, pandas as pd

data, binary = sys.argv[1], sys.argv[2]
datasets = {
    "dm6_100kb": "hictkpy/cooler_test_file.mcool::/resolutions/100000",
    "yeast_10kb": "cooler/yeast.10kb.cool",
    "mm9_CN_10Mb": "cooltools/CN.mm9.10000kb.cool",
    "gm12878_2Mb": "cooler/hg19.GM12878-MboI.matrix.2000kb.cool",
    "gm12878_2p5Mb_hicexp": "hicexplorer/hicCorrectMatrix/gm12878_raw_values.cool",
}
failures = 0

def ours(*args):
    out = subprocess.run([binary, *args], capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(out.stderr.strip())
    return pd.read_csv(io.StringIO(out.stdout), sep="\t")

def compare(key, what, a, b, columns, tolerance):
    global failures
    worst = 0.0
    for c in columns:
        x, y = a[c].to_numpy(float), b[c].to_numpy(float)
        same_mask = len(x) == len(y) and np.array_equal(np.isnan(x), np.isnan(y))
        m = ~np.isnan(y)
        if not same_mask:
            worst = np.inf
        elif m.any():
            worst = max(worst, float(np.max(np.abs(x[m] - y[m]) / np.maximum(np.abs(y[m]), 1e-300))))
    ok = worst <= tolerance
    failures += 0 if ok else 1
    print(f"{'ok  ' if ok else 'FAIL'}  {key:<22} {what:<28} max rel diff {worst:.2e}")

for key, uri in datasets.items():
    uri = f"{data}/{uri}"
    for mode, flags in [("gw", []), ("cis", ["--cis-only"])]:
        ref = pd.read_csv(f"{data}/reference/{key}.ice_{mode}.weights.tsv", sep="\t")
        compare(key, f"ICE {mode}", ours("balance", uri, *flags), ref, ["weight"], 1e-6)
    for mode, flags in [("raw", ["--raw"]), ("balanced_storedweight", [])]:
        path = f"{data}/reference/{key}.expected_cis.{mode}.tsv"
        try:
            ref = pd.read_csv(path, sep="\t")
        except FileNotFoundError:
            continue
        table = ours("expected", uri, *flags)
        columns = [c for c in ref.columns if c not in ("region1", "region2")]
        compare(key, f"expected {mode}", table, ref, columns, 1e-8)
print(f"{failures} failures")
sys.exit(1 if failures else 0)
PY
