#!/usr/bin/env bash
# compare_outputs.sh OLD NEW: run the demo and a set of extra commands (every command, the output
# formats the demo does not write) with two builds of contactmap, and compare every file they write
# and everything they print. For refactors that must not change any output (issue 27).
#
# OLD and NEW are contactmap binaries or git revisions; a revision is built in a worktree under
# target/compare (release profile, one target folder shared by both, so deps are built once).
#
# Files are compared byte for byte. HDF5 files (.cool, .mcool, .h5), whose bytes hold libhdf5's
# object times and cooler's creation-date, are compared by content instead: every group, dataset
# (shape, type, a digest of the values) and attribute but creation-date, with h5py when $PYTHON
# (default python3) has it, else through `contactmap dump` / `info --json` of the NEW binary.
# Files are recognised by their first bytes. So are .hic files, whose blocks are written in the order their compression ends: header,
# bins with every normalisation vector and pixels at every resolution. What is printed is compared after the two
# output folders' names are replaced by one placeholder.
#
# COMPARE_DIR keeps the outputs there; with COMPARE_REUSE=1 too, the outputs already there are
# compared again without running anything.
#
#   scripts/compare_outputs.sh 9847b1a HEAD
#   scripts/compare_outputs.sh /path/to/old/contactmap target/release/contactmap
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -eq 2 ] || { echo "usage: $0 OLD NEW (binaries or git revisions)" >&2; exit 2; }
root="$(pwd)"
out="${COMPARE_DIR:-$(mktemp -d)}"
mkdir -p "$out"

# binary_of REV_OR_BINARY NAME: print the path of a binary, building a revision if needed.
binary_of() {
  if [ -x "$1" ] && [ -f "$1" ]; then realpath "$1"; return; fi
  local rev tree
  rev="$(git rev-parse --verify "$1^{commit}")" || { echo "$1: not a binary nor a revision" >&2; exit 2; }
  tree="$root/target/compare/tree-$2"
  rm -rf "$tree"; git worktree prune
  git worktree add --detach -q "$tree" "$rev"
  (cd "$tree" && PATH="$(scripts/ensure-cmake.sh):$PATH" \
    CARGO_TARGET_DIR="$root/target/compare/build" cargo build --release --quiet) >&2
  cp "$root/target/compare/build/release/contactmap" "$root/target/compare/contactmap-$2"
  git worktree remove --force "$tree"
  echo "$root/target/compare/contactmap-$2"
}

# Each binary is run as OUT/bin-{old,new}/contactmap, so that what they print (usage lines name
# the program) differs only in the folder, replaced below.
mkdir -p "$out/bin-old" "$out/bin-new"
cp "$(binary_of "$1" old)" "$out/bin-old/contactmap"
cp "$(binary_of "$2" new)" "$out/bin-new/contactmap"
old="$out/bin-old/contactmap"
new="$out/bin-new/contactmap"

