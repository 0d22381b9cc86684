"""cooltools' tables (``expected_cis``, ``expected_trans``, ``directionality``,
``insulation``) and balancing."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from . import _checks as check
from . import _native
from ._file import File, _file, _pandas, _uri_of, _view_regions, _weight_name
from ._native import ContactmapError

if TYPE_CHECKING:  # pragma: no cover
    import pandas


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
    if not check.flag("intra_only", intra_only):
        raise check.unsupported(
            "intra_only", "False (between the regions of one chromosome) is not supported"
        )
    smooth = check.flag("smooth", smooth)
    aggregate_smoothed = check.flag("aggregate_smoothed", aggregate_smoothed)
    smooth_sigma = check.number("smooth_sigma", smooth_sigma, above=0)
    ignore_diags = check.integer("ignore_diags", ignore_diags, minimum=0)
    check.integer("chunksize", chunksize, minimum=1, none=True)
    check.integer("nproc", nproc, minimum=1, none=True)
    _pandas()  # the install hint before the work
    f = _file(clr)
    region1, region2, columns = _native.expected_cis(
        f._native,
        _view_regions(view_df),
        _weight_name(f, "clr_weight_name", clr_weight_name),
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
    check.integer("chunksize", chunksize, minimum=1, none=True)
    check.integer("nproc", nproc, minimum=1, none=True)
    f = _file(clr)
    region1, region2, columns = _native.expected_trans(
        f._native, _view_regions(view_df), _weight_name(f, "clr_weight_name", clr_weight_name)
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
    window_bp = check.integer("window_bp", window_bp, minimum=1)
    min_dist_bad_bin = check.integer("min_dist_bad_bin", min_dist_bad_bin, minimum=0)
    ignore_diags = check.integer("ignore_diags", ignore_diags, minimum=0, none=True)
    pd = _pandas()
    f = _file(clr)
    bins, masked, ratio, index = _native.directionality(
        f._native,
        window_bp,
        _view_regions(view_df),
        _weight_name(f, "balance", balance),
        ignore_diags,
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
            f"directionality_ratio_{window_bp}": ratio,
            f"directionality_index_{window_bp}": index,
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
    boundary_strength_W ... is_boundary_W``. ``window_bp`` is an int or a list of ints
    (cooltools'): a str is refused (TypeError)."""
    windows = check.integers("window_bp", window_bp, minimum=1)
    ignore_diags = check.integer("ignore_diags", ignore_diags, minimum=0, none=True)
    min_frac_valid_pixels = check.number(
        "min_frac_valid_pixels", min_frac_valid_pixels, minimum=0, maximum=1
    )
    min_dist_bad_bin = check.integer("min_dist_bad_bin", min_dist_bad_bin, minimum=0)
    threshold = _threshold(threshold)
    append_raw_scores = check.flag("append_raw_scores", append_raw_scores)
    check.integer("chunksize", chunksize, minimum=1, none=True)
    check.integer("nproc", nproc, minimum=1, none=True)
    check.flag("verbose", verbose)
    pd = _pandas()
    f = _file(clr)
    bins, region, bad, region_names, columns = _native.insulation(
        f._native,
        windows,
        _view_regions(view_df),
        _weight_name(f, "clr_weight_name", clr_weight_name),
        ignore_diags,
        min_frac_valid_pixels,
        min_dist_bad_bin,
        threshold,
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


def _threshold(threshold: Any) -> str:
    """insulation's ``threshold`` as the library parses it: ``"Li"``, ``"Otsu"`` (any case) or
    a number."""
    kind = "'Li', 'Otsu' or a number"
    if isinstance(threshold, str):
        if threshold.strip().lower() in ("li", "otsu"):
            return threshold
        try:
            value = float(threshold)
        except ValueError:
            value = float("nan")
        if value != value:
            raise ValueError(f"threshold: expected {kind}, got {threshold!r}")
        return threshold
    if not check.is_number(threshold):
        raise TypeError(f"threshold: expected {kind}, got {type(threshold).__name__}")
    if threshold != threshold:
        raise ValueError(f"threshold: expected {kind}, got {threshold!r}")
    return str(threshold)


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
    name: str = "weight",
    overwrite: bool = False,
    store_unconverged: bool = False,
) -> tuple[np.ndarray, dict[str, Any]]:
    """Balance a map: ``method`` ``"ice"`` (cooler's ``balance_cooler``, its defaults),
    ``"kr"``, ``"vc"``, ``"vc_sqrt"`` or ``"scale"`` (Juicer's, their defaults). Returns the
    multiplicative weights per bin (NaN masked) and a summary (``converged``, ``scale``,
    ``var``, ``n_iterations``, ``n_masked``).

    ``store=True`` (``contactmap balance --store``, cooler's ``store=True``) writes the weights
    into the cooler (a ``.cool`` or ``.mcool::/resolutions/R``) as the column ``name`` with
    cooler's attributes: an existing column only with ``overwrite``, weights that did not
    converge only with ``store_unconverged``. A ``File`` given is closed while the file is
    written and reopened after (it then lists the new column); other ``File`` objects open on
    the same file in this process must be closed first (``del f``), as libhdf5 cannot open a
    file for writing that the process holds open for reading."""
    options: _native._BalanceOptions = {
        "method": check.text("method", method),  # its value: the library's check (ContactmapError)
        "cis_only": check.flag("cis_only", cis_only),
        "ignore_diags": check.integer("ignore_diags", ignore_diags, minimum=0, none=True),
        "mad_max": check.number("mad_max", mad_max, minimum=0, none=True),
        "min_nnz": check.integer("min_nnz", min_nnz, minimum=0, none=True),
        "min_count": check.number("min_count", min_count, minimum=0, none=True),
        "tol": check.number("tol", tol, above=0, none=True),
        "max_iters": check.integer("max_iters", max_iters, minimum=1, none=True),
        "rescale_marginals": check.flag("rescale_marginals", rescale_marginals, none=True),
    }
    store = check.flag("store", store)
    name = check.text("name", name)
    overwrite = check.flag("overwrite", overwrite)
    store_unconverged = check.flag("store_unconverged", store_unconverged)
    if not store:
        return _native.balance(_file(clr)._native, options)
    uri = _uri_of(clr)
    reopen = clr if isinstance(clr, File) else None
    if reopen is not None:
        reopen._native = None  # type: ignore[assignment]  # closes the file (its only reference)
    try:
        return _native.balance_store(uri, name, overwrite, store_unconverged, options)
    except ContactmapError as e:
        if "use --force to replace it" in str(e):
            raise ContactmapError(
                str(e).replace("--force", "overwrite=True").replace("--name", "name=")
            ) from None
        if "already open" in str(e):
            raise ContactmapError(
                f"{e} (is the file open in another contactmap.File of this process? close it "
                "first: del f)"
            ) from e
        raise
    finally:
        if reopen is not None:
            reopen._native = _native.NativeFile(uri)
