"""Loops and pileups: cooltools' ``dots``, HiCCUPS' merge of dots across resolutions and
coolpuppy's ``pileup``."""

from __future__ import annotations

import io
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np

from . import _checks as check
from . import _native
from ._file import (
    File,
    _expected_arrays,
    _file,
    _pandas,
    _view_regions,
    _weight_column,
    _weight_name,
)

if TYPE_CHECKING:  # pragma: no cover
    import pandas



def _bin_coordinates(f: File, prefix: str, ids: np.ndarray) -> dict[str, Any]:
    """``chrom{prefix} start{prefix} end{prefix}`` of bins ``ids``."""
    codes, start, end = f._native.bin_columns()
    names = np.asarray([name for name, _ in f._native.chromosomes()], dtype=object)
    return {
        "chrom" + prefix: names[codes[ids]],
        "start" + prefix: start[ids].astype(np.int64),
        "end" + prefix: end[ids].astype(np.int64),
    }


def dots(
    clr: Any,
    expected: Any,
    expected_value_col: str = "balanced.avg",
    clr_weight_name: str = "weight",
    view_df: Any = None,
    kernels: Any = None,
    max_loci_separation: int = 10_000_000,
    max_nans_tolerated: int = 1,
    n_lambda_bins: int = 40,
    lambda_bin_fdr: float = 0.1,
    clustering_radius: int | None = 20_000,
    cluster_filtering: bool | None = None,
    tile_size: int = 5_000_000,
    nproc: int = 1,
    w: int | None = None,
    p: int | None = None,
) -> pandas.DataFrame:
    """cooltools' ``dots`` (HiCCUPS-style loop calling): the dots as cooltools returns them,
    ``chrom1 start1 end1 chrom2 start2 end2 count la_exp.{donut,vertical,horizontal,
    lowleft}.value ... .qval region cstart1 cstart2 c_label c_size region1 region2``
    (coordinates and ``cstart`` in bp). ``expected``: ``expected_cis``'s table
    (``expected_value_col`` of it); ``max_loci_separation`` and ``clustering_radius`` in bp;
    ``clustering_radius=None`` returns the enriched pixels (the first 15 columns) instead.
    Kernels are cooltools' recommended ones for the bin size (4-28 kb), or HiCCUPS' donut and
    lowleft of half-widths ``w`` and ``p`` (bins) when given; custom ``kernels`` arrays are not
    supported. ``tile_size`` and ``nproc`` are accepted for compatibility."""
    if kernels is not None:
        raise check.unsupported(
            "kernels",
            "custom kernel arrays are not supported; give w and p (half-widths in bins) for "
            "HiCCUPS' kernels",
        )
    w = check.integer("w", w, minimum=1, none=True)
    p = check.integer("p", p, minimum=0, none=True)
    if (w is None) != (p is None):
        raise ValueError("w and p: give both kernel half-widths, or neither")
    max_loci_separation = check.integer("max_loci_separation", max_loci_separation, minimum=1)
    max_nans_tolerated = check.integer("max_nans_tolerated", max_nans_tolerated, minimum=0)
    n_lambda_bins = check.integer("n_lambda_bins", n_lambda_bins, minimum=1)
    lambda_bin_fdr = check.number("lambda_bin_fdr", lambda_bin_fdr, above=0, below=1)
    clustering_radius = check.number("clustering_radius", clustering_radius, above=0, none=True)
    cluster_filtering = check.flag("cluster_filtering", cluster_filtering, none=True)
    check.integer("tile_size", tile_size, minimum=1)
    check.integer("nproc", nproc, minimum=1, none=True)
    pd = _pandas()
    f = _file(clr)
    kernel_names, regions, columns = _native.dots(
        f._native,
        _view_regions(view_df),
        _weight_column(f, "clr_weight_name", clr_weight_name),
        _expected_arrays(f, expected, view_df, expected_value_col, False),
        w,
        p,
        max_loci_separation,
        max_nans_tolerated,
        n_lambda_bins,
        lambda_bin_fdr,
        clustering_radius,
        True if cluster_filtering is None else cluster_filtering,
    )
    values = dict(columns)
    data: dict[str, Any] = {}
    data.update(_bin_coordinates(f, "1", values["bin1_id"]))
    data.update(_bin_coordinates(f, "2", values["bin2_id"]))
    data["count"] = values["count"]
    for suffix in ("value", "qval"):
        for name in kernel_names:
            key = f"la_exp.{name}.{suffix}"
            data[key] = values[key]
    if clustering_radius is None:
        return pd.DataFrame(data)
    region = np.asarray(regions, dtype=object)[values["region"]]
    clusters = {
        "cstart1": values["cstart1"],
        "cstart2": values["cstart2"],
        "c_label": values["c_label"],
        "c_size": values["c_size"],
    }
    # cooltools' column order; an empty table has the last seven in another order
    order = (
        ["region", "cstart1", "cstart2", "c_label", "c_size", "region1", "region2"]
        if len(region)
        else ["region", "region1", "region2", "c_label", "c_size", "cstart1", "cstart2"]
    )
    for name in order:
        data[name] = region if name.startswith("region") else clusters[name]
    return pd.DataFrame(data)


