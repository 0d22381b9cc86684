"""Writers: ``convert``, ``zoomify``, ``merge`` (as the command line's) and cooler's
``create_cooler``. Outputs are written under a temporary name and renamed when complete, so a
failed write never leaves a half-written map; an existing output is replaced, as cooler's
``mode="w"`` does, but never one of the inputs."""

from __future__ import annotations

import os
from typing import Any, Sequence

import numpy as np

from . import _checks as check
from . import _native
from ._file import _uri_of, _warn

_RESOLUTIONS = "None, a bin size (int), a list of bin sizes or a progression ('B', 'N', '4DN' ...)"


def _resolution_items(resolutions: Any) -> list[str] | None:
    """Resolutions as the library parses them: a list of bin sizes, or a progression text
    (``"B"``, ``"N"``, ``"5000N"``, ``"4DN"``), or a comma-separated list."""
    if resolutions is None:
        return None
    if isinstance(resolutions, str):
        return [item.strip() for item in resolutions.split(",")]
    if check.is_number(resolutions):
        return [str(check.integer("resolutions", resolutions, minimum=1))]
    if isinstance(resolutions, (bytes, dict)) or not hasattr(resolutions, "__iter__"):
        raise TypeError(f"resolutions: expected {_RESOLUTIONS}, got {type(resolutions).__name__}")
    items = []
    for k, r in enumerate(resolutions):
        if isinstance(r, str):
            items.append(r)
        elif check.is_number(r):
            items.append(str(check.integer(f"resolutions[{k}]", r, minimum=1)))
        else:
            raise TypeError(f"resolutions[{k}]: expected a bin size (int), got {type(r).__name__}")
    if not items:
        raise ValueError(f"resolutions: expected {_RESOLUTIONS}, got an empty list")
    return items


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
    uri, out = _uri_of(input, "input"), check.path("output", output)
    warnings = _native.convert(
        uri,
        out,
        _resolution_items(resolutions),
        check.text("assembly", assembly, none=True),
        check.texts("normalizations", normalizations, none=True),
        check.integer("compression_level", compression_level, minimum=0, maximum=9),
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
    path = check.path("out", out)
    items = _resolution_items(resolutions)
    balance = check.flag("balance", balance)
    assembly = check.text("assembly", assembly, none=True)
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
    kind = "a list of maps (paths, contactmap.File or cooler.Cooler)"
    if isinstance(inputs, (str, bytes, os.PathLike)) or not hasattr(inputs, "__iter__"):
        raise TypeError(f"inputs: expected {kind}, got {type(inputs).__name__}")
    uris = [_uri_of(i, f"inputs[{k}]") for k, i in enumerate(inputs)]
    if not uris:
        raise ValueError(f"inputs: expected {kind}, got an empty list")
    path = check.path("out", out)
    assembly = check.text("assembly", assembly, none=True)
    warnings = _native.merge(uris, path, _resolution_items(resolutions), assembly)
    _warn("merge", warnings)


def _pixel_columns(pixels: Any) -> dict[str, np.ndarray]:
    """``bin1_id bin2_id count`` of a DataFrame, a dict of arrays, or an iterable of those
    (chunks, as cooler takes them)."""
    kind = "a DataFrame or a dict with columns bin1_id bin2_id count, or an iterable of them"
    if hasattr(pixels, "keys"):
        chunks = [pixels]
    elif isinstance(pixels, (str, bytes)) or not hasattr(pixels, "__iter__"):
        raise TypeError(f"pixels: expected {kind}, got {type(pixels).__name__}")
    else:
        chunks = list(pixels)
    columns: dict[str, list[np.ndarray]] = {"bin1_id": [], "bin2_id": [], "count": []}
    for k, chunk in enumerate(chunks):
        where = "pixels" if chunk is pixels else f"pixels[{k}]"
        if not hasattr(chunk, "keys"):
            raise TypeError(f"{where}: expected {kind}, got {type(chunk).__name__}")
        missing = [name for name in columns if name not in chunk]
        if missing:
            raise ValueError(
                f"{where}: missing columns {missing}: expected the columns bin1_id bin2_id "
                f"count; it has {[str(c) for c in chunk.keys()]}"
            )
        for name in columns:
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
    if columns is not None and check.texts("columns", columns) != ["count"]:
        raise check.unsupported("columns", f"only ['count'] is supported, got {columns!r}")
    if metadata is not None:
        raise check.unsupported("metadata", "not supported (expected None)")
    if dtypes is not None and not hasattr(dtypes, "get"):
        raise TypeError(f"dtypes: expected a dict or None, got {type(dtypes).__name__}")
    assembly = check.text("assembly", assembly, none=True)
    check.flag("ordered", ordered)
    if not check.flag("symmetric_upper", symmetric_upper):
        raise check.unsupported("symmetric_upper", "False (square storage) is not supported")
    check.text("mode", mode, ["w"])
    path = check.path("cool_uri", cool_uri)
    if "::" in path:
        raise ValueError(
            f"cool_uri: {path}: a group inside a file is not supported; expected a path"
        )
    if not hasattr(bins, "keys"):
        raise TypeError(
            "bins: expected a DataFrame (or a dict) with columns chrom start end, got "
            f"{type(bins).__name__}"
        )
    missing = [name for name in ("chrom", "start", "end") if name not in bins]
    if missing:
        raise ValueError(
            f"bins: missing columns {missing}: expected the columns chrom start end "
            f"[weight ...]; it has {[str(c) for c in bins.keys()]}"
        )
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
    start = check.column_values("bins column 'start'", bins["start"], "int")
    end = check.column_values("bins column 'end'", bins["end"], "int")
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
