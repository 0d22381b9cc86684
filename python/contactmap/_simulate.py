"""The polymer simulator (``contactmap simulate polymer``) from Python: the map, the
conformations and the truth of a run, as arrays and DataFrames."""

from __future__ import annotations

import io
import os
from typing import TYPE_CHECKING, Any, NamedTuple, Sequence

import numpy as np

from . import _checks as check
from . import _native
from ._file import _pandas, _warn

if TYPE_CHECKING:  # pragma: no cover
    import numpy.typing as npt
    import pandas


class Simulation(NamedTuple):
    """What ``simulate_polymer`` returns."""

    bins: pandas.DataFrame
    """The map's bins: ``chrom start end`` (bp; one chromosome ``chr1..chrK`` per chain)."""
    pixels: pandas.DataFrame
    """The map: ``bin1_id bin2_id count`` (contacts summed over every sample, upper triangle)."""
    conformations: np.ndarray | None
    """With ``keep_conformations``: the bead positions, ``(replicas x samples, beads, 3)``
    (replica after replica; bond length 1)."""
    radius_of_gyration: np.ndarray
    """Per sample and chain, the radius of gyration (bond lengths)."""
    truth_boundaries: pandas.DataFrame
    """The bins holding a boundary element (``chrom start end``)."""
    truth_domains: pandas.DataFrame
    """The segments between consecutive boundary elements (``chrom start end``)."""
    truth_loops: pandas.DataFrame | None
    """With ``extrusion``: the bin pairs of boundary elements a LEF held bridged, and the
    fraction and number of samples that held them."""
    truth_compartments: pandas.DataFrame | None
    """With ``types``: per bin its majority type and the fraction of type A."""
    relaxation: str
    """How far the chains had relaxed at the first and last samples."""


def _bed(text: str, names: list[str]) -> Any:
    pd = _pandas()
    if not text.strip():
        return pd.DataFrame({name: [] for name in names})
    return pd.read_csv(io.StringIO(text), sep="\t", header=None, names=names)


