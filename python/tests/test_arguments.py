"""Every public function checks its arguments before any work: a wrong type is a TypeError, a
wrong value a ValueError, each message starting with the argument's name (``name: expected
...``), never an error from deep inside (KeyError, OverflowError, 'NoneType' object is not
subscriptable ...). One test per public function of ``contactmap.__all__``."""

from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np
import pandas as pd
import pytest

import contactmap as cm

from helpers import DATA, YEAST

TOPOLOGY = str(DATA / "md" / "cobrotoxin.pdb.gz")
TRAJECTORY = str(DATA / "md" / "cobrotoxin.dcd")
POLYCHROM = str(DATA / "polychrom" / "traj")
TOXD = str(DATA / "protein" / "toxd" / "toxd.pdb.gz")
TOXD_MATRIX = str(DATA / "protein" / "toxd" / "toxd.mat.gz")
MCOOL = str(DATA / "cooler_test_file.mcool")


def refused(error: type[Exception], name: str, call: Callable[[], object], *texts: str) -> str:
    """``call()`` raises ``error`` whose message starts with ``name:`` and holds ``texts``."""
    with pytest.raises(error) as info:
        call()
    message = str(info.value)
    assert message.startswith(f"{name}:"), message
    for text in texts:
        assert text in message, message
    return message


@pytest.fixture(scope="module")
def yeast() -> cm.File:
    return cm.File(YEAST)


@pytest.fixture(scope="module")
def expected(yeast: cm.File) -> pd.DataFrame:
    return cm.expected_cis(yeast)


@pytest.fixture(scope="module")
def track(yeast: cm.File) -> pd.DataFrame:
    bins = yeast.bins()[["chrom", "start", "end"]].copy()
    bins["GC"] = np.linspace(0.3, 0.6, len(bins))
    return bins


def test_file(yeast: cm.File) -> None:
    refused(TypeError, "uri", lambda: cm.File(None), "expected a path", "NoneType")
    refused(TypeError, "range1", lambda: yeast.fetch(5), "expected a str or None, got int")
    refused(ValueError, "range1", lambda: yeast.fetch("chrZZ"), "chrZZ")
    refused(TypeError, "range2", lambda: yeast.fetch("chrI", ["chrII"]), "got list")
    message = refused(
        ValueError, "normalization", lambda: yeast.fetch("chrI", normalization="bogus"), "'bogus'"
    )
    assert "avail_normalizations()" in message and "'weight'" in message
    refused(TypeError, "normalization", lambda: yeast.fetch(normalization=1), "got int")
    refused(ValueError, "query_type", lambda: yeast.fetch(query_type="BED"), "'UCSC'", "'BED'")
    refused(ValueError, "name", lambda: yeast.weights("KR"), "'KR'", "'weight'")


def test_multi_res_file() -> None:
    refused(TypeError, "path", lambda: cm.MultiResFile(None), "got NoneType")
    mcool = cm.MultiResFile(MCOOL)
    refused(TypeError, "resolution", lambda: mcool["100000"], "expected a positive int, got str")
    refused(ValueError, "resolution", lambda: mcool[5], "no resolution 5", "100000")


def test_pixel_selector(yeast: cm.File) -> None:
    selector = yeast.fetch("chrI")
    refused(TypeError, "join", lambda: selector.to_df(join="yes"), "True or False", "str")
    refused(TypeError, "file", lambda: cm.PixelSelector(YEAST, (0, 1), (0, 1), None), "str")
    refused(ValueError, "rows[1]", lambda: cm.PixelSelector(yeast, (0, 10**9), (0, 1), None))


def test_balance(yeast: cm.File) -> None:
    refused(TypeError, "clr", lambda: cm.balance(None), "NoneType")
    refused(ValueError, "ignore_diags", lambda: cm.balance(yeast, ignore_diags=-1), "got -1")
    refused(TypeError, "tol", lambda: cm.balance(yeast, tol="1e-5"), "got str")
    refused(TypeError, "cis_only", lambda: cm.balance(yeast, cis_only="yes"), "True or False")
    refused(ValueError, "max_iters", lambda: cm.balance(yeast, max_iters=0), "positive int")


