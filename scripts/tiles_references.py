#!/usr/bin/env python3
"""clodius 0.22.2's answers for the maps in data/, which the `tiles` room's tests compare with.

Run with a Python that has clodius 0.22.2 (it needs Python >= 3.12):
    /root/.pyenv/versions/3.12.1/bin/python -m venv /tmp/clodius_venv
    /tmp/clodius_venv/bin/pip install clodius==0.22.2
    /tmp/clodius_venv/bin/python scripts/tiles_references.py

Writes data/tiles/<map>.tileset_info.json: `clodius.tiles.cooler.tileset_info` of each map,
its `transforms` sorted by value (clodius lists them in Python's set order, which varies).
"""

import json
import os

import clodius
import clodius.tiles.cooler as hgc

MAPS = ["cooler_test_file.mcool", "toy.symm.upper.2.mcool"]

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data")
out = os.path.join(root, "tiles")
os.makedirs(out, exist_ok=True)
assert clodius.__version__ == "0.22.2", clodius.__version__
for name in MAPS:
    info = dict(hgc.tileset_info(os.path.join(root, name)))
    info["transforms"] = sorted(info["transforms"], key=lambda t: t["value"])
    with open(os.path.join(out, name + ".tileset_info.json"), "w") as f:
        json.dump(info, f, indent=1, sort_keys=True)
        f.write("\n")
    print(name, "->", os.path.join("data/tiles", name + ".tileset_info.json"))
