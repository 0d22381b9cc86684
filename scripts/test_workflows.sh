#!/usr/bin/env bash
# The workflows' test (run by `make test`): both Snakemake workflows on data/ with the local
# executor (--cores 2); every output compared with the same contactmap commands run by hand; the
# analysis ingest of one sample per input URI form (.cool, cooler group, .mcool level and its
# shorthand, .hic with and without a resolution, HiCExplorer .h5, BG2 with --bins, pairs) against
# `contactmap convert` by hand; the example's BAM sample (parse | sort | dedup) against the same
# commands by hand and pairtools' outputs in data/pairs/reference, and its report columns; the
# pairs inputs told apart by content (BAM without extension, SAM, 4DN pairs to deduplicate or
# already deduplicated) against pairtools' deduplicated pairs; a dry run on a 200-sample sheet
# counted per rule; the simulation's merged map against `contactmap merge` of batches simulated by
# hand. Installs the pinned snakemake into .venv-workflows when missing
# (SNAKEMAKE=path/to/snakemake uses another).
# usage: scripts/test_workflows.sh [CONTACTMAP]   (default: target/debug/contactmap)
#        scripts/test_workflows.sh --prepare      (only install snakemake: make test does it
#                                                  while cargo compiles)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -z "${SNAKEMAKE:-}" ]; then
  if [ ! -x .venv-workflows/bin/snakemake ]; then
    python3 -m venv .venv-workflows
    .venv-workflows/bin/pip install -q -r workflows/requirements.txt
  fi
  SNAKEMAKE=.venv-workflows/bin/snakemake
fi
[ "${1:-}" = "--prepare" ] && exit 0
cm=$(realpath "${1:-${CONTACTMAP:-target/debug/contactmap}}")
py=$(dirname "$SNAKEMAKE")/python
[ -x "$py" ] || py=python3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "test_workflows: FAIL: $*" >&2; exit 1; }
same() { cmp -s "$1" "$2" || fail "$1 differs from $2"; }
same_map() { # two maps: the same bins (with weights) and the same pixels
  diff -q <("$cm" dump -t bins "$1") <("$cm" dump -t bins "$2") >/dev/null || fail "bins of $1 and $2"
  diff -q <("$cm" dump "$1" --join) <("$cm" dump "$2" --join) >/dev/null || fail "pixels of $1 and $2"
}
same_json() { # the same JSON but for the "uri" and "creation-date" fields (a path, a clock)
  "$py" - "$1" "$2" <<'PY' || fail "$1 differs from $2"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
for d in (a, b):
    d.pop("uri", None)
    d.pop("creation-date", None)
sys.exit(a != b)
PY
}
quiet() { "$@" >/dev/null 2>&1 || fail "$*"; }
is_matrix() { # the ingest rule's test: a `::` group, or a file with the HDF5 or the .hic signature
  [[ $1 == *::* ]] && return 0
  local head
  head=$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')
  [[ $head == 894844460d0a1a0a || $head == 48494300* ]]
}
bin_size_option() { # URI OPTIONS BIN_SIZE: `--bin-size BIN_SIZE` where the ingest rule adds it
  is_matrix "$1" && return 0
  case " $2 " in *" --bins "*|*" --bins="*|*" --bin-size "*|*" --bin-size="*) return 0 ;; esac
  echo "--bin-size $3"
}

echo "== analysis workflow (the example sheet, local executor, 2 cores)"
out="$work/results"
"$SNAKEMAKE" -s workflows/analysis/Snakefile --cores 2 -q --config contactmap="$cm" outdir="$out" \
  > "$work/analysis.log" 2>&1 || { cat "$work/analysis.log"; fail "the analysis workflow"; }