def test_contact_frequencies() -> None:
    refused(TypeError, "trajectory", lambda: cm.contact_frequencies(None, TOPOLOGY), "path")
    refused(TypeError, "topology", lambda: cm.contact_frequencies(TRAJECTORY, None), "path")
    refused(
        ValueError, "stride", lambda: cm.contact_frequencies(TRAJECTORY, TOPOLOGY, stride=0), "0"
    )
    refused(
        ValueError, "min_sep", lambda: cm.contact_frequencies(TRAJECTORY, TOPOLOGY, min_sep=-1)
    )
    refused(
        ValueError, "cutoff", lambda: cm.contact_frequencies(TRAJECTORY, TOPOLOGY, cutoff=-8)
    )


def test_convert(tmp_path: Path) -> None:
    out = tmp_path / "out.cool"
    refused(TypeError, "input", lambda: cm.convert(None, out), "NoneType")
    refused(TypeError, "output", lambda: cm.convert(YEAST, None), "path", "NoneType")
    refused(ValueError, "compression_level", lambda: cm.convert(YEAST, out, compression_level=10))
    refused(TypeError, "normalizations", lambda: cm.convert(YEAST, out, normalizations=5))
    assert not out.exists()


def test_create_cooler(tmp_path: Path) -> None:
    out = str(tmp_path / "out.cool")
    bins = pd.DataFrame({"chrom": ["a", "a"], "start": [0, 10], "end": [10, 20]})
    pixels = pd.DataFrame({"bin1_id": [0], "bin2_id": [1], "count": [1]})
    refused(TypeError, "cool_uri", lambda: cm.create_cooler(None, bins, pixels), "path")
    refused(TypeError, "bins", lambda: cm.create_cooler(out, None, pixels), "chrom start end")
    refused(
        ValueError,
        "bins",
        lambda: cm.create_cooler(out, bins[["chrom"]], pixels),
        "missing columns ['start', 'end']",
        "chrom start end",
    )
    text = bins.assign(start=["0", "x"])
    refused(ValueError, "bins column 'start'", lambda: cm.create_cooler(out, text, pixels))
    refused(TypeError, "pixels", lambda: cm.create_cooler(out, bins, None), "bin1_id")
    refused(
        ValueError,
        "pixels",
        lambda: cm.create_cooler(out, bins, pixels[["bin1_id"]]),
        "missing columns ['bin2_id', 'count']",
    )
    assert not Path(out).exists()


def test_digitize(track: pd.DataFrame) -> None:
    refused(TypeError, "track", lambda: cm.digitize(None, 5), "NoneType")
    refused(ValueError, "track", lambda: cm.digitize(track[["chrom", "start"]], 5), "fourth")
    refused(ValueError, "n_bins", lambda: cm.digitize(track, -1), "positive int, got -1")
    refused(TypeError, "n_bins", lambda: cm.digitize(track, "5"), "got str")
    refused(ValueError, "qrange[1]", lambda: cm.digitize(track, 5, qrange=(0, 2)), "<= 1")
    refused(
        ValueError, "vrange and qrange", lambda: cm.digitize(track, 5, (0, 1), (0, 1)), "not both"
    )


def test_directionality(yeast: cm.File) -> None:
    refused(TypeError, "window_bp", lambda: cm.directionality(yeast, "100000"), "got str")
    refused(ValueError, "window_bp", lambda: cm.directionality(yeast, 0), "positive int")
    refused(ValueError, "ignore_diags", lambda: cm.directionality(yeast, ignore_diags=-1))
    refused(ValueError, "min_dist_bad_bin", lambda: cm.directionality(yeast, min_dist_bad_bin=-1))
    refused(ValueError, "balance", lambda: cm.directionality(yeast, balance="KR"), "'KR'")


