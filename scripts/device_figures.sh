#!/usr/bin/env bash
# The figures that only a lent many-core GPU machine gives (docs/performance.md), in one call:
#   1. polymer-map against polychrom's binnedContactMap (n=2), 1,000 x 10,000 beads, 3 repeats,
#      then polymer-map alone on 2 and on every thread;
#   2. scripts/bench_sim.py --device gpu --only 10k --scale 10, twice;
#   3. zoomify of the 255 M-pixel synthetic map (make_big_cool_par.py 25000 40 300) to 4 levels,
#      contactmap against `cooler zoomify -p 16`, with the coarsest level's pixels compared.
# Everything it needs travels in ignored folders (names in .git/info/exclude):
#   .pyb/contactmap                 stripped release binary
#   .pyb/polychrom_src/polychrom/   contactmaps, hdf5_format, polymerutils, polymer_analyses
#   .pyb/make_big_cool_par.py       from ../shared/tools
#   .whl/                           cooler 0.11 and the wheels it needs beyond the device image
#   .gl/                            the Vulkan / GL loaders (tool library's device notes)
# usage (device tool, carry [".pyb", ".whl", ".gl"]): bash scripts/device_figures.sh
# Output goes to $OUT/figures.txt as it comes, so a run cut short still returns what it measured.
set -u
OUT=${OUT:-/tmp/device_out}
mkdir -p "$OUT"
LOG=$OUT/figures.txt
BIN=$PWD/.pyb/contactmap
say() { echo "$@" | tee -a "$LOG"; }
# wall time and peak RSS of one command, on one line
timed() {
    python3 - "$@" <<'EOF' | tee -a "$LOG"
import resource, subprocess, sys, time
t = time.perf_counter()
r = subprocess.run(sys.argv[1:], capture_output=True, text=True)
dt = time.perf_counter() - t
peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
print(f"{dt:.2f} s, {peak:.0f} MB peak, rc {r.returncode}: {' '.join(sys.argv[1:])}")
if r.returncode:
    print(r.stderr[-2000:])
EOF
}

say "== machine: $(nproc) cores; $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null)"
say "== binary: $($BIN --version)"
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade \
    --target /tmp/site .whl/*.whl >/dev/null 2>&1 || say "wheels did not install"
export PYTHONPATH=/tmp/site
export PYTHONUNBUFFERED=1

say "== 1. polymer-map against polychrom binnedContactMap(n=2)"
PYTHONPATH=/tmp/site:.pyb/polychrom_src python3 scripts/bench_polymer_map.py "$BIN" /tmp/pmb \
    1000 10000 1.7 10 2 3 2>&1 | tee -a "$LOG"
for t in 2 16 16 16; do
    RAYON_NUM_THREADS=$t timed "$BIN" polymer-map /tmp/pmb --contact-radius 1.7 \
        --monomers-per-bin 10 -o /tmp/pm_${t}_$RANDOM.cool
    say "   (RAYON_NUM_THREADS=$t)"
done

say "== 2. simulate polymer on the GPU, 10k beads, scale 10 (twice)"
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
for r in 1 2; do
    timeout 100 python3 scripts/bench_sim.py "$BIN" --device gpu --only 10k --scale 10 2>&1 | tee -a "$LOG"
done

say "== 3. zoomify of the 255 M-pixel map"
t0=$(date +%s)
timeout 240 python3 .pyb/make_big_cool_par.py /tmp/big255.cool 25000 40 300 16 2>&1 | tee -a "$LOG"
say "   generated in $(( $(date +%s) - t0 )) s"
R=10000,20000,50000,100000
timed "$BIN" zoomify /tmp/big255.cool -r $R -o /tmp/z.mcool
timed "$BIN" zoomify /tmp/big255.cool -r $R -o /tmp/z2.mcool
timed timeout 200 python3 -m cooler zoomify -p 16 -r $R /tmp/big255.cool -o /tmp/cz.mcool
python3 - <<'EOF' 2>&1 | tee -a "$LOG"
import h5py, numpy as np
with h5py.File("/tmp/z.mcool") as a, h5py.File("/tmp/cz.mcool") as b:
    for r in ("100000", "50000"):
        pa, pb = a[f"resolutions/{r}/pixels"], b[f"resolutions/{r}/pixels"]
        same = all(np.array_equal(pa[k][:], pb[k][:]) for k in ("bin1_id", "bin2_id", "count"))
        print(f"   level {r}: {pa['count'].shape[0]} pixels (cooler {pb['count'].shape[0]}), identical: {same}")
EOF
ls -la /tmp/z.mcool /tmp/cz.mcool 2>&1 | tee -a "$LOG"
say "== done"
