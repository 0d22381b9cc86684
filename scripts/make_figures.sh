#!/usr/bin/env bash
# Regenerate the committed figures: docs/figures/demo (the pictures of `make demo`, shown in the
# README) and docs/figures/compare (our figures beside the peers' on the same data, for
# docs/plots.md). The peers need a venv with cooler, cooltools, matplotlib and conkit
# (docs/peers.md); without one only the demo figures are made.
#   scripts/make_figures.sh [VENV]        (default VENV: .venv)
set -euo pipefail
cd "$(dirname "$0")/.."
cm="${CONTACTMAP:-target/release/contactmap}"
venv="${1:-.venv}"
DEMO_FIGURES=docs/figures/demo CONTACTMAP="$cm" scripts/demo.sh > /dev/null
echo "demo figures: docs/figures/demo/"
if [[ ! -x "$venv/bin/python" ]]; then
  echo "no venv at $venv: peer figures not made (see docs/peers.md)" >&2
  exit 0
fi
py="$venv/bin/python"
out=docs/figures/compare
mkdir -p "$out"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
dm6=data/cooler_test_file.mcool::/resolutions/100000

# plot map: cooler show (its default colour map, balanced) and the cooltools notebook figures.
"$cm" plot map "$dm6" -r chr2L -o "$out/map_contactmap.png"
"$cm" plot map "$dm6" -r chr2L --cmap YlOrRd -o "$out/map_contactmap_YlOrRd.png"
"$venv/bin/cooler" show -b "$dm6" chr2L -o "$out/map_cooler_show.png"
"$cm" tads "$dm6" --window 500k -o "$work/ins.tsv" --boundaries "$work/b.bed"
"$cm" plot map "$dm6" -r chr2L --triangle --depth 3Mb --boundaries "$work/b.bed" \
  --track "$work/ins.tsv:log2_insulation_score_500000" --width 7.5 --height 4 -o "$out/triangle_contactmap.png"
"$py" scripts/figures/map_matplotlib.py "$dm6" chr2L "$work" 500000 3000000
mv "$work/mpl_square.png" "$out/map_cooltools_notebook.png"
mv "$work/mpl_triangle.png" "$out/triangle_cooltools_notebook.png"

# plot expected: the cooltools "contacts vs distance" notebook figure.
"$cm" plot expected "$dm6" data/yeast.10kb.cool -o "$out/ps_contactmap.png"
"$py" scripts/figures/ps_matplotlib.py "$dm6" data/yeast.10kb.cool "$out/ps_cooltools_notebook.png"

# plot contacts: ConKit's contact-map figure (two predictions, as its --otherfile).
p=data/protein/1atzA
"$cm" plot contacts --structure "$p/1atzA.pdb.gz" --fasta "$p/1atzA.fasta" "$p/1atzA.apc.mat.gz" \
  "$p/1atzA.noapc.mat.gz" -o "$out/contacts_contactmap_1atzA.png"
"$py" -W ignore scripts/figures/conkit_cmap.py --structure "$p/1atzA.pdb.gz" --fasta "$p/1atzA.fasta" \
  "$p/1atzA.apc.mat.gz" --other "$p/1atzA.noapc.mat.gz" -o "$out/contacts_conkit_1atzA.png" > /dev/null
echo "peer comparison figures: $out/"
