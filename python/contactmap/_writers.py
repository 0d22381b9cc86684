"""Writers: ``convert``, ``zoomify``, ``merge`` (as the command line's) and cooler's
``create_cooler``. Outputs are written under a temporary name and renamed when complete, so a
failed write never leaves a half-written map; an existing output is replaced, as cooler's
``mode="w"`` does, but never one of the inputs."""

from __future__ import annotations

import os
from typing import Any, Sequence

import numpy as np

from . import _native
from ._file import _uri_of, _warn
from ._native import ContactmapError


def _resolution_items(resolutions: Any) -> list[str] | None:
    """Resolutions as the library parses them: a list of bin sizes, or a progression text
    (``"B"``, ``"N"``, ``"5000N"``, ``"4DN"``), or a comma-separated list."""
    if resolutions is None:
        return None
    if isinstance(resolutions, str):
        return [item.strip() for item in resolutions.split(",")]
    if isinstance(resolutions, (int, np.integer)):
        return [str(int(resolutions))]
    return [str(int(r)) if isinstance(r, (int, np.integer)) else str(r) for r in resolutions]


def convert(
    input: Any,
    output: str | os.PathLike[str],
    resolutions: Any = None,
    assembly: str | None = None,
    normalizations: Sequence[str] | None = None,
    compression_level: int = 6,
) -> None:
    """``contactmap convert``: the map ``input`` (any URI contactmap reads, a File or a
    ``cooler.Cooler``) written to ``output``, in the format of its extension: ``.cool``,
    ``.mcool`` (``resolutions``: bin sizes in bp or a progression, default the map's own) or
    ``.hic`` (with ``normalizations``, default Juicer's VC, VC_SQRT, KR, SCALE, and zlib
    ``compression_level`` 0-9). Weight columns are copied to a .cool / .mcool."""
    uri, out = _uri_of(input), os.fspath(output)
    warnings = _native.convert(
        uri,
        out,
        _resolution_items(resolutions),
        assembly,
        None if normalizations is None else [str(n) for n in normalizations],
        compression_level,
    )
    _warn("convert", warnings)


def zoomify(
    clr: Any,
    out: str | os.PathLike[str] | None = None,
    resolutions: Any = "B",
    balance: bool = False,
    assembly: str | None = None,
) -> str:
    """``cooler zoomify``: the map summed into coarser bins, every level in one ``.mcool``
    (or a ``.hic``), default ``out`` the input's name with ``.mcool``. ``resolutions``: bin
    sizes in bp, or a progression (``"B"``: the map's bin size doubled up to the longest
    chromosome; ``"N"``: steps 1-2-5; ``"5000N"``, ``"4DN"``). ``balance``: ICE on every level
    with cooler's defaults, stored as ``weight`` (a .hic gets an ICE vector). Returns the
    output's path."""
    uri = _uri_of(clr)
    if out is None:
        base = os.path.splitext(uri.split("::", 1)[0])[0]
        out = base + ".mcool"
    path = os.fspath(out)
    items = _resolution_items(resolutions)
    _levels, warnings = _native.zoomify(uri, path, items or ["B"], balance, assembly)
    _warn("zoomify", warnings)
    return path


def merge(
    inputs: Sequence[Any],
    out: str | os.PathLike[str],
    resolutions: Any = None,
    assembly: str | None = None,
) -> None:
    """``cooler merge``: the pixel-wise sum of maps with the same bins, written to ``out``
    (``.cool``, or ``.mcool`` / ``.hic`` at ``resolutions``). Weights are not carried (balance
    the sum)."""
    uris = [_uri_of(i) for i in inputs]
    path = os.fspath(out)
    warnings = _native.merge(uris, path, _resolution_items(resolutions), assembly)
    _warn("merge", warnings)


