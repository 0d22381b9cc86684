#!/usr/bin/env bash
# The contactmap pipeline on the real example data in data/ (run by `make demo`).
set -euo pipefail
cd "$(dirname "$0")/.."
cm="${CONTACTMAP:-target/release/contactmap}"
# Intermediate files go to a temporary folder, removed at the end, or to DEMO_WORK, kept
# (scripts/compare_outputs.sh compares them between two binaries).
if [ -n "${DEMO_WORK:-}" ]; then
  work="$DEMO_WORK"; mkdir -p "$work"
else
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
fi
# Pictures go here (scripts/make_figures.sh points it at docs/figures/demo for the README).
figs="${DEMO_FIGURES:-demo-figures}"
mkdir -p "$figs"
step() { printf '\n\033[1m== %s\033[0m\n$ %s\n' "$1" "${*:2}"; "${@:2}"; }
# same_pixels URI_A URI_B WHAT: say that two matrices hold identical pixels, or stop the demo.
same_pixels() {
  "$cm" dump "$1" > "$work/a.tsv"
  "$cm" dump "$2" > "$work/b.tsv"
  if cmp -s "$work/a.tsv" "$work/b.tsv"; then
    echo "   $3: identical pixels ($(wc -l < "$work/a.tsv") pixels)"
  else
    echo "   $3: the pixels DIFFER" >&2; exit 1
  fi
}

# From the aligner's BAM to a picture: simulated Hi-C reads aligned by bwa mem -SP5M
# (scripts/pairs_fixture.py), through pairs (as pairtools), a multi-resolution cooler and a map.
bam=data/pairs/sim.bam
sizes=data/pairs/sim.chrom.sizes
step "Pairs from a BAM, sorted and deduplicated in one pipe (as pairtools parse | sort | dedup)" \
  bash -c "set -o pipefail; '$cm' pairs parse '$bam' -c '$sizes' --assembly sim --output-stats '$work/sim.parse.stats' \
    | '$cm' pairs sort | '$cm' pairs dedup -o '$work/sim.nodups.pairs.gz' --output-dups '$work/sim.dups.pairs.gz' \
      --output-stats '$work/sim.dedup.stats'"
grep -E '^(total|total_mapped|total_dups|total_nodups|cis|trans|cis_20kb\+)\s' "$work/sim.dedup.stats"
step "Read pairs binned at 1 kb (as cooler cload pairs)" \
  "$cm" convert "$work/sim.nodups.pairs.gz" "$work/sim.1kb.cool" --bin-size 1000
step "Zoom levels to 20 kb, each balanced (as cooler zoomify --balance)" \
  "$cm" zoomify "$work/sim.1kb.cool" -r 1000,5000,10000,20000 --balance -o "$work/sim.mcool"
# 1,065 pairs leave most 5 kb bins with fewer than 10 nonzero pixels, which ICE's default
# --min-nnz masks (and the level does not converge): balance that level again with 3.
step "The 5 kb level balanced again, masking bins with fewer than 3 nonzero pixels" \
  "$cm" balance "$work/sim.mcool::/resolutions/5000" --store --force --min-nnz 3
step "Picture: chr1 of the simulated genome at 5 kb (balanced)" \
  "$cm" plot map "$work/sim.mcool::/resolutions/5000" -r chr1 -o "$figs/sim_pairs_map.png"

mcool=data/cooler_test_file.mcool
hic=data/hic_test_file.hic

step "Inspect a multi-resolution cooler (Drosophila dm6, 4DN)" "$cm" info "$mcool"
step "Inspect one resolution" "$cm" info "$mcool::/resolutions/100000"
if [ -f "$hic" ]; then
  step "Inspect the same data as a Juicer .hic v9" "$cm" info "$hic"
  step "Convert .hic -> .cool" "$cm" convert "$hic" "$work/from_hic.cool"
  same_pixels "$work/from_hic.cool" "$mcool::/resolutions/100000" ".hic and .mcool"
fi
step "Dump a region, balanced with cooler's ICE weights, with coordinates" \
  "$cm" dump "$mcool::/resolutions/100000" -r chr2L:1,000,000-1,300,000 --join --balanced -H
