"""Proteins: a structure's residue distances and contacts, and CASP-style scores of contact
predictions against it (``contactmap contacts`` and ``contactmap score contacts``)."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, NamedTuple, Sequence

import numpy as np

from . import _checks as check
from . import _native
from ._file import _pandas, _warn

if TYPE_CHECKING:  # pragma: no cover
    import pandas


class Structure(NamedTuple):
    """A chain's observed residues as ``read_structure`` measured them."""

    chain: str
    """The chain's id."""
    numbers: np.ndarray
    """Residue numbers (author numbering, or positions on the ``fasta`` sequence, 1-based)."""
    distances: np.ndarray
    """Distances between the residues in Angstrom, ``n x n`` in the order of ``numbers``."""
    contacts: np.ndarray
    """Whether two residues are in contact (boolean ``n x n``; none on the diagonal)."""
    register: str | None
    """How the chain was placed on the ``fasta`` sequence (None without one)."""


def read_structure(
    path: str | os.PathLike[str],
    chain: str | None = None,
    atom: str = "cb",
    cutoff: float = 8.0,
    le: bool = False,
    fasta: str | os.PathLike[str] | None = None,
    register: str = "auto",
) -> Structure:
    """A chain of a PDB or mmCIF file (the first one when ``chain`` is None): its observed
    residues, their distances in Angstrom between the ``atom`` of each (``"cb"``: Cb, Ca for
    glycine, CASP's; ``"ca"``; ``"heavy"``: the closest heavy atoms), and the contacts
    ``d < cutoff`` (``d <= cutoff`` with ``le``). With ``fasta`` (a target sequence file) the
    residues are numbered by their place on it (``register``: ``"auto"``, ``"align"`` or
    ``"numbering"``)."""
    chain_id, numbers, distances, contacts, described = _native.read_structure(
        check.path("path", path),
        check.text("chain", chain, none=True),
        check.text("atom", atom),
        check.number("cutoff", cutoff, above=0),
        check.flag("le", le),
        check.path("fasta", fasta, none=True),
        check.text("register", register),
    )
    return Structure(chain_id, numbers, distances, contacts, described)


def score_contacts(
    structure: str | os.PathLike[str],
    prediction: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    chain: str | None = None,
    fasta: str | os.PathLike[str] | None = None,
    format: str | None = None,
    atom: str = "cb",
    cutoff: float = 8.0,
    le: bool = False,
    register: str = "auto",
    ranges: Sequence[str] = ("short", "medium", "long", "all"),
    top: Sequence[str] = ("L/10", "L/5", "L/2", "L"),
    min_sep: int | None = None,
    length: str | int | None = None,
    rounding: str = "floor",
    keep_unobserved: bool = False,
) -> pandas.DataFrame:
    """``contactmap score contacts``: the precision of contact predictions (files: CASP RR,
    CCMpred / PSICOV matrices, ``i j score`` tables, trRosetta ``.npz``, ``.npy``, EVfold,
    GREMLIN; ``format`` or detected) against a chain of ``structure``, CASP's way: for each
    separation range (``short`` 6-11, ``medium`` 12-23, ``long`` >= 24, ``all`` >= 6, ``A-B``,
    ``A+``; or ``min_sep``) and list size (``L/10``, ``L/5``, ``L/2``, ``L``, ``0.3L``, a
    count, ``NC``), the top pairs' ``tp precision recall f1 mcc xd``. One row per prediction x
    range x list. ``length``: what L is (``"sequence"``, ``"observed"`` or a number; default
    the sequence's length), ``rounding`` of L x fraction (``"floor"``, ``"half-up"``,
    ``"banker"``); pairs with an unobserved residue are dropped unless ``keep_unobserved``.
    Separations are in residues, ``max_sep`` is ``inf`` for an open range. With a sequence
    (``fasta``, or the prediction's own), ``df.attrs["register"]`` says per prediction file how
    the chain was placed on it."""
    args = (
        check.path("structure", structure),
        check.paths("prediction", prediction),
        check.text("chain", chain, none=True),
        check.path("fasta", fasta, none=True),
        check.text("format", format, none=True),
        check.text("atom", atom),
        check.number("cutoff", cutoff, above=0),
        check.flag("le", le),
        check.text("register", register),
        check.texts("ranges", ranges),
        check.texts("top", top),
        check.integer("min_sep", min_sep, minimum=0, none=True),
        _length(length),
        check.text("rounding", rounding),
        check.flag("keep_unobserved", keep_unobserved),
    )
    pd = _pandas()
    columns, warnings, registers = _native.score_contacts(*args)
    _warn("score_contacts", warnings)
    df = pd.DataFrame(dict(columns))
    df.attrs["register"] = dict(registers)
    return df


def _length(length: Any) -> str | None:
    """score_contacts' ``length``: ``"sequence"``, ``"observed"``, a positive int or None."""
    kind = "'sequence', 'observed', a positive int or None"
    if length is None:
        return None
    if isinstance(length, str):
        word = length.strip().lower()
        if word in ("sequence", "seq", "observed") or (word.isdigit() and int(word) > 0):
            return length
        raise ValueError(f"length: expected {kind}, got {length!r}")
    if not check.is_number(length):
        raise TypeError(f"length: expected {kind}, got {type(length).__name__}")
    return str(check.integer("length", length, minimum=1))


def contact_frequencies(
    trajectory: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    topology: str | os.PathLike[str],
    definition: str = "cb",
    cutoff: float = 8.0,
    stride: int = 1,
    periodic: bool = True,
    min_sep: int = 3,
) -> pandas.DataFrame:
    """``contactmap contacts --trajectory``: the residue contact frequencies of MD trajectories
    (DCD, XTC, multi-model PDB / mmCIF files, read one after the other) whose frames have the
    atoms of ``topology`` (a PDB or mmCIF file), as MDTraj's ``compute_contacts(traj, "all",
    scheme)`` measures them: ``definition`` ``"cb"`` (Cb, Ca for glycine: CASP's), ``"ca"``,
    ``"closest"``, ``"closest-heavy"``, ``"sidechain"``, ``"sidechain-heavy"``; a contact is a
    distance below ``cutoff`` Angstrom; pairs of residues with a CA atom, in the same chain, at
    least ``min_sep`` apart by index; every ``stride``-th frame; minimum-image distances in a
    periodic cell unless ``periodic`` is False.

    One row per pair, the columns of the command's table: ``chain residue1 residue2 name1
    name2 index1 index2 contact_frames frequency``; ``df.attrs["frames"]`` is the number of
    frames measured. ``score_contacts`` takes the table (written as TSV) as its truth through
    the command line's ``--frequencies``."""
    args = (
        check.paths("trajectory", trajectory),
        check.path("topology", topology),
        check.text("definition", definition),
        check.number("cutoff", cutoff, above=0),
        check.integer("stride", stride, minimum=1),
        check.flag("periodic", periodic),
        check.integer("min_sep", min_sep, minimum=0),
    )
    pd = _pandas()
    chain, residue1, residue2, name1, name2, index1, index2, counts, frames = (
        _native.contact_frequencies(*args)
    )
    df = pd.DataFrame(
        {
            "chain": chain,
            "residue1": residue1,
            "residue2": residue2,
            "name1": name1,
            "name2": name2,
            "index1": index1.astype(np.int64),
            "index2": index2.astype(np.int64),
            "contact_frames": counts.astype(np.int64),
            "frequency": counts / frames,
        }
    )
    df.attrs["frames"] = frames
    return df
