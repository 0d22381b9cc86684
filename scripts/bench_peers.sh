#!/usr/bin/env bash
# Side-by-side timings of contactmap and the peer tools on the same files, same machine, one run.
# Writes a Markdown table to stdout (docs/performance.md records the figures).
#
# Needs a venv with cooler and hictkpy (python3 -m venv .venv && .venv/bin/pip install cooler hictkpy
# pyarrow) and the large synthetic cooler made by ../shared/tools/make_big_cool.py (generated into
# bench-data/ on first use, ~1 min), converted once to .hic by benches/cool_to_hic.py (~4 min).
# Usage: scripts/bench_peers.sh [VENV] [GENERATOR]
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${1:-.venv}"
generator="${2:-../shared/tools/make_big_cool.py}"
cm=target/release/contactmap
py="$venv/bin/python"
mkdir -p bench-data
big=bench-data/big.cool
bighic=bench-data/big.hic
[ -f "$big" ] || "$py" "$generator" "$big" >&2
[ -f "$bighic" ] || "$py" benches/cool_to_hic.py "$big" "$bighic" 10000,100000 >&2

# time_it LABEL CMD... : wall seconds and peak RSS (MB) of one run
time_it() {
  local label="$1"; shift
  /usr/bin/time -f "%e %M" -o bench-data/.time "$@" > /dev/null
  read -r seconds kb < bench-data/.time
  printf '| %s | %s s | %d MB |\n' "$label" "$seconds" $((kb / 1024))
}

echo "machine: $(nproc) cores, $(free -g | awk '/Mem:/{print $2}') GB; $(date -u +%Y-%m-%d)"
echo
echo "| task | wall time | peak memory |"
echo "|---|---|---|"
if [ "${SKIP_IO:-0}" != 1 ]; then
nnz=$("$cm" info --json "$big" | "$py" -c 'import json,sys; print(json.load(sys.stdin)["nnz"])')
time_it "contactmap dump big.cool ($nnz pixels) > file" sh -c "$cm dump $big > bench-data/ours.tsv"
time_it "cooler dump -t pixels big.cool > file" sh -c "$venv/bin/cooler dump -t pixels $big > bench-data/theirs.tsv"
if cmp -s bench-data/ours.tsv bench-data/theirs.tsv; then
  echo "| outputs identical (cmp) | | |"
else
  echo "| OUTPUTS DIFFER | | |"
fi
rm -f bench-data/ours.tsv bench-data/theirs.tsv
time_it "contactmap dump big.hic::/resolutions/10000 > /dev/null" "$cm" dump "$bighic::/resolutions/10000"
time_it "contactmap info big.hic::/resolutions/10000 (reads every pixel)" "$cm" info "$bighic::/resolutions/10000"
time_it "hictkpy: File(big.hic, 10000).fetch().to_df()" "$py" -c "import hictkpy; df = hictkpy.File('$bighic', 10000).fetch().to_df(); print(len(df))"
time_it "hictkpy: File(big.hic, 10000).fetch().sum() and .nnz()" "$py" -c "import hictkpy; s = hictkpy.File('$bighic', 10000).fetch(); print(s.sum(), s.nnz())"
time_it "contactmap dump data/hic_test_file.hic > /dev/null (890k pixels)" "$cm" dump data/hic_test_file.hic
time_it "hictkpy: File(hic_test_file.hic, 100000).fetch().to_df()" "$py" -c "import hictkpy; print(len(hictkpy.File('data/hic_test_file.hic', 100000).fetch().to_df()))"

fi

# Numerics (issue 3): balancing and expected on the same large file.
if [ "${SKIP_NUMERICS:-0}" != 1 ]; then
  time_it "contactmap balance big.cool (ICE, cooler's defaults) -o weights.tsv" "$cm" balance "$big" -o bench-data/weights.tsv
  time_it "cooler balance -p 2 --stdout big.cool" "$venv/bin/cooler" balance -p 2 --stdout "$big"
  time_it "contactmap expected big.cool --raw -o e.tsv (smoothed, as cooltools' API)" "$cm" expected "$big" --raw -o bench-data/e.tsv
  time_it "cooltools expected-cis -p 2 --clr-weight-name '' --smooth --aggregate-smoothed big.cool" \
    "$venv/bin/cooltools" expected-cis -p 2 --clr-weight-name "" --smooth --aggregate-smoothed -o bench-data/e_cooltools.tsv "$big"
fi

# TADs (issue 4): insulation with three windows on a balanced copy of the same file (ICE does not
# converge on it within 200 iterations, in cooler either: the unconverged weights are stored, the
# same column for both tools).
if [ "${SKIP_TADS:-0}" != 1 ]; then
  bigw=bench-data/big_weighted.cool
  if [ ! -f "$bigw" ]; then
    cp "$big" "$bigw"
    "$cm" balance "$bigw" --store --store-unconverged 2> /dev/null
  fi
  time_it "contactmap tads big.cool --window 100k,200k,500k -o ins.tsv" \
    "$cm" tads "$bigw" --window 100k,200k,500k -o bench-data/ins_ours.tsv
  # cooltools' command line thresholds at 0 by default; --threshold Li is its API's default, and ours.
  time_it "cooltools insulation -p 2 --threshold Li big.cool 100000 200000 500000 -o ins.tsv" \
    "$venv/bin/cooltools" insulation -p 2 --threshold Li -o bench-data/ins_cooltools.tsv "$bigw" 100000 200000 500000
  "$py" scripts/compare_insulation.py bench-data/ins_ours.tsv bench-data/ins_cooltools.tsv
fi
