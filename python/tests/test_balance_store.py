"""balance(store=True) against cooler's balance_cooler(store=True) on copies of one file, and
what it refuses."""

from __future__ import annotations

import shutil
from pathlib import Path

import cooler
import h5py
import numpy as np
import pytest

import contactmap as cm

from helpers import MM9


def test_stored_weights_equal_coolers(tmp_path: Path) -> None:
    ours, theirs = tmp_path / "ours.cool", tmp_path / "theirs.cool"
    for path in (ours, theirs):
        shutil.copy(MM9, path)
    f = cm.File(ours)
    weights, summary = cm.balance(f, store=True, name="ice", ignore_diags=2)
    assert summary["converged"]
    assert "ice" in f.avail_normalizations()  # the File was reopened and sees the column
    np.testing.assert_array_equal(f.weights("ice"), weights)
    bias, stats = cooler.balance_cooler(cooler.Cooler(str(theirs)), store=True, store_name="ice")
    ok = ~np.isnan(bias)
    assert np.array_equal(np.isnan(weights), ~ok)
    np.testing.assert_allclose(weights[ok], bias[ok], rtol=1e-6)
    with h5py.File(ours, "r") as a, h5py.File(theirs, "r") as b:
        ours_attrs, their_attrs = dict(a["bins/ice"].attrs), dict(b["bins/ice"].attrs)
    for key in ("min_nnz", "min_count", "mad_max", "ignore_diags", "cis_only", "converged"):
        assert ours_attrs[key] == their_attrs[key], key
    np.testing.assert_allclose(ours_attrs["scale"], their_attrs["scale"], rtol=1e-6)


def test_store_refuses_to_replace_or_to_write_an_open_file(tmp_path: Path) -> None:
    path = tmp_path / "copy.cool"
    shutil.copy(MM9, path)
    with pytest.raises(cm.ContactmapError, match="already exists: use overwrite=True"):
        cm.balance(str(path), store=True)
    before = cm.File(path).weights("weight")
    other = cm.File(path)  # holds the file open for reading
    with pytest.raises(cm.ContactmapError, match="close it first"):
        cm.balance(str(path), store=True, overwrite=True, method="vc")
    del other
    weights, _ = cm.balance(str(path), store=True, overwrite=True, method="vc")
    after = cm.File(path).weights("weight")
    assert not np.allclose(before, after, equal_nan=True)
    np.testing.assert_array_equal(after, weights)
    with pytest.raises(cm.ContactmapError, match=".cool / .mcool files only"):
        cm.balance(str(Path(__file__).parents[2] / "data" / "protein" / "toxd" / "toxd.mat.gz"), store=True)
