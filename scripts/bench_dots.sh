#!/usr/bin/env bash
# Side-by-side timing of `contactmap dots` and cooltools 0.7.1 `dots` on the same balanced cooler
# (docs/performance.md, issue 28). Usage:
#   PYTHON=/path/to/venv/bin/python scripts/bench_dots.sh BALANCED.cool [NPROC=2] [CONTACTMAP=target/release/contactmap]
# The venv needs cooltools 0.7.1, pandas < 3 and scikit-learn. Each tool computes its own expected
# (cooltools expected_cis / contactmap's, equal to it) and calls with the API defaults; the script
# prints wall time and peak memory of each, and compares the outputs (scripts/compare_tables.py).
set -euo pipefail
cool="$1"; nproc="${2:-2}"; cm="${3:-target/release/contactmap}"; py="${PYTHON:-python3}"
out="${BENCH_DIR:-$(mktemp -d)}"; mkdir -p "$out"
cat > "$out/cooltools_dots.py" <<PY
import logging, sys
import cooler, cooltools
logging.disable(logging.INFO)
clr = cooler.Cooler(sys.argv[1])
exp = cooltools.expected_cis(clr, nproc=int(sys.argv[3]))
dots = cooltools.dots(clr, exp, nproc=int(sys.argv[3]))
dots.to_csv(sys.argv[2], sep="\t", index=False, na_rep="nan")
PY
echo "cooltools dots (nproc $nproc):"
/usr/bin/time -f "  wall %e s, peak %M KB" "$py" "$out/cooltools_dots.py" "$cool" "$out/cooltools.tsv" "$nproc" 2>&1 \
  | grep -v -e Warning -e idxmin -e 'groups = '
echo "contactmap dots (RAYON_NUM_THREADS=$nproc):"
RAYON_NUM_THREADS="$nproc" /usr/bin/time -f "  wall %e s, peak %M KB" "$cm" dots "$cool" -o "$out/contactmap.tsv"
python3 "$(dirname "$0")/compare_tables.py" "$out/contactmap.tsv" "$out/cooltools.tsv"
