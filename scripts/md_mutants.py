#!/usr/bin/env python3
"""MDTraj's verdict on corrupted copies of the MD fixtures (issue 51): the reference of the
trajectory readers' differential test (`tests/cli/md_mutants.rs`).

Each mutant is the fixture with one change drawn from splitmix64 seeded by its index (the test
draws the same ones):
  kind 0  a run of 1-2,000 random bytes written at a random offset (2,000 or fewer if the file
          ends first)
  kind 1  one random byte replaced
  kind 2  the file cut at a random length
The mutant is read frame by frame with MDTraj (XTCTrajectoryFile / DCDTrajectoryFile); the
verdict is `ok` with the number of frames, or `refused` with the frames read before the failure
and MDTraj's message. The coordinates of an `ok` mutant are not compared (a flipped low bit of a
coordinate is a valid file); the test asks that every mutant MDTraj refuses is refused, at that
frame or an earlier one.

usage: python scripts/md_mutants.py OUT.tsv[.gz] data/md/adk.xtc data/md/cobrotoxin.dcd [N=400]
(needs mdtraj: pip install mdtraj; MDTraj's C readers print on standard output, hence OUT)
"""

import gzip
import io
import os
import sys
import tempfile

import mdtraj.formats as formats

MASK = (1 << 64) - 1


def splitmix64(state):
    """The next (state, value) of splitmix64."""
    state = (state + 0x9E3779B97F4A7C15) & MASK
    z = state
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
    return state, z ^ (z >> 31)


def mutant(data, index):
    """The mutant `index` of `data`: (bytes, kind, offset, length)."""
    state = index
    state, kind = splitmix64(state)
    kind %= 3
    state, offset = splitmix64(state)
    offset %= len(data)
    if kind == 0:
        state, length = splitmix64(state)
        length = min(1 + length % 2000, len(data) - offset)
        out = bytearray(data)
        for k in range(length):
            state, value = splitmix64(state)
            out[offset + k] = value & 0xFF
        return bytes(out), kind, offset, length
    if kind == 1:
        state, value = splitmix64(state)
        out = bytearray(data)
        out[offset] = value & 0xFF
        return bytes(out), kind, offset, 1
    return data[:offset], kind, offset, 0


def frames_read(path, opener):
    """(verdict, frames, message) of reading `path` one frame at a time."""
    frames = 0
    try:
        with opener(path) as f:
            while True:
                chunk = f.read(n_frames=1)
                xyz = chunk[0]
                if len(xyz) == 0:
                    return "ok", frames, ""
                frames += len(xyz)
    except Exception as error:  # MDTraj raises IOError / RuntimeError / ValueError
        return "refused", frames, " ".join(str(error).split())[:120]


def main():
    # OUT.tsv.gz is written gzip-compressed (mtime 0, so reruns give the same bytes)
    if sys.argv[1].endswith(".gz"):
        out = io.TextIOWrapper(gzip.GzipFile(sys.argv[1], "wb", mtime=0))
    else:
        out = open(sys.argv[1], "w")
    paths = [p for p in sys.argv[2:] if not p.isdigit()]
    count = int(next((p for p in sys.argv[2:] if p.isdigit()), "400"))
    print("file\tindex\tkind\toffset\tlength\tverdict\tframes\tmessage", file=out)
    scratch = tempfile.mkdtemp()
    for path in paths:
        data = open(path, "rb").read()
        ext = os.path.splitext(path)[1]
        opener = formats.XTCTrajectoryFile if ext == ".xtc" else formats.DCDTrajectoryFile
        for index in range(count):
            body, kind, offset, length = mutant(data, index)
            if body == data:
                continue
            copy = os.path.join(scratch, f"mutant{ext}")
            with open(copy, "wb") as f:
                f.write(body)
            verdict, frames, message = frames_read(copy, opener)
            print(f"{os.path.basename(path)}\t{index}\t{kind}\t{offset}\t{length}\t{verdict}\t"
                  f"{frames}\t{message}", file=out)


if __name__ == "__main__":
    main()
