"""HiGlass tiles of a map, as clodius computes them for higlass-server: a notebook can serve
them as higlass-python's tilesets do (``contactmap serve`` is the same from the command line)."""

from __future__ import annotations

import json
import os
from typing import Any, Sequence

from . import _native


class Tileset:
    """A map's tileset: every resolution of an ``.mcool`` or ``.hic``, or a ``.cool``'s one.

    ``tileset_info()`` and ``tiles(ids)`` answer as ``clodius.tiles.cooler.tileset_info`` and
    ``clodius.tiles.cooler.tiles`` (0.22.2) do, tile for tile: 256 x 256 values, base64 float16
    where clodius uses float16, else float32, NaN for masked bins and past the genome's end.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self._native = _native.NativeTileset(os.fspath(path))

    def tileset_info(self) -> dict[str, Any]:
        """Resolutions, transforms, ``min_pos`` / ``max_pos``, chromsizes (``mirror_tiles``
        for square storage)."""
        info: dict[str, Any] = json.loads(self._native.tileset_info())
        return info

    def tiles(self, tile_ids: Sequence[str]) -> list[tuple[str, dict[str, Any]]]:
        """The tiles of ``tile_ids`` (``UID.z.x.y`` or ``UID.z.x.y.transform``; the UID is not
        looked at) as ``(id, tile)`` pairs; an id past the last zoom level is left out."""
        answer = json.loads(self._native.tiles([str(t) for t in tile_ids]))
        return [(tile_id, tile) for tile_id, tile in answer]


def tiles(path: str | os.PathLike[str]) -> Tileset:
    """The HiGlass tileset of the map at ``path`` (``.mcool``, ``.cool``, ``.hic``)::

        ts = contactmap.tiles("sample.mcool")
        ts.tileset_info()["resolutions"]
        ts.tiles(["x.0.0.0", "x.1.0.0.KR"])
    """
    return Tileset(path)