# run_all BINARY DIR: the demo and the extra commands, outputs under DIR, what they print in DIR.log
run_all() {
  local cm="$1" dir="$2"
  rm -rf "$dir"; mkdir -p "$dir/work" "$dir/figs" "$dir/extra"
  DEMO_WORK="$dir/work" DEMO_FIGURES="$dir/figs" CONTACTMAP="$cm" scripts/demo.sh > "$dir.log" 2>&1
  local x="$dir/extra" mcool=data/cooler_test_file.mcool
  local dm6="$mcool::/resolutions/100000"
  {
    run() { printf '$ %s\n' "$*"; "$@" || printf '[exit %s]\n' "$?"; }
    run "$cm" info --json "$dm6"
    run "$cm" info data/CN.mm9.multires.hic
    run "$cm" dump -t bins "$dm6"
    run "$cm" dump -t chroms data/hic_test_file.hic
    run "$cm" dump data/CN.mm9.10000kb.cool --balanced --join -r chr1 --region2 chr2
    run "$cm" convert "$dm6" "$x/dm6.bg2.gz"
    run "$cm" convert data/hg19.GM12878-MboI.matrix.2000kb.bg2.gz "$x/bg2.cool" \
      --bins data/hg19.bins.2000kb.bed.gz
    run "$cm" convert data/yeast.10kb.cool "$x/yeast.mcool" --resolutions 10000,20000,50000
    run "$cm" convert data/hicexplorer/small_test_matrix.h5 "$x/hicexplorer.cool"
    run "$cm" merge data/yeast.10kb.cool data/yeast.10kb.cool -o "$x/yeast2.cool"
    run "$cm" zoomify data/yeast.10kb.cool -r 10000,40000 -o "$x/zoom.hic"
    run "$cm" balance data/yeast.10kb.cool --method kr -o "$x/kr.tsv"
    run "$cm" balance data/yeast.10kb.cool --method vc -o "$x/vc.tsv"
    run "$cm" balance data/CN.mm9.10000kb.cool --cis-only -o "$x/cis.tsv"
    cp data/yeast.10kb.cool "$x/stored.cool"
    run "$cm" balance "$x/stored.cool" --store --name w2
    run "$cm" validate data/yeast.10kb.cool
    run "$cm" validate data/hic_test_file.hic
    run "$cm" expected "$dm6" --logbin -o "$x/logbin.tsv"
    run "$cm" expected data/CN.mm9.10000kb.cool --trans -o "$x/trans.tsv"
    run "$cm" expected data/yeast.10kb.cool --fit --fit-range 20k-200k
    run "$cm" normalize data/yeast.10kb.cool "$x/oe.bg2" --method log2oe
    run "$cm" normalize data/yeast.10kb.cool "$x/z.cool" --method zscore
    run "$cm" tads data/yeast.10kb.cool --method armatus -o "$x/armatus.tsv" --domains "$x/armatus.bed"
    run "$cm" tads data/yeast.10kb.cool --window 50k,100k -o "$x/ins.tsv"
    run "$cm" compartments data/CN.mm9.10000kb.cool --trans -o "$x/trans"
    run "$cm" compartments "$dm6" -o "$x/cis" --n-eigs 2
    run "$cm" saddle "$dm6" --track "$x/cis.cis.vecs.tsv:E1" --n-bins 10 -o "$x/cis"
    printf 'chr2L\t0\t10000000\tA\nchr2L\t10000000\t23500000\tB\n' > "$x/ab.bed"
    run "$cm" score compartments --truth "$x/ab.bed" "$x/cis.cis.vecs.tsv:E1"
    run "$cm" simulate blocks -o "$x/blocks.cool" --truth-boundaries "$x/truth.bed" --seed 3 \
      --chroms 2 --bins 200
    run "$cm" convert "$x/blocks.cool" "$x/blocks.hic"
    run "$cm" score boundaries --truth "$x/truth.bed" "$x/truth.bed"
    run "$cm" contacts data/protein/toxd/toxd.pdb.gz --matrix -o "$x/toxd.dist.tsv"
    run "$cm" score contacts --structure data/protein/1guuA/1guuA.pdb.gz data/protein/1guuA/1guuA.contact.rr \
      --ranges all --top L/2,L -o "$x/1guu.score.tsv"
    run "$cm" plot map data/yeast.10kb.cool -r chrI -o "$x/yeast.svg"
    run "$cm" plot expected data/yeast.10kb.cool --fit -o "$x/yeast_ps.svg"
    run "$cm" plot contacts --structure data/protein/1aapA/1aapA.pdb.gz data/protein/1aapA/1aapA.rr.gz \
      -o "$x/1aap.svg"
    run "$cm" plot saddle "$x/cis.saddle.tsv" -o "$x/saddle.svg"
    # the code issue 27 moved into the library: BED readers, tables, writers, figures
    printf 'chrom\tstart\tend\nchrI\t10000\t30000\nchrII\t0\t5000\n' > "$x/black.bed"
    run "$cm" balance data/yeast.10kb.cool --blacklist "$x/black.bed" -o "$x/black.tsv"
    printf '# arms\nchrI\t0\t100000\tleft\nchrI\t100000\t230218\n' > "$x/view.bed"
    run "$cm" expected data/yeast.10kb.cool --view "$x/view.bed" -o "$x/view_exp.tsv"
    run "$cm" expected data/yeast.10kb.cool -o "$x/yexp.tsv"
    run "$cm" dump data/yeast.10kb.cool -t bins --header --na-rep NA --float-format .4g
    run "$cm" dump data/yeast.10kb.cool -t chroms --header
    run "$cm" tads data/yeast.10kb.cool --method topdom -o "$x/topdom.tsv" --boundaries "$x/topdom.bed"
    run "$cm" tads data/yeast.10kb.cool --method directionality -o "$x/di.tsv" --domains "$x/di.bed" --json
    run "$cm" zoomify data/yeast.10kb.cool -r 10000,20000 --balance -o "$x/zb.mcool"
    run "$cm" normalize data/yeast.10kb.cool "$x/oe_table.bg2" --expected "$x/yexp.tsv"
    run "$cm" simulate polymer -o "$x/poly.cool" --chains 60 --replicas 2 --samples 2 \
      --equilibration 200 --sample-every 100 --types A10B10 --extrusion --ctcf 10+,30-,50 \
      --truth-compartments "$x/tc.bed" --truth-boundaries "$x/tb.bed" --truth-domains "$x/td.bed" \
      --stats "$x/stats.tsv" --conformations "$x/conf.tsv" --seed 1 --device cpu --monomers-per-bin 2
    run "$cm" score contacts --structure data/protein/1guuA/1guuA.pdb.gz data/protein/1guuA/1guuA.contact.rr \
      --json --curve "$x/1guu.curve.tsv"
    run "$cm" score contacts --structure data/protein/1guuA/1guuA.pdb.gz data/protein/1guuA/1guuA.contact.rr
    run "$cm" score overlap data/protein/1guuA/1guuA.contact.rr data/protein/1guuA/1guuA.contact.rr
    run "$cm" score boundaries --truth "$x/topdom.bed" "$x/topdom.bed" --truth-domains "$x/armatus.bed" \
      --domains "$x/di.bed"
    run "$cm" plot map data/yeast.10kb.cool -r chrI --oe --expected "$x/yexp.tsv" \
      --domains "$x/armatus.bed" --track "$x/ins.tsv:log2_insulation_score_50000" -o "$x/oe.svg"
    run "$cm" plot expected "$x/yexp.tsv" --per-region -o "$x/ps_table.svg"
    # moved later in issue 27: RR and overlap writers, block truth, the device choice
    run "$cm" contacts data/protein/1aapA/1aapA.pdb.gz -o "$x/1aap.contacts.rr"
    run "$cm" contacts data/protein/toxd/toxd.pdb.gz --min-sep 12 -o "$x/toxd.contacts.rr"
    run "$cm" contacts data/protein/1a8o/1A8O.pdb.gz -o "$x/1a8o.contacts.rr"
    run "$cm" score overlap data/protein/1guuA/1guuA.contact.rr data/protein/1guuA/1guuA.contact.rr --tsv \
      --length 60
    run "$cm" simulate blocks -o "$x/blocks2.cool" --truth-domains "$x/truth_domains.bed" --seed 4 \
      --chroms 1 --bins 120
    run "$cm" simulate polymer -o "$x/auto.cool" --chains 20 --replicas 1 --samples 2 \
      --equilibration 1R --sample-every 0.5r --seed 1 --threads 1
    run "$cm" completions bash
    run "$cm" man --dir "$x/man"
  } > "$dir.extra.log" 2>&1
}

