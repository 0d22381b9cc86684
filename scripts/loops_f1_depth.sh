#!/usr/bin/env bash
# F1 of `contactmap dots` against the loops a simulation held (`simulate polymer --truth-loops`),
# against depth (docs/loops.md, issue 28). Eight independent extrusion ensembles (seeds 1..8) of a
# 1,000-bead chain with nine convergent pairs of boundary elements (a + element at 100k, a - at
# 100k + 90: neighbouring loops share no site) and one LEF per 50 beads, 16 replicas of
# 5 samples each (many replicas: a chain this long does not relax within a run, so samples of one
# replica share their large-scale contacts); the maps of the first 1, 2, 4 and 8
# are merged, balanced, called with `dots` (API defaults, 5 kb bins: w=7, p=4) and scored against
# the truth of all eight (each bin pair's fraction of samples averaged over the ensembles).
# Usage: scripts/loops_f1_depth.sh [OUT_DIR=/tmp/loops_f1] [CONTACTMAP=target/release/contactmap]
set -euo pipefail
out="${1:-/tmp/loops_f1}"; cm="$(realpath "${2:-target/release/contactmap}")"
mkdir -p "$out"; cd "$out"
ctcf=$(for k in 1 2 3 4 5 6 7 8 9; do printf "%d+,%d-," $((k * 100)) $((k * 100 + 90)); done)
ctcf=${ctcf%,}
for seed in 1 2 3 4 5 6 7 8; do
  [ -f "s$seed.cool" ] && continue
  "$cm" simulate polymer -o "s$seed.cool" --chains 1000 --density 0.2 --extrusion --ctcf "$ctcf" \
    --capture 0.99 --release 0.0002 --processivity 800 --separation 50 --steps-per-move 50 \
    --monomers-per-bin 5 --replicas 16 --equilibration 10000 --sample-every 2000 --samples 5 \
    --seed "$seed" --truth-loops "s$seed.truth.bedpe" 2>/dev/null
done
# the truth of all eight: per bin pair, the mean fraction (every ensemble has as many samples)
python3 - s?.truth.bedpe > truth.bedpe <<'PY'
import sys, collections
held = collections.defaultdict(int)
for path in sys.argv[1:]:
    for line in open(path).read().splitlines()[1:]:
        f = line.split("\t")
        held[tuple(f[:6])] += int(f[7])
total = 16 * 5 * (len(sys.argv) - 1)
print("chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tfraction\tsamples")
for key in sorted(held, key=lambda k: (int(k[1]), int(k[4]))):
    print("\t".join(key), held[key] / total, held[key], sep="\t")
PY
printf "ensembles\tcontacts\tdots\tprecision\trecall\tf1\n"
for n in 1 2 4 8; do
  files=$(for s in $(seq 1 $n); do printf "s%s.cool " "$s"; done)
  rm -f "m$n.cool" "m$n.dots.bedpe"
  if [ "$n" = 1 ]; then cp s1.cool m1.cool; else "$cm" merge $files -o "m$n.cool" 2>/dev/null; fi
  "$cm" balance "m$n.cool" --store 2>/dev/null
  "$cm" dots "m$n.cool" -o "m$n.dots.bedpe" 2>/dev/null
  contacts=$("$cm" info "m$n.cool" | awk '$1 == "sum" {print $2}')
  "$cm" score loops --truth truth.bedpe "m$n.dots.bedpe" --tolerance 10k --min-fraction 0.2 \
    > "m$n.score.tsv"
  awk -v n="$n" -v c="$contacts" '$1 == "all" {print n "\t" c "\t" $5 "\t" $9 "\t" $10 "\t" $11}' "m$n.score.tsv"
done
