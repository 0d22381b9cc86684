"""Compartments: cooltools' ``eigs_cis``, ``eigs_trans``, ``digitize``, ``saddle`` and
``saddle_strength``."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from . import _checks as check
from . import _native
from ._file import (
    File,
    _expected_arrays,
    _file,
    _pandas,
    _view_regions,
    _warn,
    _weight_column,
)

if TYPE_CHECKING:  # pragma: no cover
    import pandas


def _eigvecs(f: File, vectors: Sequence[Any]) -> Any:
    """cooltools' eigvecs table: the bin table (chrom as text) with E1..EN over every bin."""
    eigvecs = f.bins()
    eigvecs["chrom"] = eigvecs["chrom"].astype(str)
    for k, vector in enumerate(vectors):
        eigvecs[f"E{k + 1}"] = np.asarray(vector, dtype=float)
    return eigvecs


def eigs_cis(
    clr: Any,
    phasing_track: Any = None,
    view_df: Any = None,
    n_eigs: int = 3,
    clr_weight_name: str = "weight",
    ignore_diags: int | None = None,
    clip_percentile: float = 99.9,
    sort_metric: str | None = None,
    map: Any = None,
) -> tuple[pandas.DataFrame, pandas.DataFrame]:
    """cooltools' ``eigs_cis``: the leading eigenvectors of each view region's observed /
    expected matrix (compartments). Returns ``(eigvals, eigvecs)``: ``chrom start end name
    eigval1..N`` per region, and the bin table (``chrom start end`` and its weight columns)
    with ``E1..EN`` (NaN outside the view). ``phasing_track``: a DataFrame of the map's bins
    whose fourth column is the track (GC content, gene density ...), or one value per bin: each
    vector's sign is turned to correlate positively with it; ``sort_metric`` (``"spearmanr"``,
    ``"pearsonr"``, ``"var_explained"``, ``"MAD_explained"``) reorders the vectors by it.
    ``ignore_diags`` defaults to the weight column's attribute, else 2; ``map`` is accepted
    for compatibility."""
    n_eigs = check.integer("n_eigs", n_eigs, minimum=1)
    ignore_diags = check.integer("ignore_diags", ignore_diags, minimum=0, none=True)
    clip_percentile = check.number("clip_percentile", clip_percentile, minimum=0, maximum=100)
    sort_metric = check.text("sort_metric", sort_metric, none=True)
    track = None if phasing_track is None else _track_values("phasing_track", phasing_track)
    pd = _pandas()
    f = _file(clr)
    regions, warnings = _native.eigs_cis(
        f._native,
        _view_regions(view_df),
        _weight_column(f, "clr_weight_name", clr_weight_name),
        track,
        n_eigs,
        ignore_diags,
        clip_percentile,
        sort_metric,
    )
    _warn("eigs_cis", warnings)
    eigvals = pd.DataFrame(
        {
            "chrom": [r[1] for r in regions],
            "start": np.array([r[2] for r in regions], dtype=np.int64),
            "end": np.array([r[3] for r in regions], dtype=np.int64),
            "name": [r[0] for r in regions],
        }
    )
    for k in range(n_eigs):
        eigvals[f"eigval{k + 1}"] = np.array([r[6][k] for r in regions], dtype=float)
    vectors = []
    for k in range(n_eigs):
        column = np.full(f.nbins(), np.nan)
        for r in regions:
            column[r[4] : r[5]] = r[7][k]
        vectors.append(column)
    return eigvals, _eigvecs(f, vectors)


def eigs_trans(
    clr: Any,
    phasing_track: Any = None,
    n_eigs: int = 3,
    partition: Any = None,
    clr_weight_name: str = "weight",
    sort_metric: str | None = None,
    perc_top: float = 99.95,
    perc_bottom: float = 1.0,
) -> tuple[pandas.DataFrame, pandas.DataFrame]:
    """cooltools' ``eigs_trans``: the leading eigenvectors of the genome-wide trans observed /
    expected matrix. Returns ``(eigvals, eigvecs)``: one row ``eigval1..N``, and the bin table
    with ``E1..EN``. ``phasing_track`` as in :func:`eigs_cis`; ``partition`` (other chromosome
    groupings) is not supported."""
    if partition is not None:
        raise check.unsupported(
            "partition", "not supported (expected None): the chromosomes are the partition"
        )
    n_eigs = check.integer("n_eigs", n_eigs, minimum=1)
    sort_metric = check.text("sort_metric", sort_metric, none=True)
    perc_top = check.number("perc_top", perc_top, minimum=0, maximum=100)
    perc_bottom = check.number("perc_bottom", perc_bottom, minimum=0, maximum=100)
    track = None if phasing_track is None else _track_values("phasing_track", phasing_track)
    pd = _pandas()
    f = _file(clr)
    weight_name = _weight_column(f, "clr_weight_name", clr_weight_name)
    values, vectors, warnings = _native.eigs_trans(
        f._native, weight_name, track, n_eigs, perc_top, perc_bottom, sort_metric
    )
    _warn("eigs_trans", warnings)
    eigvals = pd.DataFrame({f"eigval{k + 1}": [values[k]] for k in range(n_eigs)})
    return eigvals, _eigvecs(f, vectors)


_TRACK = "a DataFrame (chrom start end value), a Series or an array of numbers"