if [ -n "${COMPARE_REUSE:-}" ] && [ -d "$out/old" ] && [ -d "$out/new" ]; then
  echo "comparing the outputs already in $out (COMPARE_REUSE)" >&2
else
  echo "running OLD ($old) and NEW ($new) into $out" >&2
  run_all "$old" "$out/old"
  run_all "$new" "$out/new"
fi

# HDF5 content as text, without the times: h5py if $PYTHON (default python3) has it, else
# contactmap dump / info --json of each matrix in the file.
python="${PYTHON:-python3}"
h5_text() {
  if "$python" -c 'import h5py, numpy' 2>/dev/null; then
    "$python" - "$1" <<'EOF'
import hashlib, sys, h5py, numpy as np
def show(name, obj):
    for key in sorted(obj.attrs):
        if key != "creation-date":
            print(name, "@", key, repr(obj.attrs[key]))
    if isinstance(obj, h5py.Dataset):
        data = np.asarray(obj[()])
        digest = hashlib.sha256(data.tobytes()).hexdigest() if data.dtype.kind != "O" else repr(data)
        print(name, obj.shape, obj.dtype, obj.compression, digest)
with h5py.File(sys.argv[1], "r") as f:
    show("/", f)
    f.visititems(show)
EOF
  else
    local uri uris
    uris="$("$new" info --json "$1" 2>/dev/null | grep -o '::/resolutions/[0-9]*' | sort -u)"
    for uri in ${uris:-NONE}; do
      [ "$uri" = NONE ] && uri=""
      "$new" info --json "$1$uri" | grep -v creation
      "$new" dump -t bins "$1$uri"; "$new" dump -t pixels "$1$uri"
    done
  fi
}

