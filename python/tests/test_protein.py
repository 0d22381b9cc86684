"""Structures and contact scores from Python against the reference numbers of
data/protein/README.md (CASP-style "method P", ConEVA, the ConKit documentation) and against the
command line on the same input."""

from __future__ import annotations

import io
import subprocess

import numpy as np
import pandas as pd
import pytest

import contactmap as cm

from helpers import DATA, binary

PROTEIN = DATA / "protein"


def p(name: str) -> str:
    return str(PROTEIN / name)


@pytest.mark.parametrize(
    "structure, counts",
    [
        ("toxd/toxd.pdb.gz", (15, 43, 57, 115)),
        ("1atzA/1atzA.pdb.gz", (24, 27, 69, 120)),
        ("1aapA/1aapA.pdb.gz", (13, 44, 57, 114)),
        ("1a8o/1A8O.pdb.gz", (16, 26, 35, 77)),
        ("1a8o/1A8O.cif.gz", (16, 26, 35, 77)),
    ],
)
def test_true_contacts_per_range_are_the_references(structure: str, counts: tuple) -> None:
    s = cm.read_structure(p(structure))
    n = len(s.numbers)
    assert s.distances.shape == s.contacts.shape == (n, n)
    assert np.array_equal(s.distances, s.distances.T) and not s.contacts.diagonal().any()
    i, j = np.triu_indices(n, 1)
    separation = np.abs(s.numbers[j] - s.numbers[i])
    contact = s.contacts[i, j]
    got = tuple(
        int((contact & (separation >= lo) & (separation <= hi)).sum())
        for lo, hi in ((6, 11), (12, 23), (24, 10**9), (6, 10**9))
    )
    assert got == counts


def test_distances_equal_the_command_line() -> None:
    s = cm.read_structure(p("toxd/toxd.pdb.gz"))
    out = subprocess.run(
        [binary(), "contacts", p("toxd/toxd.pdb.gz"), "--matrix"],
        check=True,
        capture_output=True,
    ).stdout
    table = pd.read_csv(io.BytesIO(out), sep="\t", index_col=0)
    assert list(table.index) == list(s.numbers)
    np.testing.assert_allclose(table.to_numpy(), s.distances, atol=5e-4, rtol=0)


def test_method_p_precisions_are_the_references() -> None:
    # CASP style: L = the FASTA's length, k = floor(L f), long range
    cases = {
        ("toxd/toxd.pdb.gz", "toxd/toxd.mat.gz", "toxd/toxd.fasta"): [(5, 5), (9, 11), (17, 29), (22, 59)],
        ("1atzA/1atzA.pdb.gz", "1atzA/1atzA.apc.mat.gz", "1atzA/1atzA.fasta"): [
            (6, 7),
            (12, 15),
            (21, 37),
            (30, 75),
        ],
        ("1aapA/1aapA.pdb.gz", "1aapA/1aapA.rr.gz", None): [(4, 5), (9, 11), (13, 28), (17, 56)],
    }
    for (structure, prediction, fasta), want in cases.items():
        scores = cm.score_contacts(
            p(structure), p(prediction), fasta=None if fasta is None else p(fasta), ranges=["long"]
        )
        assert list(zip(scores["tp"], scores["n_scored"])) == want, prediction
    # how the chain was placed on the sequence, per prediction
    assert "1-56->1-56" in scores.attrs["register"][p("1aapA/1aapA.rr.gz")]


def test_coneva_and_conkit_conventions() -> None:
    coneva = cm.score_contacts(
        p("1aapA/1aapA.pdb.gz"), p("1aapA/1aapA.rr.gz"), ranges=["long"], length="observed",
        rounding="half-up",
    )
    np.testing.assert_allclose(
        np.round(coneva["precision"].to_numpy() * 100, 2), [83.33, 81.82, 46.43, 30.36]
    )
    conkit = cm.score_contacts(
        p("toxd/toxd.pdb.gz"), p("toxd/toxd.mat.gz"), fasta=p("toxd/toxd.fasta"), le=True, min_sep=5,
        top=["0.5L", "L", "1.5L"],
    )
    assert list(zip(conkit["tp"], conkit["n_scored"])) == [(24, 29), (35, 59), (38, 88)]