def _pixel_columns(pixels: Any) -> dict[str, np.ndarray]:
    """``bin1_id bin2_id count`` of a DataFrame, a dict of arrays, or an iterable of those
    (chunks, as cooler takes them)."""
    if hasattr(pixels, "keys"):
        chunks = [pixels]
    else:
        chunks = list(pixels)
    columns: dict[str, list[np.ndarray]] = {"bin1_id": [], "bin2_id": [], "count": []}
    for chunk in chunks:
        for name in columns:
            if name not in chunk:
                raise ContactmapError(f"pixels: no column {name!r} (bin1_id bin2_id count)")
            columns[name].append(np.asarray(chunk[name]))
    return {
        name: np.concatenate(parts) if parts else np.zeros(0)
        for name, parts in columns.items()
    }


def create_cooler(
    cool_uri: str | os.PathLike[str],
    bins: Any,
    pixels: Any,
    columns: Sequence[str] | None = None,
    dtypes: dict[str, Any] | None = None,
    metadata: Any = None,
    assembly: str | None = None,
    ordered: bool = False,
    symmetric_upper: bool = True,
    mode: str = "w",
) -> None:
    """cooler's ``create_cooler``: a ``.cool`` from a bin table (a DataFrame ``chrom start end``
    in bp, its other float columns stored as weights, e.g. ``weight``) and pixels
    (``bin1_id bin2_id count``: a DataFrame, a dict of arrays or an iterable of such chunks).
    Chromosome lengths are the largest bin end of each chromosome, in their order of
    appearance (or the categories' order). Counts are stored as integers when they are
    integers (``dtypes={"count": float}`` stores reals); repeated pixels are summed,
    lower-triangle pixels mirrored, explicit zeros kept. Other ``columns``, ``metadata``,
    ``symmetric_upper=False`` and ``mode="a"`` are not supported; ``ordered`` is accepted for
    compatibility."""
    if columns is not None and list(columns) != ["count"]:
        raise ContactmapError("columns: only 'count' is supported")
    if metadata is not None:
        raise ContactmapError("metadata is not supported")
    if not symmetric_upper:
        raise ContactmapError("symmetric_upper=False (square storage) is not supported")
    if mode != "w":
        raise ContactmapError(f"mode {mode!r}: only 'w' (a new file) is supported")
    path = os.fspath(cool_uri)
    if "::" in path:
        raise ContactmapError(f"{path}: a group inside a file is not supported; give a path")
    for name in ("chrom", "start", "end"):
        if name not in bins:
            raise ContactmapError(f"bins: no column {name!r} (chrom start end)")
    chrom = bins["chrom"]
    if hasattr(chrom, "cat"):  # a categorical Series: its categories' order
        names = [str(c) for c in chrom.cat.categories]
        codes = chrom.cat.codes.to_numpy().astype(np.int64)
    else:
        text = np.asarray(chrom).astype(str)
        names_array, first, codes = np.unique(text, return_index=True, return_inverse=True)
        order = np.argsort(first)  # the order of appearance
        rank = np.empty_like(order)
        rank[order] = np.arange(len(order))
        names = [str(n) for n in names_array[order]]
        codes = rank[codes].astype(np.int64)
    start = np.asarray(bins["start"], dtype=np.int64)
    end = np.asarray(bins["end"], dtype=np.int64)
    lengths = np.zeros(len(names), dtype=np.int64)
    np.maximum.at(lengths, codes, end)
    weights = [
        (str(name), [float(v) for v in np.asarray(bins[name], dtype=float)])
        for name in (bins.columns if hasattr(bins, "columns") else bins.keys())
        if name not in ("chrom", "start", "end") and np.asarray(bins[name]).dtype.kind == "f"
    ]
    px = _pixel_columns(pixels)
    count_dtype = np.dtype((dtypes or {}).get("count", px["count"].dtype))
    _native.create_cooler(
        path,
        [(n, int(length)) for n, length in zip(names, lengths)],
        codes,
        start,
        end,
        weights,
        px["bin1_id"].astype(np.int64, copy=False),
        px["bin2_id"].astype(np.int64, copy=False),
        px["count"].astype(np.float64, copy=False),
        count_dtype.kind in "iub",
        assembly,
    )
