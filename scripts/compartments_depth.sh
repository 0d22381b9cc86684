#!/usr/bin/env bash
# Sign accuracy of E1 on simulated A/B block copolymers by depth (docs/compartments.md).
# usage: scripts/compartments_depth.sh [OUTDIR]   (needs target/release/contactmap)
# One chain of 2000 beads (A200B200: ten blocks), sphere at density 0.3, attraction 0.4 kT between
# beads of the same type, 10 beads a bin (200 bins); the depth grows with the samples per
# replica (8 replicas). E1 is oriented by the truth's fraction of A (it only sets the sign of the
# whole chromosome) and scored bin by bin.
set -euo pipefail
bin=${CONTACTMAP:-target/release/contactmap}
out=${1:-compartments-depth}
mkdir -p "$out"
printf "samples\tconformations\tcontacts\tsign_accuracy\tpearson\n"
for samples in ${SAMPLES:-5 20 50 100 200}; do
  p="$out/ab.s$samples"
  "$bin" simulate polymer -o "$p.cool" --chains 2000 --density 0.3 --types A200B200 \
    --attraction 0.4 --monomers-per-bin 10 --replicas 8 --samples "$samples" --seed 1 \
    --device cpu --truth-compartments "$p.truth.bed" 2>/dev/null
  "$bin" balance "$p.cool" --store >/dev/null 2>&1
  "$bin" compartments "$p.cool" --phasing-track "$p.truth.bed:5" -o "$p"
  contacts=$("$bin" info "$p.cool" | awk '$1 == "sum" {print $2}')
  "$bin" score compartments --truth "$p.truth.bed" "$p.cis.vecs.tsv" |
    awk -v s="$samples" -v c="$contacts" '$1 == "all" {printf "%s\t%d\t%s\t%s\t%s\n", s, 8 * s, c, $3, $5}'
done
