"""contactmap: contact maps from Python, with the answers of cooler, cooltools and hictkpy.

Open any map contactmap reads and fetch from it as hictkpy does; compute cooltools' tables with
cooltools' argument names::

    import contactmap as cm

    f = cm.File("data/yeast.10kb.cool")
    m = f.fetch("chrIV:0-500,000", normalization="weight").to_numpy()
    exp = cm.expected_cis(f, ignore_diags=2)
    ins = cm.insulation(f, window_bp=[50_000])

The work is done by the Rust library (the same functions as the ``contactmap`` command line),
with the GIL released; arrays come back without a copy. Coordinates are 0-based, half-open, in
base pairs; weights are multiplicative (cooler's convention).
"""

from __future__ import annotations

import json
import os
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from . import _native
from ._native import ContactmapError

if TYPE_CHECKING:  # pragma: no cover
    import pandas
    import scipy.sparse

__all__ = [
    "ContactmapError",
    "File",
    "MultiResFile",
    "PixelSelector",
    "balance",
    "digitize",
    "directionality",
    "eigs_cis",
    "eigs_trans",
    "expected_cis",
    "expected_trans",
    "insulation",
    "saddle",
    "saddle_strength",
]

__version__ = "0.1.0"


def _optional(module: str, package: str, needed_by: str) -> Any:
    """An optional dependency, or an ImportError that says what needs it and how to install it."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError(
            f"{needed_by}: install {package} (pip install {package}, "
            f"or pip install 'contactmap[{package}]')"
        ) from e


def _pandas() -> Any:
    return _optional("pandas", "pandas", "this function returns a pandas DataFrame")


def _scipy_sparse() -> Any:
    return _optional("scipy.sparse", "scipy", "to_coo() / to_csr() return scipy sparse matrices")


def _uri_of(obj: Any) -> str:
    """The URI of a path, a File, or a cooler.Cooler (its ``uri``: ``path::group``)."""
    if isinstance(obj, File):
        return obj.uri()
    if isinstance(obj, (str, os.PathLike)):
        return os.fspath(obj)
    uri = getattr(obj, "uri", None)
    if isinstance(uri, str):
        return uri
    raise TypeError(
        f"expected a path, a contactmap.File or a cooler.Cooler, got {type(obj).__name__}"
    )


def _file(obj: Any) -> File:
    return obj if isinstance(obj, File) else File(obj)


class File:
    """A contact map: ``.cool``, ``.mcool::/resolutions/R``, ``.hic`` (``::/resolutions/R``
    when it has several), HiCExplorer ``.h5``, or a text table; or a ``cooler.Cooler``.

    Names follow hictkpy (``chromosomes``, ``resolution``, ``fetch``, ``avail_normalizations``)
    and cooler (``bins``, ``attributes``).

    Raises ``FileNotFoundError`` for a missing file and ``ContactmapError`` (a ``ValueError``)
    for a file contactmap cannot read, with the command line's one-line message.
    """

    def __init__(self, uri: Any) -> None:
        self._native = _native.NativeFile(_uri_of(uri))

    def __repr__(self) -> str:
        return f"contactmap.File({self.uri()!r})"

    def uri(self) -> str:
        """The URI as opened."""
        return self._native.uri()

    def path(self) -> str:
        """The file's path (the URI without its group)."""
        return self.uri().split("::", 1)[0]

    def format(self) -> str:
        """The format and its version (``cool (format-version 3)``, ``hic v9`` ...)."""
        return self._native.format()

    def chromosomes(self) -> dict[str, int]:
        """Chromosome names and lengths in bp, in the file's order."""
        return dict(self._native.chromosomes())

    def resolution(self) -> int | None:
        """The bin size in bp (None for variable-size bins)."""
        return self._native.resolution()

    def nbins(self) -> int:
        """The number of bins."""
        return len(self._native.bin_columns()[0])

    def attributes(self) -> dict[str, Any]:
        """The file's attributes (cooler's ``info``, the .hic header's fields)."""
        return json.loads(self._native.attributes_json())

    def avail_normalizations(self) -> list[str]:
        """The weight columns / normalisation vectors the file has."""
        return list(self._native.weight_names())

    def weights(self, name: str = "weight") -> np.ndarray:
        """Weights ``name`` per bin, multiplicative (divisive files inverted); NaN masked."""
        return self._native.weights(name)

    def bins(self) -> pandas.DataFrame:
        """The bin table: ``chrom`` (categorical), ``start``, ``end`` (bp) and every weight
        column, as ``cooler.Cooler.bins()[:]`` gives it."""
        pd = _pandas()
        codes, start, end = self._native.bin_columns()
        names = [name for name, _ in self._native.chromosomes()]
        df = pd.DataFrame(
            {
                "chrom": pd.Categorical.from_codes(codes.astype(np.int32), categories=names),
                "start": start.astype(np.int64, copy=False),
                "end": end.astype(np.int64, copy=False),
            }
        )
        for name in self.avail_normalizations():
            df[name] = self._native.weights(name)
        return df

    def _bins_of(self, region: str | None) -> tuple[int, int]:
        if region is None:
            return (0, self.nbins())
        return self._native.region_bins(region)

    def fetch(
        self,
        range1: str | None = None,
        range2: str | None = None,
        normalization: str | None = None,
        query_type: str = "UCSC",
    ) -> PixelSelector:
        """The pixels of ``range1 x range2`` (``range2`` defaults to ``range1``, ``range1`` to
        the whole genome). Regions are UCSC strings (``chr2L:1,000,000-2,000,000``, or a
        chromosome name). ``normalization``: None / ``"NONE"`` for raw counts, or a weight
        column (``"weight"``, ``"KR"``, ``"VC"``, ``"SCALE"`` ...)."""
        if query_type != "UCSC":
            raise ContactmapError(f"query_type {query_type!r}: only 'UCSC' is supported")
        if normalization is not None and normalization.upper() == "NONE":
            normalization = None
        rows = self._bins_of(range1)
        cols = rows if range2 is None else self._bins_of(range2)
        return PixelSelector(self, rows, cols, normalization)