step "Zoom levels balanced one by one, as cooler zoomify --balance (pixels summed into coarser bins)" \
  "$cm" zoomify "$mcool::/resolutions/100000" -r 100000N --balance -o "$work/zoom.mcool"
"$cm" info "$work/zoom.mcool"
step "Write a Juicer .hic (v9) for Juicebox: 100 kb to 1 Mb, with VC, VC_SQRT, KR and SCALE per chromosome and Juicer's expected values" \
  "$cm" convert "$mcool::/resolutions/100000" "$work/dm6.hic" --resolutions 100000,200000,500000,1000000 --genome dm6
"$cm" info "$work/dm6.hic"
same_pixels "$work/dm6.hic::/resolutions/1000000" "$mcool::/resolutions/1000000" \
  "its 1 Mb level and the .mcool's own 1 Mb level (Juicer's)"
if [ -f data/hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz ]; then
  "$cm" dump -t chroms data/hg19.GM12878-MboI.matrix.2000kb.cool > "$work/hg19.sizes"
  step "Bin read pairs into a 2 Mb cooler" "$cm" convert data/hg19.GM12878-MboI.pairs.subsample.sorted.txt.gz \
    "$work/pairs.cool" --format pairs --bin-size 2000000 --chrom-sizes "$work/hg19.sizes" --pairs-columns 1,2,4,5
  "$cm" info "$work/pairs.cool"
fi
dm6="$mcool::/resolutions/100000"
step "Balance with ICE exactly as cooler (weights to a table; --store writes them into the file)" \
  "$cm" balance "$dm6" -o "$work/weights.tsv"
head -4 "$work/weights.tsv"
step "SCALE, Juicer's default normalisation, per chromosome: the vectors Juicer stored (chrY does not converge, in Juicer either; its vector is kept, as Juicer does)" \
  "$cm" balance "$dm6" --method scale --cis-only -o "$work/scale.tsv"
cp "$mcool" "$work/dm6.mcool"
step "Store the weights in a copy of the file, as a column named ice" \
  "$cm" balance "$work/dm6.mcool::/resolutions/100000" --store --name ice
"$cm" info "$work/dm6.mcool::/resolutions/100000" | grep weights
step "Expected P(s) per diagonal (cooltools expected-cis columns)" \
  "$cm" expected "$dm6" -o "$work/expected.tsv"
head -5 "$work/expected.tsv" | cut -f1-9
step "Its power law: the exponent biologists quote, and piecewise exponents" \
  "$cm" expected "$dm6" --fit
step "Picture: P(s) with its local slope and the fitted power law (the table above works as input too)" \
  "$cm" plot expected "$dm6" --fit --labels "dm6 100 kb" -o "$figs/dm6_ps.png"
step "Observed/expected map (balanced), as a cooler" \
  "$cm" normalize "$dm6" "$work/oe.cool" --method oe
"$cm" dump "$work/oe.cool" -r chr2L:1,000,000-1,300,000 --join -H
step "Picture: observed/expected of chr2L:5-15 Mb (RdBu_r around 1, log scale)" \
  "$cm" plot map "$dm6" -r chr2L:5Mb-15Mb --oe -o "$figs/dm6_oe.png"
step "TADs: diamond insulation at three windows, as cooltools insulation (boundaries and domains as BED)" \
  "$cm" tads "$dm6" --window 300k,500k,1M -o "$work/insulation.tsv" \
  --boundaries "$work/boundaries.bed" --domains "$work/domains.bed"
head -3 "$work/insulation.tsv" | cut -f1-8
head -3 "$work/boundaries.bed"
step "TADs: directionality index with Dixon's HMM domains" \
  "$cm" tads "$dm6" --method directionality --window 500k -o "$work/di.tsv" --domains "$work/di_domains.bed"
step "Picture: chr2L with its domains and boundaries drawn on the map, the insulation score under it" \
  "$cm" plot map "$dm6" -r chr2L --domains "$work/domains.bed" --boundaries "$work/boundaries.bed" \
  --track "$work/insulation.tsv:log2_insulation_score_500000" -o "$figs/dm6_tads.png"
step "Picture: the 45-degree view to 3 Mb, with insulation and directionality tracks" \
  "$cm" plot map "$dm6" -r chr2L --triangle --depth 3Mb --boundaries "$work/boundaries.bed" \
  --track "$work/insulation.tsv:log2_insulation_score_500000" \
  --track "$work/di.tsv:directionality_index_500000" --width 8 --height 5 -o "$figs/dm6_triangle.png"
