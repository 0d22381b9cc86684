"""The writers from Python: create_cooler against cooler's own create_cooler on the same table,
zoomify against `cooler zoomify --balance` (data/reference), convert and merge against the
command line, and the maps written read back by cooler."""

from __future__ import annotations

import subprocess
from pathlib import Path

import cooler
import numpy as np
import pandas as pd
import pytest

import contactmap as cm

from helpers import DATA, MM9, REF, YEAST, binary


def pixels_of(uri: str) -> pd.DataFrame:
    return cooler.Cooler(uri).pixels()[:]


def test_create_cooler_equals_coolers_create_cooler(tmp_path: Path) -> None:
    source = cooler.Cooler(MM9)
    bins = source.bins()[:]  # chrom (categorical), start, end, weight
    pixels = source.pixels()[:]
    ours, theirs = str(tmp_path / "ours.cool"), str(tmp_path / "theirs.cool")
    cm.create_cooler(ours, bins, pixels, assembly="mm9")
    cooler.create_cooler(theirs, bins, pixels, assembly="mm9")
    a, b = cooler.Cooler(ours), cooler.Cooler(theirs)
    assert a.chromnames == b.chromnames and list(a.chromsizes) == list(b.chromsizes)
    assert a.binsize == b.binsize and a.info["nnz"] == b.info["nnz"]
    assert a.info["genome-assembly"] == "mm9"
    pd.testing.assert_frame_equal(a.pixels()[:], b.pixels()[:])
    ba, bb = a.bins()[:], b.bins()[:]
    np.testing.assert_array_equal(ba["weight"].to_numpy(), bb["weight"].to_numpy())
    np.testing.assert_array_equal(
        a.matrix(balance=True)[:, :], b.matrix(balance=True)[:, :]
    )
    # chunks of a dict of arrays, in the lower triangle and repeated: mirrored and summed
    half = len(pixels) // 2
    swapped = {
        "bin1_id": pixels["bin2_id"].to_numpy()[:half],
        "bin2_id": pixels["bin1_id"].to_numpy()[:half],
        "count": pixels["count"].to_numpy()[:half],
    }
    chunks = [swapped, pixels.iloc[half:], pixels.iloc[half:]]
    doubled = str(tmp_path / "doubled.cool")
    cm.create_cooler(doubled, bins[["chrom", "start", "end"]], chunks)
    got = pixels_of(doubled)
    want = pixels.copy()
    want.loc[half:, "count"] *= 2
    pd.testing.assert_frame_equal(got, want.reset_index(drop=True))
    # real counts
    real = pixels.assign(count=pixels["count"] / 3)
    path = str(tmp_path / "real.cool")
    cm.create_cooler(path, bins, real)
    np.testing.assert_array_equal(pixels_of(path)["count"].to_numpy(), real["count"].to_numpy())


def test_create_cooler_refuses_bad_tables(tmp_path: Path) -> None:
    bins = pd.DataFrame({"chrom": ["a", "a"], "start": [0, 10], "end": [10, 20]})
    out = str(tmp_path / "bad.cool")
    with pytest.raises(cm.ContactmapError, match="pixels row 1: bin ids \\(0, 2\\) for 2 bins"):
        cm.create_cooler(out, bins, {"bin1_id": [0, 0], "bin2_id": [1, 2], "count": [1, 1]})
    with pytest.raises(ValueError, match="pixels: missing columns \\['count'\\]"):
        cm.create_cooler(out, bins, {"bin1_id": [0], "bin2_id": [1]})
    with pytest.raises(cm.ContactmapError, match="bin1_id\\[0\\] = -1"):
        cm.create_cooler(out, bins, {"bin1_id": [-1], "bin2_id": [1], "count": [1]})
    assert not Path(out).exists()


def test_zoomify_with_balance_equals_cooler_zoomify(tmp_path: Path) -> None:
    out = cm.zoomify(YEAST, tmp_path / "yeast.mcool", [10000, 20000, 40000], balance=True)
    assert cm.MultiResFile(out).resolutions() == [10000, 20000, 40000]
    level = cooler.Cooler(f"{out}::/resolutions/20000")
    reference = pd.read_csv(REF / "yeast_20kb.zoomify_balance.weight.tsv", sep="\t")
    ours = level.bins()[:]["weight"].to_numpy()
    want = reference["weight"].to_numpy()
    assert np.array_equal(np.isnan(ours), np.isnan(want))
    np.testing.assert_allclose(ours[~np.isnan(want)], want[~np.isnan(want)], rtol=1e-6)
    # the coarse pixels are sums of the fine ones: the stored (upper-triangle) totals agree
    assert level.pixels()[:]["count"].sum() == pixels_of(YEAST)["count"].sum()


def test_convert_and_merge_equal_the_command_line(tmp_path: Path) -> None:
    for name in ("x.mcool", "x.hic"):
        ours, theirs = tmp_path / f"ours.{name}", tmp_path / f"cli.{name}"
        cm.convert(YEAST, ours, resolutions=[10000, 50000])
        subprocess.run(
            [binary(), "convert", YEAST, str(theirs), "--resolutions", "10000,50000"],
            check=True,
            capture_output=True,
        )
        for res in (10000, 50000):
            a = cm.File(f"{ours}::/resolutions/{res}").fetch().to_df()
            b = cm.File(f"{theirs}::/resolutions/{res}").fetch().to_df()
            pd.testing.assert_frame_equal(a, b)
    merged, cli = tmp_path / "merged.cool", tmp_path / "cli_merged.cool"
    cm.merge([YEAST, cm.File(YEAST)], merged)
    subprocess.run([binary(), "merge", YEAST, YEAST, "-o", str(cli)], check=True)
    pd.testing.assert_frame_equal(pixels_of(str(merged)), pixels_of(str(cli)))
    single = pixels_of(YEAST)
    np.testing.assert_array_equal(pixels_of(str(merged))["count"], 2 * single["count"])


def test_writers_refuse_to_overwrite_an_input(tmp_path: Path) -> None:
    copy = tmp_path / "copy.cool"
    copy.write_bytes(Path(YEAST).read_bytes())
    before = copy.read_bytes()
    with pytest.raises(cm.ContactmapError, match="is an input too"):
        cm.convert(str(copy), copy)
    with pytest.raises(cm.ContactmapError, match="is an input too"):
        cm.merge([str(copy), YEAST], str(copy))
    with pytest.raises(cm.ContactmapError, match=".cool, .mcool or .hic"):
        cm.convert(YEAST, tmp_path / "out.txt")
    assert copy.read_bytes() == before


def test_an_output_in_a_missing_folder_is_file_not_found(tmp_path: Path) -> None:
    out = tmp_path / "nowhere" / "out.cool"
    with pytest.raises(FileNotFoundError, match="the folder '.*nowhere' does not exist"):
        cm.convert(YEAST, out)
    assert not (tmp_path / "nowhere").exists()