class PixelSelector:
    """A query of a :class:`File` (``File.fetch``); nothing is read until asked."""

    def __init__(
        self, file: File, rows: tuple[int, int], cols: tuple[int, int], normalization: str | None
    ) -> None:
        self._file, self._rows, self._cols, self._norm = file, rows, cols, normalization

    def __repr__(self) -> str:
        return (
            f"PixelSelector(bins {self._rows[0]}..{self._rows[1]} x "
            f"{self._cols[0]}..{self._cols[1]}, normalization={self._norm!r})"
        )

    def _pixels(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]:
        return self._file._native.fetch_pixels(self._rows, self._cols, self._norm)

    def to_numpy(self) -> np.ndarray:
        """The dense rectangle of the full symmetric matrix (float64), as
        ``cooler.Cooler.matrix(balance=...).fetch`` returns it: with a normalisation,
        masked bins' rows and columns are NaN."""
        return self._file._native.fetch_dense(self._rows, self._cols, self._norm)

    def to_df(self, join: bool = False) -> pandas.DataFrame:
        """The stored (upper-triangle) pixels of the query: ``bin1_id bin2_id count`` (and
        ``balanced`` with a normalisation); with ``join``, ``chrom1 start1 end1 chrom2 start2
        end2`` instead of the bin ids."""
        pd = _pandas()
        bin1, bin2, count, balanced = self._pixels()
        columns: dict[str, Any] = {}
        if join:
            codes, start, end = self._file._native.bin_columns()
            names = [name for name, _ in self._file._native.chromosomes()]
            for k, ids in (("1", bin1), ("2", bin2)):
                columns["chrom" + k] = pd.Categorical.from_codes(
                    codes[ids].astype(np.int32), categories=names
                )
                columns["start" + k] = start[ids].astype(np.int64, copy=False)
                columns["end" + k] = end[ids].astype(np.int64, copy=False)
        else:
            columns["bin1_id"] = bin1
            columns["bin2_id"] = bin2
        columns["count"] = count
        if balanced is not None:
            columns["balanced"] = balanced
        # the columns are the library's arrays, not copies (one block per column)
        return pd.DataFrame(columns, copy=False)

    def _sparse(self) -> scipy.sparse.coo_matrix:
        sparse = _scipy_sparse()
        bin1, bin2, count, balanced = self._pixels()
        values = count if balanced is None else balanced
        shape = (self._rows[1] - self._rows[0], self._cols[1] - self._cols[0])
        return sparse.coo_matrix(
            (values, (bin1 - self._rows[0], bin2 - self._cols[0])), shape=shape
        )

    def to_coo(self) -> scipy.sparse.coo_matrix:
        """The stored pixels as a scipy COO matrix over the query's rectangle."""
        return self._sparse()

    def to_csr(self) -> scipy.sparse.csr_matrix:
        """The stored pixels as a scipy CSR matrix over the query's rectangle."""
        return self._sparse().tocsr()

    def nnz(self) -> int:
        """The number of stored pixels in the query."""
        return int(len(self._pixels()[0]))

    def sum(self) -> float:
        """The sum of the query's stored values (balanced with a normalisation, NaN left
        out)."""
        _, _, count, balanced = self._pixels()
        values = count if balanced is None else balanced
        return float(np.nansum(values))