def simulate_polymer(
    chains: int | Sequence[int] = 1000,
    monomer_bp: int = 1000,
    monomers_per_bin: int = 1,
    bonds: str = "harmonic",
    bond_wiggle: float = 0.1,
    stiffness: float = 0.0,
    repulsion: str = "polynomial",
    repulsion_energy: float | None = None,
    repulsion_radius: float | None = None,
    exclude_neighbours: int = 1,
    ideal: bool = False,
    saw: bool = False,
    types: str | None = None,
    attraction: float = 0.3,
    attraction_radius: float = 1.5,
    density: float | None = None,
    confinement: str | None = None,
    dt: float | None = None,
    replicas: int = 8,
    equilibration: int | str = 20000,
    sample_every: int | str = 2000,
    samples: int = 50,
    contact_radius: float = 1.5,
    seed: int = 0,
    extrusion: bool = False,
    ctcf: str | None = None,
    processivity: float = 100.0,
    separation: float = 200.0,
    capture: float = 0.9,
    release: float = 0.005,
    steps_per_move: int = 50,
    keep_conformations: bool = False,
    device: str = "auto",
    threads: int | None = None,
    output: str | os.PathLike[str] | None = None,
) -> Simulation:
    """``contactmap simulate polymer``: an ensemble of bead-spring chains under Brownian
    dynamics (units: bond length 1, kT 1), sampled into a contact map with its truth. The
    parameters are the command line's (``contactmap simulate polymer --help`` explains each):
    ``chains`` (beads per chain), ``monomer_bp`` (bp per bead), ``monomers_per_bin``; physics
    (``bonds`` harmonic / fene, ``repulsion`` polynomial / wca / none, ``ideal``, ``saw``,
    ``types`` such as ``"A200B200"`` with ``attraction`` kT, ``density`` with ``confinement``
    sphere / box, ``dt``); the ensemble (``replicas``, ``equilibration`` and ``sample_every``
    in steps, ``"auto"`` or Rouse times ``"2R"``, ``samples``, ``contact_radius``, ``seed``);
    loop extrusion (``extrusion``, ``ctcf`` positions ``"500+,1000-"`` or a BED path,
    ``processivity`` and ``separation`` in beads, ``capture``, ``release``,
    ``steps_per_move``). ``device``: ``"auto"``, ``"cpu"`` (every core, or ``threads``) or
    ``"gpu"``; the same seed gives the same map on any number of threads. With ``output``
    the map is also written there as a .cool (as the command line writes it). The arguments'
    types and signs are checked here; their physics (a density above close packing ...) by the
    library, whose errors (``ContactmapError``) name the command line's options."""
    options: dict[str, Any] = dict(
        chains=check.integers("chains", chains, minimum=1),
        monomer_bp=check.integer("monomer_bp", monomer_bp, minimum=1),
        monomers_per_bin=check.integer("monomers_per_bin", monomers_per_bin, minimum=1),
        bonds=check.text("bonds", bonds),
        bond_wiggle=check.number("bond_wiggle", bond_wiggle),
        stiffness=check.number("stiffness", stiffness, minimum=0),
        repulsion=check.text("repulsion", repulsion),
        repulsion_energy=check.number("repulsion_energy", repulsion_energy, above=0, none=True),
        repulsion_radius=check.number("repulsion_radius", repulsion_radius, above=0, none=True),
        exclude_neighbours=check.integer("exclude_neighbours", exclude_neighbours, minimum=0),
        ideal=check.flag("ideal", ideal),
        saw=check.flag("saw", saw),
        types=check.text("types", types, none=True),
        attraction=check.number("attraction", attraction),
        attraction_radius=check.number("attraction_radius", attraction_radius),
        density=check.number("density", density, none=True),
        confinement=check.text("confinement", confinement, none=True),
        dt=check.number("dt", dt, above=0, none=True),
        replicas=check.integer("replicas", replicas, minimum=1),
        equilibration=_steps("equilibration", equilibration, 0),
        sample_every=_steps("sample_every", sample_every, 1),
        samples=check.integer("samples", samples, minimum=1),
        contact_radius=check.number("contact_radius", contact_radius, above=0),
        seed=check.integer("seed", seed, minimum=0, maximum=2**64 - 1),
        extrusion=check.flag("extrusion", extrusion),
        ctcf=None if ctcf is None else _ctcf(ctcf),
        processivity=check.number("processivity", processivity),
        separation=check.number("separation", separation),
        capture=check.number("capture", capture),
        release=check.number("release", release),
        steps_per_move=check.integer("steps_per_move", steps_per_move, minimum=1),
        keep_conformations=check.flag("keep_conformations", keep_conformations),
    )
    device = check.text("device", device)
    threads = check.integer("threads", threads, minimum=1, none=True)
    out = check.path("output", output, none=True)
    pd = _pandas()
    chroms, (codes, start, end), (bin1, bin2, count), conformations, radii, truths, notes = (
        _native.simulate_polymer(options, device, threads, out)
    )
    names = [name for name, _ in chroms]
    bins = pd.DataFrame(
        {
            "chrom": np.asarray(names, dtype=object)[codes],
            "start": start.astype(np.int64),
            "end": end.astype(np.int64),
        }
    )
    pixels = pd.DataFrame({"bin1_id": bin1, "bin2_id": bin2, "count": count}, copy=False)
    boundaries, domains, loops, compartments = truths
    note, warning, _backend = notes
    if warning is not None:
        _warn("simulate_polymer", [warning])
    return Simulation(
        bins=bins,
        pixels=pixels,
        conformations=conformations,
        radius_of_gyration=radii,
        truth_boundaries=_bed(boundaries, ["chrom", "start", "end"]),
        truth_domains=_bed(domains, ["chrom", "start", "end"]),
        truth_loops=None if loops is None else pd.read_csv(io.StringIO(loops), sep="\t"),
        truth_compartments=None
        if compartments is None
        else _bed(compartments, ["chrom", "start", "end", "type", "fraction_A"]),
        relaxation=note,
    )


def _steps(name: str, value: Any, minimum: int) -> str:
    """simulate_polymer's ``equilibration`` / ``sample_every``: steps (an int), ``"auto"``,
    or Rouse times (``"2R"``); the text's value is the library's check."""
    if isinstance(value, str):
        return value
    if not check.is_number(value):
        raise TypeError(
            f"{name}: expected an int, 'auto' or Rouse times ('2R'), got "
            f"{type(value).__name__}"
        )
    return str(check.integer(name, value, minimum=minimum))


def _ctcf(value: Any) -> str:
    """simulate_polymer's ``ctcf``: positions (``"500+,1000-"``) or a BED file's path."""
    if isinstance(value, os.PathLike):
        return check.path("ctcf", value)
    return check.text("ctcf", value)