# A .hic's content: its header and every resolution's bins (with the normalisation vectors)
# and pixels, read by the NEW binary (blocks are written in the order their compression ends).
hic_text() {
  local res
  "$new" info --json "$1"
  for res in $("$new" info --json "$1" | grep -o '"resolutions": \[[0-9, ]*' | grep -o '[0-9][0-9]*'); do
    "$new" dump -t bins "$1::/resolutions/$res"; "$new" dump -t pixels "$1::/resolutions/$res"
  done
}

status=0
compared=0
while IFS= read -r -d '' file; do
  rel="${file#"$out/old/"}"
  other="$out/new/$rel"
  compared=$((compared + 1))
  if [ ! -f "$other" ]; then echo "only in OLD: $rel"; status=1; continue; fi
  cmp -s "$file" "$other" && continue
  case "$(head -c 4 "$file" | od -An -c | tr -d ' ')" in
    211HDF)  # HDF5, whatever the extension
      if cmp -s <(h5_text "$file" | sed "s#$out/old#OUT#g") \
        <(h5_text "$other" | sed "s#$out/new#OUT#g"); then continue; fi ;;
    'HIC\0')
      if cmp -s <(hic_text "$file" | sed "s#$out/old#OUT#g") \
        <(hic_text "$other" | sed "s#$out/new#OUT#g"); then continue; fi ;;
  esac
  echo "DIFFERS: $rel"; status=1
done < <(find "$out/old" -type f -print0 | sort -z)
while IFS= read -r -d '' file; do
  rel="${file#"$out/new/"}"
  [ -f "$out/old/$rel" ] || { echo "only in NEW: $rel"; status=1; }
done < <(find "$out/new" -type f -print0)
for log in log extra.log; do
  if ! diff <(sed -e "s#$out/old#OUT#g" -e "s#$out/bin-old#BIN#g" "$out/old.$log") \
      <(sed -e "s#$out/new#OUT#g" -e "s#$out/bin-new#BIN#g" "$out/new.$log") \
      > "$out/$log.diff"; then
    echo "printed output DIFFERS ($log): see $out/$log.diff"; head -20 "$out/$log.diff"; status=1
  fi
done
echo "$compared files compared, and what both printed: $([ $status = 0 ] && echo identical || echo 'differences above')"
exit $status