def test_scores_equal_the_command_line() -> None:
    args = [p("1atzA/1atzA.apc.mat.gz"), p("1atzA/1atzA.noapc.mat.gz")]
    ours = cm.score_contacts(p("1atzA/1atzA.pdb.gz"), args, fasta=p("1atzA/1atzA.fasta"))
    out = subprocess.run(
        [binary(), "score", "contacts", "--tsv", "--structure", p("1atzA/1atzA.pdb.gz"),
         "--fasta", p("1atzA/1atzA.fasta"), *args],
        check=True,
        capture_output=True,
    ).stdout
    cli = pd.read_csv(io.BytesIO(out), sep="\t")
    assert list(ours.columns) == list(cli.columns) and len(ours) == len(cli) == 32
    for name in cli.columns:
        if cli[name].dtype.kind == "f":
            np.testing.assert_allclose(ours[name], cli[name], rtol=1e-12, err_msg=name)
        else:
            assert [str(v) for v in ours[name]] == [str(v) for v in cli[name]], name


def test_protein_errors_name_the_file() -> None:
    with pytest.raises(FileNotFoundError, match="missing.pdb"):
        cm.read_structure(p("missing.pdb"))
    with pytest.raises(cm.ContactmapError, match="atom 'cz'"):
        cm.read_structure(p("toxd/toxd.pdb.gz"), atom="cz")
    with pytest.raises(cm.ContactmapError, match="chain"):
        cm.read_structure(p("toxd/toxd.pdb.gz"), chain="Q")
    with pytest.raises(cm.ContactmapError, match="toxd.fasta"):
        cm.score_contacts(p("toxd/toxd.pdb.gz"), p("toxd/toxd.fasta"), format="rr")


def _mdtraj_reference(name: str) -> tuple[int, int, dict]:
    """MDTraj's pairs, frames and frames in contact (data/reference/mdtraj, made by
    scripts/md_contacts_reference.py)."""
    import gzip

    with gzip.open(DATA / "reference" / "mdtraj" / f"{name}.tsv.gz", "rt") as handle:
        head = handle.readline().split("\t")
        handle.readline()
        contacts = {}
        for line in handle:
            i, j, n = (int(x) for x in line.split("\t"))
            contacts[(i, j)] = n
    return int(head[1]), int(head[3]), contacts


@pytest.mark.parametrize(
    "name, trajectory, scheme, cutoff",
    [
        ("cobrotoxin", "md/cobrotoxin.dcd", "cb", 8.0),
        ("cobrotoxin", "md/cobrotoxin.dcd", "closest-heavy", 4.5),
        ("adk", "md/adk.xtc", "ca", 8.0),
        ("adk", "md/adk.xtc", "sidechain", 4.5),
    ],
)
def test_contact_frequencies_are_mdtrajs(name: str, trajectory: str, scheme: str, cutoff: float) -> None:
    df = cm.contact_frequencies(
        str(DATA / trajectory), str(DATA / "md" / f"{name}.pdb.gz"), scheme, cutoff
    )
    pairs, frames, contacts = _mdtraj_reference(f"{name}.{scheme}")
    assert len(df) == pairs and df.attrs["frames"] == frames
    expected = [contacts.get((i, j), 0) for i, j in zip(df.index1, df.index2)]
    assert df.contact_frames.tolist() == expected
    assert np.array_equal(df.frequency, df.contact_frames / frames)
    assert (df.contact_frames > 0).sum() > 50


def test_contact_frequencies_are_the_command_lines_table(tmp_path) -> None:
    topology = str(DATA / "md" / "cobrotoxin.pdb.gz")
    trajectory = str(DATA / "md" / "cobrotoxin.dcd")
    out = tmp_path / "freq.tsv"
    subprocess.run(
        [binary(), "contacts", "--trajectory", trajectory, "--topology", topology,
         "--stride", "2", "-o", str(out)],
        check=True, capture_output=True,
    )
    table = pd.read_csv(out, sep="\t", dtype={"chain": str, "residue1": str, "residue2": str},
                        keep_default_na=False)
    df = cm.contact_frequencies([trajectory], topology, stride=2)
    assert df.attrs["frames"] == 2
    pd.testing.assert_frame_equal(df, table, check_dtype=False, check_exact=True)
    with pytest.raises(cm.ContactmapError, match="definition 'cx'"):
        cm.contact_frequencies(trajectory, topology, definition="cx")
    with pytest.raises(cm.ContactmapError, match="atoms, the topology has"):
        cm.contact_frequencies(trajectory, str(DATA / "md" / "adk.pdb.gz"))