class MultiResFile:
    """A multi-resolution file (``.mcool``, ``.hic``): ``resolutions()`` and ``f[res]``."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self._path = os.fspath(path)
        self._resolutions = list(_native.resolutions(self._path))
        if not self._resolutions:
            raise ContactmapError(f"{self._path}: not a multi-resolution file (open it with File)")

    def __repr__(self) -> str:
        return f"contactmap.MultiResFile({self._path!r})"

    def path(self) -> str:
        """The file's path."""
        return self._path

    def resolutions(self) -> list[int]:
        """The resolutions (bin sizes in bp), ascending."""
        return list(self._resolutions)

    def __getitem__(self, resolution: int) -> File:
        if resolution not in self._resolutions:
            raise ContactmapError(
                f"{self._path}: no resolution {resolution} (it has {self._resolutions})"
            )
        return File(f"{self._path}::/resolutions/{resolution}")


def _view_regions(view_df: Any) -> list[tuple[str, int, int, str | None]] | None:
    """A view as (chrom, start, end, name): a DataFrame with ``chrom start end [name]``
    (bioframe's view), or a list of such tuples."""
    if view_df is None:
        return None
    if hasattr(view_df, "itertuples"):
        has_name = "name" in view_df.columns
        return [
            (
                str(row.chrom),
                int(row.start),
                int(row.end),
                str(row.name) if has_name else None,
            )
            for row in view_df.itertuples(index=False)
        ]
    regions = []
    for region in view_df:
        chrom, start, end = region[0], int(region[1]), int(region[2])
        name = str(region[3]) if len(region) > 3 and region[3] is not None else None
        regions.append((str(chrom), start, end, name))
    return regions


def expected_cis(
    clr: Any,
    view_df: Any = None,
    intra_only: bool = True,
    smooth: bool = True,
    aggregate_smoothed: bool = True,
    smooth_sigma: float = 0.1,
    clr_weight_name: str | None = "weight",
    ignore_diags: int = 2,
    chunksize: int | None = None,
    nproc: int | None = None,
) -> pandas.DataFrame:
    """cooltools' ``expected_cis``: the average contact per diagonal of each view region,
    with its columns (``region1 region2 dist dist_bp contact_frequency n_total n_valid
    count.sum balanced.sum count.avg balanced.avg balanced.avg.smoothed
    balanced.avg.smoothed.agg``). ``clr_weight_name=None`` for raw counts. Distances
    ``dist_bp`` in bp; ``chunksize`` and ``nproc`` are accepted for compatibility (contactmap
    streams and uses every core)."""
    if not intra_only:
        raise ContactmapError(
            "intra_only=False (between the regions of one chromosome) is not supported"
        )
    _pandas()  # the install hint before the work
    f = _file(clr)
    region1, region2, columns = _native.expected_cis(
        f._native,
        _view_regions(view_df),
        clr_weight_name,
        ignore_diags,
        smooth,
        aggregate_smoothed,
        smooth_sigma,
    )
    return _columns_frame(region1, region2, columns)


def _columns_frame(region1: list[str], region2: list[str], columns: list[Any]) -> Any:
    pd = _pandas()
    data: dict[str, Any] = {"region1": region1, "region2": region2}
    for name, values in columns:
        data[name] = values.astype(np.int64) if values.dtype == np.uint64 else values
    return pd.DataFrame(data, copy=False)


def expected_trans(
    clr: Any,
    view_df: Any = None,
    clr_weight_name: str | None = "weight",
    chunksize: int | None = None,
    nproc: int | None = None,
) -> pandas.DataFrame:
    """cooltools' ``expected_trans``: per pair of view regions on different chromosomes,
    ``region1 region2 n_valid count.sum balanced.sum count.avg balanced.avg`` (the balanced
    columns with ``clr_weight_name``; None for raw counts)."""
    f = _file(clr)
    region1, region2, columns = _native.expected_trans(
        f._native, _view_regions(view_df), clr_weight_name
    )
    return _columns_frame(region1, region2, columns)


