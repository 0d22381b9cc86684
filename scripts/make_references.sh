#!/usr/bin/env bash
# Rebuild data/reference/* with the peer tools (cooler 0.11, hictkpy 1.4).
# Needs a venv with them:  python3 -m venv .venv && .venv/bin/pip install cooler cooltools hictkpy
# Usage: scripts/make_references.sh [VENV_DIR]   (default .venv)
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${1:-.venv}"
cooler="$venv/bin/cooler"
python="$venv/bin/python"
ref=data/reference
mkdir -p "$ref"
dm6=data/cooler_test_file.mcool::/resolutions/100000

# A small multi-resolution .hic v9 written by hictk (an independent .hic writer) from a real cooler.
[ -f data/CN.mm9.multires.hic ] || "$python" benches/cool_to_hic.py data/CN.mm9.10000kb.cool data/CN.mm9.multires.hic 10000000,20000000,50000000

"$cooler" dump --join --header -b -r chr2L:1,000,000-3,000,000 -r2 chr2L:2,000,000-5,000,000 "$dm6" \
  > "$ref/dm6_100kb.chr2L_box.balanced.join.tsv"
"$cooler" dump -r chrX -r2 chrY "$dm6" > "$ref/dm6_100kb.chrX_chrY.tsv"
"$cooler" dump -t bins --header data/CN.mm9.10000kb.cool > "$ref/CN.mm9.10000kb.bins.tsv"
"$cooler" dump --header data/cooler_variable_bins_test_file.cool > "$ref/variable_bins.pixels.tsv"
"$cooler" dump -t bins data/cooler_variable_bins_test_file.cool > "$ref/variable_bins.bins.tsv"
"$cooler" dump --join data/toy.symm.upper.2.mcool::/resolutions/4 > "$ref/toy_4.join.tsv"
"$python" - > "$ref/CN.mm9.multires.hic.20000000.chr1_chr2.tsv" <<'PY'
import hictkpy
df = hictkpy.File("data/CN.mm9.multires.hic", 20000000).fetch("chr1", "chr2", join=True).to_df()
for row in df.itertuples(index=False):
    print(*row, sep="\t")
PY

# observed/expected of the cis pixels by cooltools 0.7.1 (sandbox obs_over_exp, unsmoothed
# balanced.avg, ignore_diags=2), rows with a finite value: bin1_id bin2_id oe
"$python" - > "$ref/CN.mm9.10000kb.cis_oe.tsv" <<'PY'
import warnings; warnings.filterwarnings("ignore")
import bioframe, cooler, numpy as np
from cooltools.sandbox.obs_over_exp_cooler import expected_full, obs_over_exp
clr = cooler.Cooler("data/CN.mm9.10000kb.cool")
view = bioframe.make_viewframe(clr.chromsizes)
exp = expected_full(clr, view_df=view, clr_weight_name="weight", ignore_diags=2, nproc=1)
bins = clr.bins()[:]
bins["r"] = bins["chrom"].map({n: i for i, n in enumerate(view["name"])})
oe = obs_over_exp(clr.pixels()[:], bins, exp, clr_weight_name="weight")
oe = oe[(oe["chrom1"] == oe["chrom2"]) & np.isfinite(oe["oe"])]
for b1, b2, v in zip(oe["bin1_id"], oe["bin2_id"], oe["oe"]):
    print(f"{b1}\t{b2}\t{v!r}")
PY

# nbins, nnz and the sum of counts of every matrix in data/, as cooler and hictkpy compute them.
"$python" - > "$ref/totals.tsv" <<'PY'
import glob, cooler, hictkpy
print("uri\tnbins\tnnz\tsum")
for path in sorted(glob.glob("data/*.cool")) + sorted(glob.glob("data/*.mcool")):
    uris = [path] if path.endswith(".cool") else [f"{path}::{g}" for g in cooler.fileops.list_coolers(path)]
    for uri in uris:
        c = cooler.Cooler(uri)
        counts = c.pixels()["count"][:]
        print(f"{uri}\t{c.info['nbins']}\t{len(counts)}\t{counts.sum()}")
for path in sorted(glob.glob("data/*.hic")):
    for res in hictkpy.MultiResFile(path).resolutions():
        f = hictkpy.File(path, int(res))
        df = f.fetch().to_df()
        print(f"{path}::/resolutions/{res}\t{f.nbins()}\t{len(df)}\t{int(df['count'].sum())}")
PY
echo "references written to $ref"