step "TADs: TopDom" "$cm" tads "$dm6" --method topdom -o "$work/topdom.tsv" --boundaries "$work/topdom.bed"
step "Compartments: E1-E3 per chromosome as cooltools eigs-cis (sparse eigensolver; oriented by coverage here, --fasta genome.fa orients A = GC-rich)" \
  "$cm" compartments "$dm6" -o "$work/dm6"
step "Its eigenvalues per chromosome (E1 is the compartment vector where |eigval1| stands out)" \
  cat "$work/dm6.cis.lam.txt"
step "The saddle of E1 (cooltools saddle) and its strength" \
  "$cm" saddle "$dm6" --track "$work/dm6.cis.vecs.tsv:E1" --n-bins 20 -o "$work/dm6"
step "Picture: the saddle (B-B top left, A-A bottom right)" \
  "$cm" plot saddle "$work/dm6.saddle.tsv" --title "dm6 100 kb, E1 classes" -o "$figs/dm6_saddle.png"
step "Loops: cooltools' dot caller on the yeast 10 kb map (four kernels, FDR per lambda bin, BIRCH clusters; cooltools finds the same 2 dots)" \
  "$cm" dots data/yeast.10kb.cool -o "$work/yeast.dots.tsv" --enriched "$work/yeast.enriched.tsv"
sim=data/sim_extrusion.5kb.cool
step "Loops on a simulated loop-extrusion map (data/sim_extrusion.5kb.cool: 200 beads of 5 kb, five pairs of boundary elements), scored against the element pairs its LEFs held in >= 20% of the samples" \
  "$cm" dots "$sim" -o "$work/sim.dots.bedpe"
"$cm" score loops --truth data/sim_extrusion.truth_loops.bedpe "$work/sim.dots.bedpe" --min-fraction 0.2
step "The same map at 5, 10 and 25 kb: dots at each level, merged as Juicer's HiCCUPS merges them (a resolution column says where each loop came from)" \
  "$cm" zoomify "$sim" -o "$work/sim.mcool" -r 5000,10000,25000 --balance
"$cm" dots "$work/sim.mcool" --resolutions 5k,10k,25k -o "$work/sim.loops.bedpe"
step "Picture: the simulated map with its 5 kb dots outlined" \
  "$cm" plot map "$sim" --region chr1 --loops "$work/sim.dots.bedpe" -o "$figs/sim_dots.png"
step "Pileup (coolpuppy): the simulated map observed/expected at its held loops, by distance, with Juicer's APA scores" \
  "$cm" pileup "$sim" data/sim_extrusion.truth_loops.bedpe --flank 20k --mindist 0 --by-distance -o "$work/sim.loops"
cut -f1-4,8 "$work/sim.loops.scores.tsv"
step "The same with shifted random controls instead of the expected (coolpuppy's draws: --seed 1 gives coolpuppy's controls)" \
  "$cm" pileup "$sim" data/sim_extrusion.truth_loops.bedpe --flank 20k --mindist 0 --nshifts 10 --seed 1 -o "$work/sim.loops.shifts"
cut -f1-4 "$work/sim.loops.shifts.scores.tsv"
step "Picture: the pileups per distance band, as plotpup draws them (centre enrichment in the corner)" \
  "$cm" plot pileup "$work/sim.loops" -o "$figs/sim_loops_pileup.png"
step "Comparing samples: the yeast map downsampled twice to a third of its contacts, exactly (cooltools random-sample --exact; two seeds)" \
  "$cm" sample data/yeast.10kb.cool --fraction 0.33 --exact --seed 1 -o "$work/yeast.third_a.cool"
"$cm" sample data/yeast.10kb.cool --fraction 0.33 --exact --seed 2 -o "$work/yeast.third_b.cool"
step "HiCRep reproducibility of the full map and the two thirds (hicrep 0.2.6's SCC per pair and chromosome; genome-wide rows shown; h = 3 bins, 500 kb)" \
  "$cm" hicrep data/yeast.10kb.cool "$work/yeast.third_a.cool" "$work/yeast.third_b.cool" --h 3 --max-distance 500k --names full,third_a,third_b -o "$work/yeast.scc.tsv"
