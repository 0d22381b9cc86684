"""The polymer simulator from Python: the command line's files for the same options and seed,
the radii of gyration recomputed from the returned conformations, one thread or many."""

from __future__ import annotations

import subprocess
from pathlib import Path

import cooler
import numpy as np
import pandas as pd
import pytest

import contactmap as cm

from helpers import binary

# the small runs are sampled before the chains relax, on purpose (speed): the warning says so
pytestmark = pytest.mark.filterwarnings("ignore:.*sampled before they relaxed")

SMALL = dict(
    chains=[60, 40],
    replicas=2,
    samples=4,
    equilibration=400,
    sample_every=100,
    density=0.2,
    seed=5,
    extrusion=True,
    ctcf="10+,30-,70+,90-",
    processivity=20,
    separation=20,
    monomers_per_bin=2,
)


def cli_flags(options: dict) -> list[str]:
    flags = []
    for key, value in options.items():
        flag = "--" + key.replace("_", "-")
        if value is True:
            flags.append(flag)
        elif isinstance(value, list):
            flags += [flag, ",".join(str(v) for v in value)]
        else:
            flags += [flag, str(value)]
    return flags


def test_simulation_equals_the_command_line(tmp_path: Path) -> None:
    out = tmp_path / "py.cool"
    sim = cm.simulate_polymer(**SMALL, device="cpu", keep_conformations=True, output=out)
    cli = tmp_path / "cli.cool"
    truth = {name: tmp_path / f"{name}.tsv" for name in ("boundaries", "domains", "loops")}
    subprocess.run(
        [binary(), "simulate", "polymer", "-o", str(cli), "--device", "cpu", *cli_flags(SMALL),
         "--truth-boundaries", str(truth["boundaries"]), "--truth-domains", str(truth["domains"]),
         "--truth-loops", str(truth["loops"])],
        check=True,
        capture_output=True,
    )
    theirs = cooler.Cooler(str(cli))
    pd.testing.assert_frame_equal(
        sim.pixels, theirs.pixels()[:].astype({"count": np.int64}), check_dtype=False
    )
    pd.testing.assert_frame_equal(cooler.Cooler(str(out)).pixels()[:], theirs.pixels()[:])
    bins = theirs.bins()[:]
    assert list(sim.bins["chrom"]) == list(bins["chrom"].astype(str))
    assert list(sim.bins["end"]) == list(bins["end"])
    for name, table in (
        ("boundaries", sim.truth_boundaries),
        ("domains", sim.truth_domains),
    ):
        cli_table = pd.read_csv(truth[name], sep="\t", header=None).iloc[:, :3]
        assert table.to_numpy().tolist() == cli_table.to_numpy().tolist(), name
    assert sim.truth_loops is not None
    pd.testing.assert_frame_equal(sim.truth_loops, pd.read_csv(truth["loops"], sep="\t"))
    # 2 replicas x 4 samples of 100 beads; the radii of gyration are those of the positions
    assert sim.conformations is not None and sim.conformations.shape == (8, 100, 3)
    assert sim.radius_of_gyration.shape == (8, 2)
    for k, conformation in enumerate(sim.conformations):
        for chain, beads in enumerate((slice(0, 60), slice(60, 100))):
            x = conformation[beads]
            rg = np.sqrt(((x - x.mean(axis=0)) ** 2).sum(axis=1).mean())
            assert abs(rg - sim.radius_of_gyration[k, chain]) < 1e-9 * rg
    assert "relaxed" in sim.relaxation or "s*" in sim.relaxation


def test_the_seed_fixes_the_map_on_any_number_of_threads() -> None:
    small = dict(chains=50, replicas=3, samples=3, equilibration=200, sample_every=50, seed=9)
    one = cm.simulate_polymer(**small, device="cpu", threads=1)
    many = cm.simulate_polymer(**small, device="cpu")
    pd.testing.assert_frame_equal(one.pixels, many.pixels)
    other = cm.simulate_polymer(**{**small, "seed": 10}, device="cpu")
    assert not one.pixels.equals(other.pixels)
    assert one.conformations is None and one.truth_loops is None


