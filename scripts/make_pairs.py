#!/usr/bin/env python3
"""A synthetic 4DN .pairs file for ingestion benchmarks (docs/performance.md).

    python scripts/make_pairs.py OUT.pairs N_PAIRS [SEED]

Chromosomes chr1..chr4 of 250 Mb (the layout of ../shared/tools/make_big_cool.py at 10 kb);
pair separations follow P(s) ~ s^-1 from 1 kb to the chromosome length, 10% of the pairs are
trans; the file has the 4DN header (#chromsize, #columns) and columns readID chrom1 pos1 chrom2
pos2 strand1 strand2, unsorted. Needs numpy.
"""
import sys

import numpy as np

LENGTH = 250_000_000
CHROMS = [f"chr{k}" for k in range(1, 5)]


def main(argv):
    if len(argv) < 2:
        sys.exit(__doc__)
    out, n = argv[0], int(argv[1])
    rng = np.random.default_rng(int(argv[2]) if len(argv) > 2 else 1)
    with open(out, "w") as f:
        f.write("## pairs format v1.0\n")
        for c in CHROMS:
            f.write(f"#chromsize: {c} {LENGTH}\n")
        f.write("#columns: readID chr1 pos1 chr2 pos2 strand1 strand2\n")
        block = 1_000_000
        for start in range(0, n, block):
            m = min(block, n - start)
            c1 = rng.integers(0, 4, m)
            pos1 = rng.integers(1, LENGTH + 1, m)
            # log-uniform separation: P(s) ~ 1/s
            s = np.exp(rng.uniform(np.log(1e3), np.log(LENGTH), m)).astype(np.int64)
            pos2 = pos1 + s * rng.choice([-1, 1], m)
            trans = rng.random(m) < 0.1
            c2 = np.where(trans, (c1 + rng.integers(1, 4, m)) % 4, c1)
            pos2 = np.where(trans, rng.integers(1, LENGTH + 1, m), pos2)
            ok = (pos2 >= 1) & (pos2 <= LENGTH)
            lines = [
                f".\t{CHROMS[a]}\t{p}\t{CHROMS[b]}\t{q}\t+\t-\n"
                for a, p, b, q in zip(c1[ok], pos1[ok], c2[ok], pos2[ok])
            ]
            f.writelines(lines)


if __name__ == "__main__":
    main(sys.argv[1:])