def test_dots(yeast: cm.File, expected: pd.DataFrame) -> None:
    refused(TypeError, "expected", lambda: cm.dots(yeast, None), "DataFrame", "NoneType")
    refused(
        ValueError,
        "expected",
        lambda: cm.dots(yeast, pd.DataFrame({"a": [1]})),
        "missing columns ['region1', 'dist', 'balanced.avg']",
        "expected_cis",
    )
    refused(
        ValueError,
        "expected",
        lambda: cm.dots(yeast, expected, expected_value_col="nope"),
        "missing columns ['nope']",
    )
    refused(ValueError, "lambda_bin_fdr", lambda: cm.dots(yeast, expected, lambda_bin_fdr=2))
    refused(ValueError, "w", lambda: cm.dots(yeast, expected, w=-1, p=2), "got -1")
    refused(TypeError, "clr_weight_name", lambda: cm.dots(yeast, expected, clr_weight_name=None))
    refused(
        ValueError, "max_loci_separation", lambda: cm.dots(yeast, expected, max_loci_separation=-5)
    )


def test_eigs_cis(yeast: cm.File, track: pd.DataFrame) -> None:
    refused(ValueError, "n_eigs", lambda: cm.eigs_cis(yeast, n_eigs=-1), "got -1")
    refused(TypeError, "phasing_track", lambda: cm.eigs_cis(yeast, "GC"), "got str")
    refused(ValueError, "clr_weight_name", lambda: cm.eigs_cis(yeast, clr_weight_name="KR"))
    refused(TypeError, "clip_percentile", lambda: cm.eigs_cis(yeast, clip_percentile="99"))
    refused(ValueError, "ignore_diags", lambda: cm.eigs_cis(yeast, track, ignore_diags=-2))


def test_eigs_trans(yeast: cm.File) -> None:
    refused(ValueError, "n_eigs", lambda: cm.eigs_trans(yeast, n_eigs=-1), "got -1")
    refused(ValueError, "perc_top", lambda: cm.eigs_trans(yeast, perc_top=101), "<= 100")
    refused(ValueError, "partition", lambda: cm.eigs_trans(yeast, partition=[0, 5]), "None")
    refused(TypeError, "phasing_track", lambda: cm.eigs_trans(yeast, {"GC": 1}), "dict")


def test_expected_cis(yeast: cm.File) -> None:
    refused(TypeError, "clr", lambda: cm.expected_cis(None), "NoneType")
    refused(
        ValueError,
        "ignore_diags",
        lambda: cm.expected_cis(yeast, ignore_diags=-1),
        "expected a non-negative int, got -1",
    )
    refused(TypeError, "smooth_sigma", lambda: cm.expected_cis(yeast, smooth_sigma="0.1"))
    refused(
        ValueError,
        "view_df",
        lambda: cm.expected_cis(yeast, pd.DataFrame({"chrom": ["chrI"]})),
        "missing columns ['start', 'end']",
    )
    refused(ValueError, "intra_only", lambda: cm.expected_cis(yeast, intra_only=False))


def test_expected_trans(yeast: cm.File) -> None:
    refused(TypeError, "clr_weight_name", lambda: cm.expected_trans(yeast, clr_weight_name=5))
    refused(ValueError, "view_df[0]", lambda: cm.expected_trans(yeast, [("chrI", 0)]), "2 values")
    refused(ValueError, "nproc", lambda: cm.expected_trans(yeast, nproc=0))


def test_insulation(yeast: cm.File) -> None:
    # a str window is refused (cooltools takes ints), not read as a number
    refused(
        TypeError,
        "window_bp",
        lambda: cm.insulation(yeast, "100000"),
        "expected a positive int or a list of positive ints, got str",
    )
    refused(ValueError, "window_bp", lambda: cm.insulation(yeast, []), "empty")
    refused(ValueError, "window_bp[1]", lambda: cm.insulation(yeast, [50_000, 0]), "got 0")
    refused(
        ValueError,
        "min_frac_valid_pixels",
        lambda: cm.insulation(yeast, 50_000, min_frac_valid_pixels=2),
    )
    refused(ValueError, "threshold", lambda: cm.insulation(yeast, 50_000, threshold="bogus"))
    refused(ValueError, "ignore_diags", lambda: cm.insulation(yeast, 50_000, ignore_diags=-1))