_BED_FIELDS = ("chrom", "start", "end", "name", "score", "strand")
_BEDPE_FIELDS = ("chrom1", "start1", "end1", "chrom2", "start2", "end2")


def _text(value: Any) -> str:
    if isinstance(value, (float, np.floating)) and float(value).is_integer():
        return str(int(value))
    return str(value)


def _feature_rows(
    features: Any, features_format: str, name: str = "features"
) -> tuple[bool, list[str], list[list[str]]]:
    """Features (a DataFrame with coolpuppy's column names) as the library reads a BED or
    BEDPE file: the fields in BED's order (``chrom start end name score strand`` or
    ``chrom1 ... end2``, then the other columns), with the column names; ``name`` is the
    argument's, in messages."""
    features_format = check.text("features_format", features_format, ["auto", "bed", "bedpe"])
    if not hasattr(features, "columns") or not hasattr(features, "itertuples"):
        raise TypeError(
            f"{name}: expected a pandas DataFrame with columns chrom start end [...] (BED) or "
            f"chrom1 start1 end1 chrom2 start2 end2 [...] (BEDPE), got {type(features).__name__}"
        )
    columns = [str(c) for c in features.columns]
    if features_format == "auto":
        if all(c in columns for c in _BEDPE_FIELDS):
            features_format = "bedpe"
        elif all(c in columns for c in _BED_FIELDS[:3]):
            features_format = "bed"
        else:
            raise ValueError(
                f"{name}: columns {columns} are neither BED (chrom start end) nor BEDPE "
                "(chrom1 start1 end1 chrom2 start2 end2)"
            )
    bedpe = features_format == "bedpe"
    leading = list(_BEDPE_FIELDS if bedpe else _BED_FIELDS)
    check.frame(f"{name} ({features_format})", features, leading[: 6 if bedpe else 3])
    if not bedpe:
        # the optional BED columns up to the last one present (placeholders before it)
        while leading[-1] not in columns:
            leading.pop()
    header = leading + [c for c in columns if c not in leading]
    table = [
        features[c].to_numpy() if c in columns else np.full(len(features), ".", dtype=object)
        for c in header
    ]
    rows = [[_text(v) for v in row] for row in zip(*table)]
    return bedpe, header, rows


