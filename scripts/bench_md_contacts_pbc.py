#!/usr/bin/env python3
"""`contactmap contacts --trajectory` against MDTraj's compute_contacts with and without a
periodic cell: every scheme x (no box, rectangular box, triclinic cell), equality and speed.

Usage: bench_md_contacts_pbc.py BIN [BIN ...] [--frames 1000] [--repeat 3] [--schemes ca,cb,...]
                                [--boxes none,rectangular,triclinic] [--edge 8.5] [--keep DIR]
                                [--mdtraj-once]

Several binaries (e.g. before and after a change) are timed on the same runs, one column each.

The trajectory: data/md/adk.xtc's three frames (adenylate kinase, 3,341 atoms, 214 residues,
topology data/md/adk.pdb.gz) repeated to --frames frames, each moved by a seeded random
translation of up to one cell edge (so that atoms lie outside the cell and across its faces)
and seeded Gaussian noise of 0.02 nm per coordinate, written by MDTraj as DCD:

- none: no unit cell;
- rectangular: a cubic box of edge --edge nm (angles 90, 90, 90);
- triclinic: the rhombic dodecahedron of the same edge (GROMACS' xy-square one: angles 60, 60,
  90), the cell a solvated protein is usually run in.

Timing: MDTraj: md.load + compute_contacts (cb: compute_distances of the Cb atoms, Ca for
glycine, of the ca scheme's pairs) + the threshold, in one process; the multi-atom schemes by
md.iterload chunks of 100 frames, counts summed (closest's 5.4 M atom pairs would take 21 GB of
distances for 1,000 frames at once). Ours: the binary's wall time (all CPUs). Medians of
--repeat runs, alternated (--mdtraj-once: MDTraj timed on its first run only, for the slow
triclinic runs). Equality: MDTraj's frames in contact per pair against ours, every pair.
"""
import argparse
import os
import sys
import tempfile
import time
import warnings

import mdtraj as md
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_md_contacts import CUTOFF_NM, ours  # noqa: E402  (the same cutoffs and run)
from md_contacts_reference import cb_atoms  # noqa: E402  (the references' Cb choice)

CHUNK = 100


def mdtraj_counts(path, topology, scheme):
    if scheme == "cb":
        traj = md.load(path, top=topology)
        _, pairs = md.compute_contacts(traj[:1], "all", scheme="ca")
        cb = cb_atoms(traj.topology)
        pairs = np.array([p for p in pairs if cb[p[0]] >= 0 and cb[p[1]] >= 0])
        distances = md.compute_distances(traj, [[cb[i], cb[j]] for i, j in pairs])
        return pairs, (distances < np.float32(CUTOFF_NM[scheme])).sum(axis=0)
    if scheme == "ca":
        traj = md.load(path, top=topology)
        distances, pairs = md.compute_contacts(traj, "all", scheme=scheme)
        return pairs, (distances < np.float32(CUTOFF_NM[scheme])).sum(axis=0)
    # the multi-atom schemes by chunks of frames: closest's distances of all 5.4 M atom pairs
    # would take 21 GB for 1,000 frames
    counts = None
    for chunk in md.iterload(path, top=topology, chunk=CHUNK):
        distances, pairs = md.compute_contacts(chunk, "all", scheme=scheme)
        found = (distances < np.float32(CUTOFF_NM[scheme])).sum(axis=0)
        counts = found if counts is None else counts + found
    return pairs, counts


def fixture(topology, frames, box, edge, path):
    base = md.load("data/md/adk.xtc", top=topology)
    rng = np.random.default_rng(51)
    xyz = base.xyz[[k % base.n_frames for k in range(frames)]].astype(np.float64)
    xyz += rng.uniform(-edge, edge, size=(frames, 1, 3))
    xyz += rng.normal(0.0, 0.02, size=xyz.shape)
    traj = md.Trajectory(xyz.astype(np.float32), base.topology)
    if box != "none":
        angles = [90.0, 90.0, 90.0] if box == "rectangular" else [60.0, 60.0, 90.0]
        traj.unitcell_lengths = np.full((frames, 3), edge, dtype=np.float32)
        traj.unitcell_angles = np.tile(np.array(angles, dtype=np.float32), (frames, 1))
    traj.save_dcd(path)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("binaries", nargs="+")
    parser.add_argument("--frames", type=int, default=1000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--schemes", default=",".join(CUTOFF_NM))
    parser.add_argument("--boxes", default="none,rectangular,triclinic")
    parser.add_argument("--edge", type=float, default=8.5, help="cell edge, nm")
    parser.add_argument("--topology", default="data/md/adk.pdb.gz")
    parser.add_argument("--keep", help="write the trajectories here (kept) instead of a temporary")
    parser.add_argument("--mdtraj-once", action="store_true",
                        help="time MDTraj once instead of --repeat times")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    with tempfile.TemporaryDirectory() as tmp:
        folder = args.keep or tmp
        os.makedirs(folder, exist_ok=True)
        print(f"{args.frames} frames of adk (3,341 atoms, 214 residues), edge {args.edge} nm, "
              f"{os.cpu_count()} CPUs", flush=True)
        names = [os.path.basename(b) for b in args.binaries]
        print("| scheme | cell | MDTraj (s) | " + " | ".join(f"{n} (s) | ratio" for n in names)
              + " | equal |")
        print("|---|---|---:|" + "---:|---:|" * len(names) + "---|")
        for box in args.boxes.split(","):
            path = os.path.join(folder, f"adk_{box}_{args.frames}.dcd")
            if not os.path.exists(path):
                fixture(args.topology, args.frames, box, args.edge, path)
            # a first read by each (page cache, lazy imports), not timed
            md.load(path, top=args.topology)
            for binary in args.binaries:
                ours(binary, path, args.topology, "ca", os.path.join(tmp, "s.tsv"))
            for scheme in args.schemes.split(","):
                peer_times, our_times = [], [[] for _ in args.binaries]
                tables = [None] * len(args.binaries)
                for k in range(args.repeat):
                    if k == 0 or not args.mdtraj_once:
                        start = time.perf_counter()
                        pairs, counts = mdtraj_counts(path, args.topology, scheme)
                        peer_times.append(time.perf_counter() - start)
                    for b, binary in enumerate(args.binaries):
                        tables[b], seconds = ours(binary, path, args.topology, scheme,
                                                  os.path.join(tmp, "s.tsv"))
                        our_times[b].append(seconds)
                same = all(len(mine) == len(pairs) and all(
                    mine.get((i, j)) == n for (i, j), n in zip(pairs, counts)) for mine in tables)
                peer = np.median(peer_times)
                cells = " | ".join(f"{np.median(t):.3f} | {peer / np.median(t):.1f}x"
                                   for t in our_times)
                print(f"| {scheme} | {box} | {peer:.3f} | {cells} | {same} |", flush=True)

if __name__ == "__main__":
    sys.exit(main())
