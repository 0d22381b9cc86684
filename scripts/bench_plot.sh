#!/usr/bin/env bash
# `contactmap plot map` against `cooler show` and `hicPlotMatrix` on a 5,000 x 5,000-bin region of
# big.cool (docs/performance.md, "Pictures"). Needs the peers in VENV (see the table's notes).
#   scripts/bench_plot.sh VENV BIG.cool
set -euo pipefail
cd "$(dirname "$0")/.."
cm="${CONTACTMAP:-$PWD/target/release/contactmap}"
venv="$(cd "$1" && pwd)"
big="$2"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
t() { printf '%-100s ' "$*"; /usr/bin/time -f "%e s %M KB" "$@" 2>&1 >/dev/null | tail -1; }
region=chr1:0-50000000
for _ in 1 2 3; do t "$cm" plot map "$big" -r "$region" --raw -o "$out/big.png"; done
t "$cm" plot map "$big" -r "$region" --raw -o "$out/big.svg"
t "$cm" plot map "$big" -r "$region" --raw --dpi 300 -o "$out/big300.png"
t "$cm" plot map "$big" -r "$region" --raw --triangle --depth 3Mb -o "$out/tri.png"
t "$cm" plot map "$big" -r chr1 --raw -o "$out/chr1.png"
for _ in 1 2; do t "$venv/bin/cooler" show "$big" "$region" -o "$out/cshow.png"; done
if "$venv/bin/python" -c "import hicexplorer" 2>/dev/null; then
  for _ in 1 2; do
    t "$venv/bin/python" scripts/figures/hicplotmatrix.py --matrix "$big" --region "$region" \
      --log1p --outFileName "$out/hpm.png"
  done
else
  echo "hicPlotMatrix: HiCExplorer is not installed in $venv"
fi