hand="$work/hand"
# (tabs turned into unit separators: IFS whitespace would merge the empty columns)
body() { zcat -f "$1" | grep -v '^#'; } # a pairs file's records, without its header
same_pairs() { # two pairs files with the same records (headers name the commands and paths)
  cmp -s <(body "$1") <(body "$2") || fail "pairs of $1 and $2"
}
tail -n +2 workflows/example/samples.tsv | tr '\t' '\037' | while IFS=$'\037' read -r sample input bin_size fasta options _group chrom_sizes assembly; do
  o="$out/$sample"; h="$hand/$sample"; mkdir -p "$h"
  if [[ $input == *.bam || $input == *.sam ]]; then # read alignments: parse | sort | dedup first
    (set -o pipefail
     "$cm" pairs parse "$input" -c "$chrom_sizes" ${assembly:+--assembly "$assembly"} --output-stats "$h/parse.stats" \
       | "$cm" pairs sort --tmpdir "$work" \
       | "$cm" pairs dedup -o "$h/nodups.pairs.gz" --output-dups "$h/dups.pairs.gz" \
           --output-unmapped "$h/unmapped.pairs.gz" --output-stats "$h/dedup.stats") 2>/dev/null \
      || fail "pairs parse | sort | dedup of $input"
    for kind in nodups dups unmapped; do same_pairs "$o/$sample.$kind.pairs.gz" "$h/$kind.pairs.gz"; done
    for f in parse.stats dedup.stats; do same "$o/$f" "$h/$f"; done
    echo "   $sample: pairs parse | sort | dedup: 3 pairs files and 2 stats equal to the commands by hand"
    if [ "$input" = data/pairs/sim.bam ]; then # pairtools 1.1.2's own outputs
      for kind in nodups dups unmapped; do same_pairs "$o/$sample.$kind.pairs.gz" "data/pairs/reference/sim.$kind.pairs.gz"; done
      cmp -s "$o/dedup.stats" <(zcat data/pairs/reference/sim.dedup.stats.gz) || fail "$o/dedup.stats differs from pairtools'"
      echo "   $sample: nodups, dups, unmapped pairs and dedup.stats equal to pairtools 1.1.2's (data/pairs/reference)"
    fi
    input="$h/nodups.pairs.gz"
  fi
  # shellcheck disable=SC2046,SC2086
  quiet "$cm" convert "$input" "$h/base.cool" $options $(bin_size_option "$input" "$options" "$bin_size")
  cp "$h/base.cool" "$h/balanced.cool"
  "$cm" balance "$h/balanced.cool" --store --force --store-unconverged --json > "$h/balance.json" 2>/dev/null
  quiet "$cm" zoomify "$h/base.cool" -r "$bin_size,$((2 * bin_size)),$((5 * bin_size)),$((10 * bin_size))" --balance -o "$h/$sample.mcool"
  "$cm" info "$h/balanced.cool" --json > "$h/info.json"
  quiet "$cm" expected "$h/balanced.cool" -o "$h/expected.tsv"
  # a map too sparse for a power law: powerlaw.json says why, ps.png has no fit (no point: empty)
  points=fit
  if ! "$cm" expected "$h/balanced.cool" --json > "$h/powerlaw.json" 2> "$h/fit.err"; then
    points=$("$cm" expected "$h/balanced.cool" --logbin 2>/dev/null | wc -l); points=$((points - 1))
    [ "$points" -lt 3 ] || fail "expected --json of $sample"
    "$py" - "$h/fit.err" "$points" > "$h/powerlaw.json" <<'PY'
