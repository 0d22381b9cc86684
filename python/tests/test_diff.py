"""contactmap.diff_loops against ``contactmap diff loops`` on the same maps: the same table,
value for value (the statistics are compared with pydeseq2 0.5.4 in the library's tests).
Replicates: data/sim_extrusion.5kb.cool thinned by ``contactmap sample --fraction 0.5``."""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import contactmap
from helpers import DATA, binary


@pytest.fixture(scope="module")
def replicates(tmp_path_factory: pytest.TempPathFactory) -> list[str]:
    folder = tmp_path_factory.mktemp("replicates")
    paths = []
    for seed in range(1, 5):
        path = folder / f"r{seed}.cool"
        subprocess.run(
            [binary(), "sample", str(DATA / "sim_extrusion.5kb.cool"), "--fraction", "0.5",
             "--seed", str(seed), "-o", str(path)],
            check=True, capture_output=True,
        )
        paths.append(str(path))
    return paths


@pytest.mark.parametrize("given", [True, False])
def test_diff_loops_equals_the_command_line(
    replicates: list[str], tmp_path: Path, given: bool
) -> None:
    loops = str(DATA / "sim_extrusion.truth_loops.bedpe") if given else None
    second = [contactmap.File(u) for u in replicates[2:]]
    ours = contactmap.diff_loops(replicates[:2], second, loops)
    prefix = tmp_path / "cli"
    args = [binary(), "diff", "loops", "--a", *replicates[:2], "--b", *replicates[2:]]
    args += ["-o", str(prefix)]
    if loops is not None:
        args += ["--loops", loops]
    subprocess.run(args, check=True, capture_output=True)
    cli = pd.read_csv(f"{prefix}.loops.bedpe", sep="\t", keep_default_na=False, na_values=["nan"])
    assert list(ours.columns) == list(cli.columns)
    assert len(ours) == len(cli) > 0
    for name in cli.columns:
        if not pd.api.types.is_numeric_dtype(cli[name]):
            assert list(ours[name]) == list(cli[name]), name
        else:
            # the command line writes 7 significant digits
            np.testing.assert_allclose(ours[name], cli[name], rtol=1e-6, atol=0, err_msg=name)


def test_diff_loops_refuses_a_loop_off_the_maps(replicates: list[str], tmp_path: Path) -> None:
    bedpe = tmp_path / "off.bedpe"
    bedpe.write_text("chr9\t0\t5000\tchr9\t50000\t55000\n")
    with pytest.raises(contactmap.ContactmapError, match="chr9 is not a chromosome"):
        contactmap.diff_loops(replicates[:2], replicates[2:], bedpe)


@pytest.fixture(scope="module")
def balanced(replicates: list[str], tmp_path_factory: pytest.TempPathFactory) -> list[str]:
    """The replicates, copied and balanced (``balance --store``)."""
    folder = tmp_path_factory.mktemp("balanced")
    paths = []
    for k, source in enumerate(replicates):
        path = folder / f"b{k + 1}.cool"
        path.write_bytes(Path(source).read_bytes())
        subprocess.run([binary(), "balance", str(path), "--store"], check=True, capture_output=True)
        paths.append(str(path))
    return paths


def _cli_table(path: str) -> pd.DataFrame:
    return pd.read_csv(path, sep="\t", keep_default_na=False, na_values=["nan"])


def _assert_same(ours: pd.DataFrame, cli: pd.DataFrame) -> None:
    assert list(ours.columns) == list(cli.columns)
    assert len(ours) == len(cli)
    pd.testing.assert_frame_equal(ours, cli, check_exact=True)


def test_diff_boundaries_equals_the_command_line(balanced: list[str], tmp_path: Path) -> None:
    ours = contactmap.diff_boundaries(balanced[:2], balanced[2:], window=25_000)
    prefix = tmp_path / "b"
    subprocess.run(
        [binary(), "diff", "boundaries", "--a", *balanced[:2], "--b", *balanced[2:],
         "--window", "25k", "-o", str(prefix)],
        check=True, capture_output=True,
    )
    cli = _cli_table(f"{prefix}.boundaries.tsv")
    assert len(cli) > 3
    _assert_same(ours, cli)


def test_diff_compartments_equals_the_command_line(balanced: list[str], tmp_path: Path) -> None:
    # a phasing track on the map's bins: a ramp along the chromosome, as a bedGraph for the CLI
    track = np.linspace(0.0, 1.0, 200)
    bedgraph = tmp_path / "track.bedgraph"
    bedgraph.write_text("".join(f"chr1\t{5000 * k}\t{5000 * (k + 1)}\t{float(v)!r}\n" for k, v in enumerate(track)))
    table, segments = contactmap.diff_compartments(balanced[:2], balanced[2:], phasing_track=track)
    prefix = tmp_path / "c"
    subprocess.run(
        [binary(), "diff", "compartments", "--a", *balanced[:2], "--b", *balanced[2:],
         "--phasing-track", f"{bedgraph}:4", "-o", str(prefix)],
        check=True, capture_output=True,
    )
    _assert_same(table, _cli_table(f"{prefix}.compartments.tsv"))
    _assert_same(segments, _cli_table(f"{prefix}.switches.bed"))
    assert len(table) == 200


def test_diff_regions_equals_the_command_line(balanced: list[str], tmp_path: Path) -> None:
    ours = contactmap.diff_regions(balanced[0], contactmap.File(balanced[2]), window=150_000, step=25_000)
    prefix = tmp_path / "r"
    subprocess.run(
        [binary(), "diff", "regions", "--a", balanced[0], "--b", balanced[2], "--window", "150k",
         "--step", "25k", "-o", str(prefix)],
        check=True, capture_output=True,
    )
    cli = _cli_table(f"{prefix}.regions.tsv")
    assert len(cli) == 35
    _assert_same(ours, cli)
    with pytest.raises(ValueError, match="pairs or window"):
        contactmap.diff_regions(balanced[0], balanced[2])


def test_diff_boundaries_refuses_an_unbalanced_map(replicates: list[str], balanced: list[str]) -> None:
    with pytest.raises(contactmap.ContactmapError, match="weight"):
        contactmap.diff_boundaries(balanced[:1], replicates[2:3])