def test_bad_parameters_are_errors() -> None:
    with pytest.raises(cm.ContactmapError, match="density"):
        cm.simulate_polymer(chains=10, density=-1, device="cpu")
    with pytest.raises(cm.ContactmapError, match="bonds 'spring'"):
        cm.simulate_polymer(chains=10, bonds="spring")
    with pytest.raises(ValueError, match="threads: expected a positive int"):
        cm.simulate_polymer(chains=10, threads=0)


def test_polymer_map_is_polychroms(tmp_path: Path) -> None:
    """Count for count the maps of polychrom's own binnedContactMap (two chains, 4 beads a bin)
    and monomerResolutionContactMap (data/reference/polychrom), and the command line's .cool."""
    import gzip

    from helpers import DATA

    traj = str(DATA / "polychrom" / "traj")
    reference = DATA / "reference" / "polychrom"
    binned = cm.polymer_map(traj, contact_radius=1.6, monomers_per_bin=4, chains=[90, 60])
    with gzip.open(reference / "binned_4_chains90-60_cutoff1.6.tsv.gz") as f:
        want = np.loadtxt(f)
    assert binned.chain_bins == [23, 15]
    assert (binned.n_conformations, binned.n_beads) == (7, 150)
    assert np.array_equal(binned.dense(polychrom=True), want)
    assert np.array_equal(np.diag(binned.dense()) * 2, np.diag(want))
    monomer = cm.polymer_map([traj], contact_radius=1.6)
    with gzip.open(reference / "monomer_cutoff1.6.tsv.gz") as f:
        want = np.loadtxt(f)
    assert np.array_equal(monomer.dense(polychrom=True), want)
    out = tmp_path / "map.cool"
    subprocess.run(
        [binary(), "polymer-map", traj, "--contact-radius", "1.6", "--monomers-per-bin", "4",
         "--chains", "90,60", "-o", str(out)],
        check=True, capture_output=True,
    )
    pixels = cooler.Cooler(str(out)).pixels()[:]
    pd.testing.assert_frame_equal(binned.pixels, pixels, check_dtype=False, check_exact=True)
    with pytest.raises(ValueError, match="monomers_per_bin: expected a positive int"):
        cm.polymer_map(traj, contact_radius=1.6, monomers_per_bin=0)
    with pytest.raises(cm.ContactmapError, match="chains"):
        cm.polymer_map(traj, contact_radius=1.6, chains=[100, 100])


def test_polymer_stats_are_polychroms(tmp_path: Path) -> None:
    """P(s) exactly, R^2(s), Rg^2(s) and Rg^2 to polychrom's float error against the tables of
    polychrom's own functions (data/reference/polychrom), and the command line's tables."""
    from helpers import DATA

    stats = cm.polymer_stats(str(DATA / "polychrom" / "traj"), contact_radius=1.6)
    reference = DATA / "reference" / "polychrom"
    scaling = pd.read_csv(reference / "stats.scaling.tsv", sep="\t")
    assert np.array_equal(stats.scaling.s_mid, scaling.s_mid)
    assert np.array_equal(stats.scaling.contact_probability, scaling.contact_probability)
    r2 = pd.read_csv(reference / "stats.r2.tsv", sep="\t")
    assert np.array_equal(stats.r2.s, r2.s)
    assert np.allclose(stats.r2.r2, r2.r2, rtol=1e-12, atol=0)
    assert np.allclose(stats.r2.rg2, r2.rg2, rtol=1e-12, atol=0)
    rg2 = pd.read_csv(reference / "stats.rg2.tsv", sep="\t")
    # the first file's float32 positions: polychrom sums them in float32
    assert np.allclose(stats.rg2.rg2, rg2.rg2, rtol=1e-7, atol=0)
    prefix = tmp_path / "s"
    subprocess.run(
        [binary(), "polymer-stats", str(DATA / "polychrom" / "traj"), "--contact-radius",
         "1.6", "-o", str(prefix)],
        check=True, capture_output=True,
    )
    for name, table in [("scaling", stats.scaling), ("r2", stats.r2), ("rg2", stats.rg2)]:
        ours = pd.read_csv(f"{prefix}.{name}.tsv", sep="\t")
        pd.testing.assert_frame_equal(table, ours, check_dtype=False, check_exact=True)
    with pytest.raises(ValueError, match="contact_radius: expected a positive number"):
        cm.polymer_stats(str(DATA / "polychrom" / "traj"), contact_radius=-1)
