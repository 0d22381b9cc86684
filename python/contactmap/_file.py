"""Opening maps and fetching from them: ``File`` (hictkpy's names), ``PixelSelector``,
``MultiResFile``; and the helpers every function of the package shares."""

from __future__ import annotations

import json
import os
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _checks as check
from . import _native
from ._native import ContactmapError

if TYPE_CHECKING:  # pragma: no cover
    import pandas
    import scipy.sparse


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


def _uri_of(obj: Any, name: str = "clr") -> str:
    """The URI of a path, a File, or a cooler.Cooler (its ``uri``: ``path::group``); ``name``
    is the argument's, for the error."""
    if isinstance(obj, File):
        return obj.uri()
    if isinstance(obj, (str, os.PathLike)):
        return check.path(name, obj)
    uri = getattr(obj, "uri", None)
    if isinstance(uri, str):
        return uri
    raise TypeError(
        f"{name}: expected a path, a contactmap.File or a cooler.Cooler, got {type(obj).__name__}"
    )


def _file(obj: Any, name: str = "clr") -> File:
    return obj if isinstance(obj, File) else File(_uri_of(obj, name))


def _weight_name(f: File, name: str, value: Any, none: bool = True) -> str | None:
    """A weight column of ``f`` (argument ``name``), or None (raw counts) when ``none``."""
    value = check.text(name, value, none=none)
    if value is None:
        return None
    available = f.avail_normalizations()
    if value not in available:
        has = ", ".join(repr(n) for n in available) if available else "none: balance it first"
        raise ValueError(
            f"{name}: no weight column {value!r} in {f.uri()}: expected one of "
            f"avail_normalizations() ({has}){' or None for raw counts' if none else ''}"
        )
    return str(value)


def _weight_column(f: File, name: str, value: Any) -> str:
    """A weight column of ``f`` (argument ``name``), required."""
    return str(_weight_name(f, name, value, none=False))


class File:
    """A contact map: ``.cool``, ``.mcool::/resolutions/R``, ``.hic`` (``::/resolutions/R``
    when it has several), HiCExplorer ``.h5``, or a text table; or a ``cooler.Cooler``.

    Names follow hictkpy (``chromosomes``, ``resolution``, ``fetch``, ``avail_normalizations``)
    and cooler (``bins``, ``attributes``).

    ``resolution`` chooses the level of an ``.mcool`` or ``.hic`` named without one (hictkpy's
    ``File(path, resolution)``, the same as ``::/resolutions/R``); for a map of one resolution it
    must be its bin size.

    Raises ``FileNotFoundError`` for a missing file, ``ContactmapError`` (a ``ValueError``) for a
    bad argument (a resolution the file does not have) and ``FormatError`` for a file contactmap
    cannot read, with the command line's one-line message.
    """

    def __init__(self, uri: Any, resolution: int | None = None) -> None:
        resolution = check.integer("resolution", resolution, minimum=1, none=True)
        self._native = _native.NativeFile(_uri_of(uri, "uri"), resolution)

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
        return self._native.weights(_weight_column(self, "name", name))

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

    def _bins_of(self, name: str, region: Any) -> tuple[int, int]:
        region = check.text(name, region, none=True)
        if region is None:
            return (0, self.nbins())
        try:
            return self._native.region_bins(region)
        except ContactmapError as e:
            raise ContactmapError(f"{name}: {e}") from None

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
        check.text("query_type", query_type, choices=["UCSC"])
        normalization = check.text("normalization", normalization, none=True)
        if normalization is not None and normalization.upper() == "NONE":
            normalization = None
        normalization = _weight_name(self, "normalization", normalization)
        rows = self._bins_of("range1", range1)
        cols = rows if range2 is None else self._bins_of("range2", range2)
        return PixelSelector._checked(self, rows, cols, normalization)


class PixelSelector:
    """A query of a :class:`File` (``File.fetch``); nothing is read until asked."""

    def __init__(
        self, file: File, rows: tuple[int, int], cols: tuple[int, int], normalization: str | None
    ) -> None:
        if not isinstance(file, File):
            raise TypeError(f"file: expected a contactmap.File, got {type(file).__name__}")
        n = file.nbins()
        bounds = []
        for name, value in (("rows", rows), ("cols", cols)):
            first, end = check.pair(name, value, 0, n) or (0, n)
            if not (float(first).is_integer() and float(end).is_integer()):
                raise ValueError(f"{name}: expected a pair of bin ids (first, end), got {value!r}")
            bounds.append((int(first), int(end)))
        normalization = _weight_name(file, "normalization", normalization)
        self._file, self._rows, self._cols, self._norm = file, bounds[0], bounds[1], normalization

    @classmethod
    def _checked(
        cls, file: File, rows: tuple[int, int], cols: tuple[int, int], normalization: str | None
    ) -> PixelSelector:
        """A query whose arguments ``File.fetch`` checked already."""
        selector = cls.__new__(cls)
        selector._file, selector._rows, selector._cols = file, rows, cols
        selector._norm = normalization
        return selector

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
        join = check.flag("join", join)
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
        self._path = check.path("path", path)
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
        resolution = check.integer("resolution", resolution, minimum=1)
        if resolution not in self._resolutions:
            raise ValueError(
                f"resolution: {self._path} has no resolution {resolution}: expected one of "
                f"{self._resolutions}"
            )
        return File(f"{self._path}::/resolutions/{resolution}")


