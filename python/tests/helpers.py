"""What the tests share: the data paths, the command line, table comparisons."""

from __future__ import annotations

import io
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "data"
REF = DATA / "reference"
DM6 = f"{DATA}/cooler_test_file.mcool::/resolutions/100000"
MM9 = str(DATA / "CN.mm9.10000kb.cool")
GM12878 = str(DATA / "hg19.GM12878-MboI.matrix.2000kb.cool")
YEAST = str(DATA / "yeast.10kb.cool")


def binary() -> str:
    """The contactmap binary `make test` built (CONTACTMAP_BIN, else target/release or debug)."""
    for candidate in (
        os.environ.get("CONTACTMAP_BIN"),
        ROOT / "target" / "release" / "contactmap",
        ROOT / "target" / "debug" / "contactmap",
    ):
        if candidate and Path(candidate).is_file():
            return str(candidate)
    found = shutil.which("contactmap")
    assert found, "no contactmap binary: run `cargo build` first or set CONTACTMAP_BIN"
    return found


def cli_table(*args: str) -> pd.DataFrame:
    out = subprocess.run([binary(), *args], check=True, capture_output=True).stdout
    # exact floats: pandas 3 parses them round-trip by default, pandas 2 when asked
    exact = {} if int(pd.__version__.split(".")[0]) >= 3 else {"float_precision": "round_trip"}
    return pd.read_csv(io.BytesIO(out), sep="\t", **exact)


def assert_columns_close(ours: pd.DataFrame, ref: pd.DataFrame, rtol: float, what: str) -> None:
    assert len(ours) == len(ref), what
    for name in ref.columns:
        assert name in ours.columns, f"{what}: no column {name}"
        got, want = ours[name].to_numpy(), ref[name].to_numpy()
        if want.dtype.kind in "fiu" and got.dtype.kind in "fiu":
            got, want = got.astype(float), want.astype(float)
            assert np.array_equal(np.isnan(got), np.isnan(want)), f"{what}: NaN mask of {name}"
            ok = ~np.isnan(want)
            np.testing.assert_allclose(got[ok], want[ok], rtol=rtol, atol=0, err_msg=f"{what}: {name}")
        else:
            assert [str(v) for v in got] == [str(v) for v in want], f"{what}: {name}"