grep genome "$work/yeast.scc.tsv"
step "Picture: the SCCs as a clustered heatmap (average linkage of 1 - SCC, as seaborn's clustermap)" \
  "$cm" plot hicrep "$work/yeast.scc.tsv" --title "yeast, 10 kb" -o "$figs/yeast_scc.png"
step "Picture: two samples in one map, the full map above the diagonal and a third below, brought to the full map's depth by their totals" \
  "$cm" plot map data/yeast.10kb.cool -r chrIV:200k-900k --compare "$work/yeast.third_a.cool" --raw -o "$figs/yeast_compare.png"
step "A synthetic map with known domains (power-law decay, Poisson noise, no coverage bias)" \
  "$cm" simulate blocks -o "$work/blocks.cool" --truth-boundaries "$work/truth.bed" --seed 1
"$cm" info "$work/blocks.cool" | grep -E "nbins|nnz"
step "Its TADs by insulation (raw counts: the simulated map has no bias to balance)" \
  "$cm" tads "$work/blocks.cool" --raw --window 200k -o "$work/blocks_insulation.tsv" --boundaries "$work/calls.bed"
step "Boundary calls scored against the truth (precision, recall, F1 within one bin)" \
  "$cm" score boundaries --truth "$work/truth.bed" "$work/calls.bed"
step "Picture: the synthetic map, its true boundaries marked on it, the insulation score under it" \
  "$cm" plot map "$work/blocks.cool" -r chr1:0-8Mb --raw --boundaries "$work/truth.bed" \
  --track "$work/blocks_insulation.tsv:log2_insulation_score_200000" -o "$figs/blocks_truth.png"
step "A simulated polymer: 1,000 beads in a sphere, loop extrusion stalled at 4 boundary elements (Brownian dynamics, 4 replicas in parallel; a short run: the loops form within it, the chain at large does not relax, and the warning says so)" \
  "$cm" simulate polymer -o "$work/polymer.cool" --chains 1000 --density 0.2 --extrusion \
  --ctcf 200,400,600,800 --capture 0.99 --release 0.002 --processivity 200 --separation 100 \
  --steps-per-move 200 --monomers-per-bin 10 --replicas 4 --equilibration 20000 \
  --sample-every 1000 --samples 20 --seed 1 --truth-boundaries "$work/polymer.truth.bed"
step "A second ensemble with another seed, merged with the first: more contacts, the same truth" \
  "$cm" simulate polymer -o "$work/polymer2.cool" --chains 1000 --density 0.2 --extrusion \
  --ctcf 200,400,600,800 --capture 0.99 --release 0.002 --processivity 200 --separation 100 \
  --steps-per-move 200 --monomers-per-bin 10 --replicas 4 --equilibration 20000 \
  --sample-every 1000 --samples 20 --seed 2
"$cm" merge "$work/polymer.cool" "$work/polymer2.cool" -o "$work/polymer.merged.cool"
"$cm" info "$work/polymer.merged.cool" | grep -E "nnz|sum"
step "Its TADs by insulation, scored against the boundary elements" \
  "$cm" tads "$work/polymer.merged.cool" --raw --window 100k -o "$work/polymer.ins.tsv" --boundaries "$work/polymer.calls.bed"
"$cm" score boundaries --truth "$work/polymer.truth.bed" "$work/polymer.calls.bed"
step "Picture: the merged polymer ensembles' map with its boundary elements (truth) and insulation" \
  "$cm" plot map "$work/polymer.merged.cool" -r chr1 --raw --boundaries "$work/polymer.truth.bed" \
  --track "$work/polymer.ins.tsv:log2_insulation_score_100000" -o "$figs/polymer_truth.png"
step "A polychrom trajectory (data/polychrom/traj: 7 conformations, 150 beads) as polychrom's binnedContactMap counts it" \
  "$cm" polymer-map data/polychrom/traj --contact-radius 1.6 --monomers-per-bin 4 --chains 90,60 -o "$work/traj.cool"
step "Its polymer statistics as polychrom's polymer_analyses: P(s), R^2(s), Rg^2(s)" \
  "$cm" polymer-stats data/polychrom/traj --contact-radius 1.6 -o "$work/traj"
