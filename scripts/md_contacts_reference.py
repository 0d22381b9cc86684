#!/usr/bin/env python3
"""Fixtures and MDTraj references for `contactmap contacts --trajectory` (issue 32).

Usage: md_contacts_reference.py MDANALYSISTESTS_DATA_DIR [--out data]

From the MDAnalysisTests package's data (pip download MDAnalysisTests==2.7.0; its sdist holds
the files), it writes small fixtures into data/md/:

- adk.pdb.gz: adk_open.pdb (adenylate kinase, CHARMM names: HSD, HN, HT1 ...), its ATOM
  records cut to column 54 (the columns every reader uses) with the element symbol (the atom
  name's first letter: C, N, O, S, H) written in columns 77-78. The original has no element
  columns, and MDTraj then reads the element from the name's first two columns, so that the
  CHARMM hydrogens HG* and HE* become mercury and helium (heavy atoms for closest-heavy and
  sidechain-heavy); with the elements written, both tools read the same atoms;
- adk.xtc: frames 0, 49 and 97 of adk_dims.dcd (the DIMS open -> closed transition), written by
  MDTraj as XTC (no box: the run is non-periodic);
- cobrotoxin.pdb.gz / cobrotoxin.dcd: the protein atoms of cobrotoxin.pdb / cobrotoxin.xtc
  (3 frames, a 5.28 nm cubic box), written by MDTraj as DCD with its unit cell (periodic).

and for each fixture and contact scheme the residue pairs in contact in at least one frame,
with their number of frames, as MDTraj 1.11 computes them (data/reference/mdtraj/*.tsv.gz):
`compute_contacts(traj, "all", scheme)` for ca / closest / closest-heavy / sidechain /
sidechain-heavy, and `compute_distances` of the Cb atoms (Ca for glycine) of the same pairs for
cb; a frame counts when the distance (nm, float32) is below the cutoff (float32).
"""
import argparse
import gzip
import os
import sys
import warnings

import mdtraj as md
import numpy as np

CUTOFF_NM = {"ca": 0.8, "cb": 0.8, "closest": 0.45, "closest-heavy": 0.45,
             "sidechain": 0.45, "sidechain-heavy": 0.45}


def trimmed_pdb(source, target, keep, elements=False):
    lines = []
    with open(source) as handle:
        for line in handle:
            if line.startswith("CRYST1"):
                lines.append(line.rstrip("\n"))
            elif line.startswith(("ATOM  ", "HETATM")) and keep(line):
                element = line[12:16].strip()[0] if elements else ""
                lines.append(line[:54].ljust(76) + element.rjust(2) if elements else line[:54])
            elif line.startswith("TER") and lines and lines[-1].startswith(("ATOM", "HETATM")):
                lines.append("TER")
    lines.append("END")
    with gzip.GzipFile(target, "wb", mtime=0) as out:
        out.write(("\n".join(lines) + "\n").encode())


def cb_atoms(top):
    atoms = []
    for residue in top.residues:
        name = "CA" if residue.name == "GLY" else "CB"
        found = [a.index for a in residue.atoms if a.name == name]
        atoms.append(found[0] if found else -1)
    return atoms


def contacts(traj, scheme):
    if scheme == "cb":
        _, pairs = md.compute_contacts(traj[:1], "all", scheme="ca")
        cb = cb_atoms(traj.topology)
        pairs = np.array([p for p in pairs if cb[p[0]] >= 0 and cb[p[1]] >= 0])
        distances = md.compute_distances(traj, [[cb[i], cb[j]] for i, j in pairs])
    else:
        distances, pairs = md.compute_contacts(traj, "all", scheme=scheme)
    counts = (distances < np.float32(CUTOFF_NM[scheme])).sum(axis=0)
    return pairs, counts


def write_reference(traj, name, out):
    for scheme in CUTOFF_NM:
        pairs, counts = contacts(traj, scheme)
        path = os.path.join(out, "reference", "mdtraj", f"{name}.{scheme}.tsv.gz")
        with gzip.GzipFile(path, "wb", mtime=0) as handle:
            handle.write(f"# pairs\t{len(pairs)}\tframes\t{traj.n_frames}\n".encode())
            handle.write(b"index1\tindex2\tcontact_frames\n")
            for (i, j), n in zip(pairs, counts):
                if n:
                    handle.write(f"{i}\t{j}\t{n}\n".encode())
        print(f"{name} {scheme}: {len(pairs)} pairs, {int((counts > 0).sum())} in contact")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("mdatests")
    parser.add_argument("--out", default="data")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    src = args.mdatests
    md_dir = os.path.join(args.out, "md")
    os.makedirs(md_dir, exist_ok=True)
    os.makedirs(os.path.join(args.out, "reference", "mdtraj"), exist_ok=True)

    # adk: CHARMM topology, a non-periodic DCD
    trimmed_pdb(os.path.join(src, "adk_open.pdb"), os.path.join(md_dir, "adk.pdb.gz"),
                lambda line: True, elements=True)
    adk = md.load(os.path.join(src, "adk_dims.dcd"), top=os.path.join(src, "adk_open.pdb"))
    adk[[0, 49, 97]].save_xtc(os.path.join(md_dir, "adk.xtc"))
    fixture = md.load(os.path.join(md_dir, "adk.xtc"), top=os.path.join(md_dir, "adk.pdb.gz"))
    write_reference(fixture, "adk", args.out)

    # cobrotoxin: the protein of a solvated periodic run
    full = md.load(os.path.join(src, "cobrotoxin.xtc"), top=os.path.join(src, "cobrotoxin.pdb"))
    protein = full.topology.select("protein")
    names = {full.topology.atom(i).residue.name for i in protein}
    trimmed_pdb(os.path.join(src, "cobrotoxin.pdb"), os.path.join(md_dir, "cobrotoxin.pdb.gz"),
                lambda line: line[17:20].strip() in names)
    full.atom_slice(protein).save_dcd(os.path.join(md_dir, "cobrotoxin.dcd"))
    fixture = md.load(os.path.join(md_dir, "cobrotoxin.dcd"),
                      top=os.path.join(md_dir, "cobrotoxin.pdb.gz"))
    assert fixture.n_atoms == len(protein), (fixture.n_atoms, len(protein))
    write_reference(fixture, "cobrotoxin", args.out)


if __name__ == "__main__":
    sys.exit(main())
