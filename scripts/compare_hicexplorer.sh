#!/usr/bin/env bash
# Agreement of contactmap's boundary calls with HiCExplorer's hicFindTADs on the same matrix
# (a different method: a z-score based TAD-separation score averaged over window sizes). Reads
# ../shared/data/hic/hicexplorer/ (not shipped with the repo); prints a Markdown table (docs/tads.md).
#
# hicFindTADs reference: small_test_matrix.h5 (dm3, 5 kb, 37,321 contacts), --minDepth 60000
# --maxDepth 180000 --step 20000 --correctForMultipleTesting None --thresholdComparisons 1.0
# (no filtering): multiNone_boundaries.bed. We call every insulation minimum (--threshold 0) on
# raw counts (the reference test input is uncorrected), and TopDom / directionality likewise.
# Usage: scripts/compare_hicexplorer.sh [SHARED_HIC_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
shared=${1:-../shared/data/hic}
cm=${CONTACTMAP:-target/release/contactmap}
matrix="$shared/hicexplorer/small_test_matrix.cool"
reference="$shared/hicexplorer/find_TADs/None/multiNone_boundaries.bed"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Only the chromosomes hicFindTADs reported on.
cut -f1 "$reference" | sort -u > "$work/chroms"
filter() { awk 'NR == FNR { keep[$1] = 1; next } ($1 in keep)' "$work/chroms" "$1"; }
echo "| contactmap call | n calls | n hicFindTADs | F1 (tolerance 1 bin) | F1 (2 bins) | precision / recall (2 bins) |"
echo "|---|---|---|---|---|---|"
run() {
  local label=$1; shift
  "$cm" tads "$matrix" --raw "$@" --boundaries "$work/calls.bed" -o /dev/null 2> /dev/null
  filter "$work/calls.bed" > "$work/kept.bed"
  "$cm" score boundaries --truth "$reference" "$work/kept.bed" --tolerance-bins 1 --bin-size 5000 -o "$work/s1.tsv"
  "$cm" score boundaries --truth "$reference" "$work/kept.bed" --tolerance-bins 2 --bin-size 5000 -o "$work/s2.tsv"
  awk -F'\t' -v l="$label" 'NR == FNR && FNR == 2 { f1 = $7; next }
    FNR == 2 { printf "| %s | %d | %d | %.3f | %.3f | %.3f / %.3f |\n", l, $3, $2, f1, $7, $5, $6 }' \
    "$work/s1.tsv" "$work/s2.tsv"
}
for w in 60k 100k 180k; do
  run "insulation, window $w, every minimum" --window "$w" --threshold 0
  run "insulation, window $w, Li threshold" --window "$w"
done
run "TopDom, window 50 kb" --method topdom --window 50k
run "directionality + HMM, window 100 kb" --method directionality --window 100k

# The boundaries hicFindTADs keeps after its FDR filter (--correctForMultipleTesting fdr
# --thresholdComparisons 0.1: two of them): are they among our thresholded calls?
fdr="$shared/hicexplorer/find_TADs/FDR/multiFDR_boundaries.bed"
echo
echo "| contactmap call | hicFindTADs FDR boundaries found (tolerance 2 bins) |"
echo "|---|---|"
for w in 60k 100k 180k; do
  "$cm" tads "$matrix" --raw --window "$w" --boundaries "$work/calls.bed" -o /dev/null 2> /dev/null
  "$cm" score boundaries --truth "$fdr" "$work/calls.bed" --tolerance-bins 2 --bin-size 5000 -o "$work/s.tsv"
  awk -F'\t' -v w="$w" 'FNR == 2 { printf "| insulation, window %s, Li threshold (%d calls) | %d of %d |\n", w, $3, $4, $2 }' "$work/s.tsv"
done