def merge_dots(
    dots: Mapping[int, Any], near_diagonal: int = 110_000, strong: float = 100.0
) -> pandas.DataFrame:
    """Dot calls at 5, 10 and 25 kb merged into one list as Juicer's HiCCUPS merges its
    resolutions (``contactmap dots-merge``, ``dots --resolutions``): ``dots`` maps each
    resolution (bp) to its dots as ``dots`` returns them (or any table with the BEDPE columns
    and ``count``, or Juicer's ``observed``). 5 kb calls are kept when a 10 kb call lies within
    20 kb of them, when their anchors are closer than ``near_diagonal`` bp or their count is
    above ``strong``; 10 kb calls with no 5 kb call within 20 kb; 25 kb calls with no kept call
    within 50 kb. Returns the kept rows with a last column ``resolution``, sorted by
    chromosome, ``start1``, ``start2``, as the command writes them."""
    if not isinstance(dots, Mapping):
        raise TypeError(
            "dots: expected a mapping of resolution (bp) to dots DataFrame, got "
            f"{type(dots).__name__}"
        )
    lists = []
    for resolution, frame in dots.items():
        resolution = check.integer("dots: resolution", resolution, minimum=1)
        _, header, rows = _feature_rows(frame, "bedpe", f"dots[{resolution}]")
        lists.append((f"dots at {resolution} bp", resolution, header, rows))
    near_diagonal = check.integer("near_diagonal", near_diagonal, minimum=0)
    strong = check.number("strong", strong)
    text = _native.merge_dots(lists, near_diagonal, strong)
    pd = _pandas()
    # exact floats: pandas 3 parses them round-trip by default, pandas 2 when asked
    exact = {} if int(pd.__version__.split(".")[0]) >= 3 else {"float_precision": "round_trip"}
    return pd.read_csv(io.StringIO(text), sep="\t", **exact)