def directionality(
    clr: Any,
    window_bp: int = 100000,
    balance: str | None = "weight",
    min_dist_bad_bin: int = 2,
    ignore_diags: int | None = None,
    view_df: Any = None,
) -> pandas.DataFrame:
    """cooltools' ``directionality`` (Dixon et al.'s directionality index): ``chrom start end
    bad_bin_masked directionality_ratio_W directionality_index_W`` for a window of
    ``window_bp`` bp upstream and downstream; ``balance=None`` for raw counts."""
    pd = _pandas()
    f = _file(clr)
    bins, masked, ratio, index = _native.directionality(
        f._native,
        int(window_bp),
        _view_regions(view_df),
        balance,
        2 if ignore_diags is None else ignore_diags,
        min_dist_bad_bin,
    )
    codes, start, end = f._native.bin_columns()
    names = [name for name, _ in f._native.chromosomes()]
    df = pd.DataFrame(
        {
            "chrom": np.asarray(names, dtype=object)[codes[bins]],
            "start": start[bins].astype(np.int64),
            "end": end[bins].astype(np.int64),
            "bad_bin_masked": masked,
            f"directionality_ratio_{int(window_bp)}": ratio,
            f"directionality_index_{int(window_bp)}": index,
        },
        copy=False,
    )
    return df


def insulation(
    clr: Any,
    window_bp: int | Sequence[int],
    view_df: Any = None,
    ignore_diags: int | None = None,
    clr_weight_name: str | None = "weight",
    min_frac_valid_pixels: float = 0.66,
    min_dist_bad_bin: int = 0,
    threshold: str | float = "Li",
    append_raw_scores: bool = False,
    chunksize: int | None = None,
    nproc: int | None = None,
    verbose: bool = False,
) -> pandas.DataFrame:
    """cooltools' ``insulation``: the diamond insulation score per bin for each window (bp),
    with boundary strengths and calls (threshold ``"Li"``, ``"Otsu"`` or a number). Columns:
    ``chrom start end region is_bad_bin log2_insulation_score_W n_valid_pixels_W ...
    boundary_strength_W ... is_boundary_W``."""
    pd = _pandas()
    f = _file(clr)
    windows = (
        [int(window_bp)]
        if isinstance(window_bp, (int, np.integer))
        else [int(w) for w in window_bp]
    )
    bins, region, bad, region_names, columns = _native.insulation(
        f._native,
        windows,
        _view_regions(view_df),
        clr_weight_name,
        2 if ignore_diags is None else ignore_diags,
        min_frac_valid_pixels,
        min_dist_bad_bin,
        str(threshold),
        append_raw_scores,
    )
    codes, start, end = f._native.bin_columns()
    names = [name for name, _ in f._native.chromosomes()]
    data: dict[str, Any] = {
        "chrom": pd.Categorical.from_codes(codes[bins].astype(np.int32), categories=names),
        "start": start[bins].astype(np.int64),
        "end": end[bins].astype(np.int64),
        "region": np.asarray(region_names, dtype=object)[region],
        "is_bad_bin": bad,
    }
    for name, values in columns:
        data[name] = values
    df = pd.DataFrame(data, copy=False)
    df["chrom"] = df["chrom"].astype(str)
    return df


