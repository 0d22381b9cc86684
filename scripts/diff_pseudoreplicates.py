"""Held-out real replicates for `contactmap diff` (issue 55): one real sample split into four
disjoint parts, two compared with the other two. Nothing differs between the parts but the draw,
so every call at q < 0.05 is a false discovery, and the number of calls shows whether the
false-discovery rate holds on real data (under a complete null, FDR control at 0.05 means at
most one comparison in twenty with any call).

Each pixel's count is split among the four parts by a multinomial draw (numpy's default_rng,
seeds 1..N): disjoint pseudo-replicates of one library (they carry the library's sampling noise,
not the variation between biological replicates). Each part is balanced with `contactmap
balance --store` (ICE, cooler's defaults), then for each split:

  diff loops --a p1 p2 --b p3 p4 (the dots called on each condition's summed parts)
  diff boundaries --a p1 p2 --b p3 p4 --window W
  diff compartments --a p1 p2 --b p3 p4 [--phasing-track TRACK]

Run with any Python that has cooler and numpy (the project's .venv-python has them):

    .venv-python/bin/python scripts/diff_pseudoreplicates.py --binary target/release/contactmap \\
        --out /tmp/pseudo --splits 10

Writes OUT/pseudoreplicates.tsv (map, split, command, features tested, calls at q < 0.05) and
prints a summary per map and command.
"""

import argparse
import os
import shutil
import subprocess
import sys

import cooler
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# (name, uri, insulation window, phasing track or None, the commands run on it: dots, called
# by `diff loops` without --loops, have kernels for bins of 4-28 kb only)
MAPS = [
    ("dm6_100kb", "data/cooler_test_file.mcool::/resolutions/100000", "500k",
     "data/reference/compartments/dm6_100kb.phasing.tsv.gz:track", ("boundaries", "compartments")),
    ("yeast_10kb", "data/yeast.10kb.cool", "50k", None, ("loops", "boundaries", "compartments")),
]


def split(uri, out_dir, seed, n_parts=4):
    """Writes n_parts coolers whose counts sum to the map's, pixel by pixel."""
    clr = cooler.Cooler(uri)
    bins = clr.bins()[:][["chrom", "start", "end"]]
    pixels = clr.pixels()[:]
    rng = np.random.default_rng(seed)
    counts = pixels["count"].to_numpy().astype(np.int64)
    parts = rng.multinomial(counts, [1.0 / n_parts] * n_parts)
    paths = []
    for k in range(n_parts):
        path = os.path.join(out_dir, f"part{k + 1}.cool")
        part = pixels[["bin1_id", "bin2_id"]].copy()
        part["count"] = parts[:, k]
        part = part[part["count"] > 0]
        cooler.create_cooler(path, bins, part, ordered=True, symmetric_upper=True)
        paths.append(path)
    return paths


def run(args, log):
    log.write("$ " + " ".join(args) + "\n")
    done = subprocess.run(args, capture_output=True, text=True)
    log.write(done.stderr)
    if done.returncode != 0:
        sys.exit(f"failed ({done.returncode}): {' '.join(args)}\n{done.stderr}")
    return done.stderr


def count_calls(path, column, unchanged="-"):
    with open(path) as f:
        header = f.readline().rstrip("\n").split("\t")
        k = header.index(column)
        rows = [line.rstrip("\n").split("\t") for line in f]
    return len(rows), sum(1 for r in rows if r[k] != unchanged)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--binary", default=os.path.join(ROOT, "target/release/contactmap"))
    ap.add_argument("--out", default="/tmp/pseudoreplicates")
    ap.add_argument("--splits", type=int, default=10)
    opts = ap.parse_args()
    os.makedirs(opts.out, exist_ok=True)
    log = open(os.path.join(opts.out, "commands.log"), "w")
    rows = []
    for name, uri, window, track, commands in MAPS:
        for seed in range(1, opts.splits + 1):
            folder = os.path.join(opts.out, f"{name}_split{seed}")
            shutil.rmtree(folder, ignore_errors=True)
            os.makedirs(folder)
            parts = split(os.path.join(ROOT, uri), folder, seed)
            for part in parts:
                run([opts.binary, "balance", part, "--store"], log)
            a, b = parts[:2], parts[2:]
            prefix = os.path.join(folder, "diff")
            if "loops" in commands:
                run([opts.binary, "diff", "loops", "--a", *a, "--b", *b, "-o", prefix], log)
                rows.append((name, seed, "loops",
                             *count_calls(prefix + ".loops.bedpe", "direction")))
            run([opts.binary, "diff", "boundaries", "--a", *a, "--b", *b, "--window", window,
                 "-o", prefix], log)
            rows.append((name, seed, "boundaries",
                         *count_calls(prefix + ".boundaries.tsv", "status")))
            extra = [] if track is None else ["--phasing-track", os.path.join(ROOT, track)]
            run([opts.binary, "diff", "compartments", "--a", *a, "--b", *b, *extra,
                 "-o", prefix], log)
            rows.append((name, seed, "compartments",
                         *count_calls(prefix + ".compartments.tsv", "switch")))
            print(*rows[-len(commands):], sep="\n", flush=True)
    with open(os.path.join(opts.out, "pseudoreplicates.tsv"), "w") as f:
        f.write("map\tsplit\tcommand\tfeatures\tcalls\n")
        for row in rows:
            f.write("\t".join(map(str, row)) + "\n")
    print("\nmap\tcommand\tsplits\tsplits with a call\tcalls / features tested")
    for name, _, _, _, commands in MAPS:
        for command in commands:
            mine = [r for r in rows if r[0] == name and r[2] == command]
            with_call = sum(1 for r in mine if r[4] > 0)
            print(f"{name}\t{command}\t{len(mine)}\t{with_call}\t"
                  f"{sum(r[4] for r in mine)} / {sum(r[3] for r in mine)}")


if __name__ == "__main__":
    main()