def pileup(
    clr: Any,
    features: Any,
    features_format: str = "auto",
    view_df: Any = None,
    expected_df: Any = None,
    expected_value_col: str = "balanced.avg",
    clr_weight_name: str | None = "weight",
    flank: int = 100_000,
    minshift: int = 10**5,
    maxshift: int = 10**6,
    nshifts: int = 0,
    ooe: bool = True,
    mindist: int | str | None = "auto",
    maxdist: int | None = None,
    min_diag: int = 2,
    subset: int = 0,
    by_window: bool = False,
    by_strand: bool = False,
    by_distance: bool | str | Sequence[int] = False,
    groupby: Sequence[str] = (),
    ignore_group_order: bool = False,
    flip_negative_strand: bool = False,
    local: bool = False,
    coverage_norm: bool | str = False,
    trans: bool = False,
    rescale: bool = False,
    rescale_flank: float = 1,
    rescale_size: int = 99,
    store_stripes: bool = False,
    nproc: int = 1,
    seed: int | None = None,
) -> pandas.DataFrame:
    """coolpuppy's ``pileup``: the average snippet around features (BED: paired, or on the
    diagonal with ``local``; BEDPE: each pair), observed / expected with ``expected_df``
    (``expected_cis``, or ``expected_trans`` with ``trans``), over ``nshifts`` shifted random
    controls (``minshift``..``maxshift`` bp away, generator seeded with ``seed``, 0 when
    None), or raw. One row per group (by strand, by distance band, by ``groupby`` columns;
    the group of all last): ``group`` (its label), ``strand1 strand2``, ``distance_band`` (bp),
    the ``groupby`` columns, ``data`` (the mean snippet, a ``(2 flank / bin + 1)``-square
    array, or ``rescale_size`` with ``rescale``), ``num`` (snippets with a value per pixel),
    ``n`` and ``control_n``. ``flank``, ``mindist``, ``maxdist`` in bp; ``mindist="auto"``
    is coolpuppy's (2 flank + 2 bins). What was left out is in ``df.attrs["skipped"]``.
    ``ooe=False``, ``subset``, ``by_window``, ``ignore_group_order`` and ``store_stripes`` are
    not supported; ``nproc`` is accepted for compatibility."""
    if not check.flag("ooe", ooe):
        raise check.unsupported("ooe", "False is not supported")
    if check.integer("subset", subset, minimum=0):
        raise check.unsupported("subset", "only 0 (every feature) is supported")
    for name, value in (
        ("by_window", by_window),
        ("ignore_group_order", ignore_group_order),
        ("store_stripes", store_stripes),
    ):
        if check.flag(name, value):
            raise check.unsupported(name, "True is not supported")
    flank = check.integer("flank", flank, minimum=0)
    minshift = check.integer("minshift", minshift, minimum=0)
    maxshift = check.integer("maxshift", maxshift, minimum=0)
    nshifts = check.integer("nshifts", nshifts, minimum=0)
    if isinstance(mindist, str):
        check.text("mindist", mindist, ["auto"])
    min_dist = None if mindist == "auto" else check.number("mindist", mindist, minimum=0, none=True)
    max_dist = check.number("maxdist", maxdist, minimum=0, none=True)
    min_diag = check.integer("min_diag", min_diag, minimum=0)
    by_strand = check.flag("by_strand", by_strand)
    groupby_columns: list[str] = check.texts("groupby", groupby)
    flip_negative_strand = check.flag("flip_negative_strand", flip_negative_strand)
    local = check.flag("local", local)
    trans = check.flag("trans", trans)
    rescale = check.flag("rescale", rescale)
    rescale_flank = check.number("rescale_flank", rescale_flank, above=0)
    rescale_size = check.integer("rescale_size", rescale_size, minimum=1)
    check.integer("nproc", nproc, minimum=1, none=True)
    seed = check.integer("seed", seed, minimum=0, maximum=2**32 - 1, none=True)
    edges: list[int] | None
    if by_distance is None or isinstance(by_distance, (bool, np.bool_)):
        edges = [] if by_distance else None
    elif isinstance(by_distance, str):
        check.text("by_distance", by_distance, ["default"])
        edges = []
    else:
        edges = check.integers("by_distance", by_distance, minimum=0, empty=True)
    if coverage_norm is None or isinstance(coverage_norm, (bool, np.bool_)):
        norm = "total" if coverage_norm else None
    elif isinstance(coverage_norm, str):
        norm = coverage_norm  # its value: the library's check
    else:
        raise TypeError(
            "coverage_norm: expected True, False, None, 'total' or 'cis', got "
            f"{type(coverage_norm).__name__}"
        )
    pd = _pandas()
    f = _file(clr)
    bedpe, header, rows = _feature_rows(features, features_format)
    expected = None
    if expected_df is not None and nshifts == 0:
        expected = _expected_arrays(
            f, expected_df, view_df, expected_value_col, trans, "expected_df"
        )
    groups, skipped = _native.pileup(
        f._native,
        bedpe,
        header,
        rows,
        _view_regions(view_df),
        _weight_name(f, "clr_weight_name", clr_weight_name),
        expected,
        local,
        flank,
        min_dist,
        max_dist,
        min_diag,
        (rescale_flank, rescale_size) if rescale else None,
        (nshifts, minshift, maxshift, 0 if seed is None else seed) if nshifts > 0 else None,
        edges,
        by_strand,
        flip_negative_strand,
        groupby_columns,
        trans,
        norm,
    )
    table: dict[str, list[Any]] = {"group": [g[0] for g in groups]}
    if by_strand:
        table["strand1"] = [None if g[1] is None else g[1][0] for g in groups]
        table["strand2"] = [None if g[1] is None else g[1][1] for g in groups]
    if edges is not None:
        table["distance_band"] = [
            None if g[2] is None else ((g[2][0],) if g[2][1] is None else g[2]) for g in groups
        ]
    for k, name in enumerate(groupby_columns):
        table[name] = [g[3][k] if g[3] else "all" for g in groups]
    table["data"] = [g[4] for g in groups]
    table["num"] = [g[5] for g in groups]
    table["n"] = [g[6] for g in groups]
    if nshifts > 0:
        table["control_n"] = [g[7] for g in groups]
    df = pd.DataFrame(table)
    df["flank"] = int(flank)
    df["resolution"] = f.resolution()
    df["local"] = local
    df["trans"] = trans
    df["rescale"] = rescale
    df.attrs["skipped"] = dict(skipped)
    return df