import json, sys
reason = open(sys.argv[1]).read().strip().removeprefix("contactmap: error: ")
print(json.dumps({"power_law": None, "logbin_points": int(sys.argv[2]), "reason": reason}))
PY
  fi
  window=$((5 * bin_size))
  quiet "$cm" tads "$h/balanced.cool" --window "$window" -o "$h/insulation.tsv" --boundaries "$h/boundaries.bed"
  quiet "$cm" compartments "$h/balanced.cool" ${fasta:+--fasta "$fasta"} -o "$h/eigs"
  quiet "$cm" saddle "$h/balanced.cool" --track "$h/eigs.cis.vecs.tsv:E1" --n-bins 50 -o "$h/saddle"
  case $points in
    fit) quiet "$cm" plot expected "$h/balanced.cool" --fit --labels "$sample" -o "$h/ps.png" ;;
    0) : > "$h/ps.png" ;;
    *) quiet "$cm" plot expected "$h/balanced.cool" --labels "$sample" -o "$h/ps.png" ;;
  esac
  quiet "$cm" plot saddle "$h/saddle.saddle.tsv" --title "$sample" -o "$h/saddle.png"
  chrom=$("$cm" dump -t chroms "$h/balanced.cool" | head -n 1 | cut -f 1)
  quiet "$cm" plot map "$h/balanced.cool" -r "$chrom" --boundaries "$h/boundaries.bed" \
    --track "$h/insulation.tsv:log2_insulation_score_$window" -o "$h/map.png"
  for map in base.cool balanced.cool; do same_map "$o/$map" "$h/$map"; done
  for r in 1 2 5 10; do same_map "$o/$sample.mcool::/resolutions/$((r * bin_size))" "$h/$sample.mcool::/resolutions/$((r * bin_size))"; done
  for f in expected.tsv insulation.tsv boundaries.bed eigs.cis.vecs.tsv eigs.cis.lam.txt \
           saddle.saddle.tsv saddle.edges.tsv saddle.digitized.tsv saddle.strength.tsv ps.png saddle.png map.png; do
    same "$o/$f" "$h/$f"
  done
  for f in info.json powerlaw.json balance.json; do same_json "$o/$f" "$h/$f"; done
  note=""; [ "$points" = fit ] || note=" (too sparse for a power law: $points P(s) points)"
  echo "   $sample: 4 maps, 5 .mcool levels, 12 files, 3 JSON equal to the commands by hand$note"
done
# HiCRep per group of the sheet (column 6), samples in sheet order
groups=$(tail -n +2 workflows/example/samples.tsv | awk -F'\t' '$6 != "" {print $6}' | sort -u)
[ -n "$groups" ] || fail "the example sheet has no group"
mkdir -p "$hand/hicrep"
for group in $groups; do
  members=$(tail -n +2 workflows/example/samples.tsv | awk -F'\t' -v g="$group" '$6 == g {print $1}')
  maps=(); for m in $members; do maps+=("$hand/$m/base.cool"); done
  quiet "$cm" hicrep "${maps[@]}" --names "$(echo $members | tr ' ' ',')" --h auto --max-distance 5M \
    --seed 10 -o "$hand/hicrep/$group.scc.tsv"
  quiet "$cm" plot hicrep "$hand/hicrep/$group.scc.tsv" --title "$group" -o "$hand/hicrep/$group.scc.png"
  for f in "$group.scc.tsv" "$group.scc.png"; do same "$out/hicrep/$f" "$hand/hicrep/$f"; done
  echo "   hicrep $group ($(echo $members | tr ' ' ',')): SCC table and heatmap equal to the commands by hand"
done
"$py" - "$out/report.tsv" "$hand" workflows/example/samples.tsv <<'PY' || fail "report.tsv"
import csv, gzip, json, sys
report, hand, sheet = sys.argv[1:]
rows = list(csv.DictReader(open(report), delimiter="\t"))
samples = [r["sample"] for r in csv.DictReader(open(sheet), delimiter="\t")]
assert [r["sample"] for r in rows] == samples, rows
for row in rows:
    d = f"{hand}/{row['sample']}"
    info = json.load(open(f"{d}/info.json"))
    fit = json.load(open(f"{d}/powerlaw.json"))["power_law"] or {"alpha": "nan", "ci95": ["nan", "nan"],
                                                                 "r_squared": "nan"}
    n_boundaries = sum(1 for line in open(f"{d}/boundaries.bed") if line.strip())
    strength = {int(l.split()[0]): l.split()[1] for l in list(open(f"{d}/saddle.strength.tsv"))[1:]}
    want = {"nnz": info["nnz"], "contacts": info["sum"], "alpha": fit["alpha"],
            "alpha_ci_low": fit["ci95"][0], "alpha_ci_high": fit["ci95"][1],
            "fit_r2": fit["r_squared"], "n_boundaries": n_boundaries}
    for key, value in want.items():
        assert float(row[key]) == float(value) or (row[key] == value == "nan"), (row["sample"], key, row[key], value)
    # pairtools' columns: from the dedup stats of read alignments, empty for the other inputs
    pairs = ["total", "mapped", "dups", "dups_rate", "cis", "trans", "cis_20kb+"]
    try:
        stats = dict(l.rstrip("\n").split("\t") for l in open(f"{d}/dedup.stats"))
    except FileNotFoundError:
        assert all(row[k] == "" for k in pairs), row
    else:
        mapped, dups = int(stats["total_mapped"]), int(stats["total_dups"])
        want = [stats["total"], mapped, dups, dups / mapped, stats["cis"], stats["trans"], stats["cis_20kb+"]]
        assert [row[k] for k in pairs] == [str(v) for v in want], (row, want)
    if row["sample"] == "sim":  # data/pairs/sim.bam: pairtools 1.1.2's numbers
        ref = dict(l.rstrip("\n").split("\t") for l in gzip.open("data/pairs/reference/sim.dedup.stats.gz", "rt"))
        assert (row["total"], row["mapped"], row["dups"]) == (ref["total"], ref["total_mapped"], ref["total_dups"]), row
        assert float(row["dups_rate"]) == int(ref["total_dups"]) / int(ref["total_mapped"]) == float(ref["summary/frac_dups"]), row
        assert [row[k] for k in ("cis", "trans", "cis_20kb+")] == [ref[k] for k in ("cis", "trans", "cis_20kb+")], row
    assert row["saddle_strength_20pct"] == strength[10], row
    group = next(r.get("group", "") for r in csv.DictReader(open(sheet), delimiter="\t")
                 if r["sample"] == row["sample"])
    assert row["group"] == group, row
    if group:
        sccs = [float(r["scc"]) for r in csv.DictReader(open(f"{hand}/hicrep/{group}.scc.tsv"),
                                                         delimiter="\t")
                if r["chrom"] == "genome" and row["sample"] in (r["sample1"], r["sample2"])]
        assert sccs and float(row["mean_scc"]) == sum(sccs) / len(sccs), row
    else:
        assert row["mean_scc"] == "", row
