#!/usr/bin/env python3
"""Write a synthetic protein and a CCMpred-style prediction for side-by-side timings.

usage: make_protein_bench.py OUTDIR [N_RESIDUES] [SEED]

OUTDIR/bench.pdb    N residues of chain A (Ca on a compact random walk with 3.8 A steps kept in a
                    sphere, Cb 1.53 A from Ca in a random direction; Gly every 10th residue)
OUTDIR/bench.fasta  its sequence
OUTDIR/bench.mat    N x N symmetric score matrix (CCMpred layout): noise plus a bonus on pairs
                    whose Cb are closer than 8 A, so precisions are neither 0 nor 1.
Only the Python standard library is used.
"""
import math
import os
import random
import sys

out = sys.argv[1]
n = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
random.seed(int(sys.argv[3]) if len(sys.argv) > 3 else 1)
os.makedirs(out, exist_ok=True)
radius = 2.2 * n ** 0.38 * 1.3


def unit():
    while True:
        v = [random.gauss(0, 1) for _ in range(3)]
        norm = math.sqrt(sum(x * x for x in v))
        if norm > 1e-9:
            return [x / norm for x in v]


ca = [[0.0, 0.0, 0.0]]
while len(ca) < n:
    step = unit()
    candidate = [ca[-1][k] + 3.8 * step[k] for k in range(3)]
    if math.sqrt(sum(x * x for x in candidate)) <= radius:
        ca.append(candidate)
cb = []
for point in ca:
    direction = unit()
    cb.append([point[k] + 1.53 * direction[k] for k in range(3)])
letters = "ACDEFHIKLMNPQRSTVWY"
three = dict(A="ALA", C="CYS", D="ASP", E="GLU", F="PHE", G="GLY", H="HIS", I="ILE", K="LYS",
             L="LEU", M="MET", N="ASN", P="PRO", Q="GLN", R="ARG", S="SER", T="THR", V="VAL",
             W="TRP", Y="TYR")
sequence = "".join("G" if i % 10 == 0 else random.choice(letters) for i in range(n))
with open(os.path.join(out, "bench.fasta"), "w") as f:
    f.write(">bench synthetic %d residues\n%s\n" % (n, sequence))
serial = 1
with open(os.path.join(out, "bench.pdb"), "w") as f:
    for i, letter in enumerate(sequence):
        atoms = [("CA", ca[i])] + ([] if letter == "G" else [("CB", cb[i])])
        for name, xyz in atoms:
            f.write("ATOM  %5d  %-3s %3s A%4d    %8.3f%8.3f%8.3f  1.00  0.00           C\n"
                    % (serial, name, three[letter], i + 1, xyz[0], xyz[1], xyz[2]))
            serial += 1
    f.write("END\n")
representative = [ca[i] if sequence[i] == "G" else cb[i] for i in range(n)]
matrix = [[0.0] * n for _ in range(n)]
for i in range(n):
    for j in range(i + 1, n):
        d = math.dist(representative[i], representative[j])
        score = random.gauss(0.0, 1.0) + (2.0 if d < 8.0 else 0.0)
        matrix[i][j] = matrix[j][i] = score
with open(os.path.join(out, "bench.mat"), "w") as f:
    for row in matrix:
        f.write(" ".join("%.6f" % x for x in row) + "\n")
