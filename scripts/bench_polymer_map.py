#!/usr/bin/env python3
"""polymer-map against polychrom's binnedContactMap (issue 32), same files, same run.

Writes a polychrom trajectory (K conformations of N beads: random walks with Gaussian steps of
unit mean square, seed 0; blocks of 50 per blocks_X-Y.h5 file, pos float64, gzip 4) unless the
folder exists, then times, alternately, REPEATS times:
  polychrom: hdf5_format.list_URIs + contactmaps.binnedContactMap(uris, binSize=B, cutoff=R,
             n=WORKERS) (its multiprocessing path), PYTHONPATH must hold a polychrom checkout
  contactmap: contactmap polymer-map FOLDER --contact-radius R --monomers-per-bin B
and checks the maps are equal (polychrom returns triangle + triangle.T: so is ours compared).

usage: python scripts/bench_polymer_map.py CONTACTMAP_BIN FOLDER [K=1000] [N=10000] [R=1.7]
       [B=10] [WORKERS=2] [REPEATS=2]
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np


def make_trajectory(folder: str, k: int, n: int) -> None:
    os.makedirs(folder)
    rng = np.random.default_rng(0)
    for first in range(0, k, 50):
        last = min(first + 50, k) - 1
        with h5py.File(os.path.join(folder, f"blocks_{first}-{last}.h5"), "w") as f:
            for b in range(first, last + 1):
                pos = np.cumsum(rng.normal(size=(n, 3)) / np.sqrt(3), axis=0)
                f.create_group(str(b)).create_dataset(
                    "pos", data=pos, compression="gzip", compression_opts=4
                )


def main() -> None:
    binary, folder = sys.argv[1], sys.argv[2]
    k, n = (int(a) for a in (sys.argv[3:5] + ["1000", "10000"][len(sys.argv[3:5]):]))
    cutoff = float(sys.argv[5]) if len(sys.argv) > 5 else 1.7
    bin_size = int(sys.argv[6]) if len(sys.argv) > 6 else 10
    workers = int(sys.argv[7]) if len(sys.argv) > 7 else 2
    repeats = int(sys.argv[8]) if len(sys.argv) > 8 else 2
    if not os.path.isdir(folder):
        t0 = time.perf_counter()
        make_trajectory(folder, k, n)
        print(f"wrote {k} x {n} beads in {time.perf_counter() - t0:.1f} s")
    from polychrom import contactmaps, hdf5_format, polymerutils

    binned = getattr(contactmaps, "binnedContactMapParallel", contactmaps.binnedContactMap)
    ours_t, theirs_t = [], []
    out = tempfile.mkdtemp()
    for r in range(repeats):
        cool = os.path.join(out, f"map{r}.cool")
        t0 = time.perf_counter()
        subprocess.run(
            [binary, "polymer-map", folder, "--contact-radius", str(cutoff),
             "--monomers-per-bin", str(bin_size), "-o", cool],
            check=True, capture_output=True,
        )
        ours_t.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        uris = hdf5_format.list_URIs(folder)
        theirs, _ = binned(uris, binSize=bin_size, cutoff=cutoff, n=workers,
                           loadFunction=polymerutils.load)
        theirs_t.append(time.perf_counter() - t0)
    # the .cool's pixels read with h5py (no cooler needed where the peers cannot be installed)
    with h5py.File(cool, "r") as f:
        n_bins = f["bins/start"].shape[0]
        ours = np.zeros((n_bins, n_bins), dtype=np.int64)
        ours[f["pixels/bin1_id"][:], f["pixels/bin2_id"][:]] = f["pixels/count"][:]
    ours = ours + ours.T
    same = np.array_equal(ours, theirs.astype(np.int64))
    print(f"polymer-map: {', '.join(f'{t:.2f}' for t in ours_t)} s; polychrom binnedContactMap "
          f"(n={workers}): {', '.join(f'{t:.2f}' for t in theirs_t)} s; median ratio "
          f"{np.median(theirs_t) / np.median(ours_t):.1f}x; maps equal: {same}")


if __name__ == "__main__":
    main()
