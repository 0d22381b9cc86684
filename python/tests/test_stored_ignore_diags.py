"""Issue 51: insulation and directionality leave out, as cooltools 0.7.1 does when
`ignore_diags` is not given, the diagonals that the weights were balanced without (the weight
column's `ignore_diags` attribute), not a fixed 2."""

from __future__ import annotations

import shutil
import subprocess

import numpy as np

import contactmap as cm
from helpers import YEAST, binary


def _balanced_copy(tmp_path, name: str) -> str:
    copy = str(tmp_path / "yeast.cool")
    if not (tmp_path / "yeast.cool").exists():
        shutil.copy(YEAST, copy)
    subprocess.run(
        [binary(), "balance", copy, "--store", "--name", name, "--ignore-diags", "1", "--force"],
        check=True,
        capture_output=True,
    )
    return copy


def _same(a, b) -> bool:
    return all(
        np.array_equal(np.asarray(a[c]), np.asarray(b[c]), equal_nan=a[c].dtype.kind == "f")
        for c in a.columns
    )


def test_insulation_reads_the_weights_ignore_diags(tmp_path):
    copy = _balanced_copy(tmp_path, "w1")
    default = cm.insulation(copy, [50000], clr_weight_name="w1")
    assert _same(default, cm.insulation(copy, [50000], clr_weight_name="w1", ignore_diags=1))
    assert not _same(default, cm.insulation(copy, [50000], clr_weight_name="w1", ignore_diags=2))


def test_directionality_reads_the_weight_columns_ignore_diags(tmp_path):
    copy = _balanced_copy(tmp_path, "weight")
    default = cm.directionality(copy, window_bp=50000)
    assert _same(default, cm.directionality(copy, window_bp=50000, ignore_diags=1))
    assert not _same(default, cm.directionality(copy, window_bp=50000, ignore_diags=2))