print(f"   report.tsv: {len(rows)} rows equal to the by-hand values")
PY

echo "== HiCRep at equal depth (hicrep_equal_depth: true) against sample + hicrep by hand"
group=$(echo $groups | cut -d ' ' -f 1)
members=$(tail -n +2 workflows/example/samples.tsv | awk -F'\t' -v g="$group" '$6 == g {print $1}')
"$SNAKEMAKE" -s workflows/analysis/Snakefile --cores 2 -q --config contactmap="$cm" outdir="$out" \
  hicrep_equal_depth=true -- "$out/hicrep/$group.scc.tsv" > "$work/equal.log" 2>&1 \
  || { cat "$work/equal.log"; fail "the equal-depth HiCRep"; }
depth=$(for m in $members; do "$py" -c 'import json, sys; print(json.load(open(sys.argv[1]))["sum"])' "$hand/$m/info.json"; done | sort -n | head -n 1)
maps=(); rank=0
for m in $members; do
  quiet "$cm" sample "$hand/$m/base.cool" --count "$depth" --seed $((10 + rank)) -o "$hand/hicrep/$m.equal.cool"
  same_map "$out/hicrep/$group/$m.cool" "$hand/hicrep/$m.equal.cool"
  maps+=("$hand/hicrep/$m.equal.cool"); rank=$((rank + 1))
done
quiet "$cm" hicrep "${maps[@]}" --names "$(echo $members | tr ' ' ',')" --h auto --max-distance 5M \
  --seed 10 -o "$hand/hicrep/$group.equal.scc.tsv"
same "$out/hicrep/$group.scc.tsv" "$hand/hicrep/$group.equal.scc.tsv"
echo "   $group: $depth contacts per sample, maps and SCC table equal to the commands by hand"

echo "== analysis workflow's ingest, one sample per input URI form, against convert by hand"
# form | URI | bin_size | input_options | what convert needs by hand besides the options
forms="$work/forms.txt"
cat > "$forms" <<'EOF'
cool|data/yeast.10kb.cool|10000||
cooler_group|data/layouts/legacy_multires.cool::/0|10000||
mcool_level|data/cooler_test_file.mcool::/resolutions/100000|100000||
mcool_shorthand|data/cooler_test_file.mcool::100000|100000||
hic_level|data/CN.mm9.multires.hic::/resolutions/10000000|10000000||
hic_single|data/hic_test_file.hic|100000||
hicexplorer_h5|data/hicexplorer/small_test_matrix.h5|5000||
bg2_with_bins|data/hg19.GM12878-MboI.matrix.2000kb.bg2.gz|2000000|--bins data/hg19.bins.2000kb.bed.gz|
pairs|data/hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz|2000000|--format pairs --pairs-columns 1,2,4,5 --chrom-sizes workflows/example/hg19.chrom.sizes|--bin-size 2000000
EOF
sheet="$work/forms.tsv"
printf "sample\tinput\tbin_size\tfasta\tinput_options\n" > "$sheet"
targets=()
while IFS='|' read -r form uri bin_size options extra; do
  printf "%s\t%s\t%s\t\t%s\n" "$form" "$uri" "$bin_size" "$options" >> "$sheet"
  targets+=("$work/forms/$form/base.cool")
