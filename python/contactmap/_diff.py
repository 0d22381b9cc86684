"""Differences between conditions with replicates (``contactmap diff``)."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, Sequence

from . import _native
from ._file import _pandas, _uri_of

if TYPE_CHECKING:
    import pandas


def diff_loops(
    a: Sequence[Any],
    b: Sequence[Any],
    loops: str | os.PathLike[str] | None = None,
    *,
    half_width: int = 1,
    alpha: float = 0.05,
    cooks_filter: bool = True,
) -> pandas.DataFrame:
    """Loops whose contacts changed between conditions A (``a``: a map per replicate, paths,
    ``contactmap.File`` or ``cooler.Cooler``) and B (``b``), as ``contactmap diff loops``: each
    loop's raw counts in its (2 half_width + 1)^2 pixels, normalised by the smoothed expected at
    its distance, tested with DESeq2's model (pydeseq2 0.5.4's statistics), B against A.

    ``loops``: a BEDPE; ``None`` calls dots on each condition's summed replicates and pools them.
    Returns one row per loop with the columns of ``PREFIX.loops.bedpe``: ``chrom1 start1 end1
    chrom2 start2 end2 baseMean log2FoldChange lfc_low lfc_high lfcSE pvalue qvalue mean_A mean_B
    direction count_A1 ...``.
    """
    pd = _pandas()
    first = [_uri_of(m, "a") for m in a]
    second = [_uri_of(m, "b") for m in b]
    path = None if loops is None else os.fspath(loops)
    columns = _native.diff_loops(first, second, path, half_width, alpha, cooks_filter)
    return pd.DataFrame(dict(columns))


def _table(text: str) -> pandas.DataFrame:
    """A table as the command line writes it (tab-separated, a header, ``nan`` for missing)."""
    import io

    pd = _pandas()
    return pd.read_csv(io.StringIO(text), sep="\t", keep_default_na=False, na_values=["nan"])


def diff_boundaries(
    a: Sequence[Any],
    b: Sequence[Any],
    *,
    window: int | None = None,
    threshold: str | float = "li",
    ignore_diags: int = 2,
    match_bins: int = 2,
    alpha: float = 0.05,
    weight_name: str = "weight",
) -> pandas.DataFrame:
    """Boundaries gained, lost, shifted, stronger or weaker between conditions A (``a``: a
    balanced map per replicate, paths, ``contactmap.File`` or ``cooler.Cooler``) and B (``b``),
    as ``contactmap diff boundaries``: each replicate's insulation (``window`` bp, default 10
    bins), boundaries on each condition's mean score, the contacts across each tested against
    its flanks with DESeq2's model. Returns the columns of ``PREFIX.boundaries.tsv``: ``chrom
    start end start_A start_B strength_A strength_B depth_A depth_B baseMean log2FoldChange
    lfcSE pvalue qvalue shift_pvalue shift_qvalue status count_A1 ... expected_A1 ...``
    (``start_A`` / ``start_B``: ``.`` where a condition has no call).
    """
    first = [_uri_of(m, "a") for m in a]
    second = [_uri_of(m, "b") for m in b]
    text = _native.diff_boundaries(
        first, second, window, str(threshold), ignore_diags, match_bins, alpha, weight_name
    )
    return _table(text)


def diff_compartments(
    a: Sequence[Any],
    b: Sequence[Any],
    *,
    phasing_track: Sequence[float] | None = None,
    ignore_diags: int = 2,
    clip_percentile: float = 99.9,
    alpha: float = 0.05,
    weight_name: str = "weight",
) -> tuple[pandas.DataFrame, pandas.DataFrame]:
    """Compartment switches between conditions A (``a``: a balanced map per replicate) and B
    (``b``), as ``contactmap diff compartments``: each replicate's E1 (oriented by
    ``phasing_track``, one value per bin of the maps, e.g. GC content; then given the first
    replicate's sign per chromosome), the conditions' mean E1 per bin tested with limma's
    moderated t. Returns the per-bin table (``chrom start end E1_A E1_B difference se t df
    pvalue qvalue switch E1_A1 ...``) and the switched segments (``chrom start end switch n_bins
    E1_A E1_B max_qvalue``).
    """
    first = [_uri_of(m, "a") for m in a]
    second = [_uri_of(m, "b") for m in b]
    track = None if phasing_track is None else [float(v) for v in phasing_track]
    table, segments = _native.diff_compartments(
        first, second, track, ignore_diags, clip_percentile, alpha, weight_name
    )
    return _table(table), _table(segments)


def diff_regions(
    a: Any,
    b: Any,
    pairs: str | os.PathLike[str] | None = None,
    *,
    window: int | None = None,
    step: int | None = None,
    raw: bool = False,
    weight_name: str = "weight",
    min_bins: int = 20,
    mappability_cutoff: float = 0.1,
    relative_window: float = 1.0,
    absolute_window: int | None = None,
) -> pandas.DataFrame:
    """Regions whose structure differs between map ``a`` (the reference) and map ``b`` (the
    query), as ``contactmap diff regions`` and ``chess sim`` (chess-hic 0.3.8): the structural
    similarity of each pair's observed/expected matrices, its z-score, the signal-to-noise.
    ``pairs``: a BEDPE in chess pairs' format, or ``window`` (and ``step``) in bp for windows
    along every chromosome. Returns ``ID SN ssim z_ssim chrom1 start1 end1 chrom2 start2 end2``.
    """
    if (pairs is None) == (window is None):
        raise ValueError("give pairs or window, not both")
    path = None if pairs is None else os.fspath(pairs)
    text = _native.diff_regions(
        _uri_of(a, "a"),
        _uri_of(b, "b"),
        path,
        window,
        step,
        raw,
        weight_name,
        min_bins,
        mappability_cutoff,
        relative_window,
        absolute_window,
    )
    return _table(text)
