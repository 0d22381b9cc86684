#!/usr/bin/env python3
"""`contactmap contacts --trajectory` against MDTraj's compute_contacts: equality on the full
MDAnalysisTests trajectories, and speed on a 1,000-frame protein trajectory.

Usage: bench_md_contacts.py BIN MDANALYSISTESTS_DATA_DIR [--frames 1000] [--schemes ca,closest-heavy]
                            [--repeat 5] [--skip-equality]

1. Equality: adk_dims.dcd (98 frames, 3,341 atoms, topology adk_open.pdb, non-periodic) and
   adk_oplsaa.xtc (10 frames, 47,681 atoms with water, triclinic box, topology adk_oplsaa.pdb),
   every scheme: MDTraj's frames in contact per pair against ours.
2. Speed: adk_dims.dcd's frames repeated to --frames frames (a DCD written by MDTraj in a
   temporary folder); MDTraj: md.load + compute_contacts + the threshold, timed in one process;
   ours: the binary, wall time. Same machine, same run.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time
import warnings

import mdtraj as md
import numpy as np

CUTOFF_NM = {"ca": 0.8, "cb": 0.8, "closest": 0.45, "closest-heavy": 0.45,
             "sidechain": 0.45, "sidechain-heavy": 0.45}
MDTRAJ_SCHEMES = ["ca", "closest", "closest-heavy", "sidechain", "sidechain-heavy"]


def mdtraj_counts(traj, scheme):
    distances, pairs = md.compute_contacts(traj, "all", scheme=scheme)
    return pairs, (distances < np.float32(CUTOFF_NM[scheme])).sum(axis=0)


def ours(binary, trajectory, topology, scheme, out):
    cutoff = CUTOFF_NM[scheme] * 10
    start = time.perf_counter()
    subprocess.run([binary, "contacts", "--trajectory", trajectory, "--topology", topology,
                    "--definition", scheme, "--cutoff", f"{cutoff:g}", "-o", out],
                   check=True, stderr=subprocess.DEVNULL)
    seconds = time.perf_counter() - start
    counts = {}
    with open(out) as handle:
        next(handle)
        for line in handle:
            f = line.split("\t")
            counts[(int(f[5]), int(f[6]))] = int(f[7])
    return counts, seconds


def compare(binary, trajectory, topology, tmp):
    traj = md.load(trajectory, top=topology)
    for scheme in MDTRAJ_SCHEMES:
        pairs, counts = mdtraj_counts(traj, scheme)
        mine, _ = ours(binary, trajectory, topology, scheme, os.path.join(tmp, "eq.tsv"))
        diff = sum(1 for (i, j), n in zip(pairs, counts) if mine.get((i, j)) != n)
        print(f"{os.path.basename(trajectory)} ({traj.n_frames} frames, {traj.n_atoms} atoms) "
              f"{scheme}: {len(pairs)} pairs (ours {len(mine)}), "
              f"{int((counts > 0).sum())} in contact, pairs differing: {diff}", flush=True)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("binary")
    parser.add_argument("mdatests")
    parser.add_argument("--frames", type=int, default=1000)
    parser.add_argument("--schemes", default="ca,closest-heavy")
    parser.add_argument("--skip-equality", action="store_true")
    parser.add_argument("--repeat", type=int, default=5,
                        help="timed runs of each tool per scheme (medians reported)")
    parser.add_argument("--topology", default="data/md/adk.pdb.gz",
                        help="the speed run's topology: adk_open.pdb's atoms with element "
                             "columns (MDTraj reads HG* / HE* of the original as Hg / He)")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    src = args.mdatests
    with tempfile.TemporaryDirectory() as tmp:
        if not args.skip_equality:
            compare(args.binary, os.path.join(src, "adk_dims.dcd"),
                    os.path.join(src, "adk_open.pdb"), tmp)
            compare(args.binary, os.path.join(src, "adk_oplsaa.xtc"),
                    os.path.join(src, "adk_oplsaa.pdb"), tmp)
        adk = md.load(os.path.join(src, "adk_dims.dcd"), top=os.path.join(src, "adk_open.pdb"))
        repeat = adk[[k % adk.n_frames for k in range(args.frames)]]
        big = os.path.join(tmp, "adk_1000.dcd")
        repeat.save_dcd(big)
        topology = args.topology
        print(f"speed: {args.frames} frames of {adk.n_atoms} atoms ({adk.n_residues} residues), "
              f"{os.cpu_count()} CPUs", flush=True)
        # a first read of the new file by each (page cache, lazy imports), not timed
        md.load(big, top=topology)
        ours(args.binary, big, topology, "ca", os.path.join(tmp, "s.tsv"))
        for scheme in args.schemes.split(","):
            peer_times, our_times = [], []
            for _ in range(args.repeat):
                start = time.perf_counter()
                traj = md.load(big, top=topology)
                pairs, counts = mdtraj_counts(traj, scheme)
                peer_times.append(time.perf_counter() - start)
                del traj
                mine, seconds = ours(args.binary, big, topology, scheme,
                                     os.path.join(tmp, "s.tsv"))
                our_times.append(seconds)
            same = all(mine.get((i, j)) == n for (i, j), n in zip(pairs, counts))
            peer, seconds = np.median(peer_times), np.median(our_times)
            print(f"{scheme}: mdtraj {peer:.3f} s, contactmap {seconds:.3f} s (medians of "
                  f"{args.repeat}, alternated), {peer / seconds:.1f}x, frame counts equal: "
                  f"{same}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