def test_merge(tmp_path: Path) -> None:
    out = tmp_path / "merged.cool"
    refused(TypeError, "inputs", lambda: cm.merge(YEAST, out), "a list of maps", "str")
    refused(TypeError, "inputs[1]", lambda: cm.merge([YEAST, None], out), "NoneType")
    refused(TypeError, "out", lambda: cm.merge([YEAST, YEAST], None), "NoneType")
    refused(TypeError, "resolutions[0]", lambda: cm.merge([YEAST], out, resolutions=[None]))
    assert not out.exists()


def test_merge_dots() -> None:
    dots = pd.DataFrame(
        {"chrom1": ["chr1"], "start1": [0], "end1": [5000], "chrom2": ["chr1"],
         "start2": [50_000], "end2": [55_000], "count": [12]}
    )
    refused(TypeError, "dots", lambda: cm.merge_dots([dots]), "mapping", "list")
    refused(ValueError, "dots: resolution", lambda: cm.merge_dots({-5: dots}), "got -5")
    refused(
        ValueError,
        "dots[5000] (bedpe)",
        lambda: cm.merge_dots({5000: dots[["chrom1", "start1"]]}),
        "missing columns",
    )
    refused(TypeError, "near_diagonal", lambda: cm.merge_dots({5000: dots}, near_diagonal="x"))
    refused(ValueError, "strong", lambda: cm.merge_dots({5000: dots}, strong=float("nan")))


def test_pileup(yeast: cm.File) -> None:
    features = pd.DataFrame({"chrom": ["chrIV"], "start": [500_000], "end": [510_000]})
    refused(TypeError, "features", lambda: cm.pileup(yeast, None), "DataFrame", "NoneType")
    refused(ValueError, "flank", lambda: cm.pileup(yeast, features, flank=-1), "got -1")
    refused(
        ValueError,
        "expected_df",
        lambda: cm.pileup(yeast, features, expected_df=pd.DataFrame({"a": [1]})),
        "missing columns",
    )
    refused(ValueError, "by_window", lambda: cm.pileup(yeast, features, by_window=True))
    refused(TypeError, "groupby", lambda: cm.pileup(yeast, features, groupby=5), "got int")
    refused(ValueError, "seed", lambda: cm.pileup(yeast, features, nshifts=2, seed=-1))
    refused(ValueError, "mindist", lambda: cm.pileup(yeast, features, mindist="far"), "'auto'")


def test_polymer_map() -> None:
    refused(TypeError, "trajectory", lambda: cm.polymer_map(None, 1.6), "NoneType")
    refused(TypeError, "contact_radius", lambda: cm.polymer_map(POLYCHROM, "1.6"), "got str")
    refused(
        ValueError,
        "monomers_per_bin",
        lambda: cm.polymer_map(POLYCHROM, 1.6, monomers_per_bin=0),
        "positive int, got 0",
    )
    refused(ValueError, "chains[0]", lambda: cm.polymer_map(POLYCHROM, 1.6, chains=[-1]))
    pixels = pd.DataFrame({"bin1_id": [0], "bin2_id": [1], "count": [1]})
    polymer = cm.PolymerMap(pixels, [2], 1, 2)
    refused(TypeError, "polychrom", lambda: polymer.dense(polychrom="yes"), "True or False")


def test_polymer_stats() -> None:
    refused(ValueError, "contact_radius", lambda: cm.polymer_stats(POLYCHROM, -1), "got -1")
    refused(ValueError, "trajectory", lambda: cm.polymer_stats([]), "empty")
    refused(TypeError, "trajectory[0]", lambda: cm.polymer_stats([None]), "NoneType")