_VIEW = (
    "None, a DataFrame with columns chrom start end [name] or a list of (chrom, start, end"
    "[, name])"
)


def _view_regions(view_df: Any) -> list[tuple[str, int, int, str | None]] | None:
    """A view as (chrom, start, end, name): a DataFrame with ``chrom start end [name]``
    (bioframe's view), or a list of such tuples."""
    if view_df is None:
        return None
    if hasattr(view_df, "itertuples"):
        check.frame("view_df", view_df, ["chrom", "start", "end"], " [name]")
        has_name = "name" in view_df.columns
        starts = check.column_values("view_df column start", view_df["start"], "int")
        ends = check.column_values("view_df column end", view_df["end"], "int")
        names = view_df["name"] if has_name else [None] * len(view_df)
        return [
            (str(chrom), int(start), int(end), None if name is None else str(name))
            for chrom, start, end, name in zip(view_df["chrom"], starts, ends, names)
        ]
    if isinstance(view_df, (str, bytes)) or not hasattr(view_df, "__iter__"):
        raise TypeError(f"view_df: expected {_VIEW}, got {type(view_df).__name__}")
    regions = []
    for k, region in enumerate(view_df):
        if isinstance(region, (str, bytes)) or not hasattr(region, "__len__"):
            raise TypeError(
                f"view_df[{k}]: expected a tuple (chrom, start, end[, name]), got "
                f"{type(region).__name__}"
            )
        if len(region) not in (3, 4):
            raise ValueError(
                f"view_df[{k}]: expected a tuple (chrom, start, end[, name]), got {len(region)} "
                "values"
            )
        chrom = check.text(f"view_df[{k}] chrom", region[0])
        start = check.integer(f"view_df[{k}] start", region[1], minimum=0)
        end = check.integer(f"view_df[{k}] end", region[2], minimum=0)
        name = str(region[3]) if len(region) > 3 and region[3] is not None else None
        regions.append((chrom, start, end, name))
    return regions


def _expected_frame(name: str, expected: Any, value_col: Any, trans: bool) -> Any:
    """Check an expected table (argument ``name``; ``expected_cis``'s or, with ``trans``,
    ``expected_trans``'s) and its value column (argument ``expected_value_col``)."""
    value_col = check.text("expected_value_col", value_col)
    columns = ["region1", "region2" if trans else "dist", value_col]
    source = "expected_trans" if trans else "expected_cis"
    note = f" (a table of {source}; expected_value_col={value_col!r})"
    return check.frame(name, expected, columns, note)


def _expected_arrays(
    f: File, expected: Any, view_df: Any, value_col: str, trans: bool, arg: str = "expected"
) -> list[list[float]]:
    """The expected DataFrame (argument ``arg``) as the library takes it: per view region,
    its values by diagonal (cis), or per two regions (trans, ``[earlier][later]``)."""
    _expected_frame(arg, expected, value_col, trans)
    given = check.column_values(f"{arg} column {value_col!r}", expected[value_col], "float")
    regions = _view_regions(view_df)
    if regions is None:
        names = [name for name, _ in f._native.chromosomes()]
        sizes = dict(f._native.chromosomes())
        regions = [(name, 0, sizes[name], name) for name in names]
    names = [r[3] if r[3] is not None else f"{r[0]}:{r[1]}-{r[2]}" for r in regions]
    if trans:
        index = {name: k for k, name in enumerate(names)}
        table = [[float("nan")] * len(names) for _ in names]
        for a, b, v in zip(expected["region1"], expected["region2"], given):
            if a in index and b in index:
                i, j = sorted((index[a], index[b]))
                table[i][j] = float(v)
        return table
    diagonals = check.column_values(f"{arg} column 'dist'", expected["dist"], "int")
    if (diagonals < 0).any():
        raise ValueError(f"{arg} column 'dist': expected non-negative ints (diagonals)")
    out = []
    for name, (chrom, start, end, _) in zip(names, regions):
        first, last = f._native.region_bins(f"{chrom}:{start}-{end}")
        values = np.full(last - first, np.nan)
        rows = (expected["region1"] == name).to_numpy()
        dist = diagonals[rows]
        ok = dist < len(values)
        values[dist[ok]] = given[rows][ok]
        out.append([float(v) for v in values])
    return out


def _warn(function: str, lines: list[str]) -> None:
    """The library's warnings (one line each) as Python warnings from the caller."""
    import warnings

    for line in lines:
        warnings.warn(f"contactmap {function}: {line}", stacklevel=3)