def _warn(function: str, lines: list[str]) -> None:
    """The library's warnings (one line each) as Python warnings from the caller."""
    import warnings

    for line in lines:
        warnings.warn(f"contactmap {function}: {line}", stacklevel=3)


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
    pd = _pandas()
    f = _file(clr)
    track = None if phasing_track is None else _track_values(phasing_track)
    regions, warnings = _native.eigs_cis(
        f._native,
        _view_regions(view_df),
        clr_weight_name,
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
        raise ContactmapError("partition is not supported: the chromosomes are the partition")
    pd = _pandas()
    f = _file(clr)
    track = None if phasing_track is None else _track_values(phasing_track)
    values, vectors, warnings = _native.eigs_trans(
        f._native, clr_weight_name, track, n_eigs, perc_top, perc_bottom, sort_metric
    )
    _warn("eigs_trans", warnings)
    eigvals = pd.DataFrame({f"eigval{k + 1}": [values[k]] for k in range(n_eigs)})
    return eigvals, _eigvecs(f, vectors)


def _track_values(track: Any) -> list[float]:
    """A per-bin track: a DataFrame of the bins whose fourth column is the value (cooltools'
    tracks), a Series, or an array."""
    values = track.iloc[:, 3] if hasattr(track, "iloc") and track.ndim == 2 else track
    return [float(v) for v in np.asarray(values, dtype=float)]


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
    classes, edges = _native.digitize(_track_values(track), n_bins, qrange, vrange)
    if hasattr(track, "iloc") and track.ndim == 2:
        out = track.copy()
        out[str(track.columns[3]) + digitized_suffix] = classes
        return out, edges
    return classes, edges


def _expected_arrays(
    f: File, expected: Any, view_df: Any, value_col: str, trans: bool
) -> list[list[float]]:
    """The expected DataFrame as the library takes it: per view region, its values by diagonal
    (cis), or per two regions (trans, ``[earlier][later]``)."""
    regions = _view_regions(view_df)
    if regions is None:
        names = [name for name, _ in f._native.chromosomes()]
        sizes = dict(f._native.chromosomes())
        regions = [(name, 0, sizes[name], name) for name in names]
    names = [r[3] if r[3] is not None else f"{r[0]}:{r[1]}-{r[2]}" for r in regions]
    if trans:
        index = {name: k for k, name in enumerate(names)}
        table = [[float("nan")] * len(names) for _ in names]
        for a, b, v in zip(expected["region1"], expected["region2"], expected[value_col]):
            if a in index and b in index:
                i, j = sorted((index[a], index[b]))
                table[i][j] = float(v)
        return table
    out = []
    for name, (chrom, start, end, _) in zip(names, regions):
        first, last = f._native.region_bins(f"{chrom}:{start}-{end}")
        values = np.full(last - first, np.nan)
        rows = expected[expected["region1"] == name]
        dist = rows["dist"].to_numpy()
        ok = dist < len(values)
        values[dist[ok]] = rows[value_col].to_numpy()[ok]
        out.append([float(v) for v in values])
    return out


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
    (``expected`` from ``expected_trans``). ``trim_outliers`` and ``drop_track_na`` are not
    supported (the outer classes are kept, NaN track values fall out)."""
    if contact_type not in ("cis", "trans"):
        raise ContactmapError(f"contact_type {contact_type!r}: expected 'cis' or 'trans'")
    if trim_outliers:
        raise ContactmapError("trim_outliers=True is not supported")
    f = _file(clr)
    trans = contact_type == "trans"
    sums, counts, _edges, n = _native.saddle(
        f._native,
        _track_values(track),
        _expected_arrays(f, expected, view_df, expected_value_col, trans),
        clr_weight_name,
        _view_regions(view_df),
        trans,
        n_bins,
        None if vrange is not None else (qrange if qrange is not None else (0.0, 1.0)),
        vrange,
        min_diag,
        None if max_diag is None or max_diag < 0 else max_diag,
    )
    return sums.reshape(n, n), counts.reshape(n, n)


def saddle_strength(S: np.ndarray, C: np.ndarray) -> np.ndarray:
    """cooltools' ``saddle_strength``: for k = 1..n, (AA + BB) / (AB + BA) of the k extreme
    classes' corners of the saddle ``S / C`` (entry 0 is 0)."""
    S, C = np.asarray(S, dtype=float), np.asarray(C, dtype=float)
    n = S.shape[0]
    return _native.saddle_strength(
        [float(v) for v in S.ravel()], [float(v) for v in C.ravel()], n
    )


def balance(
    clr: Any,
    method: str = "ice",
    cis_only: bool = False,
    ignore_diags: int | None = None,
    mad_max: float | None = None,
    min_nnz: int | None = None,
    min_count: float | None = None,
    tol: float | None = None,
    max_iters: int | None = None,
    rescale_marginals: bool | None = None,
    store: bool = False,
) -> tuple[np.ndarray, dict[str, Any]]:
    """Balance a map: ``method`` ``"ice"`` (cooler's ``balance_cooler``, its defaults),
    ``"kr"``, ``"vc"``, ``"vc_sqrt"`` or ``"scale"`` (Juicer's, their defaults). Returns the
    multiplicative weights per bin (NaN masked) and a summary (``converged``, ``scale``,
    ``var``, ``n_iterations``, ``n_masked``). ``store=True`` is not supported yet: use
    ``contactmap balance FILE --store``."""
    if store:
        raise ContactmapError(
            "store=True is not supported from Python yet: run `contactmap balance FILE --store`"
        )
    f = _file(clr)
    return _native.balance(
        f._native,
        method,
        cis_only,
        ignore_diags,
        mad_max,
        min_nnz,
        min_count,
        tol,
        max_iters,
        rescale_marginals,
    )

