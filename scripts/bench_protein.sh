#!/usr/bin/env bash
# Side-by-side timing of long-range contact precision (L/10, L/5, L/2, L): contactmap against
# ConKit 0.13.3's documented Python computation, on a synthetic 1,000-residue protein with a
# 1000 x 1000 CCMpred-style matrix (499,500 pairs), made by scripts/make_protein_bench.py.
#
# usage: scripts/bench_protein.sh [VENV]   (VENV with conkit and biopython:
#   python3 -m venv .venv && .venv/bin/pip install numpy biopython && .venv/bin/pip install --no-deps conkit)
set -euo pipefail
cd "$(dirname "$0")/.."
venv=${1:-.venv}
work=${WORK:-$(mktemp -d)}
python3 scripts/make_protein_bench.py "$work" 1000 1
cargo build --release --quiet
cm=target/release/contactmap
echo "== contactmap"
/usr/bin/time -f "contactmap: %e s, %M KB" "$cm" score contacts --structure "$work/bench.pdb" \
  "$work/bench.mat" --fasta "$work/bench.fasta" --ranges long --tsv 2>/dev/null | cut -f5,8,9
echo "== ConKit"
/usr/bin/time -f "conkit: %e s, %M KB" "$venv/bin/python" scripts/conkit_precision.py \
  "$work/bench.pdb" "$work/bench.mat" "$work/bench.fasta" ccmpred
