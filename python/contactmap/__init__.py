"""contactmap: contact maps from Python, with the answers of cooler, cooltools and hictkpy.

Open any map contactmap reads and fetch from it as hictkpy does; compute cooltools' tables with
cooltools' argument names::

    import contactmap as cm

    f = cm.File("data/yeast.10kb.cool")
    m = f.fetch("chrIV:0-500,000", normalization="weight").to_numpy()
    exp = cm.expected_cis(f, ignore_diags=2)
    ins = cm.insulation(f, window_bp=[50_000])

The work is done by the Rust library (the same functions as the ``contactmap`` command line),
with the GIL released; arrays come back without a copy. Coordinates are 0-based, half-open, in
base pairs; weights are multiplicative (cooler's convention).
"""


from __future__ import annotations

from ._compartments import digitize, eigs_cis, eigs_trans, saddle, saddle_strength
from ._diff import diff_boundaries, diff_compartments, diff_loops, diff_regions
from ._file import File, MultiResFile, PixelSelector
from ._loops import dots, merge_dots, pileup
from ._native import ContactmapError, FormatError
from ._protein import Structure, contact_frequencies, read_structure, score_contacts
from ._simulate import (
    PolymerMap,
    PolymerStats,
    Simulation,
    polymer_map,
    polymer_stats,
    simulate_polymer,
)
from ._tables import balance, directionality, expected_cis, expected_trans, insulation
from ._tiles import Tileset, tiles
from ._writers import convert, create_cooler, merge, zoomify

__all__ = [
    "ContactmapError",
    "File",
    "FormatError",
    "MultiResFile",
    "PixelSelector",
    "PolymerMap",
    "PolymerStats",
    "Simulation",
    "Structure",
    "Tileset",
    "balance",
    "contact_frequencies",
    "convert",
    "create_cooler",
    "diff_boundaries",
    "diff_compartments",
    "diff_loops",
    "diff_regions",
    "digitize",
    "directionality",
    "dots",
    "eigs_cis",
    "eigs_trans",
    "expected_cis",
    "expected_trans",
    "insulation",
    "merge",
    "merge_dots",
    "pileup",
    "polymer_map",
    "polymer_stats",
    "read_structure",
    "saddle",
    "saddle_strength",
    "score_contacts",
    "simulate_polymer",
    "tiles",
    "zoomify",
]

__version__ = "0.1.0"
