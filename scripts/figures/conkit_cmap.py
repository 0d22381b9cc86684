#!/usr/bin/env python3
"""ConKit's contact-map figure for the input of `contactmap plot contacts`, to compare by eye.

Does what `conkit-plot cmap -p STRUCTURE -d MIN_SEP -f FACTOR FASTA fasta PRED FORMAT` does,
through the library (conkit.io.read, conkit.plot.ContactMapFigure): the prediction is put on
the sequence's register, pairs closer than MIN_SEP dropped, sorted by raw score, the top
int(L * FACTOR) kept, then matched against the contacts of the structure (ConKit's reader: Cb,
d < 8 A) with unmatched pairs removed; the figure shows the structure's contacts in grey, true
positives navy, false positives red. A second prediction (--other) goes in the other triangle
as ConKit's --otherfile; without one, ConKit draws the prediction in both triangles.

The match keeps the structure's residue numbers, as ConKit's documented Python example does
(docs/examples/rst/python_analyse_conpred.rst); --renumber matches as `conkit-plot cmap` does
(the reference given the target sequence, `match(renumber=True)`), which shifts toxd by one
residue: its residue 1 (PCA) is not read from the PDB, and the match then counts 16 true
positives in the top L instead of 34.

Usage (with the venv that has conkit and matplotlib):
  python scripts/figures/conkit_cmap.py --structure data/protein/toxd/toxd.pdb.gz \
      --fasta data/protein/toxd/toxd.fasta data/protein/toxd/toxd.mat.gz -o /tmp/toxd.conkit.png
Inputs may be gzip-compressed (`.gz`, as the fixtures of data/protein/ are): ConKit reads plain
text, so they are decompressed into a temporary folder first.
Prints the counts of true and false positives in the drawn list on standard output.
"""

import argparse
import gzip
import os
import shutil
import tempfile

import matplotlib

matplotlib.use("Agg")

import conkit.io  # noqa: E402
import conkit.plot  # noqa: E402
import conkit.plot.tools  # noqa: E402

FORMATS = {".mat": "ccmpred", ".rr": "casprr", ".npz": "rosettanpz", ".psicov": "psicov"}


def plain(path, folder):
    """`path`, or for a `.gz` file its decompressed copy in `folder` (ConKit reads plain text)."""
    if not path.endswith(".gz"):
        return path
    out = os.path.join(folder, os.path.basename(path)[: -len(".gz")])
    with gzip.open(path, "rb") as src, open(out, "wb") as dst:
        shutil.copyfileobj(src, dst)
    return out


def prediction_format(path, given):
    if given:
        return given
    name = path[: -len(".gz")] if path.endswith(".gz") else path
    ext = os.path.splitext(name)[1].lower()
    if ext not in FORMATS:
        raise SystemExit(f"cannot guess the ConKit format of {path}: give --format")
    return FORMATS[ext]


def load(path, fmt, sequence, min_sep, n_contacts):
    cmap = conkit.io.read(path, fmt)[0]
    if hasattr(cmap, "as_contactmap") and fmt == "rosettanpz":
        cmap = cmap.as_contactmap()
    cmap.sequence = sequence
    cmap.set_sequence_register()
    cmap.remove_neighbors(min_distance=min_sep, inplace=True)
    cmap.sort("raw_score", reverse=True, inplace=True)
    return cmap[:n_contacts]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--structure", required=True, help="reference PDB")
    parser.add_argument("--fasta", required=True, help="target sequence")
    parser.add_argument("--format", help="ConKit format of the predictions (default: by extension)")
    parser.add_argument("--other", help="a second prediction (ConKit's --otherfile)")
    parser.add_argument("--min-sep", type=int, default=6, help="ConKit's -d (default 6, as contactmap)")
    parser.add_argument("--factor", type=float, default=1.0, help="ConKit's -f: top int(L * f)")
    parser.add_argument("--renumber", action="store_true",
                        help="match with renumber=True, as conkit-plot cmap")
    parser.add_argument("--dpi", type=int, default=100)
    parser.add_argument("-o", "--out", required=True, help="PNG to write")
    parser.add_argument("prediction")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        run(args, folder)


def run(args, folder):
    args.structure = plain(args.structure, folder)
    args.fasta = plain(args.fasta, folder)
    args.prediction = plain(args.prediction, folder)
    if args.other:
        args.other = plain(args.other, folder)

    sequence = conkit.io.read(args.fasta, "fasta")[0]
    n_contacts = int(sequence.seq_len * args.factor)
    con = load(args.prediction, prediction_format(args.prediction, args.format), sequence,
               args.min_sep, n_contacts)
    other = None
    if args.other:
        other = load(args.other, prediction_format(args.other, args.format), sequence,
                     args.min_sep, n_contacts)

    reference = conkit.io.read(args.structure, "pdb")[0].as_contactmap()
    if args.renumber:
        # conkit-plot cmap's steps; giving the reference the target sequence alone already
        # makes match() shift toxd by one residue.
        reference.sequence = sequence
        reference.set_sequence_register()
    con = con.match(reference, match_other=True, renumber=args.renumber, remove_unmatched=True)
    if other is not None:
        other = other.match(reference, renumber=args.renumber, remove_unmatched=True)

    for name, cmap in (("prediction", con), ("other", other)):
        if cmap is None:
            continue
        tp = sum(1 for c in cmap if c.true_positive)
        fp = sum(1 for c in cmap if c.false_positive)
        print(f"{name}: listed {n_contacts}, drawn {len(cmap)}, TP {tp}, FP {fp}, "
              f"precision {tp / max(len(cmap), 1):.3f}")

    figure = conkit.plot.ContactMapFigure(con, other=other, reference=reference, legend=True)
    # conkit-plot cmap makes the axes square.
    figure.ax.set_aspect(conkit.plot.tools.get_adjusted_aspect(figure.ax, 1.0))
    if os.path.exists(args.out):
        os.remove(args.out)  # ConKit's savefig refuses to overwrite
    figure.savefig(args.out, dpi=args.dpi)


if __name__ == "__main__":
    main()
