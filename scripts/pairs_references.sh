#!/usr/bin/env bash
# Peer references of `contactmap pairs` on data/pairs/sim.bam (pairtools 1.1.2, cooler 0.11):
# regenerates data/pairs/reference/ (see data/pairs/README.md).
#
#   scripts/pairs_references.sh [DATA_DIR]          # default data/pairs
#
# The commands run in a scratch copy with relative paths, so the `#samheader: @PG` lines the
# peers write hold these command lines (pairtools writes its own path as the CL's first word).
# Every output is written plain, then `gzip -9 -n` (the cooler dump too).
set -euo pipefail

# pip install pairtools==1.1.2 pysam==0.22.1: the pairtools 1.1.2 wheel is built against pysam
# 0.22 (htslib 1.18); with pysam 0.24 `parse --add-columns mismatches` dies of a segfault
PAIRVENV=${PAIRVENV:-/tmp/pairvenv-pysam022}
COOLERVENV=${COOLERVENV:-/tmp/peervenv}  # pip install cooler (0.11.0)
NPROC=2

DATA=${1:-data/pairs}
DATA=$(cd "$DATA" && pwd)
OUT=$DATA/reference
export PATH=$PAIRVENV/bin:$PATH
export LC_ALL=C
W=$(mktemp -d /tmp/pairs_refs.XXXXXX)
trap 'rm -rf "$W"' EXIT
cp "$DATA/sim.bam" "$DATA/sim.chrom.sizes" "$W/"
[ -f "$DATA/sim.noM.bam" ] && cp "$DATA/sim.noM.bam" "$W/"
cd "$W"

pairtools --version
"$COOLERVENV/bin/cooler" --version

PARSE="pairtools parse -c sim.chrom.sizes --assembly sim --min-mapq 1 --max-molecule-size 750
 --max-inter-align-gap 20 --drop-sam --nproc-in $NPROC"
FULL=mapq,pos5,pos3,cigar,read_len,matched_bp,algn_ref_span,algn_read_span,dist_to_5,dist_to_3,mismatches

# parse: 5unique with every alignment column and the read ids, and its stats; 5unique with the
# default columns and the read ids (the input of sort, dedup, stats and, read ids dropped, merge)
$PARSE --walks-policy 5unique --add-columns $FULL --output-stats sim.5unique.full.stats \
    -o sim.5unique.full.pairs sim.bam
$PARSE --walks-policy 5unique -o sim.5unique.pairs sim.bam
# parse: the other walks policies, default columns, no read ids ('all' with the walk pair index)
for P in 5any 3unique 3any mask; do
    $PARSE --walks-policy $P --drop-readid -o sim.$P.pairs sim.bam
done
$PARSE --walks-policy all --add-pair-index --drop-readid -o sim.all.pairs sim.bam
$PARSE --walks-policy 5unique --no-flip --drop-readid -o sim.5unique.noflip.pairs sim.bam
if [ -f sim.noM.bam ]; then  # split alignments flagged supplementary (bwa mem -SP5)
    $PARSE --walks-policy 5unique --add-columns $FULL -o sim.noM.5unique.full.pairs sim.noM.bam
fi

# sort, dedup (max: every output; sum: the duplicates and the stats), stats, select
pairtools sort --nproc $NPROC -o sim.5unique.sorted.pairs sim.5unique.pairs
pairtools dedup --max-mismatch 3 --method max --mark-dups \
    --output sim.nodups.pairs --output-dups sim.dups.pairs \
    --output-unmapped sim.unmapped.pairs --output-stats sim.dedup.stats \
    sim.5unique.sorted.pairs
pairtools dedup --max-mismatch 3 --method sum --output nodups.sum.pairs \
    --output-dups sim.sum.dups.pairs --output-stats sim.sum.dedup.stats sim.5unique.sorted.pairs
pairtools stats -o sim.5unique.stats sim.5unique.pairs
# stats --merge lists the merged pair types in Python's string-hash order (a set union): fix
# the seed so that the file is made again byte for byte; compare that block as a set
PYTHONHASHSEED=0 pairtools stats --merge -o sim.merged.stats sim.5unique.stats sim.dedup.stats
pairtools select '(pair_type=="UU") or (pair_type=="UR") or (pair_type=="RU")' \
    -o sim.select_uu_ur_ru.pairs sim.5any.pairs
pairtools select '(chrom1!=chrom2) and (mapq1>=30) and (mapq2>=30)' \
    -o sim.select_trans_mapq30.pairs sim.5unique.full.pairs

# merge: sim.5unique.pairs without read ids split into odd and even lines (headers kept), each
# sorted
for h in 1 2; do
    awk -v h=$h 'BEGIN {FS = OFS = "\t"} /^#/ {print; next} {n++; $1 = "."; if (n % 2 == h % 2) print}' \
        sim.5unique.pairs > half$h.pairs
    pairtools sort --nproc $NPROC -o sim.half$h.sorted.pairs half$h.pairs
done
pairtools merge --nproc $NPROC -o sim.merged.pairs sim.half1.sorted.pairs sim.half2.sorted.pairs

# BAM -> pairs -> .cool
"$COOLERVENV/bin/cooler" cload pairs -c1 2 -p1 3 -c2 4 -p2 5 sim.chrom.sizes:1000 \
    sim.nodups.pairs sim.1000.cool
"$COOLERVENV/bin/cooler" dump sim.1000.cool > sim.1000.pixels.tsv

mkdir -p "$OUT"
rm -f "$OUT"/*.gz
for f in sim.*.pairs sim.*.stats sim.1000.pixels.tsv; do
    gzip -9 -n -c "$f" > "$OUT/$f.gz"
done
ls -l "$OUT"
