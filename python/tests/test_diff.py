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
