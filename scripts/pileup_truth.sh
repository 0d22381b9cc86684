#!/usr/bin/env bash
# Pileup at the loops a simulation held against random pairs at the same distances (issue 29):
# on the deepest merged map of scripts/loops_f1_depth.sh (run it first), the truth loops held in
# at least 20% of the samples and, for each, ten random pairs of bins as far apart, observed /
# expected, flank 20 kb; prints n, the central 3x3 enrichment and Juicer's P2LL of each.
# Usage: scripts/pileup_truth.sh [F1_DIR=/tmp/loops_f1] [CONTACTMAP=target/release/contactmap]
set -euo pipefail
dir="${1:-/tmp/loops_f1}"; cm="$(realpath "${2:-target/release/contactmap}")"
cd "$dir"
awk 'NR > 1 && $7 >= 0.2' truth.bedpe > strong.bedpe
python3 - <<'PY'
import random
random.seed(1)
with open("random.bedpe", "w") as out:
    for line in open("strong.bedpe"):
        f = line.split("\t")
        d = int(f[4]) - int(f[1])
        for _ in range(10):
            s = random.randrange(20, 420 - d // 5000 - 20) * 5000
            out.write(f"chr1\t{s}\t{s + 5000}\tchr1\t{s + d}\t{s + d + 5000}\n")
PY
printf "pairs\tn\tenrichment_3x3\tP2LL\n"
for pairs in strong random; do
  rm -f "pileup_$pairs.pileup.tsv" "pileup_$pairs.scores.tsv"
  "$cm" pileup m16.cool "$pairs.bedpe" --flank 20k --mindist 0 -o "pileup_$pairs" 2>/dev/null
  # the scores table: a header, then one line per group (here only "all")
  awk -F'\t' -v p="$pairs" 'NR == 1 {for (i = 1; i <= NF; i++) c[$i] = i}
    $1 == "all" {print p "\t" $c["n"] "\t" $c["enrichment_3x3"] "\t" $c["P2LL"]}' \
    "pileup_$pairs.scores.tsv"
done