done < "$forms"
"$SNAKEMAKE" -s workflows/analysis/Snakefile --cores 2 -q --config contactmap="$cm" samples="$sheet" \
  outdir="$work/forms" -- "${targets[@]}" > "$work/forms.log" 2>&1 || { cat "$work/forms.log"; fail "ingest of the URI forms"; }
while IFS='|' read -r form uri bin_size options extra; do
  # shellcheck disable=SC2086
  quiet "$cm" convert "$uri" "$work/forms/$form.hand.cool" $options $extra
  same_map "$work/forms/$form/base.cool" "$work/forms/$form.hand.cool"
  echo "   $form: $uri${options:+ $options}${extra:+ $extra}: base.cool equal to convert by hand"
done < "$forms"

echo "== analysis workflow's pairs inputs told apart by content, against pairtools' outputs and convert by hand"
# kind | URI | the rule that deduplicates it (none: binned as is)
kinds="$work/kinds.txt"
cp data/pairs/sim.bam "$work/sim.alignments" # BAM without its extension
zcat data/pairs/reference/sim.5unique.sorted.pairs.gz > "$work/sim.sorted.pairs"
cat > "$kinds" <<EOF
bam_by_content|$work/sim.alignments|pairs
pairs_4dn|data/pairs/reference/sim.5unique.pairs.gz|pairs_dedup
pairs_4dn_sorted_plain|$work/sim.sorted.pairs|pairs_dedup
pairs_4dn_deduplicated|data/pairs/reference/sim.nodups.pairs.gz|
EOF
if command -v samtools >/dev/null; then # SAM text (when samtools is here to write it)
  samtools view -h -o "$work/sim.sam" data/pairs/sim.bam
  echo "sam|$work/sim.sam|pairs" >> "$kinds"
fi
sheet="$work/kinds.tsv"
printf "sample\tinput\tbin_size\tfasta\tinput_options\tgroup\tchrom_sizes\n" > "$sheet"
targets=()
while IFS='|' read -r kind uri rule; do
  printf "%s\t%s\t20000\t\t\t\tdata/pairs/sim.chrom.sizes\n" "$kind" "$uri" >> "$sheet"
  targets+=("$work/kinds/$kind/base.cool")
done < "$kinds"
"$SNAKEMAKE" -s workflows/analysis/Snakefile --cores 2 -q --config contactmap="$cm" samples="$sheet" \
  outdir="$work/kinds" -- "${targets[@]}" > "$work/kinds.log" 2>&1 || { cat "$work/kinds.log"; fail "ingest of the pairs inputs"; }
quiet "$cm" convert data/pairs/reference/sim.nodups.pairs.gz "$work/kinds/hand.cool" --bin-size 20000
while IFS='|' read -r kind uri rule; do
  d="$work/kinds/$kind"
  case $rule in
    pairs) [ -s "$d/parse.stats" ] || fail "$kind: not through rule pairs" ;;
    pairs_dedup) [ -s "$d/dedup.stats" ] && [ ! -e "$d/parse.stats" ] || fail "$kind: not through rule pairs_dedup" ;;
    *) [ ! -e "$d/dedup.stats" ] || fail "$kind: deduplicated again" ;;
  esac
  if [ -n "$rule" ]; then
    same_pairs "$d/$kind.nodups.pairs.gz" data/pairs/reference/sim.nodups.pairs.gz
    cmp -s "$d/dedup.stats" <(zcat data/pairs/reference/sim.dedup.stats.gz) || fail "$kind: dedup.stats"
  fi
  same_map "$d/base.cool" "$work/kinds/hand.cool"
  what="rule $rule, nodups pairs and dedup.stats equal to pairtools'"
  [ -n "$rule" ] || what="binned as is"
  echo "   $kind: $what; base.cool equal to convert of pairtools' nodups"
