#!/usr/bin/env python3
"""The polychrom fixtures and references of issue 32 (data/polychrom, data/reference/polychrom).

Fixtures, written with h5py to polychrom's layout (polychrom/hdf5_format.py: files
blocks_X-Y.h5, groups /K with the dataset pos and attributes): a trajectory of 7 conformations
of 150 beads (random walks, seed 0), blocks 0-3 in one file (pos float32, as a simulation
saves it) and 4-6 in another (float64), gzip as polychrom's DEFAULT_OPTS.

References, made by polychrom's own functions on those files (import polychrom from a checkout
given on PYTHONPATH): hdf5_format.list_URIs, then contactmaps.monomerResolutionContactMap
(cutoff 1.6) and binnedContactMap (chains [[0, 90], [90, 150]], binSize 4, cutoff 1.6), both
with n=1 (polychrom's one-core path, averageContactsSimple, which counts as its workers do);
the dense matrices polychrom returns (triangle + triangle.T) as TSV. And polymer_analyses on
each conformation (generate_bins(150); contact_scaling with cutoff 1.6, R2_scaling,
Rg2_scaling, Rg2), the per-conformation values averaged with numpy's mean over conformations:
stats.scaling.tsv (s_mid contact_probability), stats.r2.tsv (s r2 rg2), stats.rg2.tsv (rg2 per
conformation), floats in full (repr).

usage: PYTHONPATH=/path/to/polychrom python scripts/polychrom_reference.py
"""

from __future__ import annotations

import gzip
import os

import h5py
import numpy as np

from polychrom import contactmaps, hdf5_format, polymer_analyses, polymerutils

TRAJ = "data/polychrom/traj"
REF = "data/reference/polychrom"


def write_fixtures() -> None:
    os.makedirs(TRAJ, exist_ok=True)
    rng = np.random.default_rng(0)
    confs = []
    for _ in range(7):
        steps = rng.normal(size=(150, 3)) / np.sqrt(3)
        confs.append(np.cumsum(steps, axis=0) * 0.8)
    for (first, last), dtype in (((0, 3), np.float32), ((4, 6), np.float64)):
        with h5py.File(os.path.join(TRAJ, f"blocks_{first}-{last}.h5"), "w") as f:
            for k in range(first, last + 1):
                group = f.create_group(str(k))
                group.create_dataset(
                    "pos", data=confs[k].astype(dtype), compression="gzip", compression_opts=9
                )
                group.attrs["block"] = k
                group.attrs["time"] = 0.5 * k


def write_matrix(name: str, matrix: np.ndarray) -> None:
    os.makedirs(REF, exist_ok=True)
    with gzip.open(os.path.join(REF, name), "wt") as f:
        for row in matrix:
            f.write("\t".join(str(int(v)) for v in row) + "\n")


def main() -> None:
    write_fixtures()
    uris = hdf5_format.list_URIs(TRAJ)
    assert len(uris) == 7, uris
    mono = contactmaps.monomerResolutionContactMap(
        uris, cutoff=1.6, n=1, loadFunction=polymerutils.load
    )
    write_matrix("monomer_cutoff1.6.tsv.gz", mono)
    binned, starts = contactmaps.binnedContactMap(
        uris, chains=[[0, 90], [90, 150]], binSize=4, cutoff=1.6, n=1,
        loadFunction=polymerutils.load,
    )
    write_matrix("binned_4_chains90-60_cutoff1.6.tsv.gz", binned)
    confs = [polymerutils.load(u) for u in uris]
    bins = polymer_analyses.generate_bins(150)
    scalings = [polymer_analyses.contact_scaling(c, bins, cutoff=1.6) for c in confs]
    mids = scalings[0][0]
    probability = np.mean([p for _, p in scalings], axis=0)
    r2 = np.mean([polymer_analyses.R2_scaling(c, bins)[1] for c in confs], axis=0)
    rg2s = np.mean([polymer_analyses.Rg2_scaling(c, bins)[1] for c in confs], axis=0)
    with open(os.path.join(REF, "stats.scaling.tsv"), "w") as f:
        f.write("s_mid\tcontact_probability\n")
        for m, p in zip(mids, probability):
            f.write(f"{float(m)!r}\t{float(p)!r}\n")
    with open(os.path.join(REF, "stats.r2.tsv"), "w") as f:
        f.write("s\tr2\trg2\n")
        for s, a, b in zip(bins, r2, rg2s):
            f.write(f"{int(s)}\t{float(a)!r}\t{float(b)!r}\n")
    with open(os.path.join(REF, "stats.rg2.tsv"), "w") as f:
        f.write("rg2\n")
        for c in confs:
            f.write(f"{float(polymer_analyses.Rg2(c))!r}\n")
    print("monomer", mono.shape, int(mono.sum()), "binned", binned.shape, int(binned.sum()), starts)


if __name__ == "__main__":
    main()
