"""contactmap.tiles against clodius 0.22.2's answers (data/tiles/, scripts/tiles_references.py):
the same bytes for every tile clodius was asked for, the same tileset_info."""

from __future__ import annotations

import base64
import gzip
import json
import zlib

import numpy as np
import pytest

import contactmap as cm

from helpers import DATA

MAPS = {
    "cooler_test_file.mcool": DATA / "cooler_test_file.mcool",
    "square.mcool": DATA / "tiles" / "square.mcool",
}


def reference(name: str, what: str) -> dict:
    path = DATA / "tiles" / f"{name}.{what}.json"
    if path.exists():
        return json.loads(path.read_text())
    return json.loads(gzip.decompress(path.with_suffix(".json.gz").read_bytes()))


@pytest.mark.parametrize("name", sorted(MAPS))
def test_tiles_equal_clodius(name: str) -> None:
    ts = cm.tiles(MAPS[name])
    info = ts.tileset_info()
    info["transforms"] = sorted(info["transforms"], key=lambda t: t["value"])
    assert info == reference(name, "tileset_info")
    expected = reference(name, "tiles")
    ids = [f"x.{k}" for k in expected]
    answers = dict(ts.tiles(ids))
    float16 = 0
    for key, want in expected.items():
        tile = answers.get(f"x.{key}")
        if want is None:
            assert tile is None, key
            continue
        raw = base64.b64decode(tile["dense"])
        values = np.frombuffer(raw, dtype=tile["dtype"])
        assert tile["dtype"] == want["dtype"], key
        assert zlib.crc32(raw) == want["crc32"], key
        assert int(np.isnan(values).sum()) == want["n_nan"], key
        assert values.shape == (256 * 256,)
        float16 += tile["dtype"] == "float16"
    assert float16 > 0


def test_tiles_errors() -> None:
    ts = cm.tiles(MAPS["cooler_test_file.mcool"])
    with pytest.raises(cm.ContactmapError, match="no 'KR' column"):
        ts.tiles(["x.0.0.0.KR"])
    with pytest.raises(cm.ContactmapError, match="tile id"):
        ts.tiles(["x.0.0"])
    with pytest.raises(cm.ContactmapError, match="not a number"):
        ts.tiles(["x.0.a.0"])
    assert ts.tiles(["x.5.0.0"]) == []  # past the last zoom level
    with pytest.raises(FileNotFoundError):
        cm.tiles(DATA / "no-such.mcool")
