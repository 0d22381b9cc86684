#!/usr/bin/env bash
# F1 of `contactmap dots` against the loops a simulation held (`simulate polymer --truth-loops`),
# against depth (docs/loops.md, issue 28). Sixteen independent extrusion ensembles (seeds 1..16)
# of a 420-bead chain of 5 kb beads (5 kb bins, one bead per bin) with eleven convergent pairs of
# boundary elements 30 beads apart (a + at 20 + 34k, a - at 50 + 34k: four beads between
# neighbouring loops), capture 1, release 0, processivity 300, one LEF per 30 beads; each
# ensemble 40 replicas of 5 samples 4,000 steps apart after 12,000 (many short replicas: samples
# of one replica share their chance contacts between distant segments, which the dot caller
# sees as local enrichments). The maps of the first 1, 2, 4, 8 and 16 are merged, balanced,
# called with `dots` (API defaults: w=7, p=4 at 5 kb) and scored against the truth of all
# sixteen (each bin pair's fraction of samples averaged over the ensembles).
# Usage: scripts/loops_f1_depth.sh [OUT_DIR=/tmp/loops_f1] [CONTACTMAP=target/release/contactmap]
# About 35 minutes on 2 cores.
set -euo pipefail
out="${1:-/tmp/loops_f1}"; cm="$(realpath "${2:-target/release/contactmap}")"
mkdir -p "$out"; cd "$out"
ctcf=$(for k in $(seq 0 10); do printf "%d+,%d-," $((20 + k * 34)) $((50 + k * 34)); done)
ctcf=${ctcf%,}
n_ens=16; replicas=40; samples=5
for seed in $(seq 1 $n_ens); do
  [ -f "s$seed.cool" ] && continue
  "$cm" simulate polymer -o "s$seed.cool" --chains 420 --monomer-bp 5000 --density 0.2 \
    --extrusion --ctcf "$ctcf" --capture 1 --release 0 --processivity 300 --separation 30 \
    --replicas $replicas --equilibration 12000 --sample-every 4000 --samples $samples \
    --seed "$seed" --truth-loops "s$seed.truth.bedpe" 2>/dev/null
done
# the truth of all ensembles: per bin pair, the mean fraction (every ensemble has as many samples)
python3 - $(seq -f "s%g.truth.bedpe" 1 $n_ens) > truth.bedpe <<PY
import sys, collections
held = collections.defaultdict(int)
for path in sys.argv[1:]:
    for line in open(path).read().splitlines()[1:]:
        f = line.split("\t")
        held[tuple(f[:6])] += int(f[7])
total = $replicas * $samples * (len(sys.argv) - 1)
print("chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tfraction\tsamples")
for key in sorted(held, key=lambda k: (int(k[1]), int(k[4]))):
    print("\t".join(key), held[key] / total, held[key], sep="\t")
PY
# each map called twice: with the cooltools API's defaults (FDR 0.1, clustering radius 20 kb) and
# with its command line's (--cooltools-cli: FDR 0.02, 39 kb, 45 lambda bins, 2 Mb)
printf "ensembles\tconformations\tcontacts\tdots\tprecision\trecall\tf1"
printf "\tcli_dots\tcli_precision\tcli_recall\tcli_f1\n"
for n in 1 2 4 8 16; do
  files=$(for s in $(seq 1 $n); do printf "s%s.cool " "$s"; done)
  rm -f "m$n.cool" m$n.*.dots.bedpe
  if [ "$n" = 1 ]; then cp s1.cool m1.cool; else "$cm" merge $files -o "m$n.cool" 2>/dev/null; fi
  "$cm" balance "m$n.cool" --store 2>/dev/null
  contacts=$("$cm" info "m$n.cool" | awk '$1 == "sum" {print $2}')
  printf "%s\t%s\t%s" "$n" $((n * replicas * samples)) "$contacts"
  for preset in api cli; do
    opts=(); [ "$preset" = cli ] && opts=(--cooltools-cli)
    calls="m$n.$preset.dots.bedpe"
    "$cm" dots "m$n.cool" "${opts[@]}" -o "$calls" 2>/dev/null
    "$cm" score loops --truth truth.bedpe "$calls" --tolerance 10k --min-fraction 0.2 \
      > "m$n.$preset.score.tsv"
    awk -v d="$(($(wc -l < "$calls") - 1))" \
      '$1 == "all" {printf "\t%s\t%s\t%s\t%s", d, $9, $10, $11}' "m$n.$preset.score.tsv"
  done
  printf "\n"
done