class PolymerMap(NamedTuple):
    """What ``polymer_map`` returns (the map ``contactmap polymer-map`` writes)."""

    pixels: pandas.DataFrame
    """``bin1_id bin2_id count``: the upper triangle (``bin1_id <= bin2_id``), non-zero, sorted;
    a contact within a bin counted once."""
    chain_bins: list[int]
    """The bins of each chain, in order."""
    n_conformations: int
    """Conformations counted."""
    n_beads: int
    """Beads per conformation."""

    def dense(self, polychrom: bool = False) -> npt.NDArray[np.int64]:
        """The symmetric ``n_bins x n_bins`` matrix of counts. ``polychrom=True``: as polychrom's
        ``binnedContactMap`` / ``monomerResolutionContactMap`` return it, ``triangle +
        triangle.T``, whose diagonal is twice the contacts within a bin."""
        polychrom = check.flag("polychrom", polychrom)
        n_bins = sum(self.chain_bins)
        bin1 = self.pixels.bin1_id.to_numpy()
        bin2 = self.pixels.bin2_id.to_numpy()
        count = self.pixels["count"].to_numpy()
        matrix = np.zeros((n_bins, n_bins), dtype=np.int64)
        matrix[bin1, bin2] = count
        matrix[bin2, bin1] = count
        if polychrom:
            matrix[np.diag_indices(n_bins)] *= 2
        return matrix


def polymer_map(
    trajectory: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    contact_radius: float,
    monomers_per_bin: int = 1,
    chains: Sequence[int] | None = None,
) -> PolymerMap:
    """``contactmap polymer-map``: the contact map of the conformations of ``trajectory``
    (polychrom folders, blocks files or ``file::block`` URIs, conformations tables, XYZ, DCD /
    XTC / multi-model PDB), counted on every core as polychrom's ``binnedContactMap`` counts it:
    beads at most ``contact_radius`` apart are in contact; each chain (``chains``: their bead
    counts, default one chain of every bead) is cut into bins of ``monomers_per_bin`` beads from
    its start; each contact adds one to its pair of bins, summed over the conformations.
    ``monomers_per_bin=1`` is ``monomerResolutionContactMap``. ``.dense(polychrom=True)`` is the
    matrix polychrom returns."""
    args = (
        check.paths("trajectory", trajectory),
        check.number("contact_radius", contact_radius, above=0),
        check.integer("monomers_per_bin", monomers_per_bin, minimum=1),
        None if chains is None else check.integers("chains", chains, minimum=1),
    )
    pd = _pandas()
    (bin1, bin2, count), chain_bins, n_conformations, n_beads = _native.polymer_map(*args)
    return PolymerMap(
        pd.DataFrame({"bin1_id": bin1, "bin2_id": bin2, "count": count}),
        list(chain_bins),
        n_conformations,
        n_beads,
    )


class PolymerStats(NamedTuple):
    """What ``polymer_stats`` returns (the tables of ``contactmap polymer-stats``)."""

    scaling: pandas.DataFrame
    """P(s): ``s_mid contact_probability`` (polychrom's ``contact_scaling``)."""
    r2: pandas.DataFrame
    """``s r2 rg2``: ``R2_scaling`` and ``Rg2_scaling`` at the separations."""
    rg2: pandas.DataFrame
    """``conformation rg2``: each conformation's ``Rg2``, in the order read."""


def polymer_stats(
    trajectory: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    contact_radius: float = 1.1,
) -> PolymerStats:
    """``contactmap polymer-stats``: the polymer statistics of the conformations of
    ``trajectory`` (polychrom folders, blocks files or ``file::block`` URIs, conformations
    tables, XYZ, DCD / XTC / multi-model PDB), each one chain, as polychrom's
    ``polymer_analyses`` computes them and averaged over the conformations: P(s) (contacts at
    most ``contact_radius`` apart, over separations ``generate_bins(N)``), ``<R^2(s)>``,
    ``<Rg^2(s)>``, and each conformation's ``Rg^2``."""
    files = check.paths("trajectory", trajectory)
    contact_radius = check.number("contact_radius", contact_radius, above=0)
    pd = _pandas()
    (mids, probability), (s, r2, rg2_of_s), (labels, rg2) = _native.polymer_stats(
        files, contact_radius
    )
    return PolymerStats(
        pd.DataFrame({"s_mid": mids, "contact_probability": probability}),
        pd.DataFrame({"s": s.astype(np.int64), "r2": r2, "rg2": rg2_of_s}),
        pd.DataFrame({"conformation": labels, "rg2": rg2}),
    )
