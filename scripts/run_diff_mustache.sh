#!/usr/bin/env bash
# Run Mustache's differential loop caller (diff_mustache, PyPI mustache-hic 1.3.3) on two maps
# and time it (a peer for differential loop calls). The FDR column
# of every output is the loop's BH-adjusted *detection* p-value in its own map; the difference
# p-value (cut at -pt2, unadjusted) is not reported.
#
# usage: scripts/run_diff_mustache.sh A.cool B.cool RESOLUTION OUT_PREFIX [diff_mustache options...]
#   A.cool, B.cool  one balanced map per condition (a 'weight' column; or pass -norm COLUMN).
#                   diff_mustache takes no replicates: merge them first, then balance:
#                     cooler merge A.cool A1.cool A2.cool && cooler balance A.cool
#                   (.mcool::/resolutions/N URIs are not accepted; give the .mcool path itself,
#                   diff_mustache then reads /resolutions/RESOLUTION.)
#   RESOLUTION      bin size in bp (for .cool it is read from the file; must be the same in both)
#   OUT_PREFIX      writes OUT_PREFIX.loop1 .loop2 (loops of A, of B), .diffloop1 (loops of A
#                   weaker in B), .diffloop2 (loops of B weaker in A), all with the header
#                   BIN1_CHR BIN1_START BIN1_END BIN2_CHROMOSOME BIN2_START BIN2_END FDR DETECTION_SCALE,
#                   plus OUT_PREFIX.log (its output) and OUT_PREFIX.time (/usr/bin/time -v).
#   extra options   passed on, e.g. -ch chr1 chr2 (default: every chromosome longer than 1 Mb;
#                   a map whose chromosomes are all <= 1 Mb needs -ch), -p 2 (processes,
#                   default 4, each ~1.2 GB), -pt 0.2 (detection FDR), -pt2 0.1 (difference p),
#                   -st 0.88, -d DIST (for res <= 10 kb clamped to [200 res, 2 Mb]: always 2 Mb at 10 kb).
#
# Install (Python 3.11; numpy must be < 2 and pandas < 3):
#   apt-get install -y libcurl4-openssl-dev      # hic-straw, a dependency, builds from source
#   python3 -m venv /tmp/mustache_venv
#   /tmp/mustache_venv/bin/pip install mustache-hic 'numpy<2' 'pandas<3'
# MUSTACHE_VENV overrides the venv path.
set -euo pipefail

if [ $# -lt 4 ]; then
    sed -n '2,27p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
fi
a=$1 b=$2 res=$3 out=$4
shift 4
venv=${MUSTACHE_VENV:-/tmp/mustache_venv}
py=$venv/bin/python
[ -x "$py" ] || { echo "no Python at $py: install mustache-hic there (see above)" >&2; exit 2; }
for f in "$a" "$b"; do [ -e "$f" ] || { echo "no such map: $f" >&2; exit 2; }; done

# The package installs only a `mustache` command; diff_mustache.py is run as a script (its
# `from mustache import ...` then finds mustache.py beside it).
dm=$("$py" -c 'import mustache, os; print(os.path.join(os.path.dirname(mustache.__file__), "diff_mustache.py"))')
[ -f "$dm" ] || { echo "diff_mustache.py not found in $venv" >&2; exit 2; }

mkdir -p "$(dirname "$out")"
cmd=("$py" -u "$dm" -f1 "$a" -f2 "$b" -r "$res" -o "$out" "$@")
echo "${cmd[*]}" >&2
start=$(date +%s%N)
if [ -x /usr/bin/time ]; then
    /usr/bin/time -v -o "$out.time" "${cmd[@]}" 2>&1 | tee "$out.log"
else
    "${cmd[@]}" 2>&1 | tee "$out.log"
fi
status=${PIPESTATUS[0]}
end=$(date +%s%N)
echo "wall $(( (end - start) / 1000000 )) ms (max RSS below is the largest single process; with -p N, N block processes run at once)" >&2
[ -f "$out.time" ] && grep -E 'Elapsed|Maximum resident|User time' "$out.time" >&2
for k in loop1 loop2 diffloop1 diffloop2; do
    if [ -f "$out.$k" ]; then
        echo "$out.$k: $(($(wc -l < "$out.$k") - 1)) rows" >&2
    else
        echo "$out.$k: not written (no chromosome was run: all <= 1 Mb? use -ch)" >&2
    fi
done
exit "$status"