head -4 "$work/traj.scaling.tsv" "$work/traj.r2.tsv"
step "Picture: those statistics with their local slopes" \
  "$cm" plot polymer-stats "$work/traj" --labels "polychrom traj" -o "$figs/traj_stats.png"
step "Picture: P(s) of the two simulated maps, each with its fitted power law" \
  "$cm" plot expected "$work/blocks.cool" "$work/polymer.merged.cool" --raw --fit --labels "blocks (simulate blocks)","polymer (simulate polymer)" \
  -o "$figs/simulated_ps.png"
step "Protein: true contacts of a structure (Cb-Cb < 8 A, Ca for Gly) as CASP RR" \
  "$cm" contacts data/protein/1aapA/1aapA.pdb.gz -o "$work/1aapA.true.rr"
head -4 "$work/1aapA.true.rr"
step "Protein: CCMpred and RR predictions scored against their structures (CASP long-range precision)" \
  "$cm" score contacts --structure data/protein/toxd/toxd.pdb.gz data/protein/toxd/toxd.mat.gz \
  --fasta data/protein/toxd/toxd.fasta --ranges long
"$cm" score contacts --structure data/protein/1aapA/1aapA.pdb.gz data/protein/1aapA/1aapA.rr.gz --ranges long
step "Picture: the toxd contact map, top-L CCMpred pairs coloured true / false positive, and the precision curve" \
  "$cm" plot contacts --structure data/protein/toxd/toxd.pdb.gz --fasta data/protein/toxd/toxd.fasta \
  data/protein/toxd/toxd.mat.gz -o "$figs/toxd_contacts.png"
step "Protein: a structure numbered 151-220 placed on its sequence (register), its own contacts score 1" \
  "$cm" contacts data/protein/1a8o/1A8O.cif.gz --fasta data/protein/1a8o/1A8O.fasta -o "$work/1a8o.rr"
"$cm" score contacts --structure data/protein/1a8o/1A8O.pdb.gz "$work/1a8o.rr" --ranges long --top L/5,L 2>/dev/null
step "Protein: two predictions compared without a structure (Jaccard of the top lists)" \
  "$cm" score overlap data/protein/1atzA/1atzA.apc.mat.gz data/protein/1atzA/1atzA.noapc.mat.gz --ranges long
step "An MD trajectory (data/md: adenylate kinase, 3 XTC frames of its open -> closed transition): residue contact frequencies as MDTraj's compute_contacts, closest heavy atoms < 4.5 A" \
  "$cm" contacts --trajectory data/md/adk.xtc --topology data/md/adk.pdb.gz --definition closest-heavy \
  --cutoff 4.5 -o "$work/adk.freq.tsv"
awk -F'\t' 'NR > 1 && $8 > 0 && $8 < 3' "$work/adk.freq.tsv" | wc -l | sed 's/^/   pairs in contact in some frames only (the transition): /'
printf '\n\033[1m== %s\033[0m\n$ %s\n' "The viewer: contactmap serve (HiGlass' API and page) on the dm6 map with its TAD domains; a tile asked for over HTTP" \
  "$cm serve $mcool $work/domains.bed --port 0"
"$cm" serve "$mcool" "$work/domains.bed" --port 0 2> "$work/serve.log" &
serve_pid=$!
for _ in $(seq 50); do grep -q 'http://' "$work/serve.log" && break; sleep 0.1; done
url=$(grep -o 'http://[0-9.:]*/' "$work/serve.log" | head -1)
cat "$work/serve.log"
if [ -n "$url" ] && command -v curl >/dev/null; then
  # whole answers first, then their starts: `curl | head -c` fails under pipefail when head
  # closes the pipe before curl has written everything (curl's exit 23)
  tilesets=$(curl -sf "${url}api/v1/tilesets/")
  tile=$(curl -sf "${url}api/v1/tiles/?d=cooler_test_file.1.0.0")
  echo "${tilesets:0:300} ..."
  echo "${tile:0:120} ..."
fi
kill -INT "$serve_pid"; wait "$serve_pid" || true
echo "   to look: $cm serve $mcool $work/domains.bed   (then open http://127.0.0.1:8989/)"
printf '\nDemo finished. Pictures: %s/\n' "$figs"
ls "$figs"