def test_read_structure() -> None:
    refused(TypeError, "path", lambda: cm.read_structure(None), "NoneType")
    refused(ValueError, "cutoff", lambda: cm.read_structure(TOXD, cutoff=-8), "positive")
    refused(TypeError, "chain", lambda: cm.read_structure(TOXD, chain=1), "got int")
    refused(TypeError, "le", lambda: cm.read_structure(TOXD, le="yes"), "True or False")


def test_saddle(yeast: cm.File, expected: pd.DataFrame, track: pd.DataFrame) -> None:
    refused(TypeError, "expected", lambda: cm.saddle(yeast, None, track), "NoneType")
    refused(
        ValueError,
        "expected",
        lambda: cm.saddle(yeast, expected.drop(columns="dist"), track),
        "missing columns ['dist']",
    )
    refused(TypeError, "track", lambda: cm.saddle(yeast, expected, None), "NoneType")
    refused(
        ValueError, "contact_type", lambda: cm.saddle(yeast, expected, track, "both"), "'trans'"
    )
    refused(ValueError, "n_bins", lambda: cm.saddle(yeast, expected, track, n_bins=-1))
    refused(
        ValueError,
        "vrange and qrange",
        lambda: cm.saddle(yeast, expected, track, vrange=(0, 1), qrange=(0, 1)),
    )
    refused(ValueError, "min_diag", lambda: cm.saddle(yeast, expected, track, min_diag=-1))


def test_saddle_strength() -> None:
    refused(TypeError, "S", lambda: cm.saddle_strength(None, np.ones((3, 3))), "NoneType")
    refused(ValueError, "S", lambda: cm.saddle_strength(np.ones(9), np.ones(9)), "square")
    refused(
        ValueError, "S and C", lambda: cm.saddle_strength(np.ones((3, 3)), np.ones((2, 2)))
    )


def test_score_contacts() -> None:
    refused(TypeError, "structure", lambda: cm.score_contacts(None, TOXD_MATRIX), "NoneType")
    refused(TypeError, "prediction", lambda: cm.score_contacts(TOXD, None), "NoneType")
    refused(TypeError, "cutoff", lambda: cm.score_contacts(TOXD, TOXD_MATRIX, cutoff="8"))
    refused(ValueError, "length", lambda: cm.score_contacts(TOXD, TOXD_MATRIX, length="long"))
    refused(ValueError, "min_sep", lambda: cm.score_contacts(TOXD, TOXD_MATRIX, min_sep=-1))
    refused(TypeError, "ranges", lambda: cm.score_contacts(TOXD, TOXD_MATRIX, ranges=5))


def test_simulate_polymer(tmp_path: Path) -> None:
    refused(TypeError, "chains", lambda: cm.simulate_polymer(chains="100"), "got str")
    refused(ValueError, "monomer_bp", lambda: cm.simulate_polymer(10, monomer_bp=-1), "got -1")
    refused(ValueError, "seed", lambda: cm.simulate_polymer(10, seed=-1))
    refused(TypeError, "equilibration", lambda: cm.simulate_polymer(10, equilibration=[1]))
    refused(TypeError, "output", lambda: cm.simulate_polymer(10, output=5), "got int")
    refused(TypeError, "device", lambda: cm.simulate_polymer(10, device=5), "got int")
    refused(TypeError, "density", lambda: cm.simulate_polymer(10, density="0.2"), "got str")


def test_zoomify(tmp_path: Path) -> None:
    out = tmp_path / "out.mcool"
    refused(TypeError, "clr", lambda: cm.zoomify(None, out), "NoneType")
    refused(TypeError, "resolutions[1]", lambda: cm.zoomify(YEAST, out, [10_000, None]))
    refused(ValueError, "resolutions", lambda: cm.zoomify(YEAST, out, 0), "positive int")
    refused(TypeError, "balance", lambda: cm.zoomify(YEAST, out, balance="yes"))
    refused(TypeError, "out", lambda: cm.zoomify(YEAST, 5), "got int")
    assert not out.exists()