done < "$kinds"
printf "sample\tinput\tbin_size\nno_sizes\tdata/pairs/sim.bam\t20000\n" > "$work/no_sizes.tsv"
if "$SNAKEMAKE" -s workflows/analysis/Snakefile -n --config contactmap="$cm" samples="$work/no_sizes.tsv" \
  outdir="$work/no_sizes" > "$work/no_sizes.log" 2>&1 || ! grep -q "needs chromosome sizes" "$work/no_sizes.log"; then
  cat "$work/no_sizes.log"; fail "a BAM sample without chrom_sizes was not refused"
fi
echo "   a BAM sample without chrom_sizes: refused when the sheet is read"

echo "== dry run on a 200-sample sheet in 50 groups"
sheet="$work/200.tsv"
printf "sample\tinput\tbin_size\tfasta\tinput_options\tgroup\n" > "$sheet"
for k in $(seq 1 200); do printf "s%03d\tdata/cooler_test_file.mcool::/resolutions/100000\t100000\t\t\tg%02d\n" "$k" $(((k - 1) / 4)) >> "$sheet"; done
"$SNAKEMAKE" -s workflows/analysis/Snakefile -n --config contactmap="$cm" samples="$sheet" outdir="$work/r200" \
  > "$work/dry.log" 2>&1 || { cat "$work/dry.log"; fail "dry run"; }
"$py" - "$work/dry.log" <<'PY' || fail "dry-run job counts"
import re, sys
text = open(sys.argv[1]).read()
counts = dict(re.findall(r"^(\w+)\s+(\d+)\s*$", text.split("Job stats:")[1], re.M))
per_sample = ["ingest", "balance", "zoomify", "info", "expected", "insulation", "compartments",
              "saddle", "pictures"]
for rule in per_sample:
    assert counts.get(rule) == "200", (rule, counts)
assert counts["hicrep"] == "50", counts
assert counts["report"] == "1" and counts["all"] == "1" and counts["total"] == str(200 * 9 + 50 + 2), counts
print(f"   {counts['total']} jobs: 200 of each of {len(per_sample)} per-sample rules, 50 hicrep (groups of 4), 1 report, 1 all")
PY

echo "== simulation workflow (2 batches) against simulate + merge by hand"
sim="$work/sim"
options="--chains 1000 --density 0.2 --extrusion --ctcf 250+,500-,750. --monomers-per-bin 5 --replicas 1 --equilibration 500 --sample-every 200 --samples 10"
"$SNAKEMAKE" -s workflows/simulation/Snakefile --cores 2 -q --config contactmap="$cm" outdir="$sim" batches=2 \
  seed_base=7 "simulate=$options" insulation_window=50k > "$work/sim.log" 2>&1 || { cat "$work/sim.log"; fail "the simulation workflow"; }
for k in 0 1; do
  # shellcheck disable=SC2086
  quiet "$cm" simulate polymer -o "$work/hand_$k.cool" --seed $((7 + k)) --threads 2 --device cpu $options \
    --truth-boundaries "$work/hand_$k.truth.bed"
  same_map "$sim/batches/$k.cool" "$work/hand_$k.cool"
done
quiet "$cm" merge "$work/hand_0.cool" "$work/hand_1.cool" -o "$work/hand_merged.cool"
same_map "$sim/merged.cool" "$work/hand_merged.cool"
quiet "$cm" tads "$work/hand_merged.cool" --raw --window 50k -o "$work/hand_ins.tsv" --boundaries "$work/hand_calls.bed"
quiet "$cm" score boundaries --truth "$work/hand_0.truth.bed" "$work/hand_calls.bed" -o "$work/hand_score.tsv"
same "$sim/score.tsv" "$work/hand_score.tsv"
same "$sim/truth.bed" "$work/hand_0.truth.bed"
echo "   merged map, truth and score equal to the commands by hand"
echo "test_workflows: ok"
