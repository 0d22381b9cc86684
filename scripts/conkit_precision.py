#!/usr/bin/env python3
"""ConKit 0.13.3 long-range precision at L/10, L/5, L/2, L, as its documented Python example."""
import sys, time, warnings
warnings.filterwarnings("ignore")
import conkit.io
start = time.time()
pdb_path, pred_path, fasta_path, fmt = sys.argv[1:5]
seq = conkit.io.read(fasta_path, "fasta").top
pred = conkit.io.read(pred_path, fmt).top
pred.sequence = seq
pred.set_sequence_register()
pdb = conkit.io.read(pdb_path, "pdb").top
if hasattr(pdb, "as_contactmap"):
    pdb = pdb.as_contactmap()
pred.remove_neighbors(min_distance=24, inplace=True)
pred.sort("raw_score", reverse=True, inplace=True)
pred.match(pdb, inplace=True)
for f in (0.1, 0.2, 0.5, 1.0):
    print(f, round(pred[: int(seq.seq_len * f)].precision, 6))
print("seconds", round(time.time() - start, 2), file=sys.stderr)
