#!/usr/bin/env bash
# Boundary F1 of every TAD caller on synthetic block maps with known domains, across sequencing
# depths: `contactmap simulate blocks` -> `contactmap balance --store` -> `contactmap tads` ->
# `contactmap score boundaries` (tolerance 1 bin). Prints a Markdown table (docs/tads.md).
#
# Usage: scripts/tads_synthetic.sh [DEPTHS] [SEEDS]
#   DEPTHS: contacts per map, default "3e4 1e5 3e5 1e6 1e7"; SEEDS: default "1 2 3"
# Each map: 2 chromosomes x 2,000 bins of 10 kb, domains of 10-60 bins, P(s) ~ s^-1, domain
# enrichment x2 (--enrichment 1), lognormal coverage bias (sd 0.3), 1% dead bins, pixels at every
# distance (simulate blocks' default); no trans contacts, so each chromosome is balanced alone
# (balance --cis-only, cooler's tolerance). The sparsest maps (3e4 contacts, 7 per bin) need up to
# 420 ICE iterations, past cooler's 200: --max-iters 1000 (every map converges; a map that did not
# would stop the script).
set -euo pipefail
cd "$(dirname "$0")/.."
cm=${CONTACTMAP:-target/release/contactmap}
depths=${1:-"3e4 1e5 3e5 1e6 1e7"}
seeds=${2:-"1 2 3"}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# method label -> tads arguments
methods=(
  "insulation (100 kb)|--method insulation --window 100k"
  "insulation (200 kb)|--method insulation --window 200k"
  "directionality + HMM (200 kb)|--method directionality --window 200k"
  "TopDom (w = 5 bins)|--method topdom --window 50k"
  "Armatus (level 0: gamma 0.2)|--method armatus --max-domain 1M"
)

f1_of() { awk -F'\t' 'NR == 2 { print $7 }' "$1"; }
precision_of() { awk -F'\t' 'NR == 2 { print $5 }' "$1"; }
recall_of() { awk -F'\t' 'NR == 2 { print $6 }' "$1"; }

echo "| method | depth (contacts) | precision | recall | F1 (mean of ${seeds// /, } seeds) |"
echo "|---|---|---|---|---|"
for entry in "${methods[@]}"; do
  label=${entry%%|*}
  arguments=${entry#*|}
  for depth in $depths; do
    p_sum=0; r_sum=0; f_sum=0; n=0
    for seed in $seeds; do
      map="$work/map_${depth}_${seed}.cool"
      truth="$work/truth_${depth}_${seed}.bed"
      if [ ! -f "$map" ]; then
        "$cm" simulate blocks -o "$map" --truth-boundaries "$truth" --chroms 2 --bins 2000 \
          --depth "$depth" --enrichment 1 --bias-sd 0.3 --dead-bins 0.01 --seed "$seed" 2> /dev/null
        "$cm" balance "$map" --store --cis-only --max-iters 1000 2> /dev/null
      fi
      # shellcheck disable=SC2086
      "$cm" tads "$map" $arguments --boundaries "$work/calls.bed" -o /dev/null 2> /dev/null
      "$cm" score boundaries --truth "$truth" "$work/calls.bed" --tolerance-bins 1 \
        --bin-size 10000 -o "$work/score.tsv"
      p_sum=$(awk -v a="$p_sum" -v b="$(precision_of "$work/score.tsv")" 'BEGIN { print a + b }')
      r_sum=$(awk -v a="$r_sum" -v b="$(recall_of "$work/score.tsv")" 'BEGIN { print a + b }')
      f_sum=$(awk -v a="$f_sum" -v b="$(f1_of "$work/score.tsv")" 'BEGIN { print a + b }')
      n=$((n + 1))
    done
    awk -v l="$label" -v d="$depth" -v p="$p_sum" -v r="$r_sum" -v f="$f_sum" -v n="$n" \
      'BEGIN { printf "| %s | %s | %.3f | %.3f | %.3f |\n", l, d, p / n, r / n, f / n }'
  done
done