def _track_values(name: str, track: Any) -> list[float]:
    """A per-bin track (argument ``name``): a DataFrame of the bins whose fourth column is the
    value (cooltools' tracks), a Series, or an array."""
    if hasattr(track, "iloc") and track.ndim == 2:
        if track.shape[1] < 4:
            raise ValueError(
                f"{name}: expected {_TRACK}: a DataFrame track has its values in the fourth "
                f"column, this one has the columns {[str(c) for c in track.columns]}"
            )
        column = str(track.columns[3])
        values = check.column_values(f"{name} column {column!r}", track.iloc[:, 3], "float")
    elif track is None or isinstance(track, (str, bytes, dict)) or not hasattr(track, "__len__"):
        raise TypeError(f"{name}: expected {_TRACK}, got {type(track).__name__}")
    else:
        values = check.column_values(name, track, "float")
        if values.ndim != 1:
            raise ValueError(
                f"{name}: expected {_TRACK}: one value per bin, got shape {values.shape}"
            )
    return [float(v) for v in values]


def digitize(
    track: Any,
    n_bins: int,
    vrange: tuple[float, float] | None = None,
    qrange: tuple[float, float] | None = None,
    digitized_suffix: str = ".d",
) -> tuple[Any, np.ndarray]:
    """cooltools' ``digitize``: each bin's class of ``track`` (0 below the first edge,
    ``n_bins + 1`` above the last, -1 for NaN) and the ``n_bins + 1`` edges, from quantiles
    (``qrange``, default (0, 1)) or values (``vrange``). With a DataFrame track, returns it
    with the column ``<value column><digitized_suffix>`` added."""
    values = _track_values("track", track)
    n_bins = check.integer("n_bins", n_bins, minimum=1)
    vrange, qrange = _ranges(vrange, qrange)
    digitized_suffix = check.text("digitized_suffix", digitized_suffix)
    classes, edges = _native.digitize(values, n_bins, qrange, vrange)
    if hasattr(track, "iloc") and track.ndim == 2:
        out = track.copy()
        out[str(track.columns[3]) + digitized_suffix] = classes
        return out, edges
    return classes, edges


def _ranges(vrange: Any, qrange: Any) -> tuple[Any, Any]:
    """digitize's and saddle's ``vrange`` (values) and ``qrange`` (quantiles in 0..1): one of
    them or neither."""
    vrange = check.pair("vrange", vrange)
    qrange = check.pair("qrange", qrange, 0, 1)
    if vrange is not None and qrange is not None:
        raise ValueError("vrange and qrange: give one of them, not both")
    return vrange, qrange


def saddle(
    clr: Any,
    expected: Any,
    track: Any,
    contact_type: str = "cis",
    n_bins: int = 50,
    vrange: tuple[float, float] | None = None,
    qrange: tuple[float, float] | None = None,
    view_df: Any = None,
    clr_weight_name: str = "weight",
    expected_value_col: str = "balanced.avg",
    view_name_col: str = "name",
    min_diag: int = 3,
    max_diag: int = -1,
    trim_outliers: bool = False,
    verbose: bool = False,
    drop_track_na: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """cooltools' ``saddle``: the sums and counts of observed / expected between the classes of
    ``track`` (``n_bins`` classes plus the two outer ones: ``(n_bins + 2)^2`` arrays), cis
    (``expected`` from ``expected_cis``, diagonals ``min_diag..max_diag``) or trans
    (``expected`` from ``expected_trans``). ``trim_outliers`` leaves out the outer classes'
    rows and columns (``n_bins^2`` arrays), as cooltools does; ``drop_track_na`` is accepted for
    compatibility (NaN track values fall out either way, as in cooltools' results)."""
    contact_type = check.text("contact_type", contact_type, ["cis", "trans"])
    values = _track_values("track", track)
    n_bins = check.integer("n_bins", n_bins, minimum=1)
    vrange, qrange = _ranges(vrange, qrange)
    check.text("view_name_col", view_name_col)
    min_diag = check.integer("min_diag", min_diag, minimum=0)
    max_diag = check.integer("max_diag", max_diag, none=True)
    trim_outliers = check.flag("trim_outliers", trim_outliers)
    check.flag("verbose", verbose)
    check.flag("drop_track_na", drop_track_na)
    f = _file(clr)
    trans = contact_type == "trans"
    sums, counts, _edges, n = _native.saddle(
        f._native,
        values,
        _expected_arrays(f, expected, view_df, expected_value_col, trans),
        _weight_column(f, "clr_weight_name", clr_weight_name),
        _view_regions(view_df),
        trans,
        n_bins,
        None if vrange is not None else (qrange if qrange is not None else (0.0, 1.0)),
        vrange,
        min_diag,
        None if max_diag is None or max_diag < 0 else max_diag,
    )
    sums, counts = sums.reshape(n, n), counts.reshape(n, n)
    if trim_outliers:  # cooltools: the outer classes' rows and columns left out
        return sums[1:-1, 1:-1], counts[1:-1, 1:-1]
    return sums, counts


def saddle_strength(S: np.ndarray, C: np.ndarray) -> np.ndarray:
    """cooltools' ``saddle_strength``: for k = 1..n, (AA + BB) / (AB + BA) of the k extreme
    classes' corners of the saddle ``S / C`` (entry 0 is 0)."""
    S, C = _saddle_array("S", S), _saddle_array("C", C)
    if S.shape != C.shape:
        raise ValueError(f"S and C: expected arrays of one shape, got {S.shape} and {C.shape}")
    n = S.shape[0]
    return _native.saddle_strength(
        [float(v) for v in S.ravel()], [float(v) for v in C.ravel()], n
    )


def _saddle_array(name: str, value: Any) -> np.ndarray:
    """A saddle's sums or counts: a square 2-D array of numbers."""
    kind = "a square 2-D array of numbers"
    if value is None or isinstance(value, (str, bytes)) or not hasattr(value, "__len__"):
        raise TypeError(f"{name}: expected {kind}, got {type(value).__name__}")
    array = check.column_values(name, value, "float")
    if array.ndim != 2 or array.shape[0] != array.shape[1]:
        raise ValueError(f"{name}: expected {kind}, got shape {array.shape}")
    return array
